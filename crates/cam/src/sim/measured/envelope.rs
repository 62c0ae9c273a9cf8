//! The envelope of one straight segment with a measured tool, per cell:
//! exact.
//!
//! With the notation of `sim/sweep.rs` the envelope at a cell is
//! `min over σ in [lo, hi] of zA + g·(s − σ) + h(√(σ² + w²))`. On each
//! linear piece `h = z₀ + b·(ρ − ρ₀)` (`b ≥ 0`) that is convex in `σ`, with
//! the stationary point `σ* = g·|w| / √(b² − g²)` (none when `b ≤ |g|`), so
//! the exact minimum is the least over the pieces, each over the `σ` where
//! `ρ` lies in its range. Pieces are not all visited:
//!
//! - **Level moves and plunges** (`g = 0`, the common case): `h` is
//!   non-decreasing, so the minimum is `h` at the least distance the cutter
//!   reaches, a lookup (a table of buckets over `ρ`, then a step or a short
//!   bisection). Along an axis the cells beside the segment share values:
//!   one lookup per column (moves along Y) or per row (along X).
//! - **Sloped moves**: with `γ = |g|` (the sign folded into `σ`), the side
//!   where the tip rises as the tool nears the cell is monotone, so only
//!   `σ ≥ α ≥ 0` counts, where `ρ` grows with `σ`. Where the tool's least
//!   slope beyond `ρ(α)` outruns the sinking tip (`b·α ≥ γ·ρ(α)`) the
//!   minimum is at `α`: one lookup. Else, after a cheap bound
//!   (`h(ρ(α)) − γ·β`), the lower convex hull of `h` gives a convex bound
//!   `G(σ) = hull(ρ) − γ·σ ≤ F(σ)`; its minimum `σ_G` is found on the
//!   hull's vertices (from the last cell's, galloping), and the pieces are
//!   scanned outward from the one holding `σ_G` while `G` at their near end
//!   is below the best value so far (or the cell's height). For a convex
//!   profile that is one or two pieces; a waist or wear scars add only the
//!   pieces whose bound can still win.

use super::MeasuredTool;
use crate::sim::sweep::{fmax, fmin, row_span, Band, Prep, Reach};

impl MeasuredTool {
    /// The `σ ≥ 0` that minimises `hull(√(σ² + w²)) − γ·σ` (γ > 0) over
    /// the tool's reach. The search starts from the vertex `hint` (the
    /// last one found: neighbouring cells need near ones) and leaves the
    /// one found there; the answer does not depend on it.
    fn hull_argmin(&self, w: f64, w2: f64, gamma: f64, hint: &mut usize) -> f64 {
        let m = self.hull_r.len();
        if m == 1 {
            return 0.0;
        }
        // The right derivative at vertex v, c_v·σ_v/ρ_v − γ, grows with v:
        // the first vertex where it is ≥ 0 ends the edge with the minimum.
        // c·√(ρ² − w²) ≥ γ·ρ, squared (both sides ≥ 0).
        let g2 = gamma * gamma;
        let rises = |v: usize| {
            if v == m - 1 {
                return true;
            }
            let (rv, c) = (self.hull_r[v], self.hull_c[v]);
            rv > w && c > gamma && c * c * (rv * rv - w2) >= g2 * rv * rv
        };
        // The first vertex in 1..m that rises: gallop from the hint to a
        // bracket [lo, hi] with rises(hi), then bisect.
        let v = (*hint).clamp(1, m - 1);
        let (mut lo, mut hi) = if rises(v) {
            let (mut hi, mut step) = (v, 1);
            loop {
                if hi == 1 {
                    break (1, 1);
                }
                let probe = hi.saturating_sub(step).max(1);
                if !rises(probe) {
                    break (probe + 1, hi);
                }
                hi = probe;
                step *= 2;
            }
        } else {
            let (mut lo, mut step) = (v + 1, 1);
            loop {
                let probe = (v + step).min(m - 1);
                if rises(probe) {
                    break (lo, probe);
                }
                lo = probe + 1;
                step *= 2;
            }
        };
        while lo < hi {
            let mid = (lo + hi) / 2;
            if rises(mid) {
                hi = mid;
            } else {
                lo = mid + 1;
            }
        }
        *hint = lo;
        let e = lo - 1;
        let sigma = |r: f64| (r * r - w2).max(0.0).sqrt();
        let (a, b) = (sigma(self.hull_r[e].max(w)), sigma(self.hull_r[e + 1]));
        let c = self.hull_c[e];
        let star = if c > gamma { gamma * w / (c * c - gamma * gamma).sqrt() } else { b };
        star.clamp(a, b.max(a))
    }

