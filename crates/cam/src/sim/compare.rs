//! The simulated surface against the intended one.
//!
//! The target is a set of triangles (a mesh, or a height grid split into
//! triangles). Its height at each cell centre is a vertical ray cast: the
//! highest triangle over the centre ([`target_heights`]), so a closed solid
//! gives its top face. Cells the target does not cover are left out of the
//! statistics and counted.
//!
//! Deviation is `simulated − target`: negative is a gouge (the cut went
//! below the part), positive is material left.

use super::ZMap;

/// Heights of the target's top surface at the cell centres of `grid`;
/// `f64::NEG_INFINITY` where no triangle lies over a centre. Triangles
/// with a coordinate that is not finite, or no area seen from above
/// (vertical walls, degenerate triangles), cast no height.
pub fn target_heights(grid: &ZMap, triangles: impl IntoIterator<Item = [[f64; 3]; 3]>) -> Vec<f64> {
    let (nx, ny, res) = (grid.nx, grid.ny, grid.res);
    let mut out = vec![f64::NEG_INFINITY; nx * ny];
    for t in triangles {
        if !t.iter().flatten().all(|v| v.is_finite()) {
            continue;
        }
        let [a, b, c] = t;
        // Twice the signed XY area.
        let area = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
        let scale = (b[0] - a[0]).abs().max((c[0] - a[0]).abs()).max((b[1] - a[1]).abs()).max((c[1] - a[1]).abs());
        if area.abs() <= 1e-14 * scale * scale || area.abs() == 0.0 {
            continue;
        }
        let lo_x = a[0].min(b[0]).min(c[0]);
        let hi_x = a[0].max(b[0]).max(c[0]);
        let lo_y = a[1].min(b[1]).min(c[1]);
        let hi_y = a[1].max(b[1]).max(c[1]);
        let is = super::sweep::cell_range(lo_x, hi_x, grid.x0, res, nx);
        // Rows counted over the whole grid (the same centres in a tile), then
        // those held.
        let js = super::sweep::cell_range(lo_y, hi_y, grid.y0, res, grid.first_row + ny);
        let js = js.start.max(grid.first_row) - grid.first_row..js.end.max(grid.first_row) - grid.first_row;
        // Points on an edge belong to both triangles: a small tolerance
        // keeps a centre on a shared edge from falling through.
        let eps = -1e-12 * area.abs();
        for j in js {
            let y = grid.y0 + ((grid.first_row + j) as f64 + 0.5) * res;
            for i in is.clone() {
                let x = grid.x0 + (i as f64 + 0.5) * res;
                let wa = (b[0] - x) * (c[1] - y) - (c[0] - x) * (b[1] - y);
                let wb = (c[0] - x) * (a[1] - y) - (a[0] - x) * (c[1] - y);
                let wc = (a[0] - x) * (b[1] - y) - (b[0] - x) * (a[1] - y);
                let (wa, wb, wc) = if area > 0.0 { (wa, wb, wc) } else { (-wa, -wb, -wc) };
                if wa >= eps && wb >= eps && wc >= eps {
                    let sum = wa + wb + wc;
                    let z = (wa * a[2] + wb * b[2] + wc * c[2]) / sum;
                    let k = j * nx + i;
                    if z > out[k] {
                        out[k] = z;
                    }
                }
            }
        }
    }
    out
}

/// Counts of deviations in equal bins.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Histogram {
    /// Bin edges in mm, one more than the bins.
    pub edges: Vec<f64>,
    /// Cells per bin; the last bin includes its upper edge.
    pub counts: Vec<u64>,
}

/// The simulated surface against the target.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Comparison {
    /// Cells with a target height.
    pub compared: usize,
    /// Cells without one (outside the target).
    pub missing: usize,
    /// Deepest point below the target (≥ 0, mm).
    pub max_gouge: f64,
    /// Where (cell centre), if anywhere below the target.
    pub gouge_at: Option<[f64; 2]>,
    /// Its cell (`j·nx + i`, rows counted over the whole grid).
    pub gouge_cell: Option<usize>,
    /// Most material left above the target (≥ 0, mm).
    pub max_left: f64,
    /// Where (cell centre), if anywhere above the target.
    pub left_at: Option<[f64; 2]>,
    /// Mean of |simulated − target| (mm).
    pub mean_abs_dev: f64,
    /// Lowest and highest deviation (mm).
    pub range: (f64, f64),
    /// Deviations in `bins` equal bins over `range`.
    pub histogram: Histogram,
}

