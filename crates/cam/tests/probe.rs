//! The probe library: capture order, readers, levelling, the stylus surface.

use kezuri_cam::probe::data::{read, write, Hint};
use kezuri_cam::probe::level::{level, Method, Reference};
use kezuri_cam::probe::stylus::{reconstruct, OverFlat};
use kezuri_cam::probe::{Grid, Order, ProbeGrid};
use kezuri_cam::{drop_cutter, Cutter};

#[test]
fn zigzag_order_reverses_every_other_row() {
    let g = Grid { nx: 3, ny: 2, pitch: 1.0, origin: [0.0, 0.0], order: Order::ZigZag };
    let nodes: Vec<_> = (0..6).map(|k| g.node(k)).collect();
    assert_eq!(nodes, [(0, 0), (1, 0), (2, 0), (2, 1), (1, 1), (0, 1)]);
    assert!((0..6).all(|k| g.index(g.node(k).0, g.node(k).1) == k));
}

#[test]
fn a_bare_file_round_trips_with_its_zero_record() {
    let text = "0,0\n1,1\n2,2\n3,3\n4,4\n5,5\n6,6\n";
    let hint = Hint { count: Some([3, 2]), pitch: Some(1.0), ..Hint::default() };
    let d = read(text, &hint).unwrap();
    assert_eq!(d.grid.z, [1.0, 2.0, 3.0, 6.0, 5.0, 4.0]);
    assert_eq!(write(&d.grid, &d.format), text);
    let e = read("1,1\n2,x\n", &hint).unwrap_err();
    assert_eq!(e.line, Some(2));
}

#[test]
fn plane_levelling_removes_a_tilt_and_lines_a_twist() {
    let g = Grid { nx: 11, ny: 9, pitch: 2.0, origin: [0.0, 0.0], order: Order::ZigZag };
    let twist = |x: f64, y: f64| 5.0 + 0.01 * x - 0.02 * y + 0.001 * x * y;
    let z = (0..g.len()).map(|k| twist(g.x(k % g.nx), g.y(k / g.nx))).collect();
    let data = ProbeGrid { grid: g, z };
    let l = level(&data, &Reference::Border, Method::Auto).unwrap();
    assert!(l.raw.std > 0.01);
    assert!(l.kept().name.starts_with("lines") && l.kept().stats.std < 1e-12, "{}", l.table());
    assert!((l.kept().stats.mean - l.raw.mean).abs() < 1e-12);
    assert!(level(&data, &Reference::Rows(1, 10), Method::Plane).is_err());
}

#[test]
fn the_stylus_on_its_own_surface_returns_the_readings() {
    let g = Grid { nx: 21, ny: 21, pitch: 1.0, origin: [0.0, 0.0], order: Order::ZigZag };
    let z: Vec<f64> = (0..g.len()).map(|k| (0.3 * (k % 21) as f64).sin() + 0.1 * (k / 21) as f64).collect();
    let data = ProbeGrid { grid: g, z };
    let ball: Cutter = "ball:10".parse().unwrap();
    let field = reconstruct(&data, &ball, 0.125).unwrap();
    for j in 5..16 {
        for i in 5..16 {
            let cl = drop_cutter(&ball, &field, i as f64, j as f64).unwrap();
            // Never below a reading; above it by the chords of the sampling.
            assert!(cl >= data.z(i, j) - 1e-9 && cl - data.z(i, j) < 0.002, "({i}, {j}): {cl} vs {}", data.z(i, j));
        }
    }
}

#[test]
fn over_the_flat_the_bound_is_above_the_exact_location_and_in_the_band() {
    // A flat top at 10 (noise ±0.004) with a 6 mm deep bowl in the middle.
    let g = Grid { nx: 41, ny: 31, pitch: 1.0, origin: [0.0, 0.0], order: Order::ZigZag };
    let z: Vec<f64> = (0..g.len())
        .map(|k| {
            let (x, y) = ((k % 41) as f64, (k / 41) as f64);
            let r2 = (x - 20.0).powi(2) + (y - 15.0).powi(2);
            10.0 - (6.0 - r2 / 12.0).max(0.0) + 0.004 * (k as f64 * 1.7).sin()
        })
        .collect();
    let data = ProbeGrid { grid: g, z };
    let stylus: Cutter = "ball:10".parse().unwrap();
    let field = reconstruct(&data, &stylus, 0.125).unwrap();
    let over = OverFlat::new(&data, &stylus, 10.0, 0.01);
    let (mut clear, mut not) = (0, 0);
    for tool in ["ball:10", "ball:4", "flat:6"] {
        let cutter: Cutter = tool.parse().unwrap();
        for j in 0..=120 {
            for i in 0..=160 {
                let (x, y) = (i as f64 * 0.25, j as f64 * 0.25);
                let exact = drop_cutter(&cutter, &field, x, y).unwrap();
                match over.height(x, y) {
                    Some(bound) => {
                        clear += 1;
                        assert!(bound >= exact - 1e-9, "{tool} ({x}, {y}): bound {bound} < {exact}");
                        assert!(exact >= 10.0 - 0.01, "{tool} ({x}, {y}): {exact} is below the flat band");
                    }
                    None => not += 1,
                }
            }
        }
    }
    // Both kinds of places are there; the bowl (r ≤ 8.5) and a stylus
    // radius and a pitch around it are never clear.
    assert!(clear > 1000 && not > 1000, "{clear} {not}");
    assert_eq!(over.height(20.0, 15.0 + 14.0), None);
    assert!(over.height(1.0, 1.0).is_some());
}
