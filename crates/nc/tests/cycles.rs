//! Canned cycles, hand-derived: every move of each cycle under G98/G99,
//! G90/G91 and K/L repeats, worked out from the rules in
//! docs/canned-cycles.md and written here as the control would make them.

use kezuri_geom::{MoveKind, Spindle, Toolpath};
use kezuri_nc::interp::{CycleSettings, Outcome, Settings};
use kezuri_nc::write::{program, Dialect, WriteOptions};
use kezuri_nc::ErrorKind;

mod common;

fn run_with(text: &str, settings: &Settings) -> (Outcome, kezuri_nc::Sources) {
    let ran = common::run("t.nc", text, settings);
    (ran.outcome, ran.sources)
}

fn run(text: &str) -> Outcome {
    common::run("t.nc", text, &Settings::default()).completed()
}

/// The error that stopped the run, rendered with file:line:col.
fn error(text: &str) -> String {
    common::run("t.nc", text, &Settings::default()).rendered()
}

/// Each move as `R x y z` (rapid), `F x y z` (feed) or `D s` (dwell).
fn moves(path: &Toolpath) -> Vec<String> {
    let f = |v: f64| {
        let s = format!("{v:.3}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        if s == "-0" {
            "0".to_string()
        } else {
            s.to_string()
        }
    };
    path.moves
        .iter()
        .map(|m| match m.kind {
            MoveKind::Rapid => format!("R {} {} {}", f(m.end.x), f(m.end.y), f(m.end.z)),
            MoveKind::Feed => format!("F {} {} {}", f(m.end.x), f(m.end.y), f(m.end.z)),
            MoveKind::Dwell(s) => format!("D {}", f(s)),
            other => format!("{other:?}"),
        })
        .collect()
}

fn assert_moves(text: &str, want: &[&str]) -> Outcome {
    let outcome = run(text);
    assert_eq!(moves(&outcome.toolpath), want, "\n{text}");
    outcome
}

const START: &str = "G21 G17 G90 G94 G00 X0 Y0 Z50.\n";

#[test]
fn g81_g98_returns_to_the_initial_level_and_holes_are_modal() {
    let out = assert_moves(
        &format!("{START}G98 G81 X10. Y20. Z-5. R2. F100.\nX30.\nG80\nG00 Z60.\nM30\n"),
        &[
            "R 0 0 50",
            // Hole 1: position at the initial level, rapid to R, feed to Z, rapid back up.
            "R 10 20 50",
            "R 10 20 2",
            "F 10 20 -5",
            "R 10 20 50",
            // Hole 2: the same data at X30.
            "R 30 20 50",
            "R 30 20 2",
            "F 30 20 -5",
            "R 30 20 50",
            "R 30 20 60",
        ],
    );
    assert_eq!(out.holes, 2);
}

#[test]
fn g99_returns_to_r_and_the_next_hole_is_positioned_there() {
    assert_moves(
        &format!("{START}G99 G81 X10. Y20. Z-5. R2. F100.\nX30.\nG80\nM30\n"),
        &["R 0 0 50", "R 10 20 50", "R 10 20 2", "F 10 20 -5", "R 10 20 2", "R 30 20 2", "F 30 20 -5", "R 30 20 2"],
    );
}

#[test]
fn g91_r_from_the_initial_level_z_from_r_and_k_repeats_by_the_increment() {
    // Initial level 10; R = 10 - 8 = 2; bottom = 2 - 7 = -5; three holes 10 apart.
    assert_moves(
        "G21 G90 G00 X0 Y0 Z10.\nG91 G99 G81 X10. Z-7. R-8. K3 F100.\nG90 G80\nM30\n",
        &[
            "R 0 0 10",
            "R 10 0 10",
            "R 10 0 2",
            "F 10 0 -5",
            "R 10 0 2",
            "R 20 0 2",
            "F 20 0 -5",
            "R 20 0 2",
            "R 30 0 2",
            "F 30 0 -5",
            "R 30 0 2",
        ],
    );
}

