//! Where a cutter cannot reach a surface: valleys narrower than its end,
//! walls steeper than it can follow (`mill`'s and `relief`'s warning).
//!
//! The surface a cutter can leave at best — every position allowed, not
//! only the rows of a path — is the upper envelope's lower bound
//! `S(p) = min_q CL(q) + h(|p − q|)` over the cutter locations `q` within
//! its radius (`h` the cutter's height above its tip at a distance). What
//! stays above the surface there, `S(p) − z(p)`, no stepover removes; it
//! is measured normal to the surface (times the cosine of its slope), as a
//! machinist measures material left on a wall. It is sampled on a grid of
//! cutter locations `step` apart: with fewer positions the envelope can
//! only be higher, by the scallop the grid leaves (`step²/8R` for a ball on
//! the flat, more on a steep wall where the contact points lie further
//! apart), so the figures are upper bounds within that.

use rayon::prelude::*;

use crate::Cutter;

/// What a cutter leaves of a relief where it cannot reach.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Unreached {
    /// The most material left on the relief, mm (normal to it).
    pub left: f64,
    /// Where (X, Y).
    pub at: [f64; 2],
    /// The share of the sampled relief left more than the threshold.
    pub share: f64,
}

impl Unreached {
    /// What a machinist reads: `{cutter} cannot reach all of {what}: up
    /// to … mm is left on it at X… Y… (… % of its area more than
    /// {threshold} mm): …`.
    pub fn message(&self, cutter: &Cutter, what: &str, threshold: f64) -> String {
        format!(
            "{cutter} cannot reach all of {what}: up to {:.3} mm is left on it at X{:.3} Y{:.3} ({:.1} % of its area \
             more than {threshold:.3} mm): valleys narrower than the cutter; a smaller one reaches them",
            self.left,
            self.at[0],
            self.at[1],
            self.share * 100.0
        )
    }
}

/// Material left that counts as unreached, mm, for a cutter of `radius`
/// checked on a grid `step` apart: five times the path's tolerance `tol`,
/// and not less than 0.05 mm, plus the scallop of the check's own grid on
/// the flat (`step²/8R`).
pub fn threshold(tol: f64, step: f64, radius: f64) -> f64 {
    (5.0 * tol).max(REACH_LEFT) + step * step / (8.0 * radius)
}

/// The least material left that is reported, mm.
const REACH_LEFT: f64 = 0.05;

/// Where the check is made and with what.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Area {
    /// The box `[x0, y0, x1, y1]` of the grid of cutter locations.
    pub bounds: [f64; 4],
    /// Points of the surface closer than this to the box's edge are not
    /// judged (a cutter kept inside the box leaves its edge's slopes: not
    /// a narrow feature).
    pub inset: f64,
    /// Distance between the grid's points, mm.
    pub step: f64,
}

/// Samples a surface (its height `z`, `None` where there is none) on the
/// grid of `area` with the cutter locations `cl` (the cutter's tip height
/// at a point, `None` outside what is cut) and finds where the cutter
/// leaves more than `threshold` above it; `None` where it reaches
/// everywhere within that. A point found over the threshold is tried once
/// more with the cutter placed to touch the surface's tangent plane there.
pub fn unreached(
    area: Area,
    cutter: &Cutter,
    threshold: f64,
    z_at: impl Fn(f64, f64) -> Option<f64> + Sync,
    cl: impl Fn(f64, f64) -> Option<f64> + Sync,
) -> Option<Unreached> {
    let row = |y: f64, xs: &[f64]| xs.iter().map(|&x| cl(x, y)).collect();
    unreached_by_rows(area, cutter, threshold, z_at, &cl, row)
}

