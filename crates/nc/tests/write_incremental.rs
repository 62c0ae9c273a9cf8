//! Incremental programs (G91) from the G-code writer: the same motions as
//! the absolute program, frames, homes and machine moves kept absolute, and
//! no drift over many small moves.

mod common;

use std::collections::BTreeMap;

use common::writer::{at, body, kind_name, point, run, same_motion, sample, written, Path};
use kezuri_geom::{Axes, MoveKind, Plane, Spindle, Toolpath};
use kezuri_nc::interp::{self, IntegerInput, Settings};
use kezuri_nc::write::{program, Dialect, WriteOptions};
use kezuri_nc::{parse, Program, SourceFile, Sources};
use proptest::prelude::*;

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
fn counts(p: Axes, o: &WriteOptions) -> [i64; Axes::COUNT] {
    let scale = 10f64.powi(i32::from(o.digits));
    let v = p.to_array();
    std::array::from_fn(|k| (v[k] * scale / if Axes::is_linear(k) && o.inch { 25.4 } else { 1.0 }).round() as i64)
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
