//! Coordinate systems (docs/coordinates.md): G52, G68/G69, G51/G50,
//! G51.1/G50.1, G16/G15, G30 P2–P4, G53 under G91, G90.1/G91.1. Every
//! expected point is worked out by hand in the comment above it; all are
//! checked to 1e-9 mm.

use kezuri_geom::{Axes, MoveKind, Toolpath};
use kezuri_nc::interp::{Control, CoordSettings, IntegerInput, Outcome, Settings};
use kezuri_nc::write::{program, Dialect, WriteOptions};

mod common;

fn run_with(text: &str, settings: &Settings) -> Outcome {
    common::run("t.nc", text, settings).outcome
}

/// Runs `text` to its end without an error; the toolpath.
fn path_with(text: &str, settings: &Settings) -> Toolpath {
    common::run("t.nc", text, settings).path()
}

fn path(text: &str) -> Toolpath {
    path_with(text, &Settings::default())
}

/// The error that stopped the run.
fn error_with(text: &str, settings: &Settings) -> String {
    common::run("t.nc", text, settings).message()
}

/// The end points (X Y Z) of the moves, in order.
fn ends(t: &Toolpath) -> Vec<[f64; 3]> {
    t.moves.iter().map(|m| [m.end.x, m.end.y, m.end.z]).collect()
}

#[track_caller]
fn close(got: [f64; 3], want: [f64; 3]) {
    assert!((0..3).all(|i| (got[i] - want[i]).abs() < 1e-9), "got {got:?}, want {want:?}");
}

#[track_caller]
fn all_close(got: &[[f64; 3]], want: &[[f64; 3]]) {
    assert_eq!(got.len(), want.len(), "{got:?} vs {want:?}");
    for (g, w) in got.iter().zip(want) {
        close(*g, *w);
    }
}

fn at(x: f64, y: f64, z: f64) -> Axes {
    Axes { x, y, z, ..Axes::ZERO }
}

/// G54 at X100 Y50: the work zero away from the machine's.
fn g54() -> Settings {
    let mut s = Settings::default();
    s.work_offsets[0] = at(100.0, 50.0, 0.0);
    s
}

const S30: f64 = 0.5;
const C30: f64 = 0.866_025_403_784_438_6;

#[test]
fn g52_shifts_the_work_zero_and_g52_zero_cancels_it() {
    // G54 = (100, 50). G52 X10 Y20 puts the local zero at machine
    // (110, 70): X5 Y5 is (115, 75). #5001 then reads 5 (local), so
    // X[#5001+1] is local 6 = machine 116. G52 X0 Y0: X5 Y5 is (105, 55).
    let t = path_with(
        "G90 G00 X0. Y0.\nG52 X10. Y20.\nG00 X5. Y5.\nG00 X[#5001+1.] Y#5002\nG52 X0. Y0.\nG00 X5. Y5.\nM30\n",
        &g54(),
    );
    all_close(&ends(&t), &[[100.0, 50.0, 0.0], [115.0, 75.0, 0.0], [116.0, 75.0, 0.0], [105.0, 55.0, 0.0]]);
}

#[test]
fn g52_on_linuxcnc_is_the_g92_offset() {
    // LinuxCNC: G52 X10 writes the G92 offset; a later G92 X0 at machine
    // X10 replaces it (offset 10 - 0 from the work zero): X5 is 15 both ways.
    let s = Settings {
        coords: CoordSettings { control: Control::LinuxCnc, ..CoordSettings::default() },
        integer_input: IntegerInput::Units,
        ..Settings::default()
    };
    let t = path_with("G90 G00 X0 Y0\nG52 X10\nG00 X5\nG00 X0\nG92 X0\nG00 X5\nM30\n", &s);
    all_close(&ends(&t), &[[0.0; 3], [15.0, 0.0, 0.0], [10.0, 0.0, 0.0], [15.0, 0.0, 0.0]]);
}

