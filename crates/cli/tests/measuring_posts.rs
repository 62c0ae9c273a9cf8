//! `probe plan` and `thermal plan` with every post they accept, as a user
//! runs them with a machine file: each program passes `kezuri check` with no
//! error and no warning, returns to G90 right after every G91 G28, applies
//! the tool's length offset (its H from the tool table) on its first Z move
//! after the tool change, and ends with the post's M30 or M2. The styles and
//! posts that cannot go together are refused by name. The LinuxCNC programs
//! also go through LinuxCNC's own interpreter, rs274, where it is installed.

mod common;

use std::path::Path;
use std::process::Command;

use common::{kezuri, ok, path};

const PROBE: [&str; 10] = ["probe", "plan", "--origin", "10,20", "--count", "4,3", "--pitch", "1", "--safe-z", "-60"];

/// A machine with a B axis whose T3 has its length in register H13.
fn machine(dir: &Path) -> String {
    let m = path(dir, "m.toml");
    let text = "[kinematics]\ntool = [\"X\", \"Y\", \"Z\", \"B\"]\nwork = []\n\
                [tools]\nlengths = { 13 = 101.6 }\n[tools.T3]\nshape = \"ball:2\"\nh = 13\n";
    std::fs::write(&m, text).unwrap();
    m
}

/// Writes a program with `args` (`-o` and the machine added) and checks it;
/// its text.
fn written(dir: &Path, name: &str, args: &[&str], post: &str) -> String {
    let m = machine(dir);
    let file = path(dir, name);
    let all: Vec<&str> =
        args.iter().copied().chain(["--post", post, "--machine", &m, "--tool-number", "3", "-o", &file]).collect();
    ok(&kezuri(&all));
    let text = std::fs::read_to_string(&file).unwrap();
    let what = format!("{} {post}", args[..2].join(" "));
    let report: serde_json::Value =
        serde_json::from_str(&ok(&kezuri(&["check", &file, "--machine", &m, "--json"]))).unwrap();
    assert_eq!(report["errors"], serde_json::json!([]), "{what}: errors\n{text}");
    assert_eq!(report["warnings"], serde_json::json!([]), "{what}: warnings\n{text}");
    assert_eq!(report["completed"], true, "{what}");
    framing(&text, &what, post);
    text
}

/// G90 after every G91 G28, G43 H13 on the first Z move after the tool
/// change (none on GRBL), the post's end.
fn framing(text: &str, what: &str, post: &str) {
    let lines: Vec<&str> = text.lines().collect();
    for (k, line) in lines.iter().enumerate() {
        if line.contains("G91 G28") {
            assert_eq!(lines.get(k + 1), Some(&"G90"), "{what}: line {} {line:?}", k + 1);
        }
    }
    let change = if post == "grbl" { "M0" } else { "T3 M" };
    let at = lines.iter().position(|l| l.starts_with(change)).unwrap_or_else(|| panic!("{what}: no tool change"));
    let first_z = lines[at..].iter().find(|l| l.split_whitespace().any(|w| w.starts_with('Z'))).unwrap();
    let lengths = post != "grbl";
    assert_eq!(first_z.contains("G43 H13 Z"), lengths, "{what}: first Z move {first_z:?}");
    assert!(first_z.starts_with("G0"), "{what}: the offset comes with a rapid, {first_z:?}");
    // The main program's end: before the subprograms (O1012 …), if any.
    let main = lines.iter().skip(2).position(|l| l.starts_with('O')).map_or(lines.len(), |k| k + 2);
    let end = lines[..main].iter().rev().find(|l| **l != "%");
    let want = if matches!(post, "linuxcnc" | "grbl") { "M2" } else { "M30" };
    assert_eq!(end, Some(&want), "{what}: the end");
    assert_eq!(text.matches(want).count(), 1, "{what}: one end");
    assert_eq!(text.starts_with("%\n"), matches!(post, "fanuc" | "haas"), "{what}: % framing");
}

/// The name of a program for `post`: `.ngc` is read as LinuxCNC (G4 P in
/// seconds).
fn file_name(stem: &str, post: &str) -> String {
    let ext = if matches!(post, "fanuc" | "haas") { "nc" } else { "ngc" };
    format!("{stem}-{post}.{ext}")
}

