//! Export geometry: DXF cross sections (the copy-milling paper's CAD files, one
//! polyline per row), a surface mesh, a shaded picture, and mirroring a
//! model measured on one half.

use std::fmt::Write as _;

use kezuri_geom::Triangle;

use super::data::num;
use super::ProbeGrid;

/// Which half a mirror completes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mirror {
    /// Reflect in the last column (the largest X): the grid doubles along X.
    X,
    /// Reflect in the last row (the largest Y): the grid doubles along Y.
    Y,
}

/// The model completed by its mirror image: the measured half, then its
/// reflection in the last column (or row), which is the symmetry line and
/// appears once. The grid keeps its origin, pitch and order.
pub fn mirror(data: &ProbeGrid, axis: Mirror) -> ProbeGrid {
    let g = data.grid;
    let (nx, ny) = match axis {
        Mirror::X => (2 * g.nx - 1, g.ny),
        Mirror::Y => (g.nx, 2 * g.ny - 1),
    };
    let fold = |v: usize, n: usize| if v < n { v } else { 2 * (n - 1) - v };
    let z = (0..nx * ny)
        .map(|k| {
            let (i, j) = (k % nx, k / nx);
            match axis {
                Mirror::X => data.z(fold(i, g.nx), j),
                Mirror::Y => data.z(i, fold(j, g.ny)),
            }
        })
        .collect();
    ProbeGrid { grid: super::Grid { nx, ny, ..g }, z }
}

/// An AutoCAD R12 ASCII DXF: a 3D POLYLINE per row on layer `ROWS` (the
/// paper's cross sections, X–Z profiles at each Y), and with `columns` one
/// per column on layer `COLS`. Coordinates in mm.
pub fn dxf(data: &ProbeGrid, columns: bool) -> String {
    let g = &data.grid;
    let mut out = String::new();
    let pair = |out: &mut String, code: i32, value: &str| {
        let _ = writeln!(out, "{code:>3}\n{value}");
    };
    pair(&mut out, 0, "SECTION");
    pair(&mut out, 2, "HEADER");
    pair(&mut out, 9, "$ACADVER");
    pair(&mut out, 1, "AC1009");
    pair(&mut out, 9, "$INSUNITS");
    pair(&mut out, 70, "4");
    pair(&mut out, 0, "ENDSEC");
    pair(&mut out, 0, "SECTION");
    pair(&mut out, 2, "TABLES");
    pair(&mut out, 0, "TABLE");
    pair(&mut out, 2, "LAYER");
    pair(&mut out, 70, "2");
    for (name, colour) in [("ROWS", "7"), ("COLS", "5")] {
        pair(&mut out, 0, "LAYER");
        pair(&mut out, 2, name);
        pair(&mut out, 70, "0");
        pair(&mut out, 62, colour);
        pair(&mut out, 6, "CONTINUOUS");
    }
    pair(&mut out, 0, "ENDTAB");
    pair(&mut out, 0, "ENDSEC");
    pair(&mut out, 0, "SECTION");
    pair(&mut out, 2, "ENTITIES");
    let polyline = |out: &mut String, layer: &str, points: &mut dyn Iterator<Item = [f64; 3]>| {
        pair(out, 0, "POLYLINE");
        pair(out, 8, layer);
        pair(out, 66, "1");
        pair(out, 10, "0.0");
        pair(out, 20, "0.0");
        pair(out, 30, "0.0");
        pair(out, 70, "8");
        for p in points {
            pair(out, 0, "VERTEX");
            pair(out, 8, layer);
            pair(out, 10, &num(p[0], 6));
            pair(out, 20, &num(p[1], 6));
            pair(out, 30, &num(p[2], 6));
            pair(out, 70, "32");
        }
        pair(out, 0, "SEQEND");
        pair(out, 8, layer);
    };
    for j in 0..g.ny {
        polyline(&mut out, "ROWS", &mut (0..g.nx).map(|i| [g.x(i), g.y(j), data.z(i, j)]));
    }
    if columns {
        for i in 0..g.nx {
            polyline(&mut out, "COLS", &mut (0..g.ny).map(|j| [g.x(i), g.y(j), data.z(i, j)]));
        }
    }
    pair(&mut out, 0, "ENDSEC");
    pair(&mut out, 0, "EOF");
    out
}

