//! Fields of view stitched into one picture (the thermal and wear report:
//! a tool larger than the microscope's field is imaged at several stage
//! offsets, overlapping by 100 µm and 70 µm, and the pictures joined).
//!
//! Each field is placed at its stage offset (pixels: where its pixel
//! `(0, 0)` lies in the common frame, x right, y down). For every pair of
//! fields whose placed pictures overlap, the shift between them is
//! refined: first the whole-pixel shift within `search` pixels of the
//! stage's that gives the least mean squared difference over the overlap,
//! then Gauss–Newton on the bilinear picture (Lucas–Kanade) to a thousandth
//! of a pixel. The overlap's gradients say how well it fixes each
//! direction (a straight vertical edge fixes x but not y), so the
//! positions are the weighted least-squares fit to all pairs at once
//! (`Σ (Δ − d)ᵀ H (Δ − d)`, `H` the pair's Gauss–Newton matrix), with the
//! first field held at its stage offset and a faint pull of every field
//! toward its own stage offset for directions no overlap fixes (each
//! reported in [`Placement::warnings`]).

use crate::tool_image::GrayImage;
use crate::{Error, ErrorKind};

/// A refined overlap between fields `a` and `b`.
#[derive(Clone, Debug, PartialEq)]
pub struct Overlap {
    /// The two fields (indices).
    pub fields: (usize, usize),
    /// Position of `b` less position of `a` by the stage, pixels.
    pub stage: [f64; 2],
    /// The same by the pictures.
    pub measured: [f64; 2],
    /// How strongly the overlap fixes x and y: √ of the diagonal of its
    /// Gauss–Newton matrix (gray level per pixel of shift, summed over the
    /// overlap in quadrature). Below [`WEAK`] a direction is not fixed.
    pub strength: [f64; 2],
}

/// A strength below which an overlap does not fix a direction: about two
/// pixels of a sharp edge of full contrast.
pub const WEAK: f64 = 1.0;

/// The fields' refined positions.
#[derive(Clone, Debug, PartialEq)]
pub struct Placement {
    /// Per field, where its pixel `(0, 0)` lies, pixels.
    pub at: Vec<[f64; 2]>,
    /// The refined overlaps.
    pub overlaps: Vec<Overlap>,
    /// Directions taken from the stage alone, and the like.
    pub warnings: Vec<String>,
}

/// Gray-level change per pixel below which a pixel is taken as flat
/// (backlight or tool, its gradient only noise) and left out of the fit:
/// a sharp edge changes by the full contrast within a pixel.
const FLAT: f64 = 0.05;

/// Least overlap, pixels in each direction, for a pair to be refined.
const MIN_OVERLAP: f64 = 8.0;

/// Most pixel comparisons the whole-pixel search may make (some seconds).
const MAX_COMPARISONS: f64 = 1e10;

/// The fields `(picture, stage offset)` placed: see the module.
pub fn place(fields: &[(&GrayImage, [f64; 2])], search: usize) -> Result<Placement, Error> {
    let n = fields.len();
    let mut pairs = Vec::new();
    for a in 0..n {
        for b in a + 1..n {
            let (ia, pa) = fields[a];
            let (ib, pb) = fields[b];
            let stage = [pb[0] - pa[0], pb[1] - pa[1]];
            let wide = |d: f64, wa: usize, wb: usize| (wa as f64).min(d + wb as f64) - d.max(0.0);
            if wide(stage[0], ia.width, ib.width) >= MIN_OVERLAP && wide(stage[1], ia.height, ib.height) >= MIN_OVERLAP
            {
                pairs.push((a, b, stage));
            }
        }
    }
    // A shift beyond the pictures overlaps nothing; the rest is weighed
    // before the work: each overlap tries every shift at up to 40,000
    // sampled pixels.
    let widest = fields.iter().map(|(i, _)| i.width.max(i.height)).max().unwrap_or(0);
    let search = search.min(widest);
    let comparisons = pairs.len() as f64 * ((2 * search + 1) as f64).powi(2) * 40_000.0;
    if comparisons > MAX_COMPARISONS {
        return Err(Error::new(
            ErrorKind::SearchTooWide,
            format!(
                "a search of {search} pixels over {} overlaps is up to {comparisons:.1e} comparisons, more than \
                 {MAX_COMPARISONS:.0e}: give a smaller --search-um (about the stage's error)",
                pairs.len()
            ),
        ));
    }
    let mut overlaps = Vec::new();
    for (a, b, stage) in pairs {
        let (measured, hessian) = register(fields[a].0, fields[b].0, stage, search).ok_or_else(|| {
            Error::new(ErrorKind::NoOverlap, format!("fields {} and {} do not overlap once shifted", a + 1, b + 1))
        })?;
        let hessian = fixed_part(hessian);
        let strength = [hessian[0][0].sqrt(), hessian[1][1].sqrt()];
        overlaps.push(Pair { overlap: Overlap { fields: (a, b), stage, measured, strength }, hessian });
    }
    connected(n, &overlaps)?;
    Ok(solve(fields, overlaps))
}