#[test]
fn probe_plans_for_every_post() {
    let dir = tempfile::tempdir().unwrap();
    for post in ["fanuc", "haas", "linuxcnc", "mach3", "grbl"] {
        let fanuc = matches!(post, "fanuc" | "haas");
        for style in ["subprogram", "expanded", "g31"] {
            let args: Vec<&str> = PROBE.iter().copied().chain(["--plunge", "15", "--style", style]).collect();
            if fanuc || style == "expanded" {
                let text = written(dir.path(), &file_name(style, post), &args, post);
                let (plunge, dwell) = if fanuc { ("\nG01 Z-", "\nG04 X0.5\n") } else { ("\nG1 Z-", "\nG4 P0.5\n") };
                if style != "g31" {
                    assert!(text.contains(plunge) && text.contains(dwell), "{post} {style}:\n{text}");
                }
            } else {
                let out = path(dir.path(), "refused.ngc");
                let all: Vec<&str> = args.iter().copied().chain(["--post", post, "-o", &out]).collect();
                let o = kezuri(&all);
                let e = String::from_utf8_lossy(&o.stderr);
                assert_eq!(o.status.code(), Some(1), "{post} {style}");
                assert!(e.contains("only Fanuc and Haas") && e.contains("--style expanded"), "{post} {style}: {e}");
                assert!(!Path::new(&out).exists(), "nothing written");
            }
        }
    }
}

#[test]
fn thermal_plans_for_every_post() {
    let dir = tempfile::tempdir().unwrap();
    for post in ["fanuc", "haas", "linuxcnc", "mach3"] {
        let text = written(dir.path(), &file_name("thermal", post), &["thermal", "plan"], post);
        let dwell = if matches!(post, "fanuc" | "haas") { "G04 X1. (SENSORS READ)" } else { "G4 P1 (SENSORS READ)" };
        assert_eq!(text.matches(dwell).count(), 22, "{post}:\n{text}");
    }
    let o = kezuri(&["thermal", "plan", "--machine", &machine(dir.path()), "--post", "grbl", "-o", "-"]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("GRBL has no rotary axis"));
}

/// LinuxCNC's interpreter applies the length offset (non-zero, from the
/// tool table) before the first move that changes Z after the tool change.
#[test]
fn linuxcnc_programs_through_rs274() {
    let rs274 = Path::new("/usr/bin/rs274");
    if !rs274.exists() {
        println!("skipped: /usr/bin/rs274 (LinuxCNC's interpreter, package linuxcnc-uspace) is not installed");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    // rs274 reads tool table lengths in inches: H13 is 4 in, 101.6 mm.
    let table = path(dir.path(), "tool.tbl");
    std::fs::write(&table, "T3 P3 Z1.0 D0.08 ;stylus\nT13 P13 Z4.0 D0.1 ;its length register\n").unwrap();
    let probe: Vec<&str> = PROBE.iter().copied().chain(["--plunge", "15", "--style", "expanded"]).collect();
    for (name, args) in [("probe.ngc", &probe[..]), ("thermal.ngc", &["thermal", "plan"][..])] {
        written(dir.path(), name, args, "linuxcnc");
        let out = path(dir.path(), "canon.txt");
        let run = Command::new(rs274).args(["-g", "-t", &table, &path(dir.path(), name), &out]).output().unwrap();
        let canon = std::fs::read_to_string(&out).unwrap_or_default();
        assert!(run.status.success(), "{name}: {}\n{canon}", String::from_utf8_lossy(&run.stderr));
        let (mut z, mut changed, mut offset) = (None, false, None);
        for line in canon.lines() {
            let args = |call: &str| -> Option<Vec<f64>> {
                let inner = line.split_once(call)?.1.strip_prefix('(')?.strip_suffix(')')?;
                Some(inner.split([',', ' ']).filter_map(|v| v.trim().parse().ok()).collect())
            };
            if line.contains("CHANGE_TOOL(") {
                changed = true;
            } else if let Some(v) = args("USE_TOOL_LENGTH_OFFSET") {
                offset = Some(v[2]);
            } else if let Some(v) = args("STRAIGHT_TRAVERSE").or_else(|| args("STRAIGHT_FEED")) {
                if changed && z.is_some_and(|z: f64| (z - v[2]).abs() > 1e-9) {
                    assert_eq!(offset, Some(101.6), "{name}: the first Z move after CHANGE_TOOL\n{canon}");
                    break;
                }
                z = Some(v[2]);
            }
        }
        assert!(changed && offset == Some(101.6), "{name}:\n{canon}");
        println!("{name}: rs274 applied the 101.6 mm length offset before the first Z move after the tool change");
    }
}
