//! Scallop theory: the cusp two neighbouring passes leave on an inclined
//! plane, and the pick feed that keeps it within a target (the oval end
//! mill paper's pick-feed control).
//!
//! # The geometry
//! Contour (Z-level) passes run along X on a plane that rises in Y at
//! `angle` α; the next pass is offset by the pick feed `Pf` *in the plane*
//! (the paper's `Pf`): `Pf·cos α` across in plan and `Pf·sin α` in Z. The
//! cutter is a solid of revolution about its vertical axis, swept along X,
//! so its section by a plane `x = const` is its shadow on the YZ plane: at
//! each height `z` a disc of radius `ρ(z)` projects onto `|y| ≤ ρ(z)`, which
//! is exactly the meridian region `{z ≥ height(|y|), |y| ≤ R}`, the profile
//! itself, with vertical shank walls at `|y| = R`. The plane's section is
//! the line `z = y·tan α + c`. So the problem is two-dimensional: two copies
//! of the profile, each touching the line, one shifted along the line by
//! `Pf`. What is left is the lower envelope of the two; the cusp is its
//! highest point above the line, measured square to the plane (what a
//! stylus across the passes reads).
//!
//! In the frame of the lower pass, the vertical gap between its profile and
//! the line is `g(y) = height(|y|) − y·tan α − g₀` (`g₀` makes its minimum,
//! at the contact `y = facet_radius(tan α)`, zero; `+∞` beyond the shank,
//! `|y| > R`). The upper pass's gap is `g(y − Pf·cos α)`: the plane and the
//! shift cancel. `g` is convex, so between the two contacts the first gap
//! rises and the second falls and the cusp is where they cross; where a
//! shank wall comes first (a flat end mill's corner, a V-bit past its flank)
//! the cusp is the other pass's gap at the wall. [`envelope_cusp`] finds the
//! crossing by bisection to the last bit; the cusp square to the plane is
//! the vertical gap times `cos α`.
//!
//! The passes may be cut in either order — step-up (the next pass higher
//! on the slope) or step-down (lower) — and the surface left is the lower
//! envelope of all passes either way: the order changes the chip, not what
//! is left. [`Scallop`] reports both, each computed with the neighbour on
//! its own side.
//!
//! Passes *along* the slope instead (pick feed along the contour) see a
//! different section, the cutter's shadow along an inclined direction on a
//! level line; that is not this module's case (for a ball it is the same).
//!
//! # Closed forms
//! Where one exists, [`closed_form_cusp`] gives the cusp directly: the
//! ball's classic `R − √(R² − Pf²/4)` (the same at every angle), the paper's
//! equations (1)–(6) for the oval (with the sign of (6) corrected, see
//! [`iwabe`]), a flat end mill's staircase `Pf·sin α·cos α`, a bull-nose
//! corner or flat, a V-bit. Each holds on a stated domain; outside it
//! [`cusp`] falls back to the envelope, and tests hold the two together.
//!
//! # Example
//! ```
//! use kezuri_cam::{scallop, Cutter};
//! let egg: Cutter = "oval:16,24".parse().unwrap();
//! // The oval end mill paper: a 10 µm cusp at 60° allows a 1.052 mm pick feed.
//! let s = scallop::pick_feed(&egg, 60f64.to_radians(), 0.010).unwrap();
//! assert!((s.pick_feed - 1.052).abs() < 0.002);
//! // And at 0.8 mm the cusp is about 6 µm.
//! let c = scallop::cusp(&egg, 60f64.to_radians(), 0.8).unwrap();
//! assert!((c.cusp - 0.0058).abs() < 0.0002);
//! ```

mod closed;

use std::fmt;

pub use closed::{closed_form_cusp, iwabe, ClosedForm, Iwabe};

use crate::error::{Error, ErrorKind};
use crate::Cutter;

/// The smallest positive target cusp [`pick_feed`] takes (1 pm): below it
/// the rounding of the envelope (about `1e-13` mm) would be the answer.
pub const MIN_TARGET: f64 = 1e-9;

/// Which neighbour: the next pass higher or lower on the slope.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    /// The next pass is higher on the slope (pick feed up the plane).
    Up,
    /// The next pass is lower on the slope (pick feed down the plane).
    Down,
}

/// How [`Scallop::cusp`] was computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// A closed form valid at this angle and pick feed.
    Closed(ClosedForm),
    /// The numerical envelope of the two profiles.
    Envelope,
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Method::Closed(c) => write!(f, "closed form: {c}"),
            Method::Envelope => f.write_str("envelope of the two profiles"),
        }
    }
}

