//! `shorten`: on random paths, the merged path stays within the tolerance
//! of the original both ways, keeps its ends, and never has more moves.

use std::f64::consts::TAU;

use kezuri_cam::shorten::{shorten, ShortenOptions};
use kezuri_geom::{Arc, Axes, Move, MoveKind, Plane, Toolpath};
use proptest::prelude::*;

fn at(p: [f64; 3]) -> Axes {
    Axes { x: p[0], y: p[1], z: p[2], ..Axes::ZERO }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn segment_distance(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab = sub(b, a);
    let ap = sub(p, a);
    let len2 = dot(ab, ab);
    let t = if len2 > 0.0 { (dot(ap, ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
    let d = [ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2]];
    dot(d, d).sqrt()
}

/// Distance from `p` to the curve of move `m` (straight, or an arc in XY
/// at constant Z).
fn move_distance(p: [f64; 3], m: &Move) -> f64 {
    match m.kind {
        MoveKind::Arc(arc) => {
            let (s, e) = (m.start.xyz(), m.end.xyz());
            let c = arc.center;
            let angle = |q: [f64; 3]| (q[1] - c[1]).atan2(q[0] - c[0]);
            let raw = if arc.ccw { angle(p) - angle(s) } else { angle(s) - angle(p) };
            let phi = raw.rem_euclid(TAU);
            let ends = segment_distance(p, s, s).min(segment_distance(p, e, e));
            if phi <= arc.sweep(m.start, m.end) {
                let radial = (p[0] - c[0]).hypot(p[1] - c[1]) - arc.radius(m.start);
                radial.hypot(p[2] - s[2]).min(ends)
            } else {
                ends
            }
        }
        _ => segment_distance(p, m.start.xyz(), m.end.xyz()),
    }
}

/// Points along a move, ends included.
fn samples(m: &Move, n: usize) -> Vec<[f64; 3]> {
    (0..=n)
        .map(|k| {
            let t = k as f64 / n as f64;
            match m.kind {
                MoveKind::Arc(arc) => arc.point_at(m.start, m.end, t).xyz(),
                _ => {
                    let (s, e) = (m.start.xyz(), m.end.xyz());
                    [s[0] + t * (e[0] - s[0]), s[1] + t * (e[1] - s[1]), s[2] + t * (e[2] - s[2])]
                }
            }
        })
        .collect()
}

/// Checks the merged path against the original: every merged move
/// replaces the original moves since the last merged move's line, up to
/// its own line (the test numbers the lines 1, 2, 3, …).
fn check(original: &Toolpath, merged: &Toolpath, tol: f64) -> Result<(), TestCaseError> {
    let slack = tol + 1e-9;
    prop_assert!(merged.moves.len() <= original.moves.len());
    prop_assert_eq!(merged.moves.first().map(|m| m.start), original.moves.first().map(|m| m.start));
    prop_assert_eq!(merged.moves.last().map(|m| m.end), original.moves.last().map(|m| m.end));
    let mut from = 0;
    for m in &merged.moves {
        let to = m.line as usize;
        prop_assert!(to > from, "lines go forward");
        let replaced = &original.moves[from..to];
        prop_assert_eq!(m.start, replaced[0].start);
        prop_assert_eq!(m.end, replaced[replaced.len() - 1].end);
        let same_kind = |o: &Move| match (o.kind, m.kind) {
            (MoveKind::Feed, MoveKind::Arc(_)) => true,
            (a, b) => a == b,
        };
        prop_assert!(replaced.iter().all(same_kind), "kinds kept");
        prop_assert!(replaced.iter().all(|o| o.feed == m.feed || o.kind == MoveKind::Rapid), "feeds kept");
        // Original → merged: vertices and points along every segment.
        for o in replaced {
            for p in samples(o, 8) {
                let d = move_distance(p, m);
                prop_assert!(d <= slack, "original point {:?} is {} from the merged move {:?}", p, d, m);
            }
        }
        // Merged → original.
        for p in samples(m, 64) {
            let d =
                replaced.iter().map(|o| segment_distance(p, o.start.xyz(), o.end.xyz())).fold(f64::INFINITY, f64::min);
            prop_assert!(d <= slack, "merged point {:?} is {} from the original moves", p, d);
        }
        from = to;
    }
    prop_assert_eq!(from, original.moves.len());
    Ok(())
}

/// A piece of a random path.
#[derive(Clone, Debug)]
enum Piece {
    /// Feeds along a random walk: steps, and how straight it goes.
    Walk(Vec<[f64; 3]>, u32),
    /// Feeds along a noisy circle at constant Z: radius, start angle, turn
    /// per point, points, noise per point.
    Circle(f64, f64, f64, Vec<[f64; 2]>, u32),
    /// A rapid.
    Rapid([f64; 3]),
    /// Feeds at one Z along X, as the relief paper's rows.
    Row(Vec<i8>, u32),
}

fn piece() -> impl Strategy<Value = Piece> {
    let step = (-1.0f64..1.0, -1.0f64..1.0, -0.3f64..0.3).prop_map(|(x, y, z)| [x, y, z]);
    prop_oneof![
        (proptest::collection::vec(step, 1..30), 1u32..4).prop_map(|(s, f)| Piece::Walk(s, f)),
        (
            1.0f64..30.0,
            0.0f64..TAU,
            -0.3f64..0.3,
            proptest::collection::vec((-1.0f64..1.0, -1.0f64..1.0).prop_map(|(a, b)| [a, b]), 3..60),
            1u32..4
        )
            .prop_map(|(r, a, d, n, f)| Piece::Circle(r, a, d, n, f)),
        (-50.0f64..50.0, -50.0f64..50.0, 0.0f64..10.0).prop_map(|(x, y, z)| Piece::Rapid([x, y, z])),
        (proptest::collection::vec(-3i8..3, 1..40), 1u32..4).prop_map(|(z, f)| Piece::Row(z, f)),
    ]
}

fn build(pieces: &[Piece], noise: f64) -> Toolpath {
    let mut path = Toolpath::default();
    let push = |kind: MoveKind, to: [f64; 3], feed: f64, path: &mut Toolpath| {
        let line = path.moves.len() as u32 + 1;
        let start = path.moves.last().map_or(at([0.0, 0.0, 5.0]), |m| m.end);
        path.push(Move { kind, start, end: at(to), feed, line, ..Move::default() });
    };
    let here = |path: &Toolpath| path.moves.last().map_or([0.0, 0.0, 5.0], |m| m.end.xyz());
    for p in pieces {
        match p {
            Piece::Walk(steps, f) => {
                // A straight stretch now and then: the same step again.
                for (k, s) in steps.iter().enumerate() {
                    let s = if k % (*f as usize + 1) == 0 { *s } else { steps[k - 1] };
                    let h = here(&path);
                    push(MoveKind::Feed, [h[0] + s[0], h[1] + s[1], h[2] + s[2]], f64::from(*f) * 100.0, &mut path);
                }
            }
            Piece::Circle(r, a0, turn, jitter, f) => {
                let h = here(&path);
                let c = [h[0] - r * a0.cos(), h[1] - r * a0.sin()];
                for (k, j) in jitter.iter().enumerate() {
                    let a = a0 + turn * (k + 1) as f64;
                    let rr = r + j[0] * noise;
                    let z = h[2] + if k + 1 == jitter.len() { 0.0 } else { j[1] * noise };
                    push(
                        MoveKind::Feed,
                        [c[0] + rr * a.cos(), c[1] + rr * a.sin(), z],
                        f64::from(*f) * 100.0,
                        &mut path,
                    );
                }
            }
            Piece::Rapid(to) => push(MoveKind::Rapid, *to, 0.0, &mut path),
            Piece::Row(zs, f) => {
                for z in zs {
                    let h = here(&path);
                    push(
                        MoveKind::Feed,
                        [h[0] + 0.39, h[1], f64::from(*z) * 0.6 - 2.4],
                        f64::from(*f) * 100.0,
                        &mut path,
                    );
                }
            }
        }
    }
    path
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn lines_stay_within_the_tolerance(pieces in proptest::collection::vec(piece(), 1..8), tol in 0.0f64..0.5) {
        let path = build(&pieces, 0.3 * tol);
        let merged = shorten(&path, &ShortenOptions { tolerance: tol, arcs: false });
        check(&path, &merged, tol)?;
        prop_assert!(merged.moves.iter().all(|m| !matches!(m.kind, MoveKind::Arc(_))));
    }

    #[test]
    fn arcs_stay_within_the_tolerance(pieces in proptest::collection::vec(piece(), 1..8), tol in 0.001f64..0.5) {
        let path = build(&pieces, 0.3 * tol);
        let merged = shorten(&path, &ShortenOptions { tolerance: tol, arcs: true });
        check(&path, &merged, tol)?;
    }
}

#[test]
fn a_polygon_on_a_circle_becomes_arcs() {
    let pieces = [Piece::Circle(10.0, 0.0, TAU / 200.0, vec![[0.0, 0.0]; 150], 1)];
    let path = build(&pieces, 0.0);
    let merged = shorten(&path, &ShortenOptions { tolerance: 0.01, arcs: true });
    assert!(merged.moves.iter().all(|m| matches!(m.kind, MoveKind::Arc(Arc { plane: Plane::Xy, ccw: true, .. }))));
    assert!(merged.moves.len() <= 2, "{}", merged.moves.len());
    let lines = shorten(&path, &ShortenOptions { tolerance: 0.01, arcs: false });
    assert!(lines.moves.len() > 10);
}

#[test]
fn seed_002_rows_merge_only_where_z_is_equal_at_zero_tolerance() {
    let pieces = [Piece::Row(vec![0, 0, 0, 1, 1, 1, 1, 0, 0], 1)];
    let path = build(&pieces, 0.0);
    let merged = shorten(&path, &ShortenOptions { tolerance: 0.0, arcs: false });
    // Down from the start, then three flats and the two steps between.
    assert_eq!(merged.moves.len(), 1 + 5);
    check(&path, &merged, 0.0).unwrap();
}

#[test]
fn nothing_merges_across_a_rapid_a_feed_change_or_a_bad_tolerance() {
    let pieces = [
        Piece::Walk(vec![[1.0, 0.0, 0.0]; 4], 1),
        Piece::Walk(vec![[1.0, 0.0, 0.0]; 4], 2),
        Piece::Rapid([10.0, 0.0, 5.0]),
        Piece::Rapid([20.0, 0.0, 5.0]),
        Piece::Walk(vec![[1.0, 0.0, 0.0]; 4], 2),
    ];
    let path = build(&pieces, 0.0);
    let merged = shorten(&path, &ShortenOptions { tolerance: 0.1, arcs: true });
    let kinds: Vec<(MoveKind, f64)> = merged.moves.iter().map(|m| (m.kind, m.feed)).collect();
    assert_eq!(
        kinds,
        [(MoveKind::Feed, 100.0), (MoveKind::Feed, 200.0), (MoveKind::Rapid, 0.0), (MoveKind::Feed, 200.0)]
    );
    for tol in [f64::NAN, -1.0, f64::INFINITY] {
        assert_eq!(shorten(&path, &ShortenOptions { tolerance: tol, arcs: true }), path);
    }
}
