//! `sim`'s pictures (shaded heights, deviation) and its surface as STL.

use std::path::Path;

use anyhow::{Context, Result};
use image::codecs::png::PngEncoder;
use image::{ExtendedColorType, ImageEncoder};
use kezuri_cam::sim::ZMap;
use kezuri_geom::{write_binary_stl_to, Triangle, Vec3};

use crate::files::Outputs;

/// Largest picture side; bigger grids are sampled every k-th cell.
const MAX_SIDE: usize = 4096;

/// The cells a picture shows: every `k`-th along both axes.
fn picture_grid(zmap: &ZMap) -> (usize, usize, usize) {
    let k = zmap.nx.max(zmap.ny).div_ceil(MAX_SIDE).max(1);
    (k, zmap.nx.div_ceil(k), zmap.ny.div_ceil(k))
}

fn png(rgb: &[u8], w: usize, h: usize) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    PngEncoder::new(&mut out)
        .write_image(rgb, w as u32, h as u32, ExtendedColorType::Rgb8)
        .context("cannot encode the PNG")?;
    Ok(out)
}

/// The simulated surface, hill-shaded (light from the north-west, 45° up)
/// and tinted by height; +Y up.
pub fn height_png(zmap: &ZMap) -> Result<Vec<u8>> {
    let (k, w, h) = picture_grid(zmap);
    let (lo, hi) = zmap.range();
    let span = (hi - lo).max(1e-12);
    let z = |i: usize, j: usize| zmap.height(i.min(zmap.nx - 1), j.min(zmap.ny - 1));
    let d = k as f64 * zmap.res;
    let (az, alt) = (315f64.to_radians(), 45f64.to_radians());
    let light = [alt.cos() * az.sin(), alt.cos() * az.cos(), alt.sin()];
    let mut rgb = Vec::with_capacity(w * h * 3);
    for row in 0..h {
        let j = (h - 1 - row) * k;
        for col in 0..w {
            let i = col * k;
            let gx =
                (z(i + k, j) - z(i.saturating_sub(k), j)) / (d * if i >= k && i + k < zmap.nx { 2.0 } else { 1.0 });
            let gy =
                (z(i, j + k) - z(i, j.saturating_sub(k))) / (d * if j >= k && j + k < zmap.ny { 2.0 } else { 1.0 });
            // Relief exaggerated twice, so gentle cusps show.
            let (gx, gy) = (2.0 * gx, 2.0 * gy);
            let n = (1.0 + gx * gx + gy * gy).sqrt();
            let shade = ((-gx * light[0] - gy * light[1] + light[2]) / n).clamp(0.0, 1.0);
            let t = (z(i, j) - lo) / span;
            let base = [0.45 + 0.55 * t, 0.42 + 0.5 * t, 0.38 + 0.4 * t];
            for c in base {
                rgb.push((255.0 * c * (0.15 + 0.85 * shade)).round().clamp(0.0, 255.0) as u8);
            }
        }
    }
    png(&rgb, w, h)
}

/// The deviation simulated − target: red below, blue above, white on it,
/// full colour at ±`scale`; grey where there is no target.
pub fn deviation_png(zmap: &ZMap, target: &[f64], scale: f64) -> Result<Vec<u8>> {
    let (k, w, h) = picture_grid(zmap);
    let mut rgb = Vec::with_capacity(w * h * 3);
    for row in 0..h {
        let j = (h - 1 - row) * k;
        for col in 0..w {
            let c = j * zmap.nx + col * k;
            let px = if target[c] == f64::NEG_INFINITY {
                [128.0, 128.0, 128.0]
            } else {
                let t = ((zmap.z[c] - target[c]) / scale).clamp(-1.0, 1.0);
                let end = if t < 0.0 { [200.0, 20.0, 30.0] } else { [30.0, 70.0, 210.0] };
                let a = t.abs();
                [255.0 + (end[0] - 255.0) * a, 255.0 + (end[1] - 255.0) * a, 255.0 + (end[2] - 255.0) * a]
            };
            rgb.extend(px.map(|v: f64| v.round() as u8));
        }
    }
    png(&rgb, w, h)
}

/// Adds the simulated surface to `out` as a binary STL, a triangle at a
/// time: two per square of four neighbouring cell centres, facing up, split
/// as a height grid's cells are.
pub fn stage_surface_stl(out: &mut Outputs, path: &Path, zmap: &ZMap) -> Result<()> {
    let (cx, cy) = (zmap.nx.saturating_sub(1), zmap.ny.saturating_sub(1));
    let p = |i: usize, j: usize| {
        let [x, y] = zmap.centre(i, j);
        Vec3::new(x, y, zmap.height(i, j))
    };
    let triangles = (0..2 * cx * cy).map(|k| {
        let (i, j) = ((k / 2) % cx, k / 2 / cx);
        let (a, c) = (p(i, j), p(i + 1, j + 1));
        if k % 2 == 0 {
            Triangle::new(a, p(i + 1, j), c)
        } else {
            Triangle::new(a, c, p(i, j + 1))
        }
    });
    out.add_with(Some(path), |w| write_binary_stl_to(w, triangles))
}
