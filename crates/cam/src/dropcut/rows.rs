//! A ball end mill on a height grid, whole rows of CL points at once.
//!
//! The cutter-location surface of a ball of radius `R` over a triangulated
//! surface is made of pieces, one per triangle, edge and vertex: where the
//! ball touches a point `p` with its normal `n` (pointing up, `n_z > 0`),
//! its axis stands at `p_xy + R·n_xy`. Writing the normal through the
//! gradient `g` of a plane it is normal to, the axis stands at `p_xy +
//! φ(g)` with `φ(g) = −R·g / √(1 + |g|²)`. So
//!
//! - a **facet** with gradient `g` holds the ball where its touch point lies
//!   inside it: over the triangle moved by `φ(g)`, at its plane's height
//!   plus `R·(√(1 + |g|²) − 1)`;
//! - an **edge** holds it only where the ball's normal at the edge lies
//!   between the normals of its two triangles: its gradient then lies on the
//!   segment between theirs, and where the edge is a valley (the slope across
//!   it rises) no such ball stays above both triangles, so a valley edge
//!   holds nothing its triangles do not;
//! - a **vertex** holds it only with a gradient in the convex hull of its
//!   triangles' gradients (a plane through the vertex above all of them
//!   must be: were it outside, a direction would separate it, and the
//!   triangle in that direction would rise above the plane).
//!
//! On the grid's border the missing side is a cliff: the edge's and vertex's
//! gradients may grow without end outwards.
//!
//! The true contact of a ball at a CL point is one of these, so the CL
//! point's height is the largest of the pieces whose region covers it. Each
//! piece is drawn on the rows of CL points its region (a box over the
//! gradients it may take, slightly widened against rounding) crosses, with
//! the exact contact of `contact.rs` (the facet's in closed form). Where
//! the surface is smooth the facets' regions tile the plane once, and edges
//! and vertices cover thin bands between them: the work is about one
//! contact per CL point and one region per grid primitive, against
//! thousands of cells under the ball for a query of its own.

use kezuri_geom::{Heightfield, Vec3};
use rayon::prelude::*;

use super::contact::Probe;
use crate::cutter::{Ball, Profile};

/// Widening of every region, mm: a CL point on the border between two
/// regions is in both, whatever the rounding. A facet drawn this far
/// outside its triangle holds the ball at most this much times its slope
/// change too high — on the safe side.
const SLACK: f64 = 1e-9;

/// Node rows of the grid per piece of parallel work.
const CHUNK: usize = 32;

/// The ball's tip z at every `u` of every row `(v, us)`: rows run along X
/// at `y = v` (along Y at `x = v` when `along_y`). `us` of each row must be
/// ascending. `None` where no part of the grid lies within the ball's
/// radius. The same as [`Surface::drop_cutter_with`](super::Surface) on
/// the grid at every point, to rounding.
pub(crate) fn ball_rows(
    field: &Heightfield,
    ball: &Ball,
    along_y: bool,
    rows: &[(f64, &[f64])],
) -> Vec<Vec<Option<f64>>> {
    let grid = View { field, along_y };
    let mut order: Vec<usize> = (0..rows.len()).filter(|&k| rows[k].0.is_finite()).collect();
    order.sort_by(|&a, &b| rows[a].0.total_cmp(&rows[b].0));
    let targets: Vec<Target> = order.iter().map(|&k| Target::new(rows[k].0, rows[k].1)).collect();
    let starts: Vec<usize> = (0..grid.nv()).step_by(CHUNK).collect();
    let parts: Vec<(usize, Vec<Vec<f64>>)> =
        starts.par_iter().map(|&ja| draw_chunk(&grid, ball, &targets, ja, (ja + CHUNK).min(grid.nv()))).collect();
    let mut z: Vec<Vec<f64>> = targets.iter().map(|t| vec![f64::NEG_INFINITY; t.us.len()]).collect();
    for (first, part) in parts {
        for (row, drawn) in z[first..].iter_mut().zip(part) {
            for (a, b) in row.iter_mut().zip(drawn) {
                *a = a.max(b);
            }
        }
    }
    let mut out: Vec<Vec<Option<f64>>> = rows.iter().map(|(_, us)| vec![None; us.len()]).collect();
    for (&k, row) in order.iter().zip(z) {
        out[k] = row.into_iter().map(|z| (z > f64::NEG_INFINITY).then_some(z)).collect();
    }
    out
}

