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

    /// The gradients the pieces of nodes `i0..i1`, `j0..j1` (their
    /// vertices, edges and cells) may take: those of the blocks of cells
    /// around them, opened on the grid's border.
    fn block_cone(&self, [i0, i1]: [usize; 2], [j0, j1]: [usize; 2]) -> Cone {
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
        Cone::of_slopes(s).borders([i0 == 0, i1 == nu, j0 == 0, j1 == nv])
    }

    /// The box the nodes `i0..i1`, `j0..j1` and their cells cover.
    fn block_box(&self, [i0, i1]: [usize; 2], [j0, j1]: [usize; 2]) -> [[f64; 2]; 2] {
        let (nu, nv) = (self.nu(), self.nv());
        [[self.u(i0), self.u(i1.min(nu - 1))], [self.v(j0), self.v(j1.min(nv - 1))]]
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

/// A triangle of the grid: its gradient and what the offsets need of it.
#[derive(Clone, Copy)]
struct Facet {
    /// Rise along u and v.
    g: [f64; 2],
    /// `g_k / √(1 + g_k²)` of each axis.
    sat: [f64; 2],
    /// `√(1 + |g|²)`.
    root: f64,
}

impl Facet {
    fn new(g: [f64; 2]) -> Facet {
        let sat = |g: f64| g / (1.0 + g * g).sqrt();
        Facet { g, sat: [sat(g[0]), sat(g[1])], root: (1.0 + g[0] * g[0] + g[1] * g[1]).sqrt() }
    }
}

/// The gradients a piece may take, as a box: each axis's range (and its
/// `g / √(1 + g²)`), and the largest `√(1 + |g|²)`.
#[derive(Clone, Copy)]
struct Cone {
    lo: [f64; 2],
    hi: [f64; 2],
    sat_lo: [f64; 2],
    sat_hi: [f64; 2],
    root: f64,
}

impl Cone {
    const EMPTY: Cone = Cone {
        lo: [f64::INFINITY; 2],
        hi: [f64::NEG_INFINITY; 2],
        sat_lo: [f64::INFINITY; 2],
        sat_hi: [f64::NEG_INFINITY; 2],
        root: 1.0,
    };

    /// Widened to hold the triangle's gradient.
    #[inline]
    fn with(mut self, f: Facet) -> Cone {
        for k in 0..2 {
            self.lo[k] = self.lo[k].min(f.g[k]);
            self.hi[k] = self.hi[k].max(f.g[k]);
            self.sat_lo[k] = self.sat_lo[k].min(f.sat[k]);
            self.sat_hi[k] = self.sat_hi[k].max(f.sat[k]);
        }
        self.root = self.root.max(f.root);
        self
    }

    /// The one gradient the box holds, if it holds one (a plane; never on
    /// the grid's border).
    fn single(&self) -> Option<[f64; 2]> {
        (self.lo == self.hi && self.root.is_finite()).then_some(self.lo)
    }

    /// The gradients in a box of slopes.
    fn of_slopes(s: Slopes) -> Cone {
        let sat = |g: f64| g / (1.0 + g * g).sqrt();
        Cone {
            lo: s.lo,
            hi: s.hi,
            sat_lo: [sat(s.lo[0]), sat(s.lo[1])],
            sat_hi: [sat(s.hi[0]), sat(s.hi[1])],
            root: (1.0 + s.len2).sqrt(),
        }
    }

    /// The gradients of an edge between triangles `a` and `b`, which lie on
    /// the smaller and the larger side of `axis` across it (the diagonal
    /// apart, the grid's edges run along the axes): between theirs where it
    /// is a ridge, none where it is a valley; one-sided on the grid's
    /// border.
    #[inline]
    fn of_edge(a: Option<Facet>, b: Option<Facet>, axis: usize) -> Option<Cone> {
        match (a, b) {
            (Some(a), Some(b)) => (b.g[axis] <= a.g[axis]).then(|| Cone::EMPTY.with(a).with(b)),
            (None, Some(b)) => Some(Cone::EMPTY.with(b).open(axis, true)),
            (Some(a), None) => Some(Cone::EMPTY.with(a).open(axis, false)),
            (None, None) => None,
        }
    }

    /// The grid ends on this side of the piece (`axis` 0: u, 1: v; `up`:
    /// the grid lies towards larger values): a cliff, so the gradient may
    /// grow without end towards the grid.
    fn open(mut self, axis: usize, up: bool) -> Cone {
        if up {
            (self.hi[axis], self.sat_hi[axis]) = (f64::INFINITY, 1.0);
        } else {
            (self.lo[axis], self.sat_lo[axis]) = (f64::NEG_INFINITY, -1.0);
        }
        self.root = f64::INFINITY;
        self
    }

    /// Opened (see [`Cone::open`]) where the piece lies on the grid's
    /// first or last column, first or last row.
    #[inline]
    fn borders(self, [first_u, last_u, first_v, last_v]: [bool; 4]) -> Cone {
        let mut c = self;
        for (border, axis, up) in [(first_u, 0, true), (last_u, 0, false), (first_v, 1, true), (last_v, 1, false)] {
            if border {
                c = c.open(axis, up);
            }
        }
        c
    }

    /// Each axis's range of the offset `φ_k(g) = −R·g_k / √(1 + |g|²)`
    /// over the box: `g_k / √(1 + g_k²)` bounds `g_k / √(1 + |g|²)` away
    /// from zero, `g_k / √(1 + max |g|²)` towards it.
    #[inline]
    fn reach(&self, r: f64) -> [[f64; 2]; 2] {
        let damp = 1.0 / self.root;
        let axis = |k: usize| {
            let lo = if self.lo[k] >= 0.0 { self.lo[k] * damp } else { self.sat_lo[k] };
            let hi = if self.hi[k] <= 0.0 { self.hi[k] * damp } else { self.sat_hi[k] };
            [-r * hi, -r * lo]
        };
        [axis(0), axis(1)]
    }
}

/// The triangles of the cells around a block of nodes.
struct Cells {
    /// Cell `(i0 − 1 + a, j0 − 1 + b)` at `[b][a]`; `None` off the grid.
    cells: [[Option<[Facet; 2]>; BLOCK + 1]; BLOCK + 1],
    i0: usize,
    j0: usize,
}

impl Cells {
    /// The cells of nodes `i0..i1`, `j0..j1` (the block's and those to the
    /// left and below).
    fn around(grid: &View, [i0, i1]: [usize; 2], [j0, j1]: [usize; 2]) -> Cells {
        let mut cells = [[None; BLOCK + 1]; BLOCK + 1];
        let (nu, nv) = (grid.nu(), grid.nv());
        for (b, row) in cells.iter_mut().enumerate().take(j1 - j0 + 1) {
            let Some(cj) = (j0 + b).checked_sub(1).filter(|&cj| cj + 1 < nv) else { continue };
            for (a, cell) in row.iter_mut().enumerate().take(i1 - i0 + 1) {
                if let Some(ci) = (i0 + a).checked_sub(1).filter(|&ci| ci + 1 < nu) {
                    *cell = Some([Facet::new(grid.lower(ci, cj)), Facet::new(grid.upper(ci, cj))]);
                }
            }
        }
        Cells { cells, i0, j0 }
    }

    /// The cell `back_i` columns left and `back_j` rows below node `(i, j)`'s
    /// own cell (each 0 or 1).
    #[inline]
    fn at(&self, i: usize, j: usize, back_i: usize, back_j: usize) -> Option<[Facet; 2]> {
        self.cells[j + 1 - back_j - self.j0][i + 1 - back_i - self.i0]
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
            let cone = grid.block_cone([i0, i1], [j0, j1]);
            let [[u0, u1], [v0, v1]] = grid.block_box([i0, i1], [j0, j1]);
            let [du, dv] = cone.reach(r);
            // Nothing to draw where no CL point is in reach of the block.
            if !canvas.any([[u0 + du[0], u1 + du[1]], [v0 + dv[0], v1 + dv[1]]]) {
                continue;
            }
            // A block in one plane (so are the cells around it): its facets,
            // edges and vertices all hold the ball on that plane, over the
            // block moved by the plane's offset.
            if let Some(g) = cone.single() {
                let f = Facet::new(g);
                let (ou, ov) = (-r * g[0] / f.root, -r * g[1] / f.root);
                let lift = r * (g[0] * g[0] + g[1] * g[1]) / (f.root + 1.0);
                let corner = grid.node(i0, j0);
                canvas.draw(
                    [v0 + ov, v1 + ov],
                    |_| [u0 + ou, u1 + ou],
                    |u, v, z| *z = z.max(corner.z + g[0] * (u - u0) + g[1] * (v - v0) + lift),
                );
                continue;
            }
            let cells = Cells::around(grid, [i0, i1], [j0, j1]);
            for j in j0..j1 {
                let (vj, cell_row) = (grid.v(j), j + 1 < nv);
                for i in i0..i1 {
                    let ui = grid.u(i);
                    let p = grid.node(i, j);
                    // The cells around the node: left below, below, left, own.
                    let [lb, b, l, own] =
                        [cells.at(i, j, 1, 1), cells.at(i, j, 0, 1), cells.at(i, j, 1, 0), cells.at(i, j, 0, 0)];
                    // The vertex: its up to six triangles.
                    let mut cone = Cone::EMPTY;
                    for f in [
                        lb.map(|c| c[0]),
                        lb.map(|c| c[1]),
                        b.map(|c| c[1]),
                        l.map(|c| c[0]),
                        own.map(|c| c[0]),
                        own.map(|c| c[1]),
                    ]
                    .into_iter()
                    .flatten()
                    {
                        cone = cone.with(f);
                    }
                    let [du, dv] = cone.borders([i == 0, i + 1 == nu, j == 0, !cell_row]).reach(r);
                    canvas.draw([vj + dv[0], vj + dv[1]], |_| [ui + du[0], ui + du[1]], vertex_at(p));
                    // The edge along the row to (i+1, j): triangles below and above.
                    if i + 1 < nu {
                        let (below, above) = (b.map(|c| c[1]), own.map(|c| c[0]));
                        if let Some(cone) = Cone::of_edge(below, above, 1) {
                            let [du, dv] = cone.reach(r);
                            let q = grid.node(i + 1, j);
                            canvas.draw([vj + dv[0], vj + dv[1]], |_| [ui + du[0], ui + s + du[1]], edge_at(p, q));
                        }
                    }
                    if !cell_row {
                        continue;
                    }
                    // The edge across the rows to (i, j+1): triangles left and right.
                    let (left, right) = (l.map(|c| c[0]), own.map(|c| c[1]));
                    if let Some(cone) = Cone::of_edge(left, right, 0) {
                        let [du, dv] = cone.reach(r);
                        let q = grid.node(i, j + 1);
                        canvas.draw([vj + dv[0], vj + s + dv[1]], |_| [ui + du[0], ui + du[1]], edge_at(p, q));
                    }
                    let Some([lower, upper]) = own else { continue };
                    // The diagonal to (i+1, j+1): a ridge when the slope across it,
                    // from the upper triangle to the lower, falls.
                    if (lower.g[0] - upper.g[0]) - (lower.g[1] - upper.g[1]) <= 0.0 {
                        let [du, dv] = Cone::EMPTY.with(lower).with(upper).reach(r);
                        let c = grid.node(i + 1, j + 1);
                        let along = |v: f64, dv: f64| (v - vj - dv).clamp(0.0, s);
                        canvas.draw(
                            [vj + dv[0], vj + s + dv[1]],
                            |v| [ui + along(v, dv[1]) + du[0], ui + along(v, dv[0]) + du[1]],
                            edge_at(p, c),
                        );
                    }
                    // The two facets, each over its triangle moved by φ(g).
                    for (f, is_lower) in [(lower, true), (upper, false)] {
                        let g = f.g;
                        let (ou, ov) = (-r * g[0] / f.root, -r * g[1] / f.root);
                        // R·(√(1 + |g|²) − 1), written to keep its digits.
                        let lift = r * (g[0] * g[0] + g[1] * g[1]) / (f.root + 1.0);
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
