//! Errors located and agreed: every command that reads a program says an
//! error as `file:line:column`, `check` fails where `run` refuses, `sim` and
//! `view` refuse no more than `check` and `run` do, counts read right, and a
//! word without a decimal point behind an error is named with the option
//! that reads it otherwise.

mod common;

use common::{kezuri, ok, path};

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn failed(o: &std::process::Output) -> String {
    assert_eq!(o.status.code(), Some(1), "{}", stderr(o));
    stderr(o)
}

/// A Fusion 360 program for a router (corpus/shop/shooshx__led_floor, from
/// github.com/shooshx/led_floor): its words have no decimal point, which a
/// Fanuc reads as least increments, and its first arc fails so.
const FUSION: &str =
    concat!(env!("CARGO_MANIFEST_DIR"), "/../../corpus/shop/shooshx__led_floor/1077_bore_speed_test.nc");

#[test]
fn a_fusion_router_program_names_the_option_that_reads_it() {
    let e = failed(&kezuri(&["check", FUSION]));
    assert!(
        e.contains(
            "1077_bore_speed_test.nc:21:1: error: the arc's end point is 34.6960 mm off its circle (radius 0.2700 \
             at the start, 34.9660 at the end): more than 0.02 mm, the control stops with an alarm; Y35 was read as \
             0.035 mm (Fanuc increments); with --no-decimal units it is 35 mm"
        ),
        "{e}"
    );
    // The option named is the one check takes, and with it the program runs.
    assert!(ok(&kezuri(&["check", "--help"])).contains("--no-decimal <NO_DECIMAL>"));
    let out = ok(&kezuri(&["check", FUSION, "--no-decimal", "units"]));
    assert!(out.contains("0 errors"), "{out}");
    for command in [&["run", FUSION][..], &["view", FUSION, "-o", "-"][..]] {
        let e = failed(&kezuri(command));
        assert!(e.contains("with --no-decimal units it is 35 mm"), "{command:?}: {e}");
    }
}

/// A GRBL program with cutter compensation, which GRBL has not; a LinuxCNC
/// rigid tap for a machine whose post is Fanuc's: `run` refuses both, and
/// `check` says the same and fails.
#[test]
fn check_fails_where_run_refuses() {
    let dir = tempfile::tempdir().unwrap();
    let grbl = path(dir.path(), "comp.gcode");
    std::fs::write(&grbl, "G21 G90 F300\nG0 X0 Y0 Z1\nG41 D1 G1 X10\nY10\nG40 X0\nM2\n").unwrap();
    let tap = path(dir.path(), "tap.ngc");
    std::fs::write(&tap, "G21 G90\nS500 M3\nG0 X0 Y0 Z5\nG33.1 Z-10 K1.5\nM2\n").unwrap();
    let machine = path(dir.path(), "m.toml");
    std::fs::write(&machine, "[post]\npreset = \"fanuc\"\n").unwrap();
    for (program, extra, said) in [
        (&grbl, vec![], "the program uses cutter radius compensation (G41/G42), which GRBL has not"),
        (&tap, vec!["--machine", machine.as_str()], "tap.ngc:4:1: "),
    ] {
        let args = |command: &'static str| [&[command, program.as_str()][..], &extra[..]].concat();
        let run = failed(&kezuri(&args("run")));
        assert!(run.contains(said), "{run}");
        let check = failed(&kezuri(&args("check")));
        assert!(check.contains("kezuri run refuses this") && check.contains(said), "{check}");
        let json = kezuri(&[&args("check")[..], &["--json"]].concat());
        assert_eq!(json.status.code(), Some(1));
        let v: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
        assert!(v["errors"][0].as_str().unwrap().contains(said), "{v}");
        assert_eq!(v["completed"], false);
    }
    // The rigid tap written with the linuxcnc post, as the program's own: no refusal.
    ok(&kezuri(&["check", &tap]));
    ok(&kezuri(&["run", &tap]));
}