/// The grid in the frame of the rows: `u` along them, `v` across.
struct View<'a> {
    field: &'a Heightfield,
    along_y: bool,
}

impl View<'_> {
    fn nu(&self) -> usize {
        if self.along_y {
            self.field.ny()
        } else {
            self.field.nx()
        }
    }

    fn nv(&self) -> usize {
        if self.along_y {
            self.field.nx()
        } else {
            self.field.ny()
        }
    }

    fn u(&self, i: usize) -> f64 {
        if self.along_y {
            self.field.y(i)
        } else {
            self.field.x(i)
        }
    }

    fn v(&self, j: usize) -> f64 {
        if self.along_y {
            self.field.x(j)
        } else {
            self.field.y(j)
        }
    }

    #[inline]
    fn z(&self, i: usize, j: usize) -> f64 {
        if self.along_y {
            self.field.z(j, i)
        } else {
            self.field.z(i, j)
        }
    }

    #[inline]
    fn node(&self, i: usize, j: usize) -> Vec3 {
        Vec3::new(self.u(i), self.v(j), self.z(i, j))
    }

    /// Gradient of the triangle `(i, j) (i+1, j) (i+1, j+1)` of cell `(i, j)`.
    /// (The grid's diagonal runs from `(i, j)` to `(i+1, j+1)` in either
    /// frame, so the triangles are the grid's own.)
    #[inline]
    fn lower(&self, i: usize, j: usize) -> [f64; 2] {
        let s = self.field.step();
        [(self.z(i + 1, j) - self.z(i, j)) / s, (self.z(i + 1, j + 1) - self.z(i + 1, j)) / s]
    }

    /// Gradient of the triangle `(i, j) (i+1, j+1) (i, j+1)` of cell `(i, j)`.
    #[inline]
    fn upper(&self, i: usize, j: usize) -> [f64; 2] {
        let s = self.field.step();
        [(self.z(i + 1, j + 1) - self.z(i, j + 1)) / s, (self.z(i, j + 1) - self.z(i, j)) / s]
    }
}

/// One row of CL points.
struct Target<'a> {
    v: f64,
    us: &'a [f64],
    /// `us[0]` and the inverse of the mean spacing, to guess an index.
    u0: f64,
    per_mm: f64,
}

impl<'a> Target<'a> {
    fn new(v: f64, us: &'a [f64]) -> Target<'a> {
        debug_assert!(us.windows(2).all(|w| w[0] <= w[1]), "positions along a row must ascend");
        let (u0, per_mm) = match us {
            [first, .., last] if last > first => (*first, (us.len() - 1) as f64 / (last - first)),
            _ => (us.first().copied().unwrap_or(0.0), 0.0),
        };
        Target { v, us, u0, per_mm }
    }

    /// The first index whose `u` is at least `u`.
    #[inline]
    fn first_at(&self, u: f64) -> usize {
        let n = self.us.len();
        let guess = ((u - self.u0) * self.per_mm).floor();
        let mut k = if guess.is_nan() || guess <= 0.0 { 0 } else { (guess as usize).min(n) };
        for _ in 0..8 {
            if k > 0 && self.us[k - 1] >= u {
                k -= 1;
            } else if k < n && self.us[k] < u {
                k += 1;
            } else {
                return k;
            }
        }
        self.us.partition_point(|&x| x < u)
    }
}

/// The rows a chunk of the grid can reach, and their heights so far.
struct Canvas<'t, 'a> {
    targets: &'t [Target<'a>],
    z: Vec<Vec<f64>>,
}

impl Canvas<'_, '_> {
    /// For every CL point of the rows with `v` in `[vlo, vhi]` whose `u` is
    /// in `span(v)` (both widened by [`SLACK`]): `offer(u, v, z)`.
    #[inline]
    fn draw(
        &mut self,
        [vlo, vhi]: [f64; 2],
        span: impl Fn(f64) -> [f64; 2],
        mut offer: impl FnMut(f64, f64, &mut f64),
    ) {
        let (vlo, vhi) = (vlo - SLACK, vhi + SLACK);
        let first = self.targets.partition_point(|t| t.v < vlo);
        for (t, z) in self.targets[first..].iter().zip(&mut self.z[first..]) {
            if t.v > vhi {
                break;
            }
            let [ulo, uhi] = span(t.v);
            let mut k = t.first_at(ulo - SLACK);
            while k < t.us.len() && t.us[k] <= uhi + SLACK {
                offer(t.us[k], t.v, &mut z[k]);
                k += 1;
            }
        }
    }
}

