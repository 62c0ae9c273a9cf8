//! Material-removal simulation: exact envelopes, arcs, cusps, rapids, bad
//! input.

use kezuri_cam::sim::compare::{compare, target_heights};
use kezuri_cam::sim::{simulate, swept_height, SimOptions, Stock, ZMap};
use kezuri_cam::ErrorKind;
use kezuri_cam::{scallop, Cutter};
use kezuri_geom::{Arc, Axes, Move, MoveKind, Plane, Toolpath};

fn at(x: f64, y: f64, z: f64) -> Axes {
    Axes { x, y, z, ..Axes::ZERO }
}

fn feed(a: [f64; 3], b: [f64; 3]) -> Move {
    Move { kind: MoveKind::Feed, start: at(a[0], a[1], a[2]), end: at(b[0], b[1], b[2]), ..Move::default() }
}

fn rapid(a: [f64; 3], b: [f64; 3], line: u32) -> Move {
    Move { kind: MoveKind::Rapid, line, ..feed(a, b) }
}

fn tool(spec: &str) -> Cutter {
    spec.parse().unwrap()
}

/// Heights are kept in whole nanometres: a cell is the exact envelope to
/// half of one (and the evaluation's rounding).
const NM: f64 = 0.5e-6 + 1e-12;

const SHAPES: [&str; 8] = ["ball:6", "flat:6", "oval:8,6", "oval:8,2", "bull:6,1", "bull:6,0", "v:6,90", "v:4,40"];

/// Simulates `moves` over the stock at `res`.
fn run(moves: Vec<Move>, cutter: &Cutter, stock: Stock, res: f64) -> ZMap {
    let options = SimOptions::new(res);
    let mut zmap = ZMap::new(&stock, &options).unwrap();
    simulate(&Toolpath::from(moves), cutter, &mut zmap, &options).unwrap();
    zmap
}

fn stock(x0: f64, y0: f64, x1: f64, y1: f64, top: f64) -> Stock {
    Stock { x0, y0, x1, y1, top }
}

/// Ball of radius `r`: height of the lower surface at distance `d`.
fn ball(r: f64, d: f64) -> f64 {
    r - (r * r - d * d).sqrt()
}

#[test]
fn a_level_line_leaves_exactly_the_ball_trough() {
    let (r, z0, top) = (3.0, -1.0, 0.0);
    let zmap = run(vec![feed([3.0, 5.0, z0], [12.0, 5.0, z0])], &tool("ball:6"), stock(0.0, 0.0, 15.0, 10.0, top), 0.1);
    let mut cut = 0;
    for j in 0..zmap.ny {
        for i in 0..zmap.nx {
            let [x, y] = zmap.centre(i, j);
            let along = x - x.clamp(3.0, 12.0);
            let d = along.hypot(y - 5.0);
            let want = if d <= r { (z0 + ball(r, d)).min(top) } else { top };
            let got = zmap.height(i, j);
            assert!((got - want).abs() <= NM, "cell ({x}, {y}): {got} vs {want}");
            cut += usize::from(got < top);
        }
    }
    assert!(cut > 1000, "{cut}");
}

#[test]
fn a_plunge_leaves_the_tool_imprint() {
    for spec in SHAPES {
        let c = tool(spec);
        let zmap = run(vec![feed([5.0, 5.0, 10.0], [5.0, 5.0, -2.0])], &c, stock(0.0, 0.0, 10.0, 10.0, 0.0), 0.25);
        for j in 0..zmap.ny {
            for i in 0..zmap.nx {
                let [x, y] = zmap.centre(i, j);
                let d = (x - 5.0).hypot(y - 5.0);
                let want = if d <= c.radius() { (-2.0 + c.height(d)).min(0.0) } else { 0.0 };
                assert!((zmap.height(i, j) - want).abs() <= NM, "{spec} at ({x}, {y})");
            }
        }
    }
}

