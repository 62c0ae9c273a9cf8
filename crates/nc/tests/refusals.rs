//! What no dialect may run as if it were fine: a cutting move at feed zero
//! (`F0`, or G95 with spindle speed 0), which LinuxCNC refuses and on a
//! Fanuc would wait forever; an axis word the control has not (U V W on a
//! Fanuc, Haas or GRBL mill; LinuxCNC has them), whose motion would be lost. Each is an error at the word.
//! The programs are a mill's: the lathe dialects, which read G90 G94 and U
//! W otherwise, are tested in lathe_fanuc.rs.

use kezuri_nc::interp::{self, Control, CoordSettings, IntegerInput, Settings};
use kezuri_nc::{parse_as, Dialect, Program, SourceFile, Sources};

/// Runs `text` in `dialect`; the headline of the error that stopped it, or
/// `None` when it ran to its end.
fn stopped(dialect: Dialect, text: &str) -> Option<String> {
    let whole = matches!(dialect, Dialect::LinuxCnc | Dialect::Grbl);
    let settings = Settings {
        dialect,
        integer_input: if whole { IntegerInput::Units } else { IntegerInput::Increments },
        coords: CoordSettings {
            control: match dialect {
                Dialect::LinuxCnc | Dialect::Grbl => Control::LinuxCnc,
                Dialect::Haas | Dialect::HaasLathe => Control::Haas,
                Dialect::Fanuc | Dialect::FanucLathe => Control::Fanuc,
            },
            ..CoordSettings::default()
        },
        ..Settings::default()
    };
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("t.nc", text));
    let mut program = Program::default();
    let parsed = parse_as(&mut program, file, text, dialect);
    assert!(!parsed.iter().any(|d| d.is_error()), "{text}: {parsed:?}");
    let outcome = interp::run(&mut program, &mut sources, 0, &mut interp::NoLibrary, &settings);
    match outcome.diagnostics.iter().find(|d| d.is_error()) {
        Some(d) => Some(d.headline(&sources)),
        None => {
            assert!(outcome.completed);
            None
        }
    }
}

#[test]
fn a_feed_of_zero_is_an_error_in_every_dialect() {
    for d in Dialect::ALL.into_iter().filter(|d| !d.is_lathe()) {
        let e = stopped(d, "G90 G21 G94\nG00 X0. Y0. Z1.\nG01 X10. F0\nM30\n").expect("F0 refused");
        assert!(e.starts_with("t.nc:3:10: error: a cutting move at F0"), "{d}: {e}");
        // Set in one block, used in the next: the error is at the move.
        let e = stopped(d, "G90 G21 G94 F0\nG00 X0. Y0. Z1.\nG01 X10.\nM30\n").expect("F0 refused");
        assert!(e.starts_with("t.nc:3:1: error: a cutting move at F0 (given in an earlier block)"), "{d}: {e}");
        // An arc and a canned cycle too.
        let e = stopped(d, "G90 G21 G94 F0\nG00 X0. Y0. Z1.\nG02 X10. I5.\nM30\n").expect("arc at F0 refused");
        assert!(e.contains(":3:1: error: a cutting move at F0"), "{d}: {e}");
        // Rapids need no feed.
        assert_eq!(stopped(d, "G90 G21 F0\nG00 X10. Y0. Z1.\nM30\n"), None, "{d}");
    }
    // A drilling cycle at F0 (the canned cycles of the Fanuc family and LinuxCNC).
    for d in [Dialect::Fanuc, Dialect::Haas, Dialect::LinuxCnc] {
        let e = stopped(d, "G90 G21 G94 F0\nG00 X0. Y0. Z5.\nG81 X1. Y1. Z-1. R1.\nG80\nM30\n").expect("G81 at F0");
        assert!(e.contains(":3:1: error: a cutting move at F0"), "{d}: {e}");
    }
}

#[test]
fn feed_per_revolution_needs_a_spindle_speed() {
    for d in Dialect::ALL.into_iter().filter(|d| !d.is_lathe()) {
        let e = stopped(d, "G90 G21 G95 S0 M03\nG00 X0. Y0. Z1.\nG01 X10. F0.1\nM30\n").expect("S0 refused");
        assert!(
            e.starts_with(
                "t.nc:3:1: error: feed per revolution (G95) with spindle speed S0 (given in an earlier block)"
            ),
            "{d}: {e}"
        );
        let e = stopped(d, "G90 G21 G95\nG00 X0. Y0. Z1.\nG01 X10. F0.1\nM30\n").expect("no S refused");
        assert!(
            e.starts_with("t.nc:3:1: error: feed per revolution (G95) with no spindle speed (S) given"),
            "{d}: {e}"
        );
        assert_eq!(stopped(d, "G90 G21 G95 S1000 M03\nG00 X0. Y0. Z1.\nG01 X10. F0.1\nM30\n"), None, "{d}");
    }
}