#[test]
fn haas_l_repeats_and_k0_stores_the_data_without_drilling() {
    assert_moves(
        &format!("{START}G98 G81 X10. Y0 Z-5. R2. F100. K0\nX20.\nG91 X5. L2\nG90 G80\nM30\n"),
        &[
            "R 0 0 50",
            "R 20 0 50",
            "R 20 0 2",
            "F 20 0 -5",
            "R 20 0 50",
            "R 25 0 50",
            "R 25 0 2",
            "F 25 0 -5",
            "R 25 0 50",
            "R 30 0 50",
            "R 30 0 2",
            "F 30 0 -5",
            "R 30 0 50",
        ],
    );
}

#[test]
fn g83_returns_to_r_after_each_peck_and_rapids_to_the_clearance() {
    // R 2, bottom -10, Q 4, clearance d 0.1: pecks to -2, -6, -10.
    assert_moves(
        &format!("{START}G98 G83 X5. Y5. Z-10. R2. Q4. F100.\nG80\nM30\n"),
        &[
            "R 0 0 50",
            "R 5 5 50",
            "R 5 5 2",
            "F 5 5 -2",
            "R 5 5 2",
            "R 5 5 -1.9",
            "F 5 5 -6",
            "R 5 5 2",
            "R 5 5 -5.9",
            "F 5 5 -10",
            "R 5 5 50",
        ],
    );
}

#[test]
fn g73_retracts_by_d_between_pecks() {
    let settings =
        Settings { cycles: CycleSettings { peck_retract: 0.5, ..CycleSettings::default() }, ..Settings::default() };
    let text = format!("{START}G99 G73 X5. Y5. Z-9. R1. Q4. F100.\nG80\nM30\n");
    let (outcome, _) = run_with(&text, &settings);
    // Pecks to -3, -7, then the last 2 to -9; each retract 0.5 up.
    assert_eq!(
        moves(&outcome.toolpath),
        ["R 0 0 50", "R 5 5 50", "R 5 5 1", "F 5 5 -3", "R 5 5 -2.5", "F 5 5 -7", "R 5 5 -6.5", "F 5 5 -9", "R 5 5 1"]
    );
}

#[test]
fn g82_and_g89_dwell_at_the_bottom_g85_and_g89_feed_out() {
    // Fanuc P is milliseconds.
    assert_moves(
        &format!("{START}G98 G82 X1. Y1. Z-3. R2. P500 F100.\nG80\nM30\n"),
        &["R 0 0 50", "R 1 1 50", "R 1 1 2", "F 1 1 -3", "D 0.5", "R 1 1 50"],
    );
    assert_moves(
        &format!("{START}G98 G85 X1. Y1. Z-3. R2. F100.\nG80\nM30\n"),
        &["R 0 0 50", "R 1 1 50", "R 1 1 2", "F 1 1 -3", "F 1 1 2", "R 1 1 50"],
    );
    assert_moves(
        &format!("{START}G99 G89 X1. Y1. Z-3. R2. P250 F100.\nG80\nM30\n"),
        &["R 0 0 50", "R 1 1 50", "R 1 1 2", "F 1 1 -3", "D 0.25", "F 1 1 2"],
    );
}

#[test]
fn g86_stops_the_spindle_for_the_rapid_out_and_starts_it_again() {
    let out = assert_moves(
        &format!("{START}S1000 M03\nG98 G86 X1. Y1. Z-3. R2. F100.\nG80 G00 X0\nM30\n"),
        &["R 0 0 50", "R 1 1 50", "R 1 1 2", "F 1 1 -3", "R 1 1 50", "R 0 1 50"],
    );
    let spindles: Vec<Spindle> = out.toolpath.moves.iter().map(|m| m.spindle).collect();
    assert_eq!(spindles[3], Spindle::Cw);
    assert_eq!(spindles[4], Spindle::Off);
    assert_eq!(spindles[5], Spindle::Cw);
}

