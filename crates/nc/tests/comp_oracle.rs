//! Cutter compensation against a brute-force oracle: sampled tool-centre
//! points measured against the programmed contour. And a property test:
//! random paths never panic and never make a non-finite point.

use kezuri_geom::{Arc, Axes, Move, MoveKind, Plane};
use kezuri_nc::interp::comp::{compensate, Approach, Comp, Rules, Side};
use proptest::prelude::*;

const ALL_RULES: [Rules; 3] =
    [Rules::Fanuc { startup: Approach::A }, Rules::Fanuc { startup: Approach::B }, Rules::LinuxCnc];

fn at(x: f64, y: f64) -> Axes {
    Axes { x, y, ..Axes::ZERO }
}

/// Straight moves through `pts`, numbered from line 1.
fn polyline(pts: &[(f64, f64)]) -> Vec<Move> {
    pts.windows(2)
        .enumerate()
        .map(|(k, w)| Move {
            kind: MoveKind::Feed,
            start: at(w[0].0, w[0].1),
            end: at(w[1].0, w[1].1),
            line: k as u32 + 1,
            ..Move::default()
        })
        .collect()
}

/// Distance from `p` to segment `a`–`b`.
fn seg_dist(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let t = (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
    (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dy)
}

/// Distance from `p` to the closed contour through `corners`.
fn contour_dist(p: (f64, f64), corners: &[(f64, f64)]) -> f64 {
    (0..corners.len()).map(|k| seg_dist(p, corners[k], corners[(k + 1) % corners.len()])).fold(f64::INFINITY, f64::min)
}

fn point(m: &Move, t: f64) -> (f64, f64) {
    let p = match m.kind {
        MoveKind::Arc(a) => a.point_at(m.start, m.end, t),
        _ => Axes { x: m.start.x + (m.end.x - m.start.x) * t, y: m.start.y + (m.end.y - m.start.y) * t, ..m.start },
    };
    (p.x, p.y)
}

/// Compensates a closed contour entered at `entry` from `approach_from`
/// and left back there, and checks every sampled tool-centre point is at
/// least `r` from the contour, and the middle of every compensated edge
/// exactly `r`.
fn check_contour(corners: &[(f64, f64)], entry: (f64, f64), from: (f64, f64), side: Side, r: f64, rules: Rules) {
    let mut pts = vec![from, entry];
    // From the entry point on the first edge round the contour and back.
    pts.extend(corners.iter().skip(1).copied());
    pts.push(corners[0]);
    pts.push(entry);
    pts.push(from);
    let moves = polyline(&pts);
    let n = moves.len();
    let tags: Vec<_> = (0..n).map(|k| (k < n - 1).then_some(Comp { side, radius: r, plane: Plane::Xy })).collect();
    let out = compensate(&moves, &tags, rules).unwrap_or_else(|e| panic!("{rules:?} r={r}: {e}"));
    let mut edges_checked = 0;
    for m in &out {
        for k in 0..=64 {
            let p = point(m, f64::from(k) / 64.0);
            let d = contour_dist(p, corners);
            assert!(d >= r - 1e-9, "{rules:?} r={r}: {p:?} of {m:?} is {d} from the contour");
        }
        // A compensated edge: a straight move of a contour line (not the
        // approach or the leave) parallel to its programmed edge, its middle
        // beside that edge.
        let src = &moves[m.line as usize - 1];
        let parallel = ((m.end.x - m.start.x) * (src.end.y - src.start.y)
            - (m.end.y - m.start.y) * (src.end.x - src.start.x))
            .abs()
            < 1e-9;
        let mid = point(m, 0.5);
        let (a, b) = ((src.start.x, src.start.y), (src.end.x, src.end.y));
        let along =
            ((mid.0 - a.0) * (b.0 - a.0) + (mid.1 - a.1) * (b.1 - a.1)) / ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2));
        let over_edge = (0.0..=1.0).contains(&along);
        if m.line >= 2 && (m.line as usize) < n && m.kind == MoveKind::Feed && parallel && over_edge && m.start != m.end
        {
            let d = contour_dist(mid, corners);
            assert!((d - r).abs() < 1e-9, "{rules:?} r={r}: middle of {m:?} is {d} from the contour");
            edges_checked += 1;
        }
    }
    assert!(edges_checked >= corners.len(), "{rules:?} r={r}: {edges_checked} edges checked in {out:#?}");
}

#[test]
fn rectangle_outside_stays_r_from_the_contour() {
    // Counter-clockwise outside contour, G42 puts the tool outside.
    let rect = [(0.0, 0.0), (40.0, 0.0), (40.0, 20.0), (0.0, 20.0)];
    for rules in ALL_RULES {
        for r in [0.5, 1.0, 3.0, 6.35] {
            check_contour(&rect, (20.0, 0.0), (20.0, -15.0), Side::Right, r, rules);
        }
    }
}

