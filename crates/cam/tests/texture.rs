//! The texture paper's random texture baked into toolpaths: segments, depths, what passes
//! unchanged, the distributions.

use kezuri_cam::texture::{bake, Dist, TextureOptions};
use kezuri_cam::ErrorKind;
use kezuri_geom::{Arc, Axes, AxisSet, Move, MoveKind, Plane, Toolpath};

fn at(x: f64, y: f64, z: f64) -> Axes {
    Axes { x, y, z, ..Axes::ZERO }
}

fn feed(a: Axes, b: Axes) -> Move {
    Move { kind: MoveKind::Feed, start: a, end: b, feed: 300.0, ..Move::default() }
}

/// A path through `points`, cutting.
fn polyline(points: &[Axes]) -> Toolpath {
    points.windows(2).map(|w| feed(w[0], w[1])).collect::<Vec<_>>().into()
}

fn paper(seed: u64) -> TextureOptions {
    TextureOptions { seed, ..TextureOptions::default() }
}

/// Offsets the options allow: multiples of the quantum within the spread.
fn allowed(o: &TextureOptions, offset: f64) -> bool {
    let k = offset / o.quantum;
    (k - k.round()).abs() < 1e-9 && offset.abs() <= o.spread + 1e-9
}

#[test]
fn a_long_move_is_cut_into_strokes_of_the_segment() {
    let o = paper(1);
    let t = bake(&polyline(&[at(0., 0., 0.), at(100., 0., 0.)]), &o).unwrap();
    let ends: Vec<Axes> = t.toolpath.moves.iter().map(|m| m.end).collect();
    assert_eq!(ends.len(), 5, "{ends:?}");
    for (k, e) in ends.iter().enumerate() {
        assert!((e.x - 20.0 * (k + 1) as f64).abs() < 1e-9 && e.y == 0.0);
        assert!(allowed(&o, e.z), "{}", e.z);
    }
    // The first stroke starts where the tool is; each starts where the last ended.
    assert_eq!(t.toolpath.moves[0].start, at(0., 0., 0.));
    for w in t.toolpath.moves.windows(2) {
        assert_eq!(w[0].end, w[1].start);
    }
    assert_eq!((t.moves, t.knots), (1, 6));
}

#[test]
fn short_moves_are_measured_together_in_any_direction() {
    // 0.5 mm moves on a diagonal (3-4-5) and a dome-like Z: 50 mm of XY travel.
    let points: Vec<Axes> = (0..=100)
        .map(|k| {
            let s = k as f64 * 0.5;
            at(0.6 * s, 0.8 * s, -0.01 * (s - 25.0) * (s - 25.0))
        })
        .collect();
    let path = polyline(&points);
    let o = TextureOptions { segment: 10.0, ..paper(3) };
    let t = bake(&path, &o).unwrap();
    // Knots at 10, 20, 30, 40, 50 mm fall on move ends (every 20th move): no splits.
    assert_eq!(t.toolpath.moves.len(), 100);
    let mut offsets = Vec::new();
    for (m, p) in t.toolpath.moves.iter().zip(&path.moves) {
        assert!((m.end.x - p.end.x).abs() < 1e-12 && (m.end.y - p.end.y).abs() < 1e-12);
        offsets.push(m.end.z - p.end.z);
    }
    // At the knots the offsets are allowed depths; between, they run linearly.
    for k in 1..=5 {
        assert!(allowed(&o, offsets[20 * k - 1]), "knot {k}: {}", offsets[20 * k - 1]);
    }
    for k in 0..100 {
        let knot = 20 * (k / 20 + 1) - 1;
        let before = if k < 20 { 0.0 } else { offsets[knot - 20] };
        let t = ((k % 20) + 1) as f64 / 20.0;
        let want = before + (offsets[knot] - before) * t;
        assert!((offsets[k] - want).abs() < 1e-9, "move {k}: {} vs {want}", offsets[k]);
    }
    // Not all the same: the texture is there.
    assert!((1..=5).any(|k| offsets[20 * k - 1] != offsets[19]));
}

