//! Cutter radius compensation through the command line: the radius from
//! the machine file, `run` keeping G41 D, `--apply-comp` writing the tool
//! centre, CSV and `check` on the centre path, unknown D registers.

use std::path::Path;

mod common;
use common::{kezuri, ok, path};

/// A 20 mm square, clockwise, G41 (outside), start-up and cancel on the
/// diagonal through (-10,-10).
const SQUARE: &str = "O0001
G21 G90 G17 G54
G00 X-10. Y-10.
G41 G01 X0. Y0. D1 F500.
Y20.
X20.
Y0.
X0.
G40 G00 X-10. Y-10.
M30
";

/// The square and a machine file with D1 = 2 mm in `dir`.
fn files(dir: &Path, program: &str) -> (String, String) {
    std::fs::write(dir.join("sq.nc"), program).unwrap();
    std::fs::write(dir.join("m.toml"), "[tools]\nradii = { 1 = 2.0 }\n").unwrap();
    (path(dir, "sq.nc"), path(dir, "m.toml"))
}

/// `(x, y)` of each CSV row.
fn csv_points(text: &str) -> Vec<(f64, f64)> {
    text.lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[2].parse().unwrap(), f[3].parse().unwrap())
        })
        .collect()
}

/// By hand, r = 2 (see crates/nc/tests/comp_interp.rs): start-up and cancel
/// at the inside intersections with the diagonal's offset, 2√2 - 2; the
/// outside corners at the offset lines' intersections.
fn centre() -> Vec<(f64, f64)> {
    let k = 2.0 * std::f64::consts::SQRT_2 - 2.0;
    vec![(-10.0, -10.0), (-2.0, k), (-2.0, 22.0), (22.0, 22.0), (22.0, -2.0), (k, -2.0), (-10.0, -10.0)]
}

fn assert_points(got: &[(f64, f64)], want: &[(f64, f64)], tol: f64) {
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, w) in got.iter().zip(want) {
        assert!((g.0 - w.0).abs() <= tol && (g.1 - w.1).abs() <= tol, "{g:?} want {w:?}");
    }
}

#[test]
fn csv_is_the_centre_path_and_fanuc_output_keeps_g41_d() {
    let dir = tempfile::tempdir().unwrap();
    let (nc, machine) = files(dir.path(), SQUARE);
    let csv = ok(&kezuri(&["run", &nc, "--machine", &machine, "--emit", "csv"]));
    assert_points(&csv_points(&csv), &centre(), 1e-12);
    let fanuc = ok(&kezuri(&["run", &nc, "--machine", &machine]));
    assert!(
        fanuc.contains("\nG41 D1\nG01 X0. Y0. F500.\nY20.\n") && fanuc.contains("\nG40\nG00 X-10. Y-10.\n"),
        "{fanuc}"
    );
    // The expanded program, run again, compensates the same way.
    std::fs::write(dir.path().join("expanded.nc"), &fanuc).unwrap();
    let again = ok(&kezuri(&["run", &path(dir.path(), "expanded.nc"), "--machine", &machine, "--emit", "csv"]));
    assert_points(&csv_points(&again), &centre(), 1e-12);
    // check's bounds are the centre path's; the program never names Z, so
    // no Z is the program's (where the machine stands: null).
    let check = ok(&kezuri(&["check", &nc, "--machine", &machine, "--json"]));
    let v: serde_json::Value = serde_json::from_str(&check).unwrap();
    assert_eq!(v["bounds"]["max"], serde_json::json!([22.0, 22.0, null]));
    assert_eq!(v["bounds"]["min"], serde_json::json!([-10.0, -10.0, null]));
}

#[test]
fn apply_comp_writes_the_centre_without_g41() {
    let dir = tempfile::tempdir().unwrap();
    let (nc, machine) = files(dir.path(), SQUARE);
    for emit in ["fanuc", "linuxcnc", "grbl"] {
        let text = ok(&kezuri(&["run", &nc, "--machine", &machine, "--apply-comp", "--emit", emit]));
        assert!(!text.contains("G41") && !text.contains("G42"), "{emit}: {text}");
        let out = dir.path().join(format!("centre-{emit}.nc"));
        std::fs::write(&out, &text).unwrap();
        let mut args = vec!["run", out.to_str().unwrap(), "--emit", "csv"];
        if emit != "fanuc" {
            args.extend(["--no-decimal", "units"]);
        }
        // Read back with no radii: no compensation left, the centre path
        // at the written precision.
        assert_points(&csv_points(&ok(&kezuri(&args))), &centre(), 0.0005);
    }
    // RML-1 too (it needs Z named).
    let (nc, machine) = files(dir.path(), &SQUARE.replace("G00 X-10. Y-10.\nG41", "G00 X-10. Y-10. Z0.\nG41"));
    let rml = ok(&kezuri(&["run", &nc, "--machine", &machine, "--apply-comp", "--emit", "rml"]));
    assert!(rml.contains("-200,2200"), "{rml}");
}

