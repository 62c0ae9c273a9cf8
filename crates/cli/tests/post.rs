//! Every command that makes a program, with every post: the rules a real
//! machine needs, read line by line from the written program; `check` of
//! each program gives no warning; the LinuxCNC programs through LinuxCNC's
//! own interpreter (rs274), which must apply the tool's length offset
//! before the first Z move after each tool change.

mod common;

use std::path::Path;
use std::process::Command;

use common::{kezuri, ok, path};

const POSTS: [&str; 5] = ["fanuc", "haas", "linuxcnc", "grbl", "mach3"];

/// A machine file whose tool table knows the registers the programs use,
/// so that `check` has a value for every H.
const MACHINE: &str = "[tools]\nlengths = { 1 = 100.0, 2 = 90.0, 5 = 80.0 }\n";

/// A 20 × 20 mm dome as a height grid.
fn dome(dir: &Path) -> String {
    let mut text = String::new();
    for j in 0..=40 {
        for i in 0..=40 {
            let (x, y) = (f64::from(i) * 0.5 - 10.0, f64::from(j) * 0.5 - 10.0);
            text += &format!("{x} {y} {}\n", (150.0 - x * x - y * y).max(0.0).sqrt() - 10.0);
        }
    }
    let p = path(dir, "dome.xyz");
    std::fs::write(&p, text).unwrap();
    p
}

/// The programs each command makes with `post`, named by command.
fn made(dir: &Path, post: &str) -> Vec<(&'static str, String)> {
    let dome = dome(dir);
    let sketch = concat!(env!("CARGO_MANIFEST_DIR"), "/../../samples/plum-sketch.png");
    let ext = if post == "linuxcnc" { "ngc" } else { "nc" };
    let out = |name: &str| path(dir, &format!("{name}-{post}.{ext}"));
    let mill = out("mill");
    ok(&kezuri(&[
        "mill",
        &dome,
        "--tool",
        "ball:4",
        "--stepover",
        "2",
        "--tool-number",
        "5",
        "--post",
        post,
        "-o",
        &mill,
    ]));
    let relief = out("relief");
    ok(&kezuri(&[
        "relief",
        sketch,
        "--width",
        "20",
        "--depth",
        "2",
        "--tool",
        "ball:3",
        "--rough",
        "flat:6",
        "--stepover",
        "2",
        "--rough-stepover",
        "4",
        "--post",
        post,
        "-o",
        &relief,
    ]));
    // Readings of the dome by a 4 mm ball stylus, copied with it.
    let readings = path(dir, "readings.txt");
    ok(&kezuri(&[
        "probe", "simulate", &dome, "--count", "9,9", "--pitch", "2", "--origin", "-8,-8", "--stylus", "ball:4", "-o",
        &readings,
    ]));
    let copy = out("copy");
    ok(&kezuri(&["probe", "mill", &readings, "--stylus", "ball:4", "--tool", "ball:4", "--post", post, "-o", &copy]));
    vec![("mill", mill), ("relief", relief), ("probe mill", copy)]
}

/// The rules, block by block: G90 right after every G91 G28 or G30; after
/// each tool change, the spindle on before the first feed into the
/// material and (where the post uses length offsets) G43 H on the first
/// block that moves Z; M05 before the program end.
fn keeps_the_rules(what: &str, post: &str, text: &str) {
    let lines: Vec<&str> = text.lines().filter(|l| !l.starts_with('(')).collect();
    let offsets = post != "grbl";
    let word = |l: &str, w: &str| l.split_whitespace().any(|x| x == w);
    let (mut changed, mut spindle, mut first_z_done, mut xy) = (false, false, true, false);
    for (k, l) in lines.iter().enumerate() {
        let at = format!("{what} --post {post}, block {}: '{l}'", k + 1);
        if l.contains("G91 G28") || l.contains("G91 G30") {
            assert!(lines[k + 1].starts_with("G90"), "{at}: no G90 after it");
        }
        let change = word(l, "M06") || word(l, "M6") || (post == "grbl" && word(l, "M0"));
        if change {
            (changed, spindle, first_z_done, xy) = (true, false, false, false);
        }
        if word(l, "M03") || word(l, "M3") {
            spindle = true;
        }
        if word(l, "M05") || word(l, "M5") {
            spindle = false;
        }
        let machine_move = l.contains("G28") || l.contains("G53");
        xy |= !machine_move && (l.contains('X') || l.contains('Y'));
        if changed && !first_z_done && l.contains('Z') && !machine_move {
            assert_eq!(l.contains("G43 H"), offsets, "{at}: the first Z move after the tool change");
            // After a retract the tool is placed in X Y at the top first;
            // GRBL (no retract) takes Z up first.
            assert!(xy || post == "grbl", "{at}: Z goes down before X Y are placed");
            first_z_done = true;
        }
        let feed = word(l, "G01") || word(l, "G1") || (l.starts_with('X') || l.starts_with('Y') || l.starts_with('Z'));
        if changed && feed && l.contains('F') {
            assert!(spindle, "{at}: a feed with the spindle off");
        }
    }
    assert!(changed, "{what} --post {post}: no tool change");
    let end = lines.iter().rposition(|l| word(l, "M30") || word(l, "M2")).expect("a program end");
    let stop = lines.iter().rposition(|l| word(l, "M05") || word(l, "M5")).expect("M05");
    assert!(stop < end, "{what} --post {post}: M05 after the end");
}

