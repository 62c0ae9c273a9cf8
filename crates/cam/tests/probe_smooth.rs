//! The smooth surface through ball-stylus readings: through every reading,
//! C¹ across the patch borders, no overshoot, exact on planes; the
//! curvature warning; the model under it.

use kezuri_cam::probe::smooth::{sharpest_bend, slopes, Smooth};
use kezuri_cam::probe::stylus::model;
use kezuri_cam::probe::{Grid, Order, ProbeGrid};
use kezuri_cam::{Cutter, ErrorKind};

fn grid(nx: usize, ny: usize, pitch: f64) -> Grid {
    Grid { nx, ny, pitch, origin: [-3.0, 2.0], order: Order::ZigZag }
}

fn data(g: Grid, f: impl Fn(f64, f64) -> f64) -> ProbeGrid {
    ProbeGrid { grid: g, z: (0..g.len()).map(|k| f(g.x(k % g.nx), g.y(k / g.nx))).collect() }
}

/// Rough readings: steps, tops, flats and slopes of every kind.
fn rough() -> ProbeGrid {
    let mut seed = 7u64;
    let g = grid(13, 11, 0.7);
    let mut d = data(g, |_, _| 0.0);
    for z in &mut d.z {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        let r = (seed >> 11) as f64 / (1u64 << 53) as f64;
        // A third of the readings share a height: flats and plateaus.
        *z = if r < 0.33 { 4.0 } else { 10.0 * r };
    }
    d
}

fn cells(g: &Grid) -> impl Iterator<Item = (usize, usize)> + '_ {
    (0..g.ny - 1).flat_map(move |j| (0..g.nx - 1).map(move |i| (i, j)))
}

#[test]
fn the_surface_passes_through_every_reading() {
    for d in [rough(), data(grid(9, 6, 1.0), |x, y| (x * 0.7).sin() * (y * 0.4).cos())] {
        let s = Smooth::new(&d).unwrap();
        let g = d.grid;
        for j in 0..g.ny {
            for i in 0..g.nx {
                let z = s.z(g.x(i), g.y(j));
                assert!((z - d.z(i, j)).abs() <= 1e-12, "({i}, {j}): {z} vs reading {}", d.z(i, j));
            }
        }
    }
}

#[test]
fn height_and_slopes_match_across_every_patch_border() {
    let d = rough();
    let s = Smooth::new(&d).unwrap();
    let g = d.grid;
    let e = 1e-12;
    let mut worst: f64 = 0.0;
    for k in 0..=40 {
        // Borders x = x_i, along y, and y = y_j, along x.
        let along = k as f64 / 40.0;
        for i in 1..g.nx - 1 {
            let y = g.y(0) + along * (g.ny - 1) as f64 * g.pitch;
            let (a, b) = (s.local(g.x(i) - e, y), s.local(g.x(i) + e, y));
            worst =
                worst.max((a.z - b.z).abs()).max((a.slope[0] - b.slope[0]).abs()).max((a.slope[1] - b.slope[1]).abs());
        }
        for j in 1..g.ny - 1 {
            let x = g.x(0) + along * (g.nx - 1) as f64 * g.pitch;
            let (a, b) = (s.local(x, g.y(j) - e), s.local(x, g.y(j) + e));
            worst =
                worst.max((a.z - b.z).abs()).max((a.slope[0] - b.slope[0]).abs()).max((a.slope[1] - b.slope[1]).abs());
        }
    }
    // Second derivatives up to ~10² here: within 1e-12 of a border they
    // move the slopes by ~1e-10; a jump would show as ≫ 1e-9.
    assert!(worst <= 1e-9, "largest jump across a border {worst:e}");
    // The slopes at a node are those of every cell around it.
    let n = s.node_slope(5, 4);
    let c = s.local(g.x(5), g.y(4));
    assert!((n[0] - c.slope[0]).abs() < 1e-12 && (n[1] - c.slope[1]).abs() < 1e-12);
}

#[test]
fn every_patch_stays_between_its_lowest_and_highest_reading() {
    for d in [rough(), data(grid(9, 7, 1.0), |x, y| if x + 0.3 * y > 0.0 { 5.0 } else { 0.0 })] {
        let s = Smooth::new(&d).unwrap();
        let g = d.grid;
        for (i, j) in cells(&g) {
            let corners = [d.z(i, j), d.z(i + 1, j), d.z(i, j + 1), d.z(i + 1, j + 1)];
            let lo = corners.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = corners.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            for t in 0..=20 {
                for u in 0..=20 {
                    let (x, y) = (g.x(i) + t as f64 * g.pitch / 20.0, g.y(j) + u as f64 * g.pitch / 20.0);
                    let z = s.z(x, y);
                    assert!(
                        z >= lo - 1e-12 && z <= hi + 1e-12,
                        "cell ({i}, {j}) at ({x}, {y}): {z} outside [{lo}, {hi}]"
                    );
                }
            }
        }
    }
}

