//! Raster finishing: rows of cutter-location (CL) points over a surface,
//! sampled finely where the path bends and merged where it is straight.
//!
//! [`raster`] knows nothing of meshes: it asks a CL function — "where is
//! the tip of the cutter when it rests on the surface at (x, y)?", which is
//! drop-cutter — and builds the [`Toolpath`]. So the same pattern serves an
//! STL, a height grid or a probed model.
//!
//! # Rows
//! Rows run along X (stepping over in Y), along Y, or both (a cross-hatch:
//! the X rows, then the Y rows). Zig-zag rows are linked at the row ends by
//! a feed move that follows the surface (it is sampled like a row); one-way
//! rows retract to the safe height, rapid back and plunge at the plunge
//! feed. Where the CL function has no answer (off the surface) a row is cut
//! in pieces with a retract between them.
//!
//! # Tolerance
//! Along a row the CL curve is sampled every `step`; an interval whose
//! middle or quarter points lie more than `tolerance / 2` above the chord,
//! or more than `gouge / 2` below it, is halved, down to `step / 1024`.
//! The chord joins the points as they will be written (heights rounded up
//! to the output grid) and is held against the CL curve itself. The
//! sampled polyline is then merged (Douglas–Peucker) within the same
//! halves. So the path stays within `tolerance` above the true CL curve
//! (material left) and `gouge` below it (cut into the surface) at every
//! point the tests saw; a bump narrower than the midpoint and quarter
//! tests can see is the one way past that.
//!
//! Halving goes level by level over all the rows of a pass, so that each
//! level's new points can be asked of the CL function at once
//! ([`raster_with`] and a [`ClRowsFn`]: a ball on a height grid is placed
//! on whole rows far faster than point by point).
//!
//! # Pick-feed control (`cusp`)
//! The oval end mill paper's pick-feed control, generalised: with a target cusp height,
//! each next row goes as far as the cusp between the two rows stays within
//! it. The slope across the rows is measured on the CL surface at every
//! sample of the row; the caller's `pick_feed(angle)` gives the largest pick
//! feed in the inclined plane for that slope, and `pick_feed · cos(angle)`
//! is the stepover in plan. The row goes at the smallest of these over the
//! row, and never beyond `stepover`.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::sync::atomic::{AtomicUsize, Ordering};

use kezuri_geom::{Axes, AxisSet, Move, MoveKind, Spindle, Toolpath};
use rayon::prelude::*;

/// Which way the rows run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// Rows along X, stepping over in Y.
    X,
    /// Rows along Y, stepping over in X.
    Y,
    /// X rows, then Y rows.
    Both,
}

/// How rows are linked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pattern {
    /// Every other row runs backwards; rows are linked along the surface.
    ZigZag,
    /// Every row runs the same way; retract, rapid back, plunge.
    OneWay,
}

/// The area to cover, in plan: `[x0, x1] × [y0, y1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region {
    /// Smallest X.
    pub x0: f64,
    /// Smallest Y.
    pub y0: f64,
    /// Largest X.
    pub x1: f64,
    /// Largest Y.
    pub y1: f64,
}

/// What [`raster`] makes. Lengths mm, feeds mm/min.
#[derive(Clone, Copy, Debug)]
pub struct RasterOptions {
    /// Row direction.
    pub direction: Direction,
    /// Row linking.
    pub pattern: Pattern,
    /// Distance between rows in plan (the largest, with pick-feed control).
    pub stepover: f64,
    /// Sampling step along a row.
    pub step: f64,
    /// How far the path may stray from the CL curve, above it.
    pub tolerance: f64,
    /// How far the path may go below the CL curve, into the surface (at
    /// most `tolerance`; `tolerance` for a symmetric band).
    pub gouge: f64,
    /// The program's smallest increment, mm (0: not rounded). Positions
    /// are sampled on its grid and heights rounded up to it, so the
    /// program as written keeps the band.
    pub quantum: f64,
    /// Height for rapids, above everything.
    pub safe_z: f64,
    /// Cutting feed.
    pub feed: f64,
    /// Feed of plunges from the safe height.
    pub plunge_feed: f64,
    /// Spindle speed, rpm.
    pub speed: f64,
    /// Tool number.
    pub tool: u32,
}

/// Why no toolpath could be made.
#[derive(Clone, Debug, PartialEq)]
pub enum MillError {
    /// An option out of its range.
    Option(String),
    /// The CL function has no point anywhere in the region.
    NothingToCut,
}

impl std::fmt::Display for MillError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MillError::Option(m) => f.write_str(m),
            MillError::NothingToCut => f.write_str("the surface lies nowhere under the region: nothing to cut"),
        }
    }
}

impl std::error::Error for MillError {}

/// The CL function: the tip's z over (x, y), `None` off the surface.
pub type ClFn<'a> = dyn Fn(f64, f64) -> Option<f64> + Sync + 'a;

/// The CL function asked for whole rows at once: `(along_y, rows)` with
/// each row `(v, us)` — rows along X at `y = v`, or along Y at `x = v` —
/// gives the z at every `u` (ascending) of every row. The same answers as
/// the [`ClFn`], faster where a surface can place the cutter row by row
/// (`kezuri_cam::dropcut::drop_cutter_rows`).
pub type ClRowsFn<'a> = dyn Fn(bool, &[(f64, &[f64])]) -> Vec<Vec<Option<f64>>> + Sync + 'a;

