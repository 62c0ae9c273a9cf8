//! A Fanuc (and Haas) lathe's words and modal codes: X a diameter, U W H
//! incremental, the G code systems, feed per revolution, constant surface
//! speed, threading, chamfers and corners, the tool, arcs and dwells.
//!
//! Every expected number is worked out by hand in the comments from the
//! definitions of FANUC Series 0i-TF Plus Operator's Manual (B-64604EN),
//! lathe system (cited by section), before the output was looked at.
//! Positions in a move are the tool's: X is its distance from the spindle
//! axis (a radius), whatever the program's diameter mode.

use kezuri_geom::{Axes, MoveKind, Plane, Toolpath};
use kezuri_nc::interp::{Control, CoordSettings, GCodeSystem, IntegerInput, Lathe, Outcome, Settings, XMode};
use kezuri_nc::Dialect;

mod common;

fn lathe(system: GCodeSystem) -> Settings {
    Settings {
        dialect: Dialect::FanucLathe,
        integer_input: IntegerInput::Increments,
        coords: CoordSettings { control: Control::Fanuc, ..CoordSettings::default() },
        home: Axes { x: 100.0, z: 200.0, ..Axes::ZERO },
        reference_given: [true; 4],
        lathe: Some(Lathe { x: XMode::Diameter, system }),
        ..Settings::default()
    }
}

fn fanuc() -> Settings {
    lathe(GCodeSystem::A)
}

fn path(text: &str, settings: &Settings) -> Toolpath {
    common::run("t.nc", text, settings).path()
}

fn outcome(text: &str, settings: &Settings) -> Outcome {
    common::run("t.nc", text, settings).completed()
}

/// The error's message and the text its span covers.
fn error(text: &str, settings: &Settings) -> (String, String) {
    let ran = common::run("t.nc", text, settings);
    let d = ran.error().unwrap_or_else(|| panic!("no error:\n{text}")).clone();
    (d.message.clone(), text[d.span.start as usize..d.span.end as usize].to_string())
}

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
    let haas = Settings {
        dialect: Dialect::HaasLathe,
        coords: CoordSettings { control: Control::Haas, ..CoordSettings::default() },
        lathe: None,
        ..fanuc()
    };
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
