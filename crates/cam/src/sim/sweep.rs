//! The lower envelope of a cutter swept along one straight segment, per
//! cell: exact.
//!
//! For a point `p` in XY and a segment from `A` to `B` (tip positions), the
//! swept lower surface is `min over t of z(t) + height(|p − c(t)|)` over the
//! `t` where `|p − c(t)| ≤ R`. In the segment's frame (`s` along the XY
//! direction from `A`, `w` across it) and with `σ = s − τ` the offset of `p`
//! behind the cutter's centre at along-track distance `τ`, that is
//!
//! ```text
//! min over σ in [max(s − L, −q), min(s, q)] of  zA + g·(s − σ) + height(√(σ² + w²)),
//! q = √(R² − w²),  g = Δz / L
//! ```
//!
//! a convex function of `σ` (a convex non-decreasing profile of a convex
//! distance, plus a linear term), so the minimum is the one stationary point
//! clamped to the interval.
//!
//! - **Ball, oval (ellipsoid) and flat** in closed form: with
//!   `height(ρ) = k_h·(R − √(R² − ρ²))` (`k_h` = 1 for the ball, `RL/R` for the
//!   oval, 0 for the flat bottom) the stationary point is
//!   `σ* = q·Δz / √((k_h·L)² + Δz²)`. This is the branch-free kernel the
//!   whole grid runs through; it vectorises.
//! - **Bull-nose and V-bit** through a bracketed bisection on the
//!   derivative `−g + height'(ρ)·σ/ρ` (non-decreasing), after a cheap lower
//!   bound `min(zA, zB) + height(distance to the segment)` rejects the cells
//!   the segment cannot lower.
//!
//! - **Measured tools** ([`MeasuredTool`]): a lower surface piecewise
//!   linear in `ρ` but not convex, solved piece by piece in
//!   `sim/measured.rs`.
//!
//! Segments shorter than [`PLUNGE`] in XY are plunges: the cutter at `A`,
//! from the lower of the two heights.

use super::measured::MeasuredTool;
use crate::Cutter;

/// XY length below which a segment is a vertical plunge (mm).
pub const PLUNGE: f64 = 1e-12;

/// One straight segment, ready for evaluation.
#[derive(Clone, Copy, Debug)]
pub struct Prep {
    /// XY start.
    pub ax: f64,
    /// XY start.
    pub ay: f64,
    /// Unit XY direction (1, 0 for a plunge).
    pub ux: f64,
    /// Unit XY direction.
    pub uy: f64,
    /// XY length (0 for a plunge).
    pub len: f64,
    /// 1 / len (0 for a plunge).
    pub inv_len: f64,
    /// Tip height at the start (the lower end for a plunge).
    pub za: f64,
    /// Height change along the segment (0 for a plunge).
    pub dz: f64,
    /// Closed-form shapes: σ* = q·k.
    pub k: f64,
    /// Tip height at the start, where the cutter already is before the
    /// segment moves it (a rapid is not blamed for what it cuts there).
    pub z_start: f64,
}

impl Prep {
    /// The segment from tip position `a` to `b`.
    pub fn new(a: [f64; 3], b: [f64; 3], shape: &Shape<'_>) -> Prep {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = dx.hypot(dy);
        if len <= PLUNGE {
            return Prep {
                ax: a[0],
                ay: a[1],
                ux: 1.0,
                uy: 0.0,
                len: 0.0,
                inv_len: 0.0,
                za: a[2].min(b[2]),
                dz: 0.0,
                k: 0.0,
                z_start: a[2],
            };
        }
        let dz = b[2] - a[2];
        let k = match shape {
            Shape::Closed { hs, .. } if dz != 0.0 => dz / (hs * len).hypot(dz),
            _ => 0.0,
        };
        Prep { ax: a[0], ay: a[1], ux: dx / len, uy: dy / len, len, inv_len: 1.0 / len, za: a[2], dz, k, z_start: a[2] }
    }

