//! Shortening a toolpath: fewer, longer moves within a tolerance.
//!
//! The relief paper's `auto_g2.exe` and `shorter.exe` merged consecutive moves at
//! equal Z to shrink a 1.7 MB program. [`shorten`] does that for any shape:
//! a run of consecutive moves of the same kind and state is replaced by the
//! fewest of its own points that keep the path within
//! [`ShortenOptions::tolerance`] of the original (Douglas–Peucker:
//! keep both ends, keep the point farthest from the chord while it is
//! farther than the tolerance, recurse on both halves). With
//! [`ShortenOptions::arcs`], runs of feeds are also fitted with arcs in the
//! XY plane at constant Z (`G02`/`G03`).
//!
//! # What stays
//! A run never crosses a change of move kind (a feed next to a rapid, an
//! arc, a dwell, a probe, a return), of feed, spindle, speed, coolant,
//! tool, frame or named axes, a gap (a move that does not start where the
//! last ended), or a move that turns a rotary axis. So every rapid, every
//! feed change and every tool change is where it was, the first point and
//! the last are kept exactly, and every kept point is one of the original
//! points. A merged move takes the state and the source line of the last
//! move it replaces. The move count never grows.
//!
//! # The guarantee, both ways
//! Every point of the original path is within the tolerance of the merged
//! move that replaced it, and every point of a merged move is within the
//! tolerance of the original moves it replaced (3-D distances; for lines,
//! plus [`ON_LINE`], a nanometre, so that a tolerance of 0 merges what is
//! collinear but for rounding):
//! - Lines: Douglas–Peucker keeps a chord only when every original point it
//!   replaces is within the tolerance of it. The tolerance band around a
//!   segment is convex, so the original segments between those points are
//!   inside it too; and the original path runs continuously from one end
//!   of the chord to the other, so each point of the chord has an original
//!   point projecting onto it, no farther than the original's distance to
//!   the chord's line.
//! - Arcs: for each original segment `P_k P_k+1`, with `e_k` the distance
//!   of `P_k` from the arc (radial and vertical) and `Δ_k` the angle the
//!   arc turns between their radial projections, every point of the
//!   segment is within `max(e_k, e_k+1)` of the chord of the arc between
//!   the projections, and every point of that chord within the sagitta
//!   `r(1 − cos(Δ_k/2))` of the arc, and the other way round. An arc is
//!   kept only when `sagitta + max(e_k, e_k+1)` is within the tolerance for
//!   every segment, the projections advance monotonically, it turns less
//!   than 1.9 π, and a straight chord would not do.
//!
//! Arcs are found greedily: from each point, the longest run of at least
//! four points (three moves, at most [`MAX_ARC_POINTS`]) that an arc through
//! its first, middle and last point fits, growing one point at a time; it
//! ends at a point of exactly the start's Z (points between may differ by
//! the tolerance), and the growing stops where the arc no longer fits or a
//! point leaves the start's Z by more than the tolerance, so a path whose
//! Z changes from point to point costs little to search.

use kezuri_geom::{Arc, Move, MoveKind, Plane, Toolpath};

/// How [`shorten`] merges.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShortenOptions {
    /// Largest distance between the merged path and the original, mm.
    pub tolerance: f64,
    /// Also fit arcs (XY plane, constant Z) to runs of feeds.
    pub arcs: bool,
}

/// A point this close to a chord (mm) is on it: a tolerance of 0 merges
/// points that are collinear but for floating-point rounding.
pub const ON_LINE: f64 = 1e-9;

/// Most points one fitted arc replaces (fitting costs the square of it).
pub const MAX_ARC_POINTS: usize = 2000;

