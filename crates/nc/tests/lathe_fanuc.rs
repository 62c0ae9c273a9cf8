//! A Fanuc (and Haas) lathe's words and modal codes: X a diameter, U W H
//! incremental, the G code systems, feed per revolution, constant surface
//! speed, threading, chamfers and corners, the tool, arcs and dwells.
//!
//! Every expected number is worked out by hand in the comments from the
//! definitions of FANUC Series 0i-TF Plus Operator's Manual (B-64604EN),
//! lathe system (cited by section), before the output was looked at.
//! Positions in a move are the tool's: X is its distance from the spindle
//! axis (a radius), whatever the program's diameter mode.

use kezuri_geom::{MoveKind, Plane, Toolpath};
use kezuri_nc::interp::{Control, CoordSettings, GCodeSystem, Settings};
use kezuri_nc::Dialect;

mod common;

use common::lathe::{error, fanuc, haas, lathe, outcome, path};

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

fn assert_xz(m: &kezuri_geom::Move, x: f64, z: f64) {
    assert!(close(m.end.x, x, 1e-9) && close(m.end.z, z, 1e-9), "end {:?}, expected X{x} Z{z}", m.end);
}

// "Diameter and radius programming": with diameter programming X is the
// diameter, so X50. puts the tool 25 mm from the spindle axis.
// "Feed per revolution (G99)" is the power-on state (parameter FPM): F0.2 at
// S1000 (G97, rpm) is 0.2 × 1000 = 200 mm/min.
#[test]
fn x_is_a_diameter_and_f_is_per_revolution_at_power_on() {
    let t = path("S1000 M03\nG00 X50. Z2.\nG01 Z-20. F0.2\nM30\n", &fanuc());
    assert_eq!(t.moves.len(), 2);
    assert_xz(&t.moves[0], 25.0, 2.0);
    assert_xz(&t.moves[1], 25.0, -20.0);
    assert_eq!(t.moves[1].kind, MoveKind::Feed);
    assert!(close(t.moves[1].feed, 200.0, 1e-9), "feed {}", t.moves[1].feed);
    assert!(close(t.moves[1].speed, 1000.0, 0.0));
}

// Haas lathes read system A the same way (Haas Lathe Operator's Manual,
// "G-codes": X diameter, U W incremental, G99 feed per revolution).
#[test]
fn a_haas_lathe_reads_the_same_words() {
    let haas = haas();
    let t = path("S500 M03\nG00 X30. Z1.\nG01 U-4. W-11. F0.3\nM30\n", &haas);
    // X30 → radius 15; U-4 is 4 mm off the diameter, 2 off the radius:
    // 13; W-11 from Z1: -10. Feed 0.3 × 500 = 150 mm/min.
    assert_xz(&t.moves[1], 13.0, -10.0);
    assert!(close(t.moves[1].feed, 150.0, 1e-9));
}

// "Absolute and incremental programming" (system A): X Z absolute, U W
// incremental, U a diameter's change where X is a diameter.
#[test]
fn u_and_w_are_increments_of_x_and_z() {
    let t = path("S1000\nG00 X40. Z0.\nG01 U-10. W-5. F0.1\nX40. W-5.\nU0 Z-20.\nM30\n", &fanuc());
    // X40 Z0 → (20, 0); U-10 W-5 → (20 - 5, 0 - 5) = (15, -5);
    // X40 W-5 → (20, -10); U0 Z-20 → (20, -20).
    assert_xz(&t.moves[1], 15.0, -5.0);
    assert_xz(&t.moves[2], 20.0, -10.0);
    assert_xz(&t.moves[3], 20.0, -20.0);
}

// H is the incremental C (system A).
#[test]
fn h_is_the_increment_of_c() {
    let t = path("G00 X20. Z0. C10.\nH35.\nM30\n", &fanuc());
    assert!(close(t.moves[1].end.c, 45.0, 1e-9));
}

