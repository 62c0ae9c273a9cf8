//! A measured tool in the simulation: the lower surface of a
//! [`ToolProfile`], swept exactly.
//!
//! # The tool
//! The profile is a solid of revolution: at height `z` (up from the nominal
//! tip) it fills the disc of radius `r(z)`, straight between samples. Seen
//! from below (all a 3-axis Z-map sees) it is the height function
//! `h(ρ) = min { z : r(z) ≥ ρ }` for `0 ≤ ρ ≤ R`, `R` the largest radius:
//! non-decreasing, piecewise linear between *corners*, with a jump where a
//! waist (a band worn thinner than the tool below it) hides the profile
//! above it, and flat at the first sample's height out to the first
//! sample's radius (a worn, flattened tip starts above 0 and cuts less
//! deep). Below the first sample there is no tool. Above the last sample
//! the tool is not known; it is taken as a cylinder of radius `R` (the
//! widest measured radius), which is hidden from below by the measured part,
//! so it changes no envelope — a shank wider than the widest measured
//! radius would not be seen.
//!
//! # The envelope
//! Exact at each cell centre, the least over the linear pieces of `h`
//! (each convex along the move, with a closed-form stationary point), with
//! a lookup for level moves and plunges and, for sloped moves, a bound from
//! the lower convex hull of `h` that leaves only the pieces that can win:
//! see `sim/measured/envelope.rs`.

use std::fmt;

use kezuri_geom::ToolProfile;

mod envelope;

pub use envelope::{measured_at, measured_rows};

/// Buckets of the height lookup per piece of the lower surface.
const BUCKETS_PER_PIECE: usize = 8;

/// One linear piece of the lower surface: `ρ` from `r0` to `r1`, height
/// from `z0` to `z1`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Piece {
    r0: f64,
    r1: f64,
    z0: f64,
    z1: f64,
    /// `1 / (r1 − r0)`, 0 for the zero-width first piece.
    inv_w: f64,
    /// `(z1 − z0) / (r1 − r0)`, 0 for the zero-width first piece.
    slope: f64,
    /// Height of the lower convex hull at `r0` and at `r1`.
    hull0: f64,
    hull1: f64,
}

impl Piece {
    /// Height at `rho`, clamped into the piece.
    #[inline(always)]
    fn at(&self, rho: f64) -> f64 {
        let t = ((rho - self.r0) * self.inv_w).clamp(0.0, 1.0);
        self.z0 + (self.z1 - self.z0) * t
    }
}

/// A measured tool ready for the simulation: its lower surface as linear
/// pieces, a lookup of the height by radius, and the lower convex hull.
#[derive(Clone, Debug, PartialEq)]
pub struct MeasuredTool {
    corners: Vec<(f64, f64)>,
    samples: usize,
    pieces: Vec<Piece>,
    /// `pieces[k].r1`, packed for the lookup's search.
    ends: Vec<f64>,
    /// `bucket[j]`: the first piece whose end `r1` has
    /// `⌊r1 · inv_step⌋ ≥ j`, else the last (computed with the lookup's
    /// arithmetic): the piece holding a `ρ` of bucket `j` is from
    /// `bucket[j]` to `bucket[j + 1]`.
    bucket: Vec<u32>,
    inv_step: f64,
    /// Lower convex hull of `h`: vertices `(hull_r, hull_z)`, edge slopes.
    hull_r: Vec<f64>,
    hull_z: Vec<f64>,
    hull_c: Vec<f64>,
    /// The least slope of pieces `k` and beyond (non-decreasing in `k`).
    flattest: Vec<f64>,
    radius: f64,
}

/// The lower convex hull of the points (sorted by `ρ`, `z` non-decreasing
/// where `ρ` ties): its vertices.
fn lower_hull(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut hull: Vec<(f64, f64)> = Vec::new();
    for &p in points {
        if let Some(&last) = hull.last() {
            if p.0 <= last.0 {
                // Same radius, not lower: hidden.
                continue;
            }
        }
        while hull.len() >= 2 {
            let (a, b) = (hull[hull.len() - 2], hull[hull.len() - 1]);
            let cross = (b.0 - a.0) * (p.1 - a.1) - (b.1 - a.1) * (p.0 - a.0);
            if cross <= 0.0 {
                hull.pop();
            } else {
                break;
            }
        }
        hull.push(p);
    }
    hull
}