    /// Lowest tip height along the segment.
    pub fn z_min(&self) -> f64 {
        self.za.min(self.za + self.dz)
    }
}

/// How a cutter's envelope is computed.
#[derive(Clone, Copy, Debug)]
pub enum Shape<'a> {
    /// `height(ρ) = hs·(R − √(R² − ρ²))`: ball (hs = 1), oval (hs = RL/R),
    /// flat (hs = 0).
    Closed {
        /// R.
        r: f64,
        /// R².
        r2: f64,
        /// Height scale.
        hs: f64,
    },
    /// Any other convex profile: bisection.
    General(Cutter),
    /// A measured tool's lower surface: piece by piece.
    Measured(&'a MeasuredTool),
}

impl Shape<'static> {
    /// The evaluation for `cutter`.
    pub fn of(cutter: &Cutter) -> Shape<'static> {
        let r = cutter.radius();
        let closed = |hs: f64| Shape::Closed { r, r2: r * r, hs };
        match cutter {
            Cutter::Ball(_) => closed(1.0),
            Cutter::Flat(_) => closed(0.0),
            Cutter::Oval(o) => closed(o.axial / r),
            Cutter::Bull(b) if b.corner == 0.0 => closed(0.0),
            Cutter::Bull(b) if b.corner == r => closed(1.0),
            _ => Shape::General(*cutter),
        }
    }
}

impl Shape<'_> {
    /// Cutter radius.
    pub fn radius(&self) -> f64 {
        match self {
            Shape::Closed { r, .. } => *r,
            Shape::General(c) => c.radius(),
            Shape::Measured(m) => m.radius(),
        }
    }
}

#[inline(always)]
pub(crate) fn fmin(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
    }
}

#[inline(always)]
pub(crate) fn fmax(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}

/// The closed-form envelope at `x` on a row whose offset from the segment's
/// start is `ey = y − ay`; `+∞` where the cutter does not reach.
#[inline(always)]
pub fn closed_at(p: &Prep, r: f64, r2: f64, hs: f64, x: f64, ey: f64) -> f64 {
    let dx = x - p.ax;
    let s = dx * p.ux + ey * p.uy;
    let w = ey * p.ux - dx * p.uy;
    let w2 = w * w;
    let q2 = r2 - w2;
    let q = fmax(q2, 0.0).sqrt();
    let lo = fmax(s - p.len, -q);
    let hi = fmin(s, q);
    let sigma = fmin(fmax(q * p.k, lo), hi);
    let rho2 = w2 + sigma * sigma;
    let height = hs * (r - fmax(r2 - rho2, 0.0).sqrt());
    let t = fmin(fmax((s - sigma) * p.inv_len, 0.0), 1.0);
    let z = p.za + p.dz * t + height;
    if q2 >= 0.0 && lo <= hi {
        z
    } else {
        f64::INFINITY
    }
}

/// Lowers `cells` (centres at `xs`) on one row to the closed-form envelope;
/// returns the most any cell was lowered when `TRACK` (else 0).
#[inline(always)]
fn closed_row_body<const TRACK: bool>(
    p: &Prep,
    r: f64,
    r2: f64,
    hs: f64,
    xs: &[f64],
    cells: &mut [f64],
    ey: f64,
) -> f64 {
    let mut deepest = 0.0f64;
    for (cell, &x) in cells.iter_mut().zip(xs) {
        let z = closed_at(p, r, r2, hs, x, ey);
        let old = *cell;
        if TRACK {
            // What the cutter standing at the start already occupies is
            // not the move's doing.
            let dx = x - p.ax;
            let d2 = dx * dx + ey * ey;
            let here = p.z_start + hs * (r - fmax(r2 - d2, 0.0).sqrt());
            let before = if d2 <= r2 { fmin(old, here) } else { old };
            deepest = fmax(deepest, before - z);
        }
        *cell = fmin(old, z);
    }
    deepest
}

