//! A height grid: z over a regular XY grid (an image, probe data, a
//! simulated part), and the triangulated surface it stands for.
//!
//! Node `(i, j)` lies at `x = x0 + i·step`, `y = y0 + j·step`. Each cell
//! `(i, j)`–`(i+1, j+1)` is two triangles split along the diagonal from
//! `(i, j)` to `(i+1, j+1)`; [`Heightfield::to_mesh`] builds exactly those
//! triangles, and [`Heightfield::z_at`] interpolates on them.

use crate::error::{Error, ErrorKind};
use crate::mesh::{Mesh, Triangle, Vec3};

/// Cells along each side of a block of [`Heightfield::block_top`].
pub const BLOCK: usize = 8;

/// A regular grid of heights, row by row (`y` outer, `x` inner).
#[derive(Clone, Debug, PartialEq)]
pub struct Heightfield {
    x0: f64,
    y0: f64,
    step: f64,
    nx: usize,
    ny: usize,
    z: Vec<f64>,
    /// The highest node of each block of [`BLOCK`] × [`BLOCK`] cells, row
    /// by row.
    tops: Vec<f64>,
    /// The slopes of each block's triangles: see [`Heightfield::block_slopes`].
    slopes: Vec<Slopes>,
}

/// The range of the gradients of some triangles: smallest and largest rise
/// along X and along Y (mm per mm), and the largest squared length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slopes {
    /// Smallest `[dz/dx, dz/dy]`.
    pub lo: [f64; 2],
    /// Largest `[dz/dx, dz/dy]`.
    pub hi: [f64; 2],
    /// Largest `|∇z|²`.
    pub len2: f64,
}

impl Slopes {
    /// No gradient yet.
    pub const NONE: Slopes = Slopes { lo: [f64::INFINITY; 2], hi: [f64::NEG_INFINITY; 2], len2: 0.0 };

    /// Widened to hold the gradient `g`.
    #[inline]
    pub fn with(mut self, g: [f64; 2]) -> Slopes {
        for (k, &gk) in g.iter().enumerate() {
            self.lo[k] = self.lo[k].min(gk);
            self.hi[k] = self.hi[k].max(gk);
        }
        self.len2 = self.len2.max(g[0] * g[0] + g[1] * g[1]);
        self
    }

    /// Both ranges.
    pub fn union(self, o: Slopes) -> Slopes {
        Slopes {
            lo: [self.lo[0].min(o.lo[0]), self.lo[1].min(o.lo[1])],
            hi: [self.hi[0].max(o.hi[0]), self.hi[1].max(o.hi[1])],
            len2: self.len2.max(o.len2),
        }
    }

    /// X and Y exchanged.
    pub fn transposed(self) -> Slopes {
        Slopes { lo: [self.lo[1], self.lo[0]], hi: [self.hi[1], self.hi[0]], len2: self.len2 }
    }
}

impl Heightfield {
    /// A grid of `nx × ny` nodes from `(x0, y0)` at `step` mm, with heights
    /// `z` row by row (`z[j·nx + i]`).
    pub fn new(x0: f64, y0: f64, step: f64, nx: usize, ny: usize, z: Vec<f64>) -> Result<Heightfield, Error> {
        if nx < 2 || ny < 2 {
            return Err(Error::new(
                ErrorKind::Heightfield,
                format!("a height grid needs at least 2 x 2 nodes, got {nx} x {ny}"),
            ));
        }
        if !(step > 0.0 && step.is_finite() && x0.is_finite() && y0.is_finite()) {
            return Err(Error::new(
                ErrorKind::Heightfield,
                format!("the grid step must be positive and the origin finite, got step {step}"),
            ));
        }
        if nx.checked_mul(ny) != Some(z.len()) {
            return Err(Error::new(
                ErrorKind::Heightfield,
                format!("the height grid needs {} heights, got {}", nx.saturating_mul(ny), z.len()),
            ));
        }
        if let Some(k) = z.iter().position(|v| !v.is_finite()) {
            return Err(Error::new(
                ErrorKind::Heightfield,
                format!("height at column {}, row {} is NaN or infinite", k % nx, k / nx),
            ));
        }
        let (bx, by) = ((nx - 1).div_ceil(BLOCK), (ny - 1).div_ceil(BLOCK));
        let mut tops = vec![f64::NEG_INFINITY; bx * by];
        for (j, row) in z.chunks_exact(nx).enumerate() {
            // Node rows on a block boundary belong to the blocks on both sides.
            for bj in [j / BLOCK, (j.max(1) - 1) / BLOCK] {
                let tops = &mut tops[bj.min(by - 1) * bx..][..bx];
                for (bi, top) in tops.iter_mut().enumerate() {
                    let nodes = &row[bi * BLOCK..=((bi + 1) * BLOCK).min(nx - 1)];
                    *top = nodes.iter().fold(*top, |t, &v| t.max(v));
                }
            }
        }
        let mut slopes = vec![Slopes::NONE; bx * by];
        for j in 0..ny - 1 {
            let block_row = &mut slopes[j / BLOCK * bx..][..bx];
            let (row, next) = (&z[j * nx..][..nx], &z[(j + 1) * nx..][..nx]);
            for i in 0..nx - 1 {
                let (za, zb, zc, zd) = (row[i], row[i + 1], next[i + 1], next[i]);
                let b = &mut block_row[i / BLOCK];
                *b = b.with([(zb - za) / step, (zc - zb) / step]).with([(zc - zd) / step, (zd - za) / step]);
            }
        }
        Ok(Heightfield { x0, y0, step, nx, ny, z, tops, slopes })
    }