#[test]
fn inverse_time_at_f0_is_an_error() {
    for d in [Dialect::Fanuc, Dialect::LinuxCnc] {
        let e = stopped(d, "G90 G21\nG00 X0. Y0. Z1.\nG93 G01 X10. F0\nM30\n").expect("G93 F0 refused");
        assert!(e.contains(":3:1: error: in inverse time feed (G93)"), "{d}: {e}");
    }
}

/// A hot-wire foam cutter's program (X Y for one side of the wire, U V for
/// the other), as such programs are written: on a mill the U V half of the
/// motion would be lost.
const FOAM: &str = "G21 G90 G94 F300\nG00 X0. Y0. U0. V0.\nG01 X50. Y0. U50. V5.\nG01 X50. Y20. U50. V25.\nM30\n";

#[test]
fn an_axis_the_machine_has_not_is_never_dropped() {
    // LinuxCNC has nine axes: there U V W move (linuxcnc_uvw.rs).
    assert_eq!(stopped(Dialect::LinuxCnc, FOAM), None);
    for d in Dialect::ALL.into_iter().filter(|d| !d.is_lathe() && *d != Dialect::LinuxCnc) {
        let e = stopped(d, FOAM).expect("U V refused");
        assert!(e.starts_with("t.nc:2:13: error: U is an axis this control does not have"), "{d}: {e}");
        let e = stopped(d, "G21 G90\nG00 Z5.\nG00 W-2.\nM30\n").expect("W refused");
        assert!(e.starts_with("t.nc:3:5: error: W is an axis"), "{d}: {e}");
    }
    // LinuxCNC's canned cycles in the XYZ planes take no U V W: its preview
    // parser stops at this block with "Cannot put a U in a canned cycle in
    // the XY plane".
    let e = stopped(Dialect::LinuxCnc, "G21 G90\nG0 X0 Y0 Z5\nG81 X1 Y1 Z-1 R1 U2 F100\nM2\n").expect("U refused");
    assert!(e.starts_with("t.nc:3:18: error: U in a canned cycle (G81)"), "{e}");
    // A macro's arguments are no axes.
    let call = "G65 P9001 U1. V2. W3.\nM30\nO9001\n#100=#21+#22+#23\nM99\n";
    assert_eq!(stopped(Dialect::Fanuc, call), None);
}

/// Parses `text` in `dialect`: the headlines of its diagnostics.
fn parsed(dialect: Dialect, text: &str) -> Vec<String> {
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("t.nc", text));
    let mut program = Program::default();
    parse_as(&mut program, file, text, dialect).iter().map(|d| d.headline(&sources)).collect()
}

/// A Fusion 360 program for a router (corpus/shop, shooshx/led_floor): its
/// words have no decimal point (`Y35`, `Z10`), which a Fanuc reads as
/// least increments. The arc that fails says which word, read how, and the
/// option that reads it as whole millimetres.
#[test]
fn a_word_without_a_decimal_point_behind_an_error_is_named() {
    let fusion = include_str!("../../../corpus/shop/shooshx__led_floor/1077_bore_speed_test.nc");
    let e = stopped(Dialect::Fanuc, fusion).expect("the arc fails as increments");
    assert!(e.starts_with("t.nc:21:1: error: the arc's end point is 34.6960 mm off its circle"), "{e}");
    assert!(e.ends_with("; Y35 was read as 0.035 mm (Fanuc increments); with --no-decimal units it is 35 mm"), "{e}");
    // Read as whole units (LinuxCNC, or --no-decimal units) it runs.
    assert_eq!(stopped(Dialect::LinuxCnc, fusion), None);
    // The word in an earlier block, named with its line.
    let e = stopped(Dialect::Fanuc, "G90 G21 F100\nG01 X1.\nG01 X10 Y5\nG02 X20. Y5. R3.\nM30\n").unwrap();
    assert!(
        e.ends_with("; line 3: X10 was read as 0.010 mm (Fanuc increments); with --no-decimal units it is 10 mm"),
        "{e}"
    );
    // Inches: four decimals.
    let e = stopped(Dialect::Fanuc, "G90 G20 F10.\nG01 X1.\nG02 X3 Y0. R0.1\nM30\n").unwrap();
    assert!(
        e.ends_with("; X3 was read as 0.0003 inch (Fanuc increments); with --no-decimal units it is 3 inch"),
        "{e}"
    );
}

