//! `kezuri wear apply` on a groove, as in the paper's experiment: a trough
//! finished by a 1 mm ball end mill whose measured profile has 10 µm
//! runout, a band worn 12 µm deep at 45° and a tip worn back 2 µm; the
//! simulated cut of the uncorrected and the corrected program against the
//! target.

use std::fmt::Write;
use std::path::Path;

use kezuri_geom::{write_binary_stl, Triangle, Vec3};

mod common;
use common::{kezuri, ok, path};

const R: f64 = 0.5;
/// The trough's radius; its axis along Y at z = RT (its bottom at z 0).
const RT: f64 = 1.5;

fn wear(z: f64) -> f64 {
    0.012 * (-((z - R * (1.0 - std::f64::consts::FRAC_1_SQRT_2)) / 0.1).powi(2)).exp()
}

/// The measured profile CSV.
fn profile() -> String {
    let mut s = String::from("z_mm,radius_mm\n");
    for k in 0..1100 {
        let z = 0.002 + 0.00071 * k as f64;
        let r = if z < R { (z * (2.0 * R - z)).sqrt() } else { R } + 0.010 - wear(z);
        let _ = writeln!(s, "{z:.6},{r:.6}");
    }
    s
}

/// The trough from −60° to 60°, flat beyond, as an STL.
fn trough() -> Vec<u8> {
    let quad = |a: Vec3, b: Vec3, c: Vec3, d: Vec3| [Triangle::new(a, b, c), Triangle::new(a, c, d)];
    let n = 480;
    let at = |k: usize, y: f64| {
        let t = (-60.0 + 120.0 * k as f64 / n as f64).to_radians();
        Vec3::new(RT * t.sin(), y, RT - RT * t.cos())
    };
    let (y0, y1) = (-3.0, 4.0);
    let mut t: Vec<Triangle> = (0..n).flat_map(|k| quad(at(k, y0), at(k + 1, y0), at(k + 1, y1), at(k, y1))).collect();
    let top = RT * 0.5;
    let (xl, xr) = (at(0, 0.0).x, at(n, 0.0).x);
    t.extend(quad(Vec3::new(-6.0, y0, top), Vec3::new(xl, y0, top), Vec3::new(xl, y1, top), Vec3::new(-6.0, y1, top)));
    t.extend(quad(Vec3::new(xr, y0, top), Vec3::new(6.0, y0, top), Vec3::new(6.0, y1, top), Vec3::new(xr, y1, top)));
    write_binary_stl(&t)
}

/// Passes along Y over the trough, contact angles −55° … 55°, zigzag,
/// 0.02 mm apart across (cusps under 0.1 µm).
fn program() -> String {
    let mut s = String::from("%\nO0100 (GROOVE)\nG90 G21 G17\nG0 Z3.\n");
    let passes = 120;
    for k in 0..=passes {
        let x_contact = -1.23 + 2.46 * k as f64 / passes as f64;
        let phi = (x_contact / RT).asin();
        let (x, z) = ((RT - R) * phi.sin(), RT - (RT - R) * phi.cos() - R);
        let (ya, yb) = if k % 2 == 0 { (-0.8, 1.4) } else { (1.4, -0.8) };
        if k == 0 {
            let _ = writeln!(s, "G0 X{x:.5} Y{ya:.5}\nG1 Z{z:.5} F300");
        } else {
            let _ = writeln!(s, "G1 X{x:.5} Z{z:.5}");
        }
        let _ = writeln!(s, "Y{yb:.5}");
    }
    s + "G0 Z3.\nM30\n%\n"
}

fn json(args: &[&str]) -> serde_json::Value {
    serde_json::from_str(&ok(&kezuri(args))).expect("one JSON object")
}

/// The largest error of the simulated cut against the trough, mm.
fn sim_error(dir: &Path, program: &str) -> f64 {
    let v = json(&[
        "sim",
        program,
        "--profile",
        &path(dir, "worn.csv"),
        "--res",
        "0.002",
        "--stock",
        "-1.2,0.2,1.2,0.5,0.8",
        "--compare",
        &path(dir, "trough.stl"),
        "--json",
    ]);
    v["max_gouge_mm"].as_f64().unwrap().max(v["max_left_mm"].as_f64().unwrap())
}

