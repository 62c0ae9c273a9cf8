//! Closed forms of the cusp, each on the domain where its picture of the
//! crossing holds; [`closed_form_cusp`] answers `None` elsewhere.

use std::fmt;

use crate::Cutter;

/// Which closed form gave a cusp.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClosedForm {
    /// `R − √(R² − Pf²/4)`: two circles, at any angle.
    Ball,
    /// The oval end mill paper (Iwabe, Kumaki, Hori): two ellipses, equations (1)–(6)
    /// with the sign of (6) corrected.
    Iwabe,
    /// `Pf·sin α·cos α`: the staircase of a flat end mill (0 on a level
    /// plane).
    Flat,
    /// A bull-nose: its corner circles, or its flat bottom on a level plane.
    Bull,
    /// Two V-bits: their flanks, or the staircase of their uphill flank.
    Vee,
}

impl fmt::Display for ClosedForm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ClosedForm::Ball => "ball, R - sqrt(R^2 - Pf^2/4)",
            ClosedForm::Iwabe => "oval, Iwabe's equations (1)-(6) with the sign of (6) corrected",
            ClosedForm::Flat => "flat, Pf sin(a) cos(a)",
            ClosedForm::Bull => "bull-nose corner circles",
            ClosedForm::Vee => "V-bit flanks",
        })
    }
}

/// `R − √(R² − q²)` without losing its digits when `q ≪ R`.
fn sagitta(r: f64, q: f64) -> f64 {
    q * q / (r + ((r - q) * (r + q)).max(0.0).sqrt())
}

/// The cusp of two circles of radius `r` whose centres are `pf` apart
/// along a plane at `angle` (`sin`, `cos`), with the side conditions that
/// the crossing lies on the lower arc of the lower circle (`up_to_equator`)
/// and, when `right_of_upper`, on the right of the upper circle.
fn circles(r: f64, pf: f64, sin: f64, cos: f64, right_of_upper: bool) -> Option<f64> {
    if pf > 2.0 * r {
        return None;
    }
    let s = ((r - pf / 2.0) * (r + pf / 2.0)).max(0.0).sqrt();
    // Crossing relative to the lower circle's centre: (pf/2)(cos, sin) + s(sin, −cos).
    if 0.5 * pf * sin - s * cos > 0.0 {
        return None;
    }
    // Relative to the upper circle's centre: −(pf/2)(cos, sin) + s(sin, −cos).
    if right_of_upper && s * sin - 0.5 * pf * cos < 0.0 {
        return None;
    }
    Some(sagitta(r, pf / 2.0))
}

/// The cusp by a closed form, where one holds for this cutter, angle
/// (radians) and pick feed (mm in the plane); the cusp square to the plane.
/// Inputs are assumed valid (see [`super::cusp`]).
pub fn closed_form_cusp(cutter: &Cutter, angle: f64, pf: f64) -> Option<(f64, ClosedForm)> {
    let (sin, cos) = angle.sin_cos();
    let r = cutter.radius();
    if !(pf.is_finite() && pf >= 0.0 && pf * cos <= 2.0 * r) {
        return None;
    }
    match cutter {
        Cutter::Ball(_) => circles(r, pf, sin, cos, false).map(|c| (c, ClosedForm::Ball)),
        Cutter::Oval(o) => {
            if pf == 0.0 {
                return Some((0.0, ClosedForm::Iwabe));
            }
            let i = iwabe(r, o.axial, angle, pf * cos, pf * sin)?;
            i.on_lower_half.then_some((i.cusp, ClosedForm::Iwabe))
        }
        Cutter::Flat(_) => Some((pf * sin * cos, ClosedForm::Flat)),
        Cutter::Bull(b) => {
            let rc = b.corner;
            if angle == 0.0 {
                // The flat bottoms leave nothing until the corners meet.
                let e = (pf - 2.0 * (r - rc)).max(0.0);
                return (e <= 2.0 * rc).then(|| (if e == 0.0 { 0.0 } else { sagitta(rc, e / 2.0) }, ClosedForm::Bull));
            }
            if rc == 0.0 {
                return Some((pf * sin * cos, ClosedForm::Bull));
            }
            circles(rc, pf, sin, cos, true).map(|c| (c, ClosedForm::Bull))
        }
        Cutter::Vee(v) | Cutter::Drill(v) => {
            let k = 1.0 / (v.angle_deg.to_radians() / 2.0).tan();
            let m = angle.tan();
            let dy = pf * cos;
            if m <= k {
                // Tip contact: the downhill flank of the upper pass meets the
                // uphill flank of the lower one at y = (k + m)·dy / 2k.
                ((k + m) * dy / (2.0 * k) <= r).then(|| ((k - m) * (k + m) * dy / (2.0 * k) * cos, ClosedForm::Vee))
            } else {
                // Rim contact: the lower pass's wall, the upper's uphill flank.
                (dy <= r).then_some(((m - k) * dy * cos, ClosedForm::Vee))
            }
        }
    }
}

/// The oval end mill paper's equations (1)–(6) as printed, for ellipse I centred at the
/// origin (`y²/Rs² + z²/Rl² = 1`) and ellipse II centred at `(y2, z2)`,
/// on the plane (3) `z = m·y − √(Rs²m² + Rl²)`, `m = tan α`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Iwabe {
    /// Equation (4).
    pub y_t: f64,
    /// Equation (5): the lower half of ellipse I at `y_t`.
    pub z_t: f64,
    /// Equation (6) as printed: `(m·y_t − z_t − √(Rs²m² + Rl²)) / √(m² + 1)`,
    /// the cusp with the wrong sign (the point is above the plane).
    pub printed_r_th: f64,
    /// Equation (6) with the sign corrected: the cusp, ≥ 0.
    pub cusp: f64,
    /// Whether `(y_t, z_t)` is where the ellipses cross: (4) picks the
    /// lower crossing only for `y2 > 0` (ellipse II up the slope), and (5)
    /// takes the lower half of ellipse I, right only while that crossing
    /// lies below the ellipse's centre (the egg's equator).
    pub on_lower_half: bool,
}

/// Evaluates equations (4)–(6) of the oval end mill paper; `None` where the ellipses do
/// not cross (the root in (4) would be imaginary) or coincide.
pub fn iwabe(rs: f64, rl: f64, alpha: f64, y2: f64, z2: f64) -> Option<Iwabe> {
    let m = alpha.tan();
    let q = rl * rl * y2 * y2 + rs * rs * z2 * z2;
    let root = 4.0 * rs * rs * rl * rl / q - 1.0;
    if q <= 0.0 || !root.is_finite() || root < 0.0 {
        return None;
    }
    let y_t = y2 / 2.0 + z2 * rs / (2.0 * rl) * root.sqrt();
    let z_t = -rl / rs * ((rs - y_t) * (rs + y_t)).max(0.0).sqrt();
    let c = (rs * rs * m * m + rl * rl).sqrt();
    let norm = (m * m + 1.0).sqrt();
    let printed_r_th = (m * y_t - z_t - c) / norm;
    // In coordinates scaled to unit circles the crossing (4) picks is
    // (u2/2 + v2·w, v2/2 − u2·w), w = √(1/d² − 1/4); (5) is right where
    // its second coordinate is ≤ 0.
    let (u2, v2) = (y2 / rs, z2 / rl);
    let w = (root / 4.0).sqrt();
    let v_t = v2 / 2.0 - u2 * w;
    Some(Iwabe { y_t, z_t, printed_r_th, cusp: (-printed_r_th).max(0.0), on_lower_half: y2 > 0.0 && v_t <= 0.0 })
}