#[test]
fn rapids_arcs_and_z_only_moves_pass_as_written() {
    let arc = Arc { center: [10.0, 5.0, 0.0], plane: Plane::Xy, ccw: true, turns: 0 };
    let mut moves = vec![feed(at(0., 0., 0.), at(50., 0., 0.))];
    // An arc that names no Z (it stays at the stroke's depth).
    let mut a = Move {
        kind: MoveKind::Arc(arc),
        start: at(50., 0., 0.),
        end: at(50., 10., 0.),
        ..feed(at(0., 0., 0.), at(0., 0., 0.))
    };
    a.named = AxisSet(0b011);
    moves.push(a);
    // A Z-only move, a rapid up, across, and a plunge.
    moves.push(feed(at(50., 10., 0.), at(50., 10., -1.)));
    moves.push(Move { kind: MoveKind::Rapid, ..feed(at(50., 10., -1.), at(50., 10., 5.)) });
    moves.push(Move { kind: MoveKind::Rapid, ..feed(at(50., 10., 5.), at(0., 30., 5.)) });
    let path: Toolpath = moves.into();
    let t = bake(&path, &paper(5)).unwrap();
    let out = &t.toolpath.moves;
    let stroke_end = out[2].end; // 50 mm: strokes at 20, 40, 50
    assert_eq!(out.len(), 3 + 4);
    let arc_out = &out[3];
    assert!(matches!(arc_out.kind, MoveKind::Arc(a) if a.center[..2] == [10.0, 5.0] && a.center[2] == stroke_end.z));
    assert_eq!((arc_out.start, arc_out.end), (stroke_end, at(50., 10., stroke_end.z)));
    assert_eq!(out[4].end, at(50., 10., -1.), "the Z-only move goes where it says");
    assert_eq!(out[5].end, at(50., 10., 5.));
    assert_eq!(out[6].end, at(0., 30., 5.));
    assert_eq!(t.moves, 1);
}

#[test]
fn base_depth_clamp_and_seeds() {
    let path = polyline(&[at(0., 0., 0.), at(400., 0., 0.)]);
    let o = TextureOptions { base: Some(-2.0), max_depth: Some(-2.5), ..paper(9) };
    let t = bake(&path, &o).unwrap();
    let zs: Vec<f64> = t.toolpath.moves.iter().map(|m| m.end.z).collect();
    assert_eq!(zs.len(), 20);
    assert!(zs.iter().all(|&z| (-2.5 - 1e-12..=-1.2 + 1e-12).contains(&z)), "{zs:?}");
    assert!(zs.iter().any(|&z| z == -2.5), "the clamp is reached: {zs:?}");
    let again = bake(&path, &o).unwrap();
    assert_eq!(zs, again.toolpath.moves.iter().map(|m| m.end.z).collect::<Vec<_>>());
    let other = bake(&path, &TextureOptions { seed: 10, ..o }).unwrap();
    assert_ne!(zs, other.toolpath.moves.iter().map(|m| m.end.z).collect::<Vec<_>>());
}

#[test]
fn the_step_range_keeps_successive_knots_apart() {
    let path = polyline(&[at(0., 0., 0.), at(20_000., 0., 0.)]);
    for dist in [Dist::Digits, Dist::Uniform, Dist::Normal] {
        let o = TextureOptions { step_range: Some([0.2, 1.6]), dist, ..paper(2) };
        let zs: Vec<f64> = bake(&path, &o).unwrap().toolpath.moves.iter().map(|m| m.end.z).collect();
        for w in zs.windows(2) {
            let step = (w[1] - w[0]).abs();
            assert!((0.2 - 1e-9..=1.6 + 1e-9).contains(&step), "{dist:?}: {} → {}", w[0], w[1]);
        }
    }
}

/// Counts of each offset over `n` knots.
fn histogram(o: &TextureOptions, n: usize) -> std::collections::BTreeMap<i64, usize> {
    let path = polyline(&[at(0., 0., 0.), at(o.segment * n as f64, 0., 0.)]);
    let t = bake(&path, o).unwrap();
    let mut h = std::collections::BTreeMap::new();
    for m in &t.toolpath.moves {
        *h.entry((m.end.z / o.quantum).round() as i64).or_insert(0) += 1;
    }
    h
}

/// Pearson's χ² of `counts` against the probabilities `p` (by key).
fn chi_square(counts: &std::collections::BTreeMap<i64, usize>, p: impl Fn(i64) -> f64) -> f64 {
    let n: usize = counts.values().sum();
    (-10..=10)
        .filter(|&k| p(k) > 0.0)
        .map(|k| {
            let e = p(k) * n as f64;
            let o = *counts.get(&k).unwrap_or(&0) as f64;
            (o - e) * (o - e) / e
        })
        .sum()
}

#[test]
fn digits_fall_on_nine_depths_the_base_twice_as_likely() {
    // 10,000 segments; 8 degrees of freedom: χ² beyond 26.1 has p < 0.001.
    for seed in [1, 2, 3] {
        let h = histogram(&paper(seed), 10_000);
        assert_eq!(h.keys().copied().collect::<Vec<_>>(), (-4..=4).collect::<Vec<_>>(), "nine depths");
        let chi = chi_square(&h, |k| match k {
            0 => 0.2,
            -4..=4 => 0.1,
            _ => 0.0,
        });
        assert!(chi < 26.1, "seed {seed}: χ² = {chi:.1}, {h:?}");
        // …and it can fail: against a flat nine-way split it does.
        let flat = chi_square(&h, |k| if (-4..=4).contains(&k) { 1.0 / 9.0 } else { 0.0 });
        assert!(flat > 100.0, "{flat}");
    }
}

