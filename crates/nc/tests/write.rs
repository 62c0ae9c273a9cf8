//! The G-code writer: golden programs in every dialect and the rules one
//! line each. The round trip `interp(parse(program(toolpath))) ≈ toolpath`
//! is `write_round_trip.rs`, incremental programs `write_incremental.rs`.

mod common;

use common::writer::{at, body, run, sample, written, Path};
use expect_test::{expect_file, ExpectFile};
use kezuri_geom::{Arc, Axes, AxisSet, MoveKind, Plane, Spindle, Toolpath};
use kezuri_nc::write::{program, Dialect, WriteOptions};
use kezuri_nc::{ErrorKind, Place};

/// A four- and five-axis fragment: A and B turn, C does not.
fn rotary() -> Toolpath {
    let mut p = Path::default();
    p.rapid(0.0, 0.0, 50.0);
    p.push(MoveKind::Rapid, Axes { b: 90.0, ..p.at });
    p.feed(0.0, 0.0, 20.0, 500.0);
    p.push(MoveKind::Feed, Axes { a: -45.5, x: 10.0, ..p.at });
    p.push(MoveKind::Feed, Axes { a: 0.0004, b: 0.0, ..p.at });
    p.path.clone()
}

fn options(dialect: Dialect) -> WriteOptions {
    WriteOptions { dialect, title: Some("kezuri sample".into()), ..WriteOptions::default() }
}

fn golden(path: &Toolpath, options: &WriteOptions, expect: ExpectFile) {
    let text = written(path, options);
    expect.assert_eq(&text);
    let (outcome, messages) = run(&text, options.dialect);
    assert!(messages.is_empty() && outcome.completed, "the golden program does not run cleanly: {messages:#?}");
}

#[test]
fn golden_fanuc() {
    golden(&sample(), &options(Dialect::Fanuc), expect_file!["../testdata/write/sample.fanuc.nc"]);
}

#[test]
fn golden_linuxcnc() {
    golden(&sample(), &options(Dialect::LinuxCnc), expect_file!["../testdata/write/sample.linuxcnc.ngc"]);
}

#[test]
fn golden_grbl() {
    golden(&sample(), &options(Dialect::Grbl), expect_file!["../testdata/write/sample.grbl.nc"]);
}

#[test]
fn golden_fanuc_numbered() {
    let o = WriteOptions { line_numbers: Some(10), program_number: 1234, digits: 2, ..options(Dialect::Fanuc) };
    golden(&sample(), &o, expect_file!["../testdata/write/sample-numbered.fanuc.nc"]);
}

#[test]
fn golden_rotary_fanuc() {
    golden(&rotary(), &WriteOptions::default(), expect_file!["../testdata/write/rotary.fanuc.nc"]);
}

#[test]
fn golden_rotary_linuxcnc() {
    let o = WriteOptions { dialect: Dialect::LinuxCnc, ..WriteOptions::default() };
    golden(&rotary(), &o, expect_file!["../testdata/write/rotary.linuxcnc.ngc"]);
}

fn dialect(dialect: Dialect) -> WriteOptions {
    WriteOptions { dialect, ..WriteOptions::default() }
}

#[test]
fn number_style_per_dialect() {
    let mut p = Path::default();
    p.rapid(10.0, -0.5, 0.0).feed(1.23456, -0.50049, 0.00049, 99.5).feed(-1.0004, -0.5, 0.1, 99.5);
    assert_eq!(body(&p.path, &dialect(Dialect::Fanuc)), ["G00 X10. Y-0.5 Z0.", "G01 X1.235 F99.5", "X-1. Z0.1"]);
    assert_eq!(body(&p.path, &dialect(Dialect::LinuxCnc)), ["G0 X10. Y-0.5 Z0.", "G1 X1.235 F99.5", "X-1. Z0.1"]);
    let o = WriteOptions { digits: 0, ..dialect(Dialect::Fanuc) };
    assert_eq!(body(&p.path, &o), ["G00 X10. Y-1. Z0.", "G01 X1. F100.", "X-1."]);
}

#[test]
fn rounding_to_zero_never_writes_minus_zero() {
    let mut p = Path::default();
    p.rapid(-0.0004, -0.0, -1e-12);
    assert_eq!(body(&p.path, &dialect(Dialect::Fanuc)), ["G00 X0. Y0. Z0."]);
    assert_eq!(body(&p.path, &dialect(Dialect::Grbl)), ["G0 X0. Y0. Z0."]);
}

