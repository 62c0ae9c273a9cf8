//! LinuxCNC's motion words in the linuxcnc dialect: polar `@ ^`, G4 in a
//! block with motion, G10 L1/L10/L11/L20, G43.1/G43.2, G64 P Q, M98/M99.
//! Each expectation comes from LinuxCNC's manual and was confirmed with
//! `rs274 -g` (LinuxCNC 2.9.0~pre1) on the same program, then written here
//! by hand: the tests pass without `rs274`. G33.1 and G76 threading are in
//! `linuxcnc_threading.rs`.

mod common;

use common::linuxcnc::{error, moves, path, path_with, run_with, settings};
use kezuri_geom::{MoveKind, Toolpath};
use kezuri_nc::interp::{self, Control, Settings};
use kezuri_nc::{parse_as, Dialect, Program, SourceFile, Sources};

// ---- polar coordinates ----

#[test]
fn polar_absolute_is_about_the_xy_zero() {
    // rs274: G1 @10 ^30 -> (8.6603, 5); from (3, 4) `^90` keeps the radius 5
    // -> (0, 5); `@10` keeps the angle -> (0, 10); with Z.
    let t = path("G21 G90 G1 F100 @10 ^30\nG0 X3 Y4\n^90\n@10\nG1 @2 ^60 Z-1\nM2\n");
    assert_eq!(
        moves(&t),
        [
            ('f', 8.6603, 5.0, 0.0),
            ('r', 3.0, 4.0, 0.0),
            ('r', 0.0, 5.0, 0.0),
            ('r', 0.0, 10.0, 0.0),
            ('f', 1.0, 1.7321, -1.0),
        ]
    );
}

#[test]
fn polar_incremental_adds_to_the_radius_and_the_angle() {
    // The manual's "polar square": G91 ^90 turns about the XY zero by 90°
    // and keeps the radius; its "spiral": G91 @.5 ^90 adds 0.5 each time.
    // rs274: (0, .5) (-.5, 0) (0, -.5) (.5, 0); then (0, 1) (-1.5, 0) …
    let square = path("G21 F100 G1 @.5 ^90\nG91 ^90\n^90\n^90\nM2\n");
    assert_eq!(
        moves(&square),
        [('f', 0.0, 0.5, 0.0), ('f', -0.5, 0.0, 0.0), ('f', 0.0, -0.5, 0.0), ('f', 0.5, 0.0, 0.0)]
    );
    let spiral = path("G21 F100 G1 @.5 ^90\nG91 @.5 ^90\n@.5 ^90\n@.5 ^90\nM2\n");
    assert_eq!(
        moves(&spiral),
        [('f', 0.0, 0.5, 0.0), ('f', -1.0, 0.0, 0.0), ('f', 0.0, -1.5, 0.0), ('f', 2.0, 0.0, 0.0)]
    );
    // rs274: from (1, 1.7321, -1) `G91 @2 Z1` -> (2, 3.4641, 0).
    let t = path("G21 G90 G1 F100 @2 ^60 Z-1\nG91 @2 Z1\nM2\n");
    assert_eq!(moves(&t)[1], ('f', 2.0, 3.4641, 0.0));
}

#[test]
fn polar_is_in_program_units_and_from_the_work_zero() {
    // G20: @1 is an inch; the angle is about the G54/G92 zero, not the
    // machine's (rs274: G92 X0 Y0 at (10, 0), then @5 ^90 -> (10, 5)).
    let t = path("G20 G0 @1 ^90\nM2\n");
    assert_eq!(moves(&t), [('r', 0.0, 25.4, 0.0)]);
    let t = path("G21 G0 X10 Y0\nG92 X0 Y0\nG0 @5 ^90\nM2\n");
    assert_eq!(moves(&t)[1], ('r', 10.0, 5.0, 0.0));
}

