//! `kezuri probe mill` with the stylus's own ball as cutter cuts what the
//! stylus touched: a tilted plane and a sphere digitized by `probe
//! simulate`, copied at 0.25 mm stepover and compared with `sim --compare`;
//! the program through the readings, rounded to the nearest.

use std::fmt::Write as _;
use std::path::Path;

mod common;
use common::{feed_points, kezuri, ok, path};

/// `f` as an `x y z` grid every `step` over `[a, b]²`.
fn write_xyz(dir: &Path, name: &str, a: f64, b: f64, step: f64, f: impl Fn(f64, f64) -> f64) -> String {
    let n = ((b - a) / step).round() as usize;
    let mut text = String::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (a + i as f64 * step, a + j as f64 * step);
            writeln!(text, "{x} {y} {}", f(x, y)).unwrap();
        }
    }
    let p = path(dir, name);
    std::fs::write(&p, text).unwrap();
    p
}

fn plane(x: f64, y: f64) -> f64 {
    10.0 + 0.1 * x + 0.05 * y
}

fn sphere(x: f64, y: f64) -> f64 {
    (1600.0 - x * x - y * y).sqrt() - 30.0
}

/// The model digitized with a 10 mm ball on 11 × 11 points at 1 mm pitch
/// about (0, 0): the capture file.
fn digitize(dir: &Path, name: &str, f: fn(f64, f64) -> f64) -> String {
    let model = write_xyz(dir, &format!("{name}.xyz"), -10.0, 10.0, 0.0625, f);
    let data = path(dir, &format!("{name}.txt"));
    let grid = ["--count", "11,11", "--pitch", "1", "--origin", "-5,-5", "--stylus", "ball:10"];
    ok(&kezuri(&[&["probe", "simulate", &model][..], &grid, &["-o", &data]].concat()));
    data
}

/// Largest material left and gouge, mm, of the copy of `data` (ball:10 at
/// 0.25 mm) against `f` inside the readings' box, where the ball touched.
fn copy(dir: &Path, data: &str, f: fn(f64, f64) -> f64, between: &str) -> (f64, f64) {
    let nc = path(dir, &format!("copy-{between}.nc"));
    #[rustfmt::skip]
    let args = [
        "probe", "mill", data, "--stylus", "ball:10", "--tool", "ball:10", "--stepover", "0.25",
        "--step", "0.25", "--gouge-tol", "0.0005", "--digits", "4", "--floor-z", "off",
        "--between", between, "-o", &nc,
    ];
    ok(&kezuri(&args));
    let target = write_xyz(dir, "target.xyz", -4.0, 4.0, 0.05, f);
    let v = sim_ball_10(&nc, &target);
    (v["max_left_mm"].as_f64().unwrap(), v["max_gouge_mm"].as_f64().unwrap())
}

#[test]
fn the_copy_of_a_tilted_plane_and_a_sphere_is_the_model() {
    let dir = tempfile::tempdir().unwrap();
    for (name, f) in [("plane", plane as fn(f64, f64) -> f64), ("sphere", sphere)] {
        let data = digitize(dir.path(), name, f);
        let (bound_left, bound_gouge) = copy(dir.path(), &data, f, "bound");
        let (left, gouge) = copy(dir.path(), &data, f, "smooth");
        eprintln!("{name}: bound left {bound_left:.5} gouge {bound_gouge:.5}; smooth left {left:.5} gouge {gouge:.5}");
        // Before: the cusps between stylus positions (h(p/2) = 25 µm along
        // the rows, h(p/√2) = 50 µm mid-cell, on the flat); never a gouge.
        assert!(bound_left > 0.02 && bound_gouge < 1e-6, "{name} bound: left {bound_left}, gouge {bound_gouge}");
        // Now: the cutter's own cusp at 0.25 mm (1.6 µm), the path
        // tolerance and the interpolation.
        assert!(left <= 0.002, "{name}: left {left}");
        assert!(gouge <= 0.0005, "{name}: gouge {gouge}");
    }
}