    /// Samples `f(x, y)` on the grid (non-finite values become errors).
    pub fn from_fn(
        x0: f64,
        y0: f64,
        step: f64,
        nx: usize,
        ny: usize,
        f: impl Fn(f64, f64) -> f64,
    ) -> Result<Heightfield, Error> {
        let z = (0..nx * ny).map(|k| f(x0 + (k % nx) as f64 * step, y0 + (k / nx) as f64 * step)).collect();
        Heightfield::new(x0, y0, step, nx, ny, z)
    }

    /// Nodes along X.
    pub fn nx(&self) -> usize {
        self.nx
    }

    /// Nodes along Y.
    pub fn ny(&self) -> usize {
        self.ny
    }

    /// Grid step, mm.
    pub fn step(&self) -> f64 {
        self.step
    }

    /// X of column `i`.
    #[inline]
    pub fn x(&self, i: usize) -> f64 {
        self.x0 + i as f64 * self.step
    }

    /// Y of row `j`.
    #[inline]
    pub fn y(&self, j: usize) -> f64 {
        self.y0 + j as f64 * self.step
    }

    /// Height of node `(i, j)`.
    #[inline]
    pub fn z(&self, i: usize, j: usize) -> f64 {
        self.z[j * self.nx + i]
    }

    /// All heights, row by row.
    pub fn heights(&self) -> &[f64] {
        &self.z
    }

    /// Blocks of [`BLOCK`] × [`BLOCK`] cells along X and Y (the last ones
    /// may be smaller).
    pub fn blocks(&self) -> (usize, usize) {
        ((self.nx - 1).div_ceil(BLOCK), (self.ny - 1).div_ceil(BLOCK))
    }

    /// The highest node of block `(bi, bj)`: cells `bi·BLOCK …` and
    /// `bj·BLOCK …`, nodes up to and including their far corners.
    #[inline]
    pub fn block_top(&self, bi: usize, bj: usize) -> f64 {
        self.tops[bj * self.blocks().0 + bi]
    }

    /// The gradients of the triangles of block `(bi, bj)` (its cells, as
    /// [`Heightfield::block_top`]).
    #[inline]
    pub fn block_slopes(&self, bi: usize, bj: usize) -> Slopes {
        self.slopes[bj * self.blocks().0 + bi]
    }

    /// Node `(i, j)` as a point.
    #[inline]
    pub fn node(&self, i: usize, j: usize) -> Vec3 {
        Vec3::new(self.x(i), self.y(j), self.z(i, j))
    }

    /// XY extent `[min x, min y, max x, max y]`.
    pub fn xy_box(&self) -> [f64; 4] {
        [self.x0, self.y0, self.x(self.nx - 1), self.y(self.ny - 1)]
    }

    /// The two triangles of cell `(i, j)` (`i < nx − 1`, `j < ny − 1`): below
    /// and above the diagonal from node `(i, j)` to `(i+1, j+1)`.
    #[inline]
    pub fn cell_triangles(&self, i: usize, j: usize) -> [Triangle; 2] {
        let (a, b, c, d) = (self.node(i, j), self.node(i + 1, j), self.node(i + 1, j + 1), self.node(i, j + 1));
        [Triangle::new(a, b, c), Triangle::new(a, c, d)]
    }

