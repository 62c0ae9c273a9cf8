//! A measured tool: the radius of its swept envelope about the spindle axis
//! along the tool axis (`kezuri tool profile`, its profile
//! CSV `z_mm,radius_mm`).
//!
//! `z` runs up the tool axis from the nominal tip (the tool-length
//! reference): a worn tip starts above 0. Between samples the profile is the
//! straight line between them (the surface of revolution of a polyline);
//! below the first sample the tool is absent; above the last the profile is
//! not known.

use crate::error::{Error, ErrorKind};

/// Points of a measured profile, `z` strictly increasing (mm).
#[derive(Clone, Debug, PartialEq)]
pub struct ToolProfile {
    z: Vec<f64>,
    radius: Vec<f64>,
}

/// Where a plane touches the tool: see [`ToolProfile::support`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Support {
    /// `min over the profile of z·cos φ − r·sin φ` (mm).
    pub value: f64,
    /// The sample that gives it.
    pub index: usize,
}

impl ToolProfile {
    /// The profile through `(z[i], radius[i])`: at least two samples, `z`
    /// strictly increasing, every number finite, radii ≥ 0.
    pub fn new(z: Vec<f64>, radius: Vec<f64>) -> Result<ToolProfile, Error> {
        let fail = |sample, message: String| Err(Error { sample, ..Error::new(ErrorKind::Profile, message) });
        if z.len() != radius.len() {
            return fail(None, format!("{} heights but {} radii", z.len(), radius.len()));
        }
        if z.len() < 2 {
            return fail(None, format!("{} sample(s): a profile needs at least two", z.len()));
        }
        for i in 0..z.len() {
            if !z[i].is_finite() || !radius[i].is_finite() {
                return fail(Some(i), format!("not a number: z {} radius {}", z[i], radius[i]));
            }
            if radius[i] < 0.0 {
                return fail(Some(i), format!("negative radius {}", radius[i]));
            }
            if i > 0 && z[i] <= z[i - 1] {
                return fail(Some(i), format!("z {} is not above the sample before ({})", z[i], z[i - 1]));
            }
        }
        Ok(ToolProfile { z, radius })
    }

    /// Heights of the samples, mm up from the nominal tip.
    pub fn z(&self) -> &[f64] {
        &self.z
    }

    /// Radii of the samples, mm.
    pub fn radius(&self) -> &[f64] {
        &self.radius
    }

    /// The lowest point of the tool (> 0 where the tip has worn back).
    pub fn tip(&self) -> f64 {
        self.z[0]
    }

    /// The highest measured height.
    pub fn top(&self) -> f64 {
        self.z[self.z.len() - 1]
    }

    /// The largest radius measured.
    pub fn max_radius(&self) -> f64 {
        self.radius.iter().copied().fold(0.0, f64::max)
    }

    /// The radius at height `z`, straight between samples; `None` outside
    /// the measured span.
    pub fn radius_at(&self, z: f64) -> Option<f64> {
        if !(self.tip()..=self.top()).contains(&z) {
            return None;
        }
        let i = self.z.partition_point(|&v| v <= z).clamp(1, self.z.len() - 1);
        let (z0, z1) = (self.z[i - 1], self.z[i]);
        let t = (z - z0) / (z1 - z0);
        Some(self.radius[i - 1] + t * (self.radius[i] - self.radius[i - 1]))
    }

    /// Where a plane whose normal makes the angle φ with the tool axis
    /// touches the tool: the minimum over the tool's surface of its height
    /// along the normal `(sin φ outward, cos φ up)` is
    /// `min over samples of z·cos φ − r·sin φ` (a linear function on a
    /// polyline is least at a vertex), with `sin φ ≥ 0`.
    pub fn support(&self, cos: f64, sin: f64) -> Support {
        let mut best = Support { value: f64::INFINITY, index: 0 };
        for (i, (&z, &r)) in self.z.iter().zip(&self.radius).enumerate() {
            let v = z * cos - r * sin;
            if v < best.value {
                best = Support { value: v, index: i };
            }
        }
        best
    }

    /// The tool's lower surface seen from below, as `(radius, height)`
    /// corners, both non-decreasing: the lowest height at which the tool
    /// reaches each radius (where the radius shrinks again higher up, that
    /// part is hidden from below). Straight between corners, as the
    /// profile is.
    pub fn lower_surface(&self) -> Vec<(f64, f64)> {
        let (z, r) = (&self.z, &self.radius);
        let mut out = vec![(r[0], z[0])];
        let mut reach = r[0];
        for i in 1..z.len() {
            let (r0, r1) = (r[i - 1], r[i]);
            if r1 <= reach {
                continue;
            }
            // Where this segment passes the widest radius so far: its start
            // when it starts there (not where a hidden stretch began).
            let from = if r0 >= reach { z[i - 1] } else { z[i - 1] + (reach - r0) / (r1 - r0) * (z[i] - z[i - 1]) };
            if out[out.len() - 1] != (reach, from) {
                out.push((reach, from));
            }
            out.push((r1, z[i]));
            reach = r1;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_what_is_not_a_profile() {
        assert!(ToolProfile::new(vec![0.0], vec![0.0]).is_err());
        assert!(ToolProfile::new(vec![0.0, 0.0], vec![0.0, 1.0]).unwrap_err().sample == Some(1));
        assert!(ToolProfile::new(vec![0.0, 1.0], vec![0.0, -1.0]).is_err());
        assert!(ToolProfile::new(vec![0.0, f64::NAN], vec![0.0, 1.0]).is_err());
        assert!(ToolProfile::new(vec![0.0, 1.0], vec![0.0]).is_err());
    }

    #[test]
    fn radius_between_samples_and_support_at_a_vertex() {
        let p = ToolProfile::new(vec![0.1, 0.2, 0.6], vec![0.0, 0.3, 0.5]).unwrap();
        assert!((p.radius_at(0.15).unwrap() - 0.15).abs() < 1e-15);
        assert_eq!(p.radius_at(0.05), None);
        assert_eq!(p.radius_at(0.7), None);
        // Normal straight up: the lowest point.
        assert_eq!(p.support(1.0, 0.0), Support { value: 0.1, index: 0 });
        // Normal sideways: the widest point.
        assert_eq!(p.support(0.0, 1.0), Support { value: -0.5, index: 2 });
    }

    #[test]
    fn lower_surface_hides_a_waist() {
        let p = ToolProfile::new(vec![0.0, 1.0, 2.0, 3.0], vec![0.0, 1.0, 0.5, 2.0]).unwrap();
        // From 1.0 the radius shrinks to 0.5 and comes back to 1.0 at z 2⅓.
        let s = p.lower_surface();
        assert_eq!(s.len(), 4);
        assert_eq!(s[1], (1.0, 1.0));
        assert!((s[2].0 - 1.0).abs() < 1e-12 && (s[2].1 - 7.0 / 3.0).abs() < 1e-12);
        assert_eq!(s[3], (2.0, 3.0));
        // A stretch that starts exactly at the widest radius so far, after a
        // narrower part: the step up in height is kept.
        let p = ToolProfile::new(vec![0.0, 0.5, 0.8, 1.0, 1.5], vec![0.0, 1.0, 0.7, 1.0, 1.4]).unwrap();
        assert_eq!(p.lower_surface(), vec![(0.0, 0.0), (1.0, 0.5), (1.0, 1.0), (1.4, 1.5)]);
    }
}