#[test]
fn g84_reverses_the_spindle_at_the_bottom_and_is_written_as_a_cycle() {
    let text = format!("{START}S500 M03\nG98 G84 X10. Y10. Z-8. R3. F625.\nX20.\nG80\nG00 X0\nM30\n");
    let out = assert_moves(
        &text,
        &[
            "R 0 0 50",
            "R 10 10 50",
            "R 10 10 3",
            "F 10 10 -8",
            "F 10 10 3",
            "R 10 10 50",
            "R 20 10 50",
            "R 20 10 3",
            "F 20 10 -8",
            "F 20 10 3",
            "R 20 10 50",
            "R 0 10 50",
        ],
    );
    let spindles: Vec<Spindle> = out.toolpath.moves[3..5].iter().map(|m| m.spindle).collect();
    assert_eq!(spindles, [Spindle::Cw, Spindle::Ccw]);
    assert_eq!(out.toolpath.kept.len(), 2);
    let written = program(&out.toolpath, &WriteOptions::default()).unwrap();
    // One cycle, as the program gave it: the second hole goes on in it.
    assert!(
        written.contains("G21 G90 G98 G84 X10. Y10. Z-8. R3. F625.\nG98 G84 X20. Y10. Z-8. R3. F625.\nG80\n"),
        "{written}"
    );
    // The tapping moves themselves are not written: no feed to Z-8 outside the cycle.
    assert!(!written.lines().any(|l| l.starts_with("G01") && l.contains("Z-8.")), "{written}");
    // Read back, the cycle makes the same motions.
    assert_eq!(moves(&run(&written).toolpath), moves(&out.toolpath), "{written}");
    // GRBL has no tapping cycle: refused, with the line.
    let grbl = program(&out.toolpath, &WriteOptions { dialect: Dialect::Grbl, ..WriteOptions::default() });
    let e = grbl.unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unsupported, "{e}");
    assert!(e.to_string().contains("line 3"));
}

#[test]
fn g74_taps_left_hand() {
    let out = run(&format!("{START}S500 M04\nG99 G74 X1. Y1. Z-8. R3. F625.\nG80\nM30\n"));
    let spindles: Vec<Spindle> = out.toolpath.moves[3..5].iter().map(|m| m.spindle).collect();
    assert_eq!(spindles, [Spindle::Ccw, Spindle::Cw]);
}

#[test]
fn g76_shifts_off_the_wall_before_the_retract() {
    // Shift Q 0.2 along +X (the default direction), out at rapid, back on centre.
    assert_moves(
        &format!("{START}S800 M03\nG98 G76 X10. Y10. Z-12. R2. Q0.2 P100 F50.\nG80\nM30\n"),
        &["R 0 0 50", "R 10 10 50", "R 10 10 2", "F 10 10 -12", "D 0.1", "R 10.2 10 -12", "R 10.2 10 50", "R 10 10 50"],
    );
}

#[test]
fn g87_bores_upward_from_below() {
    // Shifted by I -0.3, down to R -20 below the part, centred, bore up to Z -5,
    // shifted again, out to the initial level, centred.
    assert_moves(
        &format!("{START}S800 M03\nG98 G87 X10. Y10. Z-5. R-20. I-0.3 F50.\nG80\nM30\n"),
        &[
            "R 0 0 50",
            "R 10 10 50",
            "R 9.7 10 50",
            "R 9.7 10 -20",
            "R 10 10 -20",
            "F 10 10 -5",
            "R 9.7 10 -5",
            "R 9.7 10 50",
            "R 10 10 50",
        ],
    );
}

#[test]
fn a_group_1_code_ends_the_cycle() {
    assert_moves(
        &format!("{START}G99 G81 X1. Y1. Z-3. R2. F100.\nG00 X5.\nM30\n"),
        &["R 0 0 50", "R 1 1 50", "R 1 1 2", "F 1 1 -3", "R 1 1 2", "R 5 1 2"],
    );
}

