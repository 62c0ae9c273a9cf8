//! Cutter radius compensation end to end: NC text with G41/G42 D run by the
//! interpreter gives the tool-centre path in `Outcome::toolpath` and the
//! programmed contour, with its G41/G42 D and G40 blocks, in
//! `Outcome::programmed`. Every expected point is worked out on paper in
//! the comment above it (offset lines and their intersections, radius 2).

use std::collections::BTreeMap;

use kezuri_geom::{Move, MoveKind, Toolpath};
use kezuri_nc::interp::comp::{Approach, Rules};
use kezuri_nc::interp::{IntegerInput, Outcome, Settings};
use kezuri_nc::write::{program, Dialect, WriteOptions};
use kezuri_nc::Sources;

mod common;

fn run(text: &str, settings: &Settings) -> (Outcome, Sources) {
    let ran = common::run("t.nc", text, settings);
    (ran.outcome, ran.sources)
}

/// Runs `text`, which must complete without errors.
fn centre(text: &str, settings: &Settings) -> Outcome {
    common::run("t.nc", text, settings).completed()
}

fn radii(pairs: &[(u32, f64)]) -> Settings {
    Settings { tool_radii: BTreeMap::from_iter(pairs.iter().copied()), ..Settings::default() }
}

/// The plane end points (X, Y) of the moves, and whether each is a rapid.
fn ends(path: &Toolpath) -> Vec<(f64, f64, bool)> {
    path.moves.iter().map(|m| (m.end.x, m.end.y, m.kind == MoveKind::Rapid)).collect()
}

fn assert_ends(path: &Toolpath, want: &[(f64, f64, bool)]) {
    let got = ends(path);
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert!((g.0 - w.0).abs() < 1e-9 && (g.1 - w.1).abs() < 1e-9 && g.2 == w.2, "move {k}: {g:?}, want {w:?}");
    }
}

/// A 20 mm square, clockwise, tool on the left (outside): start-up from
/// (-10,-10) on the diagonal, cancel back along it.
const SQUARE: &str = "O0001
G21 G90 G17 G54
G00 X-10. Y-10.
G41 G01 X0. Y0. D1 F500.
Y20.
X20.
Y0.
X0.
G40 G00 X-10. Y-10.
M30
";

/// r = 2. Start-up (inside corner, both types): the start-up line's offset
/// (through (-√2, √2), direction (1,1)) meets x = -2 at y = 2√2 - 2.
/// Outside 90° corners: the offset lines' intersections (-2,22), (22,22),
/// (22,-2). Cancel (inside): y = -2 meets the cancel line's offset (through
/// (√2, -√2), direction (1,1)) at x = 2√2 - 2.
fn square_centre() -> Vec<(f64, f64, bool)> {
    let k = 2.0 * std::f64::consts::SQRT_2 - 2.0;
    vec![
        (-10.0, -10.0, true),
        (-2.0, k, false),
        (-2.0, 22.0, false),
        (22.0, 22.0, false),
        (22.0, -2.0, false),
        (k, -2.0, false),
        (-10.0, -10.0, true),
    ]
}

#[test]
fn square_with_g41_d1_is_offset_by_the_register() {
    let out = centre(SQUARE, &radii(&[(1, 2.0)]));
    assert_ends(&out.toolpath, &square_centre());
    // The programmed contour is kept, with G41 D1 before the start-up move
    // and G40 before the cancel move.
    let programmed = out.programmed.expect("the programmed contour");
    assert_ends(
        &programmed,
        &[
            (-10.0, -10.0, true),
            (0.0, 0.0, false),
            (0.0, 20.0, false),
            (20.0, 20.0, false),
            (20.0, 0.0, false),
            (0.0, 0.0, false),
            (-10.0, -10.0, true),
        ],
    );
    let kept: Vec<(usize, &str, u32)> = programmed.kept.iter().map(|k| (k.before, k.text.as_str(), k.line)).collect();
    assert_eq!(kept, [(1, "G41 D1", 4), (6, "G40", 9)]);
    assert!(out.toolpath.kept.is_empty(), "{:?}", out.toolpath.kept);
    // No warning about compensation being ignored any more.
    assert!(out.diagnostics.is_empty(), "{:?}", out.diagnostics);
}

