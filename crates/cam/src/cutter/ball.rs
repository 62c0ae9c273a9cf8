//! Ball end mill: a hemisphere of the cutter's radius.

use super::Profile;

/// `ball:D`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ball {
    radius: f64,
}

impl Ball {
    /// A ball end mill of diameter `d` (> 0).
    pub fn new(d: f64) -> Ball {
        Ball { radius: d / 2.0 }
    }
}

impl Profile for Ball {
    fn radius(&self) -> f64 {
        self.radius
    }

    fn height(&self, r: f64) -> f64 {
        let rr = self.radius;
        // R − √(R² − r²), written to keep its digits near the tip.
        let r2 = r * r;
        r2 / (rr + ((rr - r) * (rr + r)).max(0.0).sqrt())
    }

    fn height_sq(&self, r2: f64) -> f64 {
        let rr = self.radius;
        r2 / (rr + (rr * rr - r2).max(0.0).sqrt())
    }

    fn reach(&self, z: f64) -> f64 {
        // r² = z (2R − z), widened by a hair against rounding.
        if z <= 0.0 {
            0.0
        } else if z >= self.radius {
            self.radius
        } else {
            ((z * (2.0 * self.radius - z)).sqrt() * (1.0 + 1e-12)).min(self.radius)
        }
    }

    fn body_radius(&self, z: f64) -> f64 {
        // r² = z (2R − z).
        if z <= 0.0 {
            0.0
        } else if z >= self.radius {
            self.radius
        } else {
            (z * (2.0 * self.radius - z)).sqrt()
        }
    }

    fn slope(&self, r: f64) -> f64 {
        let rest = ((self.radius - r) * (self.radius + r)).max(0.0).sqrt();
        if rest == 0.0 {
            f64::INFINITY
        } else {
            r / rest
        }
    }

    fn facet_radius(&self, gradient: f64) -> f64 {
        // The normal of the sphere at r makes the plane's angle θ:
        // r = R sin θ with tan θ = gradient.
        self.radius * gradient / (1.0 + gradient * gradient).sqrt()
    }

    fn edge_argmax(&self, _d: f64, s: f64, m: f64, _lo: f64, _hi: f64) -> f64 {
        // m·x + √(s² − x²): x = m·s / √(1 + m²).
        m * s / (1.0 + m * m).sqrt()
    }
}