/// The gradients a piece may take, as a box: each component's range and
/// the largest squared length.
#[derive(Clone, Copy)]
struct Gradients {
    lo: [f64; 2],
    hi: [f64; 2],
    len2: f64,
}

impl Gradients {
    fn of(gs: &[[f64; 2]]) -> Gradients {
        let mut b = Gradients { lo: [f64::INFINITY; 2], hi: [f64::NEG_INFINITY; 2], len2: 0.0 };
        for g in gs {
            for (k, &gk) in g.iter().enumerate() {
                b.lo[k] = b.lo[k].min(gk);
                b.hi[k] = b.hi[k].max(gk);
            }
            b.len2 = b.len2.max(g[0] * g[0] + g[1] * g[1]);
        }
        b
    }

    /// The grid ends on this side of the piece (`axis` 0: u, 1: v; `up`:
    /// the grid lies towards larger values): a cliff, so the gradient may
    /// grow without end towards the grid.
    fn open(mut self, axis: usize, up: bool) -> Gradients {
        if up {
            self.hi[axis] = f64::INFINITY;
        } else {
            self.lo[axis] = f64::NEG_INFINITY;
        }
        self.len2 = f64::INFINITY;
        self
    }

    /// The range of the axis's offset `φ_k(g) = −R·g_k / √(1 + |g|²)` over
    /// the box.
    fn offsets(&self, r: f64, axis: usize) -> [f64; 2] {
        let (a, b) = (self.lo[axis], self.hi[axis]);
        // g / √(1 + g²) bounds g_k / √(1 + |g|²) away from zero, g_k / √(1 + len2) towards it.
        let far = |g: f64| if g.is_infinite() { g.signum() } else { g / (1.0 + g * g).sqrt() };
        let near = |g: f64| if self.len2.is_infinite() { 0.0 } else { g / (1.0 + self.len2).sqrt() };
        let lo = if a >= 0.0 { near(a) } else { far(a) };
        let hi = if b <= 0.0 { near(b) } else { far(b) };
        [-r * hi, -r * lo]
    }

    /// Both axes' offset ranges.
    fn reach(&self, r: f64) -> [[f64; 2]; 2] {
        [self.offsets(r, 0), self.offsets(r, 1)]
    }
}

