//! The G-code writer: golden programs in every dialect, the rules one line
//! each, and the round trip `interp(parse(program(toolpath))) ≈ toolpath`.

use std::collections::BTreeMap;
use std::f64::consts::TAU;

use expect_test::{expect_file, ExpectFile};
use kezuri_geom::{Arc, Axes, AxisSet, Coolant, Move, MoveKind, Plane, Spindle, Toolpath};
use kezuri_nc::interp::{self, IntegerInput, Outcome, Settings};
use kezuri_nc::write::{program, Dialect, WriteOptions};
use kezuri_nc::{parse, Program, SourceFile, Sources};
use kezuri_nc::{ErrorKind, Place};
use proptest::prelude::*;

/// Builds a chained toolpath: every move starts where the last ended and
/// carries the current feed, spindle, coolant and tool.
#[derive(Default)]
struct Path {
    path: Toolpath,
    at: Axes,
    feed: f64,
    speed: f64,
    spindle: Spindle,
    coolant: Coolant,
    tool: u32,
}

fn at(x: f64, y: f64, z: f64) -> Axes {
    Axes { x, y, z, ..Axes::ZERO }
}

impl Path {
    fn push(&mut self, kind: MoveKind, end: Axes) -> &mut Path {
        let line = self.path.moves.len() as u32 + 1;
        let (feed, speed, spindle, coolant, tool) = (self.feed, self.speed, self.spindle, self.coolant, self.tool);
        self.path.push(Move {
            kind,
            start: self.at,
            end,
            feed,
            speed,
            spindle,
            coolant,
            tool,
            line,
            ..Move::default()
        });
        self.at = end;
        self
    }
    fn rapid(&mut self, x: f64, y: f64, z: f64) -> &mut Path {
        self.push(MoveKind::Rapid, Axes { x, y, z, ..self.at })
    }
    fn feed(&mut self, x: f64, y: f64, z: f64, feed: f64) -> &mut Path {
        self.feed = feed;
        self.push(MoveKind::Feed, Axes { x, y, z, ..self.at })
    }
    fn probe(&mut self, x: f64, y: f64, z: f64, feed: f64) -> &mut Path {
        self.feed = feed;
        self.push(MoveKind::Probe, Axes { x, y, z, ..self.at })
    }
    fn arc(&mut self, plane: Plane, ccw: bool, center: [f64; 3], end: [f64; 3]) -> &mut Path {
        let end = Axes { x: end[0], y: end[1], z: end[2], ..self.at };
        self.push(MoveKind::Arc(Arc { center, plane, ccw, turns: 0 }), end)
    }
    fn dwell(&mut self, seconds: f64) -> &mut Path {
        self.push(MoveKind::Dwell(seconds), self.at)
    }
    fn spindle(&mut self, spindle: Spindle, speed: f64) -> &mut Path {
        self.spindle = spindle;
        self.speed = speed;
        self
    }
    fn coolant(&mut self, mist: bool, flood: bool) -> &mut Path {
        self.coolant = Coolant { mist, flood };
        self
    }
    fn tool(&mut self, tool: u32) -> &mut Path {
        self.tool = tool;
        self
    }
}

/// Rapids, feeds, arcs in all three planes, a helix (full turn and a
/// quarter), a dwell, a probe, tool changes, spindle and coolant.
fn sample() -> Toolpath {
    let mut p = Path::default();
    p.tool(1).spindle(Spindle::Cw, 12000.0).coolant(false, true);
    p.rapid(0.0, 0.0, 5.0).dwell(0.5);
    p.feed(0.0, 0.0, -1.0, 200.0).feed(20.0, 0.0, -1.0, 600.0);
    p.arc(Plane::Xy, true, [20.0, 10.0, -1.0], [30.0, 10.0, -1.0]);
    p.feed(30.0, 20.0, -1.0, 600.0);
    // G18: a half turn in X-Z around (25, -1).
    p.arc(Plane::Zx, false, [25.0, 20.0, -1.0], [20.0, 20.0, -1.0]);
    // G19: a half turn in Y-Z around (25, -1).
    p.arc(Plane::Yz, false, [20.0, 25.0, -1.0], [20.0, 30.0, -1.0]);
    // A full helical turn down 2 mm, then a quarter turn down 0.5 mm.
    p.arc(Plane::Xy, false, [20.0, 35.0, -1.0], [20.0, 30.0, -3.0]);
    p.arc(Plane::Xy, true, [20.0, 35.0, -3.0], [25.0, 35.0, -3.5]);
    p.probe(25.0, 35.0, -10.0, 100.0);
    p.rapid(25.0, 35.0, 10.0);
    p.tool(2).spindle(Spindle::Ccw, 8000.0).coolant(true, true);
    p.rapid(50.0, 50.0, 10.0);
    p.coolant(true, false);
    p.feed(50.0, 50.0, -0.25, 150.0);
    p.feed(50.12345, -0.0004, -0.25, 150.0);
    p.spindle(Spindle::Off, 8000.0).coolant(false, false);
    p.rapid(50.12345, -0.0004, 25.0);
    p.path.clone()
}

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