/// Most CL points asked of a [`ClRowsFn`] at once (their positions and
/// answers take 24 bytes each).
const BATCH_POINTS: usize = 4 << 20;

/// The pick feed (in the inclined plane) for a surface inclined at `angle`
/// radians across the rows, `None` where no pick feed meets the target.
pub type PickFeedFn<'a> = dyn Fn(f64) -> Option<f64> + Sync + 'a;

/// Most rows in one pass.
const MAX_ROWS: usize = 1_000_000;

/// Called as rows are done: rows done so far, rows in all.
pub type Progress<'a> = dyn Fn(usize, usize) + Sync + 'a;

/// A raster finishing toolpath over `region`; `pick_feed` turns on
/// pick-feed control (see the module docs). Rows are sampled in parallel.
pub fn raster(
    cl: &ClFn,
    region: Region,
    o: &RasterOptions,
    pick_feed: Option<&PickFeedFn>,
    on_row: &Progress,
) -> Result<Toolpath, MillError> {
    raster_with(cl, None, region, o, pick_feed, on_row)
}

/// [`raster`], with the samples of each row and the middle and quarter
/// points between them asked of `rows_at` for many rows at once where it is
/// given (the points that refining adds below those, the links between
/// rows and pick-feed control still ask `cl`).
pub fn raster_with(
    cl: &ClFn,
    rows_at: Option<&ClRowsFn>,
    region: Region,
    o: &RasterOptions,
    pick_feed: Option<&PickFeedFn>,
    on_row: &Progress,
) -> Result<Toolpath, MillError> {
    check(region, o)?;
    let passes: &[bool] = match o.direction {
        Direction::X => &[false],
        Direction::Y => &[true],
        Direction::Both => &[false, true],
    };
    least_points(region, o, pick_feed, passes)?;
    let mut path = Path { toolpath: Toolpath::default(), at: None, o: *o };
    // Where the rows go, pass by pass (pick-feed control measures the
    // surface for each next row), then the rows themselves in parallel.
    let mut plans = Vec::new();
    for &along_y in passes {
        // In a frame where rows run along u and step over in v.
        let (u0, u1, v0, v1) = if along_y {
            (region.y0, region.y1, region.x0, region.x1)
        } else {
            (region.x0, region.x1, region.y0, region.y1)
        };
        let at = move |u: f64, v: f64| if along_y { cl(v, u) } else { cl(u, v) };
        let mut rows = vec![v0];
        while let Some(&v) = rows.last().filter(|&&v| v < v1) {
            let step = match pick_feed {
                Some(pf) => controlled_step(&at, u0, u1, v, v1, o, pf),
                None => o.stepover,
            };
            rows.push(if v1 - (v + step) < 1e-9 { v1 } else { v + step });
            if rows.len() > MAX_ROWS {
                return Err(MillError::Option(format!(
                    "more than {MAX_ROWS} rows: the pick feed that meets the cusp target near {} = {v:.3} is {step:.2e} mm",
                    if along_y { "x" } else { "y" }
                )));
            }
        }
        let rows = rows.into_iter().map(|v| Quantum(o.quantum).snap(v)).collect::<Vec<_>>();
        plans.push((along_y, u0, u1, rows));
    }
    let total: usize = plans.iter().map(|p| p.3.len()).sum();
    let done = AtomicUsize::new(0);
    for (along_y, u0, u1, rows) in plans {
        let at = move |u: f64, v: f64| if along_y { cl(v, u) } else { cl(u, v) };
        let point = |u: f64, v: f64, z: f64| {
            if along_y {
                Axes { x: v, y: u, z, ..Axes::ZERO }
            } else {
                Axes { x: u, y: v, z, ..Axes::ZERO }
            }
        };
        let forward = |k: usize| o.pattern == Pattern::OneWay || k.is_multiple_of(2);
        let ends = |k: usize| if forward(k) { (u0, u1) } else { (u1, u0) };
        let ask = |asked: &[(f64, &[f64])]| match rows_at {
            Some(f) => f(along_y, asked),
            None => point_by_point(&at, asked),
        };
        let mut sampled = Vec::with_capacity(rows.len());
        let per_row = first_level(&row_samples(u0, u1, o), Quantum(o.quantum)).len().max(1);
        let batch = (BATCH_POINTS / per_row).max(1);
        for (b, chunk) in rows.chunks(batch).enumerate() {
            let jobs: Vec<Job> = chunk.iter().enumerate().map(|(k, &v)| (v, ends(b * batch + k))).collect();
            sampled.extend(sample_rows(&ask, rows_at.is_some(), &jobs, o));
            for _ in chunk {
                on_row(done.fetch_add(1, Ordering::Relaxed) + 1, total);
            }
        }
        let mut last_row_end: Option<(f64, f64)> = None;
        for (&v, pieces) in rows.iter().zip(&sampled) {
            for (k, piece) in pieces.iter().enumerate() {
                let first = piece[0];
                let linked = k == 0
                    && o.pattern == Pattern::ZigZag
                    && last_row_end.is_some_and(|(pu, pv)| {
                        // Link along the surface from the last row's end.
                        (pu - first.0).abs() < 1e-9 && link_is_whole(&|w| at(pu, w), pv, v, o)
                    });
                if linked {
                    let (pu, pv) = last_row_end.unwrap();
                    let along = |asked: &[(f64, &[f64])]| point_by_point(&|w, _| at(pu, w), asked);
                    for (w, z) in
                        sample_rows(&along, false, &[(0.0, (pv, v))], o).remove(0).remove(0).into_iter().skip(1)
                    {
                        path.feed_to(point(pu, w, z), o.feed);
                    }
                } else {
                    path.approach(point(first.0, v, first.1));
                }
                for &(u, z) in &piece[1..] {
                    path.feed_to(point(u, v, z), o.feed);
                }
            }
            last_row_end = pieces.last().map(|p| (p[p.len() - 1].0, v));
            if last_row_end.is_some() && (o.pattern == Pattern::OneWay || pieces.len() > 1) {
                path.retract();
                last_row_end = None;
            }
        }
        path.retract();
    }
    if path.toolpath.moves.is_empty() {
        return Err(MillError::NothingToCut);
    }
    // Rapids run at the safe height: every cut must be below it.
    if let Some(m) = path.toolpath.moves.iter().filter(|m| !m.is_rapid()).find(|m| m.end.z >= o.safe_z) {
        return Err(MillError::Option(format!(
            "the safe height {} is not above the cut at ({:.3}, {:.3}, {:.3}): rapids would run into the part",
            o.safe_z, m.end.x, m.end.y, m.end.z
        )));
    }
    Ok(path.toolpath)
}

