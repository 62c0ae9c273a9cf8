//! Cycle time of a toolpath on a machine with finite rapids and acceleration.
//!
//! Cutting moves run at their programmed feed (capped by the machine's
//! maximum), slowed at corners by a junction-deviation limit (as grbl's
//! planner does) and by the acceleration over the following moves: a
//! backward and a forward pass bound every junction speed, then each move is
//! a trapezoid (or triangle) from its entry to its exit speed. Rapids move
//! every axis at its own rapid rate (non-interpolated positioning), from
//! stop to stop. Dwells add their time.

use std::collections::VecDeque;

use crate::{Axes, Move, MoveKind, PathSink, Toolpath};

/// What the cycle time model needs to know of a machine.
#[derive(Clone, Debug, PartialEq)]
pub struct Dynamics {
    /// Rapid rate of X, Y, Z in mm/min.
    pub rapid_mm_min: [f64; 3],
    /// Rapid rate of A, B, C in degrees/min.
    pub rapid_deg_min: f64,
    /// Highest cutting feed in mm/min.
    pub max_feed_mm_min: f64,
    /// Acceleration of the tool tip in mm/s².
    pub acceleration_mm_s2: f64,
    /// Junction deviation in mm: how far a corner may be rounded at speed.
    pub junction_deviation_mm: f64,
}

impl Default for Dynamics {
    /// A small 3-axis router or machining centre.
    fn default() -> Dynamics {
        Dynamics {
            rapid_mm_min: [10_000.0; 3],
            rapid_deg_min: 3_600.0,
            max_feed_mm_min: 10_000.0,
            acceleration_mm_s2: 1_000.0,
            junction_deviation_mm: 0.01,
        }
    }
}

/// The speed (mm/s) the junction deviation allows where a move leaving in
/// direction `d1` follows one arriving in direction `d0` (unit vectors), at
/// acceleration `a`: unlimited straight on, 0 for a reversal.
fn junction_speed(d0: [f64; 3], d1: [f64; 3], a: f64, machine: &Dynamics) -> f64 {
    let cos = -(d0[0] * d1[0] + d0[1] * d1[1] + d0[2] * d1[2]);
    if cos < -0.999_999 {
        f64::INFINITY
    } else if cos > 0.999_999 {
        0.0
    } else {
        let sin_half = ((1.0 - cos) / 2.0).sqrt();
        (a * machine.junction_deviation_mm * sin_half / (1.0 - sin_half)).sqrt()
    }
}

/// Unit direction of travel at the start and end of a move (X Y Z).
fn directions(m: &Move) -> Option<([f64; 3], [f64; 3])> {
    let unit = |a: Axes, b: Axes| {
        let d = [b.x - a.x, b.y - a.y, b.z - a.z];
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        (n > 1e-12).then(|| [d[0] / n, d[1] / n, d[2] / n])
    };
    match m.kind {
        MoveKind::Arc(arc) => {
            let t = 1e-4;
            let first = unit(m.start, arc.point_at(m.start, m.end, t))?;
            let last = unit(arc.point_at(m.start, m.end, 1.0 - t), m.end)?;
            Some((first, last))
        }
        MoveKind::Feed | MoveKind::Probe => unit(m.start, m.end).map(|d| (d, d)),
        _ => None,
    }
}

/// Seconds to run `length` mm from speed `v0` to `v1` (mm/s), cruising at
/// most at `vmax`, with acceleration `a`.
fn trapezoid(length: f64, v0: f64, v1: f64, vmax: f64, a: f64) -> f64 {
    if length <= 0.0 {
        return 0.0;
    }
    let accel = (vmax * vmax - v0 * v0) / (2.0 * a);
    let decel = (vmax * vmax - v1 * v1) / (2.0 * a);
    if accel + decel <= length {
        (vmax - v0) / a + (vmax - v1) / a + (length - accel - decel) / vmax
    } else {
        // Triangle: the peak speed where the two ramps meet.
        let peak = ((2.0 * a * length + v0 * v0 + v1 * v1) / 2.0).sqrt();
        (peak - v0).max(0.0) / a + (peak - v1).max(0.0) / a
    }
}

/// Estimated seconds to run the toolpath. Moves without a feed (feed 0)
/// take no time and are counted in the second value.
pub fn cycle_time(path: &Toolpath, machine: &Dynamics) -> (f64, usize) {
    let mut clock = CycleClock::new(machine);
    clock.add(&path.moves);
    clock.finish()
}