#[test]
fn g68_rotates_absolute_and_incremental_moves_and_arcs() {
    // G68 X10 Y0 R90: program (20, 0) is 10 along +X from the centre,
    // rotated 90° CCW: 10 along +Y, (10, 10).
    // G03 X10 Y10 I-10 J0 from program (20, 0): centre (10, 0), a quarter
    // circle CCW to (10, 10). Rotated: the centre stays (10, 0) (it is the
    // rotation centre), the end (10, 10) - (10, 0) = (0, 10) turns to
    // (-10, 0): machine (0, 0). Still CCW.
    // G91 X5: the increment (5, 0) turns to (0, 5): (0, 5).
    // G69 G90 X0 Y0: unrotated (0, 0).
    let t = path(
        "G90 G17 G00 X0. Y0.\nG68 X10. Y0. R90.\nG01 X20. Y0. F100.\nG03 X10. Y10. I-10. J0.\nG91 G01 X5.\nG69 G90 G00 X0. Y0.\nM30\n",
    );
    all_close(&ends(&t), &[[0.0; 3], [10.0, 10.0, 0.0], [0.0, 0.0, 0.0], [0.0, 5.0, 0.0], [0.0; 3]]);
    let MoveKind::Arc(arc) = t.moves[2].kind else { panic!("{:?}", t.moves[2]) };
    close(arc.center, [10.0, 0.0, 0.0]);
    assert!(arc.ccw);
}

#[test]
fn g68_without_a_centre_turns_about_the_tool() {
    // The tool at (10, 0); G68 R90 without X Y: centre (10, 0). G91 X5
    // (the increment turned: (0, 5)) ends at (10, 5); G90 X10 Y5: program
    // (10, 5) is (0, 5) from the centre, turned (-5, 0): (5, 0).
    let t = path("G90 G00 X10. Y0.\nG68 R90.\nG91 G00 X5.\nG90 G00 X10. Y5.\nM30\n");
    all_close(&ends(&t), &[[10.0, 0.0, 0.0], [10.0, 5.0, 0.0], [5.0, 0.0, 0.0]]);
}

#[test]
fn g68_r_is_absolute_unless_the_setting_makes_it_follow_g91() {
    // G68 R30 then G91 G68 R60 about (0, 0), then X10 Y0:
    // R always absolute: 60°, (5, 8.660…); RIN set: 30 + 60 = 90°, (0, 10).
    let text = "G90 G00 X0. Y0.\nG68 X0. Y0. R30.\nG91 G68 X0. Y0. R60.\nG90 G00 X10. Y0.\nM30\n";
    close(ends(&path(text))[1], [5.0, 10.0 * C30, 0.0]);
    let s = Settings {
        coords: CoordSettings { rotation_incremental: true, ..CoordSettings::default() },
        ..Settings::default()
    };
    close(ends(&path_with(text, &s))[1], [0.0, 10.0, 0.0]);
}

#[test]
fn g68_without_a_decimal_point_counts_thousandths_of_a_degree() {
    // R90000 = 90.000°: X10 Y0 about (0, 0) is (0, 10).
    close(ends(&path("G90 G00 X0. Y0.\nG68 X0. Y0. R90000\nG00 X10. Y0.\nM30\n"))[1], [0.0, 10.0, 0.0]);
}

#[test]
fn positions_read_and_g92_stay_in_program_coordinates_under_g68() {
    // G68 X0 Y0 R90, tool at program (10, 0) = machine (0, 10).
    // X[#5001+1] Y#5002: program (11, 0) = machine (0, 11).
    // G92 X0 Y0 there: program (0, 0) is machine (0, 11); X1 (along the
    // turned X, machine +Y) is (0, 12).
    let t = path(
        "G90 G00 X0. Y0.\nG68 X0. Y0. R90.\nG00 X10. Y0.\nG00 X[#5001+1.] Y#5002\nG92 X0. Y0.\nG00 X1. Y0.\nM30\n",
    );
    all_close(&ends(&t), &[[0.0; 3], [0.0, 10.0, 0.0], [0.0, 11.0, 0.0], [0.0, 12.0, 0.0]]);
}