fn written(path: &Toolpath, options: &WriteOptions) -> String {
    match program(path, options) {
        Ok(text) => text,
        Err(e) => panic!("program() failed: {e}"),
    }
}

/// Parses and runs a written program as the dialect's control reads it.
fn run(text: &str, dialect: Dialect) -> (Outcome, Vec<String>) {
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("written.nc", text));
    let mut program = Program::default();
    let mut messages: Vec<String> = parse(&mut program, file, text).iter().map(|d| d.render(&sources)).collect();
    let integer_input = if dialect == Dialect::Fanuc { IntegerInput::Increments } else { IntegerInput::Units };
    let settings = Settings { integer_input, ..Settings::default() };
    let outcome = interp::run(&mut program, &mut sources, 0, &mut interp::NoLibrary, &settings);
    messages.extend(outcome.diagnostics.iter().map(|d| d.render(&sources)));
    (outcome, messages)
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

/// The program's motion blocks: the lines between the safe start and the end.
fn body(path: &Toolpath, options: &WriteOptions) -> Vec<String> {
    let text = written(path, options);
    let lines: Vec<&str> = text.lines().collect();
    let first = lines.iter().position(|l| l.contains("G21 G90")).map_or(0, |i| i + 1);
    let last = lines.iter().rposition(|l| *l == "M30" || *l == "M2").unwrap_or(lines.len());
    lines[first..last].iter().map(|l| l.to_string()).collect()
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

// ---- the round trip ----

/// One generated step after the first rapid.
#[derive(Clone, Debug)]
enum Step {
    Rapid([f64; 3]),
    Feed([f64; 3], f64),
    Probe([f64; 3], f64),
    Dwell(f64),
    /// Plane, ccw, radius, direction of the centre from the start, sweep
    /// (`None`: a full circle), rise along the normal, feed.
    Arc(Plane, bool, f64, f64, Option<f64>, f64, f64),
}

/// Spindle, coolant and tool before a step.
#[derive(Clone, Debug)]
struct State {
    spindle: Spindle,
    speed: f64,
    coolant: Coolant,
    tool: Option<u32>,
}

fn delta() -> impl Strategy<Value = f64> {
    prop_oneof![1 => Just(0.0), 3 => (0.01f64..80.0, any::<bool>()).prop_map(|(m, neg)| if neg { -m } else { m })]
}

/// A displacement that moves at least one linear axis.
fn displacement() -> impl Strategy<Value = [f64; 3]> {
    [delta(), delta(), delta()].prop_map(|mut d| {
        if d.iter().all(|&v| v == 0.0) {
            d[0] = 1.0;
        }
        d
    })
}

fn feed() -> impl Strategy<Value = f64> {
    prop_oneof![Just(500.0), 1.0f64..5000.0]
}

fn plane() -> impl Strategy<Value = Plane> {
    prop_oneof![Just(Plane::Xy), Just(Plane::Zx), Just(Plane::Yz)]
}

fn step() -> impl Strategy<Value = Step> {
    prop_oneof![
        displacement().prop_map(Step::Rapid),
        (displacement(), feed()).prop_map(|(d, f)| Step::Feed(d, f)),
        (displacement(), feed()).prop_map(|(d, f)| Step::Probe(d, f)),
        (0.0f64..10.0).prop_map(Step::Dwell),
        (
            plane(),
            any::<bool>(),
            1.0f64..60.0,
            0.0..TAU,
            prop_oneof![1 => Just(None), 4 => (0.05..TAU - 0.05).prop_map(Some)],
            prop_oneof![Just(0.0), -5.0f64..5.0],
            feed()
        )
            .prop_map(|(p, ccw, r, dir, sweep, rise, f)| Step::Arc(p, ccw, r, dir, sweep, rise, f)),
    ]
}

fn state() -> impl Strategy<Value = State> {
    let spindle = prop_oneof![Just(Spindle::Off), Just(Spindle::Cw), Just(Spindle::Ccw)];
    (spindle, prop_oneof![Just(10000.0), 0.0f64..30000.0], any::<(bool, bool)>(), proptest::option::of(0u32..4))
        .prop_map(|(spindle, speed, (mist, flood), tool)| State {
            spindle,
            speed,
            coolant: Coolant { mist, flood },
            tool,
        })
}

fn build(first: [f64; 3], steps: &[(Step, State)]) -> Toolpath {
    let mut p = Path::default();
    p.rapid(first[0], first[1], first[2]);
    for (step, state) in steps {
        p.spindle(state.spindle, state.speed).coolant(state.coolant.mist, state.coolant.flood);
        let a = p.at;
        match *step {
            Step::Rapid(d) => {
                // Tool changes come before rapids, as in real programs.
                if let Some(t) = state.tool {
                    p.tool(t);
                }
                p.rapid(a.x + d[0], a.y + d[1], a.z + d[2]);
            }
            Step::Feed(d, f) => {
                p.feed(a.x + d[0], a.y + d[1], a.z + d[2], f);
            }
            Step::Probe(d, f) => {
                p.probe(a.x + d[0], a.y + d[1], a.z + d[2], f);
            }
            Step::Dwell(s) => {
                p.dwell(s);
            }
            Step::Arc(plane, ccw, r, dir, sweep, rise, f) => {
                let (i, j, n) = plane.axes();
                let s = a.xyz();
                let mut center = s;
                center[i] += r * dir.cos();
                center[j] += r * dir.sin();
                let mut end = s;
                if let Some(sweep) = sweep {
                    let angle = dir + std::f64::consts::PI + if ccw { sweep } else { -sweep };
                    end[i] = center[i] + r * angle.cos();
                    end[j] = center[j] + r * angle.sin();
                }
                end[n] += rise;
                p.feed = f;
                p.arc(plane, ccw, center, end);
            }
        }
    }
    p.path.clone()
}

fn kind_name(k: &MoveKind) -> &'static str {
    match k {
        MoveKind::Rapid => "rapid",
        MoveKind::Home => "home",
        MoveKind::Machine => "machine",
        MoveKind::Feed => "feed",
        MoveKind::Probe => "probe",
        MoveKind::Dwell(_) => "dwell",
        MoveKind::Arc(a) if a.ccw => "ccw",
        MoveKind::Arc(_) => "cw",
    }
}