/// Estimated seconds of each move of the toolpath, in order; moves without
/// a feed (feed 0) take none and are counted in the second value.
pub fn move_times(path: &Toolpath, machine: &Dynamics) -> (Vec<f64>, usize) {
    let mut planner = Planner::new(machine);
    let mut seconds = Vec::with_capacity(path.moves.len());
    for m in &path.moves {
        planner.push(m, &mut |s| seconds.push(s));
    }
    planner.plan(true, &mut |s| seconds.push(s));
    (seconds, planner.unknown)
}

/// [`cycle_time`] of a toolpath handed on in pieces ([`PathSink`]): the
/// same seconds, to the bit, holding only the moves whose speeds later
/// moves may still change: about a braking distance from the top feed of
/// path (the window `Planner` says how it bounds).
#[derive(Clone, Debug)]
pub struct CycleClock {
    planner: Planner,
    /// The seconds of the moves planned, summed in order from +0 (an
    /// empty sum of f64 is −0, printed "-0.0 s").
    total: f64,
}

impl CycleClock {
    /// A clock for `machine`, before the first move.
    pub fn new(machine: &Dynamics) -> CycleClock {
        CycleClock { planner: Planner::new(machine), total: 0.0 }
    }

    /// The next moves of the path, in order.
    pub fn add(&mut self, moves: &[Move]) {
        self.add_timed(moves, &mut |_| {});
    }

    /// [`CycleClock::add`], handing `done` the seconds of each move as
    /// they become final, in move order ([`move_times`]' seconds, to the
    /// bit): those of the moves added before some of these, or none yet.
    pub fn add_timed(&mut self, moves: &[Move], done: &mut impl FnMut(f64)) {
        let total = &mut self.total;
        for m in moves {
            self.planner.push(m, &mut |s| {
                *total += s;
                done(s);
            });
        }
    }

    /// The estimated seconds of every move added, and how many of them had
    /// no feed (none counted for them).
    pub fn finish(self) -> (f64, usize) {
        self.finish_timed(&mut |_| {})
    }

    /// [`CycleClock::finish`], handing `done` the seconds of the moves
    /// that were still waiting, in order.
    pub fn finish_timed(mut self, done: &mut impl FnMut(f64)) -> (f64, usize) {
        let total = &mut self.total;
        self.planner.plan(true, &mut |s| {
            *total += s;
            done(s);
        });
        (self.total, self.planner.unknown)
    }
}

impl PathSink for CycleClock {
    fn take(&mut self, piece: &Toolpath, _programmed: Option<&Toolpath>) {
        self.add(&piece.moves);
    }
}

/// A move whose exit speed is not known yet: what the planner keeps of it.
#[derive(Clone, Copy, Debug)]
struct Waiting {
    /// The seconds of a move its speeds do not change (a rapid, a dwell, a
    /// move without a feed); `None` for a feed move, a trapezoid.
    fixed: Option<f64>,
    /// Cruise speed, mm/s.
    cruise: f64,
    /// [`Move::feed_distance`].
    length: f64,
    /// The highest speed at the move's start: the corner's junction limit
    /// and both moves' cruise (0 where either move has no direction).
    limit: f64,
}