#[test]
fn polar_on_an_arc_names_its_end() {
    // rs274: G2 @10 ^0 R5 from the origin -> ARC_FEED to (10, 0).
    let t = path("G21 G1 F100 X0 Y0\nG2 @10 ^0 R5\nM2\n");
    assert_eq!(moves(&t)[1], ('a', 10.0, 0.0, 0.0));
}

#[test]
fn polar_in_canned_cycles_as_linuxcncs_polar_ngc() {
    // The constructs of LinuxCNC's ncfiles/polar.ngc (in mm here): `^120`
    // alone repeats the G81 at the same radius; G91 G81 @10 … L3 steps out
    // along the ray; G91 G81 ^[360/6] … L6 turns about the XY zero.
    // rs274 on the same lines: holes at (50, 0), (-25, 43.3013),
    // (10, 0)→(20, 0) (30, 0) (40, 0); (-20, 34.641) … (40, 0).
    let t = path(
        "G21 G90 G99 G0 X50 Y0 Z5\nG81 R1 Z-2 F100\n^120\nG80\nG0 X10 Y0\n\
         G91 G81 @10 R1 Z-3 L3\nG90 G80 G0 X40 Y0 Z5\nG91 G81 ^[360/6] R1 Z-3 L6\nG90 G80\nM2\n",
    );
    let holes: Vec<(f64, f64)> = moves(&t).iter().filter(|m| m.0 == 'f').map(|m| (m.1, m.2)).collect();
    assert_eq!(
        holes,
        [
            (50.0, 0.0),
            (-25.0, 43.3013),
            (20.0, 0.0),
            (30.0, 0.0),
            (40.0, 0.0),
            (20.0, 34.641),
            (-20.0, 34.641),
            (-40.0, 0.0),
            (-20.0, -34.641),
            (20.0, -34.641),
            (40.0, 0.0),
        ]
    );
}

#[test]
fn polar_errors_are_linuxcncs() {
    // rs274: "Cannot specify both polar coordinate and X word".
    assert_eq!(
        error("G21 G1 F100 @10 X1\nM2\n"),
        "t.ngc:1:17: error: X with a polar word (@ ^): give the point in X Y or in @ ^, not both"
    );
    // rs274: "Incremental motion with polar coordinates is indeterminate when at the origin".
    assert!(error("G21 G91 G1 F100 @10\nM2\n").starts_with("t.ngc:1:17: error: an incremental (G91) polar move"));
    assert!(error("G21 G91 G81 R1 Z-1 F100 ^10\nM2\n").contains("polar move cannot start at the XY zero"));
    // rs274: "Cannot use polar coordinate except in G17 plane".
    assert_eq!(error("G21 G18 G0 @5 ^90\nM2\n"), "t.ngc:1:12: error: polar words (@ ^) need the XY plane (G17)");
    // rs274: "Polar coordinates can only be used for motion" (G28, G92, G10);
    // "Cannot use polar coordinates with G53".
    for code in ["G28", "G92", "G10 L2 P1"] {
        let e = error(&format!("G21 G0 X1 Y1\n{code} @5 ^90\nM2\n"));
        assert!(e.starts_with("t.ngc:2:1: error: polar words (@ ^) are for motion only"), "{code}: {e}");
    }
    assert!(error("G21 G53 G0 @5\nM2\n").contains("G53 cannot take polar words"));
    // A word without a value, and the word in the Fanuc dialect.
    assert!(error("G21 G0 @\nM2\n").contains("address @ has no value"));
    let mut program = Program::default();
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("t.nc", "G0 @5\n"));
    let d = parse_as(&mut program, file, "G0 @5\n", Dialect::Fanuc);
    assert_eq!(
        d[0].headline(&sources),
        "t.nc:1:4: error: '@' (a polar radius) is a LinuxCNC word: give --dialect linuxcnc to read it"
    );
}

// ---- G4 in a block with motion ----

