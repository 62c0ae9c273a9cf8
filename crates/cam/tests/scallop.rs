//! Scallop theory: the oval end mill paper's figures, the closed forms against the
//! envelope, the envelope against a brute-force sampling, the inverse, and
//! bad input.

use kezuri_cam::scallop::{self, ClosedForm, Method, Step};
use kezuri_cam::Cutter;
use kezuri_cam::ErrorKind;
use proptest::prelude::*;

fn tool(spec: &str) -> Cutter {
    spec.parse().unwrap()
}

fn rad(deg: f64) -> f64 {
    deg.to_radians()
}

const EGG: &str = "oval:16,24";

/// The oval end mill paper (Iwabe, Kumaki, Hori), Table 1 and §5.2: the pick feed that
/// keeps the theoretical roughness at 10 µm.
#[test]
fn seed_001_pick_feed_control() {
    let egg = tool(EGG);
    for (deg, paper) in [(0.0, 0.462), (15.0, 0.484), (60.0, 1.052)] {
        let s = scallop::pick_feed(&egg, rad(deg), 0.010).unwrap();
        assert!((s.pick_feed - paper).abs() <= 0.002, "{deg}°: {} vs the paper's {paper}", s.pick_feed);
        assert!((s.cusp - 0.010).abs() < 1e-9, "{deg}°: {}", s.cusp);
        assert!(!s.width_limited);
        assert_eq!(s.method, Method::Closed(ClosedForm::Iwabe));
    }
}

/// Table 1's upper value, 1.780 mm at 75°, does not follow from the
/// geometry: 10 µm needs 1.739 mm, and 1.780 mm leaves 10.48 µm (1.780 mm
/// would be right at 75.7°). See docs/scallop.md.
#[test]
fn seed_001_upper_range_value_is_not_the_geometry() {
    let egg = tool(EGG);
    let s = scallop::pick_feed(&egg, rad(75.0), 0.010).unwrap();
    assert!((s.pick_feed - 1.7391).abs() < 0.0001, "{}", s.pick_feed);
    let at_paper = scallop::cusp(&egg, rad(75.0), 1.780).unwrap();
    assert!((at_paper.cusp - 0.010476).abs() < 0.000001, "{}", at_paper.cusp);
    let envelope = scallop::envelope_cusp(&egg, rad(75.0), 1.780, Step::Up).unwrap();
    assert!((envelope - at_paper.cusp).abs() < 1e-12);
    // 1.780 mm meets 10 µm only from 75.69° up.
    let s = scallop::pick_feed(&egg, rad(75.69), 0.010).unwrap();
    assert!((s.pick_feed - 1.780).abs() < 0.0005, "{}", s.pick_feed);
}

/// §5.2: with Pf = 0.8 mm the roughness falls from 24 to 5 µm (measured)
/// as the angle goes from 15° to 60°; the theory gives 27.4 and 5.8 µm.
#[test]
fn seed_001_constant_pick_feed() {
    let egg = tool(EGG);
    let at = |deg: f64| scallop::cusp(&egg, rad(deg), 0.8).unwrap().cusp * 1e3;
    assert!((at(15.0) - 27.0).abs() < 0.5, "{}", at(15.0));
    assert!((at(60.0) - 6.0).abs() < 0.5, "{}", at(60.0));
    // Theory above the measurement, by the 3 and 1 µm the paper shows.
    assert!(at(15.0) > 24.0 && at(15.0) - 24.0 < 4.0);
    assert!(at(60.0) > 5.0 && at(60.0) - 5.0 < 1.0);
    // It falls all the way from 0° (30 µm) to 75° (2 µm).
    let mut last = f64::INFINITY;
    for deg in [0.0, 15.0, 30.0, 45.0, 60.0, 75.0] {
        assert!(at(deg) < last, "{deg}°");
        last = at(deg);
    }
    assert!((at(0.0) - 30.02).abs() < 0.01 && (at(75.0) - 2.115).abs() < 0.001);
}

