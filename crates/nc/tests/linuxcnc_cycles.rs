//! Canned cycles by LinuxCNC's own rules in the linuxcnc dialect (its
//! manual, G73–G89), each expectation confirmed with `rs274 -g` on
//! `G21 G90 G17 / S1000 M3 / G0 X0 Y0 Z5 / F100 / <cycle> / G80 / M2`
//! and written here by hand: the Z of each move after the rapid to X1.

use kezuri_geom::MoveKind;
use kezuri_nc::interp::{Control, CoordSettings, IntegerInput, Settings};
use kezuri_nc::Dialect;

mod common;

fn settings(dialect: Dialect) -> Settings {
    let lc = dialect == Dialect::LinuxCnc;
    Settings {
        dialect,
        integer_input: if lc { IntegerInput::Units } else { IntegerInput::Increments },
        coords: CoordSettings {
            control: if lc { Control::LinuxCnc } else { Control::Fanuc },
            ..CoordSettings::default()
        },
        ..Settings::default()
    }
}

fn program(cycle: &str) -> String {
    format!("G21 G90 G17\nS1000 M3\nG0 X0 Y0 Z5.\nF100.\n{cycle}\nG80\nM2\n")
}

/// (kind, Z) of each move after the rapid to X1, dwells as ('d', seconds).
fn zs(cycle: &str, dialect: Dialect) -> Vec<(char, f64)> {
    let t = common::run("c.ngc", &program(cycle), &settings(dialect)).path();
    let first = t.moves.iter().position(|m| m.end.x == 1.0).unwrap();
    t.moves[first + 1..]
        .iter()
        .map(|m| match m.kind {
            MoveKind::Rapid => ('r', (m.end.z * 1e4).round() / 1e4),
            MoveKind::Dwell(s) => ('d', s),
            _ => ('f', (m.end.z * 1e4).round() / 1e4),
        })
        .collect()
}

#[test]
fn g73_and_g83_clear_by_0_254_mm() {
    use Dialect::LinuxCnc;
    // rs274: FEED 0.6, TRAVERSE 0.854, FEED 0.2, TRAVERSE 0.454, … FEED -1, TRAVERSE 5.
    let want = [
        ('r', 1.0),
        ('f', 0.6),
        ('r', 0.854),
        ('f', 0.2),
        ('r', 0.454),
        ('f', -0.2),
        ('r', 0.054),
        ('f', -0.6),
        ('r', -0.346),
        ('f', -1.0),
        ('r', 5.0),
    ];
    assert_eq!(zs("G98 G73 X1. Z-1. R1. Q0.4", LinuxCnc), want);
    // G83: back to R, down to 0.254 above the last depth.
    let want = [
        ('r', 1.0),
        ('f', 0.6),
        ('r', 1.0),
        ('r', 0.854),
        ('f', 0.2),
        ('r', 1.0),
        ('r', 0.454),
        ('f', -0.2),
        ('r', 1.0),
        ('r', 0.054),
        ('f', -0.6),
        ('r', 1.0),
        ('r', -0.346),
        ('f', -1.0),
        ('r', 5.0),
    ];
    assert_eq!(zs("G98 G83 X1. Z-1. R1. Q0.4", LinuxCnc), want);
}

#[test]
fn g84_and_g89_feed_out_to_the_clear_level() {
    use Dialect::{Fanuc, LinuxCnc};
    // rs274 G84: FEED -1, DWELL 0.5, FEED 5 (the initial level under G98).
    assert_eq!(zs("G98 G84 X1 Z-1 R1 P0.5", LinuxCnc), [('r', 1.0), ('f', -1.0), ('d', 0.5), ('f', 5.0)]);
    assert_eq!(zs("G98 G89 X1 Z-1 R1 P0.5", LinuxCnc), [('r', 1.0), ('f', -1.0), ('d', 0.5), ('f', 5.0)]);
    // Fanuc feeds out to R and rapids on.
    assert_eq!(zs("G98 G89 X1. Z-1. R1. P500", Fanuc), [('r', 1.0), ('f', -1.0), ('d', 0.5), ('f', 1.0), ('r', 5.0)]);
    // G85 feeds out to R in both (LinuxCNC: "to the R plane if it is lower than the initial Z").
    assert_eq!(zs("G98 G85 X1 Z-1 R1", LinuxCnc), [('r', 1.0), ('f', -1.0), ('f', 1.0), ('r', 5.0)]);
}

