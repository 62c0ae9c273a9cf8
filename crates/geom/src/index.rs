//! A grid over XY that finds the triangles near a point.
//!
//! Cells are square. The finest level's cells are as large as the median
//! triangle (the larger side of its XY bounding box), so a query visits a
//! number of cells and triangles proportional to its own area, whatever the
//! size of the mesh. Each coarser level has cells twice as large, and a
//! triangle is listed in the finest level whose cells are at least as large
//! as its box: in at most 2 × 2 cells. So the index holds at most four
//! entries a triangle, whatever the size of the boxes (a few large
//! triangles among many small ones cost no more than small ones). A query
//! reports a triangle once, from the cell of its level that holds the
//! lower-left corner of the overlap of the two boxes, without a "seen" set.

use crate::mesh::Mesh;

/// The XY grid index of a mesh's triangles.
#[derive(Clone, Debug)]
pub struct XyIndex {
    /// Finest first; a level with no triangle has no cell.
    levels: Vec<Level>,
    /// XY box of each triangle: min x, min y, max x, max y.
    boxes: Vec<[f64; 4]>,
    /// The cell of each box's low corner, in the triangle's level.
    low: Vec<[u32; 2]>,
}

/// One uniform grid of the index.
#[derive(Clone, Debug)]
struct Level {
    origin: [f64; 2],
    cell: f64,
    nx: usize,
    ny: usize,
    /// Cell `k` lists `items[start[k]..start[k + 1]]`.
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Level {
    #[inline]
    fn cell_of(&self, v: f64, axis: usize) -> usize {
        let n = if axis == 0 { self.nx } else { self.ny };
        let k = ((v - self.origin[axis]) / self.cell).floor();
        if k >= 0.0 {
            (k as usize).min(n - 1)
        } else {
            0
        }
    }

    #[inline]
    fn cell_range(&self, b: &[f64; 4]) -> (usize, usize, usize, usize) {
        (self.cell_of(b[0], 0), self.cell_of(b[1], 1), self.cell_of(b[2], 0), self.cell_of(b[3], 1))
    }
}

impl XyIndex {
    /// The index of `mesh`, cells sized from its median triangle.
    pub fn new(mesh: &Mesh) -> XyIndex {
        let boxes: Vec<[f64; 4]> = mesh.iter().map(|t| t.xy_box()).collect();
        let median = {
            let mut sizes: Vec<f64> = boxes.iter().map(side).collect();
            if sizes.is_empty() {
                1.0
            } else {
                let mid = sizes.len() / 2;
                *sizes.select_nth_unstable_by(mid, f64::total_cmp).1
            }
        };
        XyIndex::build(boxes, median)
    }

    /// The index of `mesh` with finest cells of side `cell` (enlarged if the
    /// grid would have more than about four cells a triangle).
    pub fn with_cell(mesh: &Mesh, cell: f64) -> XyIndex {
        XyIndex::build(mesh.iter().map(|t| t.xy_box()).collect(), cell)
    }

