//! The post presets on a made two-tool toolpath: each preset's start, tool
//! change and end against a program written by hand
//! (`testdata/write/post/`; where each convention comes from is in
//! `docs/post.md`), and the formatting options one by one.

use std::collections::BTreeMap;
use std::f64::consts::PI;

use kezuri_geom::{Arc, Axes, AxisSet, Move, MoveKind, Plane, Spindle, Toolpath};
use kezuri_nc::write::{program, Arcs, Home, Retract, WriteOptions, PRESETS};
use kezuri_nc::{Error, ErrorKind};

fn at(x: f64, y: f64, z: f64) -> Axes {
    Axes { x, y, z, ..Axes::ZERO }
}

/// A made toolpath: tool 1 plunges, cuts, turns a quarter circle and
/// rises; tool 2 plunges, cuts and rises.
fn two_tools() -> Toolpath {
    let mut path = Toolpath::default();
    let mut last = at(10.0, 10.0, 5.0);
    let mut push = |kind, end: Axes, feed: f64, tool: u32, speed: f64| {
        path.push(Move { kind, start: last, end, feed, speed, spindle: Spindle::Cw, tool, ..Move::default() });
        last = end;
    };
    push(MoveKind::Rapid, at(10.0, 10.0, 5.0), 0.0, 1, 8000.0);
    push(MoveKind::Feed, at(10.0, 10.0, -1.0), 200.0, 1, 8000.0);
    push(MoveKind::Feed, at(30.0, 10.0, -1.0), 800.0, 1, 8000.0);
    let quarter = Arc { center: [30.0, 20.0, -1.0], plane: Plane::Xy, ccw: true, turns: 0 };
    push(MoveKind::Arc(quarter), at(40.0, 20.0, -1.0), 800.0, 1, 8000.0);
    push(MoveKind::Rapid, at(40.0, 20.0, 5.0), 0.0, 1, 8000.0);
    push(MoveKind::Rapid, at(0.0, 0.0, 5.0), 0.0, 2, 12000.0);
    push(MoveKind::Feed, at(0.0, 0.0, -0.5), 200.0, 2, 12000.0);
    push(MoveKind::Feed, at(20.0, 0.0, -0.5), 1000.0, 2, 12000.0);
    push(MoveKind::Rapid, at(20.0, 0.0, 5.0), 0.0, 2, 12000.0);
    path
}

fn written(name: &str, change: impl FnOnce(&mut WriteOptions)) -> Result<String, Error> {
    let mut o = WriteOptions { title: Some("POST TEST".into()), ..WriteOptions::preset(name).unwrap() };
    change(&mut o);
    program(&two_tools(), &o)
}

#[test]
fn every_preset_writes_the_program_written_by_hand() {
    let expected = [
        ("fanuc", include_str!("../testdata/write/post/fanuc.nc")),
        ("haas", include_str!("../testdata/write/post/haas.nc")),
        ("linuxcnc", include_str!("../testdata/write/post/linuxcnc.ngc")),
        ("grbl", include_str!("../testdata/write/post/grbl.nc")),
        ("mach3", include_str!("../testdata/write/post/mach3.nc")),
    ];
    assert_eq!(expected.map(|(n, _)| n), PRESETS);
    for (name, text) in expected {
        assert_eq!(written(name, |_| {}).unwrap(), text, "{name}");
    }
}

