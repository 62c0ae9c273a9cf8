//! LinuxCNC's numbered parameters #5161–#5428 in the linuxcnc dialect, and
//! their starting values (`Settings::parameters`, the `.var` file). The
//! motions were confirmed with `rs274 -v q.var -g q.ngc` (the same values in
//! inches: rs274 alone has inch machine units), written here in mm by hand;
//! rs274 prints program coordinates, the toolpath holds machine ones (the
//! offsets added back in the comments).

use std::collections::BTreeMap;

use kezuri_nc::interp::{Control, CoordSettings, IntegerInput, Settings};
use kezuri_nc::Dialect;

mod common;

fn linuxcnc(parameters: &[(u32, f64)]) -> Settings {
    Settings {
        dialect: Dialect::LinuxCnc,
        integer_input: IntegerInput::Units,
        coords: CoordSettings { control: Control::LinuxCnc, ..CoordSettings::default() },
        parameters: parameters.iter().copied().collect::<BTreeMap<_, _>>(),
        ..Settings::default()
    }
}

/// The `.var` of the test, in mm: G28 at (254, 508, 762), G30 at (25.4,
/// 50.8, 76.2), a G92 offset X127 applied, G55 in force, G54 X2540, G55
/// (5080, 177.8, -25.4).
const VAR: &[(u32, f64)] = &[
    (5161, 254.0),
    (5162, 508.0),
    (5163, 762.0),
    (5181, 25.4),
    (5182, 50.8),
    (5183, 76.2),
    (5210, 1.0),
    (5211, 127.0),
    (5220, 2.0),
    (5221, 2540.0),
    (5241, 5080.0),
    (5242, 177.8),
    (5243, -25.4),
];

fn close(a: [f64; 3], b: [f64; 3]) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9)
}

#[test]
fn the_var_file_offsets_and_home_positions() {
    let text = "G21 G90\nG1 X0 Y0 Z0 F100\nG1 X#5220 Y#5210\nG28\nG30\nG1 X#5420 Y#5421 Z#5422\n#5161 = 0\nG28\n\
                G54 G1 X1 Y2 Z3\n#5241 = 300\nG55 G1 X0 Y0 Z0\nM2\n";
    let t = common::run("q.ngc", text, &linuxcnc(VAR)).path();
    let ends: Vec<[f64; 3]> = t.moves.iter().map(|m| m.end.xyz()).collect();
    // rs274: STRAIGHT_FEED(0, 0, 0) in G55 + G92: machine (5080+127, 177.8, -25.4).
    assert!(close(ends[0], [5207.0, 177.8, -25.4]), "{ends:?}");
    // #5220 is 2 (G55), #5210 is 1: STRAIGHT_FEED(2, 1, 0).
    assert!(close(ends[1], [5209.0, 178.8, -25.4]), "{ends:?}");
    // G28 ends at #5161–#5163: STRAIGHT_TRAVERSE(-4953, 330.2, 787.4).
    let at = |p: [f64; 3]| ends.iter().position(|e| close(*e, p));
    let home = at([254.0, 508.0, 762.0]).expect("G28 at #5161…");
    // G30 at #5181–#5183: STRAIGHT_TRAVERSE(-5181.6, -127, 101.6).
    let second = at([25.4, 50.8, 76.2]).expect("G30 at #5181…");
    assert!(home < second);
    // #5420–#5422 are where the tool is: a move there stays.
    assert!(close(ends[second + 1], [25.4, 50.8, 76.2]), "{ends:?}");
    // #5161 = 0: G28 now ends at X0 (STRAIGHT_TRAVERSE(-5207, 330.2, 787.4)).
    assert!(ends.iter().any(|e| close(*e, [0.0, 508.0, 762.0])), "{ends:?}");
    // G54 X2540 with the G92 offset: STRAIGHT_FEED(1, 2, 3) is machine (2668, 2, 3).
    assert!(ends.iter().any(|e| close(*e, [2668.0, 2.0, 3.0])), "{ends:?}");
    // #5241 = 300 set outside G55 counts once G55 is selected: machine (427, 177.8, -25.4).
    assert!(close(*ends.last().unwrap(), [427.0, 177.8, -25.4]), "{ends:?}");
}

#[test]
fn reads_of_the_tool_and_position() {
    let s =
        Settings { tool_lengths: BTreeMap::from([(3, 40.0)]), tool_radii: BTreeMap::from([(3, 5.0)]), ..linuxcnc(&[]) };
    // #5400 the tool, #5403 its Z offset, #5410 its diameter; #5420… in
    // the program's units (G20: inches).
    let text = "T3 M6\nG1 X#5400 Y#5403 Z#5410 F100\nG20\nG1 X[#5420*2]\nM2\n";
    let t = common::run("t.ngc", text, &s).path();
    let ends: Vec<[f64; 3]> = t.moves.iter().map(|m| m.end.xyz()).collect();
    assert!(close(ends[0], [3.0, 40.0, 10.0]), "{ends:?}");
    // X was 3 mm = 0.11811 in; doubled, 0.23622 in = 6 mm.
    assert!((ends[1][0] - 6.0).abs() < 1e-9, "{ends:?}");
}