/// Compares the run of the written program with the toolpath.
fn same_motion(want: &Toolpath, got: &Toolpath, digits: u8, dialect: Dialect) -> Result<(), String> {
    let unit = 10f64.powi(-i32::from(digits));
    if want.moves.len() != got.moves.len() {
        return Err(format!("{} moves written, {} read back", want.moves.len(), got.moves.len()));
    }
    let near = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol * (1.0 + 1e-9) + 1e-9;
    for (k, (w, g)) in want.moves.iter().zip(&got.moves).enumerate() {
        let fail = |what: &str| Err(format!("move {k}: {what}\n want {w:?}\n got  {g:?}"));
        if kind_name(&w.kind) != kind_name(&g.kind) {
            return fail("kind");
        }
        let (we, ge) = (w.end.to_array(), g.end.to_array());
        if (0..6).any(|i| !near(we[i], ge[i], unit / 2.0)) {
            return fail("end point");
        }
        match (w.kind, g.kind) {
            (MoveKind::Arc(wa), MoveKind::Arc(ga)) => {
                let (i, j, _) = wa.plane.axes();
                if wa.plane != ga.plane {
                    return fail("plane");
                }
                if !near(wa.center[i], ga.center[i], 1.5 * unit) || !near(wa.center[j], ga.center[j], 1.5 * unit) {
                    return fail("centre");
                }
            }
            (MoveKind::Dwell(ws), MoveKind::Dwell(gs)) if !near(ws, gs, 0.0005) => return fail("dwell time"),
            _ => {}
        }
        if !w.is_rapid() && !matches!(w.kind, MoveKind::Dwell(_)) && !near(w.feed, g.feed, unit / 2.0) {
            return fail("feed");
        }
        if w.spindle != g.spindle || w.coolant != g.coolant || !near(w.speed, g.speed, unit / 2.0) {
            return fail("spindle or coolant");
        }
        if dialect != Dialect::Grbl && w.tool != g.tool {
            return fail("tool");
        }
    }
    Ok(())
}

