//! Simulation with a measured tool: the envelope against a brute-force
//! oracle (a waist, a worn tip, a wavy profile), the grid against the
//! per-move envelope, a finely sampled ball against `ball:D`.

use kezuri_cam::sim::{simulate, simulate_tool, swept_height_tool, MeasuredTool, SimOptions, Stock, Tool, ZMap};
use kezuri_cam::Cutter;
use kezuri_geom::{Axes, Move, MoveKind, ToolProfile, Toolpath};

fn at(x: f64, y: f64, z: f64) -> Axes {
    Axes { x, y, z, ..Axes::ZERO }
}

fn feed(a: [f64; 3], b: [f64; 3]) -> Move {
    Move { kind: MoveKind::Feed, start: at(a[0], a[1], a[2]), end: at(b[0], b[1], b[2]), ..Move::default() }
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

/// A worn tip (flat at z 0.15 out to r 0.3) and a waist: from z 0.8 the
/// radius shrinks from 1.1 to 0.8 and is 1.1 again only at z 1.5.
fn waisted() -> (Vec<f64>, Vec<f64>) {
    (vec![0.15, 0.25, 0.5, 0.8, 1.0, 1.2, 1.4, 1.7, 2.0, 3.0], vec![0.3, 0.6, 0.9, 1.1, 0.9, 0.8, 1.0, 1.3, 1.5, 1.5])
}

/// Back to exactly the widest radius after a hidden stretch, then wider.
fn rejoined() -> (Vec<f64>, Vec<f64>) {
    (vec![0.05, 0.5, 0.8, 1.0, 1.5, 2.5], vec![0.2, 1.0, 0.7, 1.0, 1.4, 1.4])
}

/// A cone with a wavy flank: not convex, with many small pockets.
fn wavy() -> (Vec<f64>, Vec<f64>) {
    let z: Vec<f64> = (0..80).map(|i| 0.02 * i as f64).collect();
    let r = z.iter().map(|&z| 0.1 + 0.8 * z + 0.006 * (z * 37.0).sin() + 0.004 * (z * 91.0).cos()).collect();
    (z, r)
}

fn measured(z: &[f64], r: &[f64]) -> Tool {
    Tool::Measured(MeasuredTool::new(&ToolProfile::new(z.to_vec(), r.to_vec()).unwrap()))
}

/// The tool as a solid of revolution, sampled: heights every `dz` (and at
/// every sample), each with the widest radius at or below it. The lowest
/// point at distance `d` from the axis is the first height whose widest
/// radius reaches `d`.
struct Solid {
    z: Vec<f64>,
    widest: Vec<f64>,
    dz: f64,
}

impl Solid {
    fn new(z: &[f64], r: &[f64], dz: f64) -> Solid {
        let mut out = Solid { z: Vec::new(), widest: Vec::new(), dz };
        let mut most = 0.0f64;
        for i in 0..z.len() - 1 {
            let n = ((z[i + 1] - z[i]) / dz).ceil() as usize;
            for k in 0..n {
                let t = k as f64 / n as f64;
                most = most.max(r[i] + t * (r[i + 1] - r[i]));
                out.z.push(z[i] + t * (z[i + 1] - z[i]));
                out.widest.push(most);
            }
        }
        out.z.push(z[z.len() - 1]);
        out.widest.push(most.max(r[r.len() - 1]));
        out
    }

    fn height(&self, d: f64) -> Option<f64> {
        let i = self.widest.partition_point(|&w| w < d);
        (i < self.z.len()).then(|| self.z[i])
    }

    fn radius(&self) -> f64 {
        self.widest[self.widest.len() - 1]
    }
}

/// The steepest the lowest point rises with the distance: no steeper than
/// any stretch of the profile that widens.
fn steepest(z: &[f64], r: &[f64]) -> f64 {
    (1..z.len()).filter(|&i| r[i] > r[i - 1]).map(|i| (z[i] - z[i - 1]) / (r[i] - r[i - 1])).fold(0.0, f64::max)
}

/// The envelope by sampling the tip along the move: 4000 positions, then
/// 400 more around each one that could hide the minimum (but inside a
/// plateau). With its error
/// bound (for the sampling of the move; plus `dz` for the tool's).
fn oracle(solid: &Solid, a: [f64; 3], b: [f64; 3], x: f64, y: f64, steep: f64) -> (Option<f64>, f64) {
    let value = |t: f64| {
        let c = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])];
        solid.height((x - c[0]).hypot(y - c[1])).map(|h| c[2] + h).unwrap_or(f64::INFINITY)
    };
    let n = 4000;
    let coarse: Vec<f64> = (0..=n).map(|k| value(k as f64 / n as f64)).collect();
    let lipschitz = steep * (b[0] - a[0]).hypot(b[1] - a[1]) + (b[2] - a[2]).abs();
    let best = coarse.iter().copied().fold(f64::INFINITY, f64::min);
    let slack = lipschitz / n as f64;
    let mut refined = best;
    for (k, &v) in coarse.iter().enumerate() {
        // Inside a plateau (the flat tip) there is nothing to refine.
        let flat = k > 0 && k < n && coarse[k - 1] == v && coarse[k + 1] == v;
        if v <= best + slack && !flat {
            let (t0, t1) = ((k.max(1) - 1) as f64 / n as f64, ((k + 1).min(n)) as f64 / n as f64);
            for m in 0..=400 {
                refined = refined.min(value(t0 + (t1 - t0) * m as f64 / 400.0));
            }
        }
    }
    (refined.is_finite().then_some(refined), slack / 200.0 + 2.0 * solid.dz + 1e-9)
}