#[test]
fn the_groove_error_is_halved_and_within_two_micrometres() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("worn.csv"), profile()).unwrap();
    std::fs::write(d.join("trough.stl"), trough()).unwrap();
    std::fs::write(d.join("groove.nc"), program()).unwrap();
    let out = kezuri(&[
        "wear",
        "apply",
        &path(d, "groove.nc"),
        "--profile",
        &path(d, "worn.csv"),
        "--nominal",
        "ball:1",
        "--surface",
        &path(d, "trough.stl"),
        "-o",
        &path(d, "corrected.nc"),
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&ok(&out)).unwrap();
    // The plunge, 120 steps across and 121 passes; the residual before
    // rounding to 4 decimals.
    assert_eq!(v["points"], 242, "{v}");
    assert!(v["max_residual_mm"].as_f64().unwrap() < 1e-9, "{v}");
    let expected = v["max_error_before_mm"].as_f64().unwrap();
    assert!(expected > 0.003, "{v}");
    let before = sim_error(d, &path(d, "groove.nc"));
    let after = sim_error(d, &path(d, "corrected.nc"));
    eprintln!("groove: largest error {:.2} µm as programmed, {:.2} µm corrected", before * 1e3, after * 1e3);
    // The simulated cut shows the worn tool's error (the largest computed is
    // at the outermost passes, beyond the stock's edge).
    assert!(before > 0.002 && before <= expected, "the worn tool's error as programmed: {before}, computed {expected}");
    assert!(after <= 0.5 * before && after <= 0.002, "corrected: {after} (before {before})");
}

#[test]
fn bad_input_is_refused_or_said() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("worn.csv"), profile()).unwrap();
    std::fs::write(d.join("trough.stl"), trough()).unwrap();
    // The program far above the part: nothing to correct.
    std::fs::write(d.join("air.nc"), "G90 G0 X0 Y0 Z10.\nG1 X1. F100\nM30\n").unwrap();
    let args = |prog: &str, nominal: &str, profile: &str| {
        kezuri(&[
            "wear",
            "apply",
            &path(d, prog),
            "--profile",
            &path(d, profile),
            "--nominal",
            nominal,
            "--surface",
            &path(d, "trough.stl"),
            "-o",
            &path(d, "out.nc"),
        ])
    };
    let o = args("air.nc", "ball:1", "worn.csv");
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && e.contains("no cutting point within 0.05 mm"), "{e}");
    assert!(!d.join("out.nc").exists());
    // A flat end mill has no cutting point.
    let o = args("air.nc", "flat:1", "worn.csv");
    assert!(String::from_utf8_lossy(&o.stderr).contains("ball and bull-nose"));
    // A profile shorter than the part of the tool that cuts the wall.
    std::fs::write(d.join("short.csv"), "z_mm,radius_mm\n0.002,0.04\n0.05,0.2\n").unwrap();
    std::fs::write(d.join("groove.nc"), program()).unwrap();
    let o = args("groove.nc", "ball:1", "short.csv");
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && e.contains("line ") && e.contains("measure more of the tool"), "{e}");
    // A point in the air among cutting points: said, with its line.
    std::fs::write(d.join("mixed.nc"), program().replacen("G1 Z", "G1 Z0.9 F300\nG1 Z", 1)).unwrap();
    let o = args("mixed.nc", "ball:1", "worn.csv");
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success() && e.contains("1 cutting point(s) farther than 0.05 mm from the surface (first at line 6)"),
        "{e}"
    );
}

#[test]
fn a_tilted_tool_on_the_mill_turn_is_corrected_along_the_normal() {
    // B −45 tilts the tool axis to (−sin 45°, 0, cos 45°): the ball touches
    // the level floor z 0 at 45° on its edge, in the worn band.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("worn.csv"), profile()).unwrap();
    std::fs::write(d.join("turn.toml"), "[kinematics]\ntool = [\"X\", \"Z\", \"B\"]\nwork = [\"Y\", \"C\"]\n").unwrap();
    let floor = {
        let q = |x: f64, y: f64| Vec3::new(x, y, 0.0);
        write_binary_stl(&[
            Triangle::new(q(-5.0, -5.0), q(5.0, -5.0), q(5.0, 5.0)),
            Triangle::new(q(-5.0, -5.0), q(5.0, 5.0), q(-5.0, 5.0)),
        ])
    };
    std::fs::write(d.join("floor.stl"), floor).unwrap();
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let (x, z) = (R * s, R - R * s);
    std::fs::write(d.join("tilt.nc"), format!("G90 G0 B-45. X{x:.6} Y-1. Z1.\nG1 Z{z:.6} F100\nY1.\nM30\n")).unwrap();
    let v = json(&[
        "wear",
        "apply",
        &path(d, "tilt.nc"),
        "--profile",
        &path(d, "worn.csv"),
        "--nominal",
        "ball:1",
        "--surface",
        &path(d, "floor.stl"),
        "--machine",
        &path(d, "turn.toml"),
        "--digits",
        "6",
        "-o",
        &path(d, "out.nc"),
        "--json",
    ]);
    assert_eq!(v["points"], 2, "{v}");
    // Along the normal by the radial error seen at 45°: runout less wear.
    let radial = 0.010 - wear(R * (1.0 - s));
    let text = std::fs::read_to_string(d.join("out.nc")).unwrap();
    let zs: Vec<f64> = text
        .lines()
        .filter(|l| l.contains("Y1.") || l.contains("G1") || l.contains("G01"))
        .filter_map(|l| l.split_whitespace().find_map(|w| w.strip_prefix('Z')).and_then(|n| n.parse().ok()))
        .collect();
    assert!(!zs.is_empty(), "{text}");
    let moved = zs[zs.len() - 1] - z;
    assert!((moved - radial * s).abs() < 3e-4 + 0.05 * radial, "moved {moved}, expected {} ({text})", radial * s);
    // The pass along Y moves in Z alone (the plunge before it along the
    // tool axis: X too).
    let pass = text.lines().find(|l| l.contains("Y1.")).unwrap();
    assert!(pass.contains(&format!("X{x:.6}")), "{text}");
}