fn point() -> impl Strategy<Value = [f64; 3]> {
    [-200.0f64..200.0, -200.0f64..200.0, -50.0f64..50.0]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn round_trip_through_parse_and_interp(
        first in point(),
        steps in proptest::collection::vec((step(), state()), 0..40),
        digits in 2u8..=5,
        numbered in proptest::option::of(1u32..100),
    ) {
        let path = build(first, &steps);
        for d in Dialect::ALL {
            let options = WriteOptions { dialect: d, digits, line_numbers: numbered, ..WriteOptions::default() };
            let text = program(&path, &options).map_err(|e| TestCaseError::fail(e.to_string()))?;
            let (outcome, messages) = run(&text, d);
            prop_assert!(outcome.completed, "{d}: the run did not complete: {messages:#?}\n{text}");
            let decimal: Vec<&String> = messages.iter().filter(|m| m.contains("decimal point")).collect();
            prop_assert!(decimal.is_empty(), "{d}: {decimal:#?}\n{text}");
            let errors: Vec<&String> = messages.iter().filter(|m| m.contains(": error:")).collect();
            prop_assert!(errors.is_empty(), "{d}: {errors:#?}\n{text}");
            if let Err(e) = same_motion(&path, &outcome.toolpath, digits, d) {
                return Err(TestCaseError::fail(format!("{d}: {e}\n{text}")));
            }
        }
    }
}

// ---- incremental programs ----

fn incremental(dialect: Dialect) -> WriteOptions {
    WriteOptions { dialect, incremental: true, ..WriteOptions::default() }
}

/// Parses and runs a written program with `settings`, which must run
/// cleanly.
fn run_clean(text: &str, dialect: Dialect, settings: &Settings) -> Toolpath {
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("written.nc", text));
    let mut program = Program::default();
    let mut errors: Vec<String> = parse(&mut program, file, text).iter().map(|d| d.render(&sources)).collect();
    let integer_input = if dialect == Dialect::Fanuc { IntegerInput::Increments } else { IntegerInput::Units };
    let settings = Settings { integer_input, ..settings.clone() };
    let outcome = interp::run(&mut program, &mut sources, 0, &mut interp::NoLibrary, &settings);
    errors.extend(outcome.diagnostics.iter().filter(|d| d.is_error()).map(|d| d.render(&sources)));
    assert!(outcome.completed && errors.is_empty(), "{errors:#?}\n{text}");
    outcome.toolpath
}

/// A position in units of the last written digit (of an inch with
/// `inch`): what the program wrote, whatever the float noise of reading it.
fn counts(p: Axes, o: &WriteOptions) -> [i64; 6] {
    let scale = 10f64.powi(i32::from(o.digits));
    let v = p.to_array();
    std::array::from_fn(|k| (v[k] * scale / if k < 3 && o.inch { 25.4 } else { 1.0 }).round() as i64)
}