#[test]
fn u_and_x_in_one_block_is_a_located_error() {
    let (message, at) = error("S1000\nG00 X40. Z0.\nG01 X20. U-2. F0.1\nM30\n", &fanuc());
    assert_eq!(at, "U-2.");
    assert!(message.contains("X and U in one block"), "{message}");
    let (message, at) = error("G00 X40. Z0.\nG00 W1. Z3.\nM30\n", &fanuc());
    assert_eq!(at, "W1.");
    assert!(message.contains("Z and W"), "{message}");
}

// "Feed per minute (G98)": F in mm/min.
#[test]
fn g98_feeds_per_minute() {
    let t = path("S1000\nG00 X40. Z0.\nG98 G01 Z-10. F150.\nG99 Z-20. F0.1\nM30\n", &fanuc());
    assert!(close(t.moves[1].feed, 150.0, 1e-9));
    // Back in G99: 0.1 × 1000.
    assert!(close(t.moves[2].feed, 100.0, 1e-9));
}

// A lathe works in the ZX plane (G18 at power-on): I K are the arc centre's
// radius-wise and Z offsets from the start ("Circular interpolation": I K
// are radii, incremental, whatever the diameter mode), R the radius.
// From X20 Z0 (radius 10) to X40 Z-10 (radius 20), centre I0 K-10: (10,
// -10); the start is 10 from it along +Z, the end 10 along +X: a quarter
// turn counter-clockwise seen with Z to the right and X up (G03).
#[test]
fn arcs_take_i_k_and_r_as_radii_under_diameter_x() {
    for arc in ["G03 X40. Z-10. I0 K-10.", "G03 X40. Z-10. R10."] {
        let t = path(&format!("S800\nG00 X20. Z0.\nG01 F0.1\n{arc}\nM30\n"), &fanuc());
        let m = t.moves.last().unwrap();
        assert_xz(m, 20.0, -10.0);
        let MoveKind::Arc(a) = m.kind else { panic!("{arc}: not an arc") };
        assert_eq!(a.plane, Plane::Zx);
        assert!(a.ccw, "{arc}");
        assert!(close(a.center[0], 10.0, 1e-9) && close(a.center[2], -10.0, 1e-9), "{arc}: {:?}", a.center);
    }
}

// "Dwell (G04)": G04 X (seconds), U (seconds, system A), P (ms, no
// decimal point). X and U there are no positions: not halved.
#[test]
fn g04_dwells_by_x_u_or_p() {
    for (block, seconds) in [("G04 U1.5", 1.5), ("G04 X1.5", 1.5), ("G04 P1500", 1.5)] {
        let t = path(&format!("G00 X20. Z0.\n{block}\nM30\n"), &fanuc());
        assert_eq!(t.moves[1].kind, MoveKind::Dwell(seconds), "{block}");
        assert_xz(&t.moves[1], 10.0, 0.0);
    }
}

// "Reference position return (G28)": G28 U0 W0 goes through the point
// zero away from here (no intermediate move) to the reference position.
#[test]
fn g28_u0_w0_returns_through_where_the_tool_is() {
    let t = path("G00 X40. Z10.\nG28 U0 W0\nM30\n", &fanuc());
    assert_eq!(t.moves.len(), 2);
    assert_eq!(t.moves[1].kind, MoveKind::Home);
    assert_xz(&t.moves[1], 100.0, 200.0);
    // With a step: through X40+U10 (radius 25), Z10+W5 = 15, then home.
    let t = path("G00 X40. Z10.\nG28 U10. W5.\nM30\n", &fanuc());
    assert_eq!(t.moves.len(), 3);
    assert_xz(&t.moves[1], 25.0, 15.0);
    assert_xz(&t.moves[2], 100.0, 200.0);
}