/// The junction-deviation planner, fed move by move: each move's seconds
/// are handed on, in order, once its entry and exit speeds are final.
///
/// The whole-path planner sets each junction `i`'s speed in a backward pass
/// `v[i] = min(limit[i], √(v[i+1]² + 2·a·L[i]))` from `v[n] = 0` (the tool
/// stops at the end), then a forward pass `v[i+1] = min(v[i+1], √(v[i]² +
/// 2·a·L[i]))` from `v[0] = 0`. Both steps are monotone in the speed they
/// start from (so are IEEE `+ × √ min`, rounding included), and every
/// backward value lies in `[0, limit[i]]`. So with the moves after the last
/// one fed unknown, running the backward pass from an assumed `v = 0` at
/// the last move's end gives a lower bound of each speed; where that lower
/// bound reaches junction `k`'s own limit (the moves from `k` on are long
/// enough to brake from `limit[k]` to a stop), the true `v[k]` is
/// `limit[k]` whatever follows, bit for bit, and every speed before `k`
/// follows from it and the moves before it alone. The window held is so the
/// moves from the last such junction: a path length of at most one braking
/// distance from the top feed, `(max_feed/60)² / 2a` (13.9 mm on the default
/// machine), plus one move; a rapid, a dwell or a reversal (limit 0) closes
/// it at once. Only many tiny moves along a smooth path at speed hold many
/// moves, 48 bytes each. The window is looked at when it has doubled since
/// it was last cut (64 moves at least), so the work stays linear.
#[derive(Clone, Debug)]
struct Planner {
    machine: Dynamics,
    /// Acceleration, mm/s².
    a: f64,
    /// The moves from the last final junction on.
    waiting: VecDeque<Waiting>,
    /// The final speed at the start of `waiting[0]`.
    entry: f64,
    /// The direction at the end of the last move pushed, and its cruise;
    /// `None` before the first move and after a move without direction.
    last: Option<([f64; 3], f64)>,
    /// The window's length at which it is next looked at.
    look_at: usize,
    /// The backward speeds of the window, scratch.
    backward: Vec<f64>,
    /// Moves without a feed.
    unknown: usize,
}

/// The fewest moves held before the window is looked at.
const LOOK_AT_LEAST: usize = 64;

impl Planner {
    fn new(machine: &Dynamics) -> Planner {
        Planner {
            machine: machine.clone(),
            a: machine.acceleration_mm_s2.max(1e-9),
            waiting: VecDeque::new(),
            entry: 0.0,
            last: None,
            look_at: LOOK_AT_LEAST,
            backward: Vec::new(),
            unknown: 0,
        }
    }

    /// Takes the next move; hands on the seconds of each move planned.
    fn push(&mut self, m: &Move, done: &mut impl FnMut(f64)) {
        let (a, machine) = (self.a, &self.machine);
        let cruise = m.feed.min(machine.max_feed_mm_min).max(0.0) / 60.0;
        let dirs = directions(m);
        let limit = match (self.last, dirs) {
            (Some((d0, before)), Some((d1, _))) => junction_speed(d0, d1, a, machine).min(before).min(cruise),
            _ => 0.0,
        };
        self.last = dirs.map(|(_, end)| (end, cruise));
        let fixed = match m.kind {
            MoveKind::Dwell(s) => Some(s),
            MoveKind::Rapid | MoveKind::Home | MoveKind::Machine => Some(rapid_seconds(m, machine, a)),
            _ if cruise <= 0.0 => {
                self.unknown += 1;
                Some(0.0)
            }
            _ => None,
        };
        self.waiting.push_back(Waiting { fixed, cruise, length: m.feed_distance(), limit });
        if self.waiting.len() >= self.look_at {
            self.plan(false, done);
            self.look_at = (2 * self.waiting.len()).max(LOOK_AT_LEAST);
        }
    }

    /// Plans the window: every move at the `end` of the path, else those
    /// before the last junction whose speed is final (see `Planner`);
    /// hands on their seconds in order and lets them go.
    fn plan(&mut self, end: bool, done: &mut impl FnMut(f64)) {
        let n = self.waiting.len();
        // The backward pass from a stop at the window's end.
        self.backward.clear();
        self.backward.resize(n + 1, 0.0);
        let mut last_final = if end { n } else { 0 };
        for i in (0..n).rev() {
            let w = &self.waiting[i];
            let v = w.limit.min((self.backward[i + 1] * self.backward[i + 1] + 2.0 * self.a * w.length).sqrt());
            self.backward[i] = v;
            if last_final == 0 && i > 0 && v == w.limit {
                last_final = i;
            }
        }
        // The forward pass to the last final junction.
        for (i, w) in self.waiting.drain(..last_final).enumerate() {
            let exit = self.backward[i + 1].min((self.entry * self.entry + 2.0 * self.a * w.length).sqrt());
            done(w.fixed.unwrap_or_else(|| trapezoid(w.length, self.entry, exit, w.cruise, self.a)));
            self.entry = exit;
        }
    }
}

