//! Cycle time of a toolpath on a machine with finite rapids and acceleration.
//!
//! Cutting moves run at their programmed feed (capped by the machine's
//! maximum), slowed at corners by a junction-deviation limit (as grbl's
//! planner does) and by the acceleration over the following moves: a
//! backward and a forward pass bound every junction speed, then each move is
//! a trapezoid (or triangle) from its entry to its exit speed. Rapids move
//! every axis at its own rapid rate (non-interpolated positioning), from
//! stop to stop. Dwells add their time.

use crate::{Axes, Move, MoveKind, Toolpath};

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
    let (times, unknown) = move_times(path, machine);
    // Summed from +0: an empty sum of f64 is −0, printed "-0.0 s".
    (times.iter().fold(0.0, |total, t| total + t), unknown)
}

/// Estimated seconds of each move of the toolpath, in order; moves without
/// a feed (feed 0) take none and are counted in the second value.
pub fn move_times(path: &Toolpath, machine: &Dynamics) -> (Vec<f64>, usize) {
    let a = machine.acceleration_mm_s2.max(1e-9);
    let moves = &path.moves;
    let n = moves.len();
    // Cruise speed and the largest speed at each move's start (junction).
    let cruise: Vec<f64> = moves.iter().map(|m| m.feed.min(machine.max_feed_mm_min).max(0.0) / 60.0).collect();
    let dirs: Vec<_> = moves.iter().map(directions).collect();
    let mut entry = vec![0.0f64; n + 1];
    for i in 1..n {
        if let (Some((_, d0)), Some((d1, _))) = (dirs[i - 1], dirs[i]) {
            let cos = -(d0[0] * d1[0] + d0[1] * d1[1] + d0[2] * d1[2]);
            let v = if cos < -0.999_999 {
                f64::INFINITY
            } else if cos > 0.999_999 {
                0.0
            } else {
                let sin_half = ((1.0 - cos) / 2.0).sqrt();
                (a * machine.junction_deviation_mm * sin_half / (1.0 - sin_half)).sqrt()
            };
            entry[i] = v.min(cruise[i - 1]).min(cruise[i]);
        }
    }
    let lengths: Vec<f64> = moves.iter().map(Move::feed_distance).collect();
    for i in (0..n).rev() {
        entry[i] = entry[i].min((entry[i + 1] * entry[i + 1] + 2.0 * a * lengths[i]).sqrt());
    }
    for i in 0..n {
        entry[i + 1] = entry[i + 1].min((entry[i] * entry[i] + 2.0 * a * lengths[i]).sqrt());
    }
    let mut unknown = 0;
    let mut seconds = Vec::with_capacity(n);
    for (i, m) in moves.iter().enumerate() {
        seconds.push(match m.kind {
            MoveKind::Dwell(s) => s,
            MoveKind::Rapid | MoveKind::Home | MoveKind::Machine => {
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
            _ if cruise[i] <= 0.0 => {
                unknown += 1;
                0.0
            }
            _ => trapezoid(lengths[i], entry[i], entry[i + 1], cruise[i], a),
        });
    }
    (seconds, unknown)
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
