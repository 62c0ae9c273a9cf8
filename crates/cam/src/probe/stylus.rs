//! The surfaces a stylus's readings imply, and flat margins to cross at
//! rapid.
//!
//! # Two surfaces
//! The readings are exact points of the surface the stylus's tip traces;
//! between them it is unknown. [`model`] (the default of `probe mill`)
//! draws the smooth surface of [`super::smooth`] through them and takes the
//! model to be the lowest of the stylus shapes hung from it: for a ball,
//! the stylus-centre surface offset inward by the radius. The stylus's own
//! shape placed on that model follows the smooth surface itself, through
//! every reading; another cutter is placed on the sampled model with
//! drop-cutter. [`reconstruct`] (`--between bound`) hangs the stylus from
//! the readings alone: the highest surface consistent with them, below.
//!
//! What is exact and what is bounded, for the smooth surface: the surface
//! passes through the readings exactly; the model is sampled at the fine
//! grid's nodes with the stylus hung from every node (not every point
//! between), so each sampled height is at or above the exact model by at
//! most about `δ²/4 · (1/R_c + 1/(R·cos³θ))` (node spacing `δ`, the
//! surface's radius of curvature `R_c` and slope `θ`, stylus radius `R`:
//! 0.7 µm on a 30 mm sphere read by a 10 mm ball at `δ` = 0.125 mm);
//! drop-cutter is exact on the triangles between the nodes, which depart
//! from the model by their chords, `δ²/(8·R_c)`. Where the smooth surface
//! bends tighter than a ball stylus ([`super::smooth::Smooth::tighter_than`])
//! the offset would fold over itself: the lowest of the stylus shapes
//! leaves the fold out, and no ball rolling on a model gives such readings
//! (a sharp edge, noise, a pitch too coarse), which `probe mill` reports.
//!
//! # The highest surface the readings allow (`--between bound`)
//! Readings are CL points of the stylus. A reading is where the stylus's
//! tip (its lowest point, the same convention as a cutter's) stopped on the
//! model: the stylus rested on the surface there without entering it. So with `c_i` the point's XY, `z_i`
//! its height and `h` the stylus profile (`h(r)` above the tip at radius
//! `r`, [`Cutter::height`]), the real surface `S` lies below every stylus
//! position:
//!
//! ```text
//! S(p) ≤ U(p) = min over i with |p − c_i| ≤ R of  z_i + h(|p − c_i|)
//! ```
//!
//! `U` is the highest surface consistent with the readings, and it touches
//! each stylus: where the stylus rested on `S` at `p_i`, `S(p_i)` equals that
//! stylus's bound and no other bound is lower (`S ≤ U`). Hence:
//!
//! - any cutter placed on `U` with drop-cutter is at or above the same
//!   cutter placed on `S`: it **never gouges the real surface**;
//! - the stylus itself placed on `U` at a measured point comes back to
//!   exactly `z_i`: with the same ball as cutter and a stepover equal to
//!   the pitch the program passes through the measured data.
//!
//! [`reconstruct`] samples `U` on a fine [`Heightfield`] (node spacing
//! `pitch / m`, so every measured point is a node) that drop-cutter then
//! uses as any surface. Between the nodes the triangles lie above `U` on
//! each stylus's piece (a ball's chord, at most `δ²/(8·r)` for node
//! spacing `δ`) and below it by at most `δ·|Δslope|/4` across the crease
//! where two styli's pieces meet — where `U` is normally well above `S`
//! (the crease is the top of the cusp between two readings).
//!
//! # How far the bound's copy can be from the model
//! Between readings the model can be anywhere below `U`: on a flat, the
//! cusp between neighbouring stylus positions is `h(p/2)` along the rows
//! and `h(p/√2)` at the middle of a cell (for a 10 mm ball at 1 mm pitch,
//! 0.025 and 0.050 mm), which the copy leaves as material.
//!
//! Over a concave region of radius of curvature `ρ` (seen from above) the
//! cusp grows to about `h(p/√2)·(1 + r/ρ)²` for a ball stylus of radius
//! `r`, and the cutter adds its own cusp at the stepover. Below the model
//! the copy goes only by what the readings do not know: their noise, the
//! levelling plane fitted through noisy points, the path tolerance and
//! the surface's sampling (a ball's chord `δ²/(8·r)` lies above `U`, so it
//! adds material, not a gouge). The end-to-end test
//! (`crates/cli/tests/probe.rs`: a 6 mm high bump with ρ ≥ 11 mm at its
//! foot, a 10 mm ball stylus at 1 mm pitch, tilt, ±0.002 mm noise, a 6 mm
//! ball at 0.5 mm stepover) holds these bounds, now with the smooth
//! surface: gouge ≤ 0.015 mm (noise 0.002 + tolerance 0.01 + samplings),
//! material left ≤ 0.12 mm (`0.050·(1 + 5/11)² = 0.105` plus the cutter's
//! 0.010 mm cusp); `crates/cli/tests/probe_copy.rs` shows the smooth
//! surface's copy within 2 µm where the bound's leaves 43–48 µm.