// System B ("G code list"): G90/G91 absolute/incremental (X still a
// diameter: G91 X-10. is 5 mm nearer the axis), G94/G95 feed per
// minute/revolution, G98/G99 the drilling return levels. U is no address.
#[test]
fn system_b_reads_g90_g91_and_g94_g95() {
    let b = lathe(GCodeSystem::B);
    let t = path("S1000\nG90 G00 X40. Z0.\nG91 G01 X-10. Z-5. F0.1\nG90 G94 Z-20. F120.\nM30\n", &b);
    assert_xz(&t.moves[1], 15.0, -5.0);
    assert!(close(t.moves[1].feed, 100.0, 1e-9));
    assert_xz(&t.moves[2], 15.0, -20.0);
    assert!(close(t.moves[2].feed, 120.0, 1e-9));
    let (message, at) = error("G00 X40. Z0.\nG01 U-2. F0.1\nM30\n", &b);
    assert_eq!(at, "U-2.");
    assert!(message.contains("U is an axis"), "{message}");
}

// System C: G70/G71 are inch/mm input, so G70 X1. is a 1 inch diameter,
// 12.7 mm from the axis.
#[test]
fn system_c_reads_g70_as_inch() {
    let t = path("G70 G00 X1. Z0.5\nM30\n", &lathe(GCodeSystem::C));
    assert!(close(t.moves[0].end.x, 12.7, 1e-9) && close(t.moves[0].end.z, 12.7, 1e-9));
}

// A mill's G90 is absolute: unchanged by the lathe's reading.
#[test]
fn a_mill_reads_x_as_x() {
    let mill = Settings {
        coords: CoordSettings { control: Control::Fanuc, ..CoordSettings::default() },
        ..Settings::default()
    };
    let t = path("G90 G00 X50. Y0 Z2.\nM30\n", &mill);
    assert!(close(t.moves[0].end.x, 50.0, 0.0));
    let o = outcome("G90 G00 X50. Y0 Z2.\nM30\n", &mill);
    assert!(o.threads.is_empty());
}

fn with(settings: Settings, f: impl FnOnce(&mut Settings)) -> Settings {
    let mut s = settings;
    f(&mut s);
    s
}

// "Coordinate system setting (G50)": G50 X100. Z50. says the tool is at
// diameter 100 (radius 50), Z50 now. From the machine position 0 the work
// zero is then at X -50, Z -50, so G00 X40. Z10. goes to machine
// X 20 - 50 = -30, Z 10 - 50 = -40. Its S is the clamp, not a speed.
#[test]
fn g50_sets_the_coordinates_with_x_a_diameter() {
    let t = path("G50 X100. Z50. S2500\nG00 X40. Z10.\nM30\n", &fanuc());
    assert_eq!(t.moves.len(), 1);
    assert_xz(&t.moves[0], -30.0, -40.0);
    assert_eq!(t.moves[0].speed, 0.0, "G50 S is the clamp, the spindle speed stays unset");
}

// "Constant surface speed control": n = 1000·V / (π·D) rpm for V m/min at
// diameter D mm, never past the clamp (G50 S).
// G96 S200 at X40: 200000 / (π·40) = 1591.549 rpm; at X20 3183.1 rpm,
// past the clamp of 2000: 2000.
#[test]
fn css_turns_the_spindle_at_1000v_over_pi_d_up_to_the_clamp() {
    let t = path("G50 S2000\nG96 S200 M03\nG00 X40. Z0.\nX20.\nM30\n", &fanuc());
    assert!(close(t.moves[0].speed, 200_000.0 / (std::f64::consts::PI * 40.0), 1e-9), "{}", t.moves[0].speed);
    assert!(close(t.moves[0].speed, 1591.549, 1e-3));
    assert_eq!(t.moves[1].speed, 2000.0);
}