/// XY distance from `(x, y)` to the segment.
fn distance(a: [f64; 3], b: [f64; 3], x: f64, y: f64) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 { (((x - a[0]) * dx + (y - a[1]) * dy) / l2).clamp(0.0, 1.0) } else { 0.0 };
    (x - a[0] - t * dx).hypot(y - a[1] - t * dy)
}

fn check_against_oracle(name: &str, (z, r): (Vec<f64>, Vec<f64>), seed: u64) {
    let tool = measured(&z, &r);
    let solid = Solid::new(&z, &r, 2e-5);
    let steep = steepest(&z, &r);
    let radius = solid.radius();
    assert_eq!(tool.radius(), radius);
    let mut next = rng(seed);
    let mut compared = 0;
    for case in 0..36 {
        let a = [3.0 * next(), 3.0 * next(), next() - 0.5];
        let b = match case % 6 {
            // Level.
            0 | 1 => [3.0 * next(), 3.0 * next(), a[2]],
            // Gently sloped.
            2 => [3.0 * next(), 3.0 * next(), a[2] + 0.2 * (next() - 0.5)],
            // Steep, either way.
            3 => [3.0 * next(), 3.0 * next(), a[2] + 5.0 * (next() - 0.5)],
            // A plunge, down or up.
            4 => [a[0], a[1], a[2] + 2.0 * (next() - 0.5)],
            // Along an axis, sloped.
            _ => [a[0] + 2.0 * (next() - 0.5), a[1], a[2] + next() - 0.5],
        };
        for q in 0..30 {
            let (x, y) = if q < 3 {
                // On the segment's line, at its ends and midway.
                let t = q as f64 / 2.0;
                (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))
            } else {
                let (x0, x1) = (a[0].min(b[0]) - radius, a[0].max(b[0]) + radius);
                let (y0, y1) = (a[1].min(b[1]) - radius, a[1].max(b[1]) + radius);
                (x0 + (x1 - x0) * next(), y0 + (y1 - y0) * next())
            };
            let got = swept_height_tool(&tool, a, b, x, y);
            let (want, tol) = oracle(&solid, a, b, x, y, steep);
            match (got, want) {
                (Some(g), Some(w)) => {
                    // The oracle's samples are points of the envelope: never below it.
                    assert!(g <= w + 1e-9, "{name} {a:?}->{b:?} at ({x}, {y}): {g} above the sample {w}");
                    assert!(g >= w - tol, "{name} {a:?}->{b:?} at ({x}, {y}): {g} vs {w} (± {tol})");
                    compared += 1;
                }
                (None, None) => {}
                (g, w) => {
                    let d = distance(a, b, x, y);
                    assert!((d - radius).abs() < 1e-6, "{name} {a:?}->{b:?} at ({x}, {y}), d {d}: {g:?} vs {w:?}");
                }
            }
        }
    }
    assert!(compared > 500, "{name}: {compared}");
}

#[test]
fn a_waist_and_a_worn_tip_match_the_oracle() {
    check_against_oracle("waisted", waisted(), 3);
}