/// Equation (6) as printed, `(m·y_t − z_t − √(Rs²m² + Rl²)) / √(m² + 1)`,
/// is the signed distance of the cusp *below* the plane: negative.
#[test]
fn seed_001_equation_6_as_printed_has_the_wrong_sign() {
    let egg = tool(EGG);
    for deg in [0.0, 15.0, 30.0, 45.0, 60.0, 75.0] {
        let a = rad(deg);
        let i = scallop::iwabe(8.0, 24.0, a, 0.8 * a.cos(), 0.8 * a.sin()).unwrap();
        let envelope = scallop::envelope_cusp(&egg, a, 0.8, Step::Up).unwrap();
        assert!(i.printed_r_th < 0.0, "{deg}°: {}", i.printed_r_th);
        assert!((-i.printed_r_th - envelope).abs() < 1e-12, "{deg}°: {} vs {envelope}", i.printed_r_th);
        // (y_t, z_t) is on both ellipses, equations (1) and (2).
        let on = |y: f64, z: f64| (y / 8.0).powi(2) + (z / 24.0).powi(2);
        assert!((on(i.y_t, i.z_t) - 1.0).abs() < 1e-12);
        assert!((on(i.y_t - 0.8 * a.cos(), i.z_t - 0.8 * a.sin()) - 1.0).abs() < 1e-12);
    }
}

/// Equation (4) picks the lower crossing only with ellipse II up the slope.
/// Given the step-down neighbour's centre, (−Pf·cos α, −Pf·sin α), it
/// picks the upper one and (5) then moves it onto ellipse I's lower half:
/// no crossing at all. The geometry is symmetric: take the lower pass as
/// ellipse I, and step-down leaves what step-up leaves.
#[test]
fn seed_001_equation_4_wants_the_upper_pass_as_ellipse_ii() {
    let egg = tool(EGG);
    let a = rad(15.0);
    let down = scallop::iwabe(8.0, 24.0, a, -0.8 * a.cos(), -0.8 * a.sin()).unwrap();
    assert!(!down.on_lower_half);
    assert!((down.cusp - 0.5953).abs() < 1e-4, "{}", down.cusp);
    let on_ii = ((down.y_t + 0.8 * a.cos()) / 8.0).powi(2) + ((down.z_t + 0.8 * a.sin()) / 24.0).powi(2);
    assert!((on_ii - 1.0).abs() > 0.01, "{on_ii}");
    let d = scallop::envelope_cusp(&egg, a, 0.8, Step::Down).unwrap();
    let u = scallop::envelope_cusp(&egg, a, 0.8, Step::Up).unwrap();
    assert!((d - u).abs() < 1e-12 && (d - 0.027377).abs() < 1e-6, "{d} {u}");
}

/// Equation (5) takes the lower half of ellipse I; wide pick feeds on steep
/// planes cross above the egg's equator, on the shank. Then the closed form
/// steps aside and the envelope answers.
#[test]
fn seed_001_equation_5_holds_below_the_equator_only() {
    let egg = tool(EGG);
    let (a, pf) = (rad(85.0), 40.0);
    let i = scallop::iwabe(8.0, 24.0, a, pf * a.cos(), pf * a.sin()).unwrap();
    assert!(!i.on_lower_half);
    let s = scallop::cusp(&egg, a, pf).unwrap();
    assert_eq!(s.method, Method::Envelope);
    assert!(s.at_wall, "{s:?}");
    assert!((i.cusp - s.cusp).abs() > 0.1, "{} vs {}", i.cusp, s.cusp);
    // Over the paper's whole range the crossing is below the equator.
    for deg in [0.0, 15.0, 30.0, 45.0, 60.0, 75.0] {
        for pf in [0.462, 0.8, 1.052, 1.78] {
            let a = rad(deg);
            assert!(scallop::iwabe(8.0, 24.0, a, pf * a.cos(), pf * a.sin()).unwrap().on_lower_half);
        }
    }
}

fn shapes() -> Vec<Cutter> {
    [
        "ball:6",
        "ball:1",
        "oval:16,24",
        "oval:16,4",
        "oval:6,3",
        "flat:6",
        "bull:10,2",
        "bull:10,5",
        "bull:10,0",
        "bull:6,0.5",
        "v:6,90",
        "v:10,30",
        "v:6,150",
    ]
    .iter()
    .map(|s| tool(s))
    .collect()
}