#[test]
fn g86_needs_p() {
    use Dialect::LinuxCnc;
    // rs274: "Dwell time p word missing with g86".
    let run = common::run("c.ngc", &program("G98 G86 X1 Z-1 R1"), &settings(LinuxCnc));
    assert!(run.message().contains("G86 needs the dwell P"), "{}", run.message());
    // With P: FEED -1, DWELL 0.5, spindle stop, TRAVERSE 5.
    assert_eq!(zs("G98 G86 X1 Z-1 R1 P0.5", LinuxCnc), [('r', 1.0), ('f', -1.0), ('d', 0.5), ('r', 5.0)]);
    // Fanuc keeps G86 without P.
    assert_eq!(zs("G98 G86 X1. Z-1. R1.", Dialect::Fanuc).last(), Some(&('r', 5.0)));
}

/// Every move of `cycle` after the program's first rapid, as (kind, x, y, z).
fn xyzs(cycle: &str) -> Vec<(char, f64, f64, f64)> {
    let t = common::run("c.ngc", &program(cycle), &settings(Dialect::LinuxCnc)).path();
    t.moves[1..]
        .iter()
        .map(|m| {
            let k = match m.kind {
                MoveKind::Rapid => 'r',
                MoveKind::Dwell(_) => 'd',
                _ => 'f',
            };
            (k, m.end.x, m.end.y, m.end.z)
        })
        .collect()
}

#[test]
fn g87_and_g88_run_as_rs274_runs_them() {
    // rs274 G98 G87 X1 Y1 Z-1 R1 I0.5 J0.5 K-2: TRAVERSE (1, 1, 5), (1, 1, 1),
    // (1.5, 1.5, 1), (1.5, 1.5, -1), (1, 1, -1), FEED (1, 1, -2), (1, 1, -1),
    // TRAVERSE (1.5, 1.5, -1), (1.5, 1.5, 5), (1, 1, 5).
    let want = [
        ('r', 1.0, 1.0, 5.0),
        ('r', 1.0, 1.0, 1.0),
        ('r', 1.5, 1.5, 1.0),
        ('r', 1.5, 1.5, -1.0),
        ('r', 1.0, 1.0, -1.0),
        ('f', 1.0, 1.0, -2.0),
        ('f', 1.0, 1.0, -1.0),
        ('r', 1.5, 1.5, -1.0),
        ('r', 1.5, 1.5, 5.0),
        ('r', 1.0, 1.0, 5.0),
    ];
    assert_eq!(xyzs("G98 G87 X1 Y1 Z-1 R1 I0.5 J0.5 K-2"), want);
    // G99: out to R; G91: K from the bottom (Z from R, R from the start).
    assert_eq!(xyzs("G99 G87 X1 Y1 Z-1 R1 I0.5 J0.5 K-2")[8], ('r', 1.5, 1.5, 1.0));
    assert_eq!(xyzs("G91 G98 G87 X1 Y1 Z-2 R-4 I0.5 J0.5 K-1")[5], ('f', 1.0, 1.0, -2.0));
    for (g, said) in [("G87 X1 Z-1 R1 K-2", "G87 needs I and J"), ("G88 X1 Z-1 R1", "G88 needs the dwell P")] {
        let run = common::run("c.ngc", &program(g), &settings(Dialect::LinuxCnc));
        assert!(run.message().contains(said), "{g}: {}", run.message());
    }
    let run =
        common::run("c.ngc", "G0 X0 Y0 Z5.\nF100.\nG87 X1 Z-1 R1 I1 J0 K-0.5\nM2\n", &settings(Dialect::LinuxCnc));
    assert!(run.message().contains("spindle turning"), "{}", run.message());
    // rs274 G98 G88 X1 Y1 Z-1 R1 P0.5: TRAVERSE (1, 1, 5), (1, 1, 1), FEED
    // (1, 1, -1), DWELL 0.5, the spindle stopped and PROGRAM_STOP: the
    // operator takes the tool out by hand; rs274 goes on from the clear
    // level (5), which kezuri draws as a rapid there.
    let want = [
        ('r', 1.0, 1.0, 5.0),
        ('r', 1.0, 1.0, 1.0),
        ('f', 1.0, 1.0, -1.0),
        ('d', 1.0, 1.0, -1.0),
        ('r', 1.0, 1.0, 5.0),
    ];
    assert_eq!(xyzs("G98 G88 X1 Y1 Z-1 R1 P0.5"), want);
}
