//! The command line as a user runs it: exit codes, JSON keys, files.

use std::io::Write;
use std::path::{Path, PathBuf};
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

fn sample(name: &str) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../samples").join(name);
    root.to_string_lossy().into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn check_json_on_the_digitizing_program() {
    let o = kezuri(&["check", &sample("o1011-digitize.nc"), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("one JSON object");
    // 85 x 105 plunges of three moves (step, down, up), 105 row returns, the
    // approach (2) and G91 G28 Z0 (no intermediate move, then home).
    assert_eq!(v["motions"], 85 * 105 * 3 + 105 + 2 + 1);
    // 100 mm of feed per plunge plus the 30 mm approach.
    let feed = v["feed_length_mm"].as_f64().unwrap();
    assert!((feed - (8925.0 * 100.0 + 30.0)).abs() < 1e-6, "{feed}");
    // 1 mm steps, 105 returns of hypot(85, 1), 30 mm home.
    let rapid = v["rapid_length_mm"].as_f64().unwrap();
    let want = 8925.0 + 105.0 * (85.0f64.hypot(1.0)) + 30.0;
    assert!((rapid - want).abs() < 1e-6, "{rapid} vs {want}");
    assert_eq!(v["bounds"]["min"], serde_json::json!([0.0, 0.0, -20.0]));
    assert_eq!(v["bounds"]["max"], serde_json::json!([85.0, 105.0, 30.0]));
    // 8,925 dwells of 0.5 s alone are 4,462.5 s.
    assert!(v["time_s"].as_f64().unwrap() > 4462.5);
    assert!(v["warnings"].as_array().unwrap().is_empty(), "{}", v["warnings"]);
    assert!(v["blocks"].as_u64().unwrap() > 8925 * 6);
}

/// The relief of the README's tour, checked with the sample router's
/// machine file (T1 31.75 mm long): the bounds are the tool tip's over the
/// program's own moves, not the reference point's Z less the tool length
/// (-31.75 before); the three `G91 G28` returns are counted apart.
#[test]
fn check_bounds_are_the_tip_s_in_program_coordinates() {
    let dir = tempfile::tempdir().unwrap();
    let nc = dir.path().join("plum.nc").to_string_lossy().into_owned();
    let o = kezuri(&[
        "relief",
        &sample("plum-sketch.png"),
        "--width",
        "40",
        "--depth",
        "3",
        "--tool",
        "ball:3",
        "--stepover",
        "1",
        "-o",
        &nc,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let machine = sample("tools/mill.toml");
    let o = kezuri(&["check", &nc, "--machine", &machine, "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["bounds"]["min"], serde_json::json!([0.078, 0.078, -3.0]), "{}", v["bounds"]);
    assert_eq!(v["bounds"]["max"], serde_json::json!([39.922, 29.922, 5.0]), "{}", v["bounds"]);
    assert_eq!(v["machine_moves"], 3);
    let o = kezuri(&["check", &nc, "--machine", &machine]);
    let text = stdout(&o);
    assert!(text.contains("  Z     -3.000 …      5.000\n"), "{text}");
    assert!(text.contains("  3 moves in machine coordinates (G28/G30/G53), not in the bounds\n"), "{text}");
    // A work offset from the machine file: still program coordinates.
    let shifted = dir.path().join("shifted.toml");
    std::fs::write(&shifted, "[offsets]\nG54 = [-300, -200, -400]\n").unwrap();
    let o = kezuri(&["check", &nc, "--machine", &shifted.to_string_lossy(), "--json"]);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let min: Vec<f64> = v["bounds"]["min"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    assert!(min.iter().zip([0.078, 0.078, -3.0]).all(|(a, b)| (a - b).abs() < 1e-9), "{min:?}");
}

#[test]
fn check_reports_a_located_error_with_exit_code_1() {
    let o = kezuri_stdin(&["check", "-"], "G01 X10. F100.\nG01 X[1+] Y2.\nM30\n");
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(err.contains("<stdin>:2:"), "{err}");
    assert!(err.contains('^'), "{err}");
}

#[test]
fn warnings_carry_file_line_and_column_in_json() {
    let o = kezuri_stdin(&["check", "-", "--json"], "G01 X100 F100.\nM30\n");
    assert!(o.status.success());
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let w = v["warnings"][0].as_str().unwrap();
    assert!(w.starts_with("<stdin>:1:5: warning:"), "{w}");
    assert_eq!(v["bounds"]["max"][0], 0.1);
}

#[test]
fn bad_usage_exits_2() {
    let o = kezuri(&["check"]);
    assert_eq!(o.status.code(), Some(2));
    let o = kezuri(&["run", "x.nc", "--emit", "nonsense"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn run_writes_csv_and_nothing_on_error() {
    let dir = tempfile::tempdir().unwrap();
    let out: PathBuf = dir.path().join("moves.csv");
    let o = kezuri(&["run", &sample("o2007-thermal.nc"), "--emit", "csv", "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.starts_with("line,kind,x,y,z,a,b,c,feed\n"));
    assert!(text.lines().any(|l| l.contains(",-90,0,")), "B-90 indexing: {text}");

    let bad = dir.path().join("bad.nc");
    std::fs::write(&bad, "#1=1/0\nM30\n").unwrap();
    let out2 = dir.path().join("never.nc");
    let o = kezuri(&["run", bad.to_str().unwrap(), "-o", out2.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("division by zero"));
    assert!(!out2.exists());
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty());
}

#[test]
fn same_clock_seed_same_bytes() {
    let a = kezuri(&["run", &sample("o7023-texture.nc"), "--clock-seed", "11"]);
    let b = kezuri(&["run", &sample("o7023-texture.nc"), "--clock-seed", "11"]);
    let c = kezuri(&["run", &sample("o7023-texture.nc"), "--clock-seed", "12"]);
    assert!(a.status.success(), "{}", stderr(&a));
    assert_eq!(a.stdout, b.stdout);
    assert_ne!(a.stdout, c.stdout);
    assert!(stdout(&a).starts_with('%'));
}

#[test]
fn subprograms_come_from_the_library_folder() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("O0100.nc"), "O0100\nG91 G01 X#24 F100.\nM99\n").unwrap();
    let main = dir.path().join("main.nc");
    std::fs::write(&main, "G90 G00 X0. Y0. Z0.\nG65 P100 X2.5 L2\nM30\n").unwrap();
    let o = kezuri(&["run", main.to_str().unwrap(), "--emit", "csv"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let last = stdout(&o).lines().last().unwrap().to_string();
    assert!(last.contains(",feed,5,0,0,"), "{last}");
}

#[test]
fn demo_makes_its_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("demo");
    let o = kezuri(&["demo", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    for f in [
        "o1011-digitize-expanded.nc",
        "o7023-texture.csv",
        "o2007-thermal.svg",
        "samples/dome.stl",
        "dome-ball.nc",
        "dome-ball.png",
        "dome-ball-deviation.png",
        "dome-oval.cl",
        "samples/plum-mould.xyz",
        "plum.txt",
        "plum-level.txt",
        "plum.dxf",
        "plum.stl",
        "plum.png",
        "plum-copy.nc",
        "plum-copy-deviation.png",
        "samples/plum-sketch.png",
        "plum-relief.nc",
        "plum-tools.toml",
        "plum-relief.stl",
        "plum-relief.png",
        "samples/nameplate-cam.nc",
        "nameplate-textured.nc",
        "nameplate-macro.nc",
        "nameplate-textured.png",
        "samples/mill-turn.toml",
        "O2007-plan.nc",
        "thermal-meas.csv",
        "thermal-model.json",
        "o2007-corrected.nc",
        "thermal-before-after.svg",
        "tool-T7-new/f00.png",
        "tool-T7-worn.csv",
        "tool-T7-worn.png",
        "tools.sqlite",
        "tool-T7-wear.png",
        "groove-T7.nc",
        "groove-deviation.png",
        "groove-before-after.png",
    ] {
        assert!(out.join(f).exists(), "{f}");
    }
    // The finishing program on the dome and the relief carving cut within
    // the 0.01 mm tolerance; the copy of the plum mould (from readings with
    // ±0.003 mm of noise) within what `probe mill` warns of at the mould's
    // rim, where the ball rolls round an edge: a straight line between
    // readings would pass p²/(8ρ) below its path (25 µm for ρ = 5 mm at
    // 1 mm), the surface followed between them 17 µm (docs/probe-copy.md;
    // `--between bound` cuts 6.6 µm below the model there, from the noise,
    // and leaves 25 µm between readings).
    let report = stdout(&o);
    let gouges: Vec<f64> = report
        .lines()
        .filter_map(|l| l.trim().strip_prefix("max gouge"))
        .filter_map(|rest| rest.split_whitespace().next()?.parse().ok())
        .collect();
    assert_eq!(gouges.len(), 5, "{report}");
    // The thermal pipeline: O2007's 22 stops corrected to within 0.1 µm.
    let line = report.lines().find(|l| l.starts_with("thermal-before-after.svg: 22 stops")).expect(&report);
    let after: f64 = line.rsplit(", ").next().unwrap().split_whitespace().next().unwrap().parse().unwrap();
    assert!(after < 0.1, "{line}");
    assert!(gouges[0] <= 0.01 && gouges[2] <= 0.01, "{gouges:?}");
    let warned: f64 = stderr(&o)
        .split("the copy may cut about ")
        .nth(1)
        .and_then(|rest| rest.split_whitespace().next()?.parse().ok())
        .expect("probe mill warns of the rim");
    assert!(gouges[1] <= warned, "the copy gouges {} mm, more than the {warned} mm warned of", gouges[1]);
    // The groove cut by the worn tool, as programmed then corrected: the
    // largest error (gouge or material left) at least halved, within 2 µm.
    let left: Vec<f64> = report
        .lines()
        .filter_map(|l| l.trim().strip_prefix("max left"))
        .filter_map(|rest| rest.split_whitespace().next()?.parse().ok())
        .collect();
    let (before, after) = (gouges[3].max(left[3]), gouges[4].max(left[4]));
    assert!(after <= 0.5 * before && after <= 0.002, "{before} then {after}");
    // Two of each tool's 36 microscope pictures are kept (all with
    // --frames), and the folder stays small.
    assert!(out.join("tool-T7-worn/f18.png").exists() && !out.join("tool-T7-worn/f01.png").exists());
    // It ends with what to open: a 3D page first, then the pictures, and
    // what the folder holds.
    let index = report.split("\nOpen first:\n").nth(1).expect(&report);
    let (page, picture) = (index.find("dome-ball.html").unwrap(), index.find("dome-ball-deviation.png").unwrap());
    assert!(page < picture, "{index}");
    let megabytes: f64 =
        index.lines().last().unwrap().split(" files, ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
    assert!(megabytes < 30.0, "{megabytes} MB");
}

#[test]
fn output_to_a_named_pipe_goes_into_the_pipe_and_leaves_it_one() {
    // Renaming a finished file over the output path (how files are written
    // whole) would put a plain file where a pipe or a device such as
    // /dev/null was.
    use std::os::unix::fs::FileTypeExt;
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let o = kezuri(&["run", &sample("o7023-texture.nc"), "--clock-seed", "3", "-o", fifo.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let through_pipe = reader.join().unwrap();
    let direct = String::from_utf8(kezuri(&["run", &sample("o7023-texture.nc"), "--clock-seed", "3"]).stdout).unwrap();
    assert_eq!(through_pipe, direct);
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
}

#[test]
fn machine_file_sets_the_variable_ranges_and_the_input_signals() {
    let dir = tempfile::tempdir().unwrap();
    let machine = dir.path().join("fanuc.toml");
    std::fs::write(&machine, "[macro]\ncommon = [\"100-199\", \"500-999\"]\n[signals]\ninputs = { 1000 = 1 }\n")
        .unwrap();
    let machine = machine.to_string_lossy().into_owned();
    // The door input is closed: the wait ends; #901200 is no variable here.
    let program = "WH[#1000EQ0]DO1\nEND1\nG01 X1. F100.\n#901200=1.\nM30\n";
    let o = kezuri_stdin(&["check", "-", "--machine", &machine], program);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(
        err.contains("<stdin>:4:1: error: #901200 is not a variable of this machine: its common variables are #100–#199, #500–#999"),
        "{err}"
    );
    // Without the machine file the default ranges have it.
    let o = kezuri_stdin(&["check", "-"], "G01 X1. F100.\n#901200=1.\nM30\n");
    assert!(o.status.success(), "{}", stderr(&o));
    // A bad range is refused with the file's name.
    std::fs::write(&machine, "[macro]\ncommon = [\"1-199\"]\n").unwrap();
    let o = kezuri_stdin(&["check", "-", "--machine", &machine], "M30\n");
    assert!(!o.status.success());
    assert!(stderr(&o).contains("overlaps the local variables"), "{}", stderr(&o));
}

#[test]
fn values_taken_from_the_machine_file_are_said_in_check_and_in_the_written_program() {
    let program = "G90 G54 G00 X0 Y0 Z10.\n#100=#5221\nG01 X#100 F100.\n#101=#3001\nM30\n";
    let o = kezuri_stdin(&["check", "-", "--json"], program);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let notes: Vec<&str> = v["machine_values"].as_array().unwrap().iter().map(|n| n.as_str().unwrap()).collect();
    assert_eq!(notes.len(), 2, "{notes:?}");
    assert!(notes[0].starts_with("#5221, the work offset read at line 2, came from the machine file"), "{notes:?}");
    assert!(notes[1].starts_with("#3001, the clock read at line 4"), "{notes:?}");
    let o = kezuri_stdin(&["run", "-"], program);
    let text = stdout(&o);
    assert!(text.lines().nth(2).unwrap().starts_with("(#5221, the work offset read at line 2"), "{text}");
    assert!(stderr(&o).contains("warning: -: #5221"), "{}", stderr(&o));
    // A program that reads nothing from the machine says nothing.
    let o = kezuri_stdin(&["run", "-"], "G90 G00 X1. Y1. Z1.\nM30\n");
    assert!(!stdout(&o).contains("machine file"), "{}", stdout(&o));
}

#[test]
fn a_program_on_standard_input_is_written_as_its_file_is() {
    // Run as the run hands its path on, from standard input as from a file:
    // the same program, to standard output and to a file.
    let file = sample("nameplate-cam.nc");
    let text = std::fs::read_to_string(&file).unwrap();
    for emit in [None, Some("csv")] {
        let mut args = vec!["run"];
        args.extend(emit.iter().flat_map(|e| ["--emit", e]));
        let from_file = kezuri(&[args.as_slice(), &[file.as_str()]].concat());
        let from_stdin = kezuri_stdin(&[args.as_slice(), &["-"]].concat(), &text);
        assert!(from_file.status.success() && from_stdin.status.success(), "{}", stderr(&from_stdin));
        assert!(!from_file.stdout.is_empty());
        // The program's title is its file's name, `-` for standard input.
        let titled = stdout(&from_stdin).replace("O0001 (-)", "O0001 (NAMEPLATE-CAM.NC)");
        assert_eq!(titled, stdout(&from_file), "{emit:?}");
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.nc").to_string_lossy().into_owned();
    let o = kezuri_stdin(&["run", "-", "-o", &out], &text);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), stdout(&kezuri_stdin(&["run", "-"], &text)));
}

#[test]
fn outputs_that_cannot_hold_a_kept_block_say_so() {
    let tapping = "G90 G00 X0 Y0 Z10.\nS500 M03\nG98 G84 X5. Y5. Z-8. R2. F500.\nG80\nM01\nM30\n";
    // RML-1 has no tapping cycle: refused with the line.
    let o = kezuri_stdin(&["run", "-", "--emit", "rml"], tapping);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("line 3") && stderr(&o).contains("tapping"), "{}", stderr(&o));
    // An M01 that RML-1 cannot write is said, not silently dropped.
    let o = kezuri_stdin(&["run", "-", "--emit", "rml"], "G90 G00 X0 Y0 Z10.\nM01\nG01 X5. F100.\nM30\n");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("not written (the first at line 2: 'M01')"), "{}", stderr(&o));
    // Scaling cannot reach the positions of a G92 kept as written.
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("g92.nc");
    std::fs::write(&file, "G90 G00 X10. Y0 Z5.\nG92 X0\nG01 X5. F100.\nM30\n").unwrap();
    let o = kezuri(&["convert", file.to_str().unwrap(), "--scale-xy", "2"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("line 2 ('G21 G90 G92 X0.')"), "{}", stderr(&o));
}
