//! The three contacts of a cutter dropped on a triangle: vertex, facet
//! (interior) and edge, each exact.
//!
//! With the cutter's axis at `c`, a surface point `p` at XY distance
//! `r ≤ R` holds the tip at or above `p.z − height(r)`; the cutter-location
//! z is the largest of these over the triangle's part inside the disk. That
//! function is concave (a linear height minus a convex profile of a convex
//! distance), so its maximum over the convex part of the triangle is either
//! the unconstrained one inside the facet ([`Probe::facet`]) or lies on the
//! boundary: on an edge ([`Probe::edge`]) or at a vertex ([`Probe::vertex`]).

use kezuri_geom::{Triangle, Vec3};

use crate::cutter::Cutter;

/// A cutter held at `(x, y)` and the highest tip z found so far.
pub(crate) struct Probe<'a> {
    cutter: &'a Cutter,
    x: f64,
    y: f64,
    radius: f64,
    r2: f64,
    /// The highest tip z so far; `-∞` until something is under the cutter.
    pub best: f64,
}

impl<'a> Probe<'a> {
    pub fn new(cutter: &'a Cutter, x: f64, y: f64) -> Probe<'a> {
        let radius = cutter.radius();
        Probe { cutter, x, y, radius, r2: radius * radius, best: f64::NEG_INFINITY }
    }

    pub fn centre(&self) -> [f64; 2] {
        [self.x, self.y]
    }

    pub fn radius(&self) -> f64 {
        self.radius
    }

    pub fn result(&self) -> Option<f64> {
        (self.best > f64::NEG_INFINITY).then_some(self.best)
    }

    /// Whether a part of the surface whose XY box is `b` and whose highest
    /// point is `top` could hold the cutter higher than `best`.
    #[inline]
    pub fn may_win(&self, b: &[f64; 4], top: f64) -> bool {
        if top <= self.best {
            return false;
        }
        let dx = (b[0] - self.x).max(self.x - b[2]).max(0.0);
        let dy = (b[1] - self.y).max(self.y - b[3]).max(0.0);
        let d2 = dx * dx + dy * dy;
        d2 <= self.r2 && top - self.cutter.height(d2.sqrt()) > self.best
    }

    #[inline]
    fn offer(&mut self, z: f64) {
        if z > self.best {
            self.best = z;
        }
    }

    /// Vertex contact: the cutter's profile on the point `p`.
    #[inline]
    pub fn vertex(&mut self, p: Vec3) {
        if p.z <= self.best {
            return;
        }
        let (dx, dy) = (p.x - self.x, p.y - self.y);
        let d2 = dx * dx + dy * dy;
        if d2 <= self.r2 {
            self.offer(p.z - self.cutter.height(d2.sqrt()));
        }
    }

    /// Facet contact: where a plane of the triangle's gradient touches the
    /// cutter, if that point lies inside the triangle.
    #[inline]
    pub fn facet(&mut self, t: &Triangle) {
        let mut n = t.normal();
        if n.z < 0.0 {
            n = n * -1.0;
        }
        if n.z.is_nan() || n.z <= 0.0 {
            return; // a vertical wall: its edges and vertices hold the cutter
        }
        // z = v0.z + a (x − v0.x) + b (y − v0.y), rising by g along (a, b).
        let (a, b) = (-n.x / n.z, -n.y / n.z);
        let g = (a * a + b * b).sqrt();
        if !g.is_finite() {
            return; // vertical to within rounding: as a wall
        }
        let r = self.cutter.facet_radius(g);
        let (qx, qy) = if g > 0.0 && r > 0.0 { (self.x + a * (r / g), self.y + b * (r / g)) } else { (self.x, self.y) };
        // Inside (or on the boundary): on the same side of all three edges,
        // whichever way the corners turn.
        let [p0, p1, p2] = t.v;
        let side = |u: Vec3, v: Vec3| (v.x - u.x) * (qy - u.y) - (v.y - u.y) * (qx - u.x);
        let (s0, s1, s2) = (side(p0, p1), side(p1, p2), side(p2, p0));
        let inside = (s0 >= 0.0 && s1 >= 0.0 && s2 >= 0.0) || (s0 <= 0.0 && s1 <= 0.0 && s2 <= 0.0);
        if inside {
            let z = p0.z + a * (qx - p0.x) + b * (qy - p0.y);
            self.offer(z - self.cutter.height(r));
        }
    }

    /// Edge contact: the highest tip z over the points of the segment
    /// `p0 p1` within the cutter's radius.
    #[inline]
    pub fn edge(&mut self, p0: Vec3, p1: Vec3) {
        if p0.z.max(p1.z) <= self.best {
            return;
        }
        let (ex, ey) = (p1.x - p0.x, p1.y - p0.y);
        let len2 = ex * ex + ey * ey;
        if len2.is_nan() || len2 <= 0.0 {
            return; // vertical: its upper vertex is the contact
        }
        let len = len2.sqrt();
        let (ux, uy) = (ex / len, ey / len);
        let (wx, wy) = (self.x - p0.x, self.y - p0.y);
        // The foot of the axis on the edge's line, `t0` along it from p0, at
        // distance `d`; the cutter meets the line for |x| ≤ s about the foot.
        let t0 = wx * ux + wy * uy;
        let d = (wx * uy - wy * ux).abs();
        if d.is_nan() || d > self.radius {
            return;
        }
        let s = ((self.radius - d) * (self.radius + d)).sqrt();
        let (lo, hi) = ((-t0).max(-s), (len - t0).min(s));
        if lo.is_nan() || hi.is_nan() || lo > hi || p0.z.max(p1.z) - self.cutter.height(d) <= self.best {
            return;
        }
        let m = (p1.z - p0.z) / len;
        let x = edge_argmax(self.cutter, d, s, m, lo, hi);
        let t = (t0 + x).clamp(0.0, len);
        let z =
            if t <= 0.5 * len { p0.z + (p1.z - p0.z) * (t / len) } else { p1.z + (p0.z - p1.z) * ((len - t) / len) };
        self.offer(z - self.cutter.height((x * x + d * d).sqrt()));
    }
}

/// The `x` in `[lo, hi]` (a part of `[−s, s]`, `s = √(R² − d²)`) that
/// maximises `m·x − height(√(x² + d²))`: the contact along an edge of slope
/// `m` whose line passes at distance `d` from the axis. Closed forms where
/// the vertical slice of the cutter is a conic (flat: a segment; ball: a
/// circle; oval: an ellipse; V-bit: a hyperbola); the bull's torus slice
/// goes to [`edge_argmax_numeric`].
#[inline]
pub(crate) fn edge_argmax(cutter: &Cutter, d: f64, s: f64, m: f64, lo: f64, hi: f64) -> f64 {
    let x = match cutter {
        Cutter::Flat(_) => {
            if m > 0.0 {
                hi
            } else if m < 0.0 {
                lo
            } else {
                0.0
            }
        }
        // m·x + √(s² − x²): x = m·s / √(1 + m²).
        Cutter::Ball(_) => m * s / (1.0 + m * m).sqrt(),
        // m·x + (b/a)·√(s² − x²): the ball's case with m scaled by a/b.
        Cutter::Oval(o) => {
            let k = m * cutter.radius() / o.axial;
            k * s / (1.0 + k * k).sqrt()
        }
        // m·x − rise·√(x² + d²): x/ρ = m/rise inside the cone, else an end.
        Cutter::Vee(_) => {
            let q = m / cutter.slope(0.0);
            if q >= 1.0 {
                hi
            } else if q <= -1.0 {
                lo
            } else {
                d * q / ((1.0 - q) * (1.0 + q)).sqrt()
            }
        }
        Cutter::Bull(_) => return edge_argmax_numeric(cutter, d, m, lo, hi),
    };
    x.clamp(lo, hi)
}

/// [`edge_argmax`] for any convex profile: the root of the non-decreasing
/// derivative `g(x) = height′(ρ)·x/ρ − m` (ρ = √(x² + d²)) bracketed in
/// `[lo, hi]`, by regula falsi with the Illinois modification, falling back
/// to bisection where `g` is infinite (the rim of a ball or a torus) or the
/// bracket shrinks too slowly; stops at a bracket of 1e-12 mm (relative to
/// the size of `x`).
pub(crate) fn edge_argmax_numeric(cutter: &Cutter, d: f64, m: f64, lo: f64, hi: f64) -> f64 {
    let g = |x: f64| {
        let rho = (x * x + d * d).sqrt();
        if rho > 0.0 {
            cutter.slope(rho) * (x / rho) - m
        } else {
            -m
        }
    };
    let (mut a, mut b) = (lo, hi);
    let (mut ga, mut gb) = (g(a), g(b));
    if ga.is_nan() || ga >= 0.0 {
        return a;
    }
    if gb.is_nan() || gb <= 0.0 {
        return b;
    }
    let mut last_side = 0i8;
    for step in 0..200 {
        let width = b - a;
        if width <= 1e-12 * (1.0 + a.abs().max(b.abs())) {
            break;
        }
        let mid = 0.5 * (a + b);
        let mut x = if ga.is_finite() && gb.is_finite() && step % 4 != 3 { (a * gb - b * ga) / (gb - ga) } else { mid };
        if !(x > a && x < b) {
            x = mid;
        }
        let gx = g(x);
        if gx < 0.0 {
            a = x;
            ga = gx;
            if last_side == -1 {
                gb *= 0.5;
            }
            last_side = -1;
        } else if gx > 0.0 {
            b = x;
            gb = gx;
            if last_side == 1 {
                ga *= 0.5;
            }
            last_side = 1;
        } else {
            return x;
        }
    }
    0.5 * (a + b)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shapes() -> Vec<Cutter> {
        ["flat:6", "ball:6", "bull:10,2", "bull:8,4", "bull:8,0", "oval:16,24", "oval:16,4", "v:6,90", "v:10,30"]
            .iter()
            .map(|s| s.parse().unwrap())
            .collect()
    }

    /// The closed forms and the generic solver find the same maximum.
    #[test]
    fn closed_forms_agree_with_the_numeric_solver() {
        let mut seed = 7u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for c in shapes() {
            let r = c.radius();
            for _ in 0..2000 {
                let d = r * next();
                let s = ((r - d) * (r + d)).sqrt();
                let m = (next() - 0.5) * 8.0;
                let (u, v) = (-s + 2.0 * s * next(), -s + 2.0 * s * next());
                let (lo, hi) = (u.min(v), u.max(v));
                let f = |x: f64| m * x - c.height(x.hypot(d));
                let exact = f(edge_argmax(&c, d, s, m, lo, hi));
                let numeric = f(edge_argmax_numeric(&c, d, m, lo, hi));
                assert!((exact - numeric).abs() < 1e-9, "{c} d={d} m={m} [{lo}, {hi}]: {exact} vs {numeric}");
                // And nothing sampled beats them.
                let sampled = (0..=1000).map(|k| f(lo + (hi - lo) * k as f64 / 1000.0)).fold(f64::MIN, f64::max);
                assert!(exact >= sampled - 1e-12, "{c}: {exact} < {sampled}");
            }
        }
    }
}