#[test]
fn g51_scales_with_p_about_its_centre() {
    // G51 X10 Y10 P2: X20 Y10 is 10 + 2 × 10 = 30 on X, Y stays 10.
    // Z: the centre is the tool's Z 0 (not named): Z-1 is -2.
    // An R arc with equal factors: R5 from program (20, 10)… machine (30, 10)
    // to program (10, 20) → machine (10, 30), radius 10, centre (10, 10)
    // (program centre (10, 10) for the short CCW arc, the scaling centre).
    // P1500 without a decimal point: 1.5 (0.001 units): X20 → 10 + 15 = 25;
    // the Z centre is the tool's Z, -2 after G50: Z0 → -2 + 1.5 × 2 = 1.
    let t = path(
        "G90 G00 X0. Y0. Z0.\nG51 X10. Y10. P2.\nG01 X20. Y10. F100.\nZ-1.\nG03 X10. Y20. R10.\nG50\nG51 X10. Y10. P1500\nG00 X20. Y10. Z0.\nM30\n",
    );
    all_close(&ends(&t), &[[0.0; 3], [30.0, 10.0, 0.0], [30.0, 10.0, -2.0], [10.0, 30.0, -2.0], [25.0, 10.0, 1.0]]);
    let MoveKind::Arc(arc) = t.moves[3].kind else { panic!() };
    close(arc.center, [10.0, 10.0, -2.0]);
}

#[test]
fn g51_scales_each_axis_with_i_j_k() {
    // G51 X0 Y0 Z0 I2 J0.5 K1: X10 Y10 Z-4 is (20, 5, -4); G91 X1 Y2 is an
    // increment (2, 1): (22, 6, -4).
    let t = path("G90 G00 X0. Y0. Z0.\nG51 X0. Y0. Z0. I2. J0.5 K1.\nG00 X10. Y10. Z-4.\nG91 X1. Y2.\nM30\n");
    all_close(&ends(&t), &[[0.0; 3], [20.0, 5.0, -4.0], [22.0, 6.0, -4.0]]);
}

#[test]
fn g51_mirror_by_a_negative_factor_swaps_the_arc() {
    // G51 X0 Y0 I-1 J1: a mirror in X. G02 from (10, 0) to (0, 10) about
    // (0, 0) becomes a CCW arc from (-10, 0) to (0, 10) about (0, 0).
    let t = path("G90 G00 X10. Y0.\nG51 X0. Y0. I-1. J1.\nG00 X10. Y0.\nG02 X0. Y10. I-10. J0. F100.\nM30\n");
    let MoveKind::Arc(arc) = t.moves[2].kind else { panic!() };
    assert!(arc.ccw);
    close(t.moves[1].end.xyz(), [-10.0, 0.0, 0.0]);
}

#[test]
fn g51_1_mirrors_x_and_swaps_arc_direction() {
    // G51.1 X5: X mirrored about the line X5. X10 Y0 → (0, 0).
    // G02 X5 Y5 I-5 J0 (program: from (10, 0) CW about (5, 0) to (5, 5),
    // three quarters round): mirrored, from (0, 0) about (5, 0) to (5, 5),
    // CCW. G50.1 X0: cancelled, X10 Y0 is (10, 0).
    let t =
        path("G90 G00 X0. Y0.\nG51.1 X5.\nG00 X10. Y0.\nG02 X5. Y5. I-5. J0. F100.\nG50.1 X0.\nG00 X10. Y0.\nM30\n");
    all_close(&ends(&t), &[[0.0; 3], [0.0, 0.0, 0.0], [5.0, 5.0, 0.0], [10.0, 0.0, 0.0]]);
    let MoveKind::Arc(arc) = t.moves[2].kind else { panic!() };
    assert!(arc.ccw);
    close(arc.center, [5.0, 0.0, 0.0]);
}

#[test]
fn g16_polar_absolute_and_incremental() {
    // G16 in G17: X is the radius, Y the angle, about the work zero.
    // X10 Y30: (10 cos 30°, 10 sin 30°) = (8.660…, 5).
    // G91 Y60 (no radius: about the work zero, angle added): 90°, (0, 10).
    // G91 X5 (an incremental radius: from the tool, at its angle 90°): (0, 15).
    // G90 Z-1 is not polar: (0, 15, -1). G15 G90 X1 Y2: Cartesian again.
    let t = path("G90 G17 G00 X0. Y0.\nG16\nG00 X10. Y30.\nG91 Y60.\nX5.\nG90 Z-1.\nG15\nG00 X1. Y2.\nM30\n");
    all_close(
        &ends(&t),
        &[
            [0.0; 3],
            [10.0 * C30, 10.0 * S30, 0.0],
            [0.0, 10.0, 0.0],
            [0.0, 15.0, 0.0],
            [0.0, 15.0, -1.0],
            [1.0, 2.0, -1.0],
        ],
    );
}