const ANGLES: [f64; 12] = [0.0, 1.0, 5.0, 15.0, 30.0, 44.0, 45.0, 60.0, 75.0, 80.0, 85.0, 89.5];
const FRACTIONS: [f64; 12] = [0.0, 1e-4, 1e-3, 0.01, 0.05, 0.1, 0.25, 0.5, 0.75, 0.9, 0.99, 1.0];

/// The cusp by brute force, sharing nothing with the library but the
/// profile: each pass is dropped onto the line `z = m·y` by sampling, the
/// surface left is the lowest pass at each sample, the cusp its highest
/// point above the line between the two contacts.
fn brute_force(c: &Cutter, angle: f64, pf: f64, n: usize) -> f64 {
    let (m, r) = (angle.tan(), c.radius());
    let prof = |y: f64| if y.abs() <= r * (1.0 + 1e-12) { c.height(y.abs()) } else { f64::INFINITY };
    // Tip height of a pass at tip position t, resting on the line.
    let drop = |t: f64| {
        let mut z = f64::NEG_INFINITY;
        for k in 0..=n {
            let y = t - r + 2.0 * r * k as f64 / n as f64;
            z = z.max(m * y - prof(y - t));
        }
        z
    };
    let dy = pf * angle.cos();
    let (z1, z2) = (drop(0.0), drop(dy));
    let mut cusp: f64 = 0.0;
    for k in 0..=4 * n {
        let y = -r + (2.0 * r + dy) * k as f64 / (4 * n) as f64;
        let surface = (z1 + prof(y)).min(z2 + prof(y - dy));
        let contact1 = c.facet_radius(m);
        if y >= contact1 && y <= contact1 + dy {
            cusp = cusp.max(surface - m * y);
        }
    }
    cusp * angle.cos()
}

#[test]
fn the_envelope_agrees_with_brute_force() {
    for c in shapes() {
        for deg in [0.0, 15.0, 45.0, 60.0, 85.0] {
            let a = rad(deg);
            let widest = scallop::widest_pick_feed(&c, a);
            for f in [0.05, 0.3, 0.7, 0.98] {
                let pf = widest * f;
                let e = scallop::envelope_cusp(&c, a, pf, Step::Up).unwrap();
                let b = brute_force(&c, a, pf, 20_000);
                // Sampling the contacts and the crossing: steps of R / 10⁴
                // times the gaps' slopes there (below 1 + tan α mostly).
                let tol = 1e-6 + 2e-3 * e + 1e-5 * c.radius() * (1.0 + a.tan());
                assert!((e - b).abs() <= tol, "{c} {deg}° pf={pf}: envelope {e} brute force {b}");
            }
        }
    }
}

#[test]
fn closed_forms_agree_with_the_envelope() {
    let mut used = std::collections::HashMap::new();
    for c in shapes() {
        for deg in ANGLES {
            let a = rad(deg);
            let widest = scallop::widest_pick_feed(&c, a);
            for f in FRACTIONS {
                let pf = (widest * f).min(widest);
                let Some((closed, form)) = scallop::closed_form_cusp(&c, a, pf) else { continue };
                let e = scallop::envelope_cusp(&c, a, pf, Step::Up).unwrap();
                let scale = c.radius() * (1.0 + a.tan());
                assert!((closed - e).abs() <= 1e-12 * scale + 1e-9 * e, "{c} {deg}° pf={pf}: {form:?} {closed} vs {e}");
                *used.entry(format!("{form:?}")).or_insert(0) += 1;
            }
        }
    }
    for form in ["Ball", "Iwabe", "Flat", "Bull", "Vee"] {
        assert!(used.get(form).copied().unwrap_or(0) >= 20, "{form}: {used:?}");
    }
}