#[test]
fn an_arc_over_a_cylinder_keeps_one_circle_through_its_corrected_ends() {
    // A cylinder of radius 5 along Y, its top at z 0; the ball's tip runs on
    // a circle of radius 5.5 about (x 0, z −5.5) from −20° to 20° in G18.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("worn.csv"), profile()).unwrap();
    let quad = |a: Vec3, b: Vec3, c: Vec3, e: Vec3| [Triangle::new(a, b, c), Triangle::new(a, c, e)];
    let n = 720;
    let at = |k: usize, y: f64| {
        let t = (-60.0 + 120.0 * k as f64 / n as f64).to_radians();
        Vec3::new(5.0 * t.sin(), y, 5.0 * t.cos() - 5.0)
    };
    let cyl: Vec<Triangle> =
        (0..n).flat_map(|k| quad(at(k, -3.0), at(k + 1, -3.0), at(k + 1, 3.0), at(k, 3.0))).collect();
    std::fs::write(d.join("cyl.stl"), write_binary_stl(&cyl)).unwrap();
    let tip = |deg: f64| {
        let t = f64::to_radians(deg);
        (5.5 * t.sin(), 5.5 * t.cos() - 5.5)
    };
    let ((x0, z0), (x1, z1)) = (tip(-20.0), tip(20.0));
    std::fs::write(
        d.join("arc.nc"),
        format!(
            "G90 G18 G0 X{x0:.6} Y0 Z1.\nG1 Z{z0:.6} F100\nG2 X{x1:.6} Z{z1:.6} I{:.6} K{:.6}\nG0 Z2.\nM30\n",
            -x0,
            -5.5 - z0
        ),
    )
    .unwrap();
    let v = json(&[
        "wear",
        "apply",
        &path(d, "arc.nc"),
        "--profile",
        &path(d, "worn.csv"),
        "--nominal",
        "ball:1",
        "--surface",
        &path(d, "cyl.stl"),
        "--digits",
        "6",
        "-o",
        &path(d, "out.nc"),
        "--json",
    ]);
    assert_eq!(v["points"], 2, "{v}");
    // Run the corrected program: the arc's radius at its start and end agree
    // (the control would refuse it otherwise) and it still turns 40°.
    let csv = ok(&kezuri(&["run", &path(d, "out.nc"), "--emit", "csv"]));
    let text = std::fs::read_to_string(d.join("out.nc")).unwrap();
    let arc = text.lines().find(|l| l.starts_with("G02") || l.contains(" G02")).expect(&text).to_string();
    let word = |c: char| -> f64 {
        arc.split_whitespace()
            .find_map(|w| w.strip_prefix(c))
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("{arc}"))
    };
    let plunge = text.lines().find(|l| l.contains("G01")).expect(&text);
    let start_z: f64 = plunge.split_whitespace().find_map(|w| w.strip_prefix('Z')).unwrap().parse().unwrap();
    let start_x = x0
        + plunge.split_whitespace().find_map(|w| w.strip_prefix('X')).map_or(0.0, |n| n.parse::<f64>().unwrap() - x0);
    let (ci, ck) = (start_x + word('I'), start_z + word('K'));
    let r_start = (start_x - ci).hypot(start_z - ck);
    let r_end = (word('X') - ci).hypot(word('Z') - ck);
    assert!((r_start - r_end).abs() < 2e-6, "{r_start} vs {r_end}\n{text}\n{csv}");
    assert!((r_start - 5.5).abs() > 1e-4 && (r_start - 5.5).abs() < 0.02, "{r_start}\n{text}");
}
