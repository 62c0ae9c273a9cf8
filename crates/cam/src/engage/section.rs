//! One rake segment at height `z`: the ρ-intervals in the chip, and the
//! closed-form integrals over them.

use super::quad::Integrand;
use super::set::{label, Set};
use super::Chip;

/// The rake face at tool angle `theta`, integrated over height.
pub(super) struct Rake<'a> {
    pub chip: &'a Chip,
    pub theta: f64,
}

impl Rake<'_> {
    /// The chip's part of the rake segment at height `z`, and the segment's
    /// direction `(sin ψ, cos ψ)` (ψ clockwise from +Y).
    #[inline]
    pub fn segment(&self, z: f64) -> (Set, f64, f64) {
        let c = self.chip;
        let psi = self.theta + c.twist * (c.reference - z);
        let (s, co) = psi.sin_cos();
        let w = c.cutter.body_radius(z);
        let mut set = Set::interval(0.0, w, label::AXIS, label::BODY_HI);
        if set.is_empty() {
            return (set, s, co);
        }
        // The body one tooth behind, axis at (b, 0): |ρu − (b, 0)|² < w².
        let b = c.behind;
        let uc = s * b;
        let bc = b * co;
        let d = (w - bc) * (w + bc);
        if d > 0.0 {
            let r = d.sqrt();
            set.remove(uc - r, uc + r, label::BEHIND_LO, label::BEHIND_HI);
        }
        // The previous pass: |ρ cos ψ − y₂| < w₂.
        let w2 = c.cutter.body_radius(z - c.z2);
        if w2 > 0.0 {
            if co > 0.0 {
                set.remove((c.y2 - w2) / co, (c.y2 + w2) / co, label::PREV_LO, label::PREV_HI);
            } else if co < 0.0 {
                set.remove((c.y2 + w2) / co, (c.y2 - w2) / co, label::PREV_HI, label::PREV_LO);
            } else if c.y2.abs() < w2 {
                set.clear();
            }
        }
        // Below the stock plane: z ≤ m ρ cos ψ + c_s.
        let t = c.slope * co;
        let need = z - c.stock;
        if t > 0.0 {
            set.keep_above(need / t, label::PLANE);
        } else if t < 0.0 {
            set.keep_below(need / t, label::PLANE);
        } else if need > 0.0 {
            set.clear();
        }
        (set, s, co)
    }
}

impl Integrand<5> for Rake<'_> {
    fn signature(&self, z: f64) -> u64 {
        self.segment(z).0.signature()
    }

    /// `[∫dA, ∫x dA, ∫y dA, ∫z dA, ∫ρ dρ]` along the segment at `z`, with
    /// `dA = √(1 + k²ρ²) dρ` per unit height.
    fn values(&self, z: f64) -> [f64; 5] {
        let (set, s, co) = self.segment(z);
        let k = self.chip.twist;
        let (mut a, mut m1, mut mp) = (0.0, 0.0, 0.0);
        for (lo, hi) in set.iter() {
            let (a1, m_1) = arc_both(k, hi);
            let (a0, m_0) = arc_both(k, lo);
            a += a1 - a0;
            m1 += m_1 - m_0;
            mp += 0.5 * (hi - lo) * (hi + lo);
        }
        [a, m1 * s, m1 * co, z * a, mp]
    }
}

/// `∫₀^ρ √(1 + k²t²) dt = (ρq + asinh(kρ)/k) / 2` and
/// `∫₀^ρ t √(1 + k²t²) dt = (q³ − 1) / (3k²)`, `q = √(1 + k²ρ²)`; the
/// second written as `ρ²(q² + q + 1) / (3(q + 1))` and `asinh x` as
/// `ln(1 + x + x²/(q + 1))` (x ≥ 0) to keep their digits for small `kρ`.
#[inline]
pub(super) fn arc_both(k: f64, rho: f64) -> (f64, f64) {
    if rho == 0.0 {
        return (0.0, 0.0);
    }
    if k == 0.0 {
        return (rho, 0.5 * rho * rho);
    }
    let x = k * rho;
    let q = (1.0 + x * x).sqrt();
    let asinh_over = (x + x * x / (q + 1.0)).ln_1p() / k;
    (0.5 * (rho * q + asinh_over), rho * rho * (q * q + q + 1.0) / (3.0 * (q + 1.0)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_forms_match_their_derivatives() {
        let arc = |k: f64, r: f64| arc_both(k, r).0;
        let arc_moment = |k: f64, r: f64| arc_both(k, r).1;
        for k in [0.0, 1e-9, 0.07, 0.5, 3.0] {
            for rho in [0.1, 1.0, 8.0] {
                let e = 1e-5;
                let d0 = (arc(k, rho + e) - arc(k, rho - e)) / (2.0 * e);
                let d1 = (arc_moment(k, rho + e) - arc_moment(k, rho - e)) / (2.0 * e);
                let q = (1.0 + k * k * rho * rho).sqrt();
                assert!((d0 - q).abs() < 1e-8 * q, "k={k} rho={rho}");
                assert!((d1 - rho * q).abs() < 1e-8 * rho * q, "k={k} rho={rho}");
            }
        }
        // The closed forms against the textbook ones where those are exact.
        for (k, rho) in [(0.5f64, 2.0f64), (3.0, 1.0)] {
            let q: f64 = (1.0 + k * k * rho * rho).sqrt();
            let want0 = 0.5 * (rho * q + (k * rho).asinh() / k);
            let want1 = (q.powi(3) - 1.0) / (3.0 * k * k);
            assert!((arc(k, rho) - want0).abs() < 1e-14 * want0);
            assert!((arc_moment(k, rho) - want1).abs() < 1e-14 * want1);
        }
        assert_eq!(arc_both(0.0, 2.0), (2.0, 2.0));
        assert_eq!(arc_both(0.3, 0.0), (0.0, 0.0));
    }
}