/// The lowest point of a capsule (the ball's centre swept from `a` to `b`,
/// radius `r`) over `(x, y)`, from the distance to the 3-D line of centres:
/// a derivation independent of the simulation's.
fn capsule_bottom(r: f64, a: [f64; 3], b: [f64; 3], x: f64, y: f64) -> Option<f64> {
    let ca = [a[0], a[1], a[2] + r];
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let dd: f64 = d.iter().map(|v| v * v).sum();
    let mut best: Option<f64> = None;
    let mut take = |z: f64| best = Some(best.map_or(z, |b: f64| b.min(z)));
    // End spheres.
    for c in [ca, [b[0], b[1], b[2] + r]] {
        let h2 = r * r - (x - c[0]).powi(2) - (y - c[1]).powi(2);
        if h2 >= 0.0 {
            take(c[2] - h2.sqrt());
        }
    }
    // The cylinder: |q − ca − t·d|² = r² with t the foot parameter; q =
    // (x, y, z). Points at distance r from the line satisfy a quadratic in z.
    let e = [x - ca[0], y - ca[1]];
    // Foot t(z) = (e·d_xy + (z − ca_z)·d_z) / dd; distance² = |w|² − (w·d)²/dd
    // with w = (e, z − ca_z). Quadratic in u = z − ca_z.
    let (ex, ey) = (e[0], e[1]);
    let ed = ex * d[0] + ey * d[1];
    // |w|² = ex² + ey² + u²; w·d = ed + u·dz.
    let qa = 1.0 - d[2] * d[2] / dd;
    let qb = -2.0 * ed * d[2] / dd;
    let qc = ex * ex + ey * ey - ed * ed / dd - r * r;
    if qa > 1e-15 {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc >= 0.0 {
            let u = (-qb - disc.sqrt()) / (2.0 * qa);
            let t = (ed + u * d[2]) / dd;
            if (0.0..=1.0).contains(&t) {
                take(ca[2] + u);
            }
        }
    }
    best
}

#[test]
fn sloped_lines_match_the_swept_sphere() {
    let c = tool("ball:6");
    let cases = [
        ([2.0, 3.0, -1.0], [9.0, 6.0, -3.0]),
        ([8.0, 8.0, 0.5], [2.5, 2.0, -2.5]),
        ([5.0, 1.0, -4.0], [5.2, 9.0, 1.0]),
    ];
    for (a, b) in cases {
        let zmap = run(vec![feed(a, b)], &c, stock(-2.0, -2.0, 12.0, 12.0, 5.0), 0.1);
        for j in 0..zmap.ny {
            for i in 0..zmap.nx {
                let [x, y] = zmap.centre(i, j);
                let want = capsule_bottom(3.0, a, b, x, y).map_or(5.0, |z| z.min(5.0));
                let got = zmap.height(i, j);
                assert!((got - want).abs() <= NM + 1e-9, "{a:?}->{b:?} at ({x}, {y}): {got} vs {want}");
            }
        }
    }
}

