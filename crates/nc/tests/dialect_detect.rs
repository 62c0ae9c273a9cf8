//! The one rule that chooses a program's dialect when `--dialect` is not
//! given (docs/linuxcnc.md, "Choosing the dialect"): extensions × contents.

use kezuri_nc::{detect, Dialect};

/// Programs by what they carry.
const PLAIN: &str = "G21 G90\nG1 X50 Y20 F300\nM2\n";
const LINUXCNC_SUB: &str = "G21\no100 sub\nG1 X#1 F100\no100 endsub\no100 call [5]\nM2\n";
const LINUXCNC_NAMED: &str = "#<depth> = 2\nG1 Z-#<depth> F100\nM2\n";
const LINUXCNC_DEBUG: &str = "G21\n(debug, hello)\nG1 X1 F100\nM2\n";
const LINUXCNC_G64: &str = "G21\nG64 P0.01 Q0.01\nG1 X1 F100\nM2\n";
const LINUXCNC_POLAR: &str = "G21\nG1 @10 ^45 F100\nM2\n";
const FANUC_O: &str = "%\nO1234 (PART)\nG21 G90\nG1 X50. F300.\nM30\n%\n";
const FANUC_G65: &str = "G21\nG65 P9010 A1.\nM30\n";
const FANUC_GOTO: &str = "#1=0\nN10 #1=#1+1\nIF [#1 LT 3] GOTO 10\nM30\n";
const FANUC_WHILE: &str = "#1=0\nWHILE [#1 LT 3] DO1\n#1=#1+1\nEND1\nM30\n";
const HAAS: &str = "G21\nG154 P5\nG1 X50. F300.\nM30\n";
const GRBL: &str = "$H\nG21\nG1 X50 F300\n";
const MIXED: &str = "O1234\nG21\no100 sub\no100 endsub\nM30\n";
/// An old Fanuc program's comment that looks like a LinuxCNC command.
const FANUC_PRINT: &str = "G0 X50000 Y12500\n(PRINT, SETUP SHEET REV 2)\nG1 Z-1000 F100\nM30\n";
/// Markers in comments do not count.
const COMMENTED: &str = "(O1234 was the old number; o100 sub, G65)\n; #<x>\nG1 X1. F1.\nM30\n";

#[test]
fn extensions_by_contents() {
    use Dialect::*;
    // (file, text, the dialect or None for a refusal, the reason / a piece of the refusal).
    let table: &[(&str, &str, Option<Dialect>, &str)] = &[
        ("a.ngc", PLAIN, Some(LinuxCnc), "the extension .ngc"),
        ("a.NGC", PLAIN, Some(LinuxCnc), "the extension .ngc"),
        ("a.gcode", PLAIN, Some(Grbl), "the extension .gcode"),
        ("a.gc", PLAIN, Some(Grbl), "the extension .gc"),
        ("a.nc", PLAIN, Some(Fanuc), "the default (no extension or marker of another dialect)"),
        ("a.tap", PLAIN, Some(Fanuc), "the default (no extension or marker of another dialect)"),
        ("", PLAIN, Some(Fanuc), "the default (no extension or marker of another dialect)"),
        ("a.nc", LINUXCNC_SUB, Some(LinuxCnc), "o100 sub on line 2"),
        ("a.tap", LINUXCNC_SUB, Some(LinuxCnc), "o100 sub on line 2"),
        ("a.ngc", LINUXCNC_SUB, Some(LinuxCnc), "o100 sub on line 2"),
        ("a.gcode", LINUXCNC_SUB, Some(LinuxCnc), "o100 sub on line 2"),
        ("a.nc", LINUXCNC_NAMED, Some(LinuxCnc), "#<…> on line 1"),
        // A comment decides nothing, LinuxCNC's comment commands included:
        // a Fanuc program may say (PRINT, …), and X50 would become 50 mm.
        ("a.nc", LINUXCNC_DEBUG, Some(Fanuc), "the default (no extension or marker of another dialect)"),
        ("a.nc", FANUC_PRINT, Some(Fanuc), "the default (no extension or marker of another dialect)"),
        ("a.ngc", LINUXCNC_DEBUG, Some(LinuxCnc), "the extension .ngc"),
        ("a.nc", LINUXCNC_G64, Some(LinuxCnc), "G64 P on line 2"),
        ("a.nc", LINUXCNC_POLAR, Some(LinuxCnc), "@ on line 2"),
        ("a.nc", FANUC_O, Some(Fanuc), "O1234 on line 2"),
        ("a.tap", FANUC_O, Some(Fanuc), "O1234 on line 2"),
        ("", FANUC_G65, Some(Fanuc), "G65 on line 2"),
        ("a.nc", FANUC_GOTO, Some(Fanuc), "GOTO on line 3"),
        ("a.nc", FANUC_WHILE, Some(Fanuc), "WHILE on line 2"),
        ("a.nc", HAAS, Some(Haas), "G154 on line 2"),
        ("a.nc", GRBL, Some(Grbl), "$H on line 1"),
        ("a.ngc", GRBL, Some(LinuxCnc), "the extension .ngc"),
        ("a.nc", COMMENTED, Some(Fanuc), "the default (no extension or marker of another dialect)"),
        // Refusals: both families' evidence.
        ("a.nc", MIXED, None, "O1234 on line 1 is fanuc's and o100 sub on line 3 is linuxcnc's"),
        ("a.ngc", FANUC_O, None, "the extension .ngc says linuxcnc but O1234 on line 2 is fanuc's"),
        ("a.gcode", FANUC_G65, None, "the extension .gcode says grbl but G65 on line 2 is fanuc's"),
        ("a.ngc", HAAS, None, "G154 on line 2 is haas's"),
        ("a.nc", &format!("{HAAS}$H\n"), None, "G154 on line 2 is haas's and $H on line 5 is grbl's"),
    ];
    for (file, text, want, why) in table {
        let got = detect(None, file, text);
        match want {
            Some(d) => {
                let got = got.unwrap_or_else(|e| panic!("{file}: {text:?}: refused: {e}"));
                assert_eq!((got.dialect, got.reason.as_str()), (*d, *why), "{file}: {text:?}");
            }
            None => {
                let e = got.expect_err(&format!("{file}: {text:?} must be refused"));
                assert!(e.contains(why) && e.contains("--dialect"), "{file}: {e}");
            }
        }
    }
}

