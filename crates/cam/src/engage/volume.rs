//! The removed cross-section in the YZ plane and the chip's volume from it:
//! at `(y, z)` the chip's length along X is `min(S_z, 2√(w² − y²))`, the
//! part of this tooth's chord that the tooth behind (`S_z` back) did not
//! cover.

use super::quad::Integrand;
use super::set::{label, Set};
use super::Chip;

/// The cross-section, integrated over height.
pub(super) struct Slab<'a> {
    pub chip: &'a Chip,
}

impl Slab<'_> {
    /// The y-intervals of the removed cross-section at height `z`, and the
    /// body's radius there.
    #[inline]
    pub fn line(&self, z: f64) -> (Set, f64) {
        let c = self.chip;
        let w = c.cutter.body_radius(z);
        let mut set = Set::interval(-w, w, label::BODY_LO, label::BODY_HI);
        if set.is_empty() {
            return (set, w);
        }
        let w2 = c.cutter.body_radius(z - c.z2);
        if w2 > 0.0 {
            set.remove(c.y2 - w2, c.y2 + w2, label::PREV_LO, label::PREV_HI);
        }
        let need = z - c.stock;
        if c.slope > 0.0 {
            set.keep_above(need / c.slope, label::PLANE);
        } else if need > 0.0 {
            set.clear();
        }
        (set, w)
    }

    /// Where the chord is the feed: `|y| ≤ y_c`, `y_c = √(w² − S_z²/4)`.
    #[inline]
    fn chord_limit(&self, w: f64) -> Option<f64> {
        let h = 0.5 * self.chip.feed_per_tooth;
        (w > h).then(|| ((w - h) * (w + h)).sqrt())
    }
}

/// `∫₀^y 2√(w² − t²) dt`.
#[inline]
fn circle(w: f64, y: f64) -> f64 {
    let y = y.clamp(-w, w);
    y * ((w - y) * (w + y)).sqrt() + w * w * (y / w).clamp(-1.0, 1.0).asin()
}

impl Integrand<3> for Slab<'_> {
    fn signature(&self, z: f64) -> u64 {
        let (set, w) = self.line(z);
        let base = set.signature();
        if base == 0 {
            return 0;
        }
        // Where each end stands against ±y_c.
        let mut regions = 0u64;
        if let Some(yc) = self.chord_limit(w) {
            regions = 1;
            for (lo, hi) in set.iter() {
                for y in [lo, hi] {
                    regions = (regions << 2)
                        | if y < -yc {
                            1
                        } else if y > yc {
                            2
                        } else {
                            3
                        };
                }
            }
        }
        base ^ (regions << 24)
    }

    /// `[∫ min(S_z, chord) dy, ∫ dy, ∫ y dy]` at `z`.
    fn values(&self, z: f64) -> [f64; 3] {
        let (set, w) = self.line(z);
        let s = self.chip.feed_per_tooth;
        let yc = self.chord_limit(w);
        let (mut v, mut a, mut m) = (0.0, 0.0, 0.0);
        for (lo, hi) in set.iter() {
            a += hi - lo;
            m += 0.5 * (hi - lo) * (hi + lo);
            match yc {
                None => v += circle(w, hi) - circle(w, lo),
                Some(yc) => {
                    if lo < -yc {
                        v += circle(w, hi.min(-yc)) - circle(w, lo);
                    }
                    let (l, h) = (lo.max(-yc), hi.min(yc));
                    if h > l {
                        v += s * (h - l);
                    }
                    if hi > yc {
                        v += circle(w, hi) - circle(w, lo.max(yc));
                    }
                }
            }
        }
        [v, a, m]
    }
}