#[test]
fn g4_dwells_before_the_blocks_motion() {
    // LinuxCNC's order of execution: dwell (G4) before motion, whatever the
    // order of the words; the motion is the mode in force when the block
    // names none. rs274: FEED (0,0), DWELL(1), FEED (5,5); a cycle: DWELL(2)
    // then the hole; M3 before the dwell.
    let t = path("G21 G1 F100 X0\nG4 P1 X5 Y5\nM2\n");
    assert_eq!(moves(&t), [('f', 0.0, 0.0, 0.0), ('d', 1.0, 0.0, 0.0), ('f', 5.0, 5.0, 0.0)]);
    let t = path("G21 G0 X1\nG81 R1 Z-1 X2 F100 G4 P2\nM2\n");
    assert_eq!(
        moves(&t),
        [
            ('r', 1.0, 0.0, 0.0),
            ('d', 2.0, 0.0, 0.0),
            ('r', 1.0, 0.0, 1.0),
            ('r', 2.0, 0.0, 1.0),
            ('f', 2.0, 0.0, -1.0),
            ('r', 2.0, 0.0, 1.0),
        ]
    );
    let t = path("G21 G0 X1\nG1 X3 F100 G4 P2 M3 S1000\nM2\n");
    assert_eq!(t.moves[1].kind, MoveKind::Dwell(2.0));
    assert_eq!(t.moves[1].spindle, kezuri_geom::Spindle::Cw);
    // rs274: "Dwell time missing with g4" (LinuxCNC has no X dwell).
    assert_eq!(
        error("G21 G4 X5 Y5\nM2\n"),
        "t.ngc:1:5: error: G4 needs P, the dwell in seconds (LinuxCNC reads no X dwell)"
    );
}

// ---- G10 L1, L10, L11, L20 ----

/// The length offset in force (mm) at the end of each move.
fn lengths(t: &Toolpath) -> Vec<f64> {
    let r = |v: f64| (v * 1e4).round() / 1e4;
    t.moves.iter().map(|m| r(t.frames[m.frame as usize].length.map_or(0.0, |l| l.value))).collect()
}

#[test]
fn g10_l10_and_l11_set_the_length_that_makes_z_read_the_value() {
    // rs274 -t with tool 1 at 254 mm: at Z5 under G43, `G10 L10 P1 Z1.5`
    // sets 257.5 (so that Z reads 1.5); the offset in force stays 254 until
    // G43 reloads it. Under G92 Z0 from Z3 (shift 3), L10 Z1 sets 256.5; in
    // G55 with the G92 shift, L11 Z2 ignores G92 and uses G59.3 (0): 257.5.
    let mut s = settings();
    s.tool_lengths.insert(1, 254.0);
    let t = path_with(
        "G21 T1 M6 G43\nG0 X0 Y0 Z5\nG10 L10 P1 Z1.5\nG0 Z4\nG43\nG0 Z3\nG92 Z0\nG10 L10 P1 Z1\nG43\nG0 Z0\n\
         G55\nG10 L11 P1 Z2\nG43\nG0 Z1\nM2\n",
        &s,
    );
    assert_eq!(lengths(&t), [254.0, 254.0, 257.5, 256.5, 257.5]);
    // L1 sets the table as given, also only at the next G43.
    let t = path_with("G21 T1 M6 G43\nG0 Z5\nG10 L1 P1 Z100 R3\nG0 Z4\nG43\nG0 Z3\nM2\n", &s);
    assert_eq!(lengths(&t), [254.0, 254.0, 100.0]);
}

#[test]
fn g10_tool_table_errors() {
    // LinuxCNC: an error with cutter compensation on, or P0.
    let mut s = settings();
    s.tool_radii.insert(1, 3.0);
    let (outcome, sources) = run_with("G21 T1 M6 G0 X0 Y0\nG41 G1 X10 F100\nG10 L10 P1 Z1\nM2\n", &s).unwrap();
    let e = outcome.diagnostics.iter().find(|d| d.is_error()).unwrap();
    assert_eq!(e.headline(&sources), "t.ngc:3:1: error: G10 L10 with cutter compensation on (G41/G42): give G40 first");
    assert!(error("G21 G10 L11 P0 Z1\nM2\n").contains("G10 L11 needs the offset number P1 to P999"));
    // kezuri keeps a length and a radius: an X offset is refused, located.
    assert_eq!(
        error("G21 G10 L1 P1 X2 Z1\nM2\n"),
        "t.ngc:1:15: error: G10 L1 X: kezuri keeps a tool's length (Z) and radius (R) only"
    );
}