#[test]
fn modal_words_and_unchanged_coordinates_are_not_repeated() {
    let mut p = Path::default();
    p.spindle(Spindle::Cw, 1000.0).rapid(1.0, 2.0, 3.0).rapid(1.0, 2.0, 1.0);
    p.feed(1.0, 2.0, 0.0, 100.0).feed(5.0, 2.0, 0.0, 100.0).feed(5.0, 2.0000001, 0.0, 100.0).feed(5.0, 6.0, 0.0, 200.0);
    p.arc(Plane::Xy, true, [5.0, 8.0, 0.0], [5.0, 10.0, 0.0]).arc(Plane::Xy, true, [5.0, 8.0, 0.0], [5.0, 6.0, 0.0]);
    p.spindle(Spindle::Cw, 1000.0).rapid(5.0, 6.0, 5.0);
    assert_eq!(
        body(&p.path, &dialect(Dialect::Fanuc)),
        [
            "S1000 M03",
            "G00 X1. Y2. Z3.",
            "Z1.",
            "G01 Z0. F100.",
            "X5.",
            "Y6. F200.",
            "G03 Y10. I0. J2.",
            "Y6. I0. J-2.",
            "G00 Z5."
        ]
    );
}

#[test]
fn first_move_and_the_move_after_a_tool_change_write_every_axis() {
    let mut p = Path::default();
    p.feed(0.0, 0.0, -1.0, 100.0).tool(3).spindle(Spindle::Cw, 5000.0).coolant(false, true);
    p.feed(0.0, 0.0, -1.0, 100.0).feed(1.0, 0.0, -1.0, 100.0);
    assert_eq!(
        body(&p.path, &dialect(Dialect::Fanuc)),
        ["G01 X0. Y0. Z-1. F100.", "T3 M06", "S5000 M03", "M08", "G01 X0. Y0. Z-1. F100.", "X1."]
    );
}

#[test]
fn where_the_position_is_unknown_only_the_named_axes_are_written() {
    // As the interpreter records `G00 X5.` at the start and `Z-1.` after a
    // tool change: the axes the source left alone stay where the control
    // has them.
    let mut p = Path::default();
    p.rapid(5.0, 0.0, 0.0).tool(2).feed(5.0, 0.0, -1.0, 100.0).feed(6.0, 0.0, -1.0, 100.0);
    p.path.moves[0].named = AxisSet(0b001);
    p.path.moves[1].named = AxisSet(0b100);
    p.path.moves[2].named = AxisSet(0b001);
    assert_eq!(body(&p.path, &dialect(Dialect::Fanuc)), ["G00 X5.", "T2 M06", "G01 Z-1. F100.", "X6."]);
}

#[test]
fn tool_change_stops_spindle_and_coolant_and_grbl_pauses() {
    let mut p = Path::default();
    p.tool(1).spindle(Spindle::Cw, 5000.0).coolant(true, true).rapid(0.0, 0.0, 5.0);
    p.tool(2).rapid(0.0, 0.0, 5.0);
    let fanuc = ["T1 M06", "S5000 M03", "M07", "M08", "G00 X0. Y0. Z5.", "M05", "M09", "T2 M06"];
    let fanuc = fanuc.into_iter().chain(["S5000 M03", "M07", "M08", "G00 X0. Y0. Z5."]).collect::<Vec<_>>();
    assert_eq!(body(&p.path, &dialect(Dialect::Fanuc)), fanuc);
    let grbl = body(&p.path, &dialect(Dialect::Grbl));
    assert_eq!(grbl[..3], ["(TOOL CHANGE: PUT IN TOOL 1, THEN RESUME)", "M0", "S5000 M3"]);
    assert_eq!(grbl[6..9], ["M5", "M9", "(TOOL CHANGE: PUT IN TOOL 2, THEN RESUME)"]);
}

#[test]
fn coolant_off_then_on_again_for_a_partial_change() {
    let mut p = Path::default();
    p.coolant(true, true).rapid(0.0, 0.0, 1.0).coolant(false, true).rapid(0.0, 0.0, 2.0);
    assert_eq!(body(&p.path, &dialect(Dialect::LinuxCnc)), ["M7", "M8", "G0 X0. Y0. Z1.", "M9", "M8", "Z2."]);
}

#[test]
fn rapids_never_carry_feed_and_probes_rewrite_the_motion_code() {
    let mut p = Path::default();
    p.feed(0.0, 0.0, 0.0, 300.0).rapid(0.0, 0.0, 5.0).probe(0.0, 0.0, -5.0, 50.0).feed(0.0, 0.0, -4.0, 50.0);
    assert_eq!(
        body(&p.path, &dialect(Dialect::Fanuc)),
        ["G01 X0. Y0. Z0. F300.", "G00 Z5.", "G31 Z-5. F50.", "G01 Z-4."]
    );
    assert_eq!(body(&p.path, &dialect(Dialect::Grbl))[2..], ["G38.2 Z-5. F50.", "G1 Z-4."]);
}