/// What the writer refuses at a line of the program is said at that line.
#[test]
fn run_says_file_line_column() {
    let dir = tempfile::tempdir().unwrap();
    let nc = path(dir.path(), "rotary.nc");
    std::fs::write(&nc, "G90 G21 G94 F100.\nG00 X0. Y0. Z1.\n  G01 X10. A90.\nM30\n").unwrap();
    let e = failed(&kezuri(&["run", &nc, "--post", "grbl"]));
    assert!(e.contains("rotary.nc:3:3: grbl has no rotary axis A, but the toolpath turns it"), "{e}");
    assert!(!e.contains("move "), "{e}");
    // A feed of zero, in every command that runs the program.
    std::fs::write(&nc, "G90 G21 G94\nG00 X0. Y0. Z1.\nG01 X10. F0\nM30\n").unwrap();
    for command in ["check", "run", "view"] {
        let e =
            failed(&kezuri(&[command, &nc, "-o", &path(dir.path(), "out")][..if command == "check" { 2 } else { 4 }]));
        assert!(e.contains("rotary.nc:3:10: error: a cutting move at F0"), "{command}: {e}");
    }
}

#[test]
fn byte_order_marks_and_utf16() {
    let dir = tempfile::tempdir().unwrap();
    let nc = path(dir.path(), "bom.nc");
    std::fs::write(&nc, b"\xEF\xBB\xBFG90 G21 F100.\nG01 X1.\nM30\n").unwrap();
    let out = ok(&kezuri(&["check", &nc]));
    assert!(out.contains("0 errors, 0 warnings") && out.contains("1 motions"), "{out}");
    let wide: Vec<u8> = "\u{feff}G90 G21 F100.\nG01 X1.\nM30\n".encode_utf16().flat_map(u16::to_le_bytes).collect();
    std::fs::write(&nc, wide).unwrap();
    let e = failed(&kezuri(&["check", &nc]));
    assert!(e.contains("bom.nc: the file is UTF-16 text (little-endian, with the byte-order mark FF FE)"), "{e}");
    assert_eq!(e.lines().count(), 1, "{e}");
}

#[test]
fn counts_read_right_and_agree_with_the_list() {
    let dir = tempfile::tempdir().unwrap();
    let nc = path(dir.path(), "count.nc");
    std::fs::write(&nc, "G90 G21 F100.\nG01 X1\nM30\n").unwrap();
    let o = kezuri(&["check", &nc]);
    assert!(ok(&o).contains("  0 errors, 1 warning\n"), "{}", ok(&o));
    // Fifteen warnings of a kind: five shown, the rest counted in one line.
    let body: String = (1..=15).map(|i| format!("G01 X{i}\n")).collect();
    std::fs::write(&nc, format!("G90 G21 F100.\n{body}M30\n")).unwrap();
    let o = kezuri(&["check", &nc]);
    assert!(ok(&o).contains("  0 errors, 15 warnings\n"), "{}", ok(&o));
    assert!(stderr(&o).contains("… and 10 more warnings like these (decimal)"));
    std::fs::write(&nc, "G90 G21 F100.\nG01 X1. G02 X0. R0.1\nM30\n").unwrap();
    let o = kezuri(&["check", &nc]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stdout).contains("  1 error, 0 warnings\n"));
    assert!(stderr(&o).ends_with("count.nc: 1 error\n"), "{}", stderr(&o));
}

/// `D1` with no radius in the tool table: check and run warn and use the
/// programmed path; sim and view do the same, they do not refuse.
#[test]
fn sim_and_view_warn_of_a_missing_radius_as_check_does() {
    let dir = tempfile::tempdir().unwrap();
    let nc = path(dir.path(), "comp.nc");
    std::fs::write(&nc, "G90 G21 G94 F100.\nG00 X0. Y0. Z1.\nG01 Z-1.\nG41 D1 G01 X10.\nX20. Y5.\nG40 X30.\nM30\n")
        .unwrap();
    let warning = "comp.nc:4:5: warning: D1 has no radius in the tool table";
    for args in
        [vec!["check", &nc], vec!["sim", &nc, "--tool", "flat:6", "--res", "0.5"], vec!["view", &nc, "-o", "page.html"]]
    {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_kezuri"))
            .args(&args)
            .current_dir(dir.path())
            .output()
            .unwrap();
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(warning), "{args:?}: {}", stderr(&o));
    }
}
