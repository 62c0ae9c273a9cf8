//! `--dialect` on every command that reads a program, and the one rule
//! that chooses it otherwise: `check` and `convert` agree on every file.

mod common;

use common::{kezuri, ok, path};

const FILES: &[(&str, &str)] = &[
    ("plain.ngc", "G21 G90\nG1 X50 Y20 F300\nM2\n"),
    ("plain.gcode", "G21 G90\nG1 X50 Y20 F300\nM2\n"),
    ("plain.nc", "G21 G90\nG1 X50 Y20 F300\nM2\n"),
    ("plain.tap", "G21 G90\nG1 X50 Y20 F300\nM2\n"),
    ("sub.nc", "G21\no100 sub\nG1 X50 F100\no100 endsub\no100 call\nM2\n"),
    ("named.tap", "#<x> = 50\nG21\nG1 X#<x> F100\nM2\n"),
    ("fanuc.nc", "%\nO1234\nG21 G90\nG1 X50 Y20 F300\nM30\n%\n"),
    ("fanuc.tap", "G21\n#1=0\nN10 #1=#1+1\nIF [#1 LT 3] GOTO 10\nG1 X50 F300\nM30\n"),
    ("haas.nc", "G21\nG154 P1\nG1 X50 F300\nM30\n"),
    ("grbl.nc", "$H\nG21\nG1 X50 F300\n"),
    ("mixed.nc", "O1234\nG21\no100 sub\no100 endsub\nM30\n"),
    ("fanuc.ngc", "O1234\nG21\nG1 X50 F300\nM30\n"),
];

/// (dialect, reason) from `check --json` (whether or not the program then
/// runs without errors), or the refusal.
fn check(file: &str) -> Result<(String, String), String> {
    let o = kezuri(&["check", file, "--json"]);
    if o.stdout.is_empty() {
        return Err(String::from_utf8_lossy(&o.stderr).into_owned());
    }
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    Ok((v["dialect"].as_str().unwrap().to_string(), v["dialect_reason"].as_str().unwrap().to_string()))
}

/// (dialect, reason) from `convert`'s summary line on standard error.
fn convert(file: &str) -> Result<(String, String), String> {
    let o = kezuri(&["convert", file, "--to", "fanuc"]);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    let Some(line) = err.lines().find_map(|l| l.split_once(": dialect ").map(|(_, d)| d.to_string())) else {
        return Err(err);
    };
    let (d, why) = line.split_once(": ").unwrap();
    Ok((d.to_string(), why.to_string()))
}

#[test]
fn check_and_convert_agree_on_every_file() {
    let dir = tempfile::tempdir().unwrap();
    let want: &[Result<(&str, &str), &str>] = &[
        Ok(("linuxcnc", "the extension .ngc")),
        Ok(("grbl", "the extension .gcode")),
        Ok(("fanuc", "the default (no extension or marker of another dialect)")),
        Ok(("fanuc", "the default (no extension or marker of another dialect)")),
        Ok(("linuxcnc", "o100 sub on line 2")),
        Ok(("linuxcnc", "#<…> on line 1")),
        Ok(("fanuc", "O1234 on line 2")),
        Ok(("fanuc", "GOTO on line 4")),
        Ok(("haas", "G154 on line 2")),
        Ok(("grbl", "$H on line 1")),
        Err("O1234 on line 1 is fanuc's and o100 sub on line 3 is linuxcnc's"),
        Err("the extension .ngc says linuxcnc but O1234 on line 1 is fanuc's"),
    ];
    for ((name, text), want) in FILES.iter().zip(want) {
        let file = path(dir.path(), name);
        std::fs::write(&file, text).unwrap();
        let (a, b) = (check(&file), convert(&file));
        match want {
            Ok((d, why)) => {
                assert_eq!(a, Ok((d.to_string(), why.to_string())), "{name}: check");
                assert_eq!(b, Ok((d.to_string(), why.to_string())), "{name}: convert");
            }
            Err(why) => {
                for (what, e) in [("check", a), ("convert", b)] {
                    let e = e.expect_err(name);
                    assert!(e.contains(why) && e.contains("give --dialect"), "{name}: {what}: {e}");
                }
            }
        }
        // `--dialect` settles every file, the mixed ones too.
        let o = kezuri(&["check", &file, "--json", "--dialect", "linuxcnc"]);
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(
            (v["dialect"].as_str(), v["dialect_reason"].as_str()),
            (Some("linuxcnc"), Some("given with --dialect"))
        );
    }
}