#[test]
fn the_ball_is_the_classic_formula_at_any_angle() {
    let ball = tool("ball:10");
    for deg in [0.0, 20.0, 45.0, 70.0] {
        for pf in [0.1, 1.0, 3.0] {
            let s = scallop::cusp(&ball, rad(deg), pf).unwrap();
            let classic = 5.0 - (25.0 - pf * pf / 4.0f64).sqrt();
            assert!((s.cusp - classic).abs() < 1e-12, "{deg}° {pf}");
            assert!((s.step_up_cusp - classic).abs() < 1e-11, "{deg}° {pf}: {}", s.step_up_cusp);
            assert_eq!(s.method, Method::Closed(ClosedForm::Ball));
        }
    }
    // An oval with RL = D/2 is that ball.
    let round = tool("oval:10,5");
    for deg in [0.0, 30.0, 60.0] {
        let a = scallop::cusp(&round, rad(deg), 1.0).unwrap().cusp;
        let b = scallop::cusp(&ball, rad(deg), 1.0).unwrap().cusp;
        assert!((a - b).abs() < 1e-12);
    }
}

#[test]
fn sharp_shapes_leave_staircases_and_plateaus() {
    // A flat end mill: steps of Pf·cos α by Pf·sin α, corner at the wall.
    let flat = tool("flat:6");
    let s = scallop::cusp(&flat, rad(30.0), 1.0).unwrap();
    assert!((s.cusp - 30f64.to_radians().sin() * 30f64.to_radians().cos()).abs() < 1e-12);
    assert!((s.step_up_cusp - s.cusp).abs() < 1e-12 && s.at_wall);
    assert_eq!(scallop::cusp(&flat, 0.0, 5.0).unwrap().cusp, 0.0);
    // A bull-nose on a level plane: nothing until the corners meet.
    let bull = tool("bull:10,2");
    assert_eq!(scallop::cusp(&bull, 0.0, 6.0).unwrap().cusp, 0.0);
    let s = scallop::cusp(&bull, 0.0, 7.0).unwrap();
    assert!((s.cusp - (2.0 - (4.0 - 0.25f64).sqrt())).abs() < 1e-12);
    // A 90° V-bit on a 45° plane: the uphill flank lies on the plane.
    let vee = tool("v:6,90");
    assert!(scallop::cusp(&vee, rad(45.0), 2.0).unwrap().cusp < 1e-12);
    // On a level plane: a triangle of height Pf / (2·tan 45°), square to it.
    assert!((scallop::cusp(&vee, 0.0, 1.0).unwrap().cusp - 0.5).abs() < 1e-12);
}

#[test]
fn step_up_and_step_down_leave_the_same_cusp() {
    for c in shapes() {
        for deg in ANGLES {
            let a = rad(deg);
            for f in FRACTIONS {
                let pf = scallop::widest_pick_feed(&c, a) * f;
                let s = scallop::cusp(&c, a, pf).unwrap();
                let scale = 1e-12 * c.radius() * (1.0 + a.tan());
                assert!((s.step_up_cusp - s.step_down_cusp).abs() <= scale, "{c} {deg}° {pf}: {s:?}");
                assert!(s.cusp.is_finite() && s.cusp >= 0.0);
                // The foot of a tall ridge (a wall, a sharp V) may lie past
                // the upper contact.
                assert!(s.cusp_offset >= -1e-9 && s.cusp_offset.is_finite(), "{c} {deg}° {pf}: {s:?}");
            }
        }
    }
}

#[test]
fn the_cusp_grows_with_the_pick_feed_and_the_inverse_finds_it() {
    for c in shapes() {
        for deg in ANGLES {
            let a = rad(deg);
            let widest = scallop::widest_pick_feed(&c, a);
            let mut last = 0.0;
            for k in 0..=200 {
                let pf = widest * k as f64 / 200.0;
                let h = scallop::cusp(&c, a, pf).unwrap().cusp;
                assert!(h >= last - 1e-12 * (1.0 + widest), "{c} {deg}° at {pf}: {h} < {last}");
                last = h;
            }
            for target in [1e-6, 0.001, 0.01, 0.1, 1.0] {
                let s = scallop::pick_feed(&c, a, target).unwrap();
                assert!(s.cusp <= target * (1.0 + 1e-9), "{c} {deg}° {target}: {s:?}");
                if s.width_limited {
                    assert!((s.pick_feed - widest).abs() <= 1e-12 * widest);
                } else {
                    // The largest: a hair wider overshoots.
                    let wider = scallop::cusp(&c, a, s.pick_feed * (1.0 + 1e-9) + 1e-12).unwrap().cusp;
                    assert!(wider > target || (s.cusp - target).abs() <= 1e-9 * target, "{c} {deg}° {target}: {s:?}");
                }
            }
        }
    }
}

