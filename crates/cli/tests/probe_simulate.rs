//! `kezuri probe simulate`: the readings of a ball stylus on a model,
//! checked against the closed form for a sphere.

use std::fmt::Write as _;

mod common;
use common::kezuri;

/// A sphere of radius 20 about (0, 0, 0), its cap over ±10 mm sampled
/// every 0.1 mm as an `x y z` grid.
fn sphere_cap() -> String {
    let mut text = String::new();
    for j in -100..=100 {
        for i in -100..=100 {
            let (x, y) = (f64::from(i) * 0.1, f64::from(j) * 0.1);
            writeln!(text, "{x} {y} {}", (400.0 - x * x - y * y).sqrt()).unwrap();
        }
    }
    text
}

/// The tip of a ball of radius `r` resting on the sphere at `(x, y)`: its
/// centre is `20 + r` from the sphere's.
fn tip_on_sphere(r: f64, x: f64, y: f64) -> f64 {
    ((20.0 + r).powi(2) - x * x - y * y).sqrt() - r
}

fn readings(text: &str) -> Vec<(usize, f64)> {
    text.lines()
        .skip_while(|l| *l != "No,Z")
        .skip(1)
        .map(|l| {
            let (k, z) = l.split_once(',').unwrap();
            (k.parse().unwrap(), z.parse().unwrap())
        })
        .collect()
}

#[test]
fn readings_are_where_a_ball_rests_on_the_model() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("cap.xyz");
    std::fs::write(&model, sphere_cap()).unwrap();
    let model = model.to_string_lossy().into_owned();
    let out = dir.path().join("cap.txt").to_string_lossy().into_owned();
    let base = ["probe", "simulate", &model, "--count", "5,4", "--pitch", "2", "--stylus", "ball:6", "-o", &out];
    let o = kezuri(&base);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&out).unwrap();
    // Centred on the model: origin (-4, -3); zig-zag order in the header.
    assert!(text.contains("# grid nx=5 ny=4 pitch=2 origin=-4,-3 pattern=zigzag"), "{text}");
    let z = readings(&text);
    assert_eq!(z.len(), 20);
    for (k, z) in &z {
        let (j, a) = ((k - 1) / 5, (k - 1) % 5);
        let i = if j % 2 == 1 { 4 - a } else { a };
        let (x, y) = (-4.0 + 2.0 * i as f64, -3.0 + 2.0 * j as f64);
        // The sampled sphere's chords (≤ 0.02²/(8·20)) and 4 decimals.
        let exact = tip_on_sphere(3.0, x, y);
        assert!((z - exact).abs() <= 1.5e-4, "No {k} at ({x}, {y}): {z} vs {exact}");
    }
    // The levelling and milling commands read the file as it is.
    let levelled = dir.path().join("level.txt").to_string_lossy().into_owned();
    let level = kezuri(&["probe", "level", &out, "--reference", "corners", "-o", &levelled]);
    assert!(level.status.success(), "{}", String::from_utf8_lossy(&level.stderr));

    // Tilt and noise: repeatable with the seed, bounded, and not nothing.
    let noisy = |seed: &str| {
        let o = kezuri(&[&base[..], &["--tilt", "0.01,-0.02", "--noise", "0.005", "--seed", seed]].concat());
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        std::fs::read_to_string(&out).unwrap()
    };
    let (a, b, c) = (noisy("3"), noisy("3"), noisy("4"));
    assert_eq!(a, b);
    assert_ne!(a, c);
    let mut largest: f64 = 0.0;
    for ((k, n), (_, z)) in readings(&a).iter().zip(&z) {
        let (j, i) = ((k - 1) / 5, (k - 1) % 5);
        let i = if j % 2 == 1 { 4 - i } else { i };
        let (x, y) = (-4.0 + 2.0 * i as f64, -3.0 + 2.0 * j as f64);
        // The grid's centre is (0, 0).
        let off = n - z - (0.01 * x - 0.02 * y);
        assert!(off.abs() <= 0.005 + 2e-4, "No {k}: noise {off}");
        largest = largest.max(off.abs());
    }
    assert!(largest > 0.002, "noise of ±0.005 gave at most {largest}");
}

#[test]
fn a_grid_off_the_model_is_an_error_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("cap.xyz");
    std::fs::write(&model, sphere_cap()).unwrap();
    let out = dir.path().join("off.txt");
    let o = kezuri(&[
        "probe",
        "simulate",
        &model.to_string_lossy(),
        "--count",
        "3,3",
        "--pitch",
        "20",
        "--origin",
        "-5,-5",
        "--stylus",
        "ball:6",
        "-o",
        &out.to_string_lossy(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("point 2 at (15, -5) is off the model"), "{err}");
    assert!(!out.exists());
    for (flag, value, says) in [
        ("--count", "1,5", "the grid needs 2 to"),
        ("--pitch", "0", "'--pitch <MM>': it must be a length"),
        ("--tilt", "0.1", "--tilt '0.1': expected two numbers"),
        ("--noise", "NaN", "'--noise <MM>': it must be zero or a length"),
    ] {
        let mut args = vec!["probe", "simulate", "x.stl", "--count", "3,3", "--pitch", "1", "--stylus", "ball:6"];
        args.extend(["-o", "never.txt"]);
        let k = args.iter().position(|a| *a == flag).map(|k| k + 1);
        match k {
            Some(k) => args[k] = value,
            None => args.extend([flag, value]),
        }
        let o = kezuri(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(says), "{flag} {value}: {err}");
    }
}