impl MeasuredTool {
    /// The tool `profile` describes (see the module docs for what is
    /// assumed where it was not measured).
    pub fn new(profile: &ToolProfile) -> MeasuredTool {
        // The corners `(ρ, z)` of `h(ρ) = min { z : r(z) ≥ ρ }`, both
        // non-decreasing; equal radii in a row are a jump (the lower counts).
        let corners = profile.lower_surface();
        let radius = corners[corners.len() - 1].0;
        let (r_first, z_first) = corners[0];
        // The flat bottom out to the first sample's radius (zero width
        // when the tip is a point), then every corner-to-corner piece that
        // is not a jump.
        let mut pieces = vec![Piece {
            r0: 0.0,
            r1: r_first,
            z0: z_first,
            z1: z_first,
            inv_w: if r_first > 0.0 { 1.0 / r_first } else { 0.0 },
            slope: 0.0,
            hull0: 0.0,
            hull1: 0.0,
        }];
        for pair in corners.windows(2) {
            let ((r0, z0), (r1, z1)) = (pair[0], pair[1]);
            if r1 > r0 {
                let inv_w = 1.0 / (r1 - r0);
                pieces.push(Piece { r0, r1, z0, z1, inv_w, slope: (z1 - z0) * inv_w, hull0: 0.0, hull1: 0.0 });
            }
        }
        let mut points = vec![(0.0, z_first)];
        points.extend_from_slice(&corners);
        let hull = lower_hull(&points);
        let hull_r: Vec<f64> = hull.iter().map(|p| p.0).collect();
        let hull_z: Vec<f64> = hull.iter().map(|p| p.1).collect();
        let hull_c: Vec<f64> = hull.windows(2).map(|e| (e[1].1 - e[0].1) / (e[1].0 - e[0].0)).collect();
        let nb = (BUCKETS_PER_PIECE * pieces.len()).max(1);
        let inv_step = if radius > 0.0 { nb as f64 / radius } else { 0.0 };
        let mut bucket = Vec::with_capacity(nb + 1);
        let mut k = 0;
        for j in 0..=nb {
            while k + 1 < pieces.len() && ((pieces[k].r1 * inv_step) as usize) < j {
                k += 1;
            }
            bucket.push(k as u32);
        }
        let ends = pieces.iter().map(|p| p.r1).collect();
        let mut flattest: Vec<f64> = pieces.iter().map(|p| p.slope).collect();
        for k in (0..flattest.len().saturating_sub(1)).rev() {
            flattest[k] = flattest[k].min(flattest[k + 1]);
        }
        let mut tool = MeasuredTool {
            corners,
            samples: profile.z().len(),
            pieces,
            ends,
            bucket,
            inv_step,
            hull_r,
            hull_z,
            hull_c,
            flattest,
            radius,
        };
        for k in 0..tool.pieces.len() {
            let (a, b) = (tool.hull_at(tool.pieces[k].r0), tool.hull_at(tool.pieces[k].r1));
            tool.pieces[k].hull0 = a;
            tool.pieces[k].hull1 = b;
        }
        tool
    }

    /// The radius the tool reaches (the widest measured), mm.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Height of the tool's lowest point above the nominal tip, mm (> 0
    /// where the tip has worn back).
    pub fn tip(&self) -> f64 {
        self.corners[0].1
    }

    /// Number of samples of the profile it was made from.
    pub fn samples(&self) -> usize {
        self.samples
    }

    /// The lower surface's corners `(ρ, height)`: both non-decreasing,
    /// straight between them; two corners at one radius are a jump.
    pub fn corners(&self) -> &[(f64, f64)] {
        &self.corners
    }

    /// The height of the tool's lower surface at distance `rho` from its
    /// axis (the lowest point it reaches there); `None` beyond its radius.
    pub fn height(&self, rho: f64) -> Option<f64> {
        (rho.abs() <= self.radius).then(|| self.lookup(rho.abs()))
    }

    /// How far behind the start of a segment descending at slope `gamma`
    /// (Δz / XY length, > 0) a cell must be for the envelope's minimum over
    /// the segment to be at its start (and likewise ahead of the end of a
    /// climbing one); at most the radius.
    ///
    /// With the cell `u₀` behind the start and `w` across, moving the tool
    /// on by `u − u₀` lowers the tip by `γ·(u − u₀)` and moves the cell out
    /// from `ρ₀` to `ρ`, with `ρ − ρ₀ = (u² − u₀²)/(ρ + ρ₀) ≥ (u − u₀)·u₀/R`;
    /// `h` rises over that by at least `b·(ρ − ρ₀)`, `b` the least slope of
    /// the pieces beyond `ρ₀ ≥ u₀` (jumps only add). So the start is lowest
    /// once `b(u₀)·u₀ ≥ γ·R`.
    pub fn monotone_beyond(&self, gamma: f64) -> f64 {
        let need = gamma * self.radius;
        // The first piece where b·u₀ reaches γ·R: b·r1 grows with the piece.
        let (mut k, mut hi) = (0, self.pieces.len());
        while k < hi {
            let mid = (k + hi) / 2;
            if self.flattest[mid] * self.pieces[mid].r1 < need {
                k = mid + 1;
            } else {
                hi = mid;
            }
        }
        if k == self.pieces.len() || !need.is_finite() {
            return self.radius;
        }
        let u = self.pieces[k].r0.max(need / self.flattest[k]);
        // A hair beyond, for the rounding of the bound.
        (u * (1.0 + 1e-9) + 1e-12).min(self.radius)
    }