/// Writes `path` absolute and incremental with `o`, runs both and checks
/// that they make the same moves to the same end points, to the last
/// written digit; returns the incremental program.
fn same_as_absolute(path: &Toolpath, o: &WriteOptions, settings: &Settings) -> String {
    let absolute = written(path, &WriteOptions { incremental: false, ..o.clone() });
    let relative = written(path, &WriteOptions { incremental: true, ..o.clone() });
    assert!(relative.contains("G91"), "{relative}");
    let (a, r) = (run_clean(&absolute, o.dialect, settings), run_clean(&relative, o.dialect, settings));
    assert_eq!(a.moves.len(), r.moves.len(), "{absolute}\n{relative}");
    for (k, (ma, mr)) in a.moves.iter().zip(&r.moves).enumerate() {
        assert_eq!(kind_name(&ma.kind), kind_name(&mr.kind), "move {k}\n{relative}");
        assert_eq!(counts(ma.end, o), counts(mr.end, o), "move {k}: {ma:?}\n{mr:?}\n{absolute}\n{relative}");
        if let (MoveKind::Arc(aa), MoveKind::Arc(ar)) = (ma.kind, mr.kind) {
            assert_eq!(aa.plane, ar.plane, "move {k}\n{relative}");
            let centre = |c: [f64; 3]| counts(Axes { x: c[0], y: c[1], z: c[2], ..Axes::ZERO }, o);
            assert_eq!(centre(aa.center), centre(ar.center), "move {k}\n{relative}");
        }
        assert!((ma.feed - mr.feed).abs() < 1e-9, "move {k}\n{relative}");
    }
    relative
}

#[test]
fn incremental_programs_make_the_same_motions_in_every_dialect() {
    // Rapids, feeds, arcs in the three planes, a helix, a probe, a dwell and
    // tool changes, in mm and in inches.
    let path = sample();
    for d in Dialect::ALL {
        for inch in [false, true] {
            let o = WriteOptions { inch, digits: if inch { 4 } else { 3 }, ..incremental(d) };
            let text = same_as_absolute(&path, &o, &Settings::default());
            // And the same as the toolpath, to half a unit.
            let (outcome, messages) = run(&text, d);
            let errors: Vec<&String> = messages.iter().filter(|m| m.contains(": error:")).collect();
            assert!(outcome.completed && errors.is_empty(), "{errors:#?}\n{text}");
            if !inch {
                if let Err(e) = same_motion(&path, &outcome.toolpath, o.digits, d) {
                    panic!("{d}: {e}\n{text}");
                }
            }
        }
    }
}

#[test]
fn incremental_starts_after_the_first_complete_positioning() {
    let mut p = Path::default();
    p.rapid(1.0, 2.0, 5.0).feed(1.0, 2.0, -1.0, 100.0).feed(11.0, 2.0, -1.0, 100.0);
    p.arc(Plane::Xy, true, [11.0, 7.0, -1.0], [16.0, 7.0, -1.0]);
    p.arc(Plane::Xy, false, [11.0, 7.0, -1.0], [16.0, 7.0, -1.0]);
    p.feed(16.0004, 7.0004, -1.0, 100.0).feed(16.0008, 7.0008, -1.0, 100.0).rapid(16.0008, 7.0008, 5.0);
    assert_eq!(
        body(&p.path, &incremental(Dialect::Fanuc)),
        [
            "G00 X1. Y2. Z5.",
            "G91 G01 Z-6. F100.",
            "X10.",
            "G03 X5. Y5. I0. J5.",
            "G02 I-5. J0.",
            // 16.0008 is written 16.001: the increments are those of the
            // rounded positions.
            "G01 X0.001 Y0.001",
            "G00 Z6.",
            "G90"
        ]
    );
    let o = WriteOptions { inch: true, digits: 4, ..incremental(Dialect::LinuxCnc) };
    let mut p = Path::default();
    p.rapid(25.4, 0.0, 2.54).feed(25.4, 0.0, -0.0254, 100.0).feed(-1.27, 12.7, -0.0254, 100.0);
    let text = written(&p.path, &o);
    assert!(text.contains("G0 X1. Y0. Z0.1\nG91 G1 Z-0.101 F3.937\nX-1.05 Y0.5\nG90\nM2\n"), "{text}");
}