/// The safety rules every preset keeps, line by line: G90 right after
/// every `G91 G28`; after each tool change the length offset on the first
/// block that moves Z (where the preset uses offsets), X and Y placed
/// before Z goes down (after a retract) and the spindle on before any feed;
/// M05 before the end.
#[test]
fn every_preset_keeps_the_safety_rules() {
    for name in PRESETS {
        let text = written(name, |_| {}).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let setup = WriteOptions::preset(name).unwrap().setup.unwrap();
        let (mut changed, mut spindle_on, mut xy) = (false, false, false);
        for (k, line) in lines.iter().enumerate() {
            if line.contains("G91 G28") {
                assert!(lines[k + 1].starts_with("G90"), "{name}: no G90 after '{line}'");
            }
            if line.contains("M06") || line.contains("M6") || *line == "M0" {
                (changed, spindle_on, xy) = (true, false, false);
            }
            if line.contains("M03") || line.contains(" M3") {
                spindle_on = true;
            }
            let machine = line.contains("G53") || line.contains("G28") || line.starts_with('(');
            xy |= !machine && (line.contains('X') || line.contains('Y'));
            if changed && !machine && line.contains('Z') {
                assert_eq!(line.contains("G43 H"), setup.length_offset, "{name}: first Z move '{line}'");
                assert!(xy || setup.retract == Retract::None, "{name}: Z goes down before X Y: '{line}'");
                changed = false;
            }
            if line.contains('F') {
                assert!(spindle_on, "{name}: a feed with the spindle off: '{line}'");
            }
        }
        let end = lines.iter().rposition(|l| l.starts_with("M30") || l.starts_with("M2")).unwrap();
        let stop = lines.iter().rposition(|l| *l == "M05" || *l == "M5").unwrap();
        assert!(stop < end, "{name}: M05 after the end");
    }
}

/// A made toolpath that starts as the raster does: up to the safe height
/// (naming Z only), then across. After the retract X and Y still go first.
#[test]
fn x_and_y_go_first_after_a_retract_whichever_axes_the_first_move_names() {
    let mut path = Toolpath::default();
    let safe = at(10.0, 20.0, 5.0);
    let base = Move { spindle: Spindle::Cw, speed: 1000.0, tool: 1, ..Move::default() };
    path.push(Move { kind: MoveKind::Rapid, start: safe, end: safe, named: AxisSet(0b100), ..base });
    path.push(Move { kind: MoveKind::Rapid, start: safe, end: safe, named: AxisSet(0b011), ..base });
    let bottom = at(10.0, 20.0, -1.0);
    path.push(Move { kind: MoveKind::Feed, start: safe, end: bottom, feed: 100.0, ..base });
    let text = program(&path, &WriteOptions::preset("fanuc").unwrap()).unwrap();
    assert!(text.contains("T1 M06\nS1000 M03\nM08\nG00 X10. Y20.\nG00 G43 H1 Z5.\nG01 Z-1. F100.\n"), "{text}");
    let grbl = program(&path, &WriteOptions::preset("grbl").unwrap()).unwrap();
    assert!(grbl.contains("M0\nG0 Z5.\nS1000 M3\nG4 P3\nX10. Y20.\nG1 Z-1. F100.\n"), "{grbl}");
    // The later part of a split program: the tool is in, no pause for it.
    let part = WriteOptions { loaded_tool: Some(1), ..WriteOptions::preset("grbl").unwrap() };
    let grbl = program(&path, &part).unwrap();
    assert!(!grbl.contains("M0\n") && grbl.contains("G54\nG0 Z5.\nS1000 M3\n"), "{grbl}");
}

#[test]
fn the_length_register_is_the_tool_tables() {
    let text = written("fanuc", |o| {
        o.setup.as_mut().unwrap().registers = BTreeMap::from([(2, 22)]);
    })
    .unwrap();
    assert!(text.contains("G00 G43 H1 Z5.\n") && text.contains("G00 G43 H22 Z5.\n"), "{text}");
}

