//! Where Fanuc, Haas and LinuxCNC differ: a G28 without axis words, and the
//! forms of G10 (docs/gcode-support.md). Expected positions worked out by
//! hand in the comments.

use std::collections::BTreeMap;

use kezuri_geom::{Axes, MoveKind, Toolpath};
use kezuri_nc::interp::{Control, CoordSettings, IntegerInput, Outcome, Settings};

mod common;

fn run_with(text: &str, settings: &Settings) -> Outcome {
    common::run("t.nc", text, settings).outcome
}

fn path(text: &str, settings: &Settings) -> Toolpath {
    common::run("t.nc", text, settings).path()
}

fn error(text: &str, settings: &Settings) -> String {
    common::run("t.nc", text, settings).message()
}

fn control(control: Control) -> Settings {
    let integer_input = if control == Control::LinuxCnc { IntegerInput::Units } else { IntegerInput::Increments };
    Settings {
        coords: CoordSettings { control, ..CoordSettings::default() },
        integer_input,
        home: Axes { x: -400.0, y: -300.0, z: 0.0, ..Axes::ZERO },
        tool_lengths: BTreeMap::from([(1, 100.0)]),
        ..Settings::default()
    }
}

fn end(t: &Toolpath) -> [f64; 3] {
    t.moves.last().unwrap().end.xyz()
}

const BARE_G28: &str = "G90 G54 G00 X10. Y20. Z30.\nG43 H1 Z30.\nG28\nM30\n";

#[test]
fn a_bare_g28_moves_nothing_on_fanuc_with_a_warning() {
    let outcome = run_with(BARE_G28, &control(Control::Fanuc));
    assert!(outcome.completed);
    assert!(!outcome.toolpath.moves.iter().any(|m| m.kind == MoveKind::Home));
    assert!(outcome.diagnostics.iter().any(|d| d.message.contains("G28 without axis words moves nothing")));
}

#[test]
fn a_bare_g28_returns_every_axis_on_linuxcnc_with_the_length_offset_kept() {
    // The gauge line goes to the reference point: the tip is 100 below it.
    let t = path(BARE_G28, &control(Control::LinuxCnc));
    assert_eq!(t.moves.last().unwrap().kind, MoveKind::Home);
    assert_eq!(end(&t), [-400.0, -300.0, -100.0]);
}

#[test]
fn a_bare_g28_on_haas_returns_every_axis_and_cancels_the_length_offset() {
    // G28 cancels G43 on a Haas: the tip goes to the reference point itself.
    let t = path(BARE_G28, &control(Control::Haas));
    assert_eq!(end(&t), [-400.0, -300.0, 0.0]);
    assert!(t.frame(t.moves.last().unwrap()).length.is_none());
}

#[test]
fn g10_l10_to_l13_set_geometry_and_wear_added() {
    // H1: geometry 100 (tool table) → L10 R50. → 50, wear L11 R0.2 → 50.2;
    // G43 H1 Z10. puts the tip at Z 10 with the gauge line at 60.2 (#5023).
    let text = "G10 L10 P1 R50.\nG10 L11 P1 R0.2\nG10 L12 P2 R3.\nG10 L13 P2 R-0.05\nG90 G00 X0 Y0\nG43 H1 Z10.\n\
                G00 X#5023 Y#2202 Z#13002\nG00 X#10001 Y#11001 Z#12002\nM30\n";
    let t = path(text, &control(Control::Fanuc));
    let m = &t.moves;
    // #2202 and #13002: D2's geometry 3 (positions are the tool tip's).
    assert_eq!(m[m.len() - 2].end.xyz(), [60.2, 3.0, 3.0]);
    // #10001 H1 wear 0.2, #11001 H1 geometry 50, #12002 D2 wear -0.05.
    let last = m.last().unwrap().end;
    assert!((last.x - 0.2).abs() < 1e-12 && last.y == 50.0 && last.z == -0.05, "{last:?}");
}

#[test]
fn g10_l1_on_linuxcnc_sets_the_tool_table() {
    // Tool 3: length 25, radius 4; G43 H3 Z0 puts the gauge line at 25.
    let t = path("G10 L1 P3 Z25 R4\nG43 H3 Z0\nG0 X#5023\nM2\n", &control(Control::LinuxCnc));
    assert_eq!(t.moves.last().unwrap().end.x, 25.0);
}