#[test]
fn uniform_normal_and_smooth_stay_within_the_spread() {
    for dist in [Dist::Uniform, Dist::Normal, Dist::Smooth] {
        let o = TextureOptions { dist, ..paper(4) };
        let h = histogram(&o, 5_000);
        assert!(h.keys().all(|k| (-4..=4).contains(k)), "{dist:?}: {h:?}");
        assert!(h.len() >= 5, "{dist:?} uses the spread: {h:?}");
    }
    let h = histogram(&TextureOptions { dist: Dist::Uniform, ..paper(4) }, 9_000);
    assert!(chi_square(&h, |k| if (-4..=4).contains(&k) { 1.0 / 9.0 } else { 0.0 }) < 26.1, "{h:?}");
}

#[test]
fn smooth_noise_relates_neighbouring_passes_either_way_and_successive_strokes() {
    // Zig-zag: a pass along +X, the next 3 mm over (the paper's step) back
    // along -X, against one 300 mm away; depths compared at the same X.
    let o = TextureOptions { dist: Dist::Smooth, quantum: 0.0, ..paper(8) };
    let pass = |y: f64, forward: bool| {
        let (a, b) = if forward { (0.0, 2000.0) } else { (2000.0, 0.0) };
        let t = bake(&polyline(&[at(a, y, 0.), at(b, y, 0.)]), &o).unwrap();
        let mut v: Vec<(f64, f64)> = t.toolpath.moves.iter().map(|m| (m.end.x, m.end.z)).collect();
        v.sort_by(|p, q| p.0.total_cmp(&q.0));
        v.into_iter().filter(|p| p.0 > 20.0 && p.0 < 1990.0).map(|p| p.1).collect::<Vec<_>>()
    };
    let diff = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(p, q)| (p - q).abs()).sum::<f64>() / a.len() as f64;
    let (a, near, far) = (pass(0.0, true), pass(3.0, false), pass(300.0, false));
    assert_eq!(a.len(), near.len());
    assert!(diff(&a, &near) < 0.2 * diff(&a, &far), "{} vs {}", diff(&a, &near), diff(&a, &far));
    // Successive strokes are related: closer than strokes 500 mm apart.
    let step = |k: usize| diff(&a[..a.len() - k], &a[k..]);
    assert!(step(1) < 0.5 * step(25), "{} vs {}", step(1), step(25));
}

#[test]
fn a_step_range_the_quantised_depths_cannot_meet_is_refused() {
    let path = polyline(&[at(0., 0., 0.), at(10., 0., 0.)]);
    // Depths are multiples of 0.2: no two differ by 0.1–0.15.
    let o = TextureOptions { step_range: Some([0.1, 0.15]), ..paper(1) };
    assert!(
        matches!(bake(&path, &o), Err(e) if e.kind == ErrorKind::Option && e.message.contains("--step-range 0.1,0.15"))
    );
    // From ±0.8 nothing is 1.7 away within ±0.9 in steps of 0.2 (uniform): refused too.
    let o = TextureOptions { spread: 0.9, step_range: Some([1.7, 2.0]), dist: Dist::Uniform, ..paper(1) };
    assert!(bake(&path, &o).is_err());
    assert!(bake(&path, &TextureOptions { step_range: Some([0.2, 1.6]), ..paper(1) }).is_ok());
}

#[test]
fn offsets_never_leave_the_spread_whatever_the_quantum() {
    for (spread, quantum) in [(0.8, 0.3), (0.5, 0.2), (1.0, 0.4)] {
        for dist in [Dist::Digits, Dist::Uniform, Dist::Normal] {
            let o = TextureOptions { spread, quantum, dist, ..paper(6) };
            let path = polyline(&[at(0., 0., 0.), at(2000., 0., 0.)]);
            for m in &bake(&path, &o).unwrap().toolpath.moves {
                assert!(m.end.z.abs() <= spread + 1e-9, "{dist:?} {spread} {quantum}: {}", m.end.z);
            }
        }
    }
}

#[test]
fn bad_options_are_refused_with_their_name() {
    let path = polyline(&[at(0., 0., 0.), at(10., 0., 0.)]);
    for (o, words) in [
        (TextureOptions { segment: 0.0, ..paper(1) }, "--segment"),
        (TextureOptions { spread: -0.5, ..paper(1) }, "--spread"),
        (TextureOptions { quantum: 1.0, ..paper(1) }, "--quantum"),
        (TextureOptions { step_range: Some([2.0, 3.0]), ..paper(1) }, "--step-range"),
        (TextureOptions { step_range: Some([0.2, 1.6]), dist: Dist::Smooth, ..paper(1) }, "--step-range"),
        (TextureOptions { base: Some(f64::NAN), ..paper(1) }, "--base"),
    ] {
        match bake(&path, &o) {
            Err(e) if e.kind == ErrorKind::Option => assert!(e.message.contains(words), "{e}"),
            other => panic!("{o:?}: {other:?}"),
        }
    }
}