/// Draws every piece of node rows `ja..jb` (their vertices and edges along
/// the rows, and the cells above them with their edges across and
/// diagonal) on the rows within the ball's radius of them; returns the
/// index of the first of those rows and their heights.
fn draw_chunk(grid: &View, ball: &Ball, targets: &[Target], ja: usize, jb: usize) -> (usize, Vec<Vec<f64>>) {
    let r = ball.radius();
    let (nu, nv) = (grid.nu(), grid.nv());
    let (vlo, vhi) = (grid.v(ja) - r - 2.0 * SLACK, grid.v(jb.min(nv - 1)) + r + 2.0 * SLACK);
    let first = targets.partition_point(|t| t.v < vlo);
    let end = first + targets[first..].partition_point(|t| t.v <= vhi);
    let targets = &targets[first..end];
    let mut canvas = Canvas { targets, z: targets.iter().map(|t| vec![f64::NEG_INFINITY; t.us.len()]).collect() };
    if targets.is_empty() {
        return (first, canvas.z);
    }
    let s = grid.field.step();
    let r2 = r * r;
    let vertex_at = |p: Vec3| {
        move |u: f64, v: f64, z: &mut f64| {
            let (du, dv) = (p.x - u, p.y - v);
            let d2 = du * du + dv * dv;
            if d2 <= r2 && p.z > *z {
                *z = z.max(p.z - ball.height_sq(d2));
            }
        }
    };
    let edge_at = |a: Vec3, b: Vec3| {
        move |u: f64, v: f64, z: &mut f64| {
            let mut probe = Probe::new(ball, u, v);
            probe.best = *z;
            probe.edge(a, b);
            *z = probe.best;
        }
    };
    for j in ja..jb {
        let (vj, cell_row) = (grid.v(j), j + 1 < nv);
        for i in 0..nu {
            let ui = grid.u(i);
            let p = grid.node(i, j);
            // The vertex: the gradients of its up to six triangles.
            let mut around = [[0.0; 2]; 6];
            let mut n = 0;
            let mut put = |g: [f64; 2]| {
                around[n] = g;
                n += 1;
            };
            if i > 0 && j > 0 {
                put(grid.lower(i - 1, j - 1));
                put(grid.upper(i - 1, j - 1));
            }
            if j > 0 && i + 1 < nu {
                put(grid.upper(i, j - 1));
            }
            if i > 0 && cell_row {
                put(grid.lower(i - 1, j));
            }
            if i + 1 < nu && cell_row {
                put(grid.lower(i, j));
                put(grid.upper(i, j));
            }
            let mut cone = Gradients::of(&around[..n]);
            for (border, axis, up) in
                [(i == 0, 0, true), (i + 1 == nu, 0, false), (j == 0, 1, true), (!cell_row, 1, false)]
            {
                if border {
                    cone = cone.open(axis, up);
                }
            }
            let [du, dv] = cone.reach(r);
            canvas.draw([vj + dv[0], vj + dv[1]], |_| [ui + du[0], ui + du[1]], vertex_at(p));
            // The edge along the row to (i+1, j): triangles below and above.
            if i + 1 < nu {
                let below = (j > 0).then(|| grid.upper(i, j - 1));
                let above = cell_row.then(|| grid.lower(i, j));
                let cone = match (below, above) {
                    (Some(b), Some(a)) => (a[1] <= b[1]).then(|| Gradients::of(&[a, b])),
                    (None, Some(a)) => Some(Gradients::of(&[a]).open(1, true)),
                    (Some(b), None) => Some(Gradients::of(&[b]).open(1, false)),
                    (None, None) => None,
                };
                if let Some(cone) = cone {
                    let [du, dv] = cone.reach(r);
                    let q = grid.node(i + 1, j);
                    canvas.draw([vj + dv[0], vj + dv[1]], |_| [ui + du[0], ui + s + du[1]], edge_at(p, q));
                }
            }
            if !cell_row {
                continue;
            }
            // The edge across the rows to (i, j+1): triangles left and right.
            let left = (i > 0).then(|| grid.lower(i - 1, j));
            let right = (i + 1 < nu).then(|| grid.upper(i, j));
            let cone = match (left, right) {
                (Some(l), Some(rt)) => (rt[0] <= l[0]).then(|| Gradients::of(&[l, rt])),
                (None, Some(rt)) => Some(Gradients::of(&[rt]).open(0, true)),
                (Some(l), None) => Some(Gradients::of(&[l]).open(0, false)),
                (None, None) => None,
            };
            let q = grid.node(i, j + 1);
            if let Some(cone) = cone {
                let [du, dv] = cone.reach(r);
                canvas.draw([vj + dv[0], vj + s + dv[1]], |_| [ui + du[0], ui + du[1]], edge_at(p, q));
            }
            if i + 1 == nu {
                continue;
            }
            let (lower, upper) = (grid.lower(i, j), grid.upper(i, j));
            // The diagonal to (i+1, j+1): a ridge when the slope across it,
            // from the upper triangle to the lower, falls.
            if (lower[0] - upper[0]) - (lower[1] - upper[1]) <= 0.0 {
                let [du, dv] = Gradients::of(&[lower, upper]).reach(r);
                let c = grid.node(i + 1, j + 1);
                let along = |v: f64, dv: f64| (v - vj - dv).clamp(0.0, s);
                canvas.draw(
                    [vj + dv[0], vj + s + dv[1]],
                    |v| [ui + along(v, dv[1]) + du[0], ui + along(v, dv[0]) + du[1]],
                    edge_at(p, c),
                );
            }
            // The two facets, each over its triangle moved by φ(g).
            for (g, is_lower) in [(lower, true), (upper, false)] {
                let len2 = g[0] * g[0] + g[1] * g[1];
                let root = (1.0 + len2).sqrt();
                let (ou, ov) = (-r * g[0] / root, -r * g[1] / root);
                // R·(√(1 + |g|²) − 1), written to keep its digits.
                let lift = r * len2 / (root + 1.0);
                let across = |v: f64| (v - vj - ov).clamp(0.0, s);
                canvas.draw(
                    [vj + ov, vj + s + ov],
                    |v| {
                        if is_lower {
                            [ui + ou + across(v), ui + ou + s]
                        } else {
                            [ui + ou, ui + ou + across(v)]
                        }
                    },
                    |u, v, z| *z = z.max(p.z + g[0] * (u - ui) + g[1] * (v - vj) + lift),
                );
            }
        }
    }
    (first, canvas.z)
}