#[test]
fn g10_l20_on_linuxcnc_makes_the_current_position_the_given_one() {
    // At machine X 30 (G54 at 0), G10 L20 P1 X10 puts G54's zero at X 20:
    // G0 X0 goes to machine X 20.
    let t = path("G90 G54 G0 X30 Y0 Z0\nG10 L20 P1 X10\nG0 X0\nM2\n", &control(Control::LinuxCnc));
    assert_eq!(end(&t)[0], 20.0);
    // On LinuxCNC, L2 P0 is the current system (Fanuc: the external offset).
    let t = path("G90 G55 G0 X0 Y0 Z0\nG10 L2 P0 X5\nG0 X0\nM2\n", &control(Control::LinuxCnc));
    assert_eq!(end(&t)[0], 5.0);
}

#[test]
fn g10_forms_a_control_lacks_are_located_errors() {
    assert!(error("G10 L20 P0 X10.\nM30\n", &control(Control::Fanuc)).contains("P1 to P99"));
    assert!(error("G10 L12 R1.\nM30\n", &control(Control::Fanuc)).contains("G10 L12 needs the offset number"));
    assert!(error("G10 L11 P1\nM30\n", &control(Control::Fanuc)).contains("needs the offset value in R"));
    assert!(error("G10 L5 P1 R1.\nM30\n", &control(Control::Fanuc)).contains("not supported"));
}

#[test]
fn linuxcnc_rules_where_they_differ_from_fanuc() {
    let lc = control(Control::LinuxCnc);
    // G30 without axis words: every axis to the G30 position (at 0 here; the
    // gauge line there, the tip 100 below with H1).
    let t = path("G0 X10 Y20 Z30\nG43 H1\nG30\nM2\n", &lc);
    assert_eq!(end(&t), [0.0, 0.0, -100.0]);
    // G43 without H takes the tool in the spindle: T1 M6 G43 is H1 (length
    // 100). Applying it moves nothing: the spindle stays at Z0, the tip is
    // 100 below, where a move without Z leaves it.
    let t = path("T1 M6\nG43\nG0 X1\nM2\n", &lc);
    assert_eq!(end(&t), [1.0, 0.0, -100.0]);
    // G10 L2 ignores G91 on LinuxCNC: G54's X is 5, not 5 + 5.
    let t = path("G10 L2 P1 X5\nG91 G10 L2 P1 X5\nG90 G0 X0\nM2\n", &lc);
    assert_eq!(end(&t)[0], 5.0);
    // G2 P3: three full turns plus the arc: the helix drops 3 in Z over all.
    let t = path("G0 X10 Y0 Z0\nG2 X10 Y0 Z-3 I-10 J0 P3 F100\nM2\n", &lc);
    let last = t.moves.last().unwrap();
    match last.kind {
        MoveKind::Arc(a) => assert_eq!(a.turns, 2),
        k => panic!("{k:?}"),
    }
    assert!((last.length() - (3.0 * std::f64::consts::TAU * 10.0).hypot(3.0)).abs() < 1e-9);
    // G98 from an initial level below R returns to R on LinuxCNC.
    let t = path("G0 X0 Y0 Z1\nG98 G81 X1 Y1 Z-2 R3 F100\nG80\nM2\n", &lc);
    assert_eq!(t.moves.last().unwrap().end.z, 3.0);
    // G76 is LinuxCNC's lathe threading cycle: P is its pitch.
    assert!(error("G76 X1 Z-2 R1 Q1 F1\nM2\n", &lc).contains("P word missing with G76"));
}

#[test]
fn m_codes_keep_their_own_words() {
    let t = path("G90 G00 X0 Y0 Z5.\nM19 R90.\nM62 P1\nG01 X1. M08 F100.\nM30\n", &control(Control::Fanuc));
    let texts: Vec<&str> = t.kept.iter().map(|k| k.text.as_str()).collect();
    assert_eq!(texts, ["M19 R90.", "M62 P1"]);
}