// Feed per revolution under constant surface speed: the time of a move is
// ∫ ds / (f·n(r)). From X40 to X20 (r 20 → 10) at F0.2, V = 200 m/min =
// 200,000 mm/min, n = V/(2πr) everywhere (clamp 5000 rpm is reached only
// below r = 6.37): T = ∫₁₀²⁰ 2πr dr / (f·V) = π(20² − 10²)/(f·V) =
// 300π/40000 = 0.0235619 min; the feed is 10 mm / T = f·V/(π·30) =
// 424.4132 mm/min (between 318.3 at the start and 636.6 at the end).
// Along Z at X40: f·n = 0.2 × 1591.549 = 318.3099 mm/min.
#[test]
fn css_feed_per_revolution_is_the_exact_time_over_the_move() {
    let prog = "G50 S5000\nG96 S200 M03\nG00 X40. Z0.\nG01 Z-10. F0.2\nX20.\nM30\n";
    let t = path(prog, &fanuc());
    assert!(close(t.moves[1].feed, 0.2 * 200_000.0 / (std::f64::consts::TAU * 20.0), 1e-9));
    assert!(close(t.moves[1].feed, 318.3099, 1e-4));
    let expected = 0.2 * 200_000.0 / (std::f64::consts::PI * 30.0);
    assert!(close(t.moves[2].feed, expected, 1e-9 * expected), "{} vs {expected}", t.moves[2].feed);
    assert!(close(t.moves[2].feed, 424.4132, 1e-4));
    // Its speed is the one at the end: 3183.1 rpm at X20.
    assert!(close(t.moves[2].speed, 3183.0989, 1e-4));
}

// The same move with the clamp at 2000 rpm: the clamp holds below r_c =
// V/(2π·2000) = 15.91549 mm. T = (1/f)[π(20² − r_c²)/V + (r_c − 10)/2000]
// = 5 × (0.0023043 + 0.0029577) = 0.0263103 min; feed 10/T = 380.0794.
#[test]
fn css_feed_counts_the_clamp_where_it_holds() {
    let prog = "G50 S2000\nG96 S200 M03\nG00 X40. Z0.\nG01 X20. F0.2\nM30\n";
    let t = path(prog, &fanuc());
    let (v, f) = (200_000.0, 0.2);
    let rc = v / (std::f64::consts::TAU * 2000.0);
    let time = (std::f64::consts::PI * (400.0 - rc * rc) / v + (rc - 10.0) / 2000.0) / f;
    assert!(close(t.moves[1].feed, 10.0 / time, 1e-9 * 380.0), "{}", t.moves[1].feed);
    assert!(close(t.moves[1].feed, 380.0794, 1e-4));
    assert_eq!(t.moves[1].speed, 2000.0);
}

// With no G50 clamp the spindle runs to the machine's top speed, with a
// warning naming it: at X10 (r 5) S200 asks 200000/(π·10) = 6366 rpm.
#[test]
fn css_without_a_clamp_runs_to_max_rpm_with_a_warning() {
    let s = with(fanuc(), |s| s.max_rpm = Some(3000.0));
    let o = outcome("G96 S200 M03\nG00 X40. Z0.\nG01 X10. F0.2\nM30\n", &s);
    assert_eq!(o.toolpath.moves[1].speed, 3000.0);
    let w = o.diagnostics.iter().find(|d| d.message.contains("top speed")).expect("a warning");
    assert!(w.message.contains("3000 rpm") && w.message.contains("6366 rpm"), "{}", w.message);
}

// Bad input: CSS reaching X0 with no maximum known: the speed has no bound.
#[test]
fn css_reaching_x0_with_no_maximum_is_a_located_error() {
    for (prog, word) in [
        ("G96 S200 M03\nG00 X40. Z0.\nG01 X0. F0.2\nM30\n", "X0."),
        ("G96 S200 M03\nG00 X40. Z0.\nG00 X0.\nM30\n", "X0."),
        ("G96 S200 M03\nG00 X40. Z0.\nG01 U-40. F0.2\nM30\n", "U-40."),
    ] {
        let (message, at) = error(prog, &fanuc());
        assert_eq!(at, word, "{prog}");
        assert!(message.contains("no bound") && message.contains("G50 S"), "{message}");
    }
    // The same with a clamp runs: G50 S1500 holds it.
    let t = path("G50 S1500\nG96 S200 M03\nG00 X40. Z0.\nG01 X0. F0.2\nM30\n", &fanuc());
    assert_eq!(t.moves[1].speed, 1500.0);
}