#[test]
fn every_made_program_keeps_the_rules_and_checks_clean() {
    let dir = tempfile::tempdir().unwrap();
    let machine = path(dir.path(), "m.toml");
    std::fs::write(&machine, MACHINE).unwrap();
    for post in POSTS {
        for (what, file) in made(dir.path(), post) {
            let text = std::fs::read_to_string(&file).unwrap();
            keeps_the_rules(what, post, &text);
            // Mach3 reads as LinuxCNC does (G91.1, whole-unit words).
            let reading: &[&str] = if post == "mach3" { &["--dialect", "linuxcnc"] } else { &[] };
            let o = kezuri(&[&["check", file.as_str(), "--machine", &machine, "--json"][..], reading].concat());
            let v: serde_json::Value = serde_json::from_str(&ok(&o)).unwrap();
            assert_eq!(v["warnings"], serde_json::json!([]), "{what} --post {post}: {v}");
            assert_eq!(v["errors"], serde_json::json!([]), "{what} --post {post}: {v}");
        }
    }
}

#[test]
fn check_warns_on_a_z_move_without_a_length_offset() {
    let dir = tempfile::tempdir().unwrap();
    let nc = path(dir.path(), "bare.nc");
    std::fs::write(&nc, "%\nO0001\nG21 G90 G54\nT1 M06\nS1000 M03\nG00 X0. Y0.\nG00 Z5.\nG01 Z-1. F100.\nM30\n%\n")
        .unwrap();
    let warned = |args: &[&str]| -> Vec<String> {
        let v: serde_json::Value = serde_json::from_str(&ok(&kezuri(args))).unwrap();
        v["warnings"].as_array().unwrap().iter().map(|w| w.as_str().unwrap().to_string()).collect()
    };
    let w = warned(&["check", &nc, "--json"]);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("line 7: Z moves after the change to T1 with no tool length offset (G43 H)"), "{w:?}");
    // A machine file that says the machine does not use length offsets, or
    // whose post is GRBL's (which has none).
    for said in ["[post]\nlength_offset = false\n", "[post]\npreset = \"grbl\"\n"] {
        let m = path(dir.path(), "router.toml");
        std::fs::write(&m, said).unwrap();
        assert!(warned(&["check", &nc, "--machine", &m, "--json"]).is_empty(), "{said}");
    }
    // T2 cut with T1's offset, still in force after the change (G43 is
    // modal across M06); T3 with H0; T4 with a register the table does not
    // give it: each is a Z that is not the tool tip's.
    let table = path(dir.path(), "table.toml");
    std::fs::write(&table, "[tools]\nlengths = { 1 = 100.0, 2 = 120.0, 4 = 90.0, 24 = 95.0 }\n[tools.T4]\nh = 24\n")
        .unwrap();
    let program = "%\nO0002\nG21 G90 G54\nT1 M06\nG00 X0. Y0.\nG00 G43 H1 Z20.\nG01 Z-1. F100.\nG91 G28 Z0.\nG90\n\
                   T2 M06\nG00 X10. Y10.\nZ20.\nG01 Z-1. F100.\nT3 M06\nG00 G43 H0 Z20.\nT4 M06\nG00 G43 H4 Z20.\n\
                   T1 M06\nG00 G43 H1 Z20.\nM30\n%\n";
    std::fs::write(&nc, program).unwrap();
    let w = warned(&["check", &nc, "--machine", &table, "--json"]);
    assert_eq!(w.len(), 3, "{w:#?}");
    assert!(
        w[0].contains("line 12: Z moves after the change to T2 with the last tool's length offset (H1) still"),
        "{w:?}"
    );
    assert!(w[1].contains("line 15: Z moves after the change to T3 with no tool length offset (G43 H)"), "{w:?}");
    assert!(
        w[2].contains("line 17: Z moves after the change to T4 with H4 in force where the tool table gives T4 H24"),
        "{w:?}"
    );
    // With G43 H1 on that move: no warning.
    std::fs::write(&nc, "%\nO0001\nG21 G90 G54\nT1 M06\nG00 X0. Y0.\nG00 G43 H1 Z5.\nM30\n%\n").unwrap();
    let with = path(dir.path(), "with.toml");
    std::fs::write(&with, MACHINE).unwrap();
    assert!(warned(&["check", &nc, "--machine", &with, "--json"]).is_empty());
}

