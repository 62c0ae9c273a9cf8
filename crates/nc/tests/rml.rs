//! RML-1: the relief paper's listing read with units, every command, located
//! errors, the writer's rules, and round trips RML → G-code → RML.

use expect_test::{expect, expect_file};
use kezuri_geom::{Arc, Axes, AxisSet, Move, MoveKind, Plane, Spindle, Toolpath};
use kezuri_nc::interp::{self, Settings};
use kezuri_nc::rml::{looks_like_rml, read_rml, write_rml, RmlOptions, RmlProgram};
use kezuri_nc::write::{csv, program, WriteOptions};
use kezuri_nc::ErrorKind;
use kezuri_nc::{parse, Program, SourceFile, Sources};
use proptest::prelude::*;

fn data(name: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("testdata/rml").join(name);
    std::fs::read_to_string(path).unwrap()
}

fn options(safe_z: f64, feed: f64) -> RmlOptions {
    RmlOptions { safe_z: Some(safe_z), feed: Some(feed), ..RmlOptions::default() }
}

/// Reads `text` and renders its diagnostics, one headline each.
fn read(name: &str, text: &str, o: &RmlOptions) -> (RmlProgram, String) {
    let mut sources = Sources::default();
    let id = sources.add(SourceFile::new(name, text));
    let read = read_rml(id, text, o);
    let rendered: Vec<String> = read.diagnostics.iter().map(|d| d.headline(&sources)).collect();
    (read, rendered.join("\n"))
}

fn fanuc(path: &Toolpath, title: &str) -> String {
    let o = WriteOptions { title: Some(title.into()), ..WriteOptions::default() };
    program(path, &o).unwrap()
}

/// Parses and runs a G-code program.
fn run_gcode(text: &str) -> Toolpath {
    let mut sources = Sources::default();
    let id = sources.add(SourceFile::new("round.nc", text));
    let mut program = Program::default();
    let diagnostics = parse(&mut program, id, text);
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let outcome = interp::run(&mut program, &mut sources, 0, &mut interp::NoLibrary, &Settings::default());
    assert!(outcome.completed && outcome.diagnostics.is_empty(), "{:?}", outcome.diagnostics);
    outcome.toolpath
}

fn at(x: f64, y: f64, z: f64) -> Axes {
    Axes { x, y, z, ..Axes::ZERO }
}

fn steps(p: Axes, unit: f64) -> [i64; 3] {
    [(p.x / unit).round() as i64, (p.y / unit).round() as i64, (p.z / unit).round() as i64]
}

/// The end points of the moves in steps, consecutive repeats dropped.
fn points(path: &Toolpath, unit: f64) -> Vec<[i64; 3]> {
    let mut out: Vec<[i64; 3]> = Vec::new();
    for m in &path.moves {
        let p = steps(m.end, unit);
        if out.last() != Some(&p) {
            out.push(p);
        }
    }
    out
}

#[test]
fn seed_002_listing_converts_with_units() {
    // Figure 1 of the paper: counts of 0.01 mm, not millimetres.
    let (read, diagnostics) = read("camm3.dat", &data("paper_fig1.rml"), &options(5.0, 600.0));
    assert_eq!(diagnostics, "");
    assert_eq!(read.commands, 14);
    let moves = &read.toolpath.moves;
    // The lift of ^PU, its travel, and one feed per Z command.
    assert_eq!(moves.len(), 2 + 12);
    assert_eq!(moves[2].end, at(0.0, 0.0, -2.4));
    assert!((moves[13].end.x - 4.31).abs() < 1e-12);
    assert_eq!(moves[3].line, 4);
    expect_file!["../testdata/rml/paper_fig1.fanuc.nc"].assert_eq(&fanuc(&read.toolpath, "CAMM3.DAT"));
}

