//! Arcs: `I J K` or `R` words that a control finds the same circle from
//! after rounding, full circles and helical turns, or chords for a control
//! without arcs.

use std::f64::consts::PI;

use kezuri_geom::{Arc, Axes, AxisSet, Move, Plane};

use super::blocks::{Motion, Writer, N};
use super::options::Arcs;
use crate::Error;

impl Writer {
    pub(super) fn arc(&mut self, m: &Move, arc: Arc) -> Result<(), Error> {
        let feed = self.non_negative(m.feed, 'F')?;
        let start = self.target(m.start)?;
        let exact = m.start.to_array();
        // Where the control's position is unknown, a generated toolpath's
        // start is real and is reached; an NC program's arc starts wherever
        // the control is, as in the source (never a move to the model's
        // guess).
        let away = (0..N).any(|k| match self.pos[k] {
            Some(p) => (p as f64 - exact[k] * self.scale).abs() > 1.0,
            None => self.generated,
        });
        if away {
            self.straight_to(Some(Motion::Linear), start, Some(feed), AxisSet::ALL);
        }
        if self.arcs == Arcs::Lines {
            return self.chords(m, arc, feed);
        }
        let single = Arc { turns: 0, ..arc };
        let mut from = m.start;
        if arc.turns > 0 {
            // One full circle per extra turn, the helical and rotary axes
            // sharing out their travel by angle.
            let total = arc.sweep(m.start, m.end);
            let (s, e) = (m.start.to_array(), m.end.to_array());
            let (_, _, n) = arc.plane.axes();
            for turn in 1..=arc.turns {
                let t = f64::from(turn) * std::f64::consts::TAU / total;
                let mut p = s;
                for k in (3..N).chain([n]) {
                    p[k] = s[k] + (e[k] - s[k]) * t;
                }
                let to = Axes::from_array(p);
                self.single_arc(from, to, single, feed, m.named)?;
                from = to;
            }
        }
        self.single_arc(from, m.end, single, feed, m.named)
    }

    /// Arc `m` as straight moves whose chords stray from it by at most one
    /// unit of the last digit (for controls without arcs); the helical and
    /// rotary axes share out their travel by angle.
    fn chords(&mut self, m: &Move, arc: Arc, feed: i64) -> Result<(), Error> {
        let (i, j, _) = arc.plane.axes();
        let (s, e) = (m.start.to_array(), m.end.to_array());
        let c = arc.center;
        let (di, dj) = (s[i] - c[i], s[j] - c[j]);
        let radius = di.hypot(dj);
        let total = arc.sweep(m.start, m.end);
        let tolerance = 1.0 / self.scale;
        let step = if radius > tolerance { 2.0 * (1.0 - tolerance / radius).acos() } else { PI };
        let count = (total / step).ceil().clamp(1.0, 1e7);
        if !count.is_finite() {
            return Err(self.number_error('R', radius));
        }
        let count = count as u32;
        let sign = if arc.ccw { 1.0 } else { -1.0 };
        for k in 1..=count {
            let p = if k == count {
                e
            } else {
                let f = f64::from(k) / f64::from(count);
                let (sin, cos) = (sign * total * f).sin_cos();
                let mut p: [f64; N] = std::array::from_fn(|a| s[a] + (e[a] - s[a]) * f);
                p[i] = c[i] + di * cos - dj * sin;
                p[j] = c[j] + di * sin + dj * cos;
                p
            };
            let t = self.target(Axes::from_array(p))?;
            self.straight_to(Some(Motion::Linear), t, Some(feed), m.named);
        }
        Ok(())
    }

