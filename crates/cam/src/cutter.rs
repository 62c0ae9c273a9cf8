//! Cutter shapes and the tool SPEC notation (`ball:6`, `oval:16,24`, …).
//!
//! A cutter is a surface of revolution about the Z axis with its tip at the
//! origin. [`Profile`] is all a shape provides: its radius `R`, the height of
//! its lower surface above the tip at radial distance `r` (`0 ≤ r ≤ R`),
//! that height's slope, and the radius where a tilted plane touches it.
//! Above the profile the cutter is a cylinder of radius `R`.
//!
//! Every profile is convex and non-decreasing with `height(0) = 0`. The
//! drop-cutter and envelope solvers rely on that: the height of the cutter
//! along any straight line in XY is then convex, so each contact is the one
//! maximum of a concave function.

mod ball;
mod bull;
mod flat;
pub mod named;
mod oval;
mod vee;

use std::fmt;
use std::str::FromStr;

use kezuri_geom::limits;

use crate::error::{Error, ErrorKind};

pub use ball::Ball;
pub use bull::Bull;
pub use flat::Flat;
pub use oval::Oval;
pub use vee::Vee;

/// What a cutter shape provides. Lengths in mm.
pub trait Profile {
    /// Radius `R` of the cylindrical shank (half the diameter).
    fn radius(&self) -> f64;

    /// Height of the cutter's lower surface above the tip at radial
    /// distance `r`, for `0 ≤ r ≤ R`; convex and non-decreasing, 0 at 0.
    fn height(&self, r: f64) -> f64;

    /// [`Profile::height`] at the radius whose square is `r2`; a shape
    /// may skip the square root.
    #[inline]
    fn height_sq(&self, r2: f64) -> f64 {
        self.height(r2.sqrt())
    }

    /// A radius at least the profile's inverse at height `z` above the tip
    /// and at most `R/4096` beyond it (0 below the tip, `R` from the rim
    /// up): how far from the axis a point `z` above the tip can touch.
    /// The default bisects; a shape with a closed form gives it.
    #[inline]
    fn reach(&self, z: f64) -> f64 {
        radius_above(self, z, 12)
    }

