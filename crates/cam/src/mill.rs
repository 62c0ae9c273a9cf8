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
//! on whole rows far faster than point by point); asked point by point,
//! the rows are refined sixteen at a time, in bounded memory.
//!
//! # Pick-feed control (`cusp`)
//! The oval end mill paper's pick-feed control, generalised: with a target cusp height,
//! each next row goes as far as the cusp between the two rows stays within
//! it. The slope across the rows is measured on the CL surface at every
//! sample of the row; the caller's `pick_feed(angle)` gives the largest pick
//! feed in the inclined plane for that slope, and `pick_feed · cos(angle)`
//! is the stepover in plan. The row goes at the smallest of these over the
//! row, and never beyond `stepover`.

pub mod reach;
mod refine;

use std::sync::atomic::{AtomicUsize, Ordering};

use kezuri_geom::{Axes, AxisSet, Move, MoveKind, PathSink, Spindle, Toolpath, WholePath};

use crate::error::{Error, ErrorKind};

use self::refine::{first_level, point_by_point, row_samples, sample_rows, Job, Quantum};

/// The gouge allowance of every command that makes or checks a surface
/// (`--gouge-tol` of mill, relief, probe mill, sim and view), mm: how far
/// below the surface a finishing path may cut.
pub const GOUGE_TOL: f64 = 0.01;

/// The words of the header comment in which a program kezuri made carries
/// its gouge allowance, read back by the simulation so that its own check
/// agrees: `KEZURI GOUGE-TOL 0.010`.
const GOUGE_NOTE: &str = "KEZURI GOUGE-TOL";

/// The header comment's text for an allowance of `tol` mm: three decimals,
/// more where `tol` has them.
pub fn gouge_note(tol: f64) -> String {
    let three = format!("{tol:.3}");
    let value = if three.parse::<f64>() == Ok(tol) { three } else { tol.to_string() };
    format!("{GOUGE_NOTE} {value}")
}

/// The allowance a comment's text gives, where it is a [`gouge_note`]
/// (any case, spaces around): a length of 0 or more.
pub fn read_gouge_note(comment: &str) -> Option<f64> {
    let text = comment.trim();
    let head = text.get(..GOUGE_NOTE.len())?;
    if !head.eq_ignore_ascii_case(GOUGE_NOTE) {
        return None;
    }
    let value: f64 = text[GOUGE_NOTE.len()..].trim().parse().ok()?;
    (value.is_finite() && (0.0..=1000.0).contains(&value)).then_some(value)
}

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

/// The error of a raster or roughing that finds no point of the surface.
pub(crate) fn nothing_to_cut() -> Error {
    Error::new(ErrorKind::NothingToCut, "the surface lies nowhere under the region: nothing to cut")
}

/// The CL function: the tip's z over (x, y), `None` off the surface.
pub type ClFn<'a> = dyn Fn(f64, f64) -> Option<f64> + Sync + 'a;

/// The CL function asked for whole rows at once: `(along_y, rows)` with
/// each row `(v, us)` — rows along X at `y = v`, or along Y at `x = v` —
/// gives the z at every `u` (ascending) of every row. The same answers as
/// the [`ClFn`], faster where a surface can place the cutter row by row
/// (`kezuri_cam::dropcut::drop_cutter_rows`).
pub type ClRowsFn<'a> = dyn Fn(bool, &[(f64, &[f64])]) -> Vec<Vec<Option<f64>>> + Sync + 'a;

/// How the CL points of the rows are asked.
#[derive(Clone, Copy)]
pub enum Rows<'a> {
    /// One by one, of the [`ClFn`].
    PointByPoint,
    /// Whole rows at once, many rows together, two levels of halving
    /// ahead: for a surface that places the cutter on whole rows far
    /// faster than point by point (a ball on a height grid).
    Whole(&'a ClRowsFn<'a>),
    /// The points of each row together, as point by point asks them: for
    /// a surface that answers the points of one row faster together (a
    /// mesh, the triangles near the row found once).
    Along(&'a ClRowsFn<'a>),
}

/// Most CL points asked of a [`ClRowsFn`] at once (their positions and
/// answers take 24 bytes each).
const BATCH_POINTS: usize = 4 << 20;

/// Rows refined together where the CL function is asked point by point:
/// enough for both cores, few enough that their refinement is small.
const ROWS_AT_ONCE: usize = 16;

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
) -> Result<Toolpath, Error> {
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
) -> Result<Toolpath, Error> {
    let mut whole = WholePath::default();
    let asking = rows_at.map_or(Rows::PointByPoint, Rows::Whole);
    raster_into(cl, asking, region, o, pick_feed, on_row, &mut whole)?;
    Ok(whole.path)
}

