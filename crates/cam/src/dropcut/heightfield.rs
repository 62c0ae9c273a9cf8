//! The fast path for height grids: the grid is its own index. A query
//! visits the nodes and cells under the cutter's disk, each node, edge and
//! triangle once, with no candidate list and no "seen" marks.

use kezuri_geom::Heightfield;

use super::contact::Probe;
use super::Surface;
use crate::cutter::Cutter;

/// The same surface as [`Heightfield::to_mesh`]: each cell split along the
/// diagonal from node `(i, j)` to `(i+1, j+1)`.
impl Surface for Heightfield {
    type Scratch = ();

    fn scratch(&self) {}

    fn drop_cutter_with(&self, cutter: &Cutter, x: f64, y: f64, _: &mut ()) -> Option<f64> {
        if !(x.is_finite() && y.is_finite()) {
            return None;
        }
        let mut probe = Probe::new(cutter, x, y);
        let r = probe.radius();
        let [x0, y0, x1, y1] = self.xy_box();
        if x + r < x0 || x - r > x1 || y + r < y0 || y - r > y1 {
            return None;
        }
        let step = self.step();
        // Cells whose box meets the disk's box.
        let cell = |v: f64, origin: f64, n: usize| (((v - origin) / step).floor().max(0.0) as usize).min(n - 2);
        let (i0, i1) = (cell(x - r, x0, self.nx()), cell(x + r, x0, self.nx()));
        let (j0, j1) = (cell(y - r, y0, self.ny()), cell(y + r, y0, self.ny()));
        for j in j0..=j1 + 1 {
            for i in i0..=i1 + 1 {
                probe.vertex(self.node(i, j));
            }
        }
        for j in j0..=j1 {
            for i in i0..=i1 {
                let (a, b, c, d) = (self.z(i, j), self.z(i + 1, j), self.z(i + 1, j + 1), self.z(i, j + 1));
                let top = a.max(b).max(c).max(d);
                let bx = [self.x(i), self.y(j), self.x(i + 1), self.y(j + 1)];
                if !probe.may_win(&bx, top) {
                    continue;
                }
                let [lower, upper] = self.cell_triangles(i, j);
                probe.facet(&lower);
                probe.facet(&upper);
                let [na, nb, nc] = lower.v;
                let nd = upper.v[2];
                // Each cell owns its bottom, left and diagonal edges; the
                // last column and row of the range also their right and top.
                probe.edge(na, nb);
                probe.edge(na, nd);
                probe.edge(na, nc);
                if i == i1 {
                    probe.edge(nb, nc);
                }
                if j == j1 {
                    probe.edge(nd, nc);
                }
            }
        }
        probe.result()
    }
}