#[test]
fn g16_polar_is_about_the_local_zero() {
    // G54 (100, 50), G52 X10: the pole is at machine (110, 50). X10 Y90 is
    // (110, 60).
    let t = path_with("G90 G00 X0. Y0.\nG52 X10.\nG16\nG00 X10. Y90.\nM30\n", &g54());
    close(ends(&t)[1], [110.0, 60.0, 0.0]);
}

#[test]
fn g30_returns_to_the_2nd_3rd_and_4th_reference_points() {
    // P2 (the default) at (-100, -200, -50), P3 at (1, 2, 3), P4 at (7, 8, 9).
    // G91 G30 Z0: Z only, to -50. G90 G30 P3 X0 Y0: via the work zero
    // (0, 0, -50), no move there from (0, 0, -50), then X Y to P3's.
    // G30 P4 Z0: via Z0 (0 in work = 0), then Z to 9.
    let s = Settings {
        coords: CoordSettings {
            reference_points: [at(-100.0, -200.0, -50.0), at(1.0, 2.0, 3.0), at(7.0, 8.0, 9.0)],
            ..CoordSettings::default()
        },
        ..Settings::default()
    };
    let t = path_with("G90 G00 X0. Y0. Z0.\nG91 G30 Z0.\nG90 G30 P3 X0. Y0.\nG30 P4 Z0.\nM30\n", &s);
    all_close(&ends(&t), &[[0.0; 3], [0.0, 0.0, -50.0], [1.0, 2.0, -50.0], [1.0, 2.0, 0.0], [1.0, 2.0, 9.0]]);
    assert!(matches!(t.moves[1].kind, MoveKind::Home));
    assert!(error_with("G30 P5 Z0.\nM30\n", &s).contains("P1 (G28's) to P4"));
}

#[test]
fn g53_under_g91_moves_incrementally_on_fanuc_and_stops_linuxcnc() {
    // Fanuc: G53 ignored, X5 an increment from X10: (15, 0), with a warning.
    let outcome = run_with("G90 G00 X10. Y0.\nG91 G53 X5.\nM30\n", &Settings::default());
    assert!(outcome.completed);
    close(ends(&outcome.toolpath)[1], [15.0, 0.0, 0.0]);
    assert!(outcome.diagnostics.iter().any(|d| d.message.contains("ignores the G53")));
    let s = Settings {
        coords: CoordSettings { control: Control::LinuxCnc, ..CoordSettings::default() },
        ..Settings::default()
    };
    assert!(error_with("G90 G00 X10. Y0.\nG91 G53 X5.\nM30\n", &s).contains("Cannot use G53 incremental"));
}

#[test]
fn g52_and_g68_together() {
    // G54 (100, 50), G52 X10 Y10, G68 X0 Y0 R90 about the local zero
    // (machine (110, 60)): X10 Y0 turns to local (0, 10): machine (110, 70).
    let t = path_with("G90 G00 X0. Y0.\nG52 X10. Y10.\nG68 X0. Y0. R90.\nG00 X10. Y0.\nM30\n", &g54());
    close(ends(&t)[1], [110.0, 70.0, 0.0]);
}

#[test]
fn g51_then_g68_scales_first_and_scales_the_centre() {
    // G51 X0 Y0 P2 then G68 X5 Y0 R90: the centre scaled to (10, 0).
    // X10 Y0 scaled (20, 0), turned about (10, 0): (10, 10).
    let t = path("G90 G00 X0. Y0.\nG51 X0. Y0. P2.\nG68 X5. Y0. R90.\nG01 X10. Y0. F100.\nM30\n");
    close(ends(&t)[1], [10.0, 10.0, 0.0]);
}

#[test]
fn a_mirror_image_reverses_the_sense_of_g68() {
    // G51.1 X0 then G68 X0 Y0 R30: X10 Y0 mirrored (-10, 0), turned -30°:
    // (-10 cos 30°, 10 sin 30°) = (-8.660…, 5): the mirror image of the
    // unmirrored (8.660…, 5).
    let t = path("G90 G00 X0. Y0.\nG51.1 X0.\nG68 X0. Y0. R30.\nG00 X10. Y0.\nM30\n");
    close(ends(&t)[1], [-10.0 * C30, 5.0, 0.0]);
}