// ---- M98 / M99 ----

#[test]
fn m98_calls_an_o_numbered_subprogram_of_the_file_as_linuxcnc_2_9() {
    // rs274 (2.9): `M98 P100 L2` runs O100 … M99 twice; nested calls
    // return; P20100 is program O20100, once (no count in front of four
    // digits, as on Fanuc).
    let x = |t: &Toolpath| t.moves.iter().map(|m| (m.end.x, m.end.y)).collect::<Vec<_>>();
    let t = path("G21\nG0 X0 Y0\nM98 P100 L2\nG0 X50\nM2\nO100\nG91 G0 X10\nG90\nM99\n");
    assert_eq!(x(&t), [(0.0, 0.0), (10.0, 0.0), (20.0, 0.0), (50.0, 0.0)]);
    let t = path("G21\nG0 X0 Y0\nM98 P20100\nG0 X50\nM2\nO20100\nG91 G0 X10\nG90\nM99\n");
    assert_eq!(x(&t), [(0.0, 0.0), (10.0, 0.0), (50.0, 0.0)]);
    let t = path("G21\nG0 X0 Y0\nM98 P100\nM2\nO100\nG91 G0 X10\nG90\nM98 P200\nM99\nO200\nG0 Y5\nM99\n");
    assert_eq!(x(&t), [(0.0, 0.0), (10.0, 0.0), (10.0, 5.0)]);
    // A program that is not there: located (rs274: "EOF … seeking o-word").
    assert!(error("G21\nM98 P300\nM2\n").starts_with("t.ngc:2:1: error: program O0300 is not in the file"));
}

// ---- tool length offset: the spindle stays ----

/// The tool table of these tests as rs274 got it (`-t`, inches): tool n
/// n·2.54 mm long, 1.27 + (n−1)·0.254 mm across.
fn with_tools() -> Settings {
    let mut s = Settings { comp_rules: interp::comp::Rules::LinuxCnc, ..settings() };
    for n in 1..=5u32 {
        s.tool_lengths.insert(n, 2.54 * f64::from(n));
        s.tool_radii.insert(n, (1.27 + 0.254 * f64::from(n - 1)) / 2.0);
    }
    s
}

#[test]
fn g43_and_g49_move_nothing_the_programmed_z_changes() {
    // LinuxCNC: applying, changing or cancelling the length offset moves no
    // axis; the tip's programmed Z changes by the change of offset, so a
    // move without Z keeps the spindle where it was. rs274: Z -2.62 after
    // G43 (tool 3, 7.62 mm) at Z5, 2.46 after G43 H1 (2.54), 5 after G49.
    let text = "G21 G90\nG0 X1 Y1 Z5\nT3 M6\nG43\nG0 X50 Y50\nG43 H1\nG0 X10\nG49\nG0 X20\nM2\n";
    let t = path_with(text, &with_tools());
    assert_eq!(
        moves(&t),
        [('r', 1.0, 1.0, 5.0), ('r', 50.0, 50.0, -2.62), ('r', 10.0, 50.0, 2.46), ('r', 20.0, 50.0, 5.0)]
    );
    // Fanuc moves Z instead: the programmed Z holds.
    let mut fanuc = with_tools();
    fanuc.dialect = Dialect::Fanuc;
    fanuc.coords.control = Control::Fanuc;
    let t = path_with("G21 G90\nG0 X1. Y1. Z5.\nT3 M6\nG43 H3\nG0 X50. Y50.\nG49\nG0 X20.\nM2\n", &fanuc);
    assert_eq!(moves(&t), [('r', 1.0, 1.0, 5.0), ('r', 50.0, 50.0, 5.0), ('r', 20.0, 50.0, 5.0)]);
    // In the same block as M6 the new tool's length (M6 comes first).
    let t = path_with("G21 G90\nG0 X1 Y1 Z5\nT2 M6 G43\nG0 X2\nM2\n", &with_tools());
    assert_eq!(moves(&t)[1], ('r', 2.0, 1.0, -0.08));
}