#[test]
fn arcs_as_radius_and_as_lines() {
    let text = written("fanuc", |o| o.arcs = Arcs::Radius).unwrap();
    assert!(text.contains("G17 G03 X40. Y20. R10.\n"), "{text}");
    let text = written("fanuc", |o| o.arcs = Arcs::Lines).unwrap();
    assert!(!text.contains("G03") && !text.contains('I'), "{text}");
    // Every chord end on the circle to the rounding of its two words
    // (√2 · 0.0005 mm), every chord within one unit (1 µm) of it and that
    // rounding: the sagitta of a chord c is r − √(r² − c²/4).
    let ends: Vec<[f64; 2]> = text
        .lines()
        .skip_while(|l| !l.starts_with("X30."))
        .skip(1)
        .take_while(|l| !l.starts_with("G00"))
        .map(|l| {
            let v = |c: char| l.split(' ').find_map(|w| w.strip_prefix(c)).map(|n| n.parse::<f64>().unwrap());
            [v('X').unwrap(), v('Y').unwrap()]
        })
        .collect();
    assert!(ends.len() > 10, "{ends:?}");
    let mut last = [30.0, 10.0];
    for p in &ends {
        let r = (p[0] - 30.0).hypot(p[1] - 20.0);
        assert!((r - 10.0).abs() <= 0.000_71, "{p:?} is {r} from the centre");
        let chord = (p[0] - last[0]).hypot(p[1] - last[1]);
        let sagitta = 10.0 - (100.0 - chord * chord / 4.0).sqrt();
        assert!(sagitta <= 0.001 + 0.000_71, "chord {chord} strays {sagitta}");
        last = *p;
    }
    assert_eq!(ends.last(), Some(&[40.0, 20.0]));
}

#[test]
fn a_full_circle_with_radius_arcs_is_two_half_circles() {
    let mut path = Toolpath::default();
    let start = at(10.0, 0.0, -1.0);
    path.push(Move { kind: MoveKind::Rapid, start, end: start, spindle: Spindle::Cw, tool: 1, ..Move::default() });
    let full = Arc { center: [0.0, 0.0, -1.0], plane: Plane::Xy, ccw: false, turns: 0 };
    path.push(Move { kind: MoveKind::Arc(full), start, end: start, feed: 500.0, tool: 1, ..Move::default() });
    assert!((full.sweep(start, start) - 2.0 * PI).abs() < 1e-9);
    let o = WriteOptions { arcs: Arcs::Radius, ..WriteOptions::preset("fanuc").unwrap() };
    let text = program(&path, &o).unwrap();
    assert!(text.contains("G17 G02 X-10. R10. F500.\nX10. R10.\n"), "{text}");
}

/// R arcs whose ends rounding moved apart (a half circle of 10.001 mm
/// chord about a 5 mm radius; a full circle split at a rounded middle):
/// every R is at least half its written chord, so a control finds a circle
/// (GRBL's error 33 otherwise), and the centre it finds is within a unit
/// of the arc's.
#[test]
fn radius_arcs_always_reach_their_written_ends() {
    let cases = [
        (at(0.0, 0.0, 0.0), at(10.001, 0.0, 0.0), [5.0, 0.0, 0.0]),
        (at(0.0, 0.0, 0.0), at(10.004, 0.0, 0.0), [5.0, 0.0, 0.0]),
        (at(1.234, 2.345, 0.0), at(1.234, 2.345, 0.0), [4.565, 3.462, 0.0]),
    ];
    for inch in [false, true] {
        for (start, end, center) in cases {
            let mut path = Toolpath::default();
            let base = Move { spindle: Spindle::Cw, speed: 1000.0, tool: 1, ..Move::default() };
            path.push(Move { kind: MoveKind::Rapid, start, end: start, ..base });
            let arc = Arc { center, plane: Plane::Xy, ccw: false, turns: 0 };
            path.push(Move { kind: MoveKind::Arc(arc), start, end, feed: 100.0, ..base });
            let o = WriteOptions { arcs: Arcs::Radius, inch, ..WriteOptions::preset("fanuc").unwrap() };
            let text = program(&path, &o).unwrap();
            let mut p = [0.0, 0.0];
            let mut arcs = 0;
            for l in text.lines().filter(|l| !l.starts_with('(') && !l.starts_with('%') && !l.starts_with('O')) {
                let v = |c: char| l.split(' ').find_map(|w| w.strip_prefix(c)).and_then(|n| n.parse::<f64>().ok());
                let q = [v('X').unwrap_or(p[0]), v('Y').unwrap_or(p[1])];
                if let Some(r) = v('R') {
                    let half = (q[0] - p[0]).hypot(q[1] - p[1]) / 2.0;
                    assert!(r.abs() >= half, "{l}: R {r} is short of half the chord {half}\n{text}");
                    arcs += 1;
                }
                p = q;
            }
            assert!(arcs >= 1, "{text}");
        }
    }
}