/// The general envelope at `x` for a cell now at `current`: `None` when the
/// segment cannot lower it (out of reach, or the lower bound is not below).
pub fn general_at(c: &Cutter, p: &Prep, x: f64, ey: f64, current: f64) -> Option<f64> {
    let r = c.radius();
    let dx = x - p.ax;
    let s = dx * p.ux + ey * p.uy;
    let w = ey * p.ux - dx * p.uy;
    let w2 = w * w;
    let q2 = r * r - w2;
    if q2 < 0.0 {
        return None;
    }
    let along = s - s.clamp(0.0, p.len);
    let d2 = w2 + along * along;
    if d2 > r * r {
        return None;
    }
    // Lower bound: the lowest tip height, the nearest approach.
    if current <= p.z_min() + c.height(d2.sqrt()) {
        return None;
    }
    let q = q2.sqrt();
    let (mut lo, mut hi) = ((s - p.len).max(-q), s.min(q));
    if lo > hi {
        return None;
    }
    let value = |sigma: f64| {
        let t = ((s - sigma) * p.inv_len).clamp(0.0, 1.0);
        p.za + p.dz * t + c.height((w2 + sigma * sigma).sqrt())
    };
    if lo < hi {
        let g = p.dz * p.inv_len;
        // d/dσ of the envelope: non-decreasing.
        let derivative = |sigma: f64| {
            if sigma == 0.0 {
                return -g;
            }
            let rho = (w2 + sigma * sigma).sqrt();
            let d = -g + c.slope(rho) * (sigma / rho);
            if d.is_nan() {
                -g
            } else {
                d
            }
        };
        if derivative(lo) >= 0.0 {
            hi = lo;
        } else if derivative(hi) <= 0.0 {
            lo = hi;
        } else {
            let tol = 1e-12 * (1.0 + r);
            while hi - lo > tol {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                if derivative(mid) < 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
        }
    }
    let z = value(lo).min(value(hi));
    (z < current).then_some(z)
}

/// A band of grid rows being cut.
pub struct Band<'a> {
    /// The band's cells, `rows × nx`.
    pub cells: &'a mut [f64],
    /// Grid row of the band's first row.
    pub first: usize,
    /// Cells per row.
    pub nx: usize,
    /// X of every cell centre of a row.
    pub xs: &'a [f64],
    /// Grid origin.
    pub x0: f64,
    /// Grid origin.
    pub y0: f64,
    /// Cell size.
    pub res: f64,
}

/// What a segment evaluates: grid rows `rows`, along-track slab
/// `from ≤ s ≤ to`.
#[derive(Clone, Copy, Debug)]
pub struct Reach {
    /// First grid row.
    pub j0: usize,
    /// One past the last grid row.
    pub j1: usize,
    /// Slab start.
    pub from: f64,
    /// Slab end.
    pub to: f64,
}

/// Index range of the cell centres `lo ≤ origin + (i + ½)·res ≤ hi`,
/// clipped to `0..n`; empty when none.
#[inline(always)]
pub fn cell_range(lo: f64, hi: f64, origin: f64, res: f64, n: usize) -> std::ops::Range<usize> {
    let a = (lo - origin) / res - 0.5;
    let b = (hi - origin) / res - 0.5;
    // ceil(a) and floor(b) + 1, clipped, without libm calls.
    let a = if a > 0.0 {
        let t = a.min(1e18) as u64 as f64;
        if t < a {
            t + 1.0
        } else {
            t
        }
    } else {
        0.0
    };
    if b.is_nan() || b < 0.0 {
        return 0..0;
    }
    let b = (b.min(1e18) as u64 as f64 + 1.0).min(n as f64);
    if a >= b {
        return 0..0;
    }
    a as usize..b as usize
}