/// A comparison gathered part by part: the tiles of a grid
/// ([`super::simulate_tiles`]) in order of rows, or a whole grid. Every
/// figure of [`compare`] but the histogram, the same to the bit as over
/// the whole grid at once (the cells are taken in the same order).
#[derive(Clone, Debug)]
pub struct Tally {
    c: Comparison,
    /// Σ |simulated − target|.
    sum: f64,
}

impl Default for Tally {
    fn default() -> Tally {
        Tally { c: Comparison { range: (f64::INFINITY, f64::NEG_INFINITY), ..Comparison::default() }, sum: 0.0 }
    }
}

impl Tally {
    /// Adds the cells of `sim` (a grid or the next tile of one) against
    /// `target` (from [`target_heights`] on it).
    pub fn add(&mut self, sim: &ZMap, target: &[f64]) {
        let (c, base) = (&mut self.c, sim.first_row * sim.nx);
        for (k, (z, &t)) in sim.heights().zip(target).enumerate() {
            if t == f64::NEG_INFINITY {
                c.missing += 1;
                continue;
            }
            let d = z - t;
            c.compared += 1;
            self.sum += d.abs();
            c.range = (c.range.0.min(d), c.range.1.max(d));
            let at = || sim.centre(k % sim.nx, k / sim.nx);
            if -d > c.max_gouge {
                c.max_gouge = -d;
                c.gouge_at = Some(at());
                c.gouge_cell = Some(base + k);
            }
            if d > c.max_left {
                c.max_left = d;
                c.left_at = Some(at());
            }
        }
    }

    /// The comparison so far, without its histogram ([`histogram`]).
    pub fn comparison(&self) -> Comparison {
        let mut c = self.c.clone();
        if c.compared == 0 {
            c.range = (0.0, 0.0);
        } else {
            c.mean_abs_dev = self.sum / c.compared as f64;
        }
        c
    }
}

/// `c`'s histogram of `bins` equal bins (at least 1) over `c.range`, of
/// the deviations of `sim` from `target`: the cells of the comparison, or
/// a sample of them.
pub fn histogram(c: &mut Comparison, sim: &ZMap, target: &[f64], bins: usize) {
    let bins = bins.max(1);
    let (lo, hi) = c.range;
    let width = (hi - lo) / bins as f64;
    c.histogram.edges = (0..=bins).map(|b| if b == bins { hi } else { lo + width * b as f64 }).collect();
    c.histogram.counts = vec![0; bins];
    for (z, &t) in sim.heights().zip(target) {
        if t == f64::NEG_INFINITY {
            continue;
        }
        let d = z - t;
        let b = if width > 0.0 { (((d - lo) / width).max(0.0) as usize).min(bins - 1) } else { 0 };
        c.histogram.counts[b] += 1;
    }
}

/// Compares `sim` with `target` (from [`target_heights`] on the same grid),
/// with a histogram of `bins` bins (at least 1).
pub fn compare(sim: &ZMap, target: &[f64], bins: usize) -> Comparison {
    let mut tally = Tally::default();
    tally.add(sim, target);
    let mut c = tally.comparison();
    if c.compared > 0 {
        histogram(&mut c, sim, target, bins);
    }
    c
}

/// The deepest gouge of one tool.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToolGouge {
    /// Depth below the target (> 0, mm).
    pub depth: f64,
    /// Where (cell centre).
    pub at: [f64; 2],
}

/// For each of `tools` tools (indices of `cut_by`, from
/// [`super::SimReport::cut_by`]), the deepest gouge among the cells it
/// lowered last, if any went below the target.
pub fn gouges_by_tool(sim: &ZMap, target: &[f64], cut_by: &[u8], tools: usize) -> Vec<Option<ToolGouge>> {
    let mut out: Vec<Option<ToolGouge>> = vec![None; tools];
    for (k, ((z, &t), &by)) in sim.heights().zip(target).zip(cut_by).enumerate() {
        let depth = t - z;
        let Some(worst) = out.get_mut(by as usize) else { continue };
        if t != f64::NEG_INFINITY && depth > 0.0 && worst.is_none_or(|g| depth > g.depth) {
            *worst = Some(ToolGouge { depth, at: sim.centre(k % sim.nx, k / sim.nx) });
        }
    }
    out
}

/// Cells of `sim` deeper than `allowance` below `target` (from
/// [`target_heights`] on the same grid): the gouges past the program's
/// allowance, which the deviation picture paints magenta.
pub fn gouged_cells(sim: &ZMap, target: &[f64], allowance: f64) -> usize {
    sim.heights().zip(target).filter(|&(z, &t)| t != f64::NEG_INFINITY && t - z > allowance).count()
}