    fn build(boxes: Vec<[f64; 4]>, cell: f64) -> XyIndex {
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for b in &boxes {
            lo = [lo[0].min(b[0]), lo[1].min(b[1])];
            hi = [hi[0].max(b[2]), hi[1].max(b[3])];
        }
        if boxes.is_empty() {
            (lo, hi) = ([0.0; 2], [0.0; 2]);
        }
        let extent = [hi[0] - lo[0], hi[1] - lo[1]];
        // Never more than ~4 finest cells a triangle (or 2^26 in all), never zero.
        let most = (4 * boxes.len() + 16).min(1 << 26) as f64;
        let floor = (extent[0] * extent[1] / most).sqrt().max(extent[0].max(extent[1]) / 65536.0);
        let cell = if cell.is_finite() && cell > floor { cell } else { floor };
        let cell = if cell > 0.0 { cell } else { 1.0 };
        // The level of each triangle: the finest whose cell holds its box.
        let level_of = |b: &[f64; 4]| {
            let mut l = 0;
            while cell * f64::powi(2.0, l) < side(b) && l < 64 {
                l += 1;
            }
            l as u8
        };
        // A byte a triangle: at most 65 levels.
        let of: Vec<u8> = boxes.iter().map(level_of).collect();
        let count = of.iter().max().map_or(1, |&l| usize::from(l) + 1);
        let mut levels: Vec<Level> = (0..count)
            .map(|l| Level {
                origin: lo,
                cell: cell * f64::powi(2.0, l as i32),
                nx: 0,
                ny: 0,
                start: vec![0],
                items: vec![],
            })
            .collect();
        for &l in &of {
            let level = &mut levels[usize::from(l)];
            if level.nx == 0 {
                level.nx = (extent[0] / level.cell) as usize + 1;
                level.ny = (extent[1] / level.cell) as usize + 1;
                level.start = vec![0; level.nx * level.ny + 1];
            }
        }
        let low = boxes
            .iter()
            .zip(&of)
            .map(|(b, &l)| {
                let level = &levels[usize::from(l)];
                [level.cell_of(b[0], 0) as u32, level.cell_of(b[1], 1) as u32]
            })
            .collect();
        // Counting sort of (cell, triangle) pairs, level by level: at most
        // four pairs a triangle, so the u32 counts cannot overflow.
        for (b, &l) in boxes.iter().zip(&of) {
            let level = &mut levels[usize::from(l)];
            let (i0, j0, i1, j1) = level.cell_range(b);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    level.start[j * level.nx + i + 1] += 1;
                }
            }
        }
        let mut fill = Vec::with_capacity(count);
        for level in &mut levels {
            for k in 1..level.start.len() {
                level.start[k] += level.start[k - 1];
            }
            level.items = vec![0; *level.start.last().unwrap_or(&0) as usize];
            fill.push(level.start.clone());
        }
        for (t, (b, &l)) in boxes.iter().zip(&of).enumerate() {
            let l = usize::from(l);
            let level = &mut levels[l];
            let (i0, j0, i1, j1) = level.cell_range(b);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    let slot = &mut fill[l][j * level.nx + i];
                    level.items[*slot as usize] = t as u32;
                    *slot += 1;
                }
            }
        }
        XyIndex { levels, boxes, low }
    }

    /// Side of a finest cell, mm.
    pub fn cell_size(&self) -> f64 {
        self.levels.first().map_or(1.0, |l| l.cell)
    }

    /// Entries in all cells of all levels: at most four a triangle.
    pub fn entries(&self) -> usize {
        self.levels.iter().map(|l| l.items.len()).sum()
    }

    /// XY bounding box `[min x, min y, max x, max y]` of triangle `t`.
    #[inline]
    pub fn triangle_box(&self, t: u32) -> [f64; 4] {
        self.boxes[t as usize]
    }

    /// Calls `f` once for each triangle whose XY bounding box meets the box
    /// `[min x, min y, max x, max y]` (boundaries included).
    #[inline]
    pub fn for_each_in_box(&self, q: [f64; 4], mut f: impl FnMut(u32)) {
        self.visit(q, |b| b[0] <= q[2] && b[2] >= q[0] && b[1] <= q[3] && b[3] >= q[1], &mut f);
    }

    /// Calls `f` once for each triangle whose XY bounding box meets the disk
    /// of `radius` about `centre` (boundaries included).
    #[inline]
    pub fn for_each_in_disk(&self, centre: [f64; 2], radius: f64, mut f: impl FnMut(u32)) {
        let q = [centre[0] - radius, centre[1] - radius, centre[0] + radius, centre[1] + radius];
        let r2 = radius * radius;
        let meets = |b: &[f64; 4]| {
            let dx = (b[0] - centre[0]).max(centre[0] - b[2]).max(0.0);
            let dy = (b[1] - centre[1]).max(centre[1] - b[3]).max(0.0);
            dx * dx + dy * dy <= r2
        };
        self.visit(q, meets, &mut f);
    }

    fn visit(&self, q: [f64; 4], meets: impl Fn(&[f64; 4]) -> bool, f: &mut impl FnMut(u32)) {
        if self.boxes.is_empty() || !(q[0] <= q[2] && q[1] <= q[3]) {
            return;
        }
        for level in self.levels.iter().filter(|l| !l.items.is_empty()) {
            let (i0, j0, i1, j1) = level.cell_range(&q);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    let k = j * level.nx + i;
                    for &t in &level.items[level.start[k] as usize..level.start[k + 1] as usize] {
                        // Report from one cell only: the one holding the low
                        // corner of the overlap of the two boxes (cell_of is
                        // monotone, so that is the larger of the low cells).
                        let [ti, tj] = self.low[t as usize];
                        if (ti as usize).max(i0) == i && (tj as usize).max(j0) == j && meets(&self.boxes[t as usize]) {
                            f(t);
                        }
                    }
                }
            }
        }
    }

    /// The triangles [`XyIndex::for_each_in_disk`] reports, in order.
    pub fn query_disk(&self, centre: [f64; 2], radius: f64) -> Vec<u32> {
        let mut out = Vec::new();
        self.for_each_in_disk(centre, radius, |t| out.push(t));
        out.sort_unstable();
        out
    }

    /// The triangles [`XyIndex::for_each_in_box`] reports, in order.
    pub fn query_box(&self, q: [f64; 4]) -> Vec<u32> {
        let mut out = Vec::new();
        self.for_each_in_box(q, |t| out.push(t));
        out.sort_unstable();
        out
    }
}