#[test]
fn the_dialect_decides_what_x50_is() {
    let dir = tempfile::tempdir().unwrap();
    let file = path(dir.path(), "part.nc");
    std::fs::write(&file, "G21 G90\nG1 X50 F300\nM2\n").unwrap();
    let end_x = |args: &[&str]| -> f64 {
        let csv = ok(&kezuri(&[&["run", file.as_str(), "--emit", "csv"][..], args].concat()));
        csv.lines().nth(1).unwrap().split(',').nth(2).unwrap().parse().unwrap()
    };
    assert_eq!(end_x(&[]), 0.05);
    assert_eq!(end_x(&["--dialect", "fanuc"]), 0.05);
    assert_eq!(end_x(&["--dialect", "haas"]), 0.05);
    assert_eq!(end_x(&["--dialect", "linuxcnc"]), 50.0);
    assert_eq!(end_x(&["--dialect", "grbl"]), 50.0);
    // --no-decimal is the finer switch.
    assert_eq!(end_x(&["--dialect", "linuxcnc", "--no-decimal", "increments"]), 0.05);
    assert_eq!(end_x(&["--dialect", "fanuc", "--no-decimal", "units"]), 50.0);
    // The writer's summary line says which and why.
    let o = kezuri(&["run", &file, "--emit", "csv", "--dialect", "grbl"]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("part.nc: dialect grbl: given with --dialect"));
    let o = kezuri(&["run", &file, "--emit", "csv", "--dialect", "okuma"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn convert_from_is_the_old_name_of_dialect() {
    let dir = tempfile::tempdir().unwrap();
    let file = path(dir.path(), "part.nc");
    std::fs::write(&file, "G21 G90\nG1 X50 F300\nM2\n").unwrap();
    for flag in ["--from", "--dialect"] {
        let out = ok(&kezuri(&["convert", &file, flag, "linuxcnc", "--to", "fanuc"]));
        assert!(out.contains("G01 X50. F300."), "{flag}: {out}");
    }
    let help = ok(&kezuri(&["convert", "--help"]));
    assert!(help.contains("--dialect") && !help.contains("--from <"), "{help}");
    // The text report names the dialect too.
    let report = ok(&kezuri(&["check", &file]));
    assert!(report.contains("  dialect fanuc: the default (no extension or marker of another dialect)\n"), "{report}");
}

#[test]
fn var_file_gives_the_starting_parameters() {
    let dir = tempfile::tempdir().unwrap();
    // rs274 -v: G55 in force (#5220 = 2) at X100 (mm here); G28 at X10.
    let var = path(dir.path(), "m.var");
    std::fs::write(&var, "5161\t10.000000\n5220 2\n5241 100\nnot a parameter line\n").unwrap();
    let file = path(dir.path(), "p.ngc");
    std::fs::write(&file, "G1 X1 F100\nG28\nM2\n").unwrap();
    let csv = ok(&kezuri(&["run", &file, "--var", &var, "--emit", "csv"]));
    let xs: Vec<&str> = csv.lines().skip(1).map(|l| l.split(',').nth(2).unwrap()).collect();
    assert_eq!(xs.first(), Some(&"101"), "{csv}");
    assert_eq!(xs.last(), Some(&"10"), "{csv}");
    // Out of order: refused with its line.
    std::fs::write(&var, "5241 100\n5220 2\n").unwrap();
    let o = kezuri(&["run", &file, "--var", &var, "--emit", "csv"]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("m.var:2: parameter #5220 after #5241"));
    // A Fanuc reading has no .var.
    let nc = path(dir.path(), "p.nc");
    std::fs::write(&nc, "G1 X1. F100.\nM30\n").unwrap();
    let o = kezuri(&["run", &nc, "--var", &var, "--emit", "csv"]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("--var is LinuxCNC's parameter file"));
}

#[test]
fn linuxcnc_motion_words_in_written_programs() {
    let dir = tempfile::tempdir().unwrap();
    // G64 P Q stays in the written program, its lengths with the units they
    // are in (rs274: SET_MOTION_CONTROL_MODE(CANON_CONTINUOUS, 0.05)).
    let file = path(dir.path(), "blend.ngc");
    std::fs::write(&file, "G21 G64 P0.05 Q0.01\nG1 X10 F100\nG61\nG1 X20\nG64\nG1 X30\nM2\n").unwrap();
    let out = ok(&kezuri(&["run", &file, "--post", "linuxcnc"]));
    assert!(out.contains("\nG21 G64 P0.05 Q0.01\nG1 X10. F100.\nG61\nX20.\nG64\nX30.\n"), "{out}");
    let file = path(dir.path(), "inch.ngc");
    std::fs::write(&file, "G20 G64 P0.002\nG1 X1 F10\nM2\n").unwrap();
    let out = ok(&kezuri(&["run", &file, "--post", "linuxcnc"]));
    assert!(out.contains("\nG20 G64 P0.002\nG21\nG1 X25.4 F254.\n"), "{out}");
    // Polar words are written as the X Y they name; sim and CSV have the
    // moves (rs274: STRAIGHT_FEED(0, 10) then (-10, 0)).
    let file = path(dir.path(), "polar.ngc");
    std::fs::write(&file, "G21 G1 F100 @10 ^90\nG91 ^90\nM2\n").unwrap();
    let out = ok(&kezuri(&["run", &file, "--post", "linuxcnc"]));
    assert!(out.contains("\nG1 X0. Y10. F100.\nX-10. Y0.\n"), "{out}");
    let csv = ok(&kezuri(&["run", &file, "--emit", "csv"]));
    let xy: Vec<String> =
        csv.lines().skip(1).map(|l| l.split(',').skip(2).take(2).collect::<Vec<_>>().join(" ")).collect();
    assert_eq!(xy.len(), 2, "{csv}");
    assert!(xy[1].starts_with("-10 "), "{csv}");
}

/// A program written to a `.ngc` or `.gcode` file without a post named is
/// written for the control its name says, so that every command reads it
/// back (it was Fanuc's, which the dialect rule then refused as mixed).
#[test]
fn a_written_program_is_read_back_by_its_name() {
    let dir = tempfile::tempdir().unwrap();
    let sample = concat!(env!("CARGO_MANIFEST_DIR"), "/../../samples/nameplate-cam.nc");
    for (name, dialect) in [("a.ngc", "linuxcnc"), ("a.gcode", "grbl"), ("a.nc", "fanuc")] {
        let out = path(dir.path(), name);
        ok(&kezuri(&["run", sample, "-o", &out]));
        let o = kezuri(&["check", &out, "--json"]);
        let v: serde_json::Value = serde_json::from_str(&ok(&o)).unwrap();
        assert_eq!(v["dialect"], dialect, "{name}");
    }
    // Every writer: the measuring program too.
    let out = path(dir.path(), "probe.ngc");
    let plan =
        ["probe", "plan", "--origin", "0,0", "--count", "3,3", "--pitch", "1", "--safe-z", "5", "--plunge", "10"];
    ok(&kezuri(&[&plan[..], &["--style", "expanded", "-o", &out]].concat()));
    let v: serde_json::Value = serde_json::from_str(&ok(&kezuri(&["check", &out, "--json"]))).unwrap();
    assert_eq!(v["dialect"], "linuxcnc");
    // A post named is what is written, whatever the name says.
    let out = path(dir.path(), "fanuc.ngc");
    ok(&kezuri(&["run", sample, "--to", "fanuc", "-o", &out]));
    assert!(std::fs::read_to_string(&out).unwrap().contains("O0001"));
}