// G97 with no S keeps the speed the spindle reached under G96.
#[test]
fn g97_keeps_the_speed_reached() {
    let t = path("G50 S3000\nG96 S200 M03\nG00 X40. Z0.\nG97\nG01 X20. F0.2\nM30\n", &fanuc());
    let n = 200_000.0 / (std::f64::consts::PI * 40.0);
    assert!(close(t.moves[1].speed, n, 1e-9));
    assert!(close(t.moves[1].feed, 0.2 * n, 1e-9));
}

// Inch input: S in ft/min, n = 12·V/(π·D) for D in inches: G96 S500 at X2.
// (2 inch) is 6000/(2π) = 954.93 rpm.
#[test]
fn css_under_g20_is_feet_per_minute() {
    let t = path("G20\nG50 S5000\nG96 S500 M03\nG00 X2. Z0.\nM30\n", &fanuc());
    assert!(close(t.moves[0].speed, 954.9297, 1e-4), "{}", t.moves[0].speed);
}

// System B: G92 S is the clamp. G96 S100 at X10: 1000·100/(π·10) = 3183
// rpm, held to 1500.
#[test]
fn system_b_clamps_with_g92_s() {
    let t = path("G92 S1500\nG96 S100 M03\nG00 X10. Z0.\nM30\n", &lathe(GCodeSystem::B));
    assert_eq!(t.moves[0].speed, 1500.0);
}

// "Threading (G32)": F is the lead along Z (mm per revolution, whatever
// G98/G99): G32 Z-20. F1.5 at S500 feeds 1.5 × 500 = 750 mm/min and cuts a
// thread of lead 1.5 from (15, 5) to (15, -20). A taper thread G32 X34.
// Z-20. F2. (ΔZ 25, Δr 2: under 45°, the lead along Z) feeds 2 × 500 along
// Z, so along the path 1000 × √(25² + 2²)/25 = 1003.1949 mm/min.
#[test]
fn g32_cuts_a_thread_at_the_lead_per_revolution() {
    let o =
        outcome("G97 S500 M03\nG00 X30. Z5.\nG32 Z-20. F1.5\nG00 X40.\nZ5.\nX30.\nG32 X34. Z-20. F2.\nM30\n", &fanuc());
    let t = &o.toolpath;
    assert_xz(&t.moves[1], 15.0, -20.0);
    assert!(close(t.moves[1].feed, 750.0, 1e-9));
    assert_eq!(o.threads.len(), 2);
    assert_eq!(o.threads[0].lead, 1.5);
    assert_eq!((o.threads[0].start.x, o.threads[0].start.z), (15.0, 5.0));
    assert_eq!((o.threads[0].end.x, o.threads[0].end.z), (15.0, -20.0));
    assert_eq!(o.threads[0].line, 3);
    assert!(close(t.moves[5].feed, 1003.1949, 1e-4), "{}", t.moves[5].feed);
    // Under G98 the lead is still per revolution.
    let t = path("G98 G97 S400 M03\nG00 X30. Z5.\nG32 Z-20. F1.\nM30\n", &fanuc());
    assert!(close(t.moves[1].feed, 400.0, 1e-9));
}

// Bad input: threading with S0 or F0.
#[test]
fn threading_with_s0_or_f0_is_a_located_error() {
    let (message, at) = error("G97 S0 M03\nG00 X30. Z5.\nG32 Z-20. F1.5\nM30\n", &fanuc());
    assert_eq!(at, "S0");
    assert!(message.contains("spindle speed S0"), "{message}");
    let (message, at) = error("G97 S500 M03\nG00 X30. Z5.\nG32 Z-20. F0\nM30\n", &fanuc());
    assert_eq!(at, "F0");
    assert!(message.contains("lead F0"), "{message}");
    // System B's G33 is the same code.
    let (_, at) = error("G97 S500 M03\nG00 X30. Z5.\nG33 Z-20. F0\nM30\n", &lathe(GCodeSystem::B));
    assert_eq!(at, "F0");
}

fn xz(t: &Toolpath) -> Vec<(f64, f64)> {
    let r = |v: f64| (v * 1e9).round() / 1e9;
    t.moves.iter().map(|m| (r(m.end.x), r(m.end.z))).collect()
}