    /// The `2·(nx−1)·(ny−1)` triangles of the surface, cell by cell (`j`
    /// outer, `i` inner), made as they are asked for: a large grid's surface
    /// can be written out without holding its triangles.
    pub fn triangles(&self) -> impl ExactSizeIterator<Item = Triangle> + '_ {
        let cells = (self.nx - 1) * (self.ny - 1);
        (0..2 * cells).map(move |k| self.cell_triangles((k / 2) % (self.nx - 1), k / 2 / (self.nx - 1))[k % 2])
    }

    /// The surface as a mesh of `2·(nx−1)·(ny−1)` triangles.
    pub fn to_mesh(&self) -> Mesh {
        Mesh::from_triangles(self.triangles())
    }

    /// The surface's height at `(x, y)`, linear on the triangles; `None`
    /// outside the grid.
    pub fn z_at(&self, x: f64, y: f64) -> Option<f64> {
        let u = (x - self.x0) / self.step;
        let v = (y - self.y0) / self.step;
        let (last_i, last_j) = ((self.nx - 1) as f64, (self.ny - 1) as f64);
        if !(u >= 0.0 && v >= 0.0 && u <= last_i && v <= last_j) {
            return None;
        }
        let i = (u.floor() as usize).min(self.nx - 2);
        let j = (v.floor() as usize).min(self.ny - 2);
        let (fu, fv) = (u - i as f64, v - j as f64);
        let (a, b, c, d) = (self.z(i, j), self.z(i + 1, j), self.z(i + 1, j + 1), self.z(i, j + 1));
        Some(if fu >= fv { a + (b - a) * fu + (c - b) * fv } else { a + (c - d) * fu + (d - a) * fv })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mesh_and_interpolation_agree() {
        let h = Heightfield::from_fn(-1.0, 2.0, 0.5, 5, 4, |x, y| (x * 1.3).sin() + y * y * 0.1).unwrap();
        let m = h.to_mesh();
        assert_eq!((m.len(), m.vertices().len(), m.skipped()), (2 * 4 * 3, 20, 0));
        for t in m.iter() {
            let c = (t.v[0] + t.v[1] + t.v[2]) * (1.0 / 3.0);
            assert!((h.z_at(c.x, c.y).unwrap() - c.z).abs() < 1e-12);
            for p in t.v {
                assert!((h.z_at(p.x, p.y).unwrap() - p.z).abs() < 1e-12);
            }
        }
        assert_eq!(h.z_at(-1.01, 2.5), None);
        assert_eq!(h.xy_box(), [-1.0, 2.0, 1.0, 3.5]);
    }

    #[test]
    fn triangles_come_cell_by_cell_and_stream_as_the_mesh_writes() {
        let h = Heightfield::from_fn(-1.0, 2.0, 0.5, 5, 4, |x, y| (x * 1.3).sin() + y * y * 0.1).unwrap();
        let streamed: Vec<Triangle> = h.triangles().collect();
        assert_eq!(h.triangles().len(), 24);
        assert_eq!(streamed, h.to_mesh().iter().collect::<Vec<_>>());
        // Cell (i, j) = (3, 2) is triangles 2·(2·4 + 3) and the next.
        assert_eq!(streamed[22..24], h.cell_triangles(3, 2));
        let mut bytes = Vec::new();
        crate::write_binary_stl_to(&mut bytes, h.triangles()).unwrap();
        assert_eq!(bytes, crate::write_binary_stl(&streamed));
        assert_eq!(bytes.len(), 84 + 50 * 24);
    }

    #[test]
    fn block_tops_are_the_highest_node_of_each_block() {
        for (nx, ny) in [(2, 2), (9, 9), (10, 17), (23, 8)] {
            let h = Heightfield::from_fn(0.0, 0.0, 1.0, nx, ny, |x, y| (x * 12.9898 + y * 78.233).sin()).unwrap();
            let (bx, by) = h.blocks();
            assert_eq!((bx, by), ((nx - 1).div_ceil(BLOCK), (ny - 1).div_ceil(BLOCK)));
            for bj in 0..by {
                for bi in 0..bx {
                    let mut top = f64::NEG_INFINITY;
                    for j in bj * BLOCK..=((bj + 1) * BLOCK).min(ny - 1) {
                        for i in bi * BLOCK..=((bi + 1) * BLOCK).min(nx - 1) {
                            top = top.max(h.z(i, j));
                        }
                    }
                    assert_eq!(h.block_top(bi, bj), top, "{nx} x {ny}, block ({bi}, {bj})");
                }
            }
        }
    }

    #[test]
    fn bad_grids_say_why() {
        let e = |r: Result<Heightfield, Error>| r.unwrap_err().to_string();
        assert_eq!(
            e(Heightfield::new(0., 0., 1., 1, 5, vec![0.; 5])),
            "a height grid needs at least 2 x 2 nodes, got 1 x 5"
        );
        assert_eq!(
            e(Heightfield::new(0., 0., 0., 2, 2, vec![0.; 4])),
            "the grid step must be positive and the origin finite, got step 0"
        );
        assert_eq!(e(Heightfield::new(0., 0., 1., 2, 2, vec![0.; 3])), "the height grid needs 4 heights, got 3");
        assert_eq!(
            e(Heightfield::new(0., 0., 1., 2, 2, vec![0., 0., 0., f64::NAN])),
            "height at column 1, row 1 is NaN or infinite"
        );
    }
}
