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

use kezuri_geom::{Heightfield, Slopes, Vec3, BLOCK};
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
    // Each row: the highest of what every chunk drew on it.
    let drawn: Vec<Vec<Option<f64>>> = (0..targets.len())
        .into_par_iter()
        .map(|k| {
            let mut z = vec![f64::NEG_INFINITY; targets[k].us.len()];
            for (first, part) in &parts {
                if let Some(row) = k.checked_sub(*first).and_then(|i| part.get(i)) {
                    for (a, &b) in z.iter_mut().zip(row) {
                        *a = a.max(b);
                    }
                }
            }
            z.into_iter().map(|z| (z > f64::NEG_INFINITY).then_some(z)).collect()
        })
        .collect();
    let mut out: Vec<Vec<Option<f64>>> = rows.iter().map(|_| Vec::new()).collect();
    for (&k, row) in order.iter().zip(drawn) {
        out[k] = row;
    }
    for (row, (_, us)) in out.iter_mut().zip(rows) {
        row.resize(us.len(), None);
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

    /// Where the pieces of nodes `i0..i1`, `j0..j1` (their vertices, edges
    /// and cells) may hold a ball of radius `r`: the box of their nodes
    /// moved by the offsets of every gradient of the cells around them.
    fn block_region(&self, [i0, i1]: [usize; 2], [j0, j1]: [usize; 2], r: f64) -> [[f64; 2]; 2] {
        let (nu, nv) = (self.nu(), self.nv());
        let (cells_u, cells_v) = ((nu - 1).div_ceil(BLOCK), (nv - 1).div_ceil(BLOCK));
        let (bu, bv) = (i0 / BLOCK, j0 / BLOCK);
        let mut s = Slopes::NONE;
        for b in [bv.wrapping_sub(1), bv] {
            for a in [bu.wrapping_sub(1), bu] {
                if a < cells_u && b < cells_v {
                    s = s.union(if self.along_y {
                        self.field.block_slopes(b, a).transposed()
                    } else {
                        self.field.block_slopes(a, b)
                    });
                }
            }
        }
        let [du, dv] = reach(borders(s, [i0 == 0, i1 == nu, j0 == 0, j1 == nv]), r);
        [[self.u(i0) + du[0], self.u(i1.min(nu - 1)) + du[1]], [self.v(j0) + dv[0], self.v(j1.min(nv - 1)) + dv[1]]]
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
        let k = if guess.is_nan() || guess <= 0.0 { 0 } else { (guess as usize).min(n) };
        self.first_near(u, k).unwrap_or_else(|| self.us.partition_point(|&x| x < u))
    }

    /// [`Target::first_at`] found within 8 steps of index `k`.
    #[inline]
    fn first_near(&self, u: f64, mut k: usize) -> Option<usize> {
        let n = self.us.len();
        for _ in 0..8 {
            if k > 0 && self.us[k - 1] >= u {
                k -= 1;
            } else if k < n && self.us[k] < u {
                k += 1;
            } else {
                return Some(k);
            }
        }
        None
    }
}

/// The rows a chunk of the grid can reach, and their heights so far.
struct Canvas<'t, 'a> {
    targets: &'t [Target<'a>],
    z: Vec<Vec<f64>>,
    /// Where the last piece drawn on each row began: the next, its
    /// neighbour, begins near it.
    near: Vec<usize>,
}

impl Canvas<'_, '_> {
    /// Whether a CL point lies in the box `[[ulo, uhi], [vlo, vhi]]`
    /// (widened by [`SLACK`]).
    fn any(&self, [[ulo, uhi], [vlo, vhi]]: [[f64; 2]; 2]) -> bool {
        let first = self.targets.partition_point(|t| t.v < vlo - SLACK);
        self.targets[first..].iter().take_while(|t| t.v <= vhi + SLACK).any(|t| {
            let k = t.first_at(ulo - SLACK);
            k < t.us.len() && t.us[k] <= uhi + SLACK
        })
    }

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
        for ((t, z), near) in self.targets[first..].iter().zip(&mut self.z[first..]).zip(&mut self.near[first..]) {
            if t.v > vhi {
                break;
            }
            let [ulo, uhi] = span(t.v);
            let u = ulo - SLACK;
            let mut k = t.first_near(u, *near).unwrap_or_else(|| t.first_at(u));
            *near = k;
            while k < t.us.len() && t.us[k] <= uhi + SLACK {
                offer(t.us[k], t.v, &mut z[k]);
                k += 1;
            }
        }
    }
}

