//! An expanded program (`kezuri run --emit`) run again on the same machine
//! makes the same motions as the original: offsets are commanded again, not
//! baked in, and returns to the reference point stay returns.

use std::collections::BTreeMap;

use kezuri_geom::{Axes, MoveKind, Toolpath};
use kezuri_nc::interp::{IntegerInput, Settings};
use kezuri_nc::write::{program, Dialect, WriteOptions};

mod common;

fn run(text: &str, settings: &Settings) -> Toolpath {
    common::run("t.nc", text, settings).path()
}

/// Settings to read a program of `dialect` with: LinuxCNC and GRBL read
/// `X10` as 10 mm.
fn read_back(dialect: Dialect, settings: &Settings) -> Settings {
    let integer_input = if dialect == Dialect::Fanuc { IntegerInput::Increments } else { IntegerInput::Units };
    Settings { integer_input, ..settings.clone() }
}

fn at(x: f64, y: f64, z: f64) -> Axes {
    Axes { x, y, z, ..Axes::ZERO }
}

/// A machine whose offsets are all different and far from zero.
fn machine() -> Settings {
    let mut work_offsets = [Axes::ZERO; 6];
    work_offsets[0] = at(10.0, 20.0, -100.0);
    work_offsets[1] = at(200.0, 20.0, -100.0);
    Settings {
        tool_lengths: BTreeMap::from([(1, 100.0), (2, 80.0)]),
        work_offsets,
        home: at(-500.0, -400.0, 0.0),
        ..Settings::default()
    }
}

const PROGRAM: &str = "O0001
G21 G90 G94 G17 G54
T1 M06
G43 H1 Z50.
G00 X10. Y10.
G01 Z-1. F100.
X20.
G02 X30. R5.
G55
G00 X0 Y0
G01 Z-2.
#5221=5.
#5222=5.
#5223=-90.
G54 G00 X1. Y1.
G92 X0 Y0
G00 X2.
G91 G28 Z0.
G90
T2 M06
G44 H2 Z20.
G53 G00 Z-10.
G49
G28 X0 Y0
M30
";

fn same(want: &Toolpath, got: &Toolpath, written: &str) {
    let kinds = |t: &Toolpath| t.moves.iter().map(|m| std::mem::discriminant(&m.kind)).collect::<Vec<_>>();
    assert_eq!(kinds(want), kinds(got), "\n{written}");
    for (k, (w, g)) in want.moves.iter().zip(&got.moves).enumerate() {
        let (we, ge) = (w.end.to_array(), g.end.to_array());
        assert!((0..6).all(|i| (we[i] - ge[i]).abs() < 6e-4), "move {k}: {:?} vs {:?}\n{written}", w.end, g.end);
        assert_eq!(want.frame(w).length.map(|l| l.register), got.frame(g).length.map(|l| l.register));
        assert_eq!(want.frame(w).work, got.frame(g).work);
    }
}

#[test]
fn expanded_program_makes_the_same_motions_on_the_same_machine() {
    let settings = machine();
    let original = run(PROGRAM, &settings);
    assert!(original.moves.iter().any(|m| matches!(m.kind, MoveKind::Home)));
    assert!(original.moves.iter().any(|m| matches!(m.kind, MoveKind::Machine)));
    for dialect in [Dialect::Fanuc, Dialect::LinuxCnc] {
        let written = program(&original, &WriteOptions { dialect, ..WriteOptions::default() }).unwrap();
        same(&original, &run(&written, &read_back(dialect, &settings)), &written);
    }
}

#[test]
fn offsets_and_returns_are_commanded_not_baked_in() {
    let written = program(&run(PROGRAM, &machine()), &WriteOptions::default()).unwrap();
    let lines: Vec<&str> = written.lines().collect();
    let expected = [
        "G43 H1",
        "G55",
        // `#5221=5.` and the others: the offsets the program set, as G10.
        "G21 G90 G10 L2 P1 X5.",
        "G21 G90 G10 L2 P1 Y5.",
        "G21 G90 G10 L2 P1 Z-90.",
        "G54",
        "G91 G28 Z0.",
        "G44 H2",
        "G49",
    ];
    for expected in expected {
        assert!(lines.contains(&expected), "no '{expected}' in\n{written}");
    }
    // G53 Z-10. is the gauge line in machine coordinates, whatever the offset.
    assert!(lines.contains(&"G53 G00 Z-10."), "{written}");
    // No move goes to the work zero of Z that the original never commanded.
    assert!(!lines.iter().any(|l| l.starts_with("G00") && l.ends_with(" Z0.")), "{written}");
}

