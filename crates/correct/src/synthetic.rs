//! Pictures of a turning tool drawn from a known shape: the tool
//! microscope's view for tests and the demo, so every step from pixels to
//! the corrected program can be checked against the truth.
//!
//! The tool's cutting edges have radius `r(z)` about the tool's own axis;
//! its cross-section is that of a two-flute cutter seen from the side: at
//! turn angle θ the silhouette's half-width is `r(z)·max(|cos θ|, web)`
//! (the edges face the camera at θ = 0 and π). The tool's axis is `runout`
//! off the spindle's, in the direction θ, so the silhouette's centre is
//! `runout·cos θ` off the spindle axis and the swept envelope's radius is
//! exactly `r(z) + runout` (reached at θ = 0). Each pixel is the backlight
//! less the tool's share of its area (four sub-rows, each row of the
//! silhouette an exact interval), plus Gaussian noise.

use kezuri_geom::{SplitMix64, ToolProfile};

use crate::tool_image::GrayImage;

/// The tool and the microscope's view of it.
#[derive(Clone, Debug)]
pub struct View {
    /// The cutting edges' radius about the tool's axis (z up from the
    /// nominal tip, mm); above the last sample, its radius.
    pub edges: ToolProfile,
    /// Eccentricity of the tool in the spindle, mm.
    pub runout_mm: f64,
    /// Half-width of the silhouette between the flutes, as a share of
    /// the radius.
    pub web: f64,
    /// Side of a pixel, mm.
    pub pixel_mm: f64,
    /// Where the spindle axis lies in the common frame, pixels (x).
    pub axis_x: f64,
    /// Where the nominal tip lies in the common frame, pixels (y, down).
    pub tip_y: f64,
    /// Gray level of the tool and of the backlight (0–1).
    pub levels: (f32, f32),
    /// Standard deviation of the noise, gray levels.
    pub noise: f64,
}

impl View {
    /// The frame at turn angle `theta` (radians) of a field `width ×
    /// height` whose pixel `(0, 0)` lies at `at` in the common frame.
    pub fn frame(&self, theta: f64, width: usize, height: usize, at: [f64; 2], rng: &mut SplitMix64) -> GrayImage {
        let (dark, bright) = (f64::from(self.levels.0), f64::from(self.levels.1));
        let shape = theta.cos().abs().max(self.web);
        let centre = self.axis_x + self.runout_mm / self.pixel_mm * theta.cos() - at[0];
        let mut img = GrayImage::filled(width, height, 0.0);
        const SUB: usize = 4;
        for r in 0..height {
            let spans: Vec<(f64, f64)> = (0..SUB)
                .filter_map(|k| {
                    let y = at[1] + r as f64 - 0.5 + (k as f64 + 0.5) / SUB as f64;
                    let z = (self.tip_y - y) * self.pixel_mm;
                    let half = self.radius(z)? * shape / self.pixel_mm;
                    Some((centre - half, centre + half))
                })
                .collect();
            for c in 0..width {
                let (a, b) = (c as f64 - 0.5, c as f64 + 0.5);
                let cover: f64 = spans.iter().map(|&(l, rr)| (b.min(rr) - a.max(l)).max(0.0)).sum::<f64>() / SUB as f64;
                let v = bright - (bright - dark) * cover + self.noise * rng.normal();
                img.pixels[r * width + c] = v.clamp(0.0, 1.0) as f32;
            }
        }
        img
    }

    /// The edges' radius at `z`: none below the tip, the last radius above
    /// the measured span.
    fn radius(&self, z: f64) -> Option<f64> {
        if z < self.edges.tip() {
            None
        } else if z > self.edges.top() {
            Some(self.edges.radius()[self.edges.radius().len() - 1])
        } else {
            self.edges.radius_at(z)
        }
    }

    /// `count` frames evenly spread around the turn (starting at angle 0).
    pub fn frames(
        &self,
        count: usize,
        width: usize,
        height: usize,
        at: [f64; 2],
        rng: &mut SplitMix64,
    ) -> Vec<GrayImage> {
        (0..count)
            .map(|k| self.frame(std::f64::consts::TAU * k as f64 / count as f64, width, height, at, rng))
            .collect()
    }
}