#[test]
fn a_stretch_rejoining_the_widest_radius_matches_the_oracle() {
    check_against_oracle("rejoined", rejoined(), 5);
}

#[test]
fn a_wavy_flank_matches_the_oracle() {
    check_against_oracle("wavy", wavy(), 9);
}

#[test]
fn the_worn_tip_cuts_less_deep_and_the_waist_leaves_a_ridge() {
    // A level line along X at z −1 under the waisted tool: on its axis the
    // tip at 0.15; at 1.1 off it the corner below the waist (0.8); just
    // beyond, the profile above the waist (1.5 and up).
    let (z, r) = waisted();
    let tool = measured(&z, &r);
    let line = feed([0.0, 0.0, -1.0], [10.0, 0.0, -1.0]);
    let h = |y: f64| swept_height_tool(&tool, line.start.xyz(), line.end.xyz(), 5.0, y).unwrap();
    assert_eq!(h(0.0), -0.85);
    assert_eq!(h(0.2), -0.85);
    assert!((h(1.1) - -0.2).abs() < 1e-12, "{}", h(1.1));
    assert!((h(1.1 + 1e-9) - 0.5).abs() < 1e-6, "{}", h(1.1 + 1e-9));
}

fn stock(x0: f64, y0: f64, x1: f64, y1: f64, top: f64) -> Stock {
    Stock { x0, y0, x1, y1, top }
}

#[test]
fn simulation_is_the_minimum_over_its_moves() {
    // Zig-zag rows of short collinear moves, level runs and sloped runs
    // (the narrowing of straight runs is at work), a plunge and a climb.
    let mut next = rng(11);
    for (name, (z, r)) in [("waisted", waisted()), ("wavy", wavy())] {
        let tool = measured(&z, &r);
        let mut moves = Vec::new();
        let mut p = [0.5, 1.0, -1.0];
        for row in 0..4 {
            for k in 0..10 {
                let dir = if row % 2 == 0 { 1.0 } else { -1.0 };
                let dz = if (row + k / 5) % 2 == 0 { 0.0 } else { 0.6 * next() - 0.3 };
                let q = [p[0] + dir * (0.2 + 0.6 * next()), p[1], (p[2] + dz).clamp(-2.0, -0.5)];
                moves.push(feed(p, q));
                p = q;
            }
            let q = [p[0], p[1] + 1.1, p[2]];
            moves.push(feed(p, q));
            p = q;
        }
        moves.push(feed(p, [p[0], p[1], -2.5]));
        moves.push(feed([p[0], p[1], -2.5], [p[0] - 3.0, p[1] - 4.0, 0.5]));
        let options = SimOptions::new(0.05);
        let mut zmap = ZMap::new(&stock(-2.0, -2.0, 9.0, 8.0, 0.0), &options).unwrap();
        simulate_tool(&Toolpath::from(moves.clone()), &tool, &mut zmap, &options).unwrap();
        let mut cut = 0;
        for j in 0..zmap.ny {
            for i in 0..zmap.nx {
                let [x, y] = zmap.centre(i, j);
                let want = moves
                    .iter()
                    .filter_map(|m| swept_height_tool(&tool, m.start.xyz(), m.end.xyz(), x, y))
                    .fold(0.0f64, f64::min);
                let got = zmap.height(i, j);
                assert!((got - want).abs() <= 0.5e-6 + 1e-12, "{name} at ({x}, {y}): {got} vs {want}");
                cut += usize::from(got < 0.0);
            }
        }
        assert!(cut > 5000, "{name}: {cut}");
    }
}