#[test]
fn arc_centre_modes() {
    // G90.1: I J are the centre's position. From (10, 0) CCW about (0, 0)
    // to (0, 10). LinuxCNC reads it silently; Fanuc with a warning.
    let text = "G90 G00 X10. Y0.\nG90.1\nG03 X0. Y10. I0. J0. F100.\nG91.1\nG03 X-10. Y0. I0. J-10.\nM30\n";
    let linuxcnc = Settings {
        coords: CoordSettings { control: Control::LinuxCnc, ..CoordSettings::default() },
        ..Settings::default()
    };
    for s in [&linuxcnc, &Settings::default()] {
        let outcome = run_with(text, s);
        assert!(outcome.completed, "{:?}", outcome.diagnostics);
        for k in [1, 2] {
            let MoveKind::Arc(arc) = outcome.toolpath.moves[k].kind else { panic!() };
            close(arc.center, [0.0; 3]);
        }
        let warned = outcome.diagnostics.iter().any(|d| d.message.contains("alarm PS0010"));
        assert_eq!(warned, s.coords.control == Control::Fanuc);
    }
    assert!(error_with("G00 X10. Y0.\nG90.1\nG03 X0. Y10. I0.\nM30\n", &linuxcnc).contains("J is missing"));
}

#[test]
fn bad_input_is_located() {
    for (text, words) in [
        ("G51 X0. Y0. P0\nM30\n", "scale factor of 0"),
        ("G51 X0. Y0. I1. J0.\nM30\n", "scale factor of 0"),
        ("G00 X0. Y10.\nG51 X0. Y0. I2. J1.\nG02 X10. Y0. R10. F1.\nM30\n", "cannot cut an ellipse"),
        ("G68 X0. Y0. R10.\nG18\nM30\n", "plane cannot change"),
        ("G68 X0. Y0. R10.\nG18 G02 X1. Z1. R1. F1.\nM30\n", "plane cannot change"),
        ("G51.1\nM30\n", "mirror line"),
        // No centre, and the tool's position never named: nothing to turn about.
        ("G68 R30.\nM30\n", "G68 without its centre in XY"),
        ("G00 X5.\nG68 R30.\nM30\n", "G68 without its centre in Y"),
        ("G51 P2.\nM30\n", "G51 without its centre in XY"),
    ] {
        assert!(error_with(text, &Settings::default()).contains(words), "{text}");
    }
    let s = Settings {
        coords: CoordSettings { control: Control::LinuxCnc, ..CoordSettings::default() },
        ..Settings::default()
    };
    assert!(error_with("G68 X0. Y0. R10.\nM30\n", &s).contains("Unknown g code"));
}

#[test]
fn g68_without_a_centre_turns_about_the_named_position() {
    // At (10, 0) G68 R90 turns about (10, 0): X20. Y0. goes to (10, 10).
    all_close(&ends(&path("G90 G00 X10. Y0.\nG68 R90.\nG01 X20. Y0. F100.\nM30\n"))[1..], &[[10.0, 10.0, 0.0]]);
}

#[test]
fn modal_groups_read_back() {
    // #4011 G51, #4016 G68, #4017 G16, #4022 G51.1, read through X words.
    let t = path(
        "G51 X0. Y0. P1.\nG68 X0. Y0. R0.\nG51.1 Z0.\nG16\n#1=#4011\n#2=#4016\n#3=#4017\n#4=#4022\nG15 G50.1 Z0. \nG69\nG50\nG00 X#1 Y#2 Z#3 A#4\nG00 X#4011 Y#4016 Z#4017 A#4022\nM30\n",
    );
    let m = &t.moves;
    assert_eq!([m[0].end.x, m[0].end.y, m[0].end.z, m[0].end.a], [51.0, 68.0, 16.0, 51.1]);
    assert_eq!([m[1].end.x, m[1].end.y, m[1].end.z, m[1].end.a], [50.0, 69.0, 15.0, 50.1]);
}