/// The surface through the points: two triangles per cell (split along the
/// diagonal from `(i, j)` to `(i+1, j+1)`, as [`kezuri_geom::Heightfield`]).
pub fn triangles(data: &ProbeGrid) -> Vec<Triangle> {
    let g = &data.grid;
    let p = |i: usize, j: usize| kezuri_geom::Vec3::new(g.x(i), g.y(j), data.z(i, j));
    let mut out = Vec::with_capacity(2 * (g.nx - 1) * (g.ny - 1));
    for j in 0..g.ny - 1 {
        for i in 0..g.nx - 1 {
            out.push(Triangle::new(p(i, j), p(i + 1, j), p(i + 1, j + 1)));
            out.push(Triangle::new(p(i, j), p(i + 1, j + 1), p(i, j + 1)));
        }
    }
    out
}

/// Width and height in pixels of [`shade`]'s picture at `scale` pixels
/// per pitch; `None` when they overflow.
pub fn shade_size(data: &ProbeGrid, scale: usize) -> Option<(usize, usize)> {
    let side = |n: usize| n.checked_sub(1)?.checked_mul(scale.max(1))?.checked_add(1);
    Some((side(data.grid.nx)?, side(data.grid.ny)?))
}

/// A hill-shaded picture (light from the north-west, 60° up, a face turned
/// from it at 60 % of its tint, never black; tinted by height), `scale`
/// pixels per pitch, +Y up: `(width, height, RGB bytes)`.
/// The caller bounds the size ([`shade_size`]).
pub fn shade(data: &ProbeGrid, scale: usize) -> (usize, usize, Vec<u8>) {
    let g = &data.grid;
    let scale = scale.max(1);
    let (w, h) = shade_size(data, scale).unwrap_or((1, 1));
    let (lo, hi) = data.range();
    let span = (hi - lo).max(1e-12);
    // Bilinear height at fractional node coordinates.
    let at = |u: f64, v: f64| {
        let (i, j) = ((u.floor() as usize).min(g.nx - 2), (v.floor() as usize).min(g.ny - 2));
        let (s, t) = (u - i as f64, v - j as f64);
        let a = data.z(i, j) * (1.0 - s) + data.z(i + 1, j) * s;
        let b = data.z(i, j + 1) * (1.0 - s) + data.z(i + 1, j + 1) * s;
        a * (1.0 - t) + b * t
    };
    let (az, alt) = (315f64.to_radians(), 60f64.to_radians());
    let light = [alt.cos() * az.sin(), alt.cos() * az.cos(), alt.sin()];
    let d = 1.0 / scale as f64;
    let mut rgb = Vec::with_capacity(w * h * 3);
    for row in 0..h {
        let v = (h - 1 - row) as f64 * d;
        for col in 0..w {
            let u = col as f64 * d;
            let (u0, u1) = ((u - d).max(0.0), (u + d).min((g.nx - 1) as f64));
            let (v0, v1) = ((v - d).max(0.0), (v + d).min((g.ny - 1) as f64));
            let gx = (at(u1, v) - at(u0, v)) / ((u1 - u0) * g.pitch);
            let gy = (at(u, v1) - at(u, v0)) / ((v1 - v0) * g.pitch);
            let n = [-gx, -gy, 1.0];
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            let lit = ((n[0] * light[0] + n[1] * light[1] + n[2] * light[2]) / len).max(0.0);
            let t = (at(u, v) - lo) / span;
            let shade = 0.6 + 0.4 * lit;
            rgb.extend_from_slice(&[
                (255.0 * shade * (0.55 + 0.45 * t)).round() as u8,
                (255.0 * shade * 0.8).round() as u8,
                (255.0 * shade * (1.0 - 0.45 * t)).round() as u8,
            ]);
        }
    }
    (w, h, rgb)
}