#[test]
fn writes_linuxcnc_would_not_apply_now_are_refused() {
    // #5221 while G54 is in force: LinuxCNC keeps the old offset until G54 is selected again.
    let m = common::run("t.ngc", "G54\n#5221 = 10\nG1 X0 F100\nM2\n", &linuxcnc(&[])).message();
    assert!(m.contains("G54") && m.contains("G10 L2 P1"), "{m}");
    let m = common::run("t.ngc", "#5211 = 10\nM2\n", &linuxcnc(&[])).message();
    assert!(m.contains("G92"), "{m}");
    let m = common::run("t.ngc", "#5420 = 10\nM2\n", &linuxcnc(&[])).message();
    assert!(m.contains("read-only"), "{m}");
    // Any other number up to #5999 is storage (0 until set).
    let t = common::run("t.ngc", "G1 X#5500 F100\n#5500 = 7\nG1 X#5500\nM2\n", &linuxcnc(&[])).path();
    assert_eq!(t.moves.iter().map(|m| m.end.x).collect::<Vec<_>>(), [0.0, 7.0]);
}

#[test]
fn fanuc_keeps_its_system_variables() {
    // In the fanuc dialect #5221 is G54's X as Fanuc numbers it, and #5420 is not a variable there.
    let fanuc =
        Settings { work_offsets: [kezuri_geom::Axes { x: 5.0, ..Default::default() }; 6], ..Settings::default() };
    let t = common::run("t.nc", "G1 X#5221 F100.\nM30\n", &fanuc).path();
    assert_eq!(t.moves[0].end.x, 10.0);
    assert!(common::run("t.nc", "#1=#5420\nM30\n", &fanuc).message().contains("5420"));
    // The starting values are LinuxCNC's: the fanuc dialect ignores them.
    let t = common::run("t.nc", "G91 G28 X0\nM30\n", &Settings { parameters: BTreeMap::from([(5161, 9.0)]), ..fanuc })
        .path();
    assert_eq!(t.moves.last().unwrap().end.x, 0.0);
}

#[test]
fn a_starting_value_no_parameter_can_hold_is_an_error() {
    // #31 is storage; #99999 is past LinuxCNC's parameters: refused, not
    // dropped without a word.
    let t = common::run("t.ngc", "G1 X#31 F100\nM2\n", &linuxcnc(&[(31, 2.0)])).path();
    assert_eq!(t.moves[0].end.x, 2.0);
    let m = common::run("t.ngc", "G1 X#31 F100\nM2\n", &linuxcnc(&[(31, 2.0), (99999, 1.0)])).message();
    assert!(m.contains("starting parameters") && m.contains("#99999"), "{m}");
}

#[test]
fn the_probe_result_is_the_tips_program_position_in_the_units_it_was_made_in() {
    // LinuxCNC's `set_probe_data` stores emccanon's probe position with the
    // tool offset taken off, in the program's units of the moment; later
    // G20/G21 leave the numbers as they are. Tool 1's length 2.54 mm (G43):
    // #5063 is the tip's Z, −5 (Fanuc's #5063 would add the offset: −2.46).
    // rs274 prints the same X Y (STRAIGHT_FEED 1 −5; in G20 1 −5, that is
    // 25.4 −127 mm; after G38.3 X0.1 Z−0.2 in G20 and back in G21, 0.1 −0.2).
    let s = Settings { tool_lengths: BTreeMap::from([(1, 2.54)]), ..linuxcnc(&[]) };
    let text = "G21 G17\nT1 M6 G43\nG0 X1 Z10\nG38.3 Z-5 F100\nG1 X#5061 Y#5063\nG20\nG1 X#5061 Y#5063\n\
                G38.3 X0.1 Z-0.2\nG21\nG1 X#5061 Y#5063\nM2\n";
    let t = common::run("t.ngc", text, &s).path();
    let xy: Vec<(f64, f64)> = t.moves.iter().map(|m| (m.end.x, m.end.y)).collect();
    let want = [(1.0, 0.0), (1.0, 0.0), (1.0, -5.0), (25.4, -127.0), (2.54, -127.0), (0.1, -0.2)];
    assert_eq!(xy.len(), want.len(), "{xy:?}");
    for (g, w) in xy.iter().zip(want) {
        assert!((g.0 - w.0).abs() < 1e-9 && (g.1 - w.1).abs() < 1e-9, "{xy:?}");
    }
}