#[test]
fn a_move_beyond_any_machine_is_an_error() {
    for d in Dialect::ALL.into_iter().filter(|d| !d.is_lathe()) {
        let e = stopped(d, "G90 G21 F100\nG01 X1.\nG01 X2000000000.\nM30\n").expect("refused");
        assert!(e.starts_with("t.nc:3:5: error: this move takes X to 2000000000.000 mm from machine zero"), "{d}: {e}");
    }
    // Inches read as whole units where the program meant increments: 25.4 km.
    let e = stopped(Dialect::LinuxCnc, "G90 G20 F10\nG01 X1000000\nM30\n").unwrap();
    assert!(e.starts_with("t.nc:2:5: error: this move takes X to 25400000.000 mm"), "{e}");
}

#[test]
fn a_percent_sign_is_reported_where_it_stands() {
    for d in Dialect::ALL.into_iter().filter(|d| !d.is_lathe()) {
        // In the middle of a program that did not open with one: an error there.
        let got = parsed(d, "G90 G21 F100\n%\nG01 X1.\nM30\n");
        assert_eq!(got.len(), 1, "{got:?}");
        assert!(got[0].starts_with("t.nc:2:1: error: a '%' in the middle of the program"), "{d}: {got:?}");
        // The closing '%' with a program after it: the warning at the '%'.
        let got = parsed(d, "%\nG90 G21 F100\n%\nG00 X0. Y0. Z1.\nG01 X10.\nM30\n%\n");
        assert_eq!(got, ["t.nc:3:1: warning: this '%' ends the tape: the 4 lines after it are not read"], "{d}");
        // Blank lines before the opening '%' (a Haas lathe program as saved): nothing to say.
        assert_eq!(parsed(d, "\n \n%\nG90 G21 F100\nG01 X1.\nM30\n%\n"), Vec::<String>::new(), "{d}");
        // After the end of the program (LinuxCNC's lathe_pawn.ngc ends `M2` `%`): nothing to say.
        assert_eq!(parsed(d, "G90 G21 F100\nG01 X1.\nM2\n%\n"), Vec::<String>::new(), "{d}");
        // A '%' inside a line: one error where it stands, none at the end.
        let got = parsed(d, "%\nG90 G21 F100\nG01 X1. %\nM30\n");
        assert_eq!(got.len(), 1, "{d}: {got:?}");
        assert!(got[0].starts_with("t.nc:3:9: error:"), "{d}: {got:?}");
    }
}

/// A file that opens with `%` and has no closing one. A Fanuc or Haas
/// control reading a program into memory ends it at its program end
/// (M02, M30 or M99: FANUC parameter No. 3201 #6 NPE at 0, as shipped), so
/// the missing `%` leaves the program whole; LinuxCNC refuses any such file
/// ("file ended with no percent sign"). Without a program end the file was
/// cut short, and every control refuses it.
#[test]
fn a_tape_without_its_closing_percent_sign() {
    for d in Dialect::ALL {
        for end in ["M30", "M02", "M99"] {
            let got = parsed(d, &format!("%\nG90 G21 F100\nG01 X1.\n{end}\n"));
            if d.is_fanuc() {
                let want = format!(
                    "t.nc:5:1: warning: the file has no closing '%': a Fanuc or Haas control loads the program up \
                     to its end ({end} on line 4) all the same; LinuxCNC would refuse it"
                );
                assert_eq!(got, [want], "{d}");
            } else {
                assert_eq!(got, ["t.nc:5:1: error: the file ends before its closing '%': is it complete?"], "{d}");
            }
        }
        // No program end: cut short, in every dialect.
        let got = parsed(d, "%\nG90 G21 F100\nG01 X1.\n");
        assert_eq!(got, ["t.nc:4:1: error: the file ends before its closing '%': is it complete?"], "{d}");
    }
}

#[test]
fn a_haas_programs_dollar_line_is_not_called_grbl() {
    let text = "%\nO1000 (HAAS VF2)\n$AXES=X,Y,Z\nG90 G21 F100\nG01 X1.\nM30\n%\n";
    let e = stopped(Dialect::Haas, text).expect("not run");
    assert_eq!(e, "t.nc:3:1: error: a '$' line is not an NC block of a Haas control: kezuri does not run it");
}