#[test]
fn after_g40_a_tool_change_finds_the_tool_where_compensation_left_it() {
    // LinuxCNC reads the position back after M6: after G40 without a move
    // the tool centre, the radius off the programmed point. rs274: Y 0.635
    // (tool 1's radius) for the moves after T2 M6; without a tool change
    // the next move goes to the programmed point (Y10).
    let text = "G21 G90\nT1 M6\nG0 X0 Y-10 Z5\nG41 G1 X0 Y0 F100\nG1 X20\nG40\nG4 P1\nT2 M6\nG0 Z10\nG0 X30\n\
                G41 G1 Y10\nG1 X40\nG40\nG0 Z12\nM2\n";
    let t = path_with(text, &with_tools());
    let m = moves(&t);
    let after: Vec<_> = m.iter().filter(|m| m.0 == 'r').skip(1).collect();
    assert_eq!(after, [&('r', 20.0, 0.635, 10.0), &('r', 30.0, 0.635, 10.0), &('r', 40.0, 10.0, 12.0)]);
}

#[test]
fn tool_changes_and_offsets_with_compensation_on_are_refused() {
    // rs274's messages, located.
    let mut s = with_tools();
    s.radii_required = true;
    for (text, at, message) in [
        ("G21 T1 M6\nG0 X0 Y0 Z5\nG41 G1 X10 F100\nG43 H1\nM2\n", "t.ngc:4:1", "Cannot change tool offset"),
        ("G21 T1 M6\nG0 X0 Y0 Z5\nG41 G1 X10 F100\nT2 M6\nM2\n", "t.ngc:4:4", "Cannot change tools"),
    ] {
        let (outcome, sources) = run_with(text, &s).unwrap();
        let e = outcome.diagnostics.iter().find(|d| d.is_error()).expect("an error");
        let headline = e.headline(&sources);
        assert!(
            headline.starts_with(&format!("{at}: error: {message} with cutter radius compensation on")),
            "{headline}"
        );
    }
}

#[test]
fn linuxcnc_starts_in_g99() {
    // rs274 starts with the R plane as the return level: G81 from Z10
    // with R2 returns to Z2.
    let t = path("G21 G90\nG0 X0 Y0 Z10\nG81 R2 Z-1 X1 F100\nG80\nM2\n");
    assert_eq!(moves(&t).last(), Some(&('r', 1.0, 0.0, 2.0)));
}

// ---- G43.1 and G43.2: dynamic tool length offsets ----