/// The part of a pair's Gauss–Newton matrix its pictures fix: directions
/// (eigenvectors) whose strength is below [`WEAK`] are dropped, so the
/// noise along a straight edge does not pull the fit there and the stage
/// offset decides it.
fn fixed_part(h: [[f64; 2]; 2]) -> [[f64; 2]; 2] {
    let (a, b, d) = (h[0][0], h[0][1], h[1][1]);
    let mean = 0.5 * (a + d);
    let spread = (0.25 * (a - d) * (a - d) + b * b).sqrt();
    let mut out = [[0.0; 2]; 2];
    for lambda in [mean + spread, mean - spread] {
        if lambda < WEAK * WEAK {
            continue;
        }
        // An eigenvector of [[a, b], [b, d]] for lambda.
        let v = if b.abs() > 1e-300 {
            [lambda - d, b]
        } else if (lambda - a).abs() <= (lambda - d).abs() {
            [1.0, 0.0]
        } else {
            [0.0, 1.0]
        };
        let n = v[0].hypot(v[1]);
        let v = [v[0] / n, v[1] / n];
        for (r, row) in out.iter_mut().enumerate() {
            for (c, x) in row.iter_mut().enumerate() {
                *x += lambda * v[r] * v[c];
            }
        }
    }
    out
}

/// An overlap with its Gauss–Newton matrix, before the solve.
struct Pair {
    overlap: Overlap,
    hessian: [[f64; 2]; 2],
}

/// Every field joined to the first through overlaps, or which is not.
fn connected(n: usize, pairs: &[Pair]) -> Result<(), Error> {
    let mut reached = vec![false; n];
    reached[0] = true;
    let mut changed = true;
    while changed {
        changed = false;
        for p in pairs {
            let (a, b) = p.overlap.fields;
            if reached[a] != reached[b] {
                (reached[a], reached[b]) = (true, true);
                changed = true;
            }
        }
    }
    match reached.iter().position(|r| !r) {
        None => Ok(()),
        Some(k) => Err(Error::new(
            ErrorKind::NoOverlap,
            format!(
                "field {} does not overlap the others by its stage offset (at least {MIN_OVERLAP} pixels each way \
                 are needed; 100 and 70 µm overlaps are usual)",
                k + 1
            ),
        )),
    }
}