#[test]
fn dwell_is_milliseconds_for_fanuc_and_seconds_otherwise() {
    let mut p = Path::default();
    p.dwell(1.5).dwell(0.0004).dwell(2.0);
    assert_eq!(body(&p.path, &dialect(Dialect::Fanuc)), ["G04 P1500", "G04 P0", "G04 P2000"]);
    assert_eq!(body(&p.path, &dialect(Dialect::LinuxCnc)), ["G4 P1.5", "G4 P0", "G4 P2"]);
}

#[test]
fn arcs_write_plane_changes_and_full_circles_with_ijk() {
    let mut p = Path::default();
    p.rapid(10.0, 0.0, 0.0).feed = 100.0;
    p.arc(Plane::Xy, false, [0.0, 0.0, 0.0], [10.0, 0.0, 0.0]);
    p.arc(Plane::Zx, true, [0.0, 0.0, 0.0], [10.0, -1.0, 0.0]);
    p.arc(Plane::Yz, true, [10.0, -1.0, 5.0], [10.0, -1.0, 10.0]);
    p.arc(Plane::Yz, true, [10.0, -1.0, 5.0], [10.0, -1.0, 0.0]);
    p.arc(Plane::Yz, true, [10.0, -1.0, 5.0], [10.0, -1.0, 10.0]);
    assert_eq!(
        body(&p.path, &dialect(Dialect::Fanuc)),
        [
            "G00 X10. Y0. Z0.",
            "G02 I-10. J0. F100.",
            "G18 G03 Y-1. I-10. K0.",
            "G19 Z10. J0. K5.",
            "Z0. J0. K-5.",
            "Z10. J0. K5."
        ]
    );
}

#[test]
fn an_arc_too_small_for_the_digits_is_a_straight_move() {
    let mut p = Path::default();
    p.rapid(10.0, 0.0, 0.0).feed(10.0, 0.0, 0.0, 100.0);
    let a = 0.00003_f64;
    p.arc(Plane::Xy, true, [0.0, 0.0, 0.0], [10.0 * a.cos(), 10.0 * a.sin(), -1.0]);
    let b = 0.00008_f64;
    p.arc(Plane::Xy, true, [0.0, 0.0, 0.0], [10.0 * b.cos(), 10.0 * b.sin(), -1.0]);
    // The first is a straight move, the second a 0.001 mm arc.
    assert_eq!(body(&p.path, &dialect(Dialect::Fanuc))[1..], ["G01 Z-1. F100.", "G03 Y0.001 I-10. J0."]);
}

#[test]
fn extra_helical_turns_are_full_circles() {
    let mut p = Path::default();
    p.rapid(10.0, 0.0, 0.0);
    p.feed = 100.0;
    let arc = Arc { center: [0.0, 0.0, 0.0], plane: Plane::Xy, ccw: true, turns: 2 };
    p.push(MoveKind::Arc(arc), at(0.0, 10.0, -9.0));
    assert_eq!(
        body(&p.path, &dialect(Dialect::LinuxCnc))[1..],
        ["G3 Z-4. I-10. J0. F100.", "Z-8. I-10. J0.", "X0. Y10. Z-9. I-10. J0."]
    );
}

#[test]
fn an_arc_away_from_the_tool_is_reached_by_a_feed_move() {
    let mut p = Path { feed: 100.0, ..Path::default() };
    p.arc(Plane::Xy, true, [0.0, 0.0, 0.0], [0.0, 5.0, 0.0]);
    p.path.moves[0].start = at(5.0, 0.0, 0.0);
    assert_eq!(body(&p.path, &dialect(Dialect::Grbl)), ["G1 X5. Y0. Z0. F100.", "G3 X0. Y5. I-5. J0."]);
}

#[test]
fn rounded_arc_centre_keeps_the_end_on_the_circle() {
    // Centre and end off the 0.01 grid: the written centre is chosen so that
    // the rounded end lies on the written circle within half a unit.
    let (c, r) = ([0.004, 0.0, 0.0], 10.0_f64);
    let a = 2.0_f64;
    let mut p = Path::default();
    p.rapid(c[0] + r, 0.0, 0.0).feed = 10.0;
    p.arc(Plane::Xy, true, c, [c[0] + r * a.cos(), r * a.sin(), 0.0]);
    let text = written(&p.path, &WriteOptions { digits: 2, ..dialect(Dialect::Fanuc) });
    let (outcome, messages) = run(&text, Dialect::Fanuc);
    assert!(messages.is_empty(), "{messages:#?}");
    let m = outcome.toolpath.moves[1];
    let MoveKind::Arc(arc) = m.kind else { panic!("not an arc: {m:?}") };
    assert!((arc.radius(m.start) - arc.radius(m.end)).abs() <= 0.005, "{text}");
}

