//! The simulated part on the page: the Z-map's cell centres as a height
//! grid (coarsened to a vertex budget, each shown vertex the lowest cell of
//! its block, so no gouge is hidden), the flat squares that can be drawn as
//! one quad, and the deviation from the target.

use kezuri_cam::sim::ZMap;
use serde_json::{json, Value};

use super::blob::Blob;
use super::pack::QUANTUM_MM;
use crate::sim::DeviationScale;

/// Deviation step of the packed values, µm.
const DEVIATION_QUANTUM_UM: f64 = 0.1;

/// A cell the target does not cover.
const NOT_COMPARED: i32 = i32::MIN;

/// What the page shows of a simulation.
pub struct Part<'a> {
    /// The simulated heights.
    pub zmap: &'a ZMap,
    /// The target's height over each cell (`-inf` where it has none).
    pub target: Option<&'a [f64]>,
    /// How the deviation is coloured (with a target).
    pub scale: Option<&'a DeviationScale>,
    /// Most vertices the page's mesh may have.
    pub max_vertices: usize,
}

/// The grid as shown: `f` cells a side per vertex.
struct Shown {
    f: usize,
    nx: usize,
    ny: usize,
}

impl Part<'_> {
    fn shown(&self) -> Shown {
        let z = self.zmap;
        let cells = (z.nx * z.ny) as f64;
        let f = (cells / self.max_vertices.max(1) as f64).sqrt().ceil().max(1.0) as usize;
        Shown { f, nx: z.nx.div_ceil(f), ny: z.ny.div_ceil(f) }
    }

    /// Deviation of cell `k` in mm, where the target covers it.
    fn deviation(&self, k: usize) -> Option<f64> {
        let t = self.target?[k];
        (t != f64::NEG_INFINITY).then(|| self.zmap.height_at(k) - t)
    }

    /// Packs sections 10 to 12 into `blob`; the meta's `sim` entry and the
    /// mesh's bounds.
    pub fn pack(&self, blob: &mut Blob) -> (Value, ([f64; 3], [f64; 3])) {
        let z = self.zmap;
        let s = self.shown();
        let mut heights = vec![f64::INFINITY; s.nx * s.ny];
        let mut deviations: Vec<Option<f64>> = vec![None; if self.target.is_some() { s.nx * s.ny } else { 0 }];
        for j in 0..z.ny {
            for i in 0..z.nx {
                let (k, shown) = (j * z.nx + i, (j / s.f) * s.nx + i / s.f);
                heights[shown] = heights[shown].min(z.height_at(k));
                if let Some(d) = self.deviation(k) {
                    let slot = &mut deviations[shown];
                    if slot.is_none_or(|old| d.abs() > old.abs()) {
                        *slot = Some(d);
                    }
                }
            }
        }
        let (lo, hi) = heights.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &h| (a.min(h), b.max(h)));
        let quanta: Vec<i32> =
            heights.iter().map(|h| ((h - lo) / QUANTUM_MM).round().min(i32::MAX as f64) as i32).collect();
        let devs: Vec<i32> = deviations
            .iter()
            .map(|d| match d {
                Some(d) => {
                    (d * 1000.0 / DEVIATION_QUANTUM_UM).round().clamp(-(i32::MAX as f64), i32::MAX as f64) as i32
                }
                None => NOT_COMPARED,
            })
            .collect();
        let key = |k: usize| (quanta[k], devs.get(k).copied().unwrap_or(0));
        let blocks = flat_blocks(s.nx, s.ny, key);

        let mut previous = 0i32;
        blob.i32s(quanta.iter().map(|&q| {
            let d = q.wrapping_sub(previous);
            previous = q;
            d
        }));
        blob.u32s(blocks.iter().flat_map(|b| b.iter().map(|&v| v as u32)));
        let deviation = self.target.zip(self.scale).map(|(_, scale)| {
            blob.i32s(devs.iter().copied());
            json!({
                "scale_um": scale.mm * 1000.0,
                "scale_basis": scale.basis,
                "gouge_um": scale.gouge * 1000.0,
                "left_max_um": scale.extremes[1] * 1000.0,
                "gouge_max_um": scale.extremes[0] * 1000.0,
                "quantum_um": DEVIATION_QUANTUM_UM,
            })
        });
        let cell = z.res * s.f as f64;
        let (x0, y0) = (z.x0 + cell / 2.0, z.y0 + cell / 2.0);
        let meta = json!({
            "nx": s.nx, "ny": s.ny, "x0_mm": x0, "y0_mm": y0, "cell_mm": cell, "sim_cell_mm": z.res,
            "z0_mm": lo, "blocks": blocks.len(), "deviation": deviation,
        });
        let far = [x0 + cell * (s.nx - 1) as f64, y0 + cell * (s.ny - 1) as f64, hi];
        (meta, ([x0, y0, lo], far))
    }
}