/// The X interval of the cells of row `y` that a segment evaluates: the
/// parallelogram `from ≤ s ≤ to`, `|w| ≤ r` (a superset of its footprint in
/// the slab; the kernels give nothing outside the footprint).
#[inline(always)]
pub(crate) fn row_span(p: &Prep, r: f64, reach: &Reach, y: f64, band: &Band) -> std::ops::Range<usize> {
    let ey = y - p.ay;
    let (mut a, mut b) = (f64::NEG_INFINITY, f64::INFINITY);
    // from ≤ ey·uy + dx·ux ≤ to and −r ≤ ey·ux − dx·uy ≤ r, dx = x − ax.
    let mut clip = |c0: f64, slope: f64, min: f64, max: f64| {
        if slope.abs() < 1e-300 {
            if c0 < min || c0 > max {
                a = f64::INFINITY;
            }
        } else {
            let (u, v) = ((min - c0) / slope, (max - c0) / slope);
            a = a.max(u.min(v));
            b = b.min(u.max(v));
        }
    };
    clip(ey * p.uy, p.ux, reach.from, reach.to);
    clip(ey * p.ux, -p.uy, -r, r);
    if a > b {
        return 0..0;
    }
    let margin = 1e-6 * band.res;
    cell_range(p.ax + a - margin, p.ax + b + margin, band.x0, band.res, band.nx)
}

#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn closed_rows_body<const TRACK: bool>(p: &Prep, r: f64, r2: f64, hs: f64, reach: &Reach, band: &mut Band) -> f64 {
    let mut deepest = 0.0f64;
    let rows = band.cells.len() / band.nx;
    let (j0, j1) = (reach.j0.max(band.first), reach.j1.min(band.first + rows));
    for j in j0..j1 {
        let y = band.y0 + (j as f64 + 0.5) * band.res;
        let span = row_span(p, r, reach, y, band);
        if span.is_empty() {
            continue;
        }
        let row = (j - band.first) * band.nx;
        let cells = &mut band.cells[row + span.start..row + span.end];
        let d = closed_row_body::<TRACK>(p, r, r2, hs, &band.xs[span], cells, y - p.ay);
        deepest = fmax(deepest, d);
    }
    deepest
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn closed_rows_avx2<const TRACK: bool>(
    p: &Prep,
    r: f64,
    r2: f64,
    hs: f64,
    reach: &Reach,
    band: &mut Band,
) -> f64 {
    // The same code compiled for AVX2 (four lanes); no `mul_add` in it, so
    // the results are bit-identical to the portable version.
    closed_rows_body::<TRACK>(p, r, r2, hs, reach, band)
}

/// Lowers the band's cells to a segment's closed-form envelope (ball,
/// oval, flat); returns the most any cell was lowered when `TRACK`.
pub fn closed_rows<const TRACK: bool>(p: &Prep, r: f64, r2: f64, hs: f64, reach: &Reach, band: &mut Band) -> f64 {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
            // SAFETY: the CPU has AVX2 and FMA, checked just above.
            return unsafe { closed_rows_avx2::<TRACK>(p, r, r2, hs, reach, band) };
        }
    }
    closed_rows_body::<TRACK>(p, r, r2, hs, reach, band)
}

/// Lowers the band's cells to a segment's envelope by the general solver;
/// returns the most any cell was lowered.
pub fn general_rows(c: &Cutter, p: &Prep, reach: &Reach, band: &mut Band) -> f64 {
    let r = c.radius();
    let mut deepest = 0.0f64;
    let rows = band.cells.len() / band.nx;
    let (j0, j1) = (reach.j0.max(band.first), reach.j1.min(band.first + rows));
    for j in j0..j1 {
        let y = band.y0 + (j as f64 + 0.5) * band.res;
        let span = row_span(p, r, reach, y, band);
        let row = (j - band.first) * band.nx;
        for i in span {
            let cell = &mut band.cells[row + i];
            if let Some(z) = general_at(c, p, band.xs[i], y - p.ay, *cell) {
                // As in the closed form: not blamed for the start.
                let d = (band.xs[i] - p.ax).hypot(y - p.ay);
                let before = if d <= r { cell.min(p.z_start + c.height(d)) } else { *cell };
                deepest = deepest.max(before - z);
                *cell = z;
            }
        }
    }
    deepest
}