/// The cusp between two neighbouring passes. Lengths mm, angle rad.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scallop {
    /// Inclination of the plane, radians in `[0, π/2)`.
    pub angle: f64,
    /// Pick feed in the inclined plane (the oval end mill paper's `Pf`).
    pub pick_feed: f64,
    /// Cusp height square to the plane (closed form where one holds).
    pub cusp: f64,
    /// The envelope's cusp with the next pass up the slope.
    pub step_up_cusp: f64,
    /// The envelope's cusp with the next pass down the slope (the same:
    /// see the module docs).
    pub step_down_cusp: f64,
    /// How `cusp` was computed.
    pub method: Method,
    /// Radius on the cutter where it touches the plane.
    pub contact_radius: f64,
    /// Where the cusp stands: the distance up the plane from the lower
    /// pass's contact point to the foot of the cusp (≥ 0; past `pick_feed`
    /// for a ridge taller than the passes are apart, at a wall or a sharp V).
    pub cusp_offset: f64,
    /// The cusp stands at a shank wall or a sharp corner rather than where
    /// two profiles cross.
    pub at_wall: bool,
    /// From [`pick_feed`]: every overlapping pick feed meets the target, and
    /// this is the widest, where the passes just touch.
    pub width_limited: bool,
}

impl Scallop {
    /// `Pf·cos α`: the stepover in plan, square to the passes.
    pub fn plan_stepover(&self) -> f64 {
        self.pick_feed * self.angle.cos()
    }

    /// `Pf·sin α`: the step in Z between contour passes.
    pub fn z_step(&self) -> f64 {
        self.pick_feed * self.angle.sin()
    }
}

