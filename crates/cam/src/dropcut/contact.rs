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

use crate::cutter::Profile;

/// The cutter resting on a whole plane: see [`Probe::plane`].
pub(crate) struct Plane {
    /// Where it touches, in XY.
    pub touch: [f64; 2],
    /// The tip's z.
    pub tip: f64,
}

/// A cutter of shape `P` held at `(x, y)` and the highest tip z found so
/// far.
pub(crate) struct Probe<'a, P: Profile> {
    cutter: &'a P,
    x: f64,
    y: f64,
    radius: f64,
    r2: f64,
    /// The highest tip z so far; `-∞` until something is under the cutter.
    pub best: f64,
}

impl<'a, P: Profile> Probe<'a, P> {
    pub fn new(cutter: &'a P, x: f64, y: f64) -> Probe<'a, P> {
        let radius = cutter.radius();
        Probe { cutter, x, y, radius, r2: radius * radius, best: f64::NEG_INFINITY }
    }

    /// The cutter's height at distance `r` (≥ 0) from its axis.
    #[inline]
    fn height(&self, r: f64) -> f64 {
        self.cutter.height(r.min(self.radius))
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

    /// The highest a part of the surface whose XY box is `b` and whose
    /// highest point is `top` could hold the cutter: `top` less the
    /// cutter's height at the box's nearest point; `None` when the box is
    /// outside the cutter's disk.
    #[inline]
    pub fn bound(&self, b: &[f64; 4], top: f64) -> Option<f64> {
        let dx = (b[0] - self.x).max(self.x - b[2]).max(0.0);
        let dy = (b[1] - self.y).max(self.y - b[3]).max(0.0);
        let d2 = dx * dx + dy * dy;
        (d2 <= self.r2).then(|| top - self.cutter.height_sq(d2))
    }

    /// Whether a part of the surface whose XY box is `b` and whose highest
    /// point is `top` could hold the cutter higher than `best`.
    #[inline]
    pub fn may_win(&self, b: &[f64; 4], top: f64) -> bool {
        top > self.best && self.bound(b, top).is_some_and(|z| z > self.best)
    }

    /// The square of the farthest distance from the axis at which a point
    /// no higher than `top` can still raise the cutter above `best`.
    #[inline]
    pub fn reach2(&self, top: f64) -> f64 {
        let r = self.cutter.reach(top - self.best);
        r * r
    }

    /// A contact found: the tip at `z`.
    #[inline]
    pub fn offer(&mut self, z: f64) {
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
            self.offer(p.z - self.cutter.height_sq(d2));
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
        // z = v0.z + a (x − v0.x) + b (y − v0.y).
        let (a, b) = (-n.x / n.z, -n.y / n.z);
        let [p0, p1, p2] = t.v;
        let Some(plane) = self.plane(a, b, p0.z + a * (self.x - p0.x) + b * (self.y - p0.y)) else {
            return; // vertical to within rounding: as a wall
        };
        // Inside (or on the boundary): on the same side of all three edges,
        // whichever way the corners turn.
        let [qx, qy] = plane.touch;
        let side = |u: Vec3, v: Vec3| (v.x - u.x) * (qy - u.y) - (v.y - u.y) * (qx - u.x);
        let (s0, s1, s2) = (side(p0, p1), side(p1, p2), side(p2, p0));
        if (s0 >= 0.0 && s1 >= 0.0 && s2 >= 0.0) || (s0 <= 0.0 && s1 <= 0.0 && s2 <= 0.0) {
            self.offer(plane.tip);
        }
    }

    /// The cutter on the whole plane `z = z0 + a (x − x) + b (y − y)` (`z0`
    /// its height on the axis): where it touches and the tip's z there.
    /// No part of the plane within the cutter's radius holds the tip
    /// higher (`tip` is the largest `z0 + g·r − height(r)`, `g` the
    /// plane's gradient), so it bounds every contact of a triangle in that
    /// plane. `None` for a plane too steep to be finite.
    #[inline]
    pub fn plane(&self, a: f64, b: f64, z0: f64) -> Option<Plane> {
        let g = (a * a + b * b).sqrt();
        if !(g.is_finite() && z0.is_finite()) {
            return None;
        }
        let r = self.cutter.facet_radius(g);
        let touch = if g > 0.0 && r > 0.0 { [self.x + a * (r / g), self.y + b * (r / g)] } else { [self.x, self.y] };
        Some(Plane { touch, tip: z0 + g * r - self.height(r) })
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
        if lo.is_nan() || hi.is_nan() || lo > hi || p0.z.max(p1.z) - self.height(d) <= self.best {
            return;
        }
        let m = (p1.z - p0.z) / len;
        let x = self.cutter.edge_argmax(d, s, m, lo, hi).clamp(lo, hi);
        let t = (t0 + x).clamp(0.0, len);
        let z =
            if t <= 0.5 * len { p0.z + (p1.z - p0.z) * (t / len) } else { p1.z + (p0.z - p1.z) * ((len - t) / len) };
        self.offer(z - self.height((x * x + d * d).sqrt()));
    }
}
