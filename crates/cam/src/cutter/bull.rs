//! Bull-nose end mill: a flat centre of radius `R − r` and a torus corner
//! of radius `r`.

use super::Profile;

/// `bull:D,R`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bull {
    radius: f64,
    /// Corner radius (0 to `D/2`).
    pub corner: f64,
}

impl Bull {
    /// A bull-nose end mill of diameter `d` and corner radius `corner`
    /// (`0 ≤ corner ≤ d/2`).
    pub fn new(d: f64, corner: f64) -> Bull {
        Bull { radius: d / 2.0, corner }
    }

    /// Radius of the flat centre, `R − r`.
    fn flat(&self) -> f64 {
        self.radius - self.corner
    }
}

impl Profile for Bull {
    fn radius(&self) -> f64 {
        self.radius
    }

    fn height(&self, r: f64) -> f64 {
        let x = r - self.flat();
        if x <= 0.0 {
            return 0.0;
        }
        let c = self.corner;
        x * x / (c + ((c - x) * (c + x)).max(0.0).sqrt())
    }

    fn body_radius(&self, z: f64) -> f64 {
        // The flat centre at z = 0, then the corner circle:
        // (r − (R − c))² = z (2c − z).
        let c = self.corner;
        if z < 0.0 {
            0.0
        } else if z >= c {
            self.radius
        } else {
            self.flat() + (z * (2.0 * c - z)).sqrt()
        }
    }

    fn slope(&self, r: f64) -> f64 {
        let x = r - self.flat();
        if x <= 0.0 {
            return 0.0;
        }
        let rest = ((self.corner - x) * (self.corner + x)).max(0.0).sqrt();
        if rest == 0.0 {
            f64::INFINITY
        } else {
            x / rest
        }
    }

    fn facet_radius(&self, gradient: f64) -> f64 {
        if gradient <= 0.0 {
            return 0.0;
        }
        self.flat() + self.corner * gradient / (1.0 + gradient * gradient).sqrt()
    }
}
