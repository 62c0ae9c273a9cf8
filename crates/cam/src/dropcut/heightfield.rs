//! The fast path for height grids: the grid is its own index. A query
//! takes the blocks of [`BLOCK`] × [`BLOCK`] cells under the cutter's disk
//! highest bound first — the block's top less the cutter's height at the
//! block's nearest point, the most it could hold the cutter at — and stops
//! at the first block whose bound cannot beat the best contact so far;
//! inside a block it visits each node, edge and triangle once.

use kezuri_geom::{Heightfield, BLOCK};

use super::contact::Probe;
use super::Surface;
use crate::cutter::{each_shape, Cutter, Profile};

/// The same surface as [`Heightfield::to_mesh`]: each cell split along the
/// diagonal from node `(i, j)` to `(i+1, j+1)`.
impl Surface for Heightfield {
    /// The blocks under the disk: bound, column, row.
    type Scratch = Vec<(f64, u32, u32)>;

    fn scratch(&self) -> Self::Scratch {
        Vec::new()
    }

    fn drop_cutter_with(&self, cutter: &Cutter, x: f64, y: f64, blocks: &mut Self::Scratch) -> Option<f64> {
        if !(x.is_finite() && y.is_finite()) {
            return None;
        }
        each_shape!(cutter, shape => drop(self, Probe::new(shape, x, y), blocks))
    }
}

/// [`Surface::drop_cutter_with`] with the cutter's shape known.
fn drop<P: Profile>(h: &Heightfield, mut probe: Probe<P>, blocks: &mut Vec<(f64, u32, u32)>) -> Option<f64> {
    let [x, y] = probe.centre();
    let r = probe.radius();
    let [x0, y0, x1, y1] = h.xy_box();
    if x + r < x0 || x - r > x1 || y + r < y0 || y - r > y1 {
        return None;
    }
    let step = h.step();
    // Cells whose box meets the disk's box.
    let cell = |v: f64, origin: f64, n: usize| (((v - origin) / step).floor().max(0.0) as usize).min(n - 2);
    let (i0, i1) = (cell(x - r, x0, h.nx()), cell(x + r, x0, h.nx()));
    let (j0, j1) = (cell(y - r, y0, h.ny()), cell(y + r, y0, h.ny()));
    blocks.clear();
    for bj in j0 / BLOCK..=j1 / BLOCK {
        for bi in i0 / BLOCK..=i1 / BLOCK {
            let (ci, cj) = (bi * BLOCK, bj * BLOCK);
            let (ce, cf) = ((ci + BLOCK).min(h.nx() - 1), (cj + BLOCK).min(h.ny() - 1));
            let bx = [h.x(ci), h.y(cj), h.x(ce), h.y(cf)];
            if let Some(bound) = probe.bound(&bx, h.block_top(bi, bj)) {
                blocks.push((bound, bi as u32, bj as u32));
            }
        }
    }
    blocks.sort_unstable_by(|a, b| b.0.total_cmp(&a.0));
    for &(bound, bi, bj) in blocks.iter() {
        if bound <= probe.best {
            break;
        }
        let (bi, bj) = (bi as usize * BLOCK, bj as usize * BLOCK);
        let cells = [bi.max(i0), (bi + BLOCK - 1).min(i1), bj.max(j0), (bj + BLOCK - 1).min(j1)];
        let top = h.block_top(bi / BLOCK, bj / BLOCK);
        drop_on_cells(h, &mut probe, cells, top);
    }
    probe.result()
}

/// The contacts of the cells `[i0, i1] × [j0, j1]`, none of whose nodes is
/// higher than `top`.
fn drop_on_cells<P: Profile>(h: &Heightfield, probe: &mut Probe<P>, [i0, i1, j0, j1]: [usize; 4], top: f64) {
    // Nothing farther than this from the axis can beat the best so far.
    let reach2 = probe.reach2(top);
    let [x, y] = probe.centre();
    let near = |xa: f64, ya: f64, xb: f64, yb: f64| {
        let dx = (xa - x).max(x - xb).max(0.0);
        let dy = (ya - y).max(y - yb).max(0.0);
        dx * dx + dy * dy <= reach2
    };
    for j in j0..=j1 + 1 {
        for i in i0..=i1 + 1 {
            let p = h.node(i, j);
            if near(p.x, p.y, p.x, p.y) {
                probe.vertex(p);
            }
        }
    }
    let step = h.step();
    for j in j0..=j1 {
        for i in i0..=i1 {
            if !near(h.x(i), h.y(j), h.x(i + 1), h.y(j + 1)) {
                continue;
            }
            let (za, zb, zc, zd) = (h.z(i, j), h.z(i + 1, j), h.z(i + 1, j + 1), h.z(i, j + 1));
            let top = za.max(zb).max(zc).max(zd);
            let bx = [h.x(i), h.y(j), h.x(i + 1), h.y(j + 1)];
            if !probe.may_win(&bx, top) {
                continue;
            }
            let (na, nb, nc, nd) = (h.node(i, j), h.node(i + 1, j), h.node(i + 1, j + 1), h.node(i, j + 1));
            // The lower triangle a b c rises (zb − za)/step along X and
            // (zc − zb)/step along Y, the upper a c d (zc − zd)/step and
            // (zd − za)/step. The cutter on a triangle's whole plane bounds
            // every contact of the triangle (facet, edges, corners), and is
            // the facet contact where it touches inside: then the
            // triangle's edges need no look.
            let (dx, dy) = (x - na.x, y - na.y);
            let lower = [(zb - za) / step, (zc - zb) / step];
            let upper = [(zc - zd) / step, (zd - za) / step];
            let lower_open = open_triangle(probe, lower, za + lower[0] * dx + lower[1] * dy, na, step, true);
            let upper_open = open_triangle(probe, upper, za + upper[0] * dx + upper[1] * dy, na, step, false);
            // Each cell owns its bottom, left and diagonal edges; the
            // last column and row of the range also their right and top.
            if lower_open {
                probe.edge(na, nb);
                if i == i1 {
                    probe.edge(nb, nc);
                }
            }
            if upper_open {
                probe.edge(na, nd);
                if j == j1 {
                    probe.edge(nd, nc);
                }
            }
            if lower_open && upper_open {
                probe.edge(na, nc);
            }
        }
    }
}

/// The cutter on the plane of one triangle of a cell whose corner `(i, j)`
/// is `corner`: offers the facet contact where it touches inside the
/// triangle (lower: `0 ≤ v ≤ u ≤ 1` in cell units, upper: `0 ≤ u ≤ v ≤
/// 1`), and says whether the triangle's edges could still hold the cutter
/// higher than the best so far. `gradient` is the plane's rise along X and
/// Y, `z_axis` its height on the cutter's axis.
#[inline]
fn open_triangle<P: Profile>(
    probe: &mut Probe<P>,
    gradient: [f64; 2],
    z_axis: f64,
    corner: kezuri_geom::Vec3,
    step: f64,
    lower: bool,
) -> bool {
    let Some(plane) = probe.plane(gradient[0], gradient[1], z_axis) else {
        return true;
    };
    if plane.tip <= probe.best {
        return false;
    }
    let (u, v) = ((plane.touch[0] - corner.x) / step, (plane.touch[1] - corner.y) / step);
    let inside = if lower { 0.0 <= v && v <= u && u <= 1.0 } else { 0.0 <= u && u <= v && v <= 1.0 };
    if inside {
        probe.offer(plane.tip);
        return false;
    }
    true
}