#[test]
fn between_monotone_readings_the_surface_is_monotone() {
    // Rising along every row (unevenly, with flats); falling down the
    // columns: every row and column curve follows.
    let g = grid(12, 9, 1.0);
    let d = data(g, |x, y| (x + 3.0).powi(3) * 0.1 + (x * 2.0).floor() - 0.5 * y + (y * 1.3).sin() * 0.2);
    let s = Smooth::new(&d).unwrap();
    for j in 0..g.ny {
        let row: Vec<f64> = (0..400).map(|k| s.z(g.x(0) + k as f64 * 11.0 / 399.0, g.y(j))).collect();
        assert!(row.windows(2).all(|w| w[1] >= w[0] - 1e-12), "row {j} falls somewhere");
    }
    // Readings that change along X only: the whole surface rises with X,
    // flats stay flat.
    let steps =
        data(g, |x, _| [0.0, 0.0, 1.0, 1.1, 4.0, 4.0, 4.0, 6.0, 9.0, 9.5, 9.5, 12.0][(x + 3.0).round() as usize]);
    let s = Smooth::new(&steps).unwrap();
    for k in 0..=600 {
        let y = g.y(0) + (k % 31) as f64 * 8.0 / 30.0;
        let x = g.x(0) + k as f64 * 11.0 / 600.0;
        let l = s.local(x, y);
        assert!(l.slope[0] >= -1e-12 && l.slope[1].abs() < 1e-12, "({x}, {y}): {:?}", l.slope);
    }
    assert_eq!(s.z(g.x(5) + 0.37, g.y(3) + 0.5), 4.0);
    // A top between readings is not invented: equal neighbours, flat slope.
    assert_eq!(slopes(&[0.0, 1.0, 1.0, 0.0]), [1.5, 0.0, 0.0, -1.5]);
    assert_eq!(slopes(&[0.0, 1.0, 0.5])[1], 0.0);
}

#[test]
fn a_tilted_plane_is_copied_exactly() {
    let d = data(grid(8, 7, 1.25), |x, y| 3.0 + 0.21 * x - 0.37 * y);
    let s = Smooth::new(&d).unwrap();
    for k in 0..500 {
        let (x, y) = (-3.0 + (k % 23) as f64 * 8.75 / 22.0, 2.0 + (k / 23) as f64 * 7.5 / 22.0);
        let l = s.local(x, y);
        assert!((l.z - (3.0 + 0.21 * x - 0.37 * y)).abs() < 1e-12, "({x}, {y}): {}", l.z);
        assert!((l.slope[0] - 0.21).abs() < 1e-12 && (l.slope[1] + 0.37).abs() < 1e-12);
    }
}

/// A ball stylus of radius `r` on a sphere of radius `big` centred at
/// (0, 0, −big): the readings (tip heights) and the model.
fn on_sphere(r: f64, big: f64) -> (ProbeGrid, impl Fn(f64, f64) -> f64) {
    let g = Grid { nx: 21, ny: 21, pitch: 1.0, origin: [-10.0, -10.0], order: Order::ZigZag };
    let tip = move |x: f64, y: f64| ((big + r).powi(2) - x * x - y * y).sqrt() - big - r;
    (data(g, tip), move |x: f64, y: f64| (big * big - x * x - y * y).sqrt() - big)
}

#[test]
fn the_model_is_the_surface_offset_by_the_stylus() {
    let (d, sphere) = on_sphere(5.0, 30.0);
    let s = Smooth::new(&d).unwrap();
    assert_eq!(s.tighter_than(5.0), None);
    let ball: Cutter = "ball:10".parse().unwrap();
    let m = model(&s, &ball, 0.125).unwrap();
    let mut worst = (0.0f64, 0.0f64);
    for j in 0..m.ny() {
        for i in 0..m.nx() {
            let (x, y) = (m.x(i), m.y(j));
            // Away from the borders, where the stylus reached beyond the data.
            if x.abs().max(y.abs()) > 6.0 {
                continue;
            }
            let e = m.z(i, j) - sphere(x, y);
            worst = (worst.0.min(e), worst.1.max(e));
        }
    }
    // Above the sphere by the sampling of the stylus positions (at most
    // δ²/4·(1/35 + 1/(5·cos³θ)) ≈ 0.9 µm here), below only by the
    // interpolation's own error.
    assert!(worst.0 > -2e-4 && worst.1 < 1.5e-3, "model − sphere in {worst:?}");
}

#[test]
fn readings_tighter_than_the_stylus_are_reported() {
    // A tent ridge read by a 10 mm ball: its tip surface is an arc of the
    // ball's own radius (5 mm) over the crest, flagged for a stylus of
    // radius 10 (and, where the arc meets the flanks, a little tighter:
    // the sharp edge the warning names).
    let g = grid(15, 9, 0.5);
    let d = data(g, |x, _| {
        let x = x - 0.5;
        // Flanks of slope 3/4: the ball touches the crest within 3 mm.
        if x.abs() < 3.0 {
            (25.0 - x * x).sqrt() - 5.0
        } else {
            -1.0 - 0.75 * (x.abs() - 3.0)
        }
    });
    let s = Smooth::new(&d).unwrap();
    let t = s.tighter_than(10.0).expect("a crest of radius < 10 mm");
    assert!(t.cells >= 2 && t.radius < 10.0 && (t.at[0] - 0.5).abs() <= 3.5, "{t:?}");
    // A sphere read by a ball is never tighter than the ball.
    assert_eq!(Smooth::new(&on_sphere(5.0, 12.0).0).unwrap().tighter_than(5.0), None);
}