/// The largest squares of quads (power-of-two sides, at least 2) whose
/// vertices all have one key, as `(i, j, size)` from vertex `(i, j)`, on a
/// grid of `nx` × `ny` vertices (`key(j·nx + i)`).
fn flat_blocks<K: PartialEq>(nx: usize, ny: usize, key: impl Fn(usize) -> K) -> Vec<[usize; 3]> {
    let (qx, qy) = (nx.saturating_sub(1), ny.saturating_sub(1));
    if qx == 0 || qy == 0 {
        return Vec::new();
    }
    // levels[l][b·w + a]: the square of 2^l quads from quad (a·2^l, b·2^l)
    // lies inside the grid and is flat; its key is its first vertex's.
    let mut levels: Vec<(usize, Vec<bool>)> = Vec::new();
    let mut flat = Vec::with_capacity(qx * qy);
    for j in 0..qy {
        for i in 0..qx {
            let k = j * nx + i;
            let first = key(k);
            flat.push(key(k + 1) == first && key(k + nx) == first && key(k + nx + 1) == first);
        }
    }
    levels.push((qx, flat));
    let mut side = 1;
    while side < qx.max(qy) {
        let (w, below) = levels.last().unwrap();
        let (w, h) = (*w, below.len() / *w);
        let (nw, nh) = (w.div_ceil(2), h.div_ceil(2));
        side *= 2;
        let mut up = vec![false; nw * nh];
        for b in 0..nh {
            for a in 0..nw {
                let inside = (a + 1) * side <= qx && (b + 1) * side <= qy;
                let children = [(2 * a, 2 * b), (2 * a + 1, 2 * b), (2 * a, 2 * b + 1), (2 * a + 1, 2 * b + 1)];
                let half = side / 2;
                up[b * nw + a] = inside && {
                    let first = key(b * side * nx + a * side);
                    children.iter().all(|&(ca, cb)| below[cb * w + ca] && key(cb * half * nx + ca * half) == first)
                };
            }
        }
        levels.push((nw, up));
    }
    let mut out = Vec::new();
    let top = levels.len() - 1;
    let (w, v) = &levels[top];
    for b in 0..v.len() / w {
        for a in 0..*w {
            emit(&levels, top, a, b, &mut out);
        }
    }
    out
}

/// Emits the square `(a, b)` of level `l` if it is flat, else its flat parts.
fn emit(levels: &[(usize, Vec<bool>)], l: usize, a: usize, b: usize, out: &mut Vec<[usize; 3]>) {
    let (w, flat) = &levels[l];
    if a >= *w || b >= flat.len() / w {
        return;
    }
    if flat[b * w + a] {
        if l > 0 {
            out.push([a << l, b << l, 1 << l]);
        }
        return;
    }
    if l > 0 {
        for (ca, cb) in [(2 * a, 2 * b), (2 * a + 1, 2 * b), (2 * a, 2 * b + 1), (2 * a + 1, 2 * b + 1)] {
            emit(levels, l - 1, ca, cb, out);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Checked cell by cell: every block is an aligned power-of-two square
    /// whose vertices all have one height, blocks never overlap, and the
    /// plain around a bump is merged into few blocks.
    #[test]
    fn blocks_cover_only_flat_quads_and_do_not_overlap() {
        let (nx, ny) = (37, 23);
        // A plateau with a bump and a slope: flat squares of many sizes.
        let h = |i: usize, j: usize| -> i32 {
            if (10..14).contains(&i) && (5..9).contains(&j) {
                7
            } else if i > 30 {
                i as i32
            } else {
                0
            }
        };
        let blocks = flat_blocks(nx, ny, |k| h(k % nx, k / nx));
        let mut covered = vec![0u8; (nx - 1) * (ny - 1)];
        for &[i, j, s] in &blocks {
            assert!(s >= 2 && s.is_power_of_two() && i % s == 0 && j % s == 0, "{i} {j} {s}");
            let first = h(i, j);
            for jj in j..=j + s {
                for ii in i..=i + s {
                    assert_eq!(h(ii, jj), first, "block {i} {j} {s} not flat at {ii} {jj}");
                }
            }
            for jj in j..j + s {
                for ii in i..i + s {
                    covered[jj * (nx - 1) + ii] += 1;
                }
            }
        }
        assert!(covered.iter().all(|&c| c <= 1));
        // Most of the plain is merged: few quads left to draw one by one.
        let single = covered.iter().filter(|&&c| c == 0).count();
        assert!(blocks.len() + single < covered.len() / 3, "{} blocks, {single} single", blocks.len());
    }
}