#[test]
fn type_b_differs_from_type_a_only_at_outside_start_up() {
    // Start-up and cancel are inside corners here: both types agree.
    let b = Settings { comp_rules: Rules::Fanuc { startup: Approach::B }, ..radii(&[(1, 2.0)]) };
    assert_ends(&centre(SQUARE, &b).toolpath, &square_centre());
    // Start-up straight up the left side from (0,-10), then a right turn
    // (an outside corner). Type A ends the start-up on the vector
    // perpendicular to the next move (+X) at its start: (0, 22); type B on
    // the offset lines' intersection, x = -2 and y = 22.
    let text = "G00 X0. Y-10.\nG41 G01 Y20. D1 F500.\nX20.\nG40 G00 X30.\nM30\n";
    let a = centre(text, &radii(&[(1, 2.0)]));
    assert_eq!((a.toolpath.moves[1].end.x, a.toolpath.moves[1].end.y), (0.0, 22.0));
    let b = centre(text, &b);
    assert_eq!((b.toolpath.moves[1].end.x, b.toolpath.moves[1].end.y), (-2.0, 22.0));
}

#[test]
fn g42_with_a_negative_register_is_g41() {
    let text = SQUARE.replace("G41 G01 X0. Y0. D1", "G42 G01 X0. Y0. D2");
    let out = centre(&text, &radii(&[(2, -2.0)]));
    assert_ends(&out.toolpath, &square_centre());
    assert_eq!(out.programmed.unwrap().kept[0].text, "G42 D2");
}

#[test]
fn d_word_on_an_earlier_block_is_the_offset_number() {
    let text = SQUARE
        .replace("G41 G01 X0. Y0. D1", "G41 G01 X0. Y0.")
        .replace("G00 X-10. Y-10.\nG41", "G00 X-10. Y-10. D1\nG41");
    let out = centre(&text, &radii(&[(1, 2.0)]));
    assert_ends(&out.toolpath, &square_centre());
    assert_eq!(out.programmed.unwrap().kept[0].text, "G41 D1");
}

#[test]
fn g18_is_g17_with_z_for_x_and_x_for_y() {
    let text = "G18\nG00 Z-10. X-10.\nG41 G01 Z0. X0. D1 F500.\nX20.\nZ20.\nX0.\nZ0.\nG40 G00 Z-10. X-10.\nM30\n";
    let out = centre(text, &radii(&[(1, 2.0)]));
    let got: Vec<(f64, f64, bool)> =
        out.toolpath.moves.iter().map(|m| (m.end.z, m.end.x, m.kind == MoveKind::Rapid)).collect();
    let want = square_centre();
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, w) in got.iter().zip(&want) {
        assert!((g.0 - w.0).abs() < 1e-9 && (g.1 - w.1).abs() < 1e-9 && g.2 == w.2, "{g:?} want {w:?}");
    }
}

#[test]
fn interference_stops_the_run_at_its_block() {
    // Tool on the left (+Y) of a 1 mm wide groove, r = 2: the groove's floor
    // X10 → X11 offset to y = -3 runs from (12,-3) back to (9,-3).
    let text = "G00 X-10. Y0.\nG41 G01 X0. Y0. D1 F500.\nX10.\nY-5.\n  X11.\nY0.\nX20.\nG40 G00 X30.\nM30\n";
    let (out, sources) = run(text, &radii(&[(1, 2.0)]));
    assert!(!out.completed);
    let errors: Vec<String> = out.diagnostics.iter().filter(|d| d.is_error()).map(|d| d.headline(&sources)).collect();
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(errors[0].starts_with("t.nc:5:3: error: cutter compensation: interference"), "{errors:?}");
    // Nothing from the alarm's block on is made.
    assert!(out.toolpath.moves.iter().all(|m| m.line < 5), "{:?}", out.toolpath.moves);
    assert!(out.programmed.unwrap().moves.iter().all(|m| m.line < 5));
}