/// The toolpath with runs of moves merged within the tolerance (see the
/// module documentation). A tolerance that is not a finite number ≥ 0
/// merges nothing.
///
/// ```
/// use kezuri_cam::shorten::{shorten, ShortenOptions};
/// use kezuri_geom::{Axes, Move, MoveKind, Toolpath};
/// let at = |x: f64, z: f64| Axes { x, z, ..Axes::ZERO };
/// // The relief paper's rows: one move per pixel, most at the same Z.
/// let zs = [-2.4, -2.4, -2.4, -1.8, -1.8, -2.4];
/// let mut path = Toolpath::default();
/// for (k, z) in zs.iter().enumerate() {
///     let start = path.moves.last().map_or(at(0.0, -2.4), |m: &Move| m.end);
///     path.push(Move { kind: MoveKind::Feed, start, end: at(0.39 * (k + 1) as f64, *z), feed: 600.0, ..Move::default() });
/// }
/// let short = shorten(&path, &ShortenOptions { tolerance: 0.001, arcs: false });
/// assert_eq!(short.moves.len(), 4);
/// assert_eq!(short.moves.last().unwrap().end, path.moves.last().unwrap().end);
/// ```
pub fn shorten(path: &Toolpath, options: &ShortenOptions) -> Toolpath {
    let tol = options.tolerance;
    if !(tol.is_finite() && tol >= 0.0) {
        return path.clone();
    }
    let moves = &path.moves;
    // Kept blocks sit between moves and stand for moves of their own: runs
    // break where a kept block sits, and its moves are left whole.
    let inside = path.covered();
    let mut barrier = vec![false; moves.len() + 1];
    for k in &path.kept {
        barrier[k.before.min(moves.len())] = true;
        barrier[(k.before + k.moves).min(moves.len())] = true;
    }
    let mut new_index = vec![0; moves.len() + 1];
    let mut out = Vec::with_capacity(moves.len());
    let mut i = 0;
    while i < moves.len() {
        new_index[i] = out.len();
        if inside[i] || !mergeable(&moves[i]) {
            out.push(moves[i]);
            i += 1;
            continue;
        }
        let mut j = i + 1;
        while j < moves.len() && !barrier[j] && same_run(&moves[j - 1], &moves[j]) {
            j += 1;
        }
        let run = &moves[i..j];
        if run.len() == 1 {
            out.push(run[0]);
        } else {
            merge_run(run, tol, options.arcs && run[0].kind == MoveKind::Feed, &mut out);
        }
        i = j;
    }
    new_index[moves.len()] = out.len();
    let kept = path.kept_in(&new_index);
    Toolpath { moves: out, frames: path.frames.clone(), unknown_start: path.unknown_start, kept }
}

/// Straight feeds and rapids that turn no rotary axis and move no U V W.
fn mergeable(m: &Move) -> bool {
    matches!(m.kind, MoveKind::Feed | MoveKind::Rapid)
        && m.start.a == m.end.a
        && m.start.b == m.end.b
        && m.start.c == m.end.c
        && m.start.uvw() == m.end.uvw()
        && m.start.to_array().iter().chain(&m.end.to_array()).all(|v| v.is_finite())
}