#[test]
fn g43_1_gives_the_offset_and_g43_2_adds_a_tools_length() {
    // rs274 -t (tools 1–3 2.54, 5.08, 7.62 mm long): USE_TOOL_LENGTH_OFFSET
    // Z 2, 3 (G91 does not make it an increment), 2.54 (G43 H1), 7.62
    // (G43.2 H2 adds 5.08), 15.24 (G43.2 H3), 0 (G49); nothing moves, the
    // tip's programmed Z changes by the change of offset.
    let text = "G21 G90\nG0 X1 Y1 Z5\nG43.1 Z2\nG0 X2\nG91 G43.1 Z3\nG90 G0 X3\nG43 H1\nG0 X4\nG43.2 H2\nG0 X5\n\
                G43.2 H3\nG0 X6\nG49\nG0 X7\nM2\n";
    let t = path_with(text, &with_tools());
    assert_eq!(
        moves(&t),
        [
            ('r', 1.0, 1.0, 5.0),
            ('r', 2.0, 1.0, 3.0),
            ('r', 3.0, 1.0, 2.0),
            ('r', 4.0, 1.0, 2.46),
            ('r', 5.0, 1.0, -2.62),
            ('r', 6.0, 1.0, -10.24),
            ('r', 7.0, 1.0, 5.0),
        ]
    );
    assert_eq!(lengths(&t), [0.0, 2.0, 3.0, 2.54, 7.62, 15.24, 0.0]);
    // G43.2 adds to a G43.1 offset, and to none after G49: rs274 4.54, then
    // 5.08 (tool 2 alone).
    let t = path_with("G21 G90\nG0 X1 Y1 Z5\nG43.1 Z2\nG43.2 H1\nG0 X2\nG49\nG43.2 H2\nG0 X3\nM2\n", &with_tools());
    assert_eq!(moves(&t)[1..], [('r', 2.0, 1.0, 0.46), ('r', 3.0, 1.0, -0.08)]);
    // G43.1 without Z leaves the offset as it was (rs274: 2, then 2.54).
    let t = path_with("G21 G90\nG0 X1 Y1 Z5\nG43.1 Z2\nG0 X4\nG43.1\nG0 X5\nG43 H1\nG43.1\nG0 X6\nM2\n", &with_tools());
    assert_eq!(moves(&t)[1..], [('r', 4.0, 1.0, 3.0), ('r', 5.0, 1.0, 3.0), ('r', 6.0, 1.0, 2.46)]);
    // Its Z word is the offset, not a move, whatever the motion mode; in
    // inches under G20 (rs274: 0.5 in, the tip at 4.5 in).
    let t = path_with("G21 G90\nG0 X1 Y1 Z5\nG1 X1 F100\nG43.1 Z2\nG0 X4\nM2\n", &with_tools());
    assert_eq!(moves(&t)[2..], [('r', 4.0, 1.0, 3.0)]);
    let t = path_with("G20 G90\nG0 X1 Y1 Z5\nG43.1 Z0.5\nG0 X2\nM2\n", &with_tools());
    assert_eq!(moves(&t)[1], ('r', 50.8, 25.4, 114.3));
}

#[test]
fn g43_1_and_g43_2_errors() {
    // rs274: "Requested tool -1 not found" for G43.2 without H (2.9 reads
    // no axis words with it), "G43.2: Can not have both H and axis words".
    assert_eq!(
        error("G21\nG43.2 Z1\nM2\n"),
        "t.ngc:2:7: error: G43.2: Can not have both H and axis words (LinuxCNC 2.9 adds a tool's length, given by H)"
    );
    assert_eq!(error("G21\nG43.2\nM2\n"), "t.ngc:2:1: error: G43.2 needs H, the tool whose length it adds");
    // G43.1 takes the block's axis words: rs274 makes them the offset and the
    // move both (`G43.1 Z2 G0 X2`: an X offset of 2). Refused.
    assert!(error("G21\nG43.1 Z2 G0 X2\nM2\n")
        .starts_with("t.ngc:2:10: error: G43.1 with G0: give the motion in another block"));
    // Offsets in X, Y, rotary axes: refused, located.
    assert!(error("G21\nG43.1 X1 Z2\nM2\n")
        .starts_with("t.ngc:2:7: error: G43.1 X: kezuri applies a tool length offset in Z only"));
    // With cutter compensation on, as G43 (rs274's message).
    let mut s = with_tools();
    s.radii_required = true;
    for text in [
        "G21 T1 M6\nG0 X1 Y1 Z5\nG41 G1 X3 F100\nG43.1 Z2\nM2\n",
        "G21 T1 M6\nG0 X1 Y1 Z5\nG41 G1 X3 F100\nG43.2 H1\nM2\n",
    ] {
        let (outcome, sources) = run_with(text, &s).unwrap();
        let e = outcome.diagnostics.iter().find(|d| d.is_error()).expect("an error").headline(&sources);
        assert!(e.starts_with("t.ngc:4:1: error: Cannot change tool offset with cutter radius compensation on"), "{e}");
    }
    // rs274 adds G43.2's length to the number of an offset set under G20
    // without converting it (0.5 in + 2.54 mm = 3.04 mm): refused.
    assert!(error("G20 G90\nG43.1 Z0.5\nG21\nG43.2 H1\nM2\n")
        .starts_with("t.ngc:4:1: error: G43.2 after G21: LinuxCNC adds"));
    // GRBL has G43.1 (kezuri's GRBL writer writes it), not G43.2.
    let grbl = Settings { dialect: Dialect::Grbl, ..with_tools() };
    let t = path_with("G21 G90\nG0 X1 Y1 Z5\nG43.1 Z2\nG0 X2\nM2\n", &grbl);
    assert_eq!(moves(&t)[1], ('r', 2.0, 1.0, 3.0));
    let (outcome, sources) = run_with("G21\nG43.2 H1\nM2\n", &grbl).unwrap();
    let e = outcome.diagnostics.iter().find(|d| d.is_error()).expect("an error").headline(&sources);
    assert_eq!(e, "t.ngc:2:1: error: G43.2 is not supported");
    // Other dialects: not their codes.
    let mut fanuc = with_tools();
    fanuc.dialect = Dialect::Fanuc;
    fanuc.coords.control = Control::Fanuc;
    let (outcome, sources) = run_with("G21\nG43.1 Z2\nM2\n", &fanuc).unwrap();
    let e = outcome.diagnostics.iter().find(|d| d.is_error()).expect("an error").headline(&sources);
    assert_eq!(e, "t.ngc:2:1: error: G43.1 is not supported");
}