#[test]
fn seed_002_listing_needs_a_safe_height_and_a_feed() {
    let (_, diagnostics) = read("camm3.dat", &data("paper_fig1.rml"), &RmlOptions::default());
    expect![[r#"
        camm3.dat:2:1: error: no tool-up height for this move: the program sets none (!PZ z1,z2); give one (--safe-z Z)
        camm3.dat:3:1: error: no feed for this cutting move: the program sets no speed before it (V, ^VS or !VZ); give one (--feed MM/MIN)"#]]
    .assert_eq(&diagnostics);
}

#[test]
fn relief_rows_golden() {
    let (read, diagnostics) = read("relief_rows.rml", &data("relief_rows.rml"), &RmlOptions::default());
    expect![[r#"relief_rows.rml:5:1: warning: device command !RC15 is not converted: spindle rate (its scale depends on the model) (later !RC commands too)"#]]
    .assert_eq(&diagnostics);
    assert_eq!(read.device.len(), 1);
    assert_eq!((read.device[0].text.as_str(), read.device[0].line), ("!RC15", 5));
    // V15.0 is 15 mm/s.
    assert!(read.toolpath.moves.iter().filter(|m| m.kind == MoveKind::Feed).all(|m| m.feed == 900.0));
    expect_file!["../testdata/rml/relief_rows.fanuc.nc"].assert_eq(&fanuc(&read.toolpath, "RELIEF_ROWS.RML"));
}

#[test]
fn every_command_with_breaks_spaces_and_a_missing_last_semicolon() {
    let (read, diagnostics) = read("commands.rml", &data("commands.rml"), &RmlOptions::default());
    expect![[r#"commands.rml:14:1: warning: device command !NR is not converted: pause until the operator continues (later !NR commands too)"#]]
    .assert_eq(&diagnostics);
    expect_file!["../testdata/rml/commands.csv"].assert_eq(&csv(&read.toolpath));
    let m = &read.toolpath.moves;
    // ^PU1000,1000 from an unknown start: a lift (Z only), then X and Y.
    assert_eq!((m[0].kind, m[0].named, m[0].end.z), (MoveKind::Rapid, AxisSet(0b100), 3.0));
    assert_eq!((m[1].named, m[1].end), (AxisSet(0b011), at(10.0, 10.0, 3.0)));
    // ^PD plunges to !PZ's Z1 at !VZ (2 mm/s), then cuts at ^VS (5 mm/s).
    assert_eq!((m[2].end, m[2].feed), (at(10.0, 10.0, -1.0), 120.0));
    assert_eq!((m[3].end, m[3].feed), (at(20.0, 10.0, -1.0), 300.0));
    // The Z command is fed at V (10 mm/s); the spindle was on from !MC1.
    let z = m.iter().find(|m| m.line == 8).unwrap();
    assert_eq!((z.end, z.feed, z.spindle), (at(10.0, 10.0, -1.5), 600.0, Spindle::Cw));
    // The relative Z move: 0.1 mm in X from where the last Z left the tool.
    assert_eq!(m.last().unwrap().end, at(30.1, 0.9, -0.5));
    assert_eq!(read.commands, 21);
}

#[test]
fn compact_and_spread_programs_read_the_same() {
    let compact = "^IN;V10;^PA;Z0,0,0;Z100,-200,-50;^PR;Z1,1,1;";
    let spread = "^ IN ;\n V 10 ;\r\n^PA;Z 0 ,\n0, 0;Z100 -200 -50\n^PR\nZ1,1,1";
    let (a, da) = read("a.rml", compact, &RmlOptions::default());
    let (b, db) = read("b.rml", spread, &RmlOptions::default());
    assert_eq!((da.as_str(), db.as_str()), ("", ""));
    let ends = |p: &RmlProgram| p.toolpath.moves.iter().map(|m| m.end).collect::<Vec<_>>();
    assert_eq!(ends(&a), ends(&b));
    assert_eq!(ends(&a)[1], at(1.0, -2.0, -0.5));
}

#[test]
fn unknown_command_is_located_by_line_and_column() {
    let text = "^PA;V10;\nZ0,0,0;\nZ10,0,0;  ^XY12,4;\nZ20,0,0;\n";
    let mut sources = Sources::default();
    let id = sources.add(SourceFile::new("bad.rml", text));
    let read = read_rml(id, text, &RmlOptions::default());
    assert_eq!(read.errors(), 1);
    expect![[r#"
        bad.rml:3:11: error: unknown RML-1 command '^XY12,4'
        3 | Z10,0,0;  ^XY12,4;
          |           ^^^^^^^"#]]
    .assert_eq(&read.diagnostics[0].render(&sources));
    // The rest is read.
    assert_eq!(read.toolpath.moves.last().unwrap().end.x, 0.2);
}

#[test]
fn bad_input() {
    let o = options(5.0, 600.0);
    let cases = [
        ("", ""),
        ("  ;;\n", ""),
        ("^PA;Z1,a,3;", "t.rml:1:8: error: expected a number after ',' in 'Z1,', found 'a'"),
        ("^PA;Z1,,3;", "t.rml:1:8: error: expected a number after ',' in 'Z1,', found ','"),
        ("^PA;Z1,2;", "t.rml:1:5: error: Z takes 3 numbers, found 2"),
        ("^PU1,2,3;", "t.rml:1:1: error: ^PU takes X,Y pairs, found 3 numbers"),
        ("V0;", "t.rml:1:2: error: V: the speed must be more than 0 mm/s, found 0"),
        ("Z1,2,99999999999;", "t.rml:1:6: error: 99999999999 steps is out of range (at most ±2147483647)"),
        ("^PA;Z1.5,0,0;", "t.rml:1:6: warning: RML-1 coordinates are whole steps of 0.01 mm: 1.5 is read as a fraction of a step"),
        ("^PD10,10;", "t.rml:1:1: error: no tool-down height for ^PD: the program sets none before it (!PZ z1,z2 or a Z move)"),
        ("^PR;Z10,0,0;", "t.rml:1:5: warning: a relative move before the position is known: it is taken from X0 Y0 Z0"),
        ("12,3;", "t.rml:1:1: error: expected an RML-1 command, found '12,3'"),
        ("^12;", "t.rml:1:1: error: expected a two-letter command name in '^12'"),
        ("^PA;Z0,0,0;!0;Z1,1,1;", "t.rml:1:12: warning: '!0' read as the end of the data, as the original RML-1 converter does; what follows it is not read"),
        ("Z\u{3000}1,\u{3000}2,3;", ""),
        ("Z\u{ff11},2,3;", "t.rml:1:2: error: expected a number in 'Z', found '\u{ff11}'"),
    ];
    for (text, want) in cases {
        let (_, got) = read("t.rml", text, &o);
        assert_eq!(got, want, "{text:?}");
    }
    // Half RML, half G-code: every G-code line is an error, one each.
    let half = "^IN;^PA;V10;\nZ0,0,-100;\nG01 X10. Y10.\nG00 Z5.\nZ100,0,-100;\n";
    let (half_read, got) = read("half.rml", half, &o);
    expect![[r#"
        half.rml:3:1: error: unknown RML-1 command 'G01' (this looks like G-code: a file is either RML-1 or G-code)
        half.rml:4:1: error: unknown RML-1 command 'G00' (this looks like G-code: a file is either RML-1 or G-code)"#]]
    .assert_eq(&got);
    assert_eq!(half_read.toolpath.moves.len(), 2);
    // Garbage is reported, a hundred diagnostics at most, never a panic.
    let garbage: String = (0..3000u32).map(|i| char::from_u32(0x20 + (i * 7919) % 0x3000).unwrap_or('?')).collect();
    let (garbage_read, _) = read("garbage.rml", &garbage, &o);
    assert!(garbage_read.diagnostics.len() <= 101 && garbage_read.errors() > 0);
    // Bad options are an error, not a panic.
    let (bad_read, got) = read("t.rml", "Z1,2,3;", &RmlOptions { unit: 0.0, ..o });
    assert_eq!(
        (bad_read.toolpath.moves.len(), got.as_str()),
        (0, "t.rml:1:1: error: RML option unit 0 is out of range")
    );
}

#[test]
fn sniffing_rml_from_g_code() {
    for rml in ["^IN;", ";;^IN;!MC0;", "  ^PA;", "PA;PA;VS4;", "IN;", "Z0,0,-240;", "Z 39, 0, -240;", "!MC1;"] {
        assert!(looks_like_rml(rml), "{rml}");
    }
    for gcode in ["%\nO0001\n", "G00 X0 Y0", "(comment)\nG01", "Z-1.", "Z10 F100", "", "INPUT"] {
        assert!(!looks_like_rml(gcode), "{gcode}");
    }
}

/// A chained toolpath builder.
struct Build {
    path: Toolpath,
    at: Axes,
}

impl Build {
    fn new(start: Axes) -> Build {
        Build { path: Toolpath::default(), at: start }
    }
    fn go(&mut self, kind: MoveKind, end: Axes, feed: f64) -> &mut Build {
        let line = self.path.moves.len() as u32 + 1;
        let spindle = if kind == MoveKind::Rapid && self.path.moves.is_empty() { Spindle::Off } else { Spindle::Cw };
        self.path.push(Move { kind, start: self.at, end, feed, spindle, tool: 1, line, ..Move::default() });
        self.at = end;
        self
    }
}

#[test]
fn writer_golden() {
    let mut b = Build::new(at(0.0, 0.0, 10.0));
    b.go(MoveKind::Rapid, at(0.0, 0.0, 5.0), 0.0)
        .go(MoveKind::Rapid, at(10.0, 0.0, 5.0), 0.0)
        .go(MoveKind::Rapid, at(10.0, 0.0, 1.0), 0.0)
        .go(MoveKind::Feed, at(10.0, 0.0, -1.005), 300.0)
        .go(MoveKind::Feed, at(20.0, 0.0, -1.005), 1000.0);
    let arc = Arc { center: [20.0, 5.0, -1.005], plane: Plane::Xy, ccw: true, turns: 0 };
    b.go(MoveKind::Arc(arc), at(20.0, 10.0, -1.005), 1000.0).go(MoveKind::Rapid, at(20.0, 10.0, 5.0), 0.0);
    let options = RmlOptions { tolerance: 0.05, ..RmlOptions::default() };
    let text = write_rml(&b.path, &options).unwrap();
    expect_file!["../testdata/rml/writer.rml"].assert_eq(&text);
    // Read back: the same points to the step.
    let (back, diagnostics) = read("writer.rml", &text, &RmlOptions::default());
    assert_eq!(diagnostics, "");
    let want: Vec<[i64; 3]> = [[0, 0, 500], [1000, 0, 500], [1000, 0, 100], [1000, 0, -100], [2000, 0, -100]].to_vec();
    assert_eq!(points(&back.toolpath, 0.01)[..5], want[..]);
    assert_eq!(*points(&back.toolpath, 0.01).last().unwrap(), [2000, 1000, 500]);
}

#[test]
fn writer_rounds_each_point_on_the_grid_without_drift() {
    // 3,000 feeds of a third of a step: rounding each delta would lose it
    // all; rounding each point keeps the sum.
    let mut b = Build::new(at(0.0, 0.0, 0.0));
    b.go(MoveKind::Feed, at(0.0, 0.0, -1.0), 600.0);
    for k in 1..=3000 {
        b.go(MoveKind::Feed, at(f64::from(k) * 0.01 / 3.0, 0.0, -1.0), 600.0);
    }
    let text = write_rml(&b.path, &RmlOptions::default()).unwrap();
    let (back, _) = read("grid.rml", &text, &RmlOptions::default());
    let last = back.toolpath.moves.iter().rev().find(|m| m.kind == MoveKind::Feed).unwrap();
    assert_eq!(last.end.x, 10.0);
    // A move that rounds to the same step writes nothing: 1,001 Z commands.
    assert_eq!(text.matches("\nZ").count(), 1001);
    for m in back.toolpath.moves.iter().filter(|m| m.kind == MoveKind::Feed) {
        assert!((m.end.x * 100.0 - (m.end.x * 100.0).round()).abs() < 1e-9);
    }
}

#[test]
fn rapids_down_become_a_tool_up_travel_and_a_fed_plunge() {
    let mut b = Build::new(at(0.0, 0.0, 5.0));
    b.go(MoveKind::Rapid, at(0.0, 0.0, 5.0), 0.0).go(MoveKind::Rapid, at(30.0, 40.0, -2.0), 0.0).go(
        MoveKind::Feed,
        at(31.0, 40.0, -2.0),
        120.0,
    );
    let text = write_rml(&b.path, &RmlOptions::default()).unwrap();
    expect![[r#"
        ;;^IN;
        ^PA;
        !PZ0,500;
        ^PU0,0;
        !MC1;
        ^PU3000,4000;
        V2.0;
        Z3000,4000,-200;
        Z3100,4000,-200;
        ^PU;
        !MC0;
        ^IN;
    "#]]
    .assert_eq(&text);
    // With a lower safe height given, rapids travel there, and
    let text = write_rml(&b.path, &RmlOptions { safe_z: Some(1.0), ..RmlOptions::default() }).unwrap();
    // a rapid above it is a ^PU and a fed rise.
    assert!(
        text.starts_with(
            ";;^IN;\n^PA;\n!PZ0,100;\n^PU0,0;\nV2.0;\nZ0,0,500;\n!MC1;\n^PU3000,4000;\nZ3000,4000,-200;\n"
        ),
        "{text}"
    );
}

#[test]
fn tool_changes_pause_and_the_spindle_follows_the_toolpath() {
    let mut b = Build::new(at(0.0, 0.0, 5.0));
    b.go(MoveKind::Rapid, at(1.0, 1.0, 5.0), 0.0).go(MoveKind::Feed, at(1.0, 1.0, -1.0), 60.0);
    b.path.push(Move {
        kind: MoveKind::Rapid,
        start: at(1.0, 1.0, -1.0),
        end: at(2.0, 2.0, 5.0),
        tool: 2,
        spindle: Spindle::Ccw,
        line: 9,
        ..Move::default()
    });
    let text = write_rml(&b.path, &RmlOptions::default()).unwrap();
    expect![[r#"
        ;;^IN;
        ^PA;
        !PZ0,500;
        ^PU100,100;
        !MC1;
        V1.0;
        Z100,100,-100;
        ^PU;
        !MC0;
        !NR;
        !MC1;
        ^PU200,200;
        !MC0;
        ^IN;
    "#]]
    .assert_eq(&text);
}

#[test]
fn writer_errors_name_the_move() {
    let base = || {
        let mut b = Build::new(at(0.0, 0.0, 5.0));
        b.go(MoveKind::Rapid, at(1.0, 1.0, 5.0), 0.0);
        b
    };
    let err = |path: &Toolpath, o: &RmlOptions| write_rml(path, o).unwrap_err().to_string();
    let o = RmlOptions::default();
    let mut b = base();
    b.go(MoveKind::Dwell(0.5), at(1.0, 1.0, 5.0), 0.0);
    assert_eq!(
        err(&b.path, &o),
        "move 2 (line 2): a dwell (G04) has no RML-1 command; remove it from the program to convert it"
    );
    let mut b = base();
    b.go(MoveKind::Probe, at(1.0, 1.0, -5.0), 100.0);
    assert!(matches!(write_rml(&b.path, &o), Err(e) if e.kind == ErrorKind::Unsupported));
    assert!(err(&b.path, &o).contains("a probing move (G31)"));
    let mut b = base();
    b.go(MoveKind::Feed, Axes { a: 90.0, ..at(1.0, 1.0, 5.0) }, 100.0);
    assert_eq!(err(&b.path, &o), "move 2 (line 2): the toolpath turns axis A; RML-1 moves X, Y and Z only");
    let mut b = base();
    b.go(MoveKind::Feed, at(1.0, 1.0, 1e9), 100.0);
    assert_eq!(err(&b.path, &o), "move 2 (line 2): Z 1000000000 cannot be written in RML-1");
    let mut b = base();
    b.go(MoveKind::Feed, at(1.0, 1.0, 1.0), 0.0);
    assert_eq!(err(&b.path, &o), "move 2 (line 2): feed 0 cannot be written in RML-1");
    let b = base();
    let bad = RmlOptions { unit: f64::NAN, ..RmlOptions::default() };
    assert!(matches!(write_rml(&b.path, &bad), Err(e) if e.kind == ErrorKind::Option));
    assert!(err(&b.path, &bad).starts_with("RML option unit NaN"));
    // An interpreted program's first cut before X and Y are named.
    let path = run_gcode("G01 Z-1. F100.\nX10. Y0.\nM30\n");
    assert_eq!(
        err(&path, &o),
        "move 1 (line 1): a cutting move before the program names X and Y; an RML-1 Z command needs all three"
    );
    // Empty: header and end only.
    assert_eq!(write_rml(&Toolpath::default(), &o).unwrap(), ";;^IN;\n^PA;\n^IN;\n");
}

#[test]
fn rml_to_gcode_to_rml_keeps_every_point() {
    for name in ["paper_fig1.rml", "relief_rows.rml", "commands.rml"] {
        let o = options(5.0, 600.0);
        let (first, diagnostics) = read(name, &data(name), &o);
        assert!(first.errors() == 0, "{diagnostics}");
        let gcode = fanuc(&first.toolpath, name);
        let interpreted = run_gcode(&gcode);
        let rml = write_rml(&interpreted, &RmlOptions { safe_z: Some(5.0), ..RmlOptions::default() }).unwrap();
        let (second, diagnostics) = read("again.rml", &rml, &RmlOptions::default());
        assert!(second.errors() == 0, "{name}: {diagnostics}\n{rml}");
        // The RML program ends with the tool up.
        let mut want = points(&first.toolpath, 0.01);
        let last = *want.last().unwrap();
        if last[2] != 500 {
            want.push([last[0], last[1], 500]);
        }
        assert_eq!(want, points(&second.toolpath, 0.01), "{name}\n{gcode}\n{rml}");
        // Feeds survive to a hundredth of a mm/s.
        let feeds =
            |p: &Toolpath| p.moves.iter().filter(|m| m.kind == MoveKind::Feed).map(|m| m.feed).collect::<Vec<_>>();
        for (a, b) in feeds(&first.toolpath).iter().zip(feeds(&second.toolpath)) {
            assert!((a - b).abs() <= 0.3, "{name}: {a} vs {b}");
        }
    }
}

/// Toolpaths the way CAM writes them: travel at a safe height, plunge
/// (rapid or fed), cut, retract.
fn cam_path() -> impl Strategy<Value = Toolpath> {
    let point = (-5000i32..5000, -5000i32..5000, -1000i32..400).prop_map(|(x, y, z)| [x, y, z]);
    let cut = (proptest::collection::vec(point, 1..6), any::<bool>(), 1u32..3000);
    proptest::collection::vec(cut, 1..6).prop_map(|cuts| {
        let mm = |p: [i32; 3]| at(f64::from(p[0]) / 97.0, f64::from(p[1]) / 97.0, f64::from(p[2]) / 97.0);
        let mut b = Build::new(at(0.0, 0.0, 5.0));
        b.go(MoveKind::Rapid, at(0.0, 0.0, 5.0), 0.0);
        for (points, rapid_down, feed) in cuts {
            let first = mm(points[0]);
            b.go(MoveKind::Rapid, Axes { z: 5.0, ..b.at }, 0.0);
            b.go(MoveKind::Rapid, Axes { z: 5.0, ..first }, 0.0);
            let kind = if rapid_down { MoveKind::Rapid } else { MoveKind::Feed };
            b.go(kind, first, f64::from(feed));
            for p in &points[1..] {
                b.go(MoveKind::Feed, mm(*p), f64::from(feed));
            }
        }
        b.go(MoveKind::Rapid, Axes { z: 5.0, ..b.at }, 0.0);
        b.path
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// write → read gives the same points to the step, and the feeds to
    /// the hundredth of a mm/s that `V` keeps.
    #[test]
    fn write_then_read_keeps_the_points(path in cam_path()) {
        // A path of rapids alone needs a feed for its plunges.
        let text = write_rml(&path, &RmlOptions { feed: Some(600.0), ..RmlOptions::default() }).unwrap();
        let (back, diagnostics) = read("p.rml", &text, &RmlOptions::default());
        prop_assert!(diagnostics.is_empty(), "{}", diagnostics);
        prop_assert_eq!(points(&path, 0.01), points(&back.toolpath, 0.01));
        for m in back.toolpath.moves.iter().filter(|m| m.kind == MoveKind::Feed) {
            let source = path.moves.iter().find(|s| steps(s.end, 0.01) == steps(m.end, 0.01) && s.kind == MoveKind::Feed);
            if let Some(s) = source {
                prop_assert!((s.feed - m.feed).abs() <= 0.3);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    /// Any text reads without a panic, and whatever it reads writes back
    /// (or says why not) without one.
    #[test]
    fn any_text_reads_and_writes_without_a_panic(text in "[\\^!;,. 0-9A-Za-z+\\-\n\u{3000}φ]{0,300}") {
        let read = read_rml(0, &text, &options(5.0, 100.0));
        prop_assert!(read.diagnostics.len() <= 101);
        let _ = write_rml(&read.toolpath, &RmlOptions::default());
        let _ = looks_like_rml(&text);
    }
}
