//! The edge of the reference tool in a line-sensor profile (the thermal and
//! wear report).
//!
//! A 2D laser line sensor sees the corner of a square reference tool as a
//! profile of points `(x, z)` across it. The profile is split into its two
//! sides, a straight line is fitted to each, and their intersection is the
//! edge: the one point of the tool the thermal measurements follow.
//!
//! - **Split.** Where it is not given, the split is the one that leaves the
//!   least squared distance of the points from the two lines fitted to the
//!   points before and after it (every split is tried, each in constant
//!   time from running sums, the points taken in order along the profile).
//! - **Lines.** Orthogonal (total) least squares: the line through the
//!   centroid along the principal direction of the points' scatter, so a
//!   steep side is fitted as well as a flat one.
//! - **Outliers.** Each side is refitted on the points within three robust
//!   standard deviations (1.4826 × the median absolute residual) of its
//!   line until the inliers stop changing; then every point goes to the
//!   line it lies nearer to and both are fitted again, so a split a few
//!   points off the corner is put right.
//!
//! A profile whose two lines are parallel (within 1°), or that is too
//! short to hold two sides, has no corner: an error, never a made-up edge.

use crate::{Error, ErrorKind};

/// A straight line: a point on it and its unit direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    /// A point on the line (the centroid of its inliers), `[x, z]` mm.
    pub point: [f64; 2],
    /// Unit direction, pointing along increasing profile order.
    pub direction: [f64; 2],
}

impl Line {
    /// Signed distance of `p` from the line (positive to the left of the
    /// direction).
    pub fn distance(&self, p: [f64; 2]) -> f64 {
        let (dx, dz) = (p[0] - self.point[0], p[1] - self.point[1]);
        self.direction[0] * dz - self.direction[1] * dx
    }

    /// The angle of its direction from +x, degrees.
    pub fn angle_deg(&self) -> f64 {
        self.direction[1].atan2(self.direction[0]).to_degrees()
    }
}

/// The edge found in a profile.
#[derive(Clone, Debug, PartialEq)]
pub struct Edge {
    /// The intersection of the two sides, `[x, z]` mm.
    pub edge: [f64; 2],
    /// The angle between the two sides at the edge, degrees (90 for a
    /// square tool seen square on).
    pub angle_deg: f64,
    /// The two sides, in profile order.
    pub sides: [Line; 2],
    /// Root mean square distance of the inliers from their lines, mm.
    pub rms_residual_mm: f64,
    /// Points of each side used in its line.
    pub inliers: [usize; 2],
    /// Points left out as outliers.
    pub outliers: usize,
    /// Index of the first point of the second side (in profile order).
    pub split: usize,
}

impl Edge {
    /// The report of `kezuri thermal edge` on the profile `name` of
    /// `points` points: the edge, the angle between the sides, each side
    /// and the residual, a line each.
    pub fn report(&self, name: &str, points: usize) -> String {
        let mut out = format!("{name}: {points} points\n");
        out += &format!("  edge       x {:.6} mm, z {:.6} mm\n", self.edge[0], self.edge[1]);
        out += &format!("  angle      {:.4}° between the sides\n", self.angle_deg);
        for (k, s) in self.sides.iter().enumerate() {
            out += &format!("  side {}     {} points, direction {:.4}°\n", k + 1, self.inliers[k], s.angle_deg());
        }
        out += &format!("  residual   {:.4} µm rms; {} outliers left out\n", self.rms_residual_mm * 1e3, self.outliers);
        out
    }
}

/// Fewest points of a profile.
pub const MIN_POINTS: usize = 6;

/// The edge of the profile `points` (in order along the profile), split at
/// `split_x` (the first point of the second side is the first with `x` at
/// least this) or where the fit is best.
pub fn find_edge(points: &[[f64; 2]], split_x: Option<f64>) -> Result<Edge, Error> {
    if points.len() < MIN_POINTS {
        return Err(Error::new(
            ErrorKind::TooFewPoints,
            format!("a profile needs at least {MIN_POINTS} points for two sides, got {}", points.len()),
        ));
    }
    if let Some(k) = points.iter().position(|p| !(p[0].is_finite() && p[1].is_finite())) {
        return Err(Error::new(ErrorKind::NotFinite, format!("point {} is not a finite number", k + 1)));
    }
    let split = match split_x {
        Some(x) => {
            let k = points.iter().position(|p| p[0] >= x).unwrap_or(points.len());
            if k < 3 || points.len() - k < 3 {
                return Err(Error::new(
                    ErrorKind::BadSplit,
                    format!("the split at x = {x} leaves a side with fewer than 3 points"),
                ));
            }
            k
        }
        None => best_split(points),
    };
    // Robust lines on each side of the split, then every point to its
    // nearer line and both fitted again (twice, so the split settles).
    let mut sides = [robust(&points[..split]), robust(&points[split..])];
    for _ in 0..2 {
        let nearer = |p: &[f64; 2]| sides[0].0.distance(*p).abs() <= sides[1].0.distance(*p).abs();
        let members: [Vec<[f64; 2]>; 2] = [
            points.iter().copied().filter(|p| nearer(p)).collect(),
            points.iter().copied().filter(|p| !nearer(p)).collect(),
        ];
        if members.iter().any(|m| m.len() < 3) {
            break;
        }
        sides = [robust(&members[0]), robust(&members[1])];
    }
    let [(a, ia, ra), (b, ib, rb)] = sides;
    let cross = a.direction[0] * b.direction[1] - a.direction[1] * b.direction[0];
    let angle = cross.abs().asin().to_degrees();
    if angle < 1.0 {
        return Err(Error::new(
            ErrorKind::NoCorner,
            format!(
                "the profile has no corner: its two best sides differ by {angle:.2}° (a straight edge, or the sensor \
                 missed the corner)"
            ),
        ));
    }
    // a.point + s·a.dir = b.point + t·b.dir.
    let (dx, dz) = (b.point[0] - a.point[0], b.point[1] - a.point[1]);
    let s = (dx * b.direction[1] - dz * b.direction[0]) / cross;
    let edge = [a.point[0] + s * a.direction[0], a.point[1] + s * a.direction[1]];
    let dot = a.direction[0] * b.direction[0] + a.direction[1] * b.direction[1];
    // The angle at the edge between the side coming in and the side going out.
    let angle_deg = (-dot).clamp(-1.0, 1.0).acos().to_degrees();
    let rms = ((ra + rb) / (ia + ib) as f64).sqrt();
    let split = points.iter().position(|p| b.distance(*p).abs() < a.distance(*p).abs()).unwrap_or(split);
    Ok(Edge {
        edge,
        angle_deg,
        sides: [a, b],
        rms_residual_mm: rms,
        inliers: [ia, ib],
        outliers: points.len() - ia - ib,
        split,
    })
}