    /// The piece holding `rho` (the first whose end is at or beyond it;
    /// the last beyond the radius): its bucket, then a bisection among
    /// the pieces that end in the bucket (none or one mostly; many where
    /// samples crowd, as near the rim of a profile sampled evenly in z).
    #[inline(always)]
    fn piece_of(&self, rho: f64) -> usize {
        let j = ((rho * self.inv_step) as usize).min(self.bucket.len() - 2);
        let (first, mut hi) = (self.bucket[j] as usize, self.bucket[j + 1] as usize);
        // One step without a branch: all a bucket holding at most one end
        // needs.
        let mut lo = (first + usize::from(self.ends[first] < rho)).min(hi);
        if hi - first <= 1 {
            return lo;
        }
        while lo < hi {
            let mid = (lo + hi) / 2;
            if self.ends[mid] < rho {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        lo
    }

    /// `h(rho)` for `0 ≤ rho ≤ R` (clamped into the last piece beyond).
    #[inline(always)]
    fn lookup(&self, rho: f64) -> f64 {
        self.pieces[self.piece_of(rho)].at(rho)
    }

    /// Height of the lower convex hull at `rho`.
    fn hull_at(&self, rho: f64) -> f64 {
        let m = self.hull_r.len();
        if m == 1 {
            return self.hull_z[0];
        }
        let e = self.hull_r.partition_point(|&r| r <= rho).clamp(1, m - 1) - 1;
        let t = ((rho - self.hull_r[e]) / (self.hull_r[e + 1] - self.hull_r[e])).clamp(0.0, 1.0);
        self.hull_z[e] + (self.hull_z[e + 1] - self.hull_z[e]) * t
    }
}

impl fmt::Display for MeasuredTool {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "measured tool (Ø{}, tip at {}, {} samples, {} corners below)",
            2.0 * self.radius,
            self.tip(),
            self.samples,
            self.corners.len()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tool(z: &[f64], r: &[f64]) -> MeasuredTool {
        MeasuredTool::new(&ToolProfile::new(z.to_vec(), r.to_vec()).unwrap())
    }

    #[test]
    fn a_stretch_at_the_widest_radius_after_a_hidden_one_starts_where_it_is() {
        // r: 0 → 1, back to 0.7, up to exactly 1 again, then out to 1.4:
        // the last stretch starts at z 1.0, not at the first corner (1, 0.5).
        let t = tool(&[0.0, 0.5, 0.8, 1.0, 1.5], &[0.0, 1.0, 0.7, 1.0, 1.4]);
        assert_eq!(t.corners(), &[(0.0, 0.0), (1.0, 0.5), (1.0, 1.0), (1.4, 1.5)]);
        assert_eq!(t.height(1.0), Some(0.5));
        assert!((t.height(1.2).unwrap() - 1.25).abs() < 1e-12);
        assert_eq!(t.height(1.5), None);
    }

    #[test]
    fn a_worn_flat_tip_and_the_lookup_at_every_corner() {
        let t = tool(&[0.1, 0.3, 0.6, 2.0], &[0.2, 0.5, 0.6, 0.6]);
        assert_eq!(t.tip(), 0.1);
        assert_eq!(t.radius(), 0.6);
        assert_eq!(t.height(0.0), Some(0.1));
        assert_eq!(t.height(0.2), Some(0.1));
        for &(r, z) in t.corners() {
            assert_eq!(t.height(r), Some(z), "at {r}");
        }
        assert!((t.height(0.35).unwrap() - 0.2).abs() < 1e-12);
    }

    #[test]
    fn the_hull_is_below_every_corner() {
        let t = tool(&[0.0, 0.2, 0.5, 0.9, 1.0, 1.6], &[0.0, 0.6, 0.7, 0.65, 0.9, 1.2]);
        for &(r, z) in t.corners() {
            assert!(t.hull_at(r) <= z + 1e-15, "{r}: {} > {z}", t.hull_at(r));
        }
        assert_eq!(t.hull_at(0.0), 0.0);
    }
}