/// Independent oracle: the reach of the cutter over `t` from the quadratic
/// `|p − c(t)|² ≤ R²`, then a ternary search on the convex envelope in `t`.
fn oracle(c: &Cutter, a: [f64; 3], b: [f64; 3], x: f64, y: f64) -> Option<f64> {
    let r = c.radius();
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let (ex, ey) = (x - a[0], y - a[1]);
    let qa = dx * dx + dy * dy;
    let (t0, t1) = if qa < 1e-24 {
        if ex * ex + ey * ey > r * r {
            return None;
        }
        (0.0, 1.0)
    } else {
        let qb = -2.0 * (ex * dx + ey * dy);
        let qc = ex * ex + ey * ey - r * r;
        let disc = qb * qb - 4.0 * qa * qc;
        if disc < 0.0 {
            return None;
        }
        let (u, v) = ((-qb - disc.sqrt()) / (2.0 * qa), (-qb + disc.sqrt()) / (2.0 * qa));
        let (u, v) = (u.max(0.0), v.min(1.0));
        if u > v {
            return None;
        }
        (u, v)
    };
    let f = |t: f64| {
        let d = (ex - t * dx).hypot(ey - t * dy).min(r);
        a[2] + t * (b[2] - a[2]) + c.height(d)
    };
    let (mut lo, mut hi) = (t0, t1);
    for _ in 0..300 {
        let m1 = lo + (hi - lo) / 3.0;
        let m2 = hi - (hi - lo) / 3.0;
        if f(m1) <= f(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    Some(f(lo).min(f(hi)).min(f(t0)).min(f(t1)))
}

/// A reproducible stream of numbers in [0, 1).
fn rng(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[test]
fn every_shape_matches_an_independent_oracle() {
    let mut next = rng(7);
    for spec in SHAPES {
        let c = tool(spec);
        for _ in 0..60 {
            let a = [10.0 * next(), 10.0 * next(), 4.0 * next() - 2.0];
            let mut b = [10.0 * next(), 10.0 * next(), 4.0 * next() - 2.0];
            if next() < 0.2 {
                // Short moves and near-plunges.
                b = [a[0] + 0.01 * next(), a[1], b[2]];
            }
            for _ in 0..40 {
                let (x, y) = (14.0 * next() - 2.0, 14.0 * next() - 2.0);
                let got = swept_height(&c, a, b, x, y);
                let want = oracle(&c, a, b, x, y);
                match (got, want) {
                    (Some(g), Some(w)) => {
                        assert!((g - w).abs() <= 1e-7, "{spec} {a:?}->{b:?} at ({x}, {y}): {g} vs {w}")
                    }
                    (None, None) => {}
                    // On the very rim either may see a hair of reach.
                    (g, w) => {
                        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
                        let t = (((x - a[0]) * dx + (y - a[1]) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
                        let d = (x - a[0] - t * dx).hypot(y - a[1] - t * dy);
                        assert!((d - c.radius()).abs() < 1e-9, "{spec} {a:?}->{b:?} at ({x}, {y}): {g:?} vs {w:?}");
                    }
                }
            }
        }
    }
}

#[test]
fn simulation_is_the_minimum_over_its_moves() {
    // Zig-zag rows of short collinear moves with changing slope (the
    // pruning of straight runs is at work), turns, a plunge and a climb.
    let mut next = rng(11);
    for spec in SHAPES {
        let c = tool(spec);
        let mut moves = Vec::new();
        let mut p = [0.5, 1.0, -1.0];
        for row in 0..4 {
            for _ in 0..12 {
                let dir = if row % 2 == 0 { 1.0 } else { -1.0 };
                let q = [p[0] + dir * (0.2 + 0.6 * next()), p[1], -1.5 + next()];
                moves.push(feed(p, q));
                p = q;
            }
            let q = [p[0], p[1] + 1.3, p[2]];
            moves.push(feed(p, q));
            p = q;
        }
        moves.push(feed(p, [p[0], p[1], -2.5]));
        moves.push(feed([p[0], p[1], -2.5], [p[0] - 3.0, p[1] - 4.0, 0.5]));
        let box_ = stock(-3.0, -3.0, 12.0, 10.0, 0.0);
        let zmap = run(moves.clone(), &c, box_, 0.1);
        for j in 0..zmap.ny {
            for i in 0..zmap.nx {
                let [x, y] = zmap.centre(i, j);
                let want = moves
                    .iter()
                    .filter_map(|m| swept_height(&c, m.start.xyz(), m.end.xyz(), x, y))
                    .fold(0.0f64, f64::min);
                let got = zmap.height(i, j);
                assert!((got - want).abs() <= NM, "{spec} at ({x}, {y}): {got} vs {want}");
            }
        }
    }
}

#[test]
fn the_result_does_not_depend_on_the_threads() {
    let c = tool("ball:3");
    let moves: Vec<Move> = (0..200)
        .map(|k| {
            let x = k as f64 * 0.05;
            feed([x, 2.0 + (x * 0.7).sin(), -1.0 - 0.2 * x.cos()], [x + 0.05, 2.0 + ((x + 0.05) * 0.7).sin(), -1.1])
        })
        .collect();
    let options = SimOptions::new(0.05);
    let box_ = stock(-2.0, 0.0, 12.0, 5.0, 0.0);
    let path = Toolpath::from(moves);
    let mut one = ZMap::new(&box_, &options).unwrap();
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| simulate(&path, &c, &mut one, &options).unwrap());
    let mut many = ZMap::new(&box_, &options).unwrap();
    rayon::ThreadPoolBuilder::new()
        .num_threads(5)
        .build()
        .unwrap()
        .install(|| simulate(&path, &c, &mut many, &options).unwrap());
    assert_eq!(one, many);
}

#[test]
fn an_arc_is_cut_within_the_chord_tolerance() {
    // A level half circle of radius 4 about (6, 6), counter-clockwise from
    // (10, 6) to (2, 6), with a 4 mm ball at z = −1.
    let (r, z0, rho) = (2.0f64, -1.0, 4.0);
    let arc = Arc { center: [6.0, 6.0, z0], plane: Plane::Xy, ccw: true, turns: 0 };
    let m = Move { kind: MoveKind::Arc(arc), start: at(10.0, 6.0, z0), end: at(2.0, 6.0, z0), ..Move::default() };
    for tol in [1e-2, 1e-3] {
        let mut options = SimOptions::new(0.05);
        options.chord_tolerance = tol;
        let mut zmap = ZMap::new(&stock(0.0, 0.0, 12.0, 12.0, 0.0), &options).unwrap();
        let report = simulate(&Toolpath::from(vec![m]), &tool("ball:4"), &mut zmap, &options).unwrap();
        // Chords of sagitta ≤ tol on radius 4.
        let step = 2.0 * (1.0 - tol / rho).acos();
        assert_eq!(report.segments, (std::f64::consts::PI / step).ceil() as usize);
        let limit = 0.8 * r;
        let slope = limit / (r * r - limit * limit).sqrt();
        let mut checked = 0;
        for j in 0..zmap.ny {
            for i in 0..zmap.nx {
                let [x, y] = zmap.centre(i, j);
                // Distance to the true arc (upper half plus its end points).
                let d = if y >= 6.0 {
                    ((x - 6.0).hypot(y - 6.0) - rho).abs()
                } else {
                    (x - 10.0).hypot(y - 6.0).min((x - 2.0).hypot(y - 6.0))
                };
                if d <= limit {
                    let want = z0 + ball(r, d);
                    let got = zmap.height(i, j);
                    assert!((got - want).abs() <= slope * tol + 1e-9, "tol {tol} at ({x}, {y}): {got} vs {want}");
                    checked += 1;
                }
            }
        }
        assert!(checked > 10_000, "{checked}");
    }
}

/// Raster rows along X over the plane `z = y·tan(angle)`, `pick_feed`
/// apart in the plane, the cutter touching the plane; returns the largest
/// and smallest deviation from the plane measured square to it, over the
/// middle of the grid.
fn inclined_raster(c: &Cutter, angle_deg: f64, pick_feed: f64, res: f64) -> (f64, f64) {
    let angle = angle_deg.to_radians();
    let g = angle.tan();
    let rc = c.facet_radius(g);
    let lift = g * rc - c.height(rc);
    let step = pick_feed * angle.cos();
    let rows = 7;
    let mut moves = Vec::new();
    for k in 0..rows {
        let y = k as f64 * step;
        let z = g * y + lift;
        // Ten collinear moves a row, zig-zag, joined at the row ends.
        let xs: Vec<f64> = (0..=10).map(|i| i as f64).collect();
        let xs: Vec<f64> = if k % 2 == 0 { xs } else { xs.into_iter().rev().collect() };
        if k > 0 {
            let prev = moves.last().map(|m: &Move| m.end.xyz()).unwrap();
            moves.push(feed(prev, [xs[0], y, z]));
        }
        for w in xs.windows(2) {
            moves.push(feed([w[0], y, z], [w[1], y, z]));
        }
    }
    let top = g * rows as f64 * step + 10.0;
    let zmap = run(moves, c, stock(0.0, -2.0 * step, 10.0, (rows + 1) as f64 * step, top), res);
    let (mut hi, mut lo) = (f64::NEG_INFINITY, f64::INFINITY);
    for j in 0..zmap.ny {
        for i in 0..zmap.nx {
            let [x, y] = zmap.centre(i, j);
            if (3.0..=7.0).contains(&x) && y - rc >= 1.0 * step && y - rc <= (rows - 2) as f64 * step {
                let dev = (zmap.height(i, j) - g * y) * angle.cos();
                hi = hi.max(dev);
                lo = lo.min(dev);
            }
        }
    }
    (hi, lo)
}

#[test]
fn level_raster_cusp_is_the_ball_scallop() {
    // Cusps at y = (k + ½)·P fall on cell centres: exact to rounding.
    let (r, p) = (3.0, 1.0);
    let c = tool("ball:6");
    let zmap = {
        let moves: Vec<Move> = (0..6)
            .flat_map(|k| {
                (0..10).map(move |i| feed([i as f64, k as f64 * p, -1.0], [i as f64 + 1.0, k as f64 * p, -1.0]))
            })
            .collect();
        run(moves, &c, stock(0.0, -0.005, 10.0, 5.995, 0.0), 0.01)
    };
    let mut hi = f64::NEG_INFINITY;
    for j in 0..zmap.ny {
        for i in 0..zmap.nx {
            let [x, y] = zmap.centre(i, j);
            if (2.0..=8.0).contains(&x) && (0.0..=5.0).contains(&y) {
                hi = hi.max(zmap.height(i, j) + 1.0);
            }
        }
    }
    let h = r - (r * r - (p / 2.0) * (p / 2.0)).sqrt();
    assert!((hi - h).abs() <= NM + 1e-9, "{hi} vs {h}");
}

#[test]
fn inclined_raster_cusp_agrees_with_scallop_theory_within_the_grid() {
    let res = 0.01;
    for (spec, angle, pf) in
        [("ball:6", 0.0, 1.0), ("ball:6", 20.0, 1.0), ("ball:6", 45.0, 0.8), ("oval:16,24", 15.0, 0.8)]
    {
        let c = tool(spec);
        let (hi, lo) = inclined_raster(&c, angle, pf, res);
        let r = c.radius();
        let classic = r - (r * r - (pf / 2.0) * (pf / 2.0)).sqrt();
        let theory = scallop::cusp(&c, f64::to_radians(angle), pf).unwrap().cusp;
        if spec.starts_with("ball") {
            assert!((theory - classic).abs() < 1e-9, "{spec} {angle}: {theory} vs {classic}");
        }
        eprintln!("{spec} {angle}°: simulated cusp {hi:.6}, theory {theory:.6}, lowest {lo:.2e}");
        // A cell centre misses the cusp's peak by at most half a cell, on
        // flanks of slope below 1 in the plane; never above it, never below
        // the plane.
        assert!(hi <= theory + NM + 1e-9 && hi >= theory - res, "{spec} {angle}°: simulated {hi} vs {theory}");
        assert!(lo >= -NM - 1e-9 && lo <= res, "{spec} {angle}°: lowest {lo}");
    }
}

#[test]
fn rapids_into_the_stock_are_reported() {
    for spec in ["ball:6", "bull:6,1"] {
        rapids_into_the_stock_with(&tool(spec));
    }
}

fn rapids_into_the_stock_with(c: &Cutter) {
    let moves = vec![
        // The program starts with the tool inside the stock and lifts it
        // straight out: what the tool stands in is not the rapid's doing.
        rapid([10.0, 10.0, -2.0], [10.0, 10.0, 20.0], 2),
        rapid([10.0, 10.0, 20.0], [5.0, 5.0, 20.0], 3),
        // Down to just above the top: air.
        rapid([5.0, 5.0, 20.0], [5.0, 5.0, 0.0], 4),
        feed([5.0, 5.0, 0.0], [5.0, 5.0, -1.0]),
        feed([5.0, 5.0, -1.0], [15.0, 5.0, -1.0]),
        rapid([15.0, 5.0, -1.0], [15.0, 5.0, 10.0], 7),
        // Across at a height that is inside the stock: a crash.
        rapid([15.0, 5.0, 10.0], [15.0, 15.0, -0.5], 8),
        rapid([15.0, 15.0, -0.5], [5.0, 15.0, -0.5], 9),
        // Back along the cut trough at its own depth: touches nothing new.
        rapid([5.0, 15.0, -0.5], [5.0, 15.0, 10.0], 10),
    ];
    let options = SimOptions::new(0.1);
    let box_ = stock(0.0, 0.0, 20.0, 20.0, 0.0);
    let mut zmap = ZMap::new(&box_, &options).unwrap();
    let report = simulate(&Toolpath::from(moves), c, &mut zmap, &options).unwrap();
    let lines: Vec<u32> = report.rapid_hits.iter().map(|h| h.line).collect();
    assert_eq!(lines, [8, 9], "{c}");
    // 0.5 mm deep at the tool's centre line, which no cell centre is on.
    assert!(report.rapid_hits.iter().all(|h| (h.depth - 0.5).abs() < 1e-3), "{:?}", report.rapid_hits);
    assert_eq!(report.moves, 9);
    // The lift did cut its hole.
    assert!((zmap.height(100, 100) - zmap.range().0).abs() < 1e-9 && zmap.range().0 < -1.99);
}

#[test]
fn stock_around_a_program() {
    let moves = vec![
        rapid([-500.0, -500.0, 100.0], [2.0, 3.0, 5.0], 1),
        feed([2.0, 3.0, 5.0], [2.0, 3.0, -1.0]),
        feed([2.0, 3.0, -1.0], [12.0, 8.0, -1.0]),
    ];
    let s = Stock::around(&Toolpath::from(moves.clone()), &tool("ball:6")).unwrap();
    // The top is the feed that moves in X or Y, not the plunge's start.
    assert_eq!(s, stock(-1.0, 0.0, 15.0, 11.0, -1.0));
    // Vertical feeds only (a drilling program): their highest point.
    let s = Stock::around(&Toolpath::from(moves[..2].to_vec()), &tool("ball:6")).unwrap();
    assert_eq!(s, stock(-1.0, 0.0, 5.0, 6.0, 5.0));
}

#[test]
fn a_comparison_with_the_plane_finds_the_cusp_as_material_left() {
    let (r, p) = (3.0, 1.0);
    let moves: Vec<Move> = (0..6).map(|k| feed([0.0, k as f64 * p, -1.0], [10.0, k as f64 * p, -1.0])).collect();
    let zmap = run(moves, &tool("ball:6"), stock(2.0, 1.0 - 0.005, 8.0, 4.005, 0.0), 0.01);
    let plane = [
        [[0.0, 0.0, -1.0], [10.0, 0.0, -1.0], [10.0, 6.0, -1.0]],
        [[0.0, 0.0, -1.0], [10.0, 6.0, -1.0], [0.0, 6.0, -1.0]],
    ];
    let target = target_heights(&zmap, plane);
    let c = compare(&zmap, &target, 8);
    let h = r - (r * r - 0.25f64).sqrt();
    assert_eq!(c.missing, 0);
    assert!((c.max_left - h).abs() <= NM + 1e-9, "{}", c.max_left);
    assert!(c.max_gouge <= NM && c.range.0 >= -NM);
    assert_eq!(c.histogram.counts.iter().sum::<u64>() as usize, c.compared);
    assert!(c.mean_abs_dev > 0.0 && c.mean_abs_dev < h);
    // The same plane raised by 0.01: everything is a gouge of up to 0.01.
    let raised: Vec<f64> = target.iter().map(|t| t + 0.01).collect();
    let c = compare(&zmap, &raised, 8);
    assert!((c.max_gouge - 0.01).abs() <= NM + 1e-9, "{}", c.max_gouge);
}

#[test]
fn bad_input_is_a_clear_error() {
    let box_ = stock(0.0, 0.0, 10.0, 10.0, 0.0);
    for res in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = ZMap::new(&box_, &SimOptions::new(res)).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Resolution, "{e}");
        assert!(e.to_string().contains("resolution"));
    }
    let e = ZMap::new(&stock(0.0, 0.0, 1e5, 1e5, 0.0), &SimOptions::new(0.001)).unwrap_err();
    assert_eq!(e.kind, ErrorKind::TooManyCells);
    let text = e.to_string();
    assert!(text.contains("100000000 × 100000000 = 10000000000000000 cells"), "{text}");
    assert!(ZMap::new(&stock(5.0, 0.0, 1.0, 10.0, 0.0), &SimOptions::new(0.1)).is_err());
    assert!(ZMap::new(&stock(0.0, 0.0, 10.0, f64::NAN, 0.0), &SimOptions::new(0.1)).is_err());

    let options = SimOptions::new(0.5);
    let mut zmap = ZMap::new(&box_, &options).unwrap();
    let c = tool("ball:2");
    assert_eq!(simulate(&Toolpath::default(), &c, &mut zmap, &options).unwrap_err().kind, ErrorKind::EmptyToolpath);
    let dwell = Move { kind: MoveKind::Dwell(1.0), ..Move::default() };
    assert_eq!(
        simulate(&Toolpath::from(vec![dwell]), &c, &mut zmap, &options).unwrap_err().kind,
        ErrorKind::EmptyToolpath
    );
    assert_eq!(Stock::around(&Toolpath::default(), &c).unwrap_err().kind, ErrorKind::EmptyToolpath);
    let mut bad = feed([1.0, 1.0, 0.0], [2.0, 2.0, 0.0]);
    bad.end.y = f64::NAN;
    bad.line = 12;
    let e = simulate(&Toolpath::from(vec![bad]), &c, &mut zmap, &options).unwrap_err();
    assert_eq!(e.kind, ErrorKind::NonFinite);
    assert_eq!(e.to_string(), "move 0 (line 12) has a coordinate that is not a finite number");
    assert!(zmap.nm.iter().all(|z| *z == 0));
}
