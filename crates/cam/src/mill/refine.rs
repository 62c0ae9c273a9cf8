//! The row refinement of [`raster`](super::raster): each row's CL curve
//! sampled every `step`, halved where a chord leaves the band about it,
//! then merged (the module docs of [`mill`](super), "Tolerance").

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use rayon::prelude::*;

use super::RasterOptions;

/// Many rows' CL points asked at once: `(v, us)` to the z at each `u`.
pub(super) type AskRows<'a> = dyn Fn(&[(f64, &[f64])]) -> Vec<Vec<Option<f64>>> + Sync + 'a;

/// A row to sample: its `v` and the ends `(from, to)` it runs between.
pub(super) type Job = (f64, (f64, f64));

/// [`AskRows`] of a CL function of `(u, v)`, point by point in parallel.
pub(super) fn point_by_point(
    at: &(dyn Fn(f64, f64) -> Option<f64> + Sync),
    asked: &[(f64, &[f64])],
) -> Vec<Vec<Option<f64>>> {
    asked.par_iter().map(|&(v, us)| us.par_iter().map(|&u| at(u, v)).collect()).collect()
}

/// The CL points of each row, as (u, z) from its `from` to its `to`, in
/// pieces where the surface is; refined and merged (module docs). Refining
/// goes level by level over all the rows, and each level's new positions
/// are asked of `ask` at once: the middles, then the quarters the
/// middles leave in doubt, as halving asks them one by one; or where
/// `ahead`, every check two levels at a time (see [`Want`]).
pub(super) fn sample_rows(ask: &AskRows, ahead: bool, jobs: &[Job], o: &RasterOptions) -> Vec<Vec<Vec<(f64, f64)>>> {
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
pub(super) fn first_level(samples: &[f64], q: Quantum) -> Vec<f64> {
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
pub(super) fn row_samples(from: f64, to: f64, o: &RasterOptions) -> Vec<f64> {
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
pub(super) struct Quantum(pub(super) f64);

impl Quantum {
    /// The nearest grid position.
    pub(super) fn snap(self, v: f64) -> f64 {
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