/// The larger side of an XY box.
fn side(b: &[f64; 4]) -> f64 {
    (b[2] - b[0]).max(b[3] - b[1])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Triangle, Vec3};

    /// A deterministic scatter of triangles of mixed sizes.
    fn scatter(n: usize) -> Mesh {
        let mut s = 12345u64;
        let mut next = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        Mesh::from_triangles((0..n).map(|k| {
            let size = if k % 10 == 0 { 20.0 } else { 1.5 };
            let (x, y) = (next() * 100.0, next() * 60.0);
            let mut p = || Vec3::new(x + size * next(), y + size * next(), next());
            Triangle::new(p(), p(), p())
        }))
    }

    #[test]
    fn queries_equal_brute_force() {
        let mesh = scatter(3000);
        for index in [XyIndex::new(&mesh), XyIndex::with_cell(&mesh, 0.1), XyIndex::with_cell(&mesh, 500.0)] {
            let boxes: Vec<[f64; 4]> = mesh.iter().map(|t| t.xy_box()).collect();
            for (k, (cx, cy, r)) in
                [(50.0, 30.0, 3.0), (-10.0, -10.0, 12.0), (0.0, 0.0, 0.5), (101.0, 61.0, 200.0), (500.0, 5.0, 3.0)]
                    .into_iter()
                    .enumerate()
            {
                let brute: Vec<u32> = (0..mesh.len() as u32)
                    .filter(|&t| {
                        let b = boxes[t as usize];
                        let dx = (b[0] - cx).max(cx - b[2]).max(0.0);
                        let dy = (b[1] - cy).max(cy - b[3]).max(0.0);
                        dx * dx + dy * dy <= r * r
                    })
                    .collect();
                assert_eq!(index.query_disk([cx, cy], r), brute, "disk {k}");
                let q = [cx - r, cy - r * 0.5, cx + r * 0.3, cy + r];
                let brute: Vec<u32> = (0..mesh.len() as u32)
                    .filter(|&t| {
                        let b = boxes[t as usize];
                        b[0] <= q[2] && b[2] >= q[0] && b[1] <= q[3] && b[3] >= q[1]
                    })
                    .collect();
                assert_eq!(index.query_box(q), brute, "box {k}");
            }
        }
    }

    #[test]
    fn cells_follow_the_median_triangle() {
        let index = XyIndex::new(&scatter(3000));
        assert!(index.cell_size() > 0.7 && index.cell_size() < 1.5, "{}", index.cell_size());
        let empty = XyIndex::new(&Mesh::default());
        assert!(empty.query_disk([0.0, 0.0], 10.0).is_empty());
    }

    #[test]
    fn large_boxes_cost_no_more_than_small_ones() {
        // Many small triangles under a few that span the whole part: each
        // large one listed in every small cell would be millions of entries.
        let small = scatter(4000);
        let large = (0..400).map(|k| {
            let z = k as f64 * 0.01;
            Triangle::new(Vec3::new(-5.0, -5.0, z), Vec3::new(105.0, -5.0, z), Vec3::new(50.0, 65.0, z))
        });
        let mesh = Mesh::from_triangles(small.iter().chain(large));
        let index = XyIndex::new(&mesh);
        assert!(index.entries() <= 4 * mesh.len(), "{} entries for {} triangles", index.entries(), mesh.len());
        assert_eq!(index.query_disk([50.0, 30.0], 0.0).iter().filter(|&&t| t >= 4000).count(), 400);
    }
}