/// LinuxCNC's own interpreter runs the LinuxCNC programs: after each
/// CHANGE_TOOL, a USE_TOOL_LENGTH_OFFSET with the tool's length comes
/// before the first move that changes Z. rs274 reads a tool table's Z in
/// inches: T1 1 in, T2 2 in, T5 3 in.
#[test]
fn linuxcnc_applies_the_length_offset_before_the_first_z_move() {
    if Command::new("rs274").arg("-h").output().is_err() {
        // CI installs it and sets KEZURI_REQUIRE_RS274: there it must run.
        assert!(std::env::var_os("KEZURI_REQUIRE_RS274").is_none(), "rs274 is required and missing");
        eprintln!("rs274 (LinuxCNC's interpreter, Debian package linuxcnc-uspace) is not here: skipped");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let table = path(dir.path(), "tool.tbl");
    std::fs::write(&table, "T1 P1 Z1.0 D0.24\nT2 P2 Z2.0 D0.12\nT5 P5 Z3.0 D0.16\n").unwrap();
    for (what, file) in made(dir.path(), "linuxcnc") {
        let canon = path(dir.path(), "canon.txt");
        // rs274 keeps its tool table in $HOME/.tool.mmap and empties it on
        // every run: runs side by side (other tests, other users) need a
        // home each.
        let o =
            Command::new("rs274").args(["-g", "-t", &table, &file, &canon]).env("HOME", dir.path()).output().unwrap();
        let out = std::fs::read_to_string(&canon).unwrap_or_default();
        assert!(out.contains("PROGRAM_END"), "{what}: rs274 stopped\n{}\n{out}", String::from_utf8_lossy(&o.stdout));
        let (mut selected, mut tool, mut offset, mut z, mut changes) = (0, 0, None::<f64>, None::<f64>, 0);
        for l in out.lines() {
            // SELECT_TOOL names the tool; CHANGE_TOOL gives its pocket index.
            if let Some(t) = l.split("SELECT_TOOL(").nth(1) {
                selected = t.trim_end_matches(')').parse::<u32>().unwrap();
            }
            if l.contains("CHANGE_TOOL(") {
                (tool, offset) = (selected, None);
                changes += 1;
            }
            if let Some(args) = l.split("USE_TOOL_LENGTH_OFFSET(").nth(1) {
                offset = args.split(',').next().unwrap().split_whitespace().nth(2).map(|v| v.parse().unwrap());
            }
            let moved = l.split("STRAIGHT_TRAVERSE(").nth(1).or_else(|| l.split("STRAIGHT_FEED(").nth(1));
            if let Some(args) = moved {
                let new_z: f64 = args.split(',').nth(2).unwrap().trim().parse().unwrap();
                if tool != 0 && z.is_some_and(|z| (z - new_z).abs() > 1e-9) {
                    let inches = [(1, 1.0), (2, 2.0), (5, 3.0)].iter().find(|(t, _)| *t == tool).unwrap().1;
                    let applied = offset.is_some_and(|o| (o - 25.4 * inches).abs() < 1e-4);
                    assert!(applied, "{what}: T{tool} moves Z to {new_z} with offset {offset:?}");
                }
                z = Some(new_z);
            }
        }
        assert!(changes >= 1, "{what}: no CHANGE_TOOL\n{out}");
    }
}