#[test]
fn incremental_programs_end_in_g90() {
    let mut p = Path::default();
    p.rapid(0.0, 0.0, 5.0).feed(0.0, 0.0, 0.0, 100.0).rapid(0.0, 0.0, 5.0);
    for d in Dialect::ALL {
        let text = written(&p.path, &incremental(d));
        let end = match d {
            Dialect::Fanuc => "G00 Z5.\nG90\nM30\n%\n",
            Dialect::LinuxCnc | Dialect::Grbl => "G0 Z5.\nG90\nM2\n",
        };
        assert!(text.contains("G91") && text.ends_with(end), "{d}:\n{text}");
    }
    // A program that never reaches G91 writes no G90 at the end either.
    let mut p = Path::default();
    p.rapid(0.0, 0.0, 5.0);
    assert_eq!(body(&p.path, &incremental(Dialect::Fanuc)), ["G00 X0. Y0. Z5."]);
    let o = WriteOptions { line_numbers: Some(10), ..incremental(Dialect::Fanuc) };
    let text = written(&p.path, &o);
    assert!(text.ends_with("N20 G00 X0. Y0. Z5.\nN30 M30\n%\n"), "{text}");
}

#[test]
fn incremental_tool_changes_run_in_g90_and_position_absolute_after() {
    let mut p = Path::default();
    p.tool(1).spindle(Spindle::Cw, 5000.0).rapid(0.0, 0.0, 5.0).feed(0.0, 0.0, 0.0, 100.0);
    p.tool(2).rapid(10.0, 0.0, 5.0).feed(10.0, 0.0, 0.0, 100.0).feed(12.0, 0.0, 0.0, 100.0);
    assert_eq!(
        body(&p.path, &incremental(Dialect::Fanuc)),
        [
            "T1 M06",
            "S5000 M03",
            "G90 G00 X0. Y0. Z5.",
            "G91 G01 Z-5. F100.",
            "G90",
            "M05",
            "T2 M06",
            "S5000 M03",
            "G90 G00 X10. Y0. Z5.",
            "G91 G01 Z-5. F100.",
            "X2.",
            "G90"
        ]
    );
}

/// A program with every kind of frame change and absolute-only move: tool
/// length offsets, work offsets changed by the program, G92, returns to the
/// reference point and G53 (as in `tests/expand.rs`).
const FRAMES: &str = "O0001
G21 G90 G94 G17 G54
T1 M06
G43 H1 Z50.
G00 X10. Y10.
G01 Z-1. F100.
X20.
G02 X30. R5.
G03 X20. I-5.
G31 Z-5.
G00 Z5.
G55
G00 X0 Y0
G01 Z-2.
X5. Y3.
#5221=5.
#5222=5.
#5223=-90.
G54 G00 X1. Y1.
G92 X0 Y0
G00 X2.
G91 G28 Z0.
G90
G00 X5.
G01 Z-3. F200.
X7.
T2 M06
G44 H2 Z20.
G01 X3. Y3.
X4.
G53 G00 Z-10.
G00 X1. Z2.
Y5.
G49
G28 X0 Y0
M30
";

#[test]
fn incremental_frames_homes_and_machine_moves_stay_absolute() {
    let mut work_offsets = [Axes::ZERO; 6];
    work_offsets[0] = at(10.0, 20.0, -100.0);
    work_offsets[1] = at(200.0, 20.0, -100.0);
    let settings = Settings {
        tool_lengths: BTreeMap::from([(1, 100.0), (2, 80.0)]),
        work_offsets,
        home: at(-500.0, -400.0, 0.0),
        ..Settings::default()
    };
    let original = run_clean(FRAMES, Dialect::Fanuc, &settings);
    for d in [Dialect::Fanuc, Dialect::LinuxCnc] {
        for inch in [false, true] {
            let o = WriteOptions { inch, digits: if inch { 4 } else { 3 }, ..incremental(d) };
            let text = same_as_absolute(&original, &o, &settings);
            if inch {
                continue;
            }
            let lines: Vec<&str> = text.lines().collect();
            let motion = if d == Dialect::Fanuc { "G00" } else { "G0" };
            // The offsets the program set (#5221…) as G10 in G90, G53 in G90;
            // the return to the reference point in G91.
            for expected in ["G21 G90 G10 L2 P1 X5.", &format!("G90 G53 {motion} Z-10."), "G91 G28 Z0."] {
                assert!(lines.contains(&expected), "{d}: no '{expected}' in\n{text}");
            }
            let g10 = lines.iter().position(|l| l.contains("G10 L2")).unwrap();
            assert!(lines[..g10].iter().any(|l| l.contains("G91")), "{d}: G91 before the frame change\n{text}");
            let g28 = lines.iter().position(|l| l.contains("G28 Z0.")).unwrap();
            // After the return, absolute until X, Y and Z are written again.
            assert!(lines[g28 + 1].starts_with("G90 "), "{d}:\n{text}");
            assert!(lines[g28 + 1..].iter().any(|l| l.starts_with("G91 ")), "{d}: G91 again after G28\n{text}");
        }
    }
}