    /// The exact inverse of the profile: the radius of the cutter's body at
    /// height `z` above the tip, `max{r ≤ R : height(r) ≤ z}` (0 below the
    /// tip, `R` from the rim up; at `z = 0` the radius of a flat bottom, if
    /// any). Every shape gives it in closed form; unlike [`Profile::reach`]
    /// it is not widened. The default bisects to the last bit.
    fn body_radius(&self, z: f64) -> f64 {
        if z < 0.0 {
            return 0.0;
        }
        let radius = self.radius();
        if z >= self.height(radius) {
            return radius;
        }
        let (mut lo, mut hi) = (0.0, radius);
        while hi - lo > 0.0 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if self.height(mid) <= z {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    }

    /// `d height / d r` at `r` (`0 ≤ r ≤ R`); `f64::INFINITY` where the
    /// profile turns vertical (the rim of a ball or an egg).
    fn slope(&self, r: f64) -> f64;

    /// The radius at which a plane rising by `gradient` (mm per mm, ≥ 0)
    /// touches the cutter: the `r` in `[0, R]` that maximises
    /// `gradient·r − height(r)`. Where several do (a flat bottom on a level
    /// plane), the smallest.
    fn facet_radius(&self, gradient: f64) -> f64;

    /// The `x` in `[lo, hi]` (a part of `[−s, s]`, `s = √(R² − d²)`) that
    /// maximises `m·x − height(√(x² + d²))`: where the cutter touches an
    /// edge of slope `m` whose line passes at distance `d` from the axis.
    /// Shapes whose vertical slice is a conic give a closed form (flat: a
    /// segment; ball: a circle; oval: an ellipse; V-bit: a hyperbola); the
    /// default is [`edge_argmax_numeric`].
    fn edge_argmax(&self, d: f64, s: f64, m: f64, lo: f64, hi: f64) -> f64 {
        let _ = s;
        edge_argmax_numeric(self, d, m, lo, hi)
    }
}

/// [`Profile::edge_argmax`] for any convex profile: the root of the
/// non-decreasing derivative `g(x) = height′(ρ)·x/ρ − m` (ρ = √(x² + d²))
/// bracketed in `[lo, hi]`, by regula falsi with the Illinois modification,
/// falling back to bisection where `g` is infinite (the rim of a ball or a
/// torus) or the bracket shrinks too slowly; stops at a bracket of 1e-12 mm
/// (relative to the size of `x`).
pub fn edge_argmax_numeric<P: Profile + ?Sized>(profile: &P, d: f64, m: f64, lo: f64, hi: f64) -> f64 {
    let radius = profile.radius();
    let g = |x: f64| {
        let rho = (x * x + d * d).sqrt();
        if rho > 0.0 {
            profile.slope(rho.min(radius)) * (x / rho) - m
        } else {
            -m
        }
    };
    let (mut a, mut b) = (lo, hi);
    let (mut ga, mut gb) = (g(a), g(b));
    if ga.is_nan() || ga >= 0.0 {
        return a;
    }
    if gb.is_nan() || gb <= 0.0 {
        return b;
    }
    let mut last_side = 0i8;
    for step in 0..200 {
        let width = b - a;
        if width <= 1e-12 * (1.0 + a.abs().max(b.abs())) {
            break;
        }
        let mid = 0.5 * (a + b);
        let mut x = if ga.is_finite() && gb.is_finite() && step % 4 != 3 { (a * gb - b * ga) / (gb - ga) } else { mid };
        if !(x > a && x < b) {
            x = mid;
        }
        let gx = g(x);
        if gx < 0.0 {
            a = x;
            ga = gx;
            if last_side == -1 {
                gb *= 0.5;
            }
            last_side = -1;
        } else if gx > 0.0 {
            b = x;
            gb = gx;
            if last_side == 1 {
                ga *= 0.5;
            }
            last_side = 1;
        } else {
            return x;
        }
    }
    0.5 * (a + b)
}

/// The upper end of the bracket of `profile`'s inverse at height `z` after
/// at most `halvings` bisections: 0 below the tip, `R` from the rim up.
#[inline]
pub fn radius_above<P: Profile + ?Sized>(profile: &P, z: f64, halvings: usize) -> f64 {
    let radius = profile.radius();
    if z <= 0.0 {
        return 0.0;
    }
    if z >= profile.height(radius) {
        return radius;
    }
    // The profile is non-decreasing.
    let (mut lo, mut hi) = (0.0, radius);
    for _ in 0..halvings {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if profile.height(mid) < z {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// A cutter: one of the shapes of the tool SPEC notation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cutter {
    /// `flat:D`: flat end mill.
    Flat(Flat),
    /// `ball:D`: ball end mill.
    Ball(Ball),
    /// `bull:D,R`: bull-nose (torus) end mill with corner radius `R`.
    Bull(Bull),
    /// `oval:D,RL`: the egg-type oval end mill of the oval end mill paper, a half-ellipsoid
    /// tip with radial semi-axis `D/2` and axial semi-axis `RL`.
    Oval(Oval),
    /// `v:D,ANGLE`: V-bit (cone) with the included angle in degrees.
    Vee(Vee),
    /// `drill:D,ANGLE`: a twist drill, its point's included angle in
    /// degrees (118 for most): the solid of `v:D,ANGLE`, but it cuts along
    /// its axis only, so the simulation flags it fed sideways in material.
    Drill(Vee),
}

/// `$e` with `$s` bound to the cutter's shape, for code generic over
/// [`Profile`].
macro_rules! each_shape {
    ($self:ident, $s:ident => $e:expr) => {
        match $self {
            Cutter::Flat($s) => $e,
            Cutter::Ball($s) => $e,
            Cutter::Bull($s) => $e,
            Cutter::Oval($s) => $e,
            Cutter::Vee($s) => $e,
            Cutter::Drill($s) => $e,
        }
    };
}
pub(crate) use each_shape;

impl Cutter {
    /// A drill (`drill:D,ANGLE`): it cuts along its axis only.
    pub fn is_drill(&self) -> bool {
        matches!(self, Cutter::Drill(_))
    }

    /// The cutter's profile.
    pub fn profile(&self) -> &dyn Profile {
        each_shape!(self, s => s)
    }

    /// Radius `R` of the shank.
    #[inline]
    pub fn radius(&self) -> f64 {
        each_shape!(self, s => s.radius())
    }

    /// Height above the tip at radial distance `r`; beyond `R` the shank is
    /// vertical, so this is the height of the rim, `height(R)`.
    #[inline]
    pub fn height(&self, r: f64) -> f64 {
        let r = r.clamp(0.0, self.radius());
        each_shape!(self, s => s.height(r))
    }

    /// `d height / d r` at `r` in `[0, R]`.
    #[inline]
    pub fn slope(&self, r: f64) -> f64 {
        each_shape!(self, s => s.slope(r.clamp(0.0, self.radius())))
    }

    /// See [`Profile::facet_radius`].
    #[inline]
    pub fn facet_radius(&self, gradient: f64) -> f64 {
        each_shape!(self, s => s.facet_radius(gradient.max(0.0)))
    }

    /// Radius of the cutter at height `z` above the tip: the inverse of the
    /// profile (0 below the tip, `R` from the rim up).
    pub fn radius_at(&self, z: f64) -> f64 {
        each_shape!(self, s => radius_above(s, z, 200))
    }

    /// See [`Profile::body_radius`]: the exact inverse of the profile, in
    /// closed form.
    #[inline]
    pub fn body_radius(&self, z: f64) -> f64 {
        each_shape!(self, s => s.body_radius(z))
    }

    /// A radius at least [`Cutter::radius_at`]`(z)` and at most `R/4096`
    /// above it: how far from the axis a point `z` above the tip can
    /// touch the cutter, cheaply.
    pub fn reach(&self, z: f64) -> f64 {
        each_shape!(self, s => s.reach(z))
    }

    /// See [`Profile::edge_argmax`]; the result is clamped to `[lo, hi]`.
    pub fn edge_argmax(&self, d: f64, s: f64, m: f64, lo: f64, hi: f64) -> f64 {
        each_shape!(self, p => p.edge_argmax(d, s, m, lo, hi)).clamp(lo, hi)
    }
}

/// Largest cutter dimension accepted, mm: ten metres, far beyond any tool,
/// and far enough below overflow for every formula.
const MAX_SIZE: f64 = 10_000.0;

impl FromStr for Cutter {
    type Err = Error;

    /// `flat:D`, `ball:D`, `bull:D,R`, `oval:D,RL`, `v:D,ANGLE`,
    /// `drill:D,ANGLE` (mm, degrees).
    fn from_str(spec: &str) -> Result<Cutter, Error> {
        let fail = |reason: String| Error::new(ErrorKind::Spec, format!("tool '{spec}': {reason}"));
        let (kind, numbers) = spec.trim().split_once(':').ok_or_else(|| {
            fail("expected SHAPE:NUMBERS, e.g. ball:6, bull:10,1, oval:16,24, v:6,90 or flat:3".into())
        })?;
        let values: Vec<f64> = numbers
            .split(',')
            .map(|n| n.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
            .collect::<Option<_>>()
            .ok_or_else(|| fail(format!("'{numbers}' is not a list of numbers")))?;
        let count = |n: usize, names: &str| {
            if values.len() == n {
                Ok(())
            } else {
                Err(fail(format!("{} takes {names}", kind.to_lowercase())))
            }
        };
        let positive = |v: f64, what: &str| {
            let v = limits::length(v, &format!("the {what}")).map_err(fail)?;
            if v <= MAX_SIZE {
                Ok(v)
            } else {
                Err(fail(format!("the {what} must be at most {MAX_SIZE} mm, got {v}")))
            }
        };
        match kind.trim().to_lowercase().as_str() {
            "flat" => {
                count(1, "the diameter: flat:D")?;
                Ok(Cutter::Flat(Flat::new(positive(values[0], "diameter")?)))
            }
            "ball" => {
                count(1, "the diameter: ball:D")?;
                Ok(Cutter::Ball(Ball::new(positive(values[0], "diameter")?)))
            }
            "bull" => {
                count(2, "the diameter and corner radius: bull:D,R")?;
                let d = positive(values[0], "diameter")?;
                let r = values[1];
                if !(0.0..=d / 2.0).contains(&r) {
                    return Err(fail(format!("the corner radius must be from 0 to D/2 = {}, got {r}", d / 2.0)));
                }
                Ok(Cutter::Bull(Bull::new(d, r)))
            }
            "oval" => {
                count(2, "the diameter and the tip's axial semi-axis: oval:D,RL")?;
                let d = positive(values[0], "diameter")?;
                Ok(Cutter::Oval(Oval::new(d, positive(values[1], "axial semi-axis RL")?)))
            }
            "v" | "drill" => {
                let drill = kind.trim().eq_ignore_ascii_case("drill");
                let form = if drill {
                    "the diameter and the point angle in degrees: drill:D,ANGLE (118 for most drills)"
                } else {
                    "the diameter and the included angle in degrees: v:D,ANGLE"
                };
                count(2, form)?;
                let d = positive(values[0], "diameter")?;
                let angle = values[1];
                if !(angle > 0.0 && angle < 180.0) {
                    return Err(fail(format!("the included angle must be between 0 and 180 degrees, got {angle}")));
                }
                let cone = Vee::new(d, angle);
                Ok(if drill { Cutter::Drill(cone) } else { Cutter::Vee(cone) })
            }
            other => Err(fail(format!("unknown shape '{other}': expected flat, ball, bull, oval, v or drill"))),
        }
    }
}

impl fmt::Display for Cutter {
    /// The SPEC: `ball:6`, `bull:10,1`, …
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let d = 2.0 * self.radius();
        match self {
            Cutter::Flat(_) => write!(f, "flat:{d}"),
            Cutter::Ball(_) => write!(f, "ball:{d}"),
            Cutter::Bull(b) => write!(f, "bull:{d},{}", b.corner),
            Cutter::Oval(o) => write!(f, "oval:{d},{}", o.axial),
            Cutter::Vee(v) => write!(f, "v:{d},{}", v.angle_deg),
            Cutter::Drill(v) => write!(f, "drill:{d},{}", v.angle_deg),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all() -> Vec<Cutter> {
        [
            "flat:6",
            "ball:6",
            "bull:10,2",
            "bull:10,0",
            "bull:10,5",
            "oval:16,24",
            "oval:16,4",
            "v:6,90",
            "v:10,30",
            "drill:6,118",
        ]
        .iter()
        .map(|s| s.parse().unwrap())
        .collect()
    }

    #[test]
    fn specs_round_trip_and_bad_specs_say_why() {
        for c in all() {
            assert_eq!(c.to_string().parse::<Cutter>().unwrap(), c);
        }
        for (bad, why) in [
            ("ball:-3", "must be a length from"),
            ("ball:1e-300", "must be a length from"),
            ("oval:16,0", "must be a length from"),
            ("bull:10,6", "corner radius"),
            ("v:6,180", "angle"),
            ("ball", "SHAPE:NUMBERS"),
            ("ball:6,1", "takes"),
            ("cone:6", "unknown shape"),
            ("drill:6", "point angle"),
            ("drill:6,180", "angle"),
            ("ball:NaN", "not a list"),
            ("ball:1e308", "must be a length from"),
            ("ball:20000", "at most 10000 mm"),
        ] {
            let e = bad.parse::<Cutter>().unwrap_err().to_string();
            assert!(e.contains(why), "{bad}: {e}");
        }
    }

    /// The closed-form inverse undoes `height` and agrees with the default
    /// bisection to the last bits.
    #[test]
    fn body_radius_inverts_the_profile() {
        struct Bisect<'a>(&'a dyn Profile);
        impl Profile for Bisect<'_> {
            fn radius(&self) -> f64 {
                self.0.radius()
            }
            fn height(&self, r: f64) -> f64 {
                self.0.height(r)
            }
            fn slope(&self, r: f64) -> f64 {
                self.0.slope(r)
            }
            fn facet_radius(&self, g: f64) -> f64 {
                self.0.facet_radius(g)
            }
        }
        for c in all() {
            let r = c.radius();
            let top = c.height(r);
            assert_eq!(c.body_radius(-1e-9), 0.0, "{c}");
            assert_eq!(c.body_radius(top + 1.0), r, "{c}");
            for k in 1..1000 {
                let z = top * k as f64 / 1000.0;
                let w = c.body_radius(z);
                let b = Bisect(c.profile()).body_radius(z);
                assert!((w - b).abs() <= 1e-12 * r, "{c} z={z}: {w} vs {b}");
                assert!((c.height(w) - z).abs() <= 1e-12 * (1.0 + top), "{c} z={z}");
            }
            for k in 1..1000 {
                let x = r * k as f64 / 1000.0;
                let h = c.height(x);
                if c.slope(x) > 0.0 && c.slope(x).is_finite() && h < top {
                    assert!((c.body_radius(h) - x).abs() <= 1e-9 * r, "{c} r={x}");
                }
            }
        }
    }

    #[test]
    fn profiles_are_convex_non_decreasing_and_slopes_match() {
        for c in all() {
            let r = c.radius();
            assert_eq!(c.height(0.0), 0.0, "{c}");
            let n = 2000;
            let h: Vec<f64> = (0..=n).map(|k| c.height(r * k as f64 / n as f64)).collect();
            for k in 1..n {
                assert!(h[k] >= h[k - 1] - 1e-12, "{c}: non-decreasing");
                assert!(h[k + 1] - 2.0 * h[k] + h[k - 1] >= -1e-9, "{c}: convex at {k}");
            }
            for k in 1..n - 1 {
                let x = r * k as f64 / n as f64;
                let e = 1e-6;
                let fd = (c.height(x + e) - c.height(x - e)) / (2.0 * e);
                let s = c.slope(x);
                assert!((fd - s).abs() <= 1e-4 * (1.0 + s.abs()), "{c}: slope at {x}: {s} vs {fd}");
            }
        }
    }

    #[test]
    fn facet_radius_maximises_against_dense_sampling() {
        for c in all() {
            let r = c.radius();
            for g in [0.0, 0.1, 0.5, 1.0, 1.5, 3.0, 20.0] {
                let best = c.facet_radius(g);
                let score = |x: f64| g * x - c.height(x);
                let sampled = (0..=100_000).map(|k| score(r * k as f64 / 100_000.0)).fold(f64::MIN, f64::max);
                assert!(score(best) >= sampled - 1e-9, "{c} g={g}: r={best}");
            }
        }
    }

    /// The closed forms of [`Profile::edge_argmax`] and the generic solver
    /// find the same maximum, and no sample beats them.
    #[test]
    fn edge_closed_forms_agree_with_the_numeric_solver() {
        let mut seed = 7u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for c in all() {
            let r = c.radius();
            for _ in 0..2000 {
                let d = r * next();
                let s = ((r - d) * (r + d)).sqrt();
                let m = (next() - 0.5) * 8.0;
                let (u, v) = (-s + 2.0 * s * next(), -s + 2.0 * s * next());
                let (lo, hi) = (u.min(v), u.max(v));
                let f = |x: f64| m * x - c.height(x.hypot(d));
                let exact = f(c.edge_argmax(d, s, m, lo, hi));
                let numeric = f(edge_argmax_numeric(c.profile(), d, m, lo, hi));
                assert!((exact - numeric).abs() < 1e-9, "{c} d={d} m={m} [{lo}, {hi}]: {exact} vs {numeric}");
                let sampled = (0..=1000).map(|k| f(lo + (hi - lo) * k as f64 / 1000.0)).fold(f64::MIN, f64::max);
                assert!(exact >= sampled - 1e-12, "{c}: {exact} < {sampled}");
            }
        }
    }

    #[test]
    fn radius_at_inverts_the_profile() {
        for c in all() {
            for k in 1..10 {
                let r = c.radius() * k as f64 / 10.0;
                let z = c.height(r);
                if z > 0.0 && c.slope(r) > 0.0 {
                    assert!((c.radius_at(z) - r).abs() < 1e-9, "{c} at r={r}");
                }
                let (exact, reach) = (c.radius_at(0.7 * z), c.reach(0.7 * z));
                assert!(reach >= exact && reach <= exact + c.radius() / 4096.0, "{c}: reach {reach}, {exact}");
            }
            assert_eq!(c.radius_at(1e9), c.radius());
        }
    }

    #[test]
    fn height_of_the_squared_radius_is_the_height() {
        for c in all() {
            for k in 0..=100 {
                let r = c.radius() * k as f64 / 100.0;
                let (z, z2) = (c.height(r), each_shape!(c, s => s.height_sq(r * r)));
                assert!((z - z2).abs() <= 1e-12 * c.radius(), "{c} at r={r}: {z} vs {z2}");
            }
        }
    }
}