use kezuri_geom::{Axes, Heightfield, Move, MoveKind, Toolpath};
use rayon::prelude::*;

use super::smooth::Smooth;
use super::ProbeGrid;
use crate::cutter::Cutter;
use crate::error::{Error, ErrorKind};

/// Most nodes of the fine grid.
pub const MAX_NODES: usize = 60_000_000;

/// The fine grid's subdivision of the pitch for a node spacing of at most
/// `resolution`.
pub fn subdivision(pitch: f64, resolution: f64) -> usize {
    ((pitch / resolution) - 1e-9).ceil().max(1.0) as usize
}

/// The highest surface consistent with the stylus readings `data` (module
/// docs), sampled every `pitch / m` with `m` the smallest whole number
/// making the spacing at most `resolution`.
pub fn reconstruct(data: &ProbeGrid, stylus: &Cutter, resolution: f64) -> Result<Heightfield, Error> {
    let g = &data.grid;
    let r = stylus.radius();
    // Every point of the grid's box must be under some stylus.
    if r < g.pitch * std::f64::consts::FRAC_1_SQRT_2 {
        return Err(Error::new(
            ErrorKind::Surface,
            format!(
                "the stylus ({stylus}) is narrower than the grid's diagonal half-pitch ({:.3} mm): \
             the surface between the points is unknown",
                g.pitch * std::f64::consts::FRAC_1_SQRT_2
            ),
        ));
    }
    let m = fine(data, resolution)?;
    envelope(&data.z, [g.nx, g.ny], m, g.origin, g.pitch / m as f64, stylus)
}

/// The model under the smooth surface of the stylus's tip: the lowest of
/// the stylus shapes hung from every point of `smooth` (for a ball, the
/// stylus-centre surface offset inward by its radius; where that surface
/// bends tighter than the stylus, the part of the offset that would fold
/// over itself is left out), sampled like [`reconstruct`] does. The
/// stylus hangs from the fine grid's nodes, not from every point between:
/// each height is at or above the exact model's, by at most about
/// `δ²/4 · (1/R_c + 1/(R·cos³θ))` for node spacing `δ`, the surface's
/// radius of curvature `R_c` and slope `θ`, and a stylus of radius `R`.
pub fn model(smooth: &Smooth, stylus: &Cutter, resolution: f64) -> Result<Heightfield, Error> {
    let g = smooth.grid();
    let data = ProbeGrid { grid: *g, z: Vec::new() };
    let m = fine(&data, resolution)?;
    let step = g.pitch / m as f64;
    let (fx, fy) = ((g.nx - 1) * m + 1, (g.ny - 1) * m + 1);
    let tip: Vec<f64> = (0..fx * fy)
        .into_par_iter()
        .map(|k| smooth.z(g.origin[0] + (k % fx) as f64 * step, g.origin[1] + (k / fx) as f64 * step))
        .collect();
    envelope(&tip, [fx, fy], 1, g.origin, step, stylus)
}