    /// One arc of at most a full turn from the control's position, which is
    /// `start` rounded.
    fn single_arc(&mut self, start: Axes, end: Axes, arc: Arc, feed: i64, named: AxisSet) -> Result<(), Error> {
        let (i, j, _) = arc.plane.axes();
        let mut t = self.target(end)?;
        // The start is the control's position where it is known, else the
        // toolpath's start (the centre is given from there, as the source
        // gave it).
        let from = self.target(start)?;
        let s: [i64; N] = std::array::from_fn(|k| self.pos[k].unwrap_or(from[k]));
        let exact_sweep = arc.sweep(start, end);
        let letters = ['I', 'J', 'K'];
        let centre = [self.fixed(arc.center[i], letters[i])?, self.fixed(arc.center[j], letters[j])?];
        let plain = [centre[0] - s[i], centre[1] - s[j]];
        let full = t[i] == s[i] && t[j] == s[j];
        let offset = if full {
            if exact_sweep <= PI {
                self.straight_to(Some(Motion::Linear), t, Some(feed), named);
                return Ok(());
            }
            if self.arcs == Arcs::Radius {
                // R cannot give a full circle: two half circles, the helical
                // and rotary axes half way at the middle.
                let (sv, ev) = (start.to_array(), end.to_array());
                let mut mid: [f64; N] = std::array::from_fn(|k| (sv[k] + ev[k]) / 2.0);
                mid[i] = 2.0 * arc.center[i] - sv[i];
                mid[j] = 2.0 * arc.center[j] - sv[j];
                let mid = Axes::from_array(mid);
                self.single_arc(start, mid, arc, feed, named)?;
                return self.single_arc(mid, end, arc, feed, named);
            }
            plain
        } else {
            // Within half a unit, and 0.001 mm, of the circle is close enough.
            let close = (0.001 * self.scale).min(0.5);
            let offset = best_centre(plain, [t[i] - s[i], t[j] - s[j]], close);
            let written = self.written_sweep(arc, &s, &t, offset);
            if (written - exact_sweep).abs() > PI {
                if exact_sweep <= PI {
                    self.straight_to(Some(Motion::Linear), t, Some(feed), named);
                    return Ok(());
                }
                // Rounding closed a near-full circle: make it a full one.
                t[i] = s[i];
                t[j] = s[j];
                plain
            } else {
                offset
            }
        };
        if offset[0] == 0 && offset[1] == 0 {
            // A radius below the last digit.
            self.straight_to(Some(Motion::Linear), t, Some(feed), named);
            return Ok(());
        }
        self.motion_block();
        if Some(arc.plane) != self.plane {
            let code = match arc.plane {
                Plane::Xy => self.codes.plane[0],
                Plane::Zx => self.codes.plane[1],
                Plane::Yz => self.codes.plane[2],
            };
            self.code(code);
            self.plane = Some(arc.plane);
        }
        let g = if arc.ccw { Motion::Ccw } else { Motion::Cw };
        if self.motion != Some(g) {
            self.code(self.codes.motion[g as usize]);
            self.motion = Some(g);
        }
        self.axis_words(&t, named);
        if self.arcs == Arcs::Radius {
            // R is the radius, negative past half a turn: rounded up from
            // the largest of the written start's and end's distances to
            // the centre and half the chord, so that a control always finds
            // a circle through the written ends (GRBL's error 33, Fanuc's
            // alarm, where R is short of half the chord).
            let chord = [t[i] - s[i], t[j] - s[j]];
            let r_end = ((chord[0] - offset[0]) as f64).hypot((chord[1] - offset[1]) as f64);
            let r_start = (offset[0] as f64).hypot(offset[1] as f64);
            let half = (chord[0] as f64).hypot(chord[1] as f64) / 2.0;
            let r = r_start.max(r_end).max(half).ceil() as i64;
            let written = self.written_sweep(arc, &s, &t, offset);
            self.word('R', if written > PI + 1e-9 { -r } else { r }, self.point);
        } else {
            for (k, letter) in letters.into_iter().enumerate() {
                if k == i {
                    self.word(letter, offset[0], self.point);
                } else if k == j {
                    self.word(letter, offset[1], self.point);
                }
            }
        }
        self.feed_word(feed);
        self.out.push('\n');
        Ok(())
    }

    /// The sweep a control computes from the written start, end and centre.
    fn written_sweep(&self, arc: Arc, s: &[i64; N], t: &[i64; N], offset: [i64; 2]) -> f64 {
        let (i, j, _) = arc.plane.axes();
        let unit = |v: i64| v as f64 / self.scale;
        let point = |p: &[i64; N]| Axes { x: unit(p[0]), y: unit(p[1]), z: unit(p[2]), ..Axes::ZERO };
        let mut center = [0.0; 3];
        center[i] = unit(s[i] + offset[0]);
        center[j] = unit(s[j] + offset[1]);
        Arc { center, ..arc }.sweep(point(s), point(t))
    }
}

/// The centre offset (in units of the last digit) to write: `plain`, the
/// rounded one, when the end (`end`, relative to the start) lies within
/// `close` units of its circle, otherwise the one of the nine around `plain`
/// that puts the end best on the circle through the start.
fn best_centre(plain: [i64; 2], end: [i64; 2], close: f64) -> [i64; 2] {
    let miss = |o: [i64; 2]| {
        let r0 = (o[0] as f64).hypot(o[1] as f64);
        let r1 = ((end[0] - o[0]) as f64).hypot((end[1] - o[1]) as f64);
        (r1 - r0).abs()
    };
    let mut best = (plain, miss(plain));
    if best.1 <= close {
        return plain;
    }
    for d0 in -1..=1 {
        for d1 in -1..=1 {
            let o = [plain[0] + d0, plain[1] + d1];
            let e = miss(o);
            if e < best.1 - 1e-9 {
                best = (o, e);
            }
        }
    }
    best.0
}