#[test]
fn g43_1_and_g43_2_are_written_back_for_linuxcnc_and_refused_by_fanuc() {
    use kezuri_nc::write::{program, Dialect as Out, WriteOptions};
    use kezuri_nc::ErrorKind;
    let text = "G21 G90\nG0 X1 Y1 Z5\nG43.1 Z2\nG0 X2\nG43 H1\nG43.2 H2\nG0 X3\nG43.2 H3\nG0 X4\nG49\nG0 X5\nM2\n";
    let t = path_with(text, &with_tools());
    let options = |dialect| WriteOptions { dialect, ..WriteOptions::default() };
    let written = program(&t, &options(Out::LinuxCnc)).unwrap();
    let lines: Vec<&str> = written.lines().collect();
    // The offset as the program gave it, for the control to apply its own
    // tool table; only the new addition where the rest is in force.
    let at = |s: &str| lines.iter().position(|l| l.ends_with(s)).unwrap_or_else(|| panic!("no {s} in\n{written}"));
    let (given, g43, add2, add3, g49) = (at("G43.1 Z2."), at("G43 H1"), at("G43.2 H2"), at("G43.2 H3"), at("G49"));
    assert!(given < g43 && g43 + 1 == add2 && add2 < add3 && add3 < g49, "{written}");
    assert_eq!(lines.iter().filter(|l| l.contains("G43 H1")).count(), 1, "{written}");
    // Read back, the same motions.
    let back = path_with(&written, &with_tools());
    assert_eq!(moves(&back), moves(&t), "{written}");
    // Fanuc (and Haas) have no such code: refused, not dropped (at the
    // first move under it).
    let e = program(&t, &options(Out::Fanuc)).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unsupported, "{e}");
    let e = e.to_string();
    assert!(e.starts_with("line 4: fanuc has no 'G43.1 Z2. (a dynamic tool length offset"), "{e}");
    let t = path_with("G21 G90\nG0 X1 Y1 Z5\nG43 H1\nG43.2 H2\nG0 X3\nM2\n", &with_tools());
    let e = program(&t, &options(Out::Fanuc)).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unsupported, "{e}");
    let e = e.to_string();
    assert!(e.contains("fanuc has no 'G43.2 H2"), "{e}");
    // GRBL gets the offset itself, as for G43 H.
    let written = program(&t, &options(Out::Grbl)).unwrap();
    assert!(written.contains("G43.1 Z7.62\n"), "{written}");
}