#[test]
fn shop_macro_system_variables_and_codes() {
    // #3004 (feed hold off) and #3901 (parts count) keep what is written;
    // #3006 stops for the operator, kept as M00 with its message; #3011 is a
    // fixed date; G09, G97 and Haas G103 change nothing of the path.
    let text = "G97 S1000 M03\n#3004=2\n#3901=#3901+1\nG103 P1\nG09 G01 X#3004 Y#3901 F100.\n#3006=1(LOAD THE NEXT PART)\nG01 Z[#3011/10000000]\nM30\n";
    let t = path(text, &control(Control::Fanuc));
    assert_eq!(t.moves[0].end.xyz(), [2.0, 1.0, 0.0]);
    assert_eq!(t.moves[1].end.z, 2.0000101);
    let texts: Vec<&str> = t.kept.iter().map(|k| k.text.as_str()).collect();
    assert_eq!(texts, ["G103 P1", "M00 (LOAD THE NEXT PART)"]);
    assert!(error("G96 S200\nM30\n", &control(Control::Fanuc)).contains("G96"));
}

fn extra_offsets() -> Settings {
    let mut s = control(Control::Fanuc);
    s.extra_work_offsets =
        BTreeMap::from([(1, Axes { x: 100.0, ..Axes::ZERO }), (12, Axes { y: 200.0, ..Axes::ZERO })]);
    s
}

#[test]
fn additional_work_offsets_g54_1_g154_and_g110() {
    // G54.1 P1 at X 100, G154 P12 at Y 200, G110 (= G154 P1), #7001 (P1's X)
    // and #14221 (P12's X) read back; G10 L20 P2 sets P2.
    let text = "G90 G54.1 P1 G00 X1. Y0 Z0\nG154 P12 X0 Y1.\nG110 X2.\nG10 L20 P2 X-5.\nG54.1 P2 X0\nG00 X#7001 Y#14221 Z#14222\nM30\n";
    let t = path(text, &extra_offsets());
    let ends: Vec<[f64; 3]> = t.moves.iter().map(|m| m.end.xyz()).collect();
    assert_eq!(ends[..4], [[101.0, 0.0, 0.0], [0.0, 201.0, 0.0], [102.0, 201.0, 0.0], [-5.0, 201.0, 0.0]]);
    // In G54.1 P2 (X -5): X#7001 = 100 → machine 95; Y#14221 = 0, Z#14222 = 200.
    assert_eq!(ends[4], [95.0, 0.0, 200.0]);
    assert!(error("G54.1 X0\nM30\n", &extra_offsets()).contains("P1 to P99"));
}

#[test]
fn additional_work_offsets_are_written_back() {
    let text = "G90 G54.1 P1 G00 X1. Y0 Z0\nG01 X5. F100.\nM30\n";
    let t = path(text, &extra_offsets());
    let fanuc = kezuri_nc::write::program(&t, &Default::default()).unwrap();
    assert!(fanuc.contains("G54.1 P1\n"), "{fanuc}");
    let lc = kezuri_nc::write::WriteOptions { dialect: kezuri_nc::write::Dialect::LinuxCnc, ..Default::default() };
    assert!(kezuri_nc::write::program(&t, &lc).unwrap().contains("G59.1"));
    let grbl = kezuri_nc::write::WriteOptions { dialect: kezuri_nc::write::Dialect::Grbl, ..Default::default() };
    assert!(kezuri_nc::write::program(&t, &grbl).is_err());
}

#[test]
fn inverse_time_feed_is_per_move() {
    // G93 F2.: each move takes half a minute: 10 mm at 20 mm/min, a 90° turn
    // of A at 180 °/min; a move without F is refused.
    let t = path("G90 G00 X0 Y0 Z0 A0\nG93 G01 X10. F2.\nA90. F2.\nG94 G01 X0 F500.\nM30\n", &control(Control::Fanuc));
    let feeds: Vec<f64> = t.moves.iter().skip(1).map(|m| m.feed).collect();
    assert_eq!(feeds, [20.0, 180.0, 500.0]);
    assert!(error("G93 G01 X10. F2.\nX20.\nM30\n", &control(Control::Fanuc)).contains("inverse time"));
    // #4130: the P of the additional work offset in force.
    let t = path("G54.1 P7\nG00 X#4130\nG54\nX#4130\nM30\n", &extra_offsets());
    assert_eq!(t.moves[0].end.x, 7.0);
    assert_eq!(t.moves[1].end.x, 0.0);
}

