//! The reference tool's edge from synthetic line-sensor profiles: known
//! corners, 1 µm noise, 5 % outliers.

use kezuri_correct::edge::find_edge;
use kezuri_correct::ErrorKind;
use kezuri_geom::SplitMix64;

/// A normal deviate (Box–Muller).
fn normal(rng: &mut SplitMix64) -> f64 {
    let (u1, u2) = (1.0 - rng.next_f64(), rng.next_f64());
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// A profile across a square tool's corner at `edge`, its first side
/// rising at `tilt` degrees: points every `pitch` mm in x over ±`half`,
/// z with `noise` mm of normal noise and a share `outliers` of points off
/// by up to ±50 µm.
fn profile(edge: [f64; 2], tilt: f64, half: f64, pitch: f64, noise: f64, outliers: f64, seed: u64) -> Vec<[f64; 2]> {
    let mut rng = SplitMix64::new(seed);
    let (up, down) = (tilt.to_radians().tan(), (90.0 - tilt).to_radians().tan());
    let n = (2.0 * half / pitch).round() as usize;
    (0..=n)
        .map(|k| {
            let x = edge[0] - half + k as f64 * pitch;
            let dx = x - edge[0];
            let mut z = edge[1] + if dx < 0.0 { dx * up } else { -dx * down };
            z += noise * normal(&mut rng);
            if rng.next_f64() < outliers {
                z += 0.05 * (2.0 * rng.next_f64() - 1.0);
            }
            [x, z]
        })
        .collect()
}

#[test]
fn the_edge_is_found_within_half_a_micrometre_through_noise_and_outliers() {
    let mut worst: f64 = 0.0;
    for seed in 0..40 {
        let edge = [0.1234 + 0.01 * seed as f64, -0.5678];
        let tilt = 30.0 + seed as f64; // 30° … 69°: sides steep and flat
        let points = profile(edge, tilt, 1.0, 0.005, 0.001, 0.05, seed);
        let e = find_edge(&points, None).unwrap();
        let miss = (e.edge[0] - edge[0]).hypot(e.edge[1] - edge[1]);
        worst = worst.max(miss);
        assert!(miss < 0.0005, "seed {seed}: {:?} vs {edge:?} ({:.3} µm)", e.edge, miss * 1e3);
        assert!((e.angle_deg - 90.0).abs() < 0.2, "seed {seed}: {}", e.angle_deg);
        // 1 µm of noise in z is 1 µm·cos(slope) from a line.
        assert!((0.0003..0.0011).contains(&e.rms_residual_mm), "seed {seed}: rms {}", e.rms_residual_mm);
        assert!(e.outliers >= 5, "seed {seed}: outliers {}", e.outliers);
    }
    eprintln!("worst edge error over 40 profiles: {:.3} µm", worst * 1e3);
}

#[test]
fn without_the_outlier_rejection_the_edge_would_be_off() {
    // The same profiles fitted with every point (outliers never dropped)
    // miss by more than the tolerance: the test above can fail.
    let points = profile([0.0, 0.0], 45.0, 1.0, 0.005, 0.001, 0.05, 3);
    let split = points.iter().position(|p| p[0] >= 0.0).unwrap();
    let fit = |s: &[[f64; 2]]| {
        // Plain least squares z(x) on all points.
        let n = s.len() as f64;
        let (mx, mz) = (s.iter().map(|p| p[0]).sum::<f64>() / n, s.iter().map(|p| p[1]).sum::<f64>() / n);
        let b = s.iter().map(|p| (p[0] - mx) * (p[1] - mz)).sum::<f64>()
            / s.iter().map(|p| (p[0] - mx).powi(2)).sum::<f64>();
        (b, mz - b * mx)
    };
    let ((b1, a1), (b2, a2)) = (fit(&points[..split]), fit(&points[split..]));
    let x = (a2 - a1) / (b1 - b2);
    let naive = [x, a1 + b1 * x];
    let robust = find_edge(&points, None).unwrap().edge;
    assert!(naive[0].hypot(naive[1]) > robust[0].hypot(robust[1]));
    assert!(robust[0].hypot(robust[1]) < 0.0005);
}

#[test]
fn a_given_split_and_profiles_without_a_corner() {
    let points = profile([0.0, 0.0], 40.0, 0.5, 0.01, 0.0005, 0.0, 1);
    let e = find_edge(&points, Some(0.0)).unwrap();
    assert!(e.edge[0].abs() < 2e-4 && e.edge[1].abs() < 2e-4, "{:?}", e.edge);
    // A straight profile: no corner.
    let line: Vec<[f64; 2]> = (0..50).map(|k| [k as f64 * 0.01, 0.3 * k as f64 * 0.01]).collect();
    assert_eq!(find_edge(&line, None).unwrap_err().kind, ErrorKind::NoCorner);
    assert_eq!(find_edge(&line[..4], None).unwrap_err().kind, ErrorKind::TooFewPoints);
    assert_eq!(find_edge(&points, Some(-10.0)).unwrap_err().kind, ErrorKind::BadSplit);
    let mut bad = points.clone();
    bad[7][1] = f64::NAN;
    assert_eq!(find_edge(&bad, None).unwrap_err().kind, ErrorKind::NotFinite);
}

#[test]
fn the_report_gives_the_edge_the_sides_and_the_residual() {
    let points = profile([0.0, 0.0], 40.0, 0.5, 0.01, 0.0, 0.0, 1);
    let e = find_edge(&points, None).unwrap();
    assert!((e.sides[0].angle_deg() - 40.0).abs() < 1e-6, "{}", e.sides[0].angle_deg());
    let report = e.report("p.csv", points.len());
    let lines: Vec<&str> = report.lines().collect();
    assert_eq!(lines.len(), 6, "{report}");
    assert_eq!(lines[0], "p.csv: 101 points");
    assert!(lines[1].starts_with("  edge       x ") && lines[2].ends_with("° between the sides"), "{report}");
    assert!(lines[5].starts_with("  residual   ") && report.ends_with("outliers left out\n"), "{report}");
}