// "Chamfering and corner R" (system A): G01 Z-10. C1. moving along Z, the
// chamfer of 1 toward +X. From (r 10, Z1) to the corner (10, -10), the next
// block X40. to (20, -10): the move stops 1 before the corner at (10, -9),
// the chamfer goes to (11, -10), the next move on to (20, -10).
#[test]
fn a_chamfer_c_after_a_move_along_z() {
    let t = path("S500\nG00 X20. Z1.\nG01 Z-10. C1. F0.1\nX40.\nM30\n", &fanuc());
    assert_eq!(xz(&t), vec![(10.0, 1.0), (10.0, -9.0), (11.0, -10.0), (20.0, -10.0)]);
    assert_eq!(t.moves[2].kind, MoveKind::Feed);
    assert_eq!(t.moves[2].line, 3, "the chamfer is the first block's");
    assert_eq!(t.moves[3].line, 4);
    // Along X first: G01 X30. C-2. (the chamfer toward -Z), then Z-20.:
    // along +X from r 10 to the corner at r 15, stopping 2 short at 13; the
    // chamfer to 2 past the corner along -Z, (15, -2); then on to (15, -20).
    let t = path("S500\nG00 X20. Z0.\nG01 X30. C-2. F0.1\nZ-20.\nM30\n", &fanuc());
    assert_eq!(xz(&t), vec![(10.0, 0.0), (13.0, 0.0), (15.0, -2.0), (15.0, -20.0)]);
}

// Corner R: G01 Z-10. R2. then X40.: the move stops 2 before the corner at
// (10, -8), a quarter circle of radius 2 about (12, -8) to (12, -10): going
// -Z then turning to +X is clockwise seen with Z right and X up (G02).
#[test]
fn a_corner_r_after_a_move_along_z() {
    let t = path("S500\nG00 X20. Z1.\nG01 Z-10. R2. F0.1\nX40.\nM30\n", &fanuc());
    assert_eq!(xz(&t), vec![(10.0, 1.0), (10.0, -8.0), (12.0, -10.0), (20.0, -10.0)]);
    let MoveKind::Arc(a) = t.moves[2].kind else { panic!("not an arc: {:?}", t.moves[2].kind) };
    assert!(!a.ccw);
    assert!(close(a.center[0], 12.0, 1e-9) && close(a.center[2], -8.0, 1e-9), "{:?}", a.center);
}

// ,C and ,R between any two lines: ,C2. between -Z and the 45° line to
// (20, -20): 2 back along -Z, (10, -8); 2 along (1, -1)/√2 from the
// corner: (11.41421, -11.41421). ,R3. at a right angle: tangent length
// 3·tan(45°) = 3: (10, -7), (13, -10), centre (13, -7).
#[test]
fn comma_c_and_comma_r_between_any_two_lines() {
    let t = path("S500\nG00 X20. Z0.\nG01 Z-10. ,C2. F0.1\nX40. Z-20.\nM30\n", &fanuc());
    let h = 2.0 / 2f64.sqrt();
    let p = xz(&t);
    assert_eq!(p[1], (10.0, -8.0));
    assert!(close(p[2].0, 10.0 + h, 1e-9) && close(p[2].1, -10.0 - h, 1e-9), "{p:?}");
    assert_eq!(p[3], (20.0, -20.0));
    let t = path("S500\nG90 G00 X20. Z0.\nG01 Z-10. ,R3. F0.1\nX40.\nM30\n", &lathe(GCodeSystem::B));
    assert_eq!(xz(&t), vec![(10.0, 0.0), (10.0, -7.0), (13.0, -10.0), (20.0, -10.0)]);
    let MoveKind::Arc(a) = t.moves[2].kind else { panic!("not an arc") };
    assert!(close(a.center[0], 13.0, 1e-9) && close(a.center[2], -7.0, 1e-9), "{:?}", a.center);
}