/// Seconds of a rapid: every axis at its own rapid rate, from stop to stop.
fn rapid_seconds(m: &Move, machine: &Dynamics, a: f64) -> f64 {
    let (s, e) = (m.start.to_array(), m.end.to_array());
    (0..Axes::COUNT)
        .map(|k| {
            // U V W at the rapid rate of X Y Z, which they parallel.
            let rate = match k {
                0..3 => machine.rapid_mm_min[k],
                3..6 => machine.rapid_deg_min,
                _ => machine.rapid_mm_min[k - 6],
            } / 60.0;
            trapezoid((e[k] - s[k]).abs(), 0.0, 0.0, rate.max(1e-9), a)
        })
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Arc, Plane};

    #[test]
    fn an_empty_program_takes_no_time_not_minus_zero() {
        let (t, unknown) = cycle_time(&Toolpath::default(), &Dynamics::default());
        assert!(t == 0.0 && t.is_sign_positive() && unknown == 0, "{t}");
    }

    fn feed(from: [f64; 3], to: [f64; 3], f: f64) -> Move {
        let at = |p: [f64; 3]| Axes { x: p[0], y: p[1], z: p[2], ..Axes::ZERO };
        Move { kind: MoveKind::Feed, start: at(from), end: at(to), feed: f, ..Move::default() }
    }

    /// The planner as it was before it took pieces, the whole path in
    /// arrays: the reference the streaming planner must match to the bit.
    fn whole_path_times(path: &Toolpath, machine: &Dynamics) -> Vec<f64> {
        let a = machine.acceleration_mm_s2.max(1e-9);
        let moves = &path.moves;
        let n = moves.len();
        let cruise: Vec<f64> = moves.iter().map(|m| m.feed.min(machine.max_feed_mm_min).max(0.0) / 60.0).collect();
        let dirs: Vec<_> = moves.iter().map(directions).collect();
        let mut entry = vec![0.0f64; n + 1];
        for i in 1..n {
            if let (Some((_, d0)), Some((d1, _))) = (dirs[i - 1], dirs[i]) {
                entry[i] = junction_speed(d0, d1, a, machine).min(cruise[i - 1]).min(cruise[i]);
            }
        }
        let lengths: Vec<f64> = moves.iter().map(Move::feed_distance).collect();
        for i in (0..n).rev() {
            entry[i] = entry[i].min((entry[i + 1] * entry[i + 1] + 2.0 * a * lengths[i]).sqrt());
        }
        for i in 0..n {
            entry[i + 1] = entry[i + 1].min((entry[i] * entry[i] + 2.0 * a * lengths[i]).sqrt());
        }
        (0..n)
            .map(|i| match moves[i].kind {
                MoveKind::Dwell(s) => s,
                MoveKind::Rapid | MoveKind::Home | MoveKind::Machine => rapid_seconds(&moves[i], machine, a),
                _ if cruise[i] <= 0.0 => 0.0,
                _ => trapezoid(lengths[i], entry[i], entry[i + 1], cruise[i], a),
            })
            .collect()
    }

    /// A long program of varied moves: straight runs cut in pieces of
    /// every length (from 1 µm), gentle and sharp corners, reversals, arcs,
    /// moves without a feed, dwells and rapids; `tiny`: only moves of 1 to
    /// 10 µm along a gently curving line at the top feed, never stopping.
    fn long_program(n: usize, seed: u64, tiny: bool) -> Toolpath {
        let mut r = crate::SplitMix64::new(seed);
        let mut at = Axes::ZERO;
        let (mut heading, mut moves) = (0.0f64, Vec::with_capacity(n));
        while moves.len() < n {
            let pick = if tiny { 99 } else { r.below(100) };
            let length = match r.below(4) {
                _ if tiny => 0.001 + 0.009 * r.next_f64(),
                0 => 0.001 + 0.01 * r.next_f64(),
                1 => 0.05 + r.next_f64(),
                2 => 1.0 + 10.0 * r.next_f64(),
                _ => 10.0 + 100.0 * r.next_f64(),
            };
            heading += match r.below(5) {
                _ if tiny => 1e-4 * r.normal(),
                0 => 0.0,
                1 => 0.01 * r.normal(),
                2 => 0.5 * r.normal(),
                3 => std::f64::consts::PI,
                _ => 2.0 * r.next_f64(),
            };
            let feed = match r.below(20) {
                _ if tiny => 10_000.0,
                0 => 0.0,
                1 => 20_000.0,
                k => 100.0 * k as f64,
            };
            let end = Axes { x: at.x + length * heading.cos(), y: at.y + length * heading.sin(), z: at.z, ..at };
            let end = if pick < 3 { Axes { z: at.z + 2.0 * r.next_f64() - 1.0, ..end } } else { end };
            let m = match pick {
                0..3 => Move { kind: MoveKind::Rapid, start: at, end, ..Move::default() },
                3..5 => Move { kind: MoveKind::Dwell(r.next_f64()), start: at, end: at, ..Move::default() },
                5..10 => {
                    let center = [(at.x + end.x) / 2.0, (at.y + end.y) / 2.0, at.z];
                    let arc = Arc { center, plane: Plane::Xy, ccw: r.below(2) == 0, turns: 0 };
                    Move { kind: MoveKind::Arc(arc), start: at, end, feed, ..Move::default() }
                }
                _ => Move { kind: MoveKind::Feed, start: at, end, feed, ..Move::default() },
            };
            at = m.end;
            moves.push(m);
        }
        Toolpath::from(moves)
    }

    #[test]
    fn pieces_of_any_size_take_the_whole_paths_time_to_the_bit() {
        let d = Dynamics::default();
        for (seed, tiny) in [(1, false), (2, false), (3, true)] {
            let path = long_program(50_000, seed, tiny);
            let reference = whole_path_times(&path, &d);
            let total = reference.iter().fold(0.0, |total, t| total + t);
            let (times, unknown) = move_times(&path, &d);
            assert_eq!(times.len(), reference.len());
            for (i, (t, r)) in times.iter().zip(&reference).enumerate() {
                assert_eq!(t.to_bits(), r.to_bits(), "move {i}: {t} against {r} (seed {seed})");
            }
            let feedless = path.moves.iter().filter(|m| m.feed <= 0.0 && !m.is_rapid()).count();
            let dwells = path.moves.iter().filter(|m| matches!(m.kind, MoveKind::Dwell(_))).count();
            assert_eq!(unknown, feedless - dwells);
            assert!(tiny || unknown > 0);
            for size in [1, 7, 4096, 50_000] {
                let mut clock = CycleClock::new(&d);
                for piece in path.moves.chunks(size) {
                    clock.take(&Toolpath::from(piece.to_vec()), None);
                }
                let (t, k) = clock.finish();
                assert_eq!((t.to_bits(), k), (total.to_bits(), unknown), "{t} against {total}, pieces of {size}");
            }
        }
    }

    #[test]
    fn the_planner_holds_a_braking_distance_of_moves() {
        // The window the planner holds: at most twice the moves since the
        // last junction whose speed is final, and 64 moves at least. Moves
        // of 1 to 110 mm with rapids among them need a few; tiny moves at
        // the top feed need a braking distance of them (13.9 mm, 1,400 to
        // 14,000 moves of 1 to 10 µm).
        let d = Dynamics::default();
        for (tiny, most) in [(false, 64), (true, 2 * 14_000)] {
            let path = long_program(50_000, 4, tiny);
            let mut planner = Planner::new(&d);
            let mut held = 0;
            for m in &path.moves {
                planner.push(m, &mut |_| {});
                held = held.max(planner.waiting.len());
            }
            assert!(held <= most, "{held} moves held");
            assert!(!tiny || held > 1_000, "{held} moves held");
        }
    }

    #[test]
    fn straight_line_is_a_trapezoid() {
        // 100 mm at 6000 mm/min = 100 mm/s with 1000 mm/s²: 0.1 s up, 0.1 s down,
        // 10 mm of ramps, 90 mm cruise = 0.9 s; total 1.1 s.
        let path = Toolpath::from(vec![feed([0.0; 3], [100.0, 0.0, 0.0], 6000.0)]);
        let (t, unknown) = cycle_time(&path, &Dynamics::default());
        assert!((t - 1.1).abs() < 1e-9, "{t}");
        assert_eq!(unknown, 0);
    }

    #[test]
    fn collinear_segments_do_not_stop() {
        let one = Toolpath::from(vec![feed([0.0; 3], [100.0, 0.0, 0.0], 6000.0)]);
        let split = Toolpath::from(
            (0..100).map(|i| feed([i as f64, 0.0, 0.0], [i as f64 + 1.0, 0.0, 0.0], 6000.0)).collect::<Vec<_>>(),
        );
        let d = Dynamics::default();
        assert!((cycle_time(&one, &d).0 - cycle_time(&split, &d).0).abs() < 1e-9);
    }

    #[test]
    fn a_reversal_stops_the_tool() {
        let d = Dynamics::default();
        let there_and_back =
            Toolpath::from(vec![feed([0.0; 3], [100.0, 0.0, 0.0], 6000.0), feed([100.0, 0.0, 0.0], [0.0; 3], 6000.0)]);
        assert!((cycle_time(&there_and_back, &d).0 - 2.2).abs() < 1e-9);
    }

    #[test]
    fn rotary_feed_is_in_degrees_per_minute() {
        let d = Dynamics { acceleration_mm_s2: 1e12, ..Dynamics::default() };
        let turn = |start: Axes, end: Axes| Move { kind: MoveKind::Feed, start, end, feed: 360.0, ..Move::default() };
        // 45° at 360°/min: 7.5 s.
        let a45 = turn(Axes::ZERO, Axes { a: 45.0, ..Axes::ZERO });
        assert!((cycle_time(&Toolpath::from(vec![a45]), &d).0 - 7.5).abs() < 1e-6);
        // X 1 mm with B -30° and C 15.5°: √(1 + 900 + 240.25) = 33.78 at 360/min.
        let mixed = turn(Axes::ZERO, Axes { x: 1.0, b: -30.0, c: 15.5, ..Axes::ZERO });
        let expected = (1.0f64 + 900.0 + 240.25).sqrt() / 6.0;
        assert!((cycle_time(&Toolpath::from(vec![mixed]), &d).0 - expected).abs() < 1e-6);
    }

    #[test]
    fn uvw_feed_as_linuxcnc_feeds_them() {
        // LinuxCNC's G-code reference, "Feed Rate": where X Y Z move, F is
        // along X Y Z and U V W follow; where only U V W move, F is along U
        // V W (rotary axes follow).
        let d = Dynamics { acceleration_mm_s2: 1e12, ..Dynamics::default() };
        let feed_to = |end: Axes| Move { kind: MoveKind::Feed, end, feed: 60.0, ..Move::default() };
        let seconds = |m: Move| cycle_time(&Toolpath::from(vec![m]), &d).0;
        // X 3 Y 4 (5 mm) with U 10: 5 mm at 60 mm/min, 5 s.
        assert!((seconds(feed_to(Axes { x: 3.0, y: 4.0, u: 10.0, ..Axes::ZERO })) - 5.0).abs() < 1e-6);
        // U 3 V 4 alone, and with A 90°: 5 mm of U V, 5 s.
        assert!((seconds(feed_to(Axes { u: 3.0, v: 4.0, ..Axes::ZERO })) - 5.0).abs() < 1e-6);
        assert!((seconds(feed_to(Axes { u: 3.0, v: 4.0, a: 90.0, ..Axes::ZERO })) - 5.0).abs() < 1e-6);
        // A full circle of radius 1 in XY with W 30 beside it: 2π mm, 2π s.
        let arc = Arc { center: [1.0, 0.0, 0.0], plane: Plane::Xy, ccw: true, turns: 0 };
        let circle = Move { kind: MoveKind::Arc(arc), ..feed_to(Axes { w: 30.0, ..Axes::ZERO }) };
        assert!((seconds(circle) - std::f64::consts::TAU).abs() < 1e-6);
        // A rapid of W 100 at Z's rapid rate (6,000 mm/min): 1 s.
        let fast = Dynamics { rapid_mm_min: [60_000.0, 60_000.0, 6_000.0], ..d };
        let w = Move { kind: MoveKind::Rapid, end: Axes { w: 100.0, ..Axes::ZERO }, ..Move::default() };
        assert!((cycle_time(&Toolpath::from(vec![w]), &fast).0 - 1.0).abs() < 1e-6);
    }

    #[test]
    fn rapids_use_the_slowest_axis() {
        let d =
            Dynamics { rapid_mm_min: [60_000.0, 60_000.0, 6_000.0], acceleration_mm_s2: 1e9, ..Dynamics::default() };
        let mut m = feed([0.0; 3], [100.0, 100.0, 10.0], 0.0);
        m.kind = MoveKind::Rapid;
        let (t, _) = cycle_time(&Toolpath::from(vec![m]), &d);
        assert!((t - 0.1).abs() < 1e-6, "{t}");
    }
}