#[test]
fn square_pocket_stays_r_from_the_walls() {
    // Counter-clockwise pocket, G41 puts the tool inside, entered from the
    // middle.
    let square = [(0.0, 0.0), (40.0, 0.0), (40.0, 40.0), (0.0, 40.0)];
    for rules in ALL_RULES {
        for r in [0.5, 1.0, 3.0, 6.35] {
            check_contour(&square, (20.0, 0.0), (20.0, 20.0), Side::Left, r, rules);
        }
    }
}

#[test]
fn triangle_with_acute_outside_corners() {
    // Acute outside corners: Fanuc's two extra vectors, LinuxCNC's arcs.
    let tri = [(0.0, 0.0), (30.0, 0.0), (5.0, 8.0)];
    for rules in ALL_RULES {
        for r in [0.5, 2.0] {
            check_contour(&tri, (10.0, 0.0), (10.0, -10.0), Side::Right, r, rules);
        }
    }
}

/// A random path: straight moves and arcs through random points, now and
/// then a plunge, compensated from the second move to the one before last.
fn path_strategy() -> impl Strategy<Value = (Vec<Move>, Vec<Option<Comp>>, Rules)> {
    let step = (-50.0..50.0f64, -50.0..50.0f64, prop::option::of(-2.0..2.0f64), prop::bool::weighted(0.15));
    (
        prop::collection::vec(step, 3..10),
        -6.0..6.0f64,
        prop::bool::ANY,
        0..3usize,
        prop::sample::select(vec![Plane::Xy, Plane::Zx]),
    )
        .prop_map(|(steps, radius, left, rules, plane)| {
            let (i, j, n) = plane.axes();
            let mut moves = Vec::new();
            let mut cur = [0.0f64; 3];
            for (u, v, bulge, plunge) in steps {
                if plunge {
                    let mut end = cur;
                    end[n] -= 1.0;
                    moves.push(Move {
                        start: Axes { x: cur[0], y: cur[1], z: cur[2], ..Axes::ZERO },
                        end: Axes { x: end[0], y: end[1], z: end[2], ..Axes::ZERO },
                        ..Move::default()
                    });
                    cur = end;
                }
                let mut end = cur;
                end[i] = u;
                end[j] = v;
                let start_a = Axes { x: cur[0], y: cur[1], z: cur[2], ..Axes::ZERO };
                let end_a = Axes { x: end[0], y: end[1], z: end[2], ..Axes::ZERO };
                let kind = match bulge {
                    // Centre on the chord's bisector, `h` chords off it.
                    Some(h) => {
                        let (mu, mv) = ((cur[i] + u) / 2.0, (cur[j] + v) / 2.0);
                        let (du, dv) = (u - cur[i], v - cur[j]);
                        let mut c = cur;
                        c[i] = mu - dv * h;
                        c[j] = mv + du * h;
                        MoveKind::Arc(Arc { center: c, plane, ccw: h > 0.0, turns: 0 })
                    }
                    None => MoveKind::Feed,
                };
                moves.push(Move { kind, start: start_a, end: end_a, ..Move::default() });
                cur = end;
            }
            let side = if left { Side::Left } else { Side::Right };
            let comp = Comp { side, radius, plane };
            let last = moves.len() - 1;
            let tags = (0..moves.len()).map(|k| (k >= 1 && k < last).then_some(comp)).collect();
            (moves, tags, ALL_RULES[rules])
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn never_panics_never_nan((moves, tags, rules) in path_strategy()) {
        match compensate(&moves, &tags, rules) {
            Ok(out) => {
                prop_assert!(out.len() >= moves.len());
                for (k, m) in out.iter().enumerate() {
                    let mut vals = m.start.to_array().to_vec();
                    vals.extend(m.end.to_array());
                    if let MoveKind::Arc(a) = m.kind {
                        vals.extend(a.center);
                    }
                    prop_assert!(vals.iter().all(|v| v.is_finite()), "move {} not finite: {:?}", k, m);
                    if k > 0 {
                        prop_assert_eq!(m.start, out[k - 1].end);
                    }
                }
            }
            Err(e) => {
                prop_assert!(e.move_index().is_some_and(|k| k < moves.len()));
                prop_assert!(!e.message.is_empty());
            }
        }
    }
}

#[test]
fn random_paths_mostly_compensate() {
    // The property above would hold vacuously if every random path were
    // refused: count the ones that compensate.
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let strategy = path_strategy();
    let (mut ok, total) = (0, 500);
    for _ in 0..total {
        let (moves, tags, rules) = strategy.new_tree(&mut runner).unwrap().current();
        ok += usize::from(compensate(&moves, &tags, rules).is_ok());
    }
    eprintln!("{ok} of {total} random paths compensated");
    assert!(ok * 5 >= total, "{ok} of {total} compensated");
}