/// A program with every transform, written out as plain moves by the
/// writer and run again: the same motions.
#[test]
fn expanded_program_makes_the_same_motions() {
    let text = "O0001
G21 G90 G17 G54
G00 X0. Y0. Z5.
G52 X10. Y5.
G68 X0. Y0. R30.
G01 Z-1. F200.
X20. Y0.
G03 X20. Y10. I0. J5.
G01 G91 X-5. Y2.
G90
G69
G51 X0. Y0. P1.5
G51.1 Y0.
G02 X10. Y-10. R10.
G50.1 Y0.
G50
G16
G00 X30. Y45.
G91 Y45.
G90 G15
G52 X0. Y0.
G91 G28 Z0.
G90 G30 P2 X0. Y0.
M30
";
    let s = Settings {
        coords: CoordSettings {
            reference_points: [at(-50.0, -60.0, 0.0), Axes::ZERO, Axes::ZERO],
            ..CoordSettings::default()
        },
        ..g54()
    };
    let original = path_with(text, &s);
    for dialect in [Dialect::Fanuc, Dialect::LinuxCnc] {
        let written = program(&original, &WriteOptions { dialect, ..WriteOptions::default() }).unwrap();
        let back = Settings {
            integer_input: if dialect == Dialect::Fanuc { IntegerInput::Increments } else { IntegerInput::Units },
            ..s.clone()
        };
        let again = path_with(&written, &back);
        assert_eq!(original.moves.len(), again.moves.len(), "\n{written}");
        for (k, (a, b)) in original.moves.iter().zip(&again.moves).enumerate() {
            assert_eq!(std::mem::discriminant(&a.kind), std::mem::discriminant(&b.kind), "move {k}\n{written}");
            let (e, f) = (a.end.to_array(), b.end.to_array());
            assert!((0..6).all(|i| (e[i] - f[i]).abs() < 6e-4), "move {k}: {:?} vs {:?}\n{written}", a.end, b.end);
            if let (MoveKind::Arc(x), MoveKind::Arc(y)) = (a.kind, b.kind) {
                assert_eq!(x.ccw, y.ccw, "move {k}\n{written}");
                assert!((0..3).all(|i| (x.center[i] - y.center[i]).abs() < 2e-3), "move {k}\n{written}");
            }
        }
    }
}

/// The interpreter says which ends are where the program put them
/// (`Move::unknown`, X Y Z A B C bits): not an axis never named since the
/// start, not a return to the reference point (G28, G30) or a G53 position
/// the machine file does not give, until an absolute move names the axis;
/// an increment from such a place is still not known. Where the machine
/// file gives the point, the return ends at a known place.
#[test]
fn machine_positions_are_said_not_known() {
    let text = "G21 G90 G54\nG0 X10. Y5.\nG43 H1 Z5.\nG1 Z-3. F100.\nG91 G28 Z0.\nG90 G0 X20.\nG91 G1 Z-1.\n\
                G90 G0 Z5.\nG53 Z0.\nG30 X0.\nG0 X1. Z2.\nG91 G28 Y0.\nG90 G92 Y0.\nG0 X3.\nM30\n";
    let settings = Settings { tool_lengths: [(1, 31.75)].into(), ..Settings::default() };
    let t = path_with(text, &settings);
    let unknown: Vec<u16> = t.moves.iter().map(|m| m.unknown.0 & 0b111).collect();
    // X Y placed, Z not yet; all three; G28 Z; X20 still at Z home; an
    // increment from there; Z5 absolute; G53 Z; G30 X: through X0 (the
    // intermediate point, absolute), then X (and Z still) at the 2nd
    // reference point; X1 Z2; G28 Y, where G92 Y0 then names the place it
    // left Y; X3.
    assert_eq!(unknown, [0b100, 0, 0, 0b100, 0b100, 0b100, 0, 0b100, 0b100, 0b101, 0, 0, 0]);
    assert_eq!(t.moves[3].kind, MoveKind::Home);
    // The reference point and the machine's position given: known.
    let given = Settings { reference_given: [true, true, false, false], ..settings };
    let t = path_with(text, &given);
    let unknown: Vec<u16> = t.moves.iter().map(|m| m.unknown.0 & 0b111).collect();
    assert_eq!(unknown, [0b100, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]);
    // G30 P3: the 3rd reference point, not given.
    let t = path_with("G90 G0 X0 Y0 Z0\nG30 P3 Z0.\nM30\n", &given);
    assert_eq!(t.moves.last().unwrap().unknown.0 & 0b111, 0b100);
}