#[test]
fn g18_drills_along_y() {
    // In G18 the drilling axis is Y: the hole is placed in Z and X.
    let out = run("G21 G18 G90 G00 X0 Y50. Z0\nG98 G81 X10. Z5. Y-4. R2. F100.\nG80\nM30\n");
    let ends: Vec<[f64; 3]> = out.toolpath.moves.iter().map(|m| m.end.xyz()).collect();
    assert_eq!(ends, [[0.0, 50.0, 0.0], [10.0, 50.0, 5.0], [10.0, 2.0, 5.0], [10.0, -4.0, 5.0], [10.0, 50.0, 5.0]]);
}

#[test]
fn inch_cycles_are_in_inches() {
    let out = run("G20 G90 G00 X0 Y0 Z1.\nG99 G81 X1. Y0 Z-0.1 R0.1 F10.\nG80\nM30\n");
    let last = out.toolpath.moves.last().unwrap();
    assert!((last.end.z - 2.54).abs() < 1e-12 && (out.toolpath.moves[3].end.z + 2.54).abs() < 1e-12);
}

#[test]
fn a_1000_hole_peck_program_expands() {
    let mut text = String::from(START);
    text.push_str("G99 G83 X0 Y0 Z-20. R0 Q2. F200.\n");
    for k in 1..1000 {
        text.push_str(&format!("X{}. Y{}.\n", k % 40, k / 40));
    }
    text.push_str("G80\nM30\n");
    let out = run(&text);
    assert_eq!(out.holes, 1000);
    // Each hole: 20 mm from R0 in pecks of 2: 10 feeds.
    let feeds = out.toolpath.moves.iter().filter(|m| m.kind == MoveKind::Feed).count();
    assert_eq!(feeds, 10_000);
}

#[test]
fn bad_cycles_are_located_errors() {
    let e = error(&format!("{START}G83 X1. Y1. Z-5. R2. Q0 F100.\nM30\n"));
    assert!(e.contains("t.nc:2:22") && e.contains("peck depth Q greater than 0"), "{e}");
    let e = error(&format!("{START}G99 G81 X1. Y1. Z5. R2. F100.\nM30\n"));
    assert!(e.contains("t.nc:2:17") && e.contains("above its R level"), "{e}");
    let e = error(&format!("{START}G81 X1. Y1. R2. F100.\nM30\n"));
    assert!(e.contains("t.nc:2:") && e.contains("bottom of the hole"), "{e}");
    let e = error(&format!("{START}G81 X1. Y1. Z-2. F100.\nM30\n"));
    assert!(e.contains("needs the R level"), "{e}");
    let e = error(&format!("{START}G81 X1. Y1. Z-2. R1. K2 L2 F100.\nM30\n"));
    assert!(e.contains("not both"), "{e}");
    let e = error(&format!("{START}G81 X1. Y1. Z-2. R1. K1.5 F100.\nM30\n"));
    assert!(e.contains("repeat count"), "{e}");
    let e = error(&format!("{START}G76 X1. Y1. Z-2. R1. F100.\nM30\n"));
    assert!(e.contains("shift"), "{e}");
}

#[test]
fn keep_cycles_writes_every_cycle_as_a_cycle_block() {
    let settings = Settings { cycles: CycleSettings { keep: true, ..CycleSettings::default() }, ..Settings::default() };
    let text = format!("{START}G98 G83 X5. Y5. Z-10. R2. Q4. F100.\nG80\nM30\n");
    let (outcome, _) = run_with(&text, &settings);
    let written = program(&outcome.toolpath, &WriteOptions::default()).unwrap();
    assert!(written.contains("G21 G90 G98 G83 X5. Y5. Z-10. R2. Q4. F100.\nG80\n"), "{written}");
    assert_eq!(moves(&run(&written).toolpath), moves(&outcome.toolpath), "{written}");
}