    /// Least of `h(√(σ² + w²)) − γ·σ` over piece `k` and `α ≤ σ ≤ β`.
    #[inline(always)]
    fn piece_min(&self, k: usize, w: f64, w2: f64, gamma: f64, alpha: f64, beta: f64) -> f64 {
        let p = &self.pieces[k];
        if p.r1 < w {
            return f64::INFINITY;
        }
        let lo = (p.r0.max(w) * p.r0.max(w) - w2).max(0.0).sqrt().max(alpha);
        let hi = (p.r1 * p.r1 - w2).max(0.0).sqrt().min(beta);
        if lo > hi {
            return f64::INFINITY;
        }
        let star = if p.slope > gamma { gamma * w / (p.slope * p.slope - gamma * gamma).sqrt() } else { hi };
        let sigma = star.clamp(lo, hi);
        p.at((sigma * sigma + w2).sqrt()) - gamma * sigma
    }

    /// `min over α ≤ σ ≤ β of h(√(σ² + w²)) − γ·σ` (`0 ≤ α ≤ β`, `γ > 0`,
    /// `w ≥ 0`) when it is below `limit`.
    #[allow(clippy::too_many_arguments)]
    fn sloped_min(
        &self,
        w: f64,
        w2: f64,
        gamma: f64,
        alpha: f64,
        beta: f64,
        limit: f64,
        hint: &mut usize,
    ) -> Option<f64> {
        let ra = (alpha * alpha + w2).sqrt();
        let k = self.piece_of(ra);
        let ha = self.pieces[k].at(ra);
        // Where the tool rises faster than the tip sinks, the minimum is at
        // α: from there ρ grows at least α/ρα as fast as σ (as fast on the
        // axis, w = 0), h at least at the least slope of the pieces beyond
        // (see `monotone_beyond`).
        let (along, across) = if w > 0.0 { (alpha, ra) } else { (1.0, 1.0) };
        if self.flattest[k] * along >= gamma * across {
            let z = ha - gamma * alpha;
            return (z < limit).then_some(z);
        }
        // Cheap bound: the nearest height, the most the slope can give.
        if ha - gamma * beta >= limit {
            return None;
        }
        let sg = self.hull_argmin(w, w2, gamma, hint).clamp(alpha, beta);
        let k = if sg == alpha { k } else { self.piece_of((sg * sg + w2).sqrt()) };
        let mut best = limit.min(self.piece_min(k, w, w2, gamma, alpha, beta));
        // Outward while the hull bound at a piece's near end can still win.
        for j in k + 1..self.pieces.len() {
            let p = &self.pieces[j];
            let s0 = (p.r0 * p.r0 - w2).max(0.0).sqrt();
            if s0 > beta || p.hull0 - gamma * s0 >= best {
                break;
            }
            best = best.min(self.piece_min(j, w, w2, gamma, alpha, beta));
        }
        for j in (0..k).rev() {
            let p = &self.pieces[j];
            if p.r1 < w {
                break;
            }
            let s1 = (p.r1 * p.r1 - w2).sqrt();
            if s1 < alpha || p.hull1 - gamma * s1 >= best {
                break;
            }
            best = best.min(self.piece_min(j, w, w2, gamma, alpha, beta));
        }
        (best < limit).then_some(best)
    }
}

/// The measured tool's envelope at `x` on a row whose offset from the
/// segment's start is `ey`, for a cell now at `current`: `None` when the
/// segment cannot lower it.
pub fn measured_at(m: &MeasuredTool, p: &Prep, x: f64, ey: f64, current: f64) -> Option<f64> {
    measured_at_from(m, p, x, ey, current, &mut 0)
}

/// [`measured_at`], its search over the hull started from `hint`.
#[inline]
fn measured_at_from(m: &MeasuredTool, p: &Prep, x: f64, ey: f64, current: f64, hint: &mut usize) -> Option<f64> {
    let r = m.radius;
    let g = p.dz * p.inv_len;
    if g == 0.0 {
        let z = level_at(m, p, r * r, x, ey);
        return (z < current).then_some(z);
    }
    let dx = x - p.ax;
    let s = dx * p.ux + ey * p.uy;
    let w = ey * p.ux - dx * p.uy;
    let w2 = w * w;
    let q2 = r * r - w2;
    if q2 < 0.0 {
        return None;
    }
    let q = q2.sqrt();
    let (lo, hi) = ((s - p.len).max(-q), s.min(q));
    if lo > hi {
        return None;
    }
    // zA + g·s − g·σ; with σ' = ±σ so that the slope term is −γ·σ'.
    let base = p.za + g * s;
    let (gamma, a, b) = if g > 0.0 { (g, lo, hi) } else { (-g, -hi, -lo) };
    let z = if b <= 0.0 {
        // Wholly on the monotone side: its end nearest the axis.
        base + m.lookup((b * b + w2).sqrt()) - gamma * b
    } else {
        base + m.sloped_min(w.abs(), w2, gamma, a.max(0.0), b, current - base, hint)?
    };
    (z < current).then_some(z)
}

