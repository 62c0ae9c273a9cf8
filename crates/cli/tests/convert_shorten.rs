//! `kezuri convert --shorten TOL [--arcs]` through the binary, as written
//! (3 decimals): on random paths the program written stays within TOL of
//! the original both ways, arcs included. (The library's own property test
//! is crates/cam/tests/shorten.rs.)

use std::path::Path;

mod common;
use common::{feed_points, kezuri, ok};

/// A small deterministic generator (splitmix64), numbers in [0, 1).
struct Random(u64);

impl Random {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        (z ^ (z >> 31)) as f64 / 2f64.powi(64)
    }
}

/// A random cutting path: walks, noisy circles at constant Z and rows of
/// equal Z, one G01 block per point.
fn random_program(seed: u64) -> String {
    let mut r = Random(seed);
    let mut text = String::from("G00 X0. Y0. Z5.\nG01 Z0. F600.\n");
    let (mut x, mut y, mut z) = (0.0f64, 0.0f64, 0.0f64);
    for _ in 0..6 {
        let noise = 0.004 * r.next();
        match (r.next() * 3.0) as u32 {
            0 => {
                let (dx, dy, dz) = (r.next() - 0.5, r.next() - 0.5, 0.2 * (r.next() - 0.5));
                for _ in 0..40 {
                    (x, y, z) = (x + dx + noise * r.next(), y + dy + noise * r.next(), z + dz);
                    text += &format!("X{x:.4} Y{y:.4} Z{z:.4}\n");
                }
            }
            1 => {
                let radius = 2.0 + 10.0 * r.next();
                let (cx, cy) = (x - radius, y);
                let turn = if r.next() < 0.5 { 0.05 } else { -0.05 };
                for k in 1..=60 {
                    let a = turn * f64::from(k);
                    let rr = radius + noise * (r.next() - 0.5);
                    (x, y) = (cx + rr * a.cos(), cy + rr * a.sin());
                    text += &format!("X{x:.4} Y{y:.4}\n");
                }
            }
            _ => {
                for _ in 0..40 {
                    x += 0.39;
                    if r.next() < 0.2 {
                        z += 0.1 * (r.next() - 0.5);
                    }
                    text += &format!("X{x:.4} Z{z:.4}\n");
                }
            }
        }
    }
    text + "G00 Z5.\nM30\n"
}

/// Distance from `p` to the polyline through `line`.
fn distance(p: [f64; 3], line: &[[f64; 3]]) -> f64 {
    let segment = |a: [f64; 3], b: [f64; 3]| {
        let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let ap = [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
        let len2 = ab.iter().map(|v| v * v).sum::<f64>();
        let t =
            if len2 > 0.0 { (ab.iter().zip(&ap).map(|(u, v)| u * v).sum::<f64>() / len2).clamp(0.0, 1.0) } else { 0.0 };
        (0..3).map(|k| (ap[k] - t * ab[k]).powi(2)).sum::<f64>().sqrt()
    };
    line.windows(2).map(|w| segment(w[0], w[1])).fold(f64::INFINITY, f64::min)
}

/// The farthest either polyline gets from the other.
fn both_ways(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    let one = |from: &[[f64; 3]], to: &[[f64; 3]]| from.iter().map(|p| distance(*p, to)).fold(0.0, f64::max);
    one(a, b).max(one(b, a))
}

fn file(dir: &Path, name: &str) -> String {
    dir.join(name).to_string_lossy().into_owned()
}

#[test]
fn the_written_program_stays_within_the_tolerance_both_ways() {
    let dir = tempfile::tempdir().unwrap();
    // What the written program adds: its 3 decimals (0.0005 mm an axis)
    // and, for arcs, the chords RML-1 makes of them at 0.001 mm steps.
    let slack = 0.0015;
    let (mut arcs_fitted, mut worst) = (0, 0.0f64);
    for seed in 1..=6u64 {
        let input = file(dir.path(), &format!("p{seed}.nc"));
        std::fs::write(&input, random_program(seed)).unwrap();
        let original = feed_points(&input);
        for tol in [0.002, 0.02, 0.2] {
            let short = file(dir.path(), "short.nc");
            ok(&kezuri(&["convert", &input, "--shorten", &tol.to_string(), "-o", &short]));
            let merged = feed_points(&short);
            assert!(merged.len() < original.len(), "seed {seed} tol {tol}: nothing merged");
            let d = both_ways(&original, &merged);
            assert!(d <= tol + slack, "seed {seed}, --shorten {tol}: {d} mm apart");
            worst = worst.max(d / tol);

            // With arcs: G02/G03, each made chords again (0.0005 mm) by
            // RML-1 at 0.001 mm steps and read back, to measure it.
            let arcs = file(dir.path(), "arcs.nc");
            ok(&kezuri(&["convert", &input, "--shorten", &tol.to_string(), "--arcs", "-o", &arcs]));
            let text = std::fs::read_to_string(&arcs).unwrap();
            let fitted = text.lines().filter(|l| l.starts_with("G02") || l.starts_with("G03")).count();
            let (rml, back) = (file(dir.path(), "arcs.rml"), file(dir.path(), "back.nc"));
            ok(&kezuri(&["convert", &arcs, "--rml-unit", "0.001", "-o", &rml]));
            ok(&kezuri(&["convert", &rml, "--rml-unit", "0.001", "-o", &back]));
            let chords = feed_points(&back);
            let d = both_ways(&original, &chords);
            assert!(d <= tol + slack + 0.001, "seed {seed}, --shorten {tol} --arcs ({fitted} arcs): {d} mm apart");
            arcs_fitted += fitted;
        }
    }
    eprintln!("{arcs_fitted} arcs; lines up to {worst:.3} of the tolerance apart");
    assert!(arcs_fitted >= 10, "{arcs_fitted} arcs fitted");
    // The merging uses the room it has: a path that stays far inside the
    // tolerance is merging too little.
    assert!(worst >= 0.5, "at most {worst} of the tolerance");
}
