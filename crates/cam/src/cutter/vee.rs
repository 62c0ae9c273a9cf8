//! V-bit: a cone of the given included angle up to the cutter's diameter.

use super::Profile;

/// `v:D,ANGLE`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vee {
    radius: f64,
    /// Included angle of the cone, degrees (0 to 180).
    pub angle_deg: f64,
    /// Rise per unit radius, cot(angle/2).
    rise: f64,
}

impl Vee {
    /// A V-bit of diameter `d` and included angle `angle_deg`.
    pub fn new(d: f64, angle_deg: f64) -> Vee {
        Vee { radius: d / 2.0, angle_deg, rise: 1.0 / (angle_deg.to_radians() / 2.0).tan() }
    }
}

impl Profile for Vee {
    fn radius(&self) -> f64 {
        self.radius
    }

    fn height(&self, r: f64) -> f64 {
        r * self.rise
    }

    fn body_radius(&self, z: f64) -> f64 {
        // r = z tan(angle / 2) up to the rim.
        if z <= 0.0 {
            0.0
        } else {
            (z / self.rise).min(self.radius)
        }
    }

    fn slope(&self, _r: f64) -> f64 {
        self.rise
    }

    fn facet_radius(&self, gradient: f64) -> f64 {
        // A plane steeper than the cone touches the rim, a flatter one the tip.
        if gradient > self.rise {
            self.radius
        } else {
            0.0
        }
    }

    fn edge_argmax(&self, d: f64, _s: f64, m: f64, lo: f64, hi: f64) -> f64 {
        // m·x − rise·√(x² + d²): x/ρ = m/rise inside the cone, else an end.
        let q = m / self.rise;
        if q >= 1.0 {
            hi
        } else if q <= -1.0 {
            lo
        } else {
            d * q / ((1.0 - q) * (1.0 + q)).sqrt()
        }
    }
}