fn check(r: Region, o: &RasterOptions) -> Result<(), MillError> {
    let positive = |v: f64, what: &str| kezuri_geom::limits::length(v, what).map(|_| ()).map_err(MillError::Option);
    positive(o.stepover, "the stepover")?;
    positive(o.step, "the sampling step")?;
    positive(o.tolerance, "the tolerance")?;
    positive(o.gouge, "the gouge tolerance")?;
    if !(o.quantum.is_finite() && o.quantum >= 0.0 && o.quantum <= o.step) {
        return Err(MillError::Option(format!(
            "the output increment must be between 0 and the step, got {}",
            o.quantum
        )));
    }
    positive(o.feed, "the feed")?;
    positive(o.plunge_feed, "the plunge feed")?;
    if !(o.safe_z.is_finite() && o.speed.is_finite() && o.speed >= 0.0) {
        return Err(MillError::Option(format!(
            "the safe height ({}) and the spindle speed ({}) must be finite numbers",
            o.safe_z, o.speed
        )));
    }
    if ![r.x0, r.y0, r.x1, r.y1].iter().all(|v| v.is_finite()) || r.x1 < r.x0 || r.y1 < r.y0 {
        return Err(MillError::Option(format!("the region {r:?} must be finite with x0 ≤ x1 and y0 ≤ y1")));
    }
    Ok(())
}

/// Many rows' CL points asked at once: `(v, us)` to the z at each `u`.
type AskRows<'a> = dyn Fn(&[(f64, &[f64])]) -> Vec<Vec<Option<f64>>> + Sync + 'a;

/// A row to sample: its `v` and the ends `(from, to)` it runs between.
type Job = (f64, (f64, f64));

/// [`AskRows`] of a CL function of `(u, v)`, point by point in parallel.
fn point_by_point(at: &(dyn Fn(f64, f64) -> Option<f64> + Sync), asked: &[(f64, &[f64])]) -> Vec<Vec<Option<f64>>> {
    asked.par_iter().map(|&(v, us)| us.par_iter().map(|&u| at(u, v)).collect()).collect()
}

/// The CL points of each row, as (u, z) from its `from` to its `to`, in
/// pieces where the surface is; refined and merged (module docs). Refining
/// goes level by level over all the rows, and each level's new positions
/// are asked of `ask` at once: the middles, then the quarters the
/// middles leave in doubt, as halving asks them one by one; or where
/// `ahead`, every check two levels at a time (see [`Want`]).
fn sample_rows(ask: &AskRows, ahead: bool, jobs: &[Job], o: &RasterOptions) -> Vec<Vec<Vec<(f64, f64)>>> {
    let q = Quantum(o.quantum);
    let r = Refining { band: Band::half(o), min_gap: o.step / 1024.0, quantum: q };
    let mut rows: Vec<RowSampling> = jobs
        .par_iter()
        .map(|&(v, (from, to))| {
            let samples = row_samples(from, to, o);
            let wanted = if ahead { first_level(&samples, q) } else { samples.clone() };
            RowSampling {
                v,
                ascending: to >= from,
                samples,
                found: HashMap::default(),
                wanted,
                open: Vec::new(),
                added: Vec::new(),
                cells: Vec::new(),
                lifted: HashMap::default(),
            }
        })
        .collect();
    ask_wanted(ask, &mut rows);
    rows.par_iter_mut().for_each(|row| row.open_between_samples(q));
    let stages: &[Want] = if ahead { &[Want::TwoLevels] } else { &[Want::Middles, Want::Quarters] };
    while rows.iter().any(|row| !row.open.is_empty() || !row.cells.is_empty()) {
        for &stage in stages {
            rows.par_iter_mut().for_each(|row| row.want(r, stage));
            ask_wanted(ask, &mut rows);
        }
        rows.par_iter_mut().for_each(|row| row.halve(r));
    }
    rows.into_par_iter().map(|row| row.pieces(o)).collect()
}