#[test]
fn a_chamfer_the_next_block_cannot_take_is_a_located_error() {
    // The next block goes toward -X, the chamfer said +X.
    let (message, _) = error("S500\nG00 X20. Z1.\nG01 Z-10. C1. F0.1\nX10.\nM30\n", &fanuc());
    assert!(message.contains("toward +X"), "{message}");
    // A rapid after it.
    let (message, _) = error("S500\nG00 X20. Z1.\nG01 Z-10. C1. F0.1\nG00 X40.\nM30\n", &fanuc());
    assert!(message.contains("must be a G01"), "{message}");
    // Longer than the move: 15 from a corner 11 away.
    let (message, at) = error("S500\nG00 X20. Z1.\nG01 Z-10. C15. F0.1\nX60.\nM30\n", &fanuc());
    assert_eq!(at, "C15.");
    assert!(message.contains("longer than a move"), "{message}");
    // The program ends with the chamfer waiting.
    let (message, at) = error("S500\nG00 X20. Z1.\nG01 Z-10. ,R1. F0.1\nM30\n", &fanuc());
    assert_eq!(at, ",R1.");
    assert!(message.contains("program ends before"), "{message}");
    // ,C on a mill: not run in silence.
    let mill = Settings {
        coords: CoordSettings { control: Control::Fanuc, ..CoordSettings::default() },
        ..Settings::default()
    };
    let (message, at) = error("G00 X0. Y0.\nG01 X10. ,C1. F100.\nY10.\nM30\n", &mill);
    assert_eq!(at, ",C1.");
    assert!(message.contains("read on a lathe only"), "{message}");
}

// "T code": T0101 is tool 01 with offset 01; its length (the tool
// table's) is counted as the machine position, the tip stays programmed.
// T0100 cancels the offset.
#[test]
fn t0101_selects_the_tool_and_its_offset() {
    let s = with(fanuc(), |s| {
        s.tool_lengths.insert(1, 30.0);
    });
    let t = path("T0101\nG00 X20. Z5.\nT0100\nG00 X30.\nT0202\nG00 X40.\nM30\n", &s);
    assert_eq!(t.moves[0].tool, 1);
    assert_xz(&t.moves[0], 10.0, 5.0);
    let length = t.frames[t.moves[0].frame as usize].length.expect("offset 01 in force");
    assert_eq!((length.register, length.value), (1, 30.0));
    assert!(t.frames[t.moves[1].frame as usize].length.is_none());
    assert_eq!(t.moves[2].tool, 2);
    assert!(t.frames[t.moves[2].frame as usize].length.is_none(), "offset 02 is not in the table");
}

// The code tables ("G code list"): in system A G91 is no code; in system C
// G20 is the cutting cycle, not inch input (G70 is).
#[test]
fn codes_that_differ_between_systems() {
    let (message, at) = error("G91 G00 X10.\nM30\n", &fanuc());
    assert_eq!(at, "G91");
    assert!(message.contains("U, W and H are the incremental"), "{message}");
    // System B's G98 is the drilling return level: no feed mode change,
    // so F0.1 stays per revolution: 0.1 × 1000.
    let t = path("S1000\nG90 G00 X20. Z0.\nG98 G01 Z-5. F0.1\nM30\n", &lathe(GCodeSystem::B));
    assert!(close(t.moves[1].feed, 100.0, 1e-9));
}

// Under G96 the first cut may start where the program never put X (after a
// tool change): its speed is reckoned at its end, no error.
#[test]
fn css_from_an_x_never_named() {
    let t = path("G50 S2000\nG96 S100 M03\nG01 X40. Z0. F0.2\nM30\n", &fanuc());
    // 1000·100 / (π·40) = 795.77 rpm at the end.
    assert!(close(t.moves[0].speed, 795.7747, 1e-4), "{}", t.moves[0].speed);
}