/// The envelope of a level segment or plunge at `x` on the row `ey`;
/// `+∞` out of reach. `h` is non-decreasing, so it is `h` at the least
/// distance reached: to the nearest point of the segment (`σ = 0` where
/// the interval `[lo, hi]` holds it, else its end nearer 0, which is that).
#[inline(always)]
fn level_at(m: &MeasuredTool, p: &Prep, r2: f64, x: f64, ey: f64) -> f64 {
    let dx = x - p.ax;
    let s = dx * p.ux + ey * p.uy;
    let w = ey * p.ux - dx * p.uy;
    let along = s - fmin(fmax(s, 0.0), p.len);
    let rho2 = along * along + w * w;
    let h = m.lookup(rho2.sqrt());
    if rho2 <= r2 {
        p.za + h
    } else {
        f64::INFINITY
    }
}

/// Lowers the band's cells along a level segment or plunge: the lookup at
/// the least distance reached. Returns the most a cell was lowered when
/// `TRACK` (else 0).
///
/// Along an axis (the common raster) the cells beside the segment, where
/// the nearest point is inside it, share their values: along Y every such
/// row has the same values (computed once), along X every such cell of a
/// row has one value. The same arithmetic as [`level_at`], bit for bit.
fn level_rows<const TRACK: bool>(m: &MeasuredTool, p: &Prep, reach: &Reach, band: &mut Band) -> f64 {
    let (r, r2) = (m.radius, m.radius * m.radius);
    let mut deepest = 0.0f64;
    let rows = band.cells.len() / band.nx;
    let (j0, j1) = (reach.j0.max(band.first), reach.j1.min(band.first + rows));
    // Along Y: the values of a row beside the segment, and their cells.
    let mut shared: (Vec<f64>, std::ops::Range<usize>) = (Vec::new(), 0..0);
    for j in j0..j1 {
        let y = band.y0 + (j as f64 + 0.5) * band.res;
        let span = row_span(p, r, reach, y, band);
        let ey = y - p.ay;
        let row = (j - band.first) * band.nx;
        if !TRACK && p.ux == 0.0 && !span.is_empty() {
            let s = ey * p.uy;
            if (0.0..=p.len).contains(&s) {
                if shared.0.is_empty() {
                    shared = (band.xs[span.clone()].iter().map(|&x| level_at(m, p, r2, x, ey)).collect(), span.clone());
                }
                if shared.1 == span {
                    let cells = &mut band.cells[row + span.start..row + span.end];
                    for (cell, &z) in cells.iter_mut().zip(&shared.0) {
                        *cell = fmin(*cell, z);
                    }
                    continue;
                }
            }
        }
        let cells = &mut band.cells[row + span.start..row + span.end];
        if !TRACK && p.uy == 0.0 {
            // Along X: one value where the nearest point is inside.
            let w = ey * p.ux;
            let rho2 = w * w;
            let inner = if rho2 <= r2 { p.za + m.lookup(rho2.sqrt()) } else { f64::INFINITY };
            for (cell, &x) in cells.iter_mut().zip(&band.xs[span]) {
                let s = (x - p.ax) * p.ux;
                let z = if (0.0..=p.len).contains(&s) { inner } else { level_at(m, p, r2, x, ey) };
                *cell = fmin(*cell, z);
            }
            continue;
        }
        for (cell, &x) in cells.iter_mut().zip(&band.xs[span]) {
            let z = level_at(m, p, r2, x, ey);
            if TRACK && z < *cell {
                deepest = deepest.max(before(m, p, x, ey, *cell) - z);
            }
            *cell = fmin(*cell, z);
        }
    }
    deepest
}

/// What a cell is with the cutter standing at the segment's start: a
/// rapid is not blamed for that.
#[inline]
fn before(m: &MeasuredTool, p: &Prep, x: f64, ey: f64, cell: f64) -> f64 {
    let d = (x - p.ax).hypot(ey);
    if d <= m.radius {
        cell.min(p.z_start + m.lookup(d))
    } else {
        cell
    }
}

/// Lowers the band's cells to a segment's envelope with the measured tool;
/// returns the most any cell was lowered when `track` (else 0).
pub fn measured_rows(m: &MeasuredTool, p: &Prep, reach: &Reach, band: &mut Band, track: bool) -> f64 {
    if p.dz == 0.0 {
        return if track { level_rows::<true>(m, p, reach, band) } else { level_rows::<false>(m, p, reach, band) };
    }
    let mut deepest = 0.0f64;
    let rows = band.cells.len() / band.nx;
    let (j0, j1) = (reach.j0.max(band.first), reach.j1.min(band.first + rows));
    let mut hint = 0;
    for j in j0..j1 {
        let y = band.y0 + (j as f64 + 0.5) * band.res;
        let span = row_span(p, m.radius, reach, y, band);
        let row = (j - band.first) * band.nx;
        for i in span {
            let cell = &mut band.cells[row + i];
            if let Some(z) = measured_at_from(m, p, band.xs[i], y - p.ay, *cell, &mut hint) {
                if track {
                    deepest = deepest.max(before(m, p, band.xs[i], y - p.ay, *cell) - z);
                }
                *cell = z;
            }
        }
    }
    deepest
}