#[test]
fn a_g98_hole_after_g99_holes_returns_to_the_cycle_s_initial_level_when_written() {
    // The last hole clears the clamps: G98 after G99 holes goes back to Z50,
    // the level where the cycle began, in the source and in what is written.
    let text = "G21 G90 G00 X0 Y0 Z50.\nS500 M03\nM29 S500\nG99 G84 X0 Y0 Z-10. R2. F500.\nX10.\nG98 X20.\nG80\nG00 X100.\nM30\n";
    let out = run(text);
    assert_eq!(out.toolpath.moves.last().unwrap().end.z, 50.0);
    let written = program(&out.toolpath, &WriteOptions::default()).unwrap();
    // Rigid tapping once, the holes in one cycle, G80 after the last.
    assert!(
        written.contains("M29 S500\nG21 G90 G99 G84 X0. Y0. Z-10. R2. F500.\nG99 G84 X10. Y0. Z-10. R2. F500.\nG98 G84 X20. Y0. Z-10. R2. F500.\nG80\n"),
        "{written}"
    );
    assert_eq!(moves(&run(&written).toolpath), moves(&out.toolpath), "{written}");
}

#[test]
fn a_kept_hole_under_g92_is_written_from_the_program_s_zero() {
    // G92 X0 Y0 at (10, 10): the tap at X5 Y0 is machine (15, 10); the kept
    // G92 is written again, so the hole's words are the program's own.
    let text =
        "G21 G90 G54 G00 X10. Y10. Z50.\nG92 X0 Y0\nS500 M03\nG98 G84 X5. Y0 Z-10. R2. F500.\nG80\nG00 X0 Y0\nM30\n";
    let out = run(text);
    let written = program(&out.toolpath, &WriteOptions::default()).unwrap();
    assert!(written.contains("G98 G84 X5. Y0. Z-10. R2. F500."), "{written}");
    assert_eq!(moves(&run(&written).toolpath), moves(&out.toolpath), "{written}");
}

#[test]
fn cycles_with_compensation_or_inverse_time_are_refused() {
    let e = error(&format!("{START}G41 D1 G01 X1. Y1. F100.\nG81 X5. Y5. Z-2. R1.\nM30\n"));
    assert!(e.contains("G40 first"), "{e}");
    let e = error(&format!("{START}G93\nG81 X5. Y5. Z-2. R1. F2.\nM30\n"));
    assert!(e.contains("G94 first"), "{e}");
}

#[test]
fn spindle_coolant_and_m_codes_between_kept_holes_leave_the_cycle_on() {
    // M08, M10 and S600 between taps: the cycle goes on (one G80 at the end),
    // the G98 hole returns to Z50 where the cycle began, M29 given once.
    let text = "G21 G90 G00 X0 Y0 Z50.\nS500 M03\nM29 S500\nG99 G84 X0 Y0 Z-10. R2. F500.\nM08\nM10\nX10.\nS600\nG98 X20.\nG80\nG00 X100.\nM30\n";
    let out = run(text);
    let written = program(&out.toolpath, &WriteOptions::default()).unwrap();
    assert_eq!(written.matches("G80").count(), 2, "{written}"); // the safe start's and one after the holes
    assert_eq!(written.matches("M29").count(), 1, "{written}");
    assert_eq!(moves(&run(&written).toolpath), moves(&out.toolpath), "{written}");
}

#[test]
fn a_tap_after_drilled_holes_keeps_the_whole_cycle() {
    // G81 holes then a G98 tap without G80: the tap returns to the level
    // where the drilling began (Z50); written, the holes are one cycle.
    let text = "G21 G90 G00 X0 Y0 Z50.\nS500 M03\nG99 G81 X0 Y0 Z-5. R2. F100.\nX10.\nG98 G84 X20. Z-10. F500.\nG80\nG00 X100.\nM30\n";
    let out = run(text);
    assert_eq!(out.toolpath.moves.last().unwrap().end.z, 50.0);
    let written = program(&out.toolpath, &WriteOptions::default()).unwrap();
    assert!(written.contains("G21 G90 G99 G81 X0. Y0. Z-5. R2. F100.\nG99 G81 X10."), "{written}");
    assert!(written.contains("G98 G84 X20. Y0. Z-10. R2. F500.\nG80\n"), "{written}");
    assert_eq!(moves(&run(&written).toolpath), moves(&out.toolpath), "{written}");
}