/// A park position is mm in the machine file, written in the program's
/// units; Mach3 probes with G31.
#[test]
fn park_in_inches_and_mach3_probing() {
    let text = written("haas", |o| {
        o.inch = true;
        o.digits = 4;
        o.setup.as_mut().unwrap().home = Home::Park([-300.0, -10.0]);
    })
    .unwrap();
    assert!(text.contains("\nG53 G00 X-11.811 Y-0.3937\nM30\n"), "{text}");
    let mut path = Toolpath::default();
    let base = Move { tool: 1, ..Move::default() };
    path.push(Move { kind: MoveKind::Rapid, start: at(0.0, 0.0, 5.0), end: at(0.0, 0.0, 5.0), ..base });
    let probe = Move { kind: MoveKind::Probe, start: at(0.0, 0.0, 5.0), end: at(0.0, 0.0, -10.0), feed: 100.0, ..base };
    path.push(probe);
    let mach3 = program(&path, &WriteOptions { setup: None, ..WriteOptions::preset("mach3").unwrap() }).unwrap();
    assert!(mach3.contains("\nG31 Z-10. F100.\n"), "{mach3}");
    let linuxcnc = program(&path, &WriteOptions { setup: None, ..WriteOptions::preset("linuxcnc").unwrap() }).unwrap();
    assert!(linuxcnc.contains("\nG38.2 Z-10. F100.\n"), "{linuxcnc}");
}

#[test]
fn limits_comments_and_dwell_units() {
    let e = written("fanuc", |o| o.block_limit = Some(12)).unwrap_err();
    // Spaces and comments are not kept: 'G90G17G94G40G49G80' is 18.
    assert_eq!(
        e.to_string(),
        "block 4 of the program ('G90 G17 G94 G40 G49 G80') is 18 characters, more than the 12 the control takes"
    );
    let whole = written("fanuc", |_| {}).unwrap().len() as u64;
    let e = written("fanuc", |o| o.byte_limit = Some(whole - 1)).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Limit, "{e}");
    assert!(e.to_string().starts_with(&format!("the program is {whole} bytes (drip-feed it")), "{e}");
    assert!(written("fanuc", |o| o.byte_limit = Some(whole)).is_ok());
    let framed = written("linuxcnc", |o| o.percent = Some(true)).unwrap();
    assert!(framed.starts_with("%\n(POST TEST)\n") && framed.ends_with("M2\n%\n"), "{framed}");
    let bare = written("fanuc", |o| o.percent = Some(false)).unwrap();
    assert!(bare.starts_with("O0001 (POST TEST)\n") && bare.ends_with("M30\n"), "{bare}");
    let bare = written("grbl", |o| o.comments = false).unwrap();
    assert!(!bare.contains('('), "{bare}");
    assert!(bare.starts_with("G21\nG90 G17 G94\nG54\nM0\n"), "{bare}");
    let ms = written("mach3", |o| o.dwell_ms = Some(true)).unwrap();
    assert!(ms.contains("\nG4 P2000\n"), "{ms}");
    let seconds = written("fanuc", |o| {
        o.dwell_ms = Some(false);
        o.setup.as_mut().unwrap().spindle_dwell = 1.5;
    })
    .unwrap();
    assert!(seconds.contains("S8000 M03\nG04 X1.5\n"), "{seconds}");
}

/// A program kezuri transforms (no setup) keeps its own start, tool
/// changes and end: no retract, no G43, no M01 is added.
#[test]
fn a_transformed_program_gets_only_the_formatting() {
    let o = WriteOptions { setup: None, line_numbers: Some(5), ..WriteOptions::preset("haas").unwrap() };
    let text = program(&two_tools(), &o).unwrap();
    for absent in ["G28", "G53", "G43", "M01", "M08"] {
        assert!(!text.contains(absent), "{absent} in\n{text}");
    }
    assert!(text.starts_with("%\nO0001\nN5 G21 G90 G17 G94 G40 G49 G80 G54\nN10 T1 M06\n"), "{text}");
}
