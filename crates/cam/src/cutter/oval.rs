//! The egg-type oval end mill of the oval end mill paper: a half-ellipsoid tip with radial
//! semi-axis `a = D/2` and axial semi-axis `b = RL`, on a cylinder of
//! diameter `D`. `b > a` is the paper's egg; `b < a` an oblate "spoon";
//! `b = a` a ball.

use super::Profile;

/// `oval:D,RL`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Oval {
    radius: f64,
    /// Axial semi-axis `RL` of the tip.
    pub axial: f64,
}

impl Oval {
    /// An oval end mill of diameter `d` with a tip of axial semi-axis
    /// `axial` (both > 0).
    pub fn new(d: f64, axial: f64) -> Oval {
        Oval { radius: d / 2.0, axial }
    }
}

impl Profile for Oval {
    fn radius(&self) -> f64 {
        self.radius
    }

    fn height(&self, r: f64) -> f64 {
        // b (1 − √(1 − (r/a)²)), written to keep its digits near the tip.
        let s = r / self.radius;
        self.axial * s * s / (1.0 + ((1.0 - s) * (1.0 + s)).max(0.0).sqrt())
    }

    fn body_radius(&self, z: f64) -> f64 {
        // r² = a² t (2 − t), t = z / b: the ellipse of eq. (1) from its tip.
        if z <= 0.0 {
            0.0
        } else if z >= self.axial {
            self.radius
        } else {
            let t = z / self.axial;
            self.radius * (t * (2.0 - t)).sqrt()
        }
    }

    fn slope(&self, r: f64) -> f64 {
        let s = r / self.radius;
        let rest = ((1.0 - s) * (1.0 + s)).max(0.0).sqrt();
        if rest == 0.0 {
            f64::INFINITY
        } else {
            self.axial / self.radius * s / rest
        }
    }

    fn facet_radius(&self, gradient: f64) -> f64 {
        // slope(r) = gradient: (b/a)·s/√(1 − s²) = g, s = g / √((b/a)² + g²).
        let k = self.axial / self.radius;
        self.radius * gradient / (k * k + gradient * gradient).sqrt()
    }

    fn edge_argmax(&self, _d: f64, s: f64, m: f64, _lo: f64, _hi: f64) -> f64 {
        // m·x + (b/a)·√(s² − x²): the ball's case with m scaled by a/b.
        let k = m * self.radius / self.axial;
        k * s / (1.0 + k * k).sqrt()
    }
}
