//! Where a cutter cannot reach a relief: valleys narrower than its end.
//!
//! The surface a cutter can leave at best — every position allowed, not
//! only the rows of a path — is the upper envelope's lower bound
//! `S(p) = min_q CL(q) + h(|p − q|)` over the cutter locations `q` within
//! its radius (`h` the cutter's height above its tip at a distance). What
//! stays above the relief there, `S(p) − z(p)`, no stepover removes; it
//! is measured normal to the relief (times the cosine of its slope), as a
//! machinist measures material left on a wall. It is sampled on a grid of
//! cutter locations `step` apart: with fewer positions the envelope can
//! only be higher, by the scallop the grid leaves (`step²/8R` for a ball on
//! the flat, more on a steep wall where the contact points lie further
//! apart), so the figures are upper bounds within that.

use kezuri_geom::Heightfield;

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

/// Samples a relief every `step` mm with the cutter locations `cl` (the
/// cutter's tip height at a point, `None` outside what is carved) and
/// finds where the cutter leaves more than `threshold` above it; `None`
/// where it reaches everywhere within that.
pub fn unreached(
    field: &Heightfield,
    cutter: &Cutter,
    step: f64,
    threshold: f64,
    cl: impl Fn(f64, f64) -> Option<f64>,
) -> Option<Unreached> {
    let [x0, y0, x1, y1] = field.xy_box();
    let (nx, ny) = (((x1 - x0) / step).floor() as usize + 1, ((y1 - y0) / step).floor() as usize + 1);
    let at = |i: usize, j: usize| (x0 + i as f64 * step, y0 + j as f64 * step);
    let locations: Vec<Option<f64>> = (0..nx * ny)
        .map(|k| {
            let (x, y) = at(k % nx, k / nx);
            cl(x, y)
        })
        .collect();
    let reach = (cutter.radius() / step).floor() as isize;
    // The cutter's height at each grid offset within its radius.
    let offsets: Vec<(isize, isize, f64)> = (-reach..=reach)
        .flat_map(|dj| (-reach..=reach).map(move |di| (di, dj)))
        .filter_map(|(di, dj)| {
            let r = step * (di as f64).hypot(dj as f64);
            (r <= cutter.radius()).then(|| (di, dj, cutter.height(r)))
        })
        .collect();
    let (mut worst, mut over, mut sampled): (Option<Unreached>, usize, usize) = (None, 0, 0);
    for j in 0..ny {
        for i in 0..nx {
            if locations[j * nx + i].is_none() {
                continue;
            }
            let (x, y) = at(i, j);
            let Some(z) = field.z_at(x, y) else { continue };
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
            let (gx, gy) =
                (slope(field.z_at(x - d, y), field.z_at(x + d, y)), slope(field.z_at(x, y - d), field.z_at(x, y + d)));
            let left = (best - z) / (1.0 + gx * gx + gy * gy).sqrt();
            sampled += 1;
            if left > threshold {
                over += 1;
                if worst.is_none_or(|w| left > w.left) {
                    worst = Some(Unreached { left, at: [x, y], share: 0.0 });
                }
            }
        }
    }
    worst.map(|w| Unreached { share: over as f64 / sampled.max(1) as f64, ..w })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dropcut::drop_cutter;

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
            unreached(&field, &c, 0.05, 0.05, |x, y| drop_cutter(&c, &field, x, y))
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
        let u = unreached(&v, &c, 0.05, 0.05, |x, y| drop_cutter(&c, &v, x, y)).unwrap();
        assert!((u.left - 0.5 * (2f64.sqrt() - 1.0)).abs() < 1e-3, "{u:?}");
        assert!((u.at[0] - 5.0).abs() < 0.06, "{u:?}");
    }
}