/// [`raster_with`], the CL points asked as `asking` says, handed to `sink`
/// row by row as the rows are made, so that a program of any size is never
/// held: the pieces joined are the path [`raster_with`] returns. An error (the safe height below a cut,
/// nothing to cut) comes after the pieces before it were handed on.
pub fn raster_into(
    cl: &ClFn,
    asking: Rows,
    region: Region,
    o: &RasterOptions,
    pick_feed: Option<&PickFeedFn>,
    on_row: &Progress,
    sink: &mut dyn PathSink,
) -> Result<(), Error> {
    check(region, o)?;
    let passes: &[bool] = match o.direction {
        Direction::X => &[false],
        Direction::Y => &[true],
        Direction::Both => &[false, true],
    };
    least_points(region, o, pick_feed, passes)?;
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
                return Err(Error::new(ErrorKind::Option, format!(
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
    let mut path = Path { piece: Toolpath::default(), at: None, o: *o, sink, handed: false };
    for (along_y, u0, u1, rows) in &plans {
        let (along_y, u0, u1) = (*along_y, *u0, *u1);
        let at = move |u: f64, v: f64| if along_y { cl(v, u) } else { cl(u, v) };
        let forward = |k: usize| o.pattern == Pattern::OneWay || k.is_multiple_of(2);
        let ends = |k: usize| if forward(k) { (u0, u1) } else { (u1, u0) };
        let ask = |asked: &[(f64, &[f64])]| match asking {
            Rows::Whole(f) | Rows::Along(f) => f(along_y, asked),
            Rows::PointByPoint => point_by_point(&at, asked),
        };
        let whole_rows = matches!(asking, Rows::Whole(_));
        let per_row = first_level(&row_samples(u0, u1, o), Quantum(o.quantum)).len().max(1);
        // Rows asked point by point are refined a few at a time: what a
        // row holds while it is refined (every CL point asked of it, some
        // six for each point it keeps) is let go as soon as it is done.
        let batch = if whole_rows { (BATCH_POINTS / per_row).max(1) } else { ROWS_AT_ONCE };
        let mut last_row_end: Option<(f64, f64)> = None;
        for (b, chunk) in rows.chunks(batch).enumerate() {
            let jobs: Vec<Job> = chunk.iter().enumerate().map(|(k, &v)| (v, ends(b * batch + k))).collect();
            let sampled = sample_rows(&ask, whole_rows, &jobs, o);
            for (&v, pieces) in chunk.iter().zip(sampled) {
                last_row_end = path.row(along_y, &at, v, &pieces, last_row_end);
                path.hand_on()?;
            }
            for _ in chunk {
                on_row(done.fetch_add(1, Ordering::Relaxed) + 1, total);
            }
        }
        path.retract();
    }
    path.hand_on()?;
    if !path.handed {
        return Err(nothing_to_cut());
    }
    Ok(())
}

fn check(r: Region, o: &RasterOptions) -> Result<(), Error> {
    let positive = |v: f64, what: &str| {
        kezuri_geom::limits::length(v, what).map(|_| ()).map_err(|m| Error::new(ErrorKind::Option, m))
    };
    positive(o.stepover, "the stepover")?;
    positive(o.step, "the sampling step")?;
    positive(o.tolerance, "the tolerance")?;
    positive(o.gouge, "the gouge tolerance")?;
    if !(o.quantum.is_finite() && o.quantum >= 0.0 && o.quantum <= o.step) {
        return Err(Error::new(
            ErrorKind::Option,
            format!("the output increment must be between 0 and the step, got {}", o.quantum),
        ));
    }
    positive(o.feed, "the feed")?;
    positive(o.plunge_feed, "the plunge feed")?;
    if !(o.safe_z.is_finite() && o.speed.is_finite() && o.speed >= 0.0) {
        return Err(Error::new(
            ErrorKind::Option,
            format!("the safe height ({}) and the spindle speed ({}) must be finite numbers", o.safe_z, o.speed),
        ));
    }
    if ![r.x0, r.y0, r.x1, r.y1].iter().all(|v| v.is_finite()) || r.x1 < r.x0 || r.y1 < r.y0 {
        return Err(Error::new(ErrorKind::Option, format!("the region {r:?} must be finite with x0 ≤ x1 and y0 ≤ y1")));
    }
    Ok(())
}

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
) -> Result<(), Error> {
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
        return Err(Error::new(
            ErrorKind::Option,
            format!(
            "{rows:.0} rows ({by}, {widest:.3e} mm) of {samples:.0} samples (the step, {} mm) is more than {} million \
             CL points: raise the stepover, the cusp height or the step",
            o.step,
            MAX_POINTS / 1e6
        ),
        ));
    }
    Ok(())
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

/// The toolpath being made, the row at hand, and where the tool is.
struct Path<'s> {
    /// The moves not handed on yet.
    piece: Toolpath,
    at: Option<Axes>,
    o: RasterOptions,
    sink: &'s mut dyn PathSink,
    /// Whether a move was handed on.
    handed: bool,
}

impl Path<'_> {
    fn push(&mut self, kind: MoveKind, end: Axes, feed: f64, named: AxisSet) {
        let start = self.at.unwrap_or(end);
        self.piece.push(Move {
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

    /// The moves of the row at `v` (its `pieces` of points `(u, z)`) after
    /// the row that ended at `last_row_end` (`(u, v)`, where the tool
    /// stays down to link along the surface); where this one ends.
    fn row(
        &mut self,
        along_y: bool,
        at: &(dyn Fn(f64, f64) -> Option<f64> + Sync),
        v: f64,
        pieces: &[Vec<(f64, f64)>],
        mut last_row_end: Option<(f64, f64)>,
    ) -> Option<(f64, f64)> {
        let o = self.o;
        let point = |u: f64, v: f64, z: f64| {
            if along_y {
                Axes { x: v, y: u, z, ..Axes::ZERO }
            } else {
                Axes { x: u, y: v, z, ..Axes::ZERO }
            }
        };
        for (k, piece) in pieces.iter().enumerate() {
            let first = piece[0];
            let link = last_row_end.filter(|&(pu, pv)| {
                // Link along the surface from the last row's end.
                k == 0
                    && o.pattern == Pattern::ZigZag
                    && (pu - first.0).abs() < 1e-9
                    && link_is_whole(&|w| at(pu, w), pv, v, &o)
            });
            if let Some((pu, pv)) = link {
                let along = |asked: &[(f64, &[f64])]| point_by_point(&|w, _| at(pu, w), asked);
                for (w, z) in sample_rows(&along, false, &[(0.0, (pv, v))], &o).remove(0).remove(0).into_iter().skip(1)
                {
                    self.feed_to(point(pu, w, z), o.feed);
                }
            } else {
                self.approach(point(first.0, v, first.1));
            }
            for &(u, z) in &piece[1..] {
                self.feed_to(point(u, v, z), o.feed);
            }
        }
        last_row_end = pieces.last().map(|p| (p[p.len() - 1].0, v));
        if last_row_end.is_some() && (o.pattern == Pattern::OneWay || pieces.len() > 1) {
            self.retract();
            last_row_end = None;
        }
        last_row_end
    }

    /// Hands the moves made since the last time on to the sink. Rapids run
    /// at the safe height: every cut must be below it.
    fn hand_on(&mut self) -> Result<(), Error> {
        if self.piece.moves.is_empty() {
            return Ok(());
        }
        let safe_z = self.o.safe_z;
        if let Some(m) = self.piece.moves.iter().filter(|m| !m.is_rapid()).find(|m| m.end.z >= safe_z) {
            return Err(Error::new(
                ErrorKind::Option,
                format!(
                    "the safe height {safe_z} is not above the cut at ({:.3}, {:.3}, {:.3}): rapids would run into the part",
                    m.end.x, m.end.y, m.end.z
                ),
            ));
        }
        // Handed over, not copied; the next row starts with the room this one had.
        let room = self.piece.moves.capacity();
        self.sink.take_owned(std::mem::take(&mut self.piece), None);
        self.piece.moves.reserve(room);
        self.handed = true;
        Ok(())
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

    #[test]
    fn the_gouge_note_reads_back() {
        for tol in [GOUGE_TOL, 0.001, 0.0005, 0.25, 1.0] {
            assert_eq!(read_gouge_note(&gouge_note(tol)), Some(tol), "{}", gouge_note(tol));
        }
        assert_eq!(gouge_note(0.01), "KEZURI GOUGE-TOL 0.010");
        assert_eq!(read_gouge_note(" kezuri gouge-tol 0.02 "), Some(0.02));
        for other in ["KEZURI GOUGE-TOL", "KEZURI GOUGE-TOL x", "KEZURI GOUGE-TOL -1", "GOUGE-TOL 0.01", "T1 D=6"] {
            assert_eq!(read_gouge_note(other), None, "{other}");
        }
    }

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
        assert!(
            raster(&|_, _| None, SQUARE, &options(), None, &|_, _| {}).unwrap_err().kind == ErrorKind::NothingToCut
        );
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
        assert!(
            matches!(raster(&|_, _| Some(0.0), SQUARE, &bad, None, &|_, _| {}), Err(e) if e.kind == ErrorKind::Option)
        );
        let nan = RasterOptions { tolerance: f64::NAN, ..options() };
        assert!(raster(&|_, _| Some(0.0), SQUARE, &nan, None, &|_, _| {}).is_err());
    }
}