/// The subdivision of the pitch for a node spacing of at most
/// `resolution`, checked to give a grid of at most [`MAX_NODES`].
fn fine(data: &ProbeGrid, resolution: f64) -> Result<usize, Error> {
    let g = &data.grid;
    if !(resolution.is_finite() && resolution > 0.0) {
        return Err(Error::new(
            ErrorKind::Surface,
            format!("the resolution must be a positive number of mm, got {resolution}"),
        ));
    }
    let m = subdivision(g.pitch, resolution);
    let (fx, fy) = ((g.nx - 1).saturating_mul(m) + 1, (g.ny - 1).saturating_mul(m) + 1);
    if fx.saturating_mul(fy) > MAX_NODES {
        return Err(Error::new(
            ErrorKind::Surface,
            format!("a fine grid of {fx} × {fy} nodes is too large: raise the resolution (now {resolution} mm)"),
        ));
    }
    Ok(m)
}

/// The lowest of the stylus shapes with their tips at the heights `src`
/// (`size[0] × size[1]` of them, row by row, every `stride` nodes of a
/// fine grid of `step` from `origin`), at every node of that fine grid.
fn envelope(
    src: &[f64],
    size: [usize; 2],
    stride: usize,
    origin: [f64; 2],
    step: f64,
    stylus: &Cutter,
) -> Result<Heightfield, Error> {
    let (fx, fy) = ((size[0] - 1) * stride + 1, (size[1] - 1) * stride + 1);
    let r = stylus.radius();
    // The stylus height at every offset (di, dj) fine steps from its tip.
    let k = (r / step).floor() as usize;
    let w = 2 * k + 1;
    let table: Vec<f64> = (0..w * w)
        .map(|t| {
            let (di, dj) = ((t % w) as f64 - k as f64, (t / w) as f64 - k as f64);
            let d = (di * di + dj * dj).sqrt() * step;
            if d <= r {
                stylus.height(d)
            } else {
                f64::INFINITY
            }
        })
        .collect();
    // Half the width of the stylus's disc on each row of the table.
    let half: Vec<usize> =
        (0..w).map(|dj| (0..=k).rev().find(|&d| table[dj * w + k + d].is_finite()).unwrap_or(0)).collect();
    // Source points within `reach` fine steps of fine index f: [lo, hi].
    let span = |f: usize, reach: usize, n: usize| {
        ((f.saturating_sub(reach)).div_ceil(stride), ((f + reach) / stride).min(n - 1))
    };
    let rows: Vec<Vec<f64>> = (0..fy)
        .into_par_iter()
        .map(|fj| {
            let (j0, j1) = span(fj, k, size[1]);
            (0..fx)
                .map(|fi| {
                    let mut best = f64::INFINITY;
                    for j in j0..=j1 {
                        let dj = j * stride + k - fj;
                        let (i0, i1) = span(fi, half[dj], size[0]);
                        let (line, heights) = (&table[dj * w..(dj + 1) * w], &src[j * size[0]..(j + 1) * size[0]]);
                        for i in i0..=i1 {
                            best = best.min(heights[i] + line[i * stride + k - fi]);
                        }
                    }
                    best
                })
                .collect()
        })
        .collect();
    let z: Vec<f64> = rows.into_iter().flatten().collect();
    if z.iter().any(|v| !v.is_finite()) {
        return Err(Error::new(ErrorKind::Surface, "a point of the grid is under no stylus position"));
    }
    Heightfield::new(origin[0], origin[1], step, fx, fy, z).map_err(|e| Error::new(ErrorKind::Surface, e.to_string()))
}

/// The height of a flat margin at the top of the data: the highest height
/// shared (within `tol`) by at least `share` of the points, if any.
pub fn detect_flat(data: &ProbeGrid, tol: f64, share: f64) -> Option<f64> {
    let (_, top) = data.range();
    let on: Vec<f64> = data.z.iter().copied().filter(|z| *z >= top - tol).collect();
    (on.len() as f64 >= share * data.z.len() as f64).then(|| on.iter().sum::<f64>() / on.len() as f64)
}