/// Asks every row's wanted positions at once and files the answers.
fn ask_wanted(ask: &AskRows, rows: &mut [RowSampling]) {
    if rows.iter().all(|row| row.wanted.is_empty()) {
        return;
    }
    let asked: Vec<(f64, &[f64])> = rows.iter().map(|row| (row.v, &row.wanted[..])).collect();
    let answers = ask(&asked);
    rows.par_iter_mut().zip(answers).for_each(|(row, zs)| {
        for (u, z) in std::mem::take(&mut row.wanted).into_iter().zip(zs) {
            row.found.insert(u.to_bits(), z);
        }
    });
}

/// The positions a row asks first: its samples and the middle and quarter
/// points [`RowSampling::halve`] tries between each two, ascending.
fn first_level(samples: &[f64], q: Quantum) -> Vec<f64> {
    let mut us = samples.to_vec();
    for w in samples.windows(2) {
        us.extend(checks(w[0], w[1], q));
    }
    us.sort_by(f64::total_cmp);
    us.dedup();
    us
}

/// The samples of a row from `from` to `to`, every `step` or less, on the
/// output grid, each once.
/// Most CL points the rows may ask before refining (as a drop-cutter grid).
const MAX_POINTS: f64 = crate::dropcut::Grid::MAX_POINTS as f64;

/// Refuses, before any work, a raster whose rows hold more than
/// [`MAX_POINTS`] samples even at the widest stepover it can take (on the
/// flat, with pick-feed control).
fn least_points(
    region: Region,
    o: &RasterOptions,
    pick_feed: Option<&PickFeedFn>,
    passes: &[bool],
) -> Result<(), MillError> {
    let widest = pick_feed.and_then(|pf| pf(0.0)).map_or(o.stepover, |w| w.min(o.stepover));
    let (w, h) = (region.x1 - region.x0, region.y1 - region.y0);
    let (mut rows, mut samples) = (0.0, 0.0);
    for &along_y in passes {
        let (u, v) = if along_y { (h, w) } else { (w, h) };
        rows += (v / widest).ceil() + 1.0;
        samples = f64::max(samples, (u / o.step).ceil() + 1.0);
    }
    if rows * samples > MAX_POINTS {
        let by = if pick_feed.is_some() { "the pick feed of the cusp height on the flat" } else { "the stepover" };
        return Err(MillError::Option(format!(
            "{rows:.0} rows ({by}, {widest:.3e} mm) of {samples:.0} samples (the step, {} mm) is more than {} million \
             CL points: raise the stepover, the cusp height or the step",
            o.step,
            MAX_POINTS / 1e6
        )));
    }
    Ok(())
}

fn row_samples(from: f64, to: f64, o: &RasterOptions) -> Vec<f64> {
    let q = Quantum(o.quantum);
    let n = (((to - from).abs() / o.step).ceil() as usize).max(1);
    let mut us: Vec<f64> =
        (0..=n).map(|k| q.snap(if k == n { to } else { from + (to - from) * k as f64 / n as f64 })).collect();
    us.dedup();
    us
}

/// Chords of at most this many grid steps are also held against the CL
/// between the grid positions.
const FEW_CELLS: usize = 4;

/// The positions asked between the grid positions of a chord of a few
/// grid steps: the quarters of each step.
fn between_grid(a: f64, b: f64, q: Quantum) -> impl Iterator<Item = f64> {
    let n = q.cells(a, b).clamp(1, FEW_CELLS);
    (1..4 * n).filter(|k| k % 4 != 0).map(move |k| a + (b - a) * k as f64 / (4 * n) as f64)
}

/// The middle and the quarter points tried between `a` and `b`.
fn checks(a: f64, b: f64, q: Quantum) -> [f64; 3] {
    [q.snap(0.5 * (a + b)), q.snap(a + 0.25 * (b - a)), q.snap(a + 0.75 * (b - a))]
}

/// Hashes the bits of a position: one multiplication (the keys are
/// positions of one row, not chosen by anyone).
#[derive(Default)]
struct BitsHasher(u64);