// An arc under constant surface speed: G03 X40. Z-10. R10. from (r 10,
// Z0), centre (10, -10): the point at angle a (from +Z toward +X) is
// X = 10 + 10·sin a, ds = 10·da, a from 0 to π/2. With n = V/(2πX)
// (the clamp of 5000 rpm is reached only below r 6.37):
// T = ∫ ds/(f·n) = (2π/(f·V))·10·∫₀^{π/2} (10 + 10 sin a) da
//   = (2π/(f·V))·100·(π/2 + 1); L = 5π; feed = L/T = f·V/(40·(π/2 + 1))
//   = 0.2 × 200000 / (40 × 2.5707963) = 388.9845 mm/min.
#[test]
fn css_feed_over_an_arc_is_its_exact_time() {
    let t = path("G50 S5000\nG96 S200 M03\nG00 X20. Z0.\nG03 X40. Z-10. R10. F0.2\nM30\n", &fanuc());
    let expected = 0.2 * 200_000.0 / (40.0 * (std::f64::consts::FRAC_PI_2 + 1.0));
    assert!(close(t.moves[1].feed, expected, 1e-9 * expected), "{} vs {expected}", t.moves[1].feed);
    assert!(close(t.moves[1].feed, 388.9845, 1e-4));
}

// The chamfer's other addresses ("Chamfering and corner R": I after a move
// along Z, K after one along X; parameter 3405 CCR chooses C or I K): the
// same path as C. A Haas lathe's C is its C axis, so there I K R only.
#[test]
fn a_chamfer_by_i_or_k() {
    let t = path("S500\nG00 X20. Z1.\nG01 Z-10. I1. F0.1\nX40.\nM30\n", &fanuc());
    assert_eq!(xz(&t), vec![(10.0, 1.0), (10.0, -9.0), (11.0, -10.0), (20.0, -10.0)]);
    let t = path("S500\nG00 X20. Z0.\nG01 X30. K-2. F0.1\nZ-20.\nM30\n", &fanuc());
    assert_eq!(xz(&t), vec![(10.0, 0.0), (13.0, 0.0), (15.0, -2.0), (15.0, -20.0)]);
    let haas = Settings {
        dialect: Dialect::HaasLathe,
        coords: CoordSettings { control: Control::Haas, ..CoordSettings::default() },
        ..fanuc()
    };
    let t = path("S500\nG00 X20. Z1.\nG01 Z-10. I1. F0.1\nX40.\nM30\n", &haas);
    assert_eq!(xz(&t), vec![(10.0, 1.0), (10.0, -9.0), (11.0, -10.0), (20.0, -10.0)]);
    // G01 Z-10. C90. on a Haas turns C as Z moves.
    let t = path("S500\nG00 X20. Z1. C0.\nG01 Z-10. C90. F0.1\nM30\n", &haas);
    assert_eq!(t.moves.len(), 2);
    assert_eq!(t.moves[1].end.c, 90.0);
}

// Two corners in a row: the second block both ends the first chamfer and
// asks for its own. G01 Z-10. C1. then X40. C-1. (along +X, toward -Z)
// then Z-20.: (10, -9), chamfer to (11, -10), along X to 1 short of the
// corner (20, -10): (19, -10), chamfer to (20, -11), on to (20, -20).
#[test]
fn chamfers_in_a_row() {
    let t = path("S500\nG00 X20. Z1.\nG01 Z-10. C1. F0.1\nX40. C-1.\nZ-20.\nM30\n", &fanuc());
    assert_eq!(xz(&t), vec![(10.0, 1.0), (10.0, -9.0), (11.0, -10.0), (19.0, -10.0), (20.0, -11.0), (20.0, -20.0)]);
}

// #4001… read the lathe's groups ("G code list", lathe system): 01 the
// threading mode (G32), 02 G96, 05 G99 (system A), 16 the plane G18.
#[test]
fn modal_reads_follow_the_lathe_groups() {
    let prog = "G50 S2000\nG96 S100 M03\nG00 X20. Z5.\nG32 Z-5. F1.\n#101=#4001\n#102=#4002\n#105=#4005\n#116=#4016\n\
                DPRNT[A#101[2]B#102[2]C#105[2]D#116[2]]\nM30\n";
    let o = outcome(prog, &fanuc());
    assert_eq!(o.prints, vec!["A32B96C99D18".to_string()], "{:?}", o.prints);
}