#[test]
fn bad_readings_are_refused() {
    let mut d = data(grid(3, 3, 1.0), |_, _| 1.0);
    d.z[4] = f64::NAN;
    let e = Smooth::new(&d).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Surface, "{e}");
    assert!(e.to_string().contains("(1, 1)"));
    assert!(Smooth::new(&data(grid(1, 3, 1.0), |_, _| 1.0)).is_err());
}

/// `(x, y)` every tenth of the pitch along every row of readings.
fn along_rows(g: &Grid) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
    cells(g).flat_map(move |(i, j)| (0..=10).map(move |k| (i, j, k as f64 / 10.0)))
}

#[test]
fn the_path_followed_is_the_higher_of_the_surface_and_the_straight_line() {
    for d in [rough(), data(grid(9, 6, 1.0), |x, y| (x * 0.7).sin() * (y * 0.4).cos())] {
        let s = Smooth::new(&d).unwrap();
        let g = d.grid;
        for (i, j, t) in along_rows(&g) {
            let (x, y) = (g.x(i) + t * g.pitch, g.y(j));
            let (a, b) = (d.z(i, j), d.z(i + 1, j));
            let line = a + t * (b - a);
            let f = s.over_chord(x, y);
            assert!((s.chord(x, y) - line).abs() <= 1e-12, "({x}, {y})");
            assert!((f - line.max(s.z(x, y))).abs() <= 1e-12, "({x}, {y})");
            // Through the readings and between them, as the surface.
            assert!(f >= a.min(b) - 1e-12 && f <= a.max(b) + 1e-12, "({x}, {y}): {f} outside [{a}, {b}]");
        }
    }
}

#[test]
fn next_to_a_bottom_reading_the_path_stays_above_the_valley() {
    // A valley whose bottom lies just before a reading: the surface starts
    // flat at that reading (its slope must be 0) and falls below the
    // valley; the straight line does not (a valley lies under its chords).
    let f = |x: f64, y: f64| (x + 0.4).powi(2) + 0.1 * y;
    let d = data(grid(9, 4, 1.0), f);
    let s = Smooth::new(&d).unwrap();
    let g = d.grid;
    let (mut surface, mut path) = (0.0f64, 0.0f64);
    for (i, j, t) in along_rows(&g) {
        let (x, y) = (g.x(i) + t * g.pitch, g.y(j));
        surface = surface.max(f(x, y) - s.z(x, y));
        path = path.max(f(x, y) - s.over_chord(x, y));
    }
    assert!(surface > 0.1, "the surface falls {surface} below the valley");
    assert!(path <= 1e-12, "the path falls {path} below the valley");
}

#[test]
fn on_a_crest_the_path_is_the_surface_and_the_bend_is_the_chords_sag() {
    // A crest of radius 5 mm (a ball rolled over a sharp ridge) with its
    // top on the middle reading: the surface is above its chords, and the
    // readings' bend, −Δ²z/8 at the top, is the sag of the straight line
    // between two readings.
    let rho = 5.0;
    let arc = |x: f64, _: f64| (rho * rho - (x + 2.0).powi(2)).sqrt();
    let d = data(grid(3, 3, 1.0), arc);
    let s = Smooth::new(&d).unwrap();
    let g = d.grid;
    let mut sag: f64 = 0.0;
    for (i, j, t) in along_rows(&g) {
        let (x, y) = (g.x(i) + t * g.pitch, g.y(j));
        assert!((s.over_chord(x, y) - s.z(x, y)).abs() <= 1e-12, "({x}, {y})");
        sag = sag.max(arc(x, y) - s.chord(x, y));
    }
    let b = sharpest_bend(&d, 0.001).expect("a crest of radius 5 mm bends 25 µm at 1 mm");
    assert!((b.depth - sag).abs() <= 0.03 * sag, "bend {} against the chords' sag {sag}", b.depth);
    assert!((b.depth - 1.0 / (8.0 * rho)).abs() <= 0.02 / (8.0 * rho), "{}", b.depth);
    assert_eq!(b.at, [g.x(1), g.y(0)]);
    assert_eq!(b.points, 3, "{b:?}");
    assert_eq!(sharpest_bend(&d, sag * 1.1), None);
    // A plane and a valley do not bend down.
    assert_eq!(sharpest_bend(&data(grid(6, 5, 1.0), |x, y| 2.0 + 0.3 * x - 0.8 * y), 1e-12), None);
    assert_eq!(sharpest_bend(&data(grid(6, 5, 1.0), |x, y| x * x + y * y), 1e-12), None);
}