/// Running sums of points, for fitting a line to any run of them.
#[derive(Clone, Copy, Default)]
struct Sums {
    n: f64,
    x: f64,
    z: f64,
    xx: f64,
    zz: f64,
    xz: f64,
}

impl Sums {
    fn add(self, p: [f64; 2], sign: f64) -> Sums {
        Sums {
            n: self.n + sign,
            x: self.x + sign * p[0],
            z: self.z + sign * p[1],
            xx: self.xx + sign * p[0] * p[0],
            zz: self.zz + sign * p[1] * p[1],
            xz: self.xz + sign * p[0] * p[1],
        }
    }

    /// The sum of squared distances from the best line: the smaller
    /// eigenvalue of the scatter matrix.
    fn residual(&self) -> f64 {
        let (cx, cz) = (self.x / self.n, self.z / self.n);
        let sxx = self.xx - self.n * cx * cx;
        let szz = self.zz - self.n * cz * cz;
        let sxz = self.xz - self.n * cx * cz;
        let (mean, diff) = (0.5 * (sxx + szz), (0.25 * (sxx - szz) * (sxx - szz) + sxz * sxz).sqrt());
        (mean - diff).max(0.0)
    }
}

/// The split (index of the first point of the second side) whose two lines
/// leave the least squared distance. Coordinates are taken about the
/// profile's centroid so the running sums keep their digits.
fn best_split(points: &[[f64; 2]]) -> usize {
    let n = points.len() as f64;
    let c = points.iter().fold([0.0, 0.0], |c, p| [c[0] + p[0] / n, c[1] + p[1] / n]);
    let local: Vec<[f64; 2]> = points.iter().map(|p| [p[0] - c[0], p[1] - c[1]]).collect();
    let total = local.iter().fold(Sums::default(), |s, &p| s.add(p, 1.0));
    let mut left = Sums::default();
    let mut best = (f64::INFINITY, 3);
    for (k, &p) in local.iter().enumerate() {
        if k >= 3 && local.len() - k >= 3 {
            let right = Sums {
                n: total.n - left.n,
                x: total.x - left.x,
                z: total.z - left.z,
                xx: total.xx - left.xx,
                zz: total.zz - left.zz,
                xz: total.xz - left.xz,
            };
            let cost = left.residual() + right.residual();
            if cost < best.0 {
                best = (cost, k);
            }
        }
        left = left.add(p, 1.0);
    }
    best.1
}

/// The total least squares line through `points`, with its direction along
/// the points' order.
fn fit(points: &[[f64; 2]]) -> Line {
    let n = points.len() as f64;
    let c = points.iter().fold([0.0, 0.0], |c, p| [c[0] + p[0] / n, c[1] + p[1] / n]);
    let (mut sxx, mut szz, mut sxz) = (0.0, 0.0, 0.0);
    for p in points {
        let (dx, dz) = (p[0] - c[0], p[1] - c[1]);
        sxx += dx * dx;
        szz += dz * dz;
        sxz += dx * dz;
    }
    // The principal direction: angle ½·atan2(2 sxz, sxx − szz).
    let theta = 0.5 * (2.0 * sxz).atan2(sxx - szz);
    let mut d = [theta.cos(), theta.sin()];
    let (first, last) = (points[0], points[points.len() - 1]);
    if (last[0] - first[0]) * d[0] + (last[1] - first[1]) * d[1] < 0.0 {
        d = [-d[0], -d[1]];
    }
    Line { point: c, direction: d }
}

/// A line fitted to `points` without its outliers: the line, the inliers'
/// count and their sum of squared distances.
fn robust(points: &[[f64; 2]]) -> (Line, usize, f64) {
    let mut line = fit(points);
    let mut kept: Vec<[f64; 2]> = points.to_vec();
    for _ in 0..20 {
        let mut r: Vec<f64> = points.iter().map(|p| line.distance(*p).abs()).collect();
        r.sort_by(f64::total_cmp);
        let mad = r[r.len() / 2];
        // Three robust standard deviations, and never tighter than rounding.
        let cut = (3.0 * 1.4826 * mad).max(1e-12);
        let next: Vec<[f64; 2]> = points.iter().copied().filter(|p| line.distance(*p).abs() <= cut).collect();
        if next.len() < 3 {
            break;
        }
        let same = next == kept;
        kept = next;
        line = fit(&kept);
        if same {
            break;
        }
    }
    let ss = kept.iter().map(|p| line.distance(*p).powi(2)).sum();
    (line, kept.len(), ss)
}