/// A path of many small moves: feeds (and now and then a rapid or an arc)
/// of a few µm to a few tenths of a mm, whose exact positions fall between
/// the written digits.
fn small_moves() -> impl Strategy<Value = Vec<(u8, [f64; 3])>> {
    let d = || prop_oneof![1 => Just(0.0), 4 => -0.3f64..0.3, 1 => -0.002f64..0.002];
    proptest::collection::vec((0u8..10, [d(), d(), d()]), 100..600)
}

fn small_path(first: [f64; 3], steps: &[(u8, [f64; 3])]) -> Toolpath {
    let mut p = Path::default();
    p.rapid(first[0], first[1], first[2]);
    for &(kind, d) in steps {
        let a = p.at;
        match kind {
            0 => {
                p.rapid(a.x + d[0], a.y + d[1], a.z + d[2]);
            }
            1 if d[0].hypot(d[1]) > 0.01 => {
                // A half circle in XY over the chord (d[0], d[1]), rising d[2].
                let c = [a.x + d[0] / 2.0, a.y + d[1] / 2.0, a.z];
                p.feed = 1000.0;
                p.arc(Plane::Xy, d[2] > 0.0, c, [a.x + d[0], a.y + d[1], a.z + d[2]]);
            }
            _ => {
                p.feed(a.x + d[0], a.y + d[1], a.z + d[2], 1000.0);
            }
        }
    }
    p.path.clone()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn incremental_programs_do_not_drift(
        first in point(),
        steps in small_moves(),
        digits in 2u8..=5,
        inch in any::<bool>(),
        dialect in prop_oneof![Just(Dialect::Fanuc), Just(Dialect::LinuxCnc), Just(Dialect::Grbl)],
    ) {
        let path = small_path(first, &steps);
        // Arcs of a few tenths of a mm need the digits: 0.01 inch is too
        // coarse for the control's radius check.
        let digits = if inch { digits.max(4) } else { digits };
        let o = WriteOptions { dialect, digits, inch, incremental: true, ..WriteOptions::default() };
        let absolute = program(&path, &WriteOptions { incremental: false, ..o.clone() })
            .map_err(|e| TestCaseError::fail(e.to_string()))?;
        let relative = program(&path, &o).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let (a, r) = (run(&absolute, dialect), run(&relative, dialect));
        let errors: Vec<&String> = a.1.iter().chain(&r.1).filter(|m| m.contains(": error:")).collect();
        prop_assert!(a.0.completed && r.0.completed && errors.is_empty(), "{errors:#?}\n{relative}");
        prop_assert_eq!(a.0.toolpath.moves.len(), r.0.toolpath.moves.len());
        // Every end point, and so the last, to the last digit.
        for (ma, mr) in a.0.toolpath.moves.iter().zip(&r.0.toolpath.moves) {
            prop_assert_eq!(counts(ma.end, &o), counts(mr.end, &o), "{:?}\n{:?}", ma, mr);
        }
        let last = |t: &Toolpath| t.moves.last().map(|m| counts(m.end, &o));
        prop_assert_eq!(last(&a.0.toolpath), last(&r.0.toolpath));
        // And the last position the toolpath asks for, rounded once.
        let want = counts(path.moves.last().unwrap().end, &o);
        let got = last(&r.0.toolpath).unwrap();
        prop_assert!((0..3).all(|k| (want[k] - got[k]).abs() <= 1), "{want:?} {got:?}");
    }
}
