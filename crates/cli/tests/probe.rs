//! `kezuri probe level|export|mill` as a user runs them, end to end: an
//! analytic model, the readings a 10 mm ball stylus would give on it (tilted,
//! with noise), levelling, milling with another cutter, and `kezuri sim
//! --compare` against the model.

use std::fmt::Write as _;
use std::path::Path;
use std::process::Output;

use kezuri_cam::dropcut::drop_cutter;
use kezuri_cam::Cutter;
use kezuri_geom::Heightfield;

mod common;
use common::{kezuri, ok, path};

fn json(o: &Output) -> serde_json::Value {
    serde_json::from_str(&ok(o)).expect("one JSON object")
}

const N: usize = 51;
const C: f64 = 25.0;

/// A smooth bump on a flat plate: 6 mm high, 18 mm in radius, concave
/// radius of curvature at its foot about 11 mm (> the stylus's 5 mm).
fn model(x: f64, y: f64) -> f64 {
    let r = ((x - C).powi(2) + (y - C).powi(2)).sqrt();
    if r < 18.0 {
        6.0 * (std::f64::consts::PI * r / 36.0).cos().powi(2)
    } else {
        0.0
    }
}

/// The tip heights a ball stylus reads at the grid points (drop-cutter on
/// a 0.1 mm sampling of the model), plus `tilt` about the centre and
/// uniform noise of ±`noise`, as a capture file.
fn readings(stylus: &str, tilt: [f64; 2], noise: f64) -> String {
    let fine = Heightfield::from_fn(-6.0, -6.0, 0.1, 621, 621, model).unwrap();
    let ball: Cutter = stylus.parse().unwrap();
    let mut seed = 12345u64;
    let mut rand = move || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut text =
        format!("# grid nx={N} ny={N} pitch=1 origin=0,0 pattern=zigzag\n# simulated {stylus} readings\nNo,Z\n");
    for k in 0..N * N {
        let (j, a) = (k / N, k % N);
        let i = if j % 2 == 1 { N - 1 - a } else { a };
        let (x, y) = (i as f64, j as f64);
        let z = drop_cutter(&ball, &fine, x, y).unwrap() + tilt[0] * (x - C) + tilt[1] * (y - C) + noise * rand();
        writeln!(text, "{},{z:.4}", k + 1).unwrap();
    }
    text
}

/// The model as an `x y z` grid for `sim --compare`.
fn target(dir: &Path) -> String {
    let mut text = String::new();
    for j in 0..=200 {
        for i in 0..=200 {
            let (x, y) = (i as f64 * 0.25, j as f64 * 0.25);
            writeln!(text, "{x} {y} {}", model(x, y)).unwrap();
        }
    }
    let p = path(dir, "model.xyz");
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn tilted_noisy_readings_are_levelled_and_milled_within_the_pitch_bound() {
    let dir = tempfile::tempdir().unwrap();
    let data = path(dir.path(), "capture.txt");
    std::fs::write(&data, readings("ball:10", [0.004, -0.003], 0.002)).unwrap();
    let levelled = path(dir.path(), "level.txt");
    let v = json(&kezuri(&[
        "probe",
        "level",
        &data,
        "--reference",
        "border",
        "--method",
        "auto",
        "-o",
        &levelled,
        "--json",
    ]));
    assert_eq!(v["reference_points"], 4 * (N - 1));
    let (before, after) = (v["std_before_mm"].as_f64().unwrap(), v["std_after_mm"].as_f64().unwrap());
    assert!(before > 0.03 && after < 0.0015, "{v}");
    // The capture header survives, with a note of the levelling.
    let text = std::fs::read_to_string(&levelled).unwrap();
    assert!(text.starts_with("# grid nx=51") && text.contains("# levelled:"), "{}", &text[..200]);

    let nc = path(dir.path(), "copy.nc");
    let o = kezuri(&[
        "probe",
        "mill",
        &levelled,
        "--stylus",
        "ball:10",
        "--tool",
        "ball:6",
        "--stepover",
        "0.5",
        "--step",
        "0.5",
        "--floor-z",
        "off",
        "-o",
        &nc,
    ]);
    ok(&o);
    let report = String::from_utf8_lossy(&o.stderr);
    assert!(report.contains("cycle time") && report.contains("bytes"), "{report}");
    let target = target(dir.path());
    let v = json(&kezuri(&["sim", &nc, "--tool", "ball:6", "--res", "0.1", "--compare", &target, "--json"]));
    let (gouge, left) = (v["max_gouge_mm"].as_f64().unwrap(), v["max_left_mm"].as_f64().unwrap());
    // Gouge: the noise (0.002), the plane fitted through noisy points, the
    // path tolerance (0.01) and the samplings; left: the cusp between
    // stylus positions, h(p/√2)·(1 + r/ρ)² for a 10 mm ball at 1 mm pitch
    // over a radius of curvature ρ ≥ 11 mm (0.105 mm), plus the cutter's
    // own cusp at 0.5 mm stepover (0.010 mm).
    assert!(gouge <= 0.015, "gouge {gouge}: {v}");
    assert!(left <= 0.12, "left {left}: {v}");
    assert!(v["mean_abs_dev_mm"].as_f64().unwrap() < 0.03, "{v}");
}

#[test]
fn the_stylus_ball_as_cutter_at_the_pitch_follows_the_readings() {
    let dir = tempfile::tempdir().unwrap();
    let data = path(dir.path(), "capture.txt");
    let text = readings("ball:10", [0.0, 0.0], 0.0);
    std::fs::write(&data, &text).unwrap();
    let nc = path(dir.path(), "same.nc");
    ok(&kezuri(&["probe", "mill", &data, "--stylus", "ball:10", "--tool", "ball:10", "--floor-z", "off", "-o", &nc]));
    let csv = ok(&kezuri(&["run", &nc, "--emit", "csv"]));
    // Measured heights by node.
    let mut z = vec![0.0; N * N];
    for (k, line) in text.lines().skip(3).enumerate() {
        let (j, a) = (k / N, k % N);
        let i = if j % 2 == 1 { N - 1 - a } else { a };
        z[j * N + i] = line.split(',').nth(1).unwrap().parse::<f64>().unwrap();
    }
    let mut on_nodes = 0;
    for line in csv.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        if f[1] != "feed" {
            continue;
        }
        let (x, y, pz): (f64, f64, f64) = (f[2].parse().unwrap(), f[3].parse().unwrap(), f[4].parse().unwrap());
        if (x - x.round()).abs() < 1e-9 && (y - y.round()).abs() < 1e-9 {
            let d = z[y.round() as usize * N + x.round() as usize];
            // The reading rounded to the nearest thousandth.
            assert!((pz - d).abs() <= 0.0005 + 1e-9, "({x}, {y}): path {pz}, reading {d}");
            on_nodes += 1;
        }
    }
    assert!(on_nodes > N * 10, "{on_nodes} path points on grid nodes");
}