#[test]
fn grbl_writes_the_length_offset_itself() {
    let text = "G21 G90\nG43 H1 Z5.\nG01 X1. F100.\nG49\nM30\n";
    let settings = Settings { tool_lengths: BTreeMap::from([(1, 42.5)]), ..Settings::default() };
    let written =
        program(&run(text, &settings), &WriteOptions { dialect: Dialect::Grbl, ..WriteOptions::default() }).unwrap();
    assert!(written.contains("G43.1 Z42.5\n"), "{written}");
    // Read back without a tool table, the motions are the same.
    let back = read_back(Dialect::Grbl, &settings);
    same(&run(text, &settings), &run(&written.replace("G43.1 Z42.5", "G43 H1"), &back), &written);
}

#[test]
fn inch_output_makes_the_same_motions() {
    let settings = machine();
    let original = run(PROGRAM, &settings);
    let written = program(&original, &WriteOptions { inch: true, digits: 5, ..WriteOptions::default() }).unwrap();
    assert!(written.lines().nth(2).unwrap().starts_with("G20 G90"), "{written}");
    // 5 decimals of an inch are 0.000254 mm.
    same(&original, &run(&written, &settings), &written);
}

/// Another machine: other offsets, tool lengths and reference point.
fn other_machine() -> Settings {
    let mut work_offsets = [Axes::ZERO; 6];
    work_offsets[0] = at(-250.0, 75.0, -320.0);
    work_offsets[1] = at(40.0, -60.0, -280.0);
    Settings {
        tool_lengths: BTreeMap::from([(1, 123.4), (2, 55.5)]),
        work_offsets,
        home: at(10.0, 20.0, 30.0),
        ..Settings::default()
    }
}

/// A program expanded with one machine file and run on another makes the
/// same motions as the source run on that other machine.
fn portable(text: &str) -> String {
    let written = program(&run(text, &machine()), &WriteOptions::default()).unwrap();
    same(&run(text, &other_machine()), &run(&written, &other_machine()), &written);
    written
}

#[test]
fn an_increment_after_a_reference_return_stays_an_increment() {
    // Expanded as `G90 G01 Z290.` from the machine file's G54, this plunged
    // wherever another machine's offset put Z 290.
    let written =
        portable("G90 G54 G00 X10. Y10. Z50.\nG91 G28 X0 Y0 Z0\nG91 G01 Z-10. F100.\nX5.\nG90 G00 Z60.\nM30\n");
    assert!(written.contains("G91 G01 Z-10. F100.\n"), "{written}");
    assert!(written.contains("X5.\n"), "{written}");
}

#[test]
fn increments_from_where_the_program_starts_stay_increments() {
    portable("G91 G01 X10. Y-5. F200.\nG02 X10. I5.\nG90 G00 Z5.\nM30\n");
}

#[test]
fn increments_after_g53_a_new_work_offset_and_a_tool_change_stay_increments() {
    portable(
        "G90 G54 G00 X0 Y0 Z10.\nG53 G00 Z0\nG91 G00 Z-20.\nG90 G55\nG91 G01 X3. F100.\n\
         T1 M06\nG91 G00 Y4.\nG90 G43 H1 Z5.\nG91 Z-1.\nM30\n",
    );
}

#[test]
fn work_offsets_the_program_sets_are_set_again() {
    // `G10 L2 P1 X10.` puts G54's zero at machine X 10 on any machine.
    let written =
        portable("G10 L2 P1 X10. Y0 Z-50.\nG90 G54 G00 X0 Y0 Z5.\nG01 X5. F100.\nG91 G10 L2 P1 X2.\nG90 G00 X0\nM30\n");
    assert!(written.contains("G21 G90 G10 L2 P1 X10. Y0. Z-50.\n"), "{written}");
    assert!(written.contains("G21 G91 G10 L2 P1 X2.\n"), "{written}");
}

#[test]
fn m_codes_the_machine_needs_are_kept_in_place() {
    let written = portable("G90 G00 X0 Y0 Z5.\nM11\nG00 B90.\nM10\nM13\nG01 Z-1. F100.\nM01\nM19\nM30\n");
    let at = |code: &str| written.find(code).unwrap_or_else(|| panic!("no {code} in\n{written}"));
    assert!(at("M11") < at("B90.") && at("B90.") < at("M10") && at("M10") < at("M13"), "{written}");
    assert!(at("Z-1.") < at("M01") && at("M01") < at("M19"), "{written}");
}