/// Whether `b` continues the run `a` is in.
fn same_run(a: &Move, b: &Move) -> bool {
    mergeable(b)
        && a.kind == b.kind
        && a.end == b.start
        && (a.kind == MoveKind::Rapid || a.feed == b.feed)
        && a.speed == b.speed
        && a.spindle == b.spindle
        && a.coolant == b.coolant
        && a.tool == b.tool
        && a.frame == b.frame
        && a.named == b.named
        && a.unknown == b.unknown
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Distance from `p` to the segment `a`–`b`.
fn segment_distance(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab = sub(b, a);
    let ap = sub(p, a);
    let len2 = dot(ab, ab);
    let t = if len2 > 0.0 { (dot(ap, ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
    let d = [ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2]];
    dot(d, d).sqrt()
}

/// Replaces the moves of one run, pushing the merged moves onto `out`.
fn merge_run(run: &[Move], tol: f64, arcs: bool, out: &mut Vec<Move>) {
    let points: Vec<[f64; 3]> = std::iter::once(run[0].start.xyz()).chain(run.iter().map(|m| m.end.xyz())).collect();
    let n = points.len() - 1;
    // Point `k` is where move `k` starts and move `k - 1` ends.
    let lines = |a: usize, b: usize, out: &mut Vec<Move>| {
        let kept = douglas_peucker(&points, a, b, tol);
        for w in kept.windows(2) {
            out.push(Move { start: run[w[0]].start, ..run[w[1] - 1] });
        }
    };
    if !arcs {
        lines(0, n, out);
        return;
    }
    let mut gap = 0;
    let mut i = 0;
    while i + 3 <= n {
        match longest_arc(&points, i, n, tol) {
            Some((j, arc)) => {
                if gap < i {
                    lines(gap, i, out);
                }
                let last = &run[j - 1];
                out.push(Move { kind: MoveKind::Arc(arc), start: run[i].start, end: last.end, ..*last });
                gap = j;
                i = j;
            }
            None => i += 1,
        }
    }
    if gap < n {
        lines(gap, n, out);
    }
}

/// Indices of the points Douglas–Peucker keeps between `a` and `b`
/// (both kept), in order: every point between two kept ones is within
/// `tol` (plus [`ON_LINE`]) of the segment joining them.
pub fn douglas_peucker(points: &[[f64; 3]], a: usize, b: usize, tol: f64) -> Vec<usize> {
    let mut keep = vec![a];
    let mut stack = vec![(a, b)];
    let mut kept_inner = Vec::new();
    while let Some((s, e)) = stack.pop() {
        let mut far = (0.0, 0);
        for k in s + 1..e {
            let d = segment_distance(points[k], points[s], points[e]);
            if d > far.0 {
                far = (d, k);
            }
        }
        if far.0 > tol + ON_LINE {
            kept_inner.push(far.1);
            stack.push((s, far.1));
            stack.push((far.1, e));
        }
    }
    kept_inner.sort_unstable();
    keep.extend(kept_inner);
    keep.push(b);
    keep
}

/// The longest arc from point `i` (ending at `j ≤ n`, at least three moves
/// on, at a point of the same Z), unless a straight chord fits as well. The
/// search stops at the first end the arc does not fit, or at a point more
/// than the tolerance away from the start's Z (no arc at that Z can come
/// near it).
fn longest_arc(points: &[[f64; 3]], i: usize, n: usize, tol: f64) -> Option<(usize, Arc)> {
    let z = points[i][2];
    if (i + 1..(i + 3).min(n + 1)).any(|k| (points[k][2] - z).abs() > tol) {
        return None;
    }
    let mut best = None;
    let mut j = i + 3;
    while j <= n && j - i < MAX_ARC_POINTS && (points[j][2] - z).abs() <= tol {
        if points[j][2] == z {
            match fit_arc(points, i, j, tol) {
                Some(arc) => best = Some((j, arc)),
                None => break,
            }
        }
        j += 1;
    }
    let (j, arc) = best?;
    let straight = (i + 1..j).all(|k| segment_distance(points[k], points[i], points[j]) <= tol + ON_LINE);
    (!straight).then_some((j, arc))
}

/// An arc in the XY plane at the Z of points `a` and `b` through their XY
/// and the XY of the point between, if every segment of `a..=b` stays
/// within `tol` of it (see the module documentation).
fn fit_arc(points: &[[f64; 3]], a: usize, b: usize, tol: f64) -> Option<Arc> {
    let (p, q, r) = (points[a], points[(a + b) / 2], points[b]);
    let z = p[2];
    if r[2] != z {
        return None;
    }
    // Circle through three points in XY.
    let (bx, by) = (q[0] - p[0], q[1] - p[1]);
    let (cx, cy) = (r[0] - p[0], r[1] - p[1]);
    let d = 2.0 * (bx * cy - by * cx);
    let scale = (bx * bx + by * by).max(cx * cx + cy * cy);
    if d.is_nan() || d.abs() <= 1e-12 * scale {
        return None;
    }
    let b2 = bx * bx + by * by;
    let c2 = cx * cx + cy * cy;
    let ux = (cy * b2 - by * c2) / d;
    let uy = (bx * c2 - cx * b2) / d;
    let center = [p[0] + ux, p[1] + uy];
    let radius = ux.hypot(uy);
    if !(radius.is_finite() && radius > tol && radius < 1e6) {
        return None;
    }
    let ccw = d > 0.0;
    let angle = |k: usize| (points[k][1] - center[1]).atan2(points[k][0] - center[0]);
    let a0 = angle(a);
    let turn = |k: usize| {
        let raw = if ccw { angle(k) - a0 } else { a0 - angle(k) };
        raw.rem_euclid(std::f64::consts::TAU)
    };
    let error = |k: usize| {
        let pk = points[k];
        let radial = (pk[0] - center[0]).hypot(pk[1] - center[1]) - radius;
        radial.hypot(pk[2] - z)
    };
    let mut previous = 0.0;
    let mut e_prev = error(a);
    for k in a + 1..=b {
        let phi = if k == b { turn(b) } else { turn(k) };
        let delta = phi - previous;
        if !(delta > 0.0 && delta < std::f64::consts::PI) {
            return None;
        }
        let e = error(k);
        let sagitta = radius * (1.0 - (delta / 2.0).cos());
        if sagitta + e.max(e_prev) > tol {
            return None;
        }
        previous = phi;
        e_prev = e;
    }
    if previous >= 1.9 * std::f64::consts::PI {
        return None;
    }
    Some(Arc { center: [center[0], center[1], z], plane: Plane::Xy, ccw, turns: 0 })
}