#[test]
fn line_numbers_count_by_their_step_and_wrap() {
    let mut p = Path::default();
    for k in 0..4 {
        p.rapid(f64::from(k), 0.0, 0.0);
    }
    let text = written(&p.path, &WriteOptions { line_numbers: Some(40_000), ..dialect(Dialect::Fanuc) });
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[..4], ["%", "O0001", "N40000 G21 G90 G17 G94 G40 G49 G80 G54", "N80000 G00 X0. Y0. Z0."]);
    assert_eq!(lines[4..], ["N40000 X1.", "N80000 X2.", "N40000 X3.", "N80000 M30", "%"]);
}

#[test]
fn framing_per_dialect() {
    let o = WriteOptions { title: Some("a (b) 100% é".into()), program_number: 42, ..dialect(Dialect::Fanuc) };
    assert_eq!(written(&Toolpath::default(), &o), "%\nO0042 (a [b] 100_ _)\nG21 G90 G17 G94 G40 G49 G80 G54\nM30\n%\n");
    let o = WriteOptions { dialect: Dialect::LinuxCnc, ..o };
    assert_eq!(written(&Toolpath::default(), &o), "(a [b] 100_ _)\nG21 G90 G17 G94 G40 G49 G80 G54\nM2\n");
    assert_eq!(written(&Toolpath::default(), &dialect(Dialect::Grbl)), "G21 G90 G17 G94 G40 G49 G80 G54\nM2\n");
}

#[test]
fn errors_name_the_move_and_the_problem() {
    let error = |path: &Toolpath, o: &WriteOptions| match program(path, o) {
        Ok(text) => panic!("expected an error, got\n{text}"),
        Err(e) => (e.clone(), e.to_string()),
    };
    let mut p = Path::default();
    p.rapid(0.0, 0.0, 1.0).rapid(f64::NAN, 0.0, 1.0);
    let (e, text) = error(&p.path, &WriteOptions::default());
    assert!(e.kind == ErrorKind::Number && e.place == Place::Move { index: 1, line: 2 }, "{e:?}");
    assert_eq!(text, "move 2 (line 2): XNaN cannot be written in a program");
    let mut p = Path::default();
    p.feed(0.0, 0.0, 1.0, -5.0);
    assert_eq!(error(&p.path, &WriteOptions::default()).1, "move 1 (line 1): F-5 cannot be written in a program");
    let mut p = Path::default();
    p.dwell(f64::INFINITY);
    assert!(
        matches!(error(&p.path, &WriteOptions::default()).0, e if e.kind == ErrorKind::Number && e.message.starts_with('P'))
    );
    let (e, text) = error(&rotary(), &dialect(Dialect::Grbl));
    assert!(e.kind == ErrorKind::RotaryAxis && e.move_index() == Some(1), "{e:?}");
    assert_eq!(text, "move 2 (line 2): grbl has no rotary axis B, but the toolpath turns it");
    let (_, text) = error(&Toolpath::default(), &WriteOptions { digits: 7, ..WriteOptions::default() });
    assert_eq!(text, "digits 7 is out of range: it must be 0 to 6");
    let (_, text) = error(&Toolpath::default(), &WriteOptions { line_numbers: Some(0), ..WriteOptions::default() });
    assert_eq!(text, "line_numbers 0 is out of range: it must be 1 to 99999");
    let (_, text) = error(&Toolpath::default(), &WriteOptions { program_number: 10_000, ..WriteOptions::default() });
    assert_eq!(text, "program_number 10000 is out of range: it must be 1 to 9999");
}

#[test]
fn grbl_accepts_rotary_axes_that_stay_at_zero() {
    let mut p = Path::default();
    p.push(MoveKind::Rapid, Axes { a: 0.0004, c: -0.0, ..at(1.0, 2.0, 3.0) });
    assert_eq!(body(&p.path, &dialect(Dialect::Grbl)), ["G0 X1. Y2. Z3."]);
}

#[test]
fn dialect_names() {
    for d in Dialect::ALL {
        assert_eq!(d.to_string().parse::<Dialect>(), Ok(d));
    }
    assert_eq!("LinuxCNC".parse::<Dialect>(), Ok(Dialect::LinuxCnc));
    let e = "rml".parse::<Dialect>().map(|_| ()).map_err(|e| e.to_string());
    assert_eq!(e, Err("unknown dialect 'rml': expected fanuc, linuxcnc or grbl".to_string()));
}