#[test]
fn unknown_register_warns_and_keeps_the_programmed_path() {
    let (out, sources) = run(SQUARE, &Settings::default());
    assert!(out.completed);
    let warnings: Vec<String> = out.diagnostics.iter().map(|d| d.headline(&sources)).collect();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].starts_with("t.nc:4:17: warning: D1 has no radius in the tool table"), "{warnings:?}");
    let programmed = out.programmed.expect("the programmed contour");
    assert_eq!(out.toolpath.moves, programmed.moves);
    // Where the centre path is needed, it is an error at the D word.
    let (out, sources) = run(SQUARE, &Settings { radii_required: true, ..Settings::default() });
    assert!(!out.completed);
    let errors: Vec<String> = out.diagnostics.iter().map(|d| d.headline(&sources)).collect();
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(errors[0].starts_with("t.nc:4:17: error: D1 has no radius"), "{errors:?}");
}

/// Writes `path` in `dialect` and runs the text again.
fn rerun(path: &Toolpath, dialect: Dialect, settings: &Settings) -> Outcome {
    let text = program(path, &WriteOptions { dialect, ..WriteOptions::default() }).unwrap();
    let integer_input = if dialect == Dialect::Fanuc { IntegerInput::Increments } else { IntegerInput::Units };
    centre(&text, &Settings { integer_input, ..settings.clone() })
}

fn same_path(a: &[Move], b: &[Move]) {
    assert_eq!(a.len(), b.len(), "{a:#?}\n{b:#?}");
    for (k, (p, q)) in a.iter().zip(b).enumerate() {
        let d = p.end.to_array().iter().zip(q.end.to_array()).map(|(u, v)| (u - v).abs()).fold(0.0, f64::max);
        assert!(
            d < 1e-3 && std::mem::discriminant(&p.kind) == std::mem::discriminant(&q.kind),
            "move {k}: {p:?} {q:?}"
        );
    }
}

#[test]
fn expanded_program_keeps_g41_and_gives_the_same_centre_path() {
    let settings = radii(&[(1, 2.0)]);
    let out = centre(SQUARE, &settings);
    let programmed = out.programmed.as_ref().unwrap();
    let text = program(programmed, &WriteOptions::default()).unwrap();
    assert!(text.contains("\nG41 D1\n") && text.contains("\nG40\n"), "{text}");
    let again = rerun(programmed, Dialect::Fanuc, &settings);
    same_path(&out.toolpath.moves, &again.toolpath.moves);
    // A LinuxCNC program of it, read with LinuxCNC's rules, compensates too.
    let lcnc = Settings { comp_rules: Rules::LinuxCnc, ..settings.clone() };
    let again = rerun(programmed, Dialect::LinuxCnc, &lcnc);
    assert!(again.programmed.is_some());
}

#[test]
fn centre_path_written_has_no_compensation_and_reads_back_the_same() {
    let settings = radii(&[(1, 2.0)]);
    let out = centre(SQUARE, &settings);
    let text = program(&out.toolpath, &WriteOptions::default()).unwrap();
    assert!(!text.contains("G41") && !text.contains("G42"), "{text}");
    let again = rerun(&out.toolpath, Dialect::Fanuc, &Settings::default());
    assert!(again.programmed.is_none());
    same_path(&out.toolpath.moves, &again.toolpath.moves);
}

/// A move's end X, Y, and for an arc its centre X, Y and direction.
type Seen = (f64, f64, Option<(f64, f64, bool)>);