/// [`unreached`], the grid's cutter locations asked a row at a time of
/// `cl_row(y, xs)` (the same answers as `cl` at each `(x, y)`: a surface
/// may answer a row's points faster together).
pub fn unreached_by_rows(
    area: Area,
    cutter: &Cutter,
    threshold: f64,
    z_at: impl Fn(f64, f64) -> Option<f64> + Sync,
    cl: &(dyn Fn(f64, f64) -> Option<f64> + Sync),
    cl_row: impl Fn(f64, &[f64]) -> Vec<Option<f64>> + Sync,
) -> Option<Unreached> {
    let Area { bounds: [x0, y0, x1, y1], inset, step } = area;
    let (nx, ny) = (((x1 - x0) / step).floor() as usize + 1, ((y1 - y0) / step).floor() as usize + 1);
    let at = |i: usize, j: usize| (x0 + i as f64 * step, y0 + j as f64 * step);
    // Both cores: the locations row by row, then the rows of points judged.
    let xs: Vec<f64> = (0..nx).map(|i| at(i, 0).0).collect();
    let locations: Vec<Option<f64>> = (0..ny).into_par_iter().flat_map_iter(|j| cl_row(at(0, j).1, &xs)).collect();
    let reach = (cutter.radius() / step).floor() as isize;
    // The cutter's height at each grid offset within its radius.
    let offsets: Vec<(isize, isize, f64)> = (-reach..=reach)
        .flat_map(|dj| (-reach..=reach).map(move |di| (di, dj)))
        .filter_map(|(di, dj)| {
            let r = step * (di as f64).hypot(dj as f64);
            (r <= cutter.radius()).then(|| (di, dj, cutter.height(r)))
        })
        .collect();
    // What each point leaves, `None` for a point not judged.
    let left_at = |i: usize, j: usize| -> Option<f64> {
        locations[j * nx + i]?;
        let (x, y) = at(i, j);
        if inset > 0.0 && (x - x0 < inset || x1 - x < inset || y - y0 < inset || y1 - y < inset) {
            return None;
        }
        let z = z_at(x, y)?;
        let best = offsets
            .iter()
            .filter_map(|&(di, dj, h)| {
                let (qi, qj) = (i as isize + di, j as isize + dj);
                if qi < 0 || qj < 0 || qi >= nx as isize || qj >= ny as isize {
                    return None;
                }
                locations[qj as usize * nx + qi as usize].map(|c| c + h)
            })
            .fold(f64::INFINITY, f64::min);
        // The slope's cosine, from the relief half a step either side.
        let d = step / 2.0;
        let slope = |a: Option<f64>, b: Option<f64>| a.zip(b).map_or(0.0, |(a, b)| (b - a) / (2.0 * d));
        let (gx, gy) = (slope(z_at(x - d, y), z_at(x + d, y)), slope(z_at(x, y - d), z_at(x, y + d)));
        let cos = 1.0 / (1.0 + gx * gx + gy * gy).sqrt();
        let mut left = (best - z) * cos;
        if left > threshold {
            // Before it is called unreached: the cutter placed where it
            // would touch the tangent plane at this very point (its axis
            // downhill of it by the radius a plane of this slope touches),
            // which no grid of locations need hold: a flat end on a wall
            // leaves the grid's steps, not the wall.
            let g = gx.hypot(gy);
            let rho = if g > 0.0 { cutter.facet_radius(g) } else { 0.0 };
            let (ux, uy) = if g > 0.0 { (gx / g, gy / g) } else { (0.0, 0.0) };
            if let Some(c) = cl(x - rho * ux, y - rho * uy) {
                left = left.min((c + cutter.height(rho) - z) * cos);
            }
        }
        Some(left)
    };
    // Each row's worst point (the first of the worst), points over and
    // points judged; then the rows in order, as one pass would find them.
    let rows: Vec<(Option<Unreached>, usize, usize)> = (0..ny)
        .into_par_iter()
        .map(|j| {
            let (mut worst, mut over, mut sampled): (Option<Unreached>, usize, usize) = (None, 0, 0);
            for i in 0..nx {
                let Some(left) = left_at(i, j) else { continue };
                sampled += 1;
                if left > threshold {
                    over += 1;
                    if worst.is_none_or(|w| left > w.left) {
                        worst = Some(Unreached { left, at: [at(i, j).0, at(i, j).1], share: 0.0 });
                    }
                }
            }
            (worst, over, sampled)
        })
        .collect();
    let (mut worst, mut over, mut sampled): (Option<Unreached>, usize, usize) = (None, 0, 0);
    for (row_worst, row_over, row_sampled) in rows {
        over += row_over;
        sampled += row_sampled;
        if let Some(w) = row_worst.filter(|r| worst.is_none_or(|w| r.left > w.left)) {
            worst = Some(w);
        }
    }
    worst.map(|w| Unreached { share: over as f64 / sampled.max(1) as f64, ..w })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dropcut::drop_cutter;
    use kezuri_geom::Heightfield;

    /// A flat relief with a round groove along Y, 2 mm wide and 1 mm deep
    /// (a half cylinder of radius 1): a 1 mm ball reaches its bottom; a
    /// 6 mm ball rests on both edges, its tip 3 − √(9 − 1) = 0.172 mm below
    /// the top, so 1 − 0.172 mm is left. A sharp V no ball reaches: a
    /// 90° one leaves R(√2 − 1).
    #[test]
    fn a_ball_wider_than_a_groove_leaves_its_bottom() {
        let pixel = 0.05;
        let field =
            Heightfield::from_fn(0.0, 0.0, pixel, 201, 101, |x, _| -(1.0 - (x - 5.0).powi(2)).max(0.0).sqrt()).unwrap();
        let find = |spec: &str| {
            let c: Cutter = spec.parse().unwrap();
            let area = Area { bounds: field.xy_box(), inset: 0.0, step: 0.05 };
            unreached(area, &c, 0.05, |x, y| field.z_at(x, y), |x, y| drop_cutter(&c, &field, x, y))
        };
        assert_eq!(find("ball:1"), None);
        let u = find("ball:6").unwrap();
        let want = 1.0 - (3.0 - 8f64.sqrt());
        assert!((u.left - want).abs() < 2e-3, "{u:?}");
        assert!((u.at[0] - 5.0).abs() < 0.06, "{u:?}");
        // The groove is a fifth of the width; what is left is a part of it.
        assert!(u.share > 0.05 && u.share < 0.2, "{u:?}");
        let v = Heightfield::from_fn(0.0, 0.0, pixel, 201, 101, |x, _| -(1.0 - (x - 5.0).abs()).max(0.0)).unwrap();
        let c: Cutter = "ball:1".parse().unwrap();
        let area = Area { bounds: v.xy_box(), inset: 0.0, step: 0.05 };
        let u = unreached(area, &c, 0.05, |x, y| v.z_at(x, y), |x, y| drop_cutter(&c, &v, x, y)).unwrap();
        assert!((u.left - 0.5 * (2f64.sqrt() - 1.0)).abs() < 1e-3, "{u:?}");
        assert!((u.at[0] - 5.0).abs() < 0.06, "{u:?}");
    }
}