#[test]
fn bare_files_flat_margins_incremental_and_split() {
    let dir = tempfile::tempdir().unwrap();
    // The paper's kind of file: a concave pocket in a flat top, `0,0` first.
    let (nx, ny) = (21, 15);
    let mut text = String::from("0,0\n");
    for k in 0..nx * ny {
        let (j, a) = (k / nx, k % nx);
        let i = if j % 2 == 1 { nx - 1 - a } else { a };
        let r = ((i as f64 - 10.0).powi(2) + (j as f64 - 7.0).powi(2)).sqrt();
        writeln!(text, "{},{:.4}", k + 1, 19.16 - if r < 5.0 { (25.0 - r * r).sqrt() * 0.6 } else { 0.0 }).unwrap();
    }
    let data = path(dir.path(), "ume.txt");
    std::fs::write(&data, &text).unwrap();
    let grid = ["--count", "21,15", "--pitch", "1"];
    // Level writes a bare file back, `0,0` and all.
    let out = path(dir.path(), "ume-2.txt");
    let table =
        ok(&kezuri(&[&["probe", "level", &data][..], &grid, &["--reference", "cols:1,21", "-o", &out]].concat()));
    assert!(table.contains("raw") && table.contains("plane") && table.contains("lines cols 1,21"), "{table}");
    let levelled = std::fs::read_to_string(&out).unwrap();
    let first = levelled.strip_prefix("0,0\n1,").and_then(|rest| rest.lines().next()).unwrap_or_default();
    let z: f64 = first.parse().unwrap_or(f64::NAN);
    assert!((z - 19.16).abs() < 1e-9, "levelled file starts {:?}", &levelled[..levelled.len().min(40)]);

    let nc = path(dir.path(), "ume.nc");
    let mill = |extra: &[&str]| {
        kezuri(
            &[&["probe", "mill", &data][..], &grid, &["--stylus", "ball:10", "--tool", "ball:10", "-o", &nc], extra]
                .concat(),
        )
    };
    let o = mill(&[]);
    ok(&o);
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("flat top z = 19.160"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let absolute = std::fs::read_to_string(&nc).unwrap();
    assert!(absolute.starts_with("%\n") && absolute.trim_end().ends_with('%'));
    let rapids = |csv: &str| csv.lines().filter(|l| l.contains(",rapid,")).count();
    let moves = ok(&kezuri(&["run", &nc, "--emit", "csv"]));
    assert!(rapids(&moves) > 10, "flat rows are crossed at rapid");

    // Incremental: the same motions.
    ok(&mill(&["--incremental"]));
    let inc = std::fs::read_to_string(&nc).unwrap();
    assert!(inc.contains("G91") && inc.contains("G90"));
    let moves_inc = ok(&kezuri(&["run", &nc, "--emit", "csv"]));
    let ends = |csv: &str| -> Vec<[f64; 3]> {
        csv.lines()
            .skip(1)
            .map(|l| {
                let f: Vec<f64> = l.split(',').skip(2).take(3).map(|v| v.parse().unwrap()).collect();
                [f[0], f[1], f[2]]
            })
            .collect()
    };
    let same_ends = |a: &[[f64; 3]], b: &[[f64; 3]]| {
        assert_eq!(a.len(), b.len());
        for (p, q) in a.iter().zip(b) {
            assert!((0..3).all(|k| (p[k] - q[k]).abs() < 1e-9), "{p:?} {q:?}");
        }
    };
    same_ends(&ends(&moves), &ends(&moves_inc));
    // `kezuri run --incremental` makes the same motions from the absolute program.
    let (abs, again) = (path(dir.path(), "absolute.nc"), path(dir.path(), "again.nc"));
    std::fs::write(&abs, &absolute).unwrap();
    ok(&kezuri(&["run", &abs, "--incremental", "-o", &again]));
    assert!(std::fs::read_to_string(&again).unwrap().contains("G91"));
    same_ends(&ends(&moves), &ends(&ok(&kezuri(&["run", &again, "--emit", "csv"]))));

    // Split: parts under the limit, each a whole program (a finer step
    // along the rows, for a program worth splitting).
    ok(&mill(&["--step", "0.25"]));
    let limit = std::fs::read_to_string(&nc).unwrap().len() / 3;
    ok(&mill(&["--step", "0.25", "--split-bytes", &limit.to_string()]));
    let mut parts = 0;
    for k in 1.. {
        let p = dir.path().join(format!("ume-{k}.nc"));
        let Ok(t) = std::fs::read_to_string(&p) else { break };
        assert!(t.len() <= limit && t.starts_with('%'), "part {k}: {} bytes", t.len());
        ok(&kezuri(&["check", &p.to_string_lossy()]));
        parts += 1;
    }
    assert!(parts >= 3, "{parts} parts");
}

#[test]
fn export_writes_dxf_stl_png_csv_and_mirrors() {
    let dir = tempfile::tempdir().unwrap();
    let data = path(dir.path(), "half.csv");
    let mut text = String::from("x,y,z\n");
    for j in 0..4 {
        for i in 0..3 {
            writeln!(text, "{i},{j},{}", i * j).unwrap();
        }
    }
    std::fs::write(&data, text).unwrap();
    let (dxf, stl, png, csv) =
        (path(dir.path(), "a.dxf"), path(dir.path(), "a.stl"), path(dir.path(), "a.png"), path(dir.path(), "a.csv"));
    ok(&kezuri(&[
        "probe", "export", &data, "--mirror", "x", "--dxf", &dxf, "--stl", &stl, "--png", &png, "--csv", &csv,
    ]));
    let d = std::fs::read_to_string(&dxf).unwrap();
    assert_eq!(d.matches("POLYLINE").count(), 4);
    assert_eq!(d.matches("VERTEX").count(), 4 * 5);
    assert!(d.contains("AC1009") && d.trim_end().ends_with("EOF"));
    assert_eq!(std::fs::read(&stl).unwrap().len(), 84 + 50 * 2 * 4 * 3);
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    let c = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(c.lines().count(), 1 + 5 * 4);
    assert!(c.contains("\n4,3,0\n") && c.contains("\n2,3,6\n"), "{c}");
}

#[test]
fn bad_input_is_a_clear_error_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let out = path(dir.path(), "out.txt");
    let grid = ["--count", "3,2", "--pitch", "1"];
    let cases = [
        ("1,0\n2,0\n3,0\n4,0\n5,0\n", "5 points, but the 3 × 2 grid has 6", "border"),
        ("1,0\n2,0\n3,abc\n4,0\n5,0\n6,0\n", "line 3, column 3: 'abc' is not a number", "border"),
        (
            "1,0\n2,0\n3,0\n4,NaN\n5,0\n6,0\n",
            "line 4, column 3: 'NaN' must be a coordinate from -1000000 to 1000000 mm, got NaN",
            "border",
        ),
        ("1,0\n2,0\n4,0\n", "line 3: point No 4 where No 3", "border"),
        ("1,0\n2,0\n3,0\n4,0\n5,0\n6,0\n", "row 3 is outside the grid's rows 1..2", "rows:1,3"),
    ];
    for (text, message, reference) in cases {
        let data = path(dir.path(), "bad.txt");
        std::fs::write(&data, text).unwrap();
        let o = kezuri(&[&["probe", "level", &data][..], &grid, &["--reference", reference, "-o", &out]].concat());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(message), "{text:?}: {err}");
        assert!(!Path::new(&out).exists(), "{text:?}: output written");
    }
}