#[test]
fn bad_input_is_an_error_never_a_panic_or_nan() {
    let egg = tool(EGG);
    for a in [-0.1, std::f64::consts::FRAC_PI_2, 2.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(scallop::cusp(&egg, a, 0.5), Err(e) if e.kind == ErrorKind::Angle), "{a}");
        assert!(matches!(scallop::pick_feed(&egg, a, 0.01), Err(e) if e.kind == ErrorKind::Angle), "{a}");
    }
    for pf in [-1.0, f64::NAN, f64::INFINITY, -0.0 - 1e-300] {
        assert!(matches!(scallop::cusp(&egg, 0.3, pf), Err(e) if e.kind == ErrorKind::PickFeed), "{pf}");
    }
    let e = scallop::cusp(&egg, rad(60.0), 33.0).unwrap_err();
    assert!(e.kind == ErrorKind::NoOverlap && e.to_string().contains("32"), "{e}");
    for t in [-0.01, f64::NAN, f64::INFINITY] {
        assert!(matches!(scallop::pick_feed(&egg, 0.3, t), Err(e) if e.kind == ErrorKind::Target), "{t}");
    }
    assert!(matches!(scallop::pick_feed(&egg, 0.3, 1e-12), Err(e) if e.kind == ErrorKind::TargetBelowResolution));
    let e = scallop::pick_feed(&egg, 0.3, 0.0).unwrap_err();
    assert!(e.kind == ErrorKind::Unreachable && e.to_string().contains("no pick feed"), "{e}");
    assert!(matches!(scallop::pick_feed(&tool("ball:6"), 0.0, 0.0), Err(e) if e.kind == ErrorKind::Unreachable));
    // A flat bottom on a level plane meets 0 at every overlapping pick feed.
    let s = scallop::pick_feed(&tool("flat:6"), 0.0, 0.0).unwrap();
    assert!(s.width_limited && s.pick_feed == 6.0 && s.cusp == 0.0);
    // Zero pick feed: no cusp.
    for c in shapes() {
        assert_eq!(scallop::cusp(&c, 0.5, 0.0).unwrap().cusp, 0.0, "{c}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn random_cases_are_finite_symmetric_and_closed_forms_hold(
        shape in 0usize..5,
        d in 0.5f64..30.0,
        second in 0.01f64..1.0,
        deg in 0.0f64..89.9,
        f in 0.0f64..1.0,
    ) {
        let spec = match shape {
            0 => format!("flat:{d}"),
            1 => format!("ball:{d}"),
            2 => format!("bull:{d},{}", second * d / 2.0),
            3 => format!("oval:{d},{}", second * 3.0 * d),
            _ => format!("v:{d},{}", 10.0 + 160.0 * second),
        };
        let c = tool(&spec);
        let a = rad(deg);
        let pf = scallop::widest_pick_feed(&c, a) * f;
        let s = scallop::cusp(&c, a, pf).unwrap();
        prop_assert!(s.cusp.is_finite() && s.cusp >= 0.0);
        let scale = 1e-11 * c.radius() * (1.0 + a.tan());
        prop_assert!((s.step_up_cusp - s.step_down_cusp).abs() <= scale);
        prop_assert!((s.cusp - s.step_up_cusp).abs() <= scale + 1e-9 * s.cusp, "{:?}", s);
        if s.cusp > 1e-6 {
            let back = scallop::pick_feed(&c, a, s.cusp).unwrap();
            prop_assert!(back.pick_feed >= pf * (1.0 - 1e-6), "{:?} vs {}", back, pf);
        }
    }
}