#[test]
fn with_the_same_ball_at_the_pitch_the_program_is_the_readings() {
    let dir = tempfile::tempdir().unwrap();
    let data = digitize(dir.path(), "sphere", sphere);
    let readings: Vec<f64> = std::fs::read_to_string(&data)
        .unwrap()
        .lines()
        .skip(5)
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    let reading = |x: f64, y: f64| {
        let (i, j) = ((x + 5.0).round() as usize, (y + 5.0).round() as usize);
        readings[j * 11 + if j % 2 == 1 { 10 - i } else { i }]
    };
    let nc = path(dir.path(), "same.nc");
    #[rustfmt::skip]
    let args = ["probe", "mill", &data, "--stylus", "ball:10", "--tool", "ball:10", "--step", "1", "--floor-z", "off", "-o", &nc];
    ok(&kezuri(&args));
    let points = feed_points(&nc);
    let mut on_nodes = 0;
    for [x, y, z] in &points {
        let node = (x - x.round()).abs() < 1e-9 && (y - y.round()).abs() < 1e-9;
        assert!(node, "({x}, {y}) is not a reading's place");
        // The reading rounded to the nearest thousandth, as written.
        let r = reading(*x, *y);
        assert_eq!(format!("{z:.3}"), format!("{r:.3}"), "({x}, {y}): reading {r}");
        on_nodes += 1;
    }
    // Every reading is cut (a few in a straight line may be merged).
    assert!(on_nodes >= 110, "{on_nodes} of 121 readings in the program");
}

#[test]
fn a_reading_of_ten_is_written_z10() {
    let dir = tempfile::tempdir().unwrap();
    let data = digitize(dir.path(), "flat", |_, _| 10.0);
    assert!(std::fs::read_to_string(&data).unwrap().contains("\n1,10\n"));
    let nc = path(dir.path(), "flat.nc");
    let mill = |between: &str| {
        #[rustfmt::skip]
        let args = ["probe", "mill", &data, "--stylus", "ball:10", "--tool", "ball:10", "--floor-z", "off", "--between", between, "-o", &nc];
        ok(&kezuri(&args));
        std::fs::read_to_string(&nc).unwrap()
    };
    let text = mill("smooth");
    assert!(text.contains("Z10.\n") || text.contains("Z10. "), "{text}");
    assert!(!text.contains("Z10.001"), "{text}");
    // The bound rounds up, never below it.
    assert!(mill("bound").contains("Z10.001"));
}

fn roof(x: f64, _: f64) -> f64 {
    10.0 - 0.5 * (x - 0.37).abs()
}

#[test]
fn over_a_sharp_ridge_the_copy_follows_the_ball_between_the_readings() {
    // The ball rolls round the roof's ridge on an arc of its own radius:
    // straight lines from reading to reading (--step the pitch) cut about
    // p²/(8R) = 25 µm below the roof; the default follows the surface
    // between the readings, and `probe mill` warns of the ridge.
    let dir = tempfile::tempdir().unwrap();
    let data = digitize(dir.path(), "roof", roof);
    let target = write_xyz(dir.path(), "roof-target.xyz", -4.0, 4.0, 0.05, roof);
    let gouge = |extra: &[&str]| {
        let nc = path(dir.path(), "roof.nc");
        #[rustfmt::skip]
        let args = [&["probe", "mill", &data, "--stylus", "ball:10", "--tool", "ball:10", "--floor-z", "off", "-o", &nc][..], extra].concat();
        let o = kezuri(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v = sim_ball_10(&nc, &target);
        (v["max_gouge_mm"].as_f64().unwrap(), String::from_utf8_lossy(&o.stderr).into_owned())
    };
    let (straight, _) = gouge(&["--step", "1"]);
    let (followed, report) = gouge(&[]);
    eprintln!("roof: straight {straight:.5}, followed {followed:.5}\n{report}");
    let warned: f64 = report
        .split("may cut about ")
        .nth(1)
        .and_then(|rest| rest.split_whitespace().next()?.parse().ok())
        .expect(&report);
    assert!(straight > 0.02, "{straight}");
    assert!(followed <= 0.5 * straight && followed <= warned, "{followed} (straight {straight}, warned {warned})");
}

/// `kezuri sim --json` of `nc` cut by a 10 mm ball at 0.025 mm against
/// `target`.
fn sim_ball_10(nc: &str, target: &str) -> serde_json::Value {
    let o = kezuri(&["sim", nc, "--tool", "ball:10", "--res", "0.025", "--compare", target, "--json"]);
    serde_json::from_str(&ok(&o)).unwrap()
}