/// The weighted least-squares positions (module docs).
fn solve(fields: &[(&GrayImage, [f64; 2])], pairs: Vec<Pair>) -> Placement {
    let n = fields.len();
    let m = 2 * (n - 1);
    let mut warnings = Vec::new();
    if n == 1 {
        return Placement { at: vec![fields[0].1], overlaps: Vec::new(), warnings };
    }
    let mut a = vec![vec![0.0; m]; m];
    let mut rhs = vec![0.0; m];
    let trace = pairs.iter().map(|p| p.hessian[0][0] + p.hessian[1][1]).fold(0.0, f64::max).max(1.0);
    let prior = 1e-9 * trace;
    let fixed = fields[0].1;
    for p in &pairs {
        let (i, j) = p.overlap.fields;
        let h = p.hessian;
        let hd = [
            h[0][0] * p.overlap.measured[0] + h[0][1] * p.overlap.measured[1],
            h[1][0] * p.overlap.measured[0] + h[1][1] * p.overlap.measured[1],
        ];
        for u in 0..2 {
            // Unknown index of field k's coordinate u, None for the fixed field.
            let at = |k: usize| (k > 0).then(|| 2 * (k - 1) + u);
            if let Some(r) = at(j) {
                rhs[r] += hd[u];
            }
            if let Some(r) = at(i) {
                rhs[r] -= hd[u];
            }
            for v in 0..2 {
                let at_v = |k: usize| (k > 0).then(|| 2 * (k - 1) + v);
                for (x, y, sign) in [(j, j, 1.0), (i, i, 1.0), (i, j, -1.0), (j, i, -1.0)] {
                    match (at(x), at_v(y)) {
                        (Some(r), Some(c)) => a[r][c] += sign * h[u][v],
                        // The fixed field's terms move to the right-hand side.
                        (Some(r), None) => rhs[r] -= sign * h[u][v] * fixed[v],
                        _ => {}
                    }
                }
            }
        }
    }
    for k in 1..n {
        for u in 0..2 {
            a[2 * (k - 1) + u][2 * (k - 1) + u] += prior;
            rhs[2 * (k - 1) + u] += prior * fields[k].1[u];
        }
        for (u, name) in ["x", "y"].iter().enumerate() {
            let strong = pairs
                .iter()
                .any(|p| (p.overlap.fields.0 == k || p.overlap.fields.1 == k) && p.overlap.strength[u] >= WEAK);
            if !strong {
                warnings.push(format!(
                    "field {}: no edge across its overlaps fixes {name}: its {name} is the stage offset's",
                    k + 1
                ));
            }
        }
    }
    let x = gauss(a, rhs);
    let mut at = vec![fixed];
    at.extend((1..n).map(|k| [x[2 * (k - 1)], x[2 * (k - 1) + 1]]));
    Placement { at, overlaps: pairs.into_iter().map(|p| p.overlap).collect(), warnings }
}

/// `a·x = b` by Gaussian elimination with partial pivoting (`a` positive
/// definite here, so never singular).
fn gauss(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Vec<f64> {
    let m = b.len();
    for col in 0..m {
        let p = (col..m).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs())).unwrap_or(col);
        a.swap(col, p);
        b.swap(col, p);
        let (pivot_rows, rest) = a.split_at_mut(col + 1);
        let pivot = &pivot_rows[col];
        for (k, row) in rest.iter_mut().enumerate() {
            let f = row[col] / pivot[col];
            for (x, &p) in row[col..].iter_mut().zip(&pivot[col..]) {
                *x -= f * p;
            }
            b[col + 1 + k] -= f * b[col];
        }
    }
    let mut x = vec![0.0; m];
    for r in (0..m).rev() {
        let s: f64 = (r + 1..m).map(|c| a[r][c] * x[c]).sum();
        x[r] = (b[r] - s) / a[r][r];
    }
    x
}

/// Mean squared difference of `a` at pixel `p` and `b` at `p − d` over the
/// overlap, every `step`-th pixel; `None` if they share fewer than 16.
fn msd(a: &GrayImage, b: &GrayImage, d: [i64; 2], step: usize) -> Option<f64> {
    let (c0, c1) = (d[0].max(0), (a.width as i64).min(d[0] + b.width as i64));
    let (r0, r1) = (d[1].max(0), (a.height as i64).min(d[1] + b.height as i64));
    let (mut sum, mut count) = (0.0, 0usize);
    for r in (r0..r1).step_by(step) {
        for c in (c0..c1).step_by(step) {
            let e = f64::from(a.at(c as usize, r as usize)) - f64::from(b.at((c - d[0]) as usize, (r - d[1]) as usize));
            sum += e * e;
            count += 1;
        }
    }
    (count >= 16).then(|| sum / count as f64)
}