#[test]
fn outputs_without_compensation_refuse_it_unless_applied() {
    let dir = tempfile::tempdir().unwrap();
    let (nc, machine) = files(dir.path(), SQUARE);
    for emit in ["grbl", "rml"] {
        let o = kezuri(&["run", &nc, "--machine", &machine, "--emit", emit]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains("--apply-comp"), "{emit}: {err}");
    }
}

#[test]
fn unknown_d_warns_in_check_run_and_sim_and_stops_apply_comp() {
    let dir = tempfile::tempdir().unwrap();
    let (nc, _) = files(dir.path(), SQUARE);
    let warning = "sq.nc:4:17: warning: D1 has no radius in the tool table";
    let o = kezuri(&["check", &nc]);
    assert!(o.status.success() && String::from_utf8_lossy(&o.stderr).contains(warning));
    // The programmed path, radius 0.
    let csv = ok(&kezuri(&["run", &nc, "--emit", "csv"]));
    let programmed = [(-10.0, -10.0), (0.0, 0.0), (0.0, 20.0), (20.0, 20.0), (20.0, 0.0), (0.0, 0.0), (-10.0, -10.0)];
    assert_points(&csv_points(&csv), &programmed, 0.0);
    let error = "sq.nc:4:17: error: D1 has no radius in the tool table";
    let o = kezuri(&["run", &nc, "--apply-comp"]);
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains(error));
    // sim refuses no more than check and run: it warns and cuts the programmed path.
    let o = kezuri(&["sim", &nc, "--tool", "flat:4", "--res", "0.5", "--stock", "-15,-15,30,30,0"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && err.contains(warning), "{err}");
}

#[test]
fn interference_is_located() {
    let dir = tempfile::tempdir().unwrap();
    let groove = "G00 X-10. Y0.\nG41 G01 X0. Y0. D1 F500.\nX10.\nY-5.\nX11.\nY0.\nX20.\nG40 G00 X30.\nM30\n";
    let (nc, machine) = files(dir.path(), groove);
    let o = kezuri(&["check", &nc, "--machine", &machine]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("sq.nc:5:1: error: cutter compensation: interference"), "{err}");
}

#[test]
fn machine_file_startup_type_b() {
    let dir = tempfile::tempdir().unwrap();
    // An outside start-up: type A ends on the next move's perpendicular
    // (0, 22), type B on the offset lines' intersection (-2, 22).
    let text = "G00 X0. Y-10.\nG41 G01 Y20. D1 F500.\nX20.\nG40 G00 X30.\nM30\n";
    let (nc, machine) = files(dir.path(), text);
    let a = csv_points(&ok(&kezuri(&["run", &nc, "--machine", &machine, "--emit", "csv"])));
    assert_eq!(a[1], (0.0, 22.0));
    std::fs::write(dir.path().join("b.toml"), "[tools]\nradii = { 1 = 2.0 }\n[comp]\nstartup = \"B\"\n").unwrap();
    let b = csv_points(&ok(&kezuri(&["run", &nc, "--machine", &path(dir.path(), "b.toml"), "--emit", "csv"])));
    assert_eq!(b[1], (-2.0, 22.0));
}

#[test]
fn ngc_files_use_linuxcnc_rules() {
    let dir = tempfile::tempdir().unwrap();
    // LinuxCNC: the convex corner at (0,20) gets an arc around it; Fanuc
    // rules would make the corner at (-2,22) instead. The file's extension
    // alone chooses the rules.
    let text = "G00 X0. Y-10.\nG41 G01 Y0. D1 F500.\nY20.\nX20.\nG40 G00 X30.\nM2\n";
    std::fs::write(dir.path().join("p.ngc"), text).unwrap();
    std::fs::write(dir.path().join("m.toml"), "[tools]\nradii = { 1 = 2.0 }\n").unwrap();
    let csv =
        ok(&kezuri(&["run", &path(dir.path(), "p.ngc"), "--machine", &path(dir.path(), "m.toml"), "--emit", "csv"]));
    let kinds: Vec<&str> = csv.lines().skip(1).map(|l| l.split(',').nth(1).unwrap()).collect();
    assert_eq!(kinds, ["rapid", "feed", "feed", "cw", "feed", "rapid"], "{csv}");
    let lcnc = ok(&kezuri(&[
        "run",
        &path(dir.path(), "p.ngc"),
        "--machine",
        &path(dir.path(), "m.toml"),
        "--emit",
        "linuxcnc",
    ]));
    assert!(lcnc.contains("\nG41 D1\n"), "{lcnc}");
}