/// `x` to the micrometre, without trailing zeros.
fn mm(x: f64) -> String {
    let s = format!("{x:.6}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

fn check_angle(angle: f64) -> Result<(), Error> {
    if angle.is_finite() && (0.0..std::f64::consts::FRAC_PI_2).contains(&angle) && angle.cos() > 0.0 {
        Ok(())
    } else {
        Err(Error::new(
            ErrorKind::Angle,
            format!("the plane's angle must be from 0 up to (not including) 90 degrees, got {}", angle.to_degrees()),
        ))
    }
}

/// The widest pick feed at which two passes still overlap: `2R / cos α`.
pub fn widest_pick_feed(cutter: &Cutter, angle: f64) -> f64 {
    2.0 * cutter.radius() / angle.cos()
}

fn check_pick_feed(cutter: &Cutter, angle: f64, pick_feed: f64) -> Result<(), Error> {
    if !(pick_feed.is_finite() && pick_feed >= 0.0) {
        return Err(Error::new(ErrorKind::PickFeed, format!("the pick feed must be a number ≥ 0 mm, got {pick_feed}")));
    }
    // A hair of slack so that `widest_pick_feed` itself passes.
    if pick_feed * angle.cos() > 2.0 * cutter.radius() * (1.0 + 1e-12) {
        return Err(Error::new(
            ErrorKind::NoOverlap,
            format!(
                "a pick feed of {pick_feed} mm leaves an uncut strip between the passes: \
                 the widest that overlaps at this angle is {} mm (the diameter / cos angle)",
                mm(widest_pick_feed(cutter, angle))
            ),
        ));
    }
    Ok(())
}

/// The cusp between two passes `pick_feed` apart in a plane inclined at
/// `angle` radians: closed form where one holds, the envelope otherwise.
pub fn cusp(cutter: &Cutter, angle: f64, pick_feed: f64) -> Result<Scallop, Error> {
    check_angle(angle)?;
    check_pick_feed(cutter, angle, pick_feed)?;
    let up = Envelope::new(cutter, angle).between(pick_feed);
    let down = Envelope::new(cutter, angle).between(-pick_feed);
    let (value, method) = match closed_form_cusp(cutter, angle, pick_feed) {
        Some((v, form)) => (v, Method::Closed(form)),
        None => (up.cusp, Method::Envelope),
    };
    Ok(Scallop {
        angle,
        pick_feed,
        cusp: value,
        step_up_cusp: up.cusp,
        step_down_cusp: down.cusp,
        method,
        contact_radius: cutter.facet_radius(angle.tan()),
        cusp_offset: up.offset,
        at_wall: up.at_wall,
        width_limited: false,
    })
}

/// The cusp from the numerical envelope alone, with the next pass on the
/// `step` side (the two agree).
pub fn envelope_cusp(cutter: &Cutter, angle: f64, pick_feed: f64, step: Step) -> Result<f64, Error> {
    check_angle(angle)?;
    check_pick_feed(cutter, angle, pick_feed)?;
    let signed = match step {
        Step::Up => pick_feed,
        Step::Down => -pick_feed,
    };
    Ok(Envelope::new(cutter, angle).between(signed).cusp)
}

/// The largest pick feed in the plane whose cusp is at most `target`
/// (mm), by bisection on the bracket `[0, widest]`: the cusp grows with the
/// pick feed (the gaps are convex), so the set meeting the target is an
/// interval from 0. Where even the widest overlapping pick feed meets it,
/// that one, flagged [`Scallop::width_limited`].
pub fn pick_feed(cutter: &Cutter, angle: f64, target: f64) -> Result<Scallop, Error> {
    check_angle(angle)?;
    if !(target.is_finite() && target >= 0.0) {
        return Err(Error::new(ErrorKind::Target, format!("the target cusp must be a number ≥ 0 mm, got {target}")));
    }
    if target > 0.0 && target < MIN_TARGET {
        return Err(Error::new(
            ErrorKind::TargetBelowResolution,
            format!(
                "a target cusp of {target} mm is below the resolution of the computation ({MIN_TARGET} mm); \
                 no pick feed can be told apart from one that meets it"
            ),
        ));
    }
    let envelope = Envelope::new(cutter, angle);
    let value = |pf: f64| closed_form_cusp(cutter, angle, pf).map_or_else(|| envelope.between(pf).cusp, |c| c.0);
    let widest = widest_pick_feed(cutter, angle);
    if value(widest) <= target {
        let mut s = cusp(cutter, angle, widest)?;
        s.width_limited = true;
        return Ok(s);
    }
    let (mut lo, mut hi) = (0.0, widest);
    for _ in 0..2000 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if value(mid) <= target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    // A target of 0 is met only on a plateau (a flat bottom on a level
    // plane); elsewhere the bisection creeps to where rounding hides the cusp.
    if target < MIN_TARGET && lo < 1e-6 * cutter.radius().max(1.0) {
        return Err(Error::new(
            ErrorKind::Unreachable,
            format!(
                "no pick feed leaves a cusp of {target} mm: with this cutter at this angle every pick feed \
                 leaves some cusp; give a positive target"
            ),
        ));
    }
    cusp(cutter, angle, lo)
}

/// The gap between the lower pass's profile and the plane, in its frame.
struct Envelope<'a> {
    cutter: &'a Cutter,
    /// `tan α`.
    m: f64,
    cos: f64,
    /// The contact, `y` on the profile.
    contact: f64,
    /// `height(contact)`.
    contact_height: f64,
}

/// One crossing of two gaps.
struct Crossing {
    /// Square to the plane.
    cusp: f64,
    /// Foot of the cusp up the plane from the lower contact.
    offset: f64,
    at_wall: bool,
}

impl<'a> Envelope<'a> {
    fn new(cutter: &'a Cutter, angle: f64) -> Envelope<'a> {
        let m = angle.tan();
        let contact = cutter.facet_radius(m);
        Envelope { cutter, m, cos: angle.cos(), contact, contact_height: cutter.height(contact) }
    }

    /// Vertical gap above the plane at `y` (lower pass's frame); `+∞` off
    /// the cutter.
    fn gap(&self, y: f64) -> f64 {
        if y.abs() > self.cutter.radius() {
            return f64::INFINITY;
        }
        ((self.cutter.height(y.abs()) - self.contact_height) - self.m * (y - self.contact)).max(0.0)
    }

    /// The cusp between a pass and its neighbour `signed` mm along the plane
    /// (positive up the slope).
    fn between(&self, signed: f64) -> Crossing {
        let diameter = 2.0 * self.cutter.radius();
        let shift = (signed * self.cos).clamp(-diameter, diameter);
        // Put the lower pass at the origin of y: the previous one when
        // stepping up, the next one when stepping down.
        let (lower, upper) = if shift >= 0.0 { (0.0, shift) } else { (shift, 0.0) };
        let g_lower = |y: f64| self.gap(y - lower);
        let g_upper = |y: f64| self.gap(y - upper);
        // From the lower contact (g_lower = 0) to the upper one (g_upper = 0)
        // g_lower rises and g_upper falls: bisect on which is lower.
        let (mut lo, mut hi) = (lower + self.contact, upper + self.contact);
        for _ in 0..2000 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if g_lower(mid) < g_upper(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        // The envelope's supremum on either side of the crossing; a wall
        // makes one side jump to +∞ and the other side's value the cusp.
        let left = g_lower(lo).min(g_upper(lo));
        let right = g_lower(hi).min(g_upper(hi));
        let vertical = left.max(right);
        let at_wall = g_lower(hi).is_infinite() || g_upper(lo).is_infinite();
        let y = 0.5 * (lo + hi) - (lower + self.contact);
        let sin = self.m * self.cos;
        Crossing { cusp: vertical * self.cos, offset: y / self.cos + vertical * sin, at_wall }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ball_on_a_level_plane_is_the_classic_formula() {
        let ball: Cutter = "ball:10".parse().unwrap();
        let e = Envelope::new(&ball, 0.0).between(2.0);
        let want = 5.0 - (25.0f64 - 1.0).sqrt();
        assert!((e.cusp - want).abs() < 1e-12, "{}", e.cusp);
        assert!((e.offset - 1.0).abs() < 1e-9);
        assert!(!e.at_wall);
    }

    #[test]
    fn a_flat_end_mill_leaves_a_staircase() {
        let flat: Cutter = "flat:10".parse().unwrap();
        let a = 30f64.to_radians();
        let e = Envelope::new(&flat, a).between(2.0);
        assert!((e.cusp - 2.0 * a.sin() * a.cos()).abs() < 1e-12, "{}", e.cusp);
        assert!(e.at_wall);
    }
}