/// The shift `d` (b's position less a's) that best overlays `b` on `a`,
/// searched from `stage`, with the overlap's Gauss–Newton matrix.
fn register(a: &GrayImage, b: &GrayImage, stage: [f64; 2], search: usize) -> Option<([f64; 2], [[f64; 2]; 2])> {
    let base = [stage[0].round() as i64, stage[1].round() as i64];
    let s = search as i64;
    let area = (a.width * a.height) as f64;
    let step = ((area / 40_000.0).sqrt() as usize).max(1);
    let mut best: Option<(f64, [i64; 2])> = None;
    for dy in -s..=s {
        for dx in -s..=s {
            let d = [base[0] + dx, base[1] + dy];
            if let Some(e) = msd(a, b, d, step) {
                if best.is_none_or(|(b, _)| e < b) {
                    best = Some((e, d));
                }
            }
        }
    }
    let (_, d) = best?;
    let mut d = [d[0] as f64, d[1] as f64];
    let mut h = [[0.0; 2]; 2];
    for _ in 0..30 {
        let (mut g, mut hh) = ([0.0; 2], [[0.0; 2]; 2]);
        for r in 1..a.height - 1 {
            for c in 1..a.width - 1 {
                let (x, y) = (c as f64 - d[0], r as f64 - d[1]);
                let (Some(v), Some(xp), Some(xm), Some(yp), Some(ym)) = (
                    b.sample(x, y),
                    b.sample(x + 0.5, y),
                    b.sample(x - 0.5, y),
                    b.sample(x, y + 0.5),
                    b.sample(x, y - 0.5),
                ) else {
                    continue;
                };
                let j = [xp - xm, yp - ym];
                if j[0].hypot(j[1]) < FLAT {
                    continue;
                }
                let res = f64::from(a.at(c, r)) - v;
                for u in 0..2 {
                    g[u] += j[u] * res;
                    for w in 0..2 {
                        hh[u][w] += j[u] * j[w];
                    }
                }
            }
        }
        h = hh;
        let det = hh[0][0] * hh[1][1] - hh[0][1] * hh[1][0];
        if det <= 1e-12 * (hh[0][0] + hh[1][1]).powi(2) || det == 0.0 {
            break;
        }
        let step = [-(hh[1][1] * g[0] - hh[0][1] * g[1]) / det, -(hh[0][0] * g[1] - hh[1][0] * g[0]) / det];
        // Gauss–Newton on a picture: never more than a pixel at a time.
        let len = step[0].hypot(step[1]);
        let k = if len > 1.0 { 1.0 / len } else { 1.0 };
        d = [d[0] + k * step[0], d[1] + k * step[1]];
        if len < 1e-4 {
            break;
        }
    }
    Some((d, h))
}

/// The fields joined into one picture on whole pixels of the common frame:
/// each pixel the darkest of the fields that cover it (bilinear at their
/// positions), `NaN` where none does. Returns the picture and where its
/// pixel `(0, 0)` lies.
pub fn composite(fields: &[&GrayImage], at: &[[f64; 2]]) -> (GrayImage, [f64; 2]) {
    let lo = |u: usize| at.iter().map(|p| p[u]).fold(f64::INFINITY, f64::min).floor();
    let hi = |u: usize, size: &dyn Fn(&GrayImage) -> usize| {
        fields.iter().zip(at).map(|(f, p)| p[u] + (size(f) - 1) as f64).fold(f64::NEG_INFINITY, f64::max).ceil()
    };
    let origin = [lo(0), lo(1)];
    let width = (hi(0, &|f| f.width) - origin[0]) as usize + 1;
    let height = (hi(1, &|f| f.height) - origin[1]) as usize + 1;
    let mut out = GrayImage::filled(width, height, f32::NAN);
    for (f, p) in fields.iter().zip(at) {
        let (dx, dy) = (origin[0] - p[0], origin[1] - p[1]);
        for r in 0..height {
            for c in 0..width {
                if let Some(v) = f.sample(c as f64 + dx, r as f64 + dy) {
                    let o = &mut out.pixels[r * width + c];
                    if o.is_nan() || (v as f32) < *o {
                        *o = v as f32;
                    }
                }
            }
        }
    }
    (out, origin)
}
