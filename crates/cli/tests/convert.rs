//! `kezuri convert` as a user runs it: RML-1 with units, G-code to RML-1
//! and back, scaling with the cutter warning, shortening, bad input with
//! nothing written, bad usage with exit code 2.

use std::io::Write;
use std::path::Path;
use std::process::{Command, Output, Stdio};

mod common;
use common::kezuri;

fn kezuri_stdin(args: &[&str], input: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_kezuri"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("kezuri runs");
    child.stdin.take().unwrap().write_all(input.as_bytes()).unwrap();
    child.wait_with_output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn ok(o: &Output) -> String {
    assert!(o.status.success(), "{}", stderr(o));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn failed(o: &Output, code: i32) -> String {
    assert_eq!(o.status.code(), Some(code), "stdout: {}\nstderr: {}", String::from_utf8_lossy(&o.stdout), stderr(o));
    stderr(o)
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_string_lossy().into_owned()
}

fn rml_data(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../nc/testdata/rml").join(name).to_string_lossy().into_owned()
}

/// Files in `dir`, sorted.
fn files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}

#[test]
fn seed_002_listing_in_millimetres_not_counts() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("camm3.nc");
    let o = kezuri(&[
        "convert",
        &rml_data("paper_fig1.rml"),
        "--safe-z",
        "5",
        "--feed",
        "600",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(ok(&o), "");
    let nc = std::fs::read_to_string(&out).unwrap();
    assert!(nc.contains("G00 Z5.\nX0. Y0.\nG01 Z-2.4 F600.\nX0.39\nX0.78\n"), "{nc}");
    assert!(nc.contains("X4.31\nM30\n"), "{nc}");
    assert!(!nc.contains("X39.") && !nc.contains("Z-240."));
    // The paper's raw counts are 1 mm steps.
    let counts =
        ok(&kezuri(&["convert", &rml_data("paper_fig1.rml"), "--rml-unit", "1", "--safe-z", "50", "--feed", "600"]));
    assert!(counts.contains("G01 Z-240. F600.\nX39.\n"), "{counts}");
    // Without the height and the feed, located errors and no program.
    let o = kezuri(&["convert", &rml_data("paper_fig1.rml")]);
    let e = failed(&o, 1);
    assert!(e.contains("paper_fig1.rml:2:1: error: no tool-up height") && e.contains("--safe-z"), "{e}");
    assert!(e.contains("paper_fig1.rml:3:1: error: no feed") && e.contains("nothing written"), "{e}");
    assert!(o.stdout.is_empty());
}

#[test]
fn rml_is_recognised_by_its_text_and_on_stdin() {
    let dir = tempfile::tempdir().unwrap();
    let program = ";;^IN;V10;^PA;Z0,0,0;Z100,200,-50;^IN;";
    let txt = write(dir.path(), "from-the-engraver.txt", program);
    let nc = ok(&kezuri(&["convert", &txt, "--to", "grbl"]));
    assert!(nc.contains("G1 X0. Y0. Z0. F600.\nX1. Y2. Z-0.5\n"), "{nc}");
    let stdin = ok(&kezuri_stdin(&["convert", "-"], program));
    assert!(stdin.contains("G01 X0. Y0. Z0. F600.\nX1. Y2. Z-0.5\n"), "{stdin}");
    // The MDX-20 steps 0.025 mm.
    let mdx = ok(&kezuri_stdin(&["convert", "-", "--rml-unit", "0.025"], program));
    assert!(mdx.contains("X2.5 Y5. Z-1.25"), "{mdx}");
    // Scaled about the program zero.
    let big = ok(&kezuri_stdin(&["convert", "-", "--scale-xy", "2", "--scale-z", "0.5"], program));
    assert!(big.contains("X2. Y4. Z-0.25"), "{big}");
}

#[test]
fn gcode_to_rml_and_back() {
    let dir = tempfile::tempdir().unwrap();
    let nc = write(
        dir.path(),
        "part.nc",
        "%\nO0100\nG21 G90 G17\nS12000 M03\nG00 Z5.\nX10. Y10.\nG01 Z-1. F300.\nX30. F900.\n\
         G02 X40. Y20. I10. J0.\nG01 Y40.\nG00 Z5.\nX0. Y0.\nM05\nM30\n%\n",
    );
    let rml = dir.path().join("part.rml");
    ok(&kezuri(&["convert", &nc, "-o", rml.to_str().unwrap()]));
    let text = std::fs::read_to_string(&rml).unwrap();
    assert!(
        text.starts_with(
            ";;^IN;\n^PA;\n!PZ0,500;\n!MC1;\n^PU;\n^PU1000,1000;\nV5.0;\nZ1000,1000,-100;\nV15.0;\nZ3000,1000,-100;\n"
        ),
        "{text}"
    );
    assert!(text.ends_with("Z4000,4000,-100;\n^PU0,0;\n!MC0;\n^IN;\n"), "{text}");
    // The quarter arc is chords within half a step: 0.005 mm at 10 mm is
    // 0.063 rad, 25 chords; and three straight feeds.
    let chords = text.lines().filter(|l| l.starts_with('Z')).count();
    assert_eq!(chords, 25 + 3, "{text}");
    let back = dir.path().join("back.nc");
    ok(&kezuri(&["convert", rml.to_str().unwrap(), "-o", back.to_str().unwrap()]));
    let check = |file: &Path| -> serde_json::Value {
        serde_json::from_str(&ok(&kezuri(&["check", file.to_str().unwrap(), "--json"]))).unwrap()
    };
    let (a, b) = (check(Path::new(&nc)), check(&back));
    assert_eq!(a["bounds"], b["bounds"]);
    let (fa, fb) = (a["feed_length_mm"].as_f64().unwrap(), b["feed_length_mm"].as_f64().unwrap());
    assert!((fa - fb).abs() < 0.01, "{fa} vs {fb}");
    // A .gcode output is GRBL.
    let gcode = dir.path().join("back.gcode");
    ok(&kezuri(&["convert", rml.to_str().unwrap(), "-o", gcode.to_str().unwrap()]));
    assert!(std::fs::read_to_string(&gcode).unwrap().contains("\nG1 Z-1. F300.\n"));
}

#[test]
fn errors_leave_the_output_alone() {
    let dir = tempfile::tempdir().unwrap();
    let out = write(dir.path(), "out.nc", "keep\n");
    let cases: [(&str, &str, &str); 7] = [
        ("unknown.rml", "^PA;V10;\nZ0,0,0;^QQ1;\n", "unknown.rml:2:8: error: unknown RML-1 command '^QQ1'"),
        (
            "letters.rml",
            "^PA;V10;\nZ0,x,0;\n",
            "letters.rml:2:4: error: expected a number after ',' in 'Z0,', found 'x'",
        ),
        (
            "half.rml",
            "^IN;V10;Z0,0,0;\nG01 X10. Y10.\n",
            "half.rml:2:1: error: unknown RML-1 command 'G01' (this looks like G-code",
        ),
        ("empty.rml", "", "empty.rml: the program has no motion to convert; nothing written"),
        ("empty.nc", "%\n%\n", "empty.nc:3:1: error: the file holds no program"),
        ("still.nc", "G90 G21\nM30\n", "still.nc: the program has no motion to convert; nothing written"),
        ("bad.nc", "G01 X[1+] F100\n", "bad.nc:1:9: error"),
    ];
    for (name, text, want) in cases {
        let input = write(dir.path(), name, text);
        let e = failed(&kezuri(&["convert", &input, "-o", &out]), 1);
        assert!(e.contains(want), "{name}: {e}");
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "keep\n", "{name}");
    }
    // G-code that RML-1 cannot say: a dwell.
    let dwell = write(dir.path(), "dwell.nc", "G00 X0. Y0. Z5.\nG01 Z-1. F100.\nG04 P500\nM30\n");
    let rml = dir.path().join("dwell.rml");
    let e = failed(&kezuri(&["convert", &dwell, "-o", rml.to_str().unwrap()]), 1);
    assert!(e.contains("move 3 (line 3): a dwell (G04) has no RML-1 command"), "{e}");
    assert!(!rml.exists());
    // No temporary file is left behind.
    let names = files(dir.path());
    assert!(names.iter().all(|n| !n.ends_with(".tmp")), "{names:?}");
}

#[test]
fn bad_usage_is_exit_code_2_and_a_bad_number_1() {
    let input = rml_data("relief_rows.rml");
    for (args, code) in [
        (vec!["--scale-xy", "0"], 1),
        (vec!["--scale-z", "-1"], 2),
        (vec!["--scale-xy", "nan"], 1),
        (vec!["--rml-unit", "inf"], 1),
        (vec!["--tool", "drill:3"], 1),
        (vec!["--arcs"], 2),
        (vec!["--shorten", "-0.1"], 2),
        (vec!["--shorten", "0.01", "--arcs", "--to", "rml"], 2),
        (vec!["--from", "heidenhain"], 2),
    ] {
        let mut words = vec!["convert", input.as_str()];
        words.extend(&args);
        let o = kezuri(&words);
        failed(&o, code);
        assert!(o.stdout.is_empty(), "{args:?}");
    }
}

#[test]
fn scaling_warns_when_the_cutter_is_not_a_whole_millimetre() {
    let rows = rml_data("relief_rows.rml");
    let o = kezuri(&["convert", &rows, "--scale-xy", "1.3", "--tool", "ball:14"]);
    let e = stderr(&o);
    ok(&o);
    assert!(
        e.contains("needs a φ18.2 mm cutter, which is not a standard whole-millimetre diameter (nearest: φ18 and φ19)"),
        "{e}"
    );
    assert!(e.contains("ball:14 cutter's tip is stretched"), "{e}");
    let o = kezuri(&["convert", &rows, "--scale-xy", "1.5", "--scale-z", "1.5", "--tool", "ball:14"]);
    let e = stderr(&o);
    ok(&o);
    assert!(
        e.contains("note: scaled by 1.5 in X/Y, the program made for a ball:14 cutter (--tool) needs a φ21 mm cutter"),
        "{e}"
    );
    assert!(!e.contains("warning: scaled"), "{e}");
    // A cutter named in a comment of a G-code program.
    let dir = tempfile::tempdir().unwrap();
    let nc =
        write(dir.path(), "fusion.nc", "(T1 D=6. CR=0. - FLAT END MILL)\nG00 X0. Y0. Z5.\nG01 Z-1. F100.\nX10.\nM30\n");
    let e = stderr(&kezuri(&["convert", &nc, "--scale-xy", "1.25"]));
    // The CAM post's tool line gives the shape too.
    assert!(e.contains("a flat:6 cutter (line 1) needs a φ7.5 mm cutter"), "{e}");
    // None named: a note.
    let e = stderr(&kezuri(&["convert", &rows, "--scale-xy", "2"]));
    assert!(e.contains("note: the program names no cutter"), "{e}");
}

#[test]
fn shorten_merges_within_the_tolerance_and_fits_arcs() {
    let dir = tempfile::tempdir().unwrap();
    // A 10 mm circle as 360 G01 points, then a row of equal Z.
    let mut nc = String::from("G00 X10. Y0. Z5.\nG01 Z-1. F500.\n");
    for k in 1..=360 {
        let a = f64::from(k).to_radians();
        nc += &format!("X{:.4} Y{:.4}\n", 10.0 * a.cos(), 10.0 * a.sin());
    }
    for k in 1..=50 {
        nc += &format!("X{:.2} Y0. Z-1.\n", 10.0 + f64::from(k) * 0.39);
    }
    nc += "G00 Z5.\nM30\n";
    let input = write(dir.path(), "circle.nc", &nc);
    let o = kezuri(&["convert", &input, "--shorten", "0.01", "--arcs"]);
    let out = ok(&o);
    assert!(stderr(&o).contains("moves ->"), "{}", stderr(&o));
    let arcs = out.lines().filter(|l| l.starts_with("G03")).count();
    assert!(arcs >= 1, "{out}");
    assert!(out.lines().count() < 20, "{out}");
    let lines_only = ok(&kezuri(&["convert", &input, "--shorten", "0.01"]));
    assert!(!lines_only.contains("G03") && lines_only.lines().count() < 130);
    // The shortened program covers the same ground.
    let short = write(dir.path(), "short.nc", &out);
    let check = |f: &str| -> serde_json::Value { serde_json::from_str(&ok(&kezuri(&["check", f, "--json"]))).unwrap() };
    let (a, b) = (check(&input), check(&short));
    let (fa, fb) = (a["feed_length_mm"].as_f64().unwrap(), b["feed_length_mm"].as_f64().unwrap());
    assert!((fa - fb).abs() < 0.05, "{fa} vs {fb}");
    // Without --shorten, one block per move.
    let plain = ok(&kezuri(&["convert", &input]));
    assert!(plain.lines().count() > 400);
}

#[test]
fn help_explains_with_examples() {
    let help = ok(&kezuri(&["convert", "--help"]));
    for want in
        ["Examples:", "kezuri convert plate.rml --safe-z 5 --feed 600 -o plate.nc", "--rml-unit", "--shorten", "φ14"]
    {
        assert!(help.contains(want), "{want}");
    }
}

#[test]
fn a_spindle_turned_on_without_a_speed_is_never_s0() {
    let dir = tempfile::tempdir().unwrap();
    // RML-1's !MC1 and G-code's M03 without S: no speed is known, and S0
    // would stop the spindle.
    let rml = write(dir.path(), "on.rml", "^IN;^PA;!MC1;V10;Z0,0,0;Z100,0,-50;!MC0;");
    let nc = write(dir.path(), "on.nc", "G00 X0. Y0. Z5.\nM03\nG01 Z-1. F100.\nX10.\nM05\nM30\n");
    for input in [&rml, &nc] {
        let o = kezuri(&["convert", input]);
        let out = ok(&o);
        assert!(out.contains("\nM03\n") && !out.contains("S0"), "{out}");
        assert!(stderr(&o).contains("the spindle is turned on with no speed"), "{}", stderr(&o));
        let o = kezuri(&["convert", input, "--speed", "12000"]);
        assert!(ok(&o).contains("\nS12000 M03\n") && !stderr(&o).contains("no speed"), "{}", stderr(&o));
    }
    // A speed the program sets is kept, and no warning.
    let set = write(dir.path(), "set.nc", "S8000 M03\nG00 X0. Y0. Z5.\nG01 Z-1. F100.\nM30\n");
    let o = kezuri(&["convert", &set]);
    assert!(ok(&o).contains("\nS8000 M03\n") && !stderr(&o).contains("no speed"), "{}", stderr(&o));
}

#[test]
fn a_long_program_on_standard_input_converts_as_its_file_does() {
    // Over 8 MB: standard input is spooled to a temporary file and mapped,
    // and the conversion streams as a file's does.
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from("%\nO1000\nG21 G90 G17\nG0 X0 Y0 Z5.\nG1 Z-1. F1200.\n");
    for k in 0..400_000 {
        let (row, i) = (k / 1000, k % 1000);
        let i = if row % 2 == 1 { 999 - i } else { i };
        text += &format!(
            "X{:.3} Y{:.3} Z{:.3}\n",
            f64::from(i) * 0.1,
            f64::from(row) * 0.5,
            -1.0 - 0.001 * f64::from(k % 7)
        );
    }
    text += "G0 Z5.\nM30\n%\n";
    assert!(text.len() > 8 << 20);
    let file = write(dir.path(), "long.nc", &text);
    let from_file = ok(&kezuri(&["convert", &file, "--to", "linuxcnc", "--scale-xy", "2"]));
    let from_stdin = ok(&kezuri_stdin(&["convert", "-", "--to", "linuxcnc", "--scale-xy", "2"], &text));
    assert_eq!(from_stdin, from_file.replacen("(LONG.NC)", "(-)", 1));
    assert!(from_file.contains("(LONG.NC)") && from_file.lines().count() > 400_000, "{}", &from_file[..300]);
}