impl Hasher for BitsHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }

    fn write_u64(&mut self, bits: u64) {
        self.0 = (self.0 ^ bits).wrapping_mul(0x9e37_79b9_7f4a_7c15).rotate_left(29);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

/// What a pass of halving asks.
#[derive(Clone, Copy, Debug)]
enum Want {
    /// The middles of the open chords.
    Middles,
    /// Their quarters, where the middle is on the surface and within the
    /// band (where it is not, the chord is halved whatever they are).
    Quarters,
    /// Middles and quarters of the open chords and of their halves: for a
    /// CL function that answers rows at once, asking two levels together
    /// halves the passes, each of which costs more than the points it asks.
    TwoLevels,
}

/// One row being sampled.
struct RowSampling {
    v: f64,
    /// Whether the row runs towards larger `u`.
    ascending: bool,
    /// Its samples, in the row's order.
    samples: Vec<f64>,
    /// CL z (as the CL function gave it) by the bits of `u`.
    found: HashMap<u64, Option<f64>, BuildHasherDefault<BitsHasher>>,
    /// Positions to ask next.
    wanted: Vec<f64>,
    /// Chords still to try: their ends, (u, z) on the output grid.
    open: Vec<[(f64, f64); 2]>,
    /// Points refining added.
    added: Vec<(f64, f64)>,
    /// Chords of a few grid steps whose CL between the grid positions is
    /// still to be asked and held against them ([`RowSampling::hold`]).
    cells: Vec<[(f64, f64); 2]>,
    /// Heights points are lifted to, by the bits of `u`.
    lifted: HashMap<u64, f64, BuildHasherDefault<BitsHasher>>,
}

impl RowSampling {
    /// The CL z at `u` on the output grid; `None` off the surface (or not
    /// asked).
    fn z(&self, u: f64, q: Quantum) -> Option<f64> {
        self.cl(u).map(|z| q.up(z))
    }

    /// The CL z at `u` as the CL function gave it.
    fn cl(&self, u: f64) -> Option<f64> {
        self.found.get(&u.to_bits()).copied().flatten()
    }

    /// The chords between samples on the surface.
    fn open_between_samples(&mut self, q: Quantum) {
        let points: Vec<Option<(f64, f64)>> = self.samples.iter().map(|&u| self.z(u, q).map(|z| (u, z))).collect();
        self.open = points.windows(2).filter_map(|w| Some([w[0]?, w[1]?])).collect();
    }

    /// The middle and quarter points of the open chords not asked yet.
    /// The positions `stage` asks of the open chords that are not known
    /// yet.
    fn want(&mut self, r: Refining, stage: Want) {
        let q = r.quantum;
        let unknown = |u: f64| !self.found.contains_key(&u.to_bits());
        // The unknown checks of the chord `a b` that `pick` keeps; its middle.
        let want = |a: f64, b: f64, pick: [bool; 3], wanted: &mut Vec<f64>| {
            let within = |u: f64| (u - a) * (b - u) > 0.0;
            if (b - a).abs() <= r.min_gap {
                return None;
            }
            let points = checks(a, b, q);
            let picked = points.into_iter().zip(pick).filter(|&(u, p)| p && within(u) && unknown(u));
            wanted.extend(picked.map(|(u, _)| u));
            within(points[0]).then_some(points[0])
        };
        let mut wanted = Vec::new();
        for &[a, b] in &self.open {
            match stage {
                Want::Middles => {
                    want(a.0, b.0, [true, false, false], &mut wanted);
                }
                Want::Quarters => {
                    let [m, ..] = checks(a.0, b.0, q);
                    let z = self.cl(m);
                    if z.is_some_and(|z| !band_off(r.band, a, b, m, z)) {
                        want(a.0, b.0, [false, true, true], &mut wanted);
                    }
                }
                Want::TwoLevels => {
                    let before = wanted.len();
                    if let Some(m) = want(a.0, b.0, [true; 3], &mut wanted).filter(|_| wanted.len() > before) {
                        want(a.0, m, [true; 3], &mut wanted);
                        want(m, b.0, [true; 3], &mut wanted);
                    }
                }
            }
        }
        for &[a, b] in &self.cells {
            wanted.extend(between_grid(a.0, b.0, q).filter(|&u| unknown(u)));
        }
        wanted.sort_by(f64::total_cmp);
        wanted.dedup();
        self.wanted = wanted;
    }

    /// Halves each open chord whose middle or a quarter point is outside
    /// the band about it, down to `min_gap`; the middle is kept and its two
    /// halves are tried next. A chord whose middle is off the surface is
    /// kept (the row is cut there only where a sample misses).
    fn halve(&mut self, r: Refining) {
        let q = r.quantum;
        let cells = std::mem::take(&mut self.cells);
        let mut next = Vec::new();
        for [a, b] in std::mem::take(&mut self.open) {
            if (b.0 - a.0).abs() <= r.min_gap {
                continue;
            }
            let within = |u: f64| (u - a.0) * (b.0 - u) > 0.0;
            let [u, u1, u3] = checks(a.0, b.0, q);
            if !within(u) {
                // No grid position in between: the CL inside is asked and
                // held against the chord next time.
                self.cells.push([a, b]);
                continue;
            }
            let Some(z) = self.cl(u) else { continue };
            // The chord is tried at its middle and quarters: a narrow bump
            // between samples shows at one of them more often than at the
            // middle alone. The chord joins points as written (rounded up
            // to the output grid); it is held against the CL curve itself.
            let off = |u: f64| within(u) && self.cl(u).is_some_and(|z| band_off(r.band, a, b, u, z));
            if band_off(r.band, a, b, u, z) || off(u1) || off(u3) {
                let z = q.up(z);
                self.added.push((u, z));
                next.push([a, (u, z)]);
                next.push([(u, z), b]);
            } else if q.cells(a.0, b.0) <= FEW_CELLS && (a.1 - b.1).abs() > r.band.below {
                // Its checks were grid positions: a chord that rises (where
                // the CL may bulge over it between them) is held against the
                // CL between them too.
                self.cells.push([a, b]);
            }
        }
        for [a, b] in cells {
            self.hold(r, a, b, &mut next);
        }
        self.open = next;
    }

    /// Holds the chord `a b` of a few grid steps against the CL between the
    /// grid positions (asked since). Where it passes below by more than the
    /// band, a chord with a grid position inside is halved there (into
    /// `next`); a chord between neighbours, with none left to add, has both
    /// ends lifted to the highest CL over it, rounded up, so that it is
    /// above the CL all across; so has one between neighbours that rises
    /// by more than the band, where the CL may jump unseen. A steep CL (a
    /// flat cutter's rim going over a steep flank: 0.07 mm in a 0.01 mm
    /// step) bulges over such a chord; lifting leaves material within that
    /// step instead of cutting in.
    fn hold(&mut self, r: Refining, a: (f64, f64), b: (f64, f64), next: &mut Vec<[(f64, f64); 2]>) {
        let q = r.quantum;
        let inside: Vec<(f64, f64)> = between_grid(a.0, b.0, q).filter_map(|u| Some((u, self.cl(u)?))).collect();
        let below = |&(u, z): &(f64, f64)| z - (a.1 + (u - a.0) / (b.0 - a.0) * (b.1 - a.1)) > r.band.below;
        let m = checks(a.0, b.0, q)[0];
        let neighbours = (m - a.0) * (b.0 - m) <= 0.0;
        // Between neighbours the CL may jump anywhere (a flat cutter's rim
        // leaving a steep flank) where no sample shows it: a chord that
        // rises there is lifted as well.
        let rises = neighbours && (a.1 - b.1).abs() > r.band.below;
        if !(rises || inside.iter().any(below)) {
            return;
        }
        match self.cl(m) {
            Some(z) if !neighbours => {
                let z = q.up(z);
                self.added.push((m, z));
                next.push([a, (m, z)]);
                next.push([(m, z), b]);
            }
            _ => {
                let top = inside.iter().map(|p| p.1).chain([a.1, b.1]).fold(f64::NEG_INFINITY, f64::max);
                let top = q.up(top);
                for u in [a.0, b.0] {
                    let h = self.lifted.entry(u.to_bits()).or_insert(top);
                    *h = h.max(top);
                }
            }
        }
    }

    /// The samples and the added points in the row's order, in pieces where
    /// the surface is, each merged.
    fn pieces(self, o: &RasterOptions) -> Vec<Vec<(f64, f64)>> {
        let q = Quantum(o.quantum);
        let mut all: Vec<(f64, Option<f64>)> = self.samples.iter().map(|&u| (u, self.z(u, q))).collect();
        all.extend(self.added.iter().map(|&(u, z)| (u, Some(z))));
        for (u, z) in &mut all {
            if let (Some(z), Some(&h)) = (z.as_mut(), self.lifted.get(&u.to_bits())) {
                *z = z.max(h);
            }
        }
        all.sort_by(|a, b| if self.ascending { a.0.total_cmp(&b.0) } else { b.0.total_cmp(&a.0) });
        all.split(|p| p.1.is_none())
            .filter(|piece| !piece.is_empty())
            .map(|piece| merge(piece.iter().map(|&(u, z)| (u, z.unwrap_or_default())).collect(), Band::half(o)))
            .collect()
    }
}

/// The output grid of [`RasterOptions::quantum`].
#[derive(Clone, Copy, Debug)]
struct Quantum(f64);

impl Quantum {
    /// The nearest grid position.
    fn snap(self, v: f64) -> f64 {
        if self.0 > 0.0 {
            (v / self.0).round() * self.0
        } else {
            v
        }
    }

    /// How many grid steps lie between `a` and `b` (`usize::MAX` without a
    /// grid).
    fn cells(self, a: f64, b: f64) -> usize {
        if self.0 > 0.0 {
            ((b - a).abs() / self.0).round() as usize
        } else {
            usize::MAX
        }
    }

    /// The grid height at or above `z` (within a millionth of a step).
    fn up(self, z: f64) -> f64 {
        if self.0 > 0.0 {
            ((z / self.0) - 1e-6).ceil() * self.0
        } else {
            z
        }
    }
}

/// How [`RowSampling::halve`] halves.
#[derive(Clone, Copy, Debug)]
struct Refining {
    band: Band,
    /// No interval narrower than this is halved.
    min_gap: f64,
    /// Points lie on this grid.
    quantum: Quantum,
}

/// Whether the CL point `(u, z)` is outside `band` about the chord `a b`.
fn band_off(band: Band, a: (f64, f64), b: (f64, f64), u: f64, z: f64) -> bool {
    let t = (u - a.0) / (b.0 - a.0);
    band.outside(z, a.1 + t * (b.1 - a.1))
}

/// How far a chord may pass above and below the CL points it stands for.
#[derive(Clone, Copy, Debug)]
struct Band {
    /// The chord above the CL point (material left).
    above: f64,
    /// The chord below the CL point (into the surface).
    below: f64,
}

impl Band {
    /// Half of each side: one half for sampling, one for merging.
    fn half(o: &RasterOptions) -> Band {
        Band { above: o.tolerance / 2.0, below: o.gouge.min(o.tolerance) / 2.0 }
    }

    /// How far the chord height `chord` is outside the band about the CL
    /// height `z` (0 inside it), measured against the side it is on.
    fn excess(self, z: f64, chord: f64) -> f64 {
        if chord >= z { (chord - z) - self.above } else { (z - chord) - self.below }.max(0.0)
    }

    fn outside(self, z: f64, chord: f64) -> bool {
        self.excess(z, chord) > 0.0
    }
}

/// Douglas–Peucker: the fewest points of `points` whose polyline stays
/// within `band` (in z, as the cutter sees it) of every dropped point.
fn merge(points: Vec<(f64, f64)>, band: Band) -> Vec<(f64, f64)> {
    if points.len() <= 2 {
        return points;
    }
    let mut keep = vec![false; points.len()];
    keep[0] = true;
    keep[points.len() - 1] = true;
    let mut stack = vec![(0, points.len() - 1)];
    while let Some((i, j)) = stack.pop() {
        let (a, b) = (points[i], points[j]);
        let mut worst = (0.0, 0);
        for (k, p) in points.iter().enumerate().take(j).skip(i + 1) {
            let t = (p.0 - a.0) / (b.0 - a.0);
            let off = band.excess(p.1, a.1 + t * (b.1 - a.1));
            if off > worst.0 {
                worst = (off, k);
            }
        }
        if worst.0 > 0.0 {
            keep[worst.1] = true;
            stack.push((i, worst.1));
            stack.push((worst.1, j));
        }
    }
    points.into_iter().zip(keep).filter_map(|(p, k)| k.then_some(p)).collect()
}

/// Whether the surface is there all along a link from `v_from` to `v_to`.
fn link_is_whole(at: &dyn Fn(f64) -> Option<f64>, v_from: f64, v_to: f64, o: &RasterOptions) -> bool {
    let n = (((v_to - v_from).abs() / o.step).ceil() as usize).max(1);
    (0..=n).all(|k| at(v_from + (v_to - v_from) * k as f64 / n as f64).is_some())
}

/// The stepover from the row at `v` under pick-feed control.
fn controlled_step(
    at: &dyn Fn(f64, f64) -> Option<f64>,
    u0: f64,
    u1: f64,
    v: f64,
    v1: f64,
    o: &RasterOptions,
    pick_feed: &PickFeedFn,
) -> f64 {
    let n = (((u1 - u0) / o.step).ceil() as usize).max(1);
    let here: Vec<(f64, Option<f64>)> =
        (0..=n).map(|k| u0 + (u1 - u0) * k as f64 / n as f64).map(|u| (u, at(u, v))).collect();
    let mut step = o.stepover.min(v1 - v).max(1e-6);
    // The slope between this row and the next depends on where the next row
    // is: shrink the step until the cusp over it is within the target.
    for _ in 0..8 {
        let mut allowed = step;
        for &(u, z) in &here {
            let (Some(z), Some(z2)) = (z, at(u, v + step)) else { continue };
            let angle = ((z2 - z) / step).atan().abs();
            let plan = pick_feed(angle).map_or(o.step / 1024.0, |pf| pf * angle.cos());
            allowed = allowed.min(plan);
        }
        if allowed >= step * 0.999 {
            return step;
        }
        step = allowed.max(o.step / 1024.0);
    }
    step
}

/// The toolpath being built and where the tool is.
struct Path {
    toolpath: Toolpath,
    at: Option<Axes>,
    o: RasterOptions,
}

impl Path {
    fn push(&mut self, kind: MoveKind, end: Axes, feed: f64, named: AxisSet) {
        let start = self.at.unwrap_or(end);
        self.toolpath.push(Move {
            kind,
            start,
            end,
            feed,
            speed: self.o.speed,
            spindle: Spindle::Cw,
            tool: self.o.tool,
            named,
            ..Move::default()
        });
        self.at = Some(end);
    }

    /// Up to the safe height (first Z alone, as the tool may be anywhere),
    /// across at rapid, then down at the plunge feed to `p`.
    fn approach(&mut self, p: Axes) {
        let safe = Axes { z: self.o.safe_z, ..p };
        match self.at {
            None => {
                self.push(MoveKind::Rapid, safe, 0.0, AxisSet(0b100));
                self.push(MoveKind::Rapid, safe, 0.0, AxisSet(0b011));
            }
            Some(a) => {
                if a.z < self.o.safe_z {
                    self.push(MoveKind::Rapid, Axes { z: self.o.safe_z, ..a }, 0.0, AxisSet::ALL);
                }
                self.push(MoveKind::Rapid, safe, 0.0, AxisSet::ALL);
            }
        }
        self.push(MoveKind::Feed, p, self.o.plunge_feed, AxisSet::ALL);
    }

    fn feed_to(&mut self, p: Axes, feed: f64) {
        self.push(MoveKind::Feed, p, feed, AxisSet::ALL);
    }

    fn retract(&mut self) {
        if let Some(a) = self.at {
            if a.z < self.o.safe_z {
                self.push(MoveKind::Rapid, Axes { z: self.o.safe_z, ..a }, 0.0, AxisSet::ALL);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options() -> RasterOptions {
        RasterOptions {
            direction: Direction::X,
            pattern: Pattern::ZigZag,
            stepover: 1.0,
            step: 0.5,
            tolerance: 0.01,
            gouge: 0.01,
            quantum: 0.0,
            safe_z: 10.0,
            feed: 1000.0,
            plunge_feed: 200.0,
            speed: 10000.0,
            tool: 1,
        }
    }

    const SQUARE: Region = Region { x0: 0.0, y0: 0.0, x1: 10.0, y1: 4.0 };

    fn cuts(path: &Toolpath) -> Vec<&Move> {
        path.moves.iter().filter(|m| m.kind == MoveKind::Feed).collect()
    }

    #[test]
    fn a_plane_is_cut_in_straight_rows_linked_along_the_surface() {
        let path = raster(&|x, y| Some(0.1 * x + 0.2 * y), SQUARE, &options(), None, &|_, _| {}).unwrap();
        // Plunge, then per row one straight move (merged), links between rows.
        let feeds = cuts(&path);
        assert_eq!(feeds.len(), 1 + 5 + 4, "{feeds:#?}");
        assert!(feeds.iter().all(|m| (m.end.z - (0.1 * m.end.x + 0.2 * m.end.y)).abs() < 1e-12));
        // Rapids only at the start and the end: Z alone first.
        assert_eq!(path.moves[0].named, AxisSet(0b100));
        assert_eq!(path.moves.last().unwrap().end.z, 10.0);
    }

    #[test]
    fn curved_rows_stay_within_the_tolerance() {
        let surface = |x: f64, y: f64| Some((x * 0.7).sin() * 2.0 + 0.1 * y);
        // Symmetric, and one-sided: 0.02 mm of material left allowed but
        // only 0.0005 mm into the surface.
        for (tolerance, gouge) in [(0.002, 0.002), (0.02, 0.0005)] {
            let o = RasterOptions { tolerance, gouge, ..options() };
            let path = raster(&surface, SQUARE, &o, None, &|_, _| {}).unwrap();
            let (mut deepest, mut highest) = (0.0f64, 0.0f64);
            for m in cuts(&path).iter().filter(|m| m.start.y == m.end.y && m.feed == o.feed) {
                for k in 1..50 {
                    let t = k as f64 / 50.0;
                    let x = m.start.x + t * (m.end.x - m.start.x);
                    let z = m.start.z + t * (m.end.z - m.start.z);
                    let off = z - surface(x, m.end.y).unwrap();
                    assert!(off <= tolerance * 1.01 && -off <= gouge * 1.01, "{off} at x={x}");
                    (deepest, highest) = (deepest.max(-off), highest.max(off));
                }
            }
            // The band is used, not just respected.
            assert!(highest > 0.3 * tolerance, "{tolerance}: {highest}");
            assert!(deepest > 0.1 * gouge, "{gouge}: {deepest}");
        }
    }

    #[test]
    fn one_way_rows_retract_and_plunge() {
        let o = RasterOptions { pattern: Pattern::OneWay, ..options() };
        let path = raster(&|_, _| Some(0.0), SQUARE, &o, None, &|_, _| {}).unwrap();
        let plunges = path.moves.iter().filter(|m| m.kind == MoveKind::Feed && m.feed == o.plunge_feed).count();
        assert_eq!(plunges, 5);
        assert!(cuts(&path).iter().filter(|m| m.feed == o.feed).all(|m| m.end.x > m.start.x));
    }

    #[test]
    fn holes_in_the_surface_split_rows() {
        let surface = |x: f64, _y: f64| (!(4.0..6.0).contains(&x)).then_some(0.0);
        let path = raster(&surface, SQUARE, &options(), None, &|_, _| {}).unwrap();
        // No cut crosses the hole.
        assert!(cuts(&path).iter().all(|m| !(m.start.x < 4.5 && m.end.x > 5.5 || m.end.x < 4.5 && m.start.x > 5.5)));
        assert!(raster(&|_, _| None, SQUARE, &options(), None, &|_, _| {}) == Err(MillError::NothingToCut));
    }

    #[test]
    fn pick_feed_control_narrows_rows_where_the_slope_asks() {
        // Level for y < 2, a 45° ramp beyond; the pick feed allowed in the
        // plane is 1.0 on the level and 0.2 on the ramp.
        let surface = |_x: f64, y: f64| Some(if y < 2.0 { 0.0 } else { y - 2.0 });
        let pf = |angle: f64| Some(if angle > 0.1 { 0.2 } else { 1.0 });
        let region = Region { x0: 0.0, y0: 0.0, x1: 1.0, y1: 4.0 };
        let path = raster(&surface, region, &options(), Some(&pf), &|_, _| {}).unwrap();
        let mut rows: Vec<f64> = cuts(&path).iter().filter(|m| m.start.y == m.end.y).map(|m| m.end.y).collect();
        rows.dedup();
        let on_ramp = rows.windows(2).filter(|w| w[0] >= 2.0).map(|w| w[1] - w[0]).fold(0.0, f64::max);
        assert!(on_ramp <= 0.2 * (std::f64::consts::FRAC_PI_4).cos() + 1e-9, "{rows:?}");
        assert!((rows[1] - rows[0] - 1.0).abs() < 1e-9, "{rows:?}");
    }

    #[test]
    fn a_safe_height_below_the_cut_is_an_error() {
        let low = RasterOptions { safe_z: 0.5, ..options() };
        let e = raster(&|x, _| Some(x * 0.1), SQUARE, &low, None, &|_, _| {}).unwrap_err();
        assert!(e.to_string().contains("not above the cut"), "{e}");
        let nan = RasterOptions { safe_z: f64::NAN, ..options() };
        let e = raster(&|_, _| Some(0.0), SQUARE, &nan, None, &|_, _| {}).unwrap_err();
        assert!(e.to_string().contains("safe height"), "{e}");
    }

    #[test]
    fn bad_options_are_errors() {
        let bad = RasterOptions { stepover: 0.0, ..options() };
        assert!(matches!(raster(&|_, _| Some(0.0), SQUARE, &bad, None, &|_, _| {}), Err(MillError::Option(_))));
        let nan = RasterOptions { tolerance: f64::NAN, ..options() };
        assert!(raster(&|_, _| Some(0.0), SQUARE, &nan, None, &|_, _| {}).is_err());
    }
}