#[test]
fn smoothing_and_path_modes_are_kept_and_g92_1_cancels_the_shift() {
    let text = "G90 G00 X0 Y0 Z5.\nG05.1 Q1\nG08 P1\nG187 P2 E0.01\nG64\nG92 X10.\nG01 X12. F100.\nG92.1 X0\nG01 X5.\nG05.1 Q0\nM30\n";
    let written = portable(text);
    for code in ["G05.1 Q1\n", "G08 P1\n", "G187 P2 E0.01\n", "G64\n", "G05.1 Q0\n"] {
        assert!(written.contains(code), "no {code} in\n{written}");
    }
    // G92 X10. at X0 puts the work zero at machine X -10: X12. is machine X 2;
    // G92.1 cancels the shift: X5. is machine X 5.
    let ends: Vec<f64> = run(text, &Settings::default()).moves.iter().map(|m| m.end.x).collect();
    assert_eq!(ends, [0.0, 2.0, 5.0]);
}

#[test]
fn kept_blocks_keep_their_place_among_tool_changes_and_coolant() {
    // M01 before the tool change, M11 after it, M19 and M62 before M08.
    let text = "G90 G00 X0 Y0 Z5.\nM01\nT2 M06\nM11\nG00 B90.\nM19 R90.\nM62 P1\nG01 X1. M08 F100.\nM30\n";
    let written = portable(text);
    let at = |code: &str| written.find(code).unwrap_or_else(|| panic!("no {code} in\n{written}"));
    assert!(at("M01") < at("T2 M06") && at("T2 M06") < at("M11") && at("M11") < at("B90."), "{written}");
    assert!(at("M19 R90.") < at("M62 P1") && at("M62 P1") < at("M08"), "{written}");
}

#[test]
fn offsets_set_through_variables_are_written_as_g10() {
    // #5201 (the external offset), #7001 (G54.1 P1's X), #2001 (H1).
    let written = portable("#5201=10.\n#7001=-20.\n#2001=55.5\nG90 G54 G00 X0 Y0 Z5.\nG43 H1 Z10.\nM30\n");
    for line in ["G21 G90 G10 L2 P0 X10.\n", "G21 G90 G10 L20 P1 X-20.\n", "G21 G90 G10 L10 P1 R55.5\n"] {
        assert!(written.contains(line), "no {line} in\n{written}");
    }
}

/// A Haas machine: the control's rules, G154 P1, three tools, D1.
fn haas(offset: Axes, lengths: [f64; 3], home: Axes) -> Settings {
    use kezuri_nc::interp::{Control, CoordSettings};
    Settings {
        coords: CoordSettings { control: Control::Haas, ..CoordSettings::default() },
        tool_lengths: BTreeMap::from([(1, lengths[0]), (2, lengths[1]), (3, lengths[2])]),
        tool_radii: BTreeMap::from([(1, 5.0)]),
        extra_work_offsets: BTreeMap::from([(1, offset)]),
        home,
        ..Settings::default()
    }
}

#[test]
fn a_haas_job_with_cycles_compensation_and_a_local_subprogram_runs_the_same_on_another_machine() {
    // A program in the style of a CAM post for Haas (testdata/shop): G154 P1,
    // G43 H, G187, G41 D1, M97, G83 and rigid G84 holes, G53 and G28 returns.
    let text = include_str!("../testdata/shop/haas_bracket.nc");
    let a = haas(at(-300.0, -200.0, -400.0), [120.0, 95.5, 101.2], at(0.0, 0.0, 0.0));
    let b = haas(at(-512.5, -133.25, -377.0), [88.0, 140.25, 77.7], at(-20.0, 15.0, 5.0));
    // What `kezuri run` writes: the programmed contour, with its G41 D1.
    let on_a = common::run("haas_bracket.nc", text, &a).completed();
    let programmed = on_a.programmed.expect("the contour with G41 D1");
    assert_eq!(programmed.kept.iter().filter(|k| k.cycle.is_some()).count(), 3, "three taps kept");
    let written = program(&programmed, &WriteOptions::default()).unwrap();
    for line in
        ["G54.1 P1\n", "G187 P2 E0.02\n", "G41 D1\n", "M29 S500\n", "G98 G84 X50. Y30. Z-10. R3. F625.\nG80\n", "M01\n"]
    {
        assert!(written.contains(line), "no {line} in\n{written}");
    }
    same(&run(text, &b), &run(&written, &b), &written);
}