#[test]
fn a_rapid_into_the_stock_is_reported_with_the_measured_tool() {
    let (z, r) = waisted();
    let tool = measured(&z, &r);
    let rapid = Move { kind: MoveKind::Rapid, line: 7, ..feed([1.0, 5.0, -1.0], [9.0, 5.0, -1.0]) };
    let options = SimOptions::new(0.1);
    let mut zmap = ZMap::new(&stock(0.0, 0.0, 10.0, 10.0, 0.0), &options).unwrap();
    let report = simulate_tool(&Toolpath::from(vec![rapid]), &tool, &mut zmap, &options).unwrap();
    assert_eq!(report.rapid_hits.len(), 1);
    assert_eq!(report.rapid_hits[0].line, 7);
    // The tip where the tool did not stand already: 1 − 0.15 deep.
    assert!((report.rapid_hits[0].depth - 0.85).abs() < 1e-12, "{:?}", report.rapid_hits);
    // Straight down at the start: what it stood in already is no crash.
    let down = Move { kind: MoveKind::Rapid, ..feed([5.0, 5.0, -1.0], [5.0, 5.0, 3.0]) };
    let mut zmap = ZMap::new(&stock(0.0, 0.0, 10.0, 10.0, 0.0), &options).unwrap();
    let report = simulate_tool(&Toolpath::from(vec![down]), &tool, &mut zmap, &options).unwrap();
    assert!(report.rapid_hits.is_empty(), "{:?}", report.rapid_hits);
}

#[test]
fn a_finely_sampled_ball_cuts_as_the_ball_within_its_sagitta() {
    // ball:1 sampled at 1400 angles up to the equator, then its shank: an
    // inscribed polygon, between the ball and the ball shrunk by the
    // chords' sagitta δ (tip raised by δ).
    let (rb, n) = (0.5f64, 1400);
    let step = std::f64::consts::FRAC_PI_2 / n as f64;
    let mut z: Vec<f64> = (0..=n).map(|i| rb - rb * (i as f64 * step).cos()).collect();
    let mut r: Vec<f64> = (0..=n).map(|i| rb * (i as f64 * step).sin()).collect();
    z[n] = rb;
    r[n] = rb;
    z.push(rb + 1.0);
    r.push(rb);
    let tool = measured(&z, &r);
    let delta = rb * (1.0 - (step / 2.0).cos());

    // Level rows along Y, a wavy sloped row along X, a plunge, a slanted
    // descent.
    let mut moves = Vec::new();
    for k in 0..6 {
        let x = 0.3 + 0.23 * k as f64;
        moves.push(feed([x, 0.2, -0.3], [x, 1.8, -0.3]));
    }
    let mut p = [0.1, 1.0, -0.2];
    for k in 1..=40 {
        let x = 0.1 + 0.045 * k as f64;
        let q = [x, 1.0 + 0.2 * (x * 3.0).sin(), -0.2 - 0.25 * (x * 2.0).sin().abs()];
        moves.push(feed(p, q));
        p = q;
    }
    moves.push(feed([1.5, 0.5, 0.2], [1.5, 0.5, -0.45]));
    moves.push(feed([0.2, 1.9, 0.1], [1.9, 0.1, -0.5]));
    let raised: Vec<Move> = moves
        .iter()
        .map(|m| feed([m.start.x, m.start.y, m.start.z + delta], [m.end.x, m.end.y, m.end.z + delta]))
        .collect();

    let options = SimOptions::new(0.01);
    let box_ = stock(-0.5, -0.5, 2.5, 2.5, 0.0);
    let run = |moves: &[Move], tool: &Tool| {
        let mut zmap = ZMap::new(&box_, &options).unwrap();
        simulate_tool(&Toolpath::from(moves.to_vec()), tool, &mut zmap, &options).unwrap();
        zmap
    };
    let ball: Cutter = "ball:1".parse().unwrap();
    let mut outer = ZMap::new(&box_, &options).unwrap();
    simulate(&Toolpath::from(moves.clone()), &ball, &mut outer, &options).unwrap();
    let small: Cutter = format!("ball:{}", 2.0 * (rb - delta)).parse().unwrap();
    let inner = run(&raised, &Tool::Cutter(small));
    let got = run(&moves, &tool);
    let mut most = 0.0f64;
    for c in 0..got.cells() {
        let (o, g, i) = (outer.height_at(c), got.height_at(c), inner.height_at(c));
        // Each kept to the nanometre: the order holds to one.
        assert!(o <= g + 1e-6, "cell {c}: ball {o} below the samples {g}");
        assert!(g <= i + 1e-6, "cell {c}: samples {g} below the small ball {i}");
        most = most.max(g - o);
    }
    // Where the contact is not on the steep rim, the sagitta (1.6e-7) is
    // all: the deepest cut is the same.
    assert!((got.range().0 - outer.range().0).abs() <= 2.0 * delta, "{:?} vs {:?}", got.range(), outer.range());
    assert!(most < 2e-3, "{most}");
}