/// LinuxCNC: the entry move ends perpendicular to itself; convex corners
/// get arcs of radius r around the programmed corner (clockwise for G41);
/// G40 leaves from the last offset point.
#[test]
fn linuxcnc_square_entry_and_corner_arcs() {
    let text = "G21 G90 G17\nG00 X0 Y-10\nG41 G01 Y0 D1 F500\nY20\nX20\nY0\nX0\nG40 G00 X-10\nM2\n";
    let settings = Settings { comp_rules: Rules::LinuxCnc, integer_input: IntegerInput::Units, ..radii(&[(1, 2.0)]) };
    let out = centre(text, &settings);
    let got: Vec<Seen> = out
        .toolpath
        .moves
        .iter()
        .map(|m| match m.kind {
            MoveKind::Arc(a) => (m.end.x, m.end.y, Some((a.center[0], a.center[1], a.ccw))),
            _ => (m.end.x, m.end.y, None),
        })
        .collect();
    let cw = |x, y| Some((x, y, false));
    let want = [
        (0.0, -10.0, None),
        (-2.0, 0.0, None),
        (-2.0, 20.0, None),
        (0.0, 22.0, cw(0.0, 20.0)),
        (20.0, 22.0, None),
        (22.0, 20.0, cw(20.0, 20.0)),
        (22.0, 0.0, None),
        (20.0, -2.0, cw(20.0, 0.0)),
        (0.0, -2.0, None),
        (-10.0, 0.0, None),
    ];
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, w) in got.iter().zip(&want) {
        let close = |a: f64, b: f64| (a - b).abs() < 1e-9;
        let centre_ok = match (g.2, w.2) {
            (None, None) => true,
            (Some(a), Some(b)) => close(a.0, b.0) && close(a.1, b.1) && a.2 == b.2,
            _ => false,
        };
        assert!(close(g.0, w.0) && close(g.1, w.1) && centre_ok, "{g:?} want {w:?}");
    }
    // G41.1 D4 (a 4 mm diameter) is the same compensation.
    let dynamic = centre(&text.replace("G41 G01 Y0 D1", "G41.1 G01 Y0 D4"), &settings);
    assert_eq!(dynamic.toolpath.moves, out.toolpath.moves);
    assert_eq!(dynamic.programmed.unwrap().kept[0].text, "G21 G41.1 D4.");
    // G41 without D: the loaded tool's radius.
    let loaded = centre(&text.replace("G41 G01 Y0 D1", "T1 M6\nG41 G01 Y0"), &settings);
    let shape = |p: &Toolpath| p.moves.iter().map(|m| (m.kind, m.end)).collect::<Vec<_>>();
    assert_eq!(shape(&loaded.toolpath), shape(&out.toolpath));
}

#[test]
fn g41_1_is_refused_with_fanuc_rules_and_twice_on_with_linuxcnc() {
    let (out, sources) = run("G41.1 D4. X1.\nM30\n", &Settings::default());
    let e = out.diagnostics[0].headline(&sources);
    assert!(e.contains("error: G41.1") && e.contains("LinuxCNC's"), "{e}");
    let lcnc = Settings { comp_rules: Rules::LinuxCnc, ..radii(&[(1, 2.0)]) };
    let (out, sources) = run("G41 D1\nG01 X10. F100.\nG42 D1\nM2\n", &lcnc);
    let e = out.diagnostics[0].headline(&sources);
    assert!(e.starts_with("t.nc:3:1: error: Cannot turn cutter radius comp on when on"), "{e}");
}

#[test]
fn kept_blocks_move_with_the_compensated_moves() {
    // An M01 between the outside corners: in the centre path it comes
    // before the move made for the programmed X20 (the corner vectors of
    // type C at an obtuse-or-right corner add no move, so the indices
    // agree here); the G41 and G40 blocks are not in the centre path.
    let text = SQUARE.replace("X20.\n", "M01\nX20.\n");
    let out = centre(&text, &radii(&[(1, 2.0)]));
    let kept: Vec<(usize, &str)> = out.toolpath.kept.iter().map(|k| (k.before, k.text.as_str())).collect();
    assert_eq!(kept, [(3, "M01")]);
    let programmed = out.programmed.unwrap();
    let kept: Vec<(usize, &str)> = programmed.kept.iter().map(|k| (k.before, k.text.as_str())).collect();
    assert_eq!(kept, [(1, "G41 D1"), (3, "M01"), (6, "G40")]);
}

#[test]
fn a_mirror_image_swaps_g41_and_g42() {
    // G51.1 X0 mirrors X: the square is cut on the other side of Y, in the
    // other direction, and the tool stays outside it: the centre path is the
    // mirror of the unmirrored one.
    let plain = centre(SQUARE, &radii(&[(1, 2.0)]));
    let mirrored = centre(&SQUARE.replacen("G00 X-10. Y-10.", "G51.1 X0\nG00 X-10. Y-10.", 1), &radii(&[(1, 2.0)]));
    let want: Vec<(f64, f64, bool)> = ends(&plain.toolpath).into_iter().map(|(x, y, r)| (-x, y, r)).collect();
    assert_ends(&mirrored.toolpath, &want);
}