/// The grid ends on this side of a piece (`axis` 0: u, 1: v; `up`: the
/// grid lies towards larger values): a cliff, so the piece's gradient may
/// grow without end towards the grid.
fn open(mut s: Slopes, axis: usize, up: bool) -> Slopes {
    if up {
        s.hi[axis] = f64::INFINITY;
    } else {
        s.lo[axis] = f64::NEG_INFINITY;
    }
    s.len2 = f64::INFINITY;
    s
}

/// The range of the axis's offset `φ_k(g) = −R·g_k / √(1 + |g|²)` over
/// the gradients `s` holds.
fn offsets(s: Slopes, r: f64, axis: usize) -> [f64; 2] {
    let (a, b) = (s.lo[axis], s.hi[axis]);
    // g / √(1 + g²) bounds g_k / √(1 + |g|²) away from zero, g_k / √(1 + len2) towards it.
    let far = |g: f64| if g.is_infinite() { g.signum() } else { g / (1.0 + g * g).sqrt() };
    let near = |g: f64| if s.len2.is_infinite() { 0.0 } else { g / (1.0 + s.len2).sqrt() };
    let lo = if a >= 0.0 { near(a) } else { far(a) };
    let hi = if b <= 0.0 { near(b) } else { far(b) };
    [-r * hi, -r * lo]
}

/// `s` opened (see [`open`]) where a piece lies on the grid's first or
/// last column, first or last row.
fn borders(s: Slopes, [first_u, last_u, first_v, last_v]: [bool; 4]) -> Slopes {
    let mut s = s;
    for (border, axis, up) in [(first_u, 0, true), (last_u, 0, false), (first_v, 1, true), (last_v, 1, false)] {
        if border {
            s = open(s, axis, up);
        }
    }
    s
}

/// Both axes' offset ranges.
fn reach(s: Slopes, r: f64) -> [[f64; 2]; 2] {
    [offsets(s, r, 0), offsets(s, r, 1)]
}

/// The gradients of some triangles.
fn slopes(gs: &[[f64; 2]]) -> Slopes {
    gs.iter().fold(Slopes::NONE, |s, &g| s.with(g))
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
    let z = targets.iter().map(|t| vec![f64::NEG_INFINITY; t.us.len()]).collect();
    let mut canvas = Canvas { targets, z, near: vec![0; targets.len()] };
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
    for j0 in (ja..jb).step_by(BLOCK) {
        let j1 = (j0 + BLOCK).min(jb);
        for i0 in (0..nu).step_by(BLOCK) {
            let i1 = (i0 + BLOCK).min(nu);
            // Nothing to draw where no CL point is in reach of the block.
            if !canvas.any(grid.block_region([i0, i1], [j0, j1], r)) {
                continue;
            }
            for j in j0..j1 {
                let (vj, cell_row) = (grid.v(j), j + 1 < nv);
                for i in i0..i1 {
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
                    let cone = borders(slopes(&around[..n]), [i == 0, i + 1 == nu, j == 0, !cell_row]);
                    let [du, dv] = reach(cone, r);
                    canvas.draw([vj + dv[0], vj + dv[1]], |_| [ui + du[0], ui + du[1]], vertex_at(p));
                    // The edge along the row to (i+1, j): triangles below and above.
                    if i + 1 < nu {
                        let below = (j > 0).then(|| grid.upper(i, j - 1));
                        let above = cell_row.then(|| grid.lower(i, j));
                        let cone = match (below, above) {
                            (Some(b), Some(a)) => (a[1] <= b[1]).then(|| slopes(&[a, b])),
                            (None, Some(a)) => Some(open(slopes(&[a]), 1, true)),
                            (Some(b), None) => Some(open(slopes(&[b]), 1, false)),
                            (None, None) => None,
                        };
                        if let Some(cone) = cone {
                            let [du, dv] = reach(cone, r);
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
                        (Some(l), Some(rt)) => (rt[0] <= l[0]).then(|| slopes(&[l, rt])),
                        (None, Some(rt)) => Some(open(slopes(&[rt]), 0, true)),
                        (Some(l), None) => Some(open(slopes(&[l]), 0, false)),
                        (None, None) => None,
                    };
                    let q = grid.node(i, j + 1);
                    if let Some(cone) = cone {
                        let [du, dv] = reach(cone, r);
                        canvas.draw([vj + dv[0], vj + s + dv[1]], |_| [ui + du[0], ui + du[1]], edge_at(p, q));
                    }
                    if i + 1 == nu {
                        continue;
                    }
                    let (lower, upper) = (grid.lower(i, j), grid.upper(i, j));
                    // The diagonal to (i+1, j+1): a ridge when the slope across it,
                    // from the upper triangle to the lower, falls.
                    if (lower[0] - upper[0]) - (lower[1] - upper[1]) <= 0.0 {
                        let [du, dv] = reach(slopes(&[lower, upper]), r);
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
        }
    }
    (first, canvas.z)
}