/// What [`rapid_margins`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Margins {
    /// Runs of cuts turned into rapids.
    pub runs: usize,
    /// Length of cutting moves turned into rapids, mm.
    pub length: f64,
}

/// Turns runs of cutting moves that stay on the flat at `flat_z` (each end
/// no lower than `flat_z − tol`, so nothing below the flat is left
/// uncut by more than `tol`, and no higher than `clearance / 2` above it —
/// a cutter on the readings rides over the cusps between stylus positions)
/// and are at least `min_length` long into rapids
/// `clearance` above it along the same path: lift, traverse, and a plunge
/// at `plunge_feed` back onto the path (the copy-milling paper did this by hand for the
/// rows over the margin, where there is nothing to cut).
pub fn rapid_margins(
    path: &Toolpath,
    flat_z: f64,
    tol: f64,
    clearance: f64,
    min_length: f64,
    plunge_feed: f64,
) -> (Toolpath, Margins) {
    let on = |z: f64| z >= flat_z - tol && z <= flat_z + 0.5 * clearance;
    let flat = |m: &Move| m.kind == MoveKind::Feed && on(m.start.z) && on(m.end.z);
    let mut out = Toolpath { moves: Vec::with_capacity(path.moves.len()), ..path.clone() };
    let mut report = Margins::default();
    let moves = &path.moves;
    // Where each move's replacement begins, for the kept blocks.
    // A kept block inside a run lifted to the traverse height goes to the
    // run's start.
    let mut first = vec![0; moves.len() + 1];
    let (mut filled, mut previous) = (0, 0);
    let mut k = 0;
    while k < moves.len() {
        while filled < k {
            first[filled] = first[previous];
            filled += 1;
        }
        first[k] = out.moves.len();
        (filled, previous) = (k + 1, k);
        if !flat(&moves[k]) {
            out.moves.push(moves[k]);
            k += 1;
            continue;
        }
        let end = (k..moves.len()).find(|&e| !flat(&moves[e])).unwrap_or(moves.len());
        let length: f64 = moves[k..end].iter().map(|m| m.length()).sum();
        if length < min_length {
            out.moves.extend_from_slice(&moves[k..end]);
        } else {
            let high = flat_z + clearance;
            let lift = |p: Axes| Axes { z: high, ..p };
            let first = moves[k];
            let vertical = |m: &Move| m.start.x == m.end.x && m.start.y == m.end.y;
            // A plunge onto the run's start stops at the traverse height.
            match out.moves.last_mut() {
                Some(p) if p.kind == MoveKind::Feed && vertical(p) && p.end == first.start && p.start.z > high => {
                    p.end = lift(first.start);
                }
                _ => {
                    out.moves.push(Move { kind: MoveKind::Rapid, start: first.start, end: lift(first.start), ..first })
                }
            }
            for m in &moves[k..end] {
                let (a, b) = (lift(m.start), lift(m.end));
                // Collinear traverses in the same direction become one.
                match out.moves.last_mut() {
                    Some(p) if p.kind == MoveKind::Rapid && p.end == a && same_direction(p.start, a, b) => p.end = b,
                    _ => out.moves.push(Move { kind: MoveKind::Rapid, start: a, end: b, ..*m }),
                }
            }
            let last = moves[end - 1];
            // A retract after the run starts from the traverse height.
            match moves.get(end) {
                Some(next) if next.is_rapid() && vertical(next) && next.end.z >= high => {
                    out.moves.push(Move { start: lift(last.end), ..*next });
                    k = end + 1;
                }
                _ => {
                    out.moves.push(Move {
                        kind: MoveKind::Feed,
                        start: lift(last.end),
                        end: last.end,
                        feed: plunge_feed,
                        ..last
                    });
                    k = end;
                }
            }
            report.runs += 1;
            report.length += length;
            continue;
        }
        k = end;
    }
    while filled < moves.len() {
        first[filled] = first[previous];
        filled += 1;
    }
    first[moves.len()] = out.moves.len();
    out.kept = path.kept_in(&first);
    (out, report)
}