#[test]
fn given_dialect_wins_and_says_so() {
    for d in Dialect::ALL {
        let got = detect(Some(d), "a.nc", MIXED).unwrap();
        assert_eq!(got.dialect, d);
        assert_eq!(got.to_string(), format!("dialect {d}: given with --dialect"));
    }
    let got = detect(None, "dir/a.ngc", PLAIN).unwrap();
    assert_eq!(got.to_string(), "dialect linuxcnc: the extension .ngc");
}

#[test]
fn lower_case_and_sequence_numbers() {
    let got = detect(None, "a.nc", "n10 o<probe> call\n").unwrap();
    assert_eq!(got.dialect, Dialect::LinuxCnc);
    let got = detect(None, "a.nc", "N5 if [#1 gt 2] goto 7\n").unwrap();
    assert_eq!(got.dialect, Dialect::Fanuc);
    // G64 without P is Fanuc's cutting mode too: no marker.
    assert_eq!(detect(None, "a.nc", "G64\n").unwrap().dialect, Dialect::Fanuc);
    assert!(detect(None, "a.nc", "G64\n").unwrap().reason.starts_with("the default"));
}

/// A CAM system's header names the machine or the post it wrote for: the
/// rule reads it where the code says nothing, and says so.
#[test]
fn cam_headers_name_the_control() {
    use Dialect::*;
    // Fusion 360's Haas post: `(Machine)` then `(  vendor: Haas Automation)`.
    let fusion_haas =
        "%\nO1001 (BRACKET)\n(Machine)\n(  vendor: Haas Automation)\n(  model: VF-2)\nG21 G90\nG1 X5. F100.\nM30\n%\n";
    let got = detect(None, "a.nc", fusion_haas).unwrap();
    assert_eq!(got.dialect, Haas, "{got}");
    assert_eq!(got.reason, "O1001 on line 2 and the CAM header's comment (vendor: Haas Automation) on line 4");
    // HAAS in a comment of the head, with no code marker at all.
    let haas = "(MACHINE: HAAS VF2)\nG21 G90\nG1 X5. F100.\nM30\n";
    let got = detect(None, "a.nc", haas).unwrap();
    assert_eq!((got.dialect, got.reason.as_str()), (Haas, "the CAM header's comment (MACHINE: HAAS VF2) on line 1"));
    // Fusion's MPCNC post (a GRBL/Marlin machine): X10 is 10 mm.
    let mpcnc = "%\n(Fusion CAM 2.0.18961)\n( Posts processor: MPCNC21.cps)\nG0 Z3 F300\nG1 Z-3 F1000\n";
    let got = detect(None, "a.nc", mpcnc).unwrap();
    assert_eq!(got.dialect, Grbl, "{got}");
    assert!(got.reason.contains("Posts processor: MPCNC21.cps") && got.reason.ends_with("on line 3"), "{got}");
    // A maker named outside a machine or post comment decides nothing.
    for note in ["(CUT THE GRBL LOGO)", "(THE LAST ONE IS VALID, AS ON A LINUXCNC CONTROL: X1 IS 1 MM)"] {
        let got = detect(None, "a.nc", &format!("{note}\nG21\nG1 X5. F100.\nM30\n")).unwrap();
        assert_eq!(
            (got.dialect, got.reason.as_str()),
            (Fanuc, "the default (no extension or marker of another dialect)")
        );
    }
    // The code's markers and the extension come first.
    assert_eq!(detect(None, "a.ngc", haas).unwrap().dialect, LinuxCnc);
}

/// `$` lines that are no GRBL command (a Haas program's) are no GRBL
/// evidence: the program is not refused as mixed.
#[test]
fn dollar_lines_that_are_not_grbl_commands() {
    let haas = "%\nO1000 (HAAS VF2)\n$AXES=X,Y,Z\nG21 G90\nG1 X1. F100.\nM30\n%\n";
    let got = detect(None, "a.nc", haas).unwrap();
    assert_eq!(got.dialect, Dialect::Haas, "{got}");
    for grbl in ["$H", "$X", "$J=G91 X1 F100", "$$", "$#", "$110=500", "$N0=G21", "$SLP", "$RST=*"] {
        let got = detect(None, "a.nc", &format!("{grbl}\nG21\nG1 X50 F300\n")).unwrap();
        assert_eq!(got.dialect, Dialect::Grbl, "{grbl}: {got}");
    }
}