#[test]
fn a_bare_return_is_written_with_its_axes_and_g92_reaches_grbl() {
    use kezuri_nc::write::{program, Dialect, WriteOptions};
    // LinuxCNC's bare G30 goes to the G30 point: written as G30, with X Y Z
    // (no rotary axis the program never turned).
    let t = path("G0 X10 Y20 Z30\nG30\nM2\n", &control(Control::LinuxCnc));
    let lc = program(&t, &WriteOptions { dialect: Dialect::LinuxCnc, ..WriteOptions::default() }).unwrap();
    assert!(lc.contains("G91 G30 X0. Y0. Z0.\n") && !lc.contains("G28"), "{lc}");
    let t = path("G0 X10 Y20 Z30\nG28\nM2\n", &control(Control::Haas));
    let fanuc = program(&t, &WriteOptions::default()).unwrap();
    assert!(fanuc.contains("G91 G28 X0. Y0. Z0.\n"), "{fanuc}");
    // GRBL has G92 and G92.1.
    let t = path("G0 X10 Y0 Z0\nG92 X0\nG1 X5 F100\nG92.1\nM2\n", &control(Control::LinuxCnc));
    let grbl = program(&t, &WriteOptions { dialect: Dialect::Grbl, ..WriteOptions::default() }).unwrap();
    assert!(grbl.contains("G92 X0.") && grbl.contains("G92.1"), "{grbl}");
}

#[test]
fn linuxcnc_rises_to_r_before_the_hole_when_below_it() {
    // From Z1 below R5: up to R first, then across to the hole (LinuxCNC's
    // convert_cycle_xy); Fanuc positions first.
    let text = "G0 X0 Y0 Z1\nG98 G81 X50 Y0 Z-5 R5 F100\nG80\nM2\n";
    let t = path(text, &control(Control::LinuxCnc));
    let ends: Vec<[f64; 3]> = t.moves.iter().map(|m| m.end.xyz()).collect();
    assert_eq!(ends[1..3], [[0.0, 0.0, 5.0], [50.0, 0.0, 5.0]]);
}

#[test]
fn linuxcnc_g10_reaches_g59_1_to_g59_3() {
    // G10 L2 P7 sets G59.1; G10 L20 P8 sets G59.2 so that X reads 5 here.
    let t = path("G10 L2 P7 X100\nG59.1 G0 X0 Y0 Z0\nG10 L20 P8 X5\nG59.2 G0 X5\nM2\n", &control(Control::LinuxCnc));
    let ends: Vec<f64> = t.moves.iter().map(|m| m.end.x).collect();
    assert_eq!(ends, [100.0, 100.0]);
}

#[test]
fn stops_keep_their_words_and_their_message_reaches_grbl() {
    use kezuri_nc::write::{program, Dialect, WriteOptions};
    let t = path("G0 X1 Y1 Z1\nM00 P5\n#3006=1(CHECK THE CLAMPS)\nG1 X2 F100\nM2\n", &control(Control::LinuxCnc));
    let texts: Vec<&str> = t.kept.iter().map(|k| k.text.as_str()).collect();
    assert_eq!(texts, ["M00 P5", "M00 (CHECK THE CLAMPS)"]);
    let grbl = program(&t, &WriteOptions { dialect: Dialect::Grbl, ..WriteOptions::default() });
    assert!(grbl.is_err(), "GRBL has no M00 P5");
    let t = path("G0 X1 Y1 Z1\n#3006=1(CHECK THE CLAMPS)\nG1 X2 F100\nM2\n", &control(Control::LinuxCnc));
    let grbl = program(&t, &WriteOptions { dialect: Dialect::Grbl, ..WriteOptions::default() }).unwrap();
    assert!(grbl.contains("M00 (CHECK THE CLAMPS)"), "{grbl}");
    // An offset the program wrote and reads back is the program's own.
    let outcome = common::run("t.nc", "#7001=5.\nG0 X#7001\nM30\n", &control(Control::Fanuc)).completed();
    assert!(outcome.model_reads.is_empty(), "{:?}", outcome.model_reads);
}

#[test]
fn a_skip_move_in_inverse_time_is_refused() {
    // It had the feed 0, silently.
    assert!(error("G93 G31 X10. F2.\nM30\n", &control(Control::Fanuc)).contains("G94 first"));
}