/// Whether `b − a` runs the same way as `a − p` (in plan, at one height).
fn same_direction(p: Axes, a: Axes, b: Axes) -> bool {
    let (u, v) = ([a.x - p.x, a.y - p.y], [b.x - a.x, b.y - a.y]);
    let cross = u[0] * v[1] - u[1] * v[0];
    let dot = u[0] * v[0] + u[1] * v[1];
    p.z == a.z && a.z == b.z && dot > 0.0 && cross.abs() <= 1e-12 * (dot.abs() + 1.0)
}

/// Where a cutter's exact location on a flat margin does not matter,
/// because a program that crosses the flat at rapid turns it into a
/// traverse: a safe bound of it serves, with no drop-cutter.
///
/// With every reading at most `flat_z + tol` (the flat is the top), the
/// surface `U` the readings imply is nowhere above `flat_z + tol + h(p/√2)`
/// (the stylus's cusp in the middle of a cell, `p` the pitch), and a
/// cutter resting on `U` is no higher than the highest point under it:
/// that height is a cutter location never below the exact one. Where every
/// reading within the stylus's radius plus a pitch of the cutter's axis is
/// within `tol` of `flat_z`, `U` under the axis is at least `flat_z − tol`,
/// so the exact location lies in the band [`rapid_margins`] turns into
/// rapids, and the bound does too. On a flat run too short to become a
/// rapid the bound leaves at most `tol + h(p/√2)` more material than the
/// exact location; it never cuts deeper. The same holds on the smooth
/// surface's model ([`model`]): its cells stay between their readings, so
/// under the axis it lies between `flat_z − tol` and `flat_z + tol`.
#[derive(Clone, Debug)]
pub struct OverFlat {
    grid: super::Grid,
    /// Node by node: every reading near enough to shape the surface there
    /// is flat.
    clear: Vec<bool>,
    /// The bound returned there.
    z: f64,
}

impl OverFlat {
    /// The nodes of `data` whose readings within the stylus's radius plus a
    /// pitch are all on the flat at `flat_z` (within `tol`).
    pub fn new(data: &ProbeGrid, stylus: &Cutter, flat_z: f64, tol: f64) -> OverFlat {
        let g = data.grid;
        let reach = stylus.radius() + g.pitch;
        let k = (reach / g.pitch).ceil() as isize;
        let mut clear = vec![true; g.len()];
        for j in 0..g.ny {
            for i in 0..g.nx {
                if (data.z(i, j) - flat_z).abs() <= tol {
                    continue;
                }
                // A reading off the flat: no node within reach is clear.
                for dj in -k..=k {
                    for di in -k..=k {
                        let (a, b) = (i as isize + di, j as isize + dj);
                        let near = ((di * di + dj * dj) as f64).sqrt() * g.pitch <= reach;
                        if near && a >= 0 && b >= 0 && (a as usize) < g.nx && (b as usize) < g.ny {
                            clear[b as usize * g.nx + a as usize] = false;
                        }
                    }
                }
            }
        }
        let z = flat_z + tol + stylus.height(g.pitch * std::f64::consts::FRAC_1_SQRT_2);
        OverFlat { grid: g, clear, z }
    }

    /// The bound at `(x, y)` where only flat readings shape the surface
    /// under the axis (judged at the nearest node, within the pitch the
    /// reach allows for); `None` elsewhere.
    pub fn height(&self, x: f64, y: f64) -> Option<f64> {
        let g = &self.grid;
        let i = ((x - g.origin[0]) / g.pitch).round();
        let j = ((y - g.origin[1]) / g.pitch).round();
        if !(i >= 0.0 && j >= 0.0 && i < g.nx as f64 && j < g.ny as f64) {
            return None;
        }
        self.clear[j as usize * g.nx + i as usize].then_some(self.z)
    }
}
