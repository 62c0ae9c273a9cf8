//! Flat end mill: the profile is the bottom face, height 0 out to the rim.

use super::Profile;

/// `flat:D`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flat {
    radius: f64,
}

impl Flat {
    /// A flat end mill of diameter `d` (> 0).
    pub fn new(d: f64) -> Flat {
        Flat { radius: d / 2.0 }
    }
}

impl Profile for Flat {
    fn radius(&self) -> f64 {
        self.radius
    }

    fn height(&self, _r: f64) -> f64 {
        0.0
    }

    fn body_radius(&self, z: f64) -> f64 {
        // The bottom face at z = 0, the shank above.
        if z < 0.0 {
            0.0
        } else {
            self.radius
        }
    }

    fn slope(&self, _r: f64) -> f64 {
        0.0
    }

    fn facet_radius(&self, gradient: f64) -> f64 {
        // A tilted plane touches the rim; a level one the whole face.
        if gradient > 0.0 {
            self.radius
        } else {
            0.0
        }
    }

    fn edge_argmax(&self, _d: f64, _s: f64, m: f64, lo: f64, hi: f64) -> f64 {
        // m·x on a level bottom: the end the edge rises toward.
        if m > 0.0 {
            hi
        } else if m < 0.0 {
            lo
        } else {
            0.0
        }
    }
}
