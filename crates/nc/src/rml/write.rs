//! A toolpath to RML-1 text (see the module documentation for the rules).

use std::fmt::Write as _;

use kezuri_geom::{Axes, Move, MoveKind, Spindle, Toolpath};

use super::{RmlOptions, MAX_STEPS};
use crate::{Error, ErrorKind, Place};

/// An error of `kind` at move `index` (source line `line`).
fn at_move(kind: ErrorKind, index: usize, line: u32, message: impl Into<String>) -> Error {
    Error::new(kind, message).at(Place::Move { index, line })
}

/// A number RML-1 cannot hold: a coordinate beyond ±2³¹ steps or not
/// finite, a feed that is not positive.
fn number(index: usize, line: u32, what: &str, value: f64) -> Error {
    at_move(ErrorKind::Number, index, line, format!("{what} {value} cannot be written in RML-1"))
}

/// A move RML-1 has no command for.
fn unsupported(index: usize, line: u32, what: &str) -> Error {
    let message = format!("{what} has no RML-1 command; remove it from the program to convert it");
    at_move(ErrorKind::Unsupported, index, line, message)
}

/// Writes `path` as an RML-1 program in absolute steps of `options.unit`
/// mm (see the module documentation).
///
/// ```
/// use kezuri_geom::{Axes, Move, MoveKind, Toolpath};
/// use kezuri_nc::rml::{write_rml, RmlOptions};
/// let at = |x, y, z| Axes { x, y, z, ..Axes::ZERO };
/// let mut path = Toolpath::default();
/// path.push(Move { kind: MoveKind::Rapid, start: at(0.0, 0.0, 5.0), end: at(10.0, 0.0, 5.0), ..Move::default() });
/// let (start, end) = (at(10.0, 0.0, 5.0), at(10.0, 0.0, -2.4));
/// path.push(Move { kind: MoveKind::Feed, start, end, feed: 600.0, ..Move::default() });
/// let text = write_rml(&path, &RmlOptions::default()).unwrap();
/// assert_eq!(text, ";;^IN;\n^PA;\n!PZ0,500;\n^PU1000,0;\nV10.0;\nZ1000,0,-240;\n^PU;\n^IN;\n");
/// ```
pub fn write_rml(path: &Toolpath, options: &RmlOptions) -> Result<String, Error> {
    if let Some((name, value)) = options.invalid() {
        return Err(Error::new(ErrorKind::Option, format!("RML option {name} {value} is out of range")));
    }
    // A tapping cycle synchronises spindle and feed: no plain moves for it.
    if let Some(k) = path.kept.iter().find(|k| k.cycle.is_some()) {
        return Err(unsupported(k.before, k.line, "a tapping cycle"));
    }
    let origin = path.moves.first().map_or(Axes::ZERO, |m| path.frame(m).origin);
    let rotary = path.moves.first().map_or(Axes::ZERO, |m| m.start);
    let mut w = Writer {
        out: String::with_capacity(path.moves.len() * 18 + 64),
        unit: options.unit,
        tolerance: options.tolerance,
        default_feed: options.feed,
        origin,
        up: 0,
        pos: [None; 3],
        v: None,
        spindle_on: false,
        tool: 0,
        named: [false; 3],
        at: (0, 0),
        path,
    };
    for (index, m) in path.moves.iter().enumerate() {
        w.at = (index, m.line);
        if path.frame(m).origin != origin {
            let message = "the toolpath changes work offset; RML-1 has one work origin";
            return Err(at_move(ErrorKind::Unsupported, index, m.line, message));
        }
        for (k, axis) in [(3, 'A'), (4, 'B'), (5, 'C'), (6, 'U'), (7, 'V'), (8, 'W')] {
            let base = rotary.to_array()[k];
            if m.start.to_array()[k] != base || m.end.to_array()[k] != base {
                let turns = if k < 6 { "turns" } else { "moves" };
                let message = format!("the toolpath {turns} axis {axis}; RML-1 moves X, Y and Z only");
                return Err(at_move(ErrorKind::RotaryAxis, index, m.line, message));
            }
        }
    }
    let up = match options.safe_z {
        Some(z) => Some(z),
        None => {
            let highest = |rapids: bool| {
                path.moves
                    .iter()
                    .filter(|m| !rapids || m.kind == MoveKind::Rapid)
                    .flat_map(|m| [m.start.z, m.end.z].into_iter().skip(usize::from(rapids)))
                    .map(|z| z - origin.z)
                    .fold(None, |a: Option<f64>, z| Some(a.map_or(z, |a| a.max(z))))
            };
            highest(true).or_else(|| highest(false))
        }
    };
    w.out.push_str(";;^IN;\n^PA;\n");
    if let Some(up) = up {
        w.up = w.step(up, "safe Z")?;
        let _ = writeln!(w.out, "!PZ0,{};", w.up);
    }
    for (index, m) in path.moves.iter().enumerate() {
        w.at = (index, m.line);
        if m.tool != w.tool {
            if w.tool != 0 {
                w.tool_change();
            }
            w.tool = m.tool;
        }
        w.spindle(m.spindle != Spindle::Off);
        match m.kind {
            MoveKind::Dwell(_) => return Err(w.unsupported("a dwell (G04)")),
            MoveKind::Probe => return Err(w.unsupported("a probing move (G31)")),
            MoveKind::Home | MoveKind::Machine => w.lift(),
            MoveKind::Rapid => w.rapid(m, index)?,
            MoveKind::Feed => w.feed_to(m.end, m.feed, m)?,
            MoveKind::Arc(_) => {
                let start = w.steps(m.start)?;
                if w.pos.iter().zip(start).any(|(p, s)| *p != Some(s)) {
                    w.feed_to(m.start, m.feed, m)?;
                }
                for p in m.linearize(w.tolerance) {
                    w.feed_to(p, m.feed, m)?;
                }
            }
        }
        for k in 0..3 {
            w.named[k] |= m.named.contains(k);
        }
    }
    if w.pos[2].is_some_and(|z| z != w.up) {
        w.lift();
    }
    w.spindle(false);
    w.out.push_str("^IN;\n");
    Ok(w.out)
}

struct Writer<'a> {
    out: String,
    unit: f64,
    tolerance: f64,
    default_feed: Option<f64>,
    /// Program zero in machine coordinates.
    origin: Axes,
    /// Tool-up height, steps.
    up: i64,
    /// The machine's position in steps, where known.
    pos: [Option<i64>; 3],
    /// The `V` last written.
    v: Option<String>,
    spindle_on: bool,
    tool: u32,
    /// Axes some move has named: the toolpath's position of the others is
    /// only the interpreter's assumption.
    named: [bool; 3],
    at: (usize, u32),
    path: &'a Toolpath,
}

impl Writer<'_> {
    fn unsupported(&self, what: &'static str) -> Error {
        unsupported(self.at.0, self.at.1, what)
    }

    /// A length in program mm as whole steps.
    fn step(&self, mm: f64, what: &'static str) -> Result<i64, Error> {
        let v = mm / self.unit;
        if !v.is_finite() || v.abs() > MAX_STEPS {
            return Err(number(self.at.0, self.at.1, what, mm));
        }
        Ok(v.round() as i64)
    }

    /// A machine position as program steps.
    fn steps(&self, p: Axes) -> Result<[i64; 3], Error> {
        let o = self.origin;
        Ok([self.step(p.x - o.x, "X")?, self.step(p.y - o.y, "Y")?, self.step(p.z - o.z, "Z")?])
    }

    fn spindle(&mut self, on: bool) {
        if on != self.spindle_on {
            self.out.push_str(if on { "!MC1;\n" } else { "!MC0;\n" });
            self.spindle_on = on;
        }
    }

    /// `^PU;`: the tool up where it is.
    fn lift(&mut self) {
        if self.pos[2] != Some(self.up) {
            self.out.push_str("^PU;\n");
            self.pos[2] = Some(self.up);
        }
    }

    fn tool_change(&mut self) {
        self.lift();
        self.spindle(false);
        self.out.push_str("!NR;\n");
    }

    /// Writes `V` for `feed` mm/min where it changes.
    fn speed(&mut self, feed: f64) -> Result<(), Error> {
        if !(feed.is_finite() && feed > 0.0 && feed < 1e9) {
            return Err(number(self.at.0, self.at.1, "feed", feed));
        }
        let mut text = format!("{:.2}", feed / 60.0);
        while text.ends_with('0') && !text.ends_with(".0") {
            text.pop();
        }
        if self.v.as_deref() != Some(text.as_str()) {
            let _ = writeln!(self.out, "V{text};");
            self.v = Some(text);
        }
        Ok(())
    }

    /// `Z x,y,z;` to `p` at `feed`, where the rounded position changes.
    fn feed_to(&mut self, p: Axes, feed: f64, m: &Move) -> Result<(), Error> {
        let t = self.steps(p)?;
        if self.pos == t.map(Some) {
            return Ok(());
        }
        if (0..3).any(|k| !self.named[k] && !m.named.contains(k)) {
            let message = "a cutting move before the program names X and Y; an RML-1 Z command needs all three";
            return Err(at_move(ErrorKind::UnknownPosition, self.at.0, self.at.1, message));
        }
        self.speed(feed)?;
        self.z(t);
        Ok(())
    }

    fn z(&mut self, t: [i64; 3]) {
        let _ = writeln!(self.out, "Z{},{},{};", t[0], t[1], t[2]);
        self.pos = t.map(Some);
    }

    /// The feed for the `Z` of a rapid: the current `V`, else the next
    /// cutting feed of the toolpath, else the options' feed.
    fn plunge_speed(&mut self, index: usize) -> Result<(), Error> {
        if self.v.is_some() {
            return Ok(());
        }
        let ahead = self.path.moves[index..]
            .iter()
            .find(|m| matches!(m.kind, MoveKind::Feed | MoveKind::Arc(_)) && m.feed > 0.0)
            .map(|m| m.feed);
        match ahead.or(self.default_feed) {
            Some(f) => self.speed(f),
            None => {
                let message =
                    "a rapid down needs a speed (V) for its Z move, and the toolpath has no cutting feed; give a feed";
                Err(at_move(ErrorKind::NoFeed, index, self.at.1, message))
            }
        }
    }

    fn rapid(&mut self, m: &Move, index: usize) -> Result<(), Error> {
        let t = self.steps(m.end)?;
        let known = |k: usize| self.named[k] || m.named.contains(k);
        if !known(0) || !known(1) {
            // Before the program names X and Y only a lift can be written;
            // a rapid of X or Y alone is written with the first that knows
            // both.
            if m.named.contains(2) {
                self.lift();
            }
            return Ok(());
        }
        let moves_xy = self.pos[0] != Some(t[0]) || self.pos[1] != Some(t[1]);
        if moves_xy {
            let _ = writeln!(self.out, "^PU{},{};", t[0], t[1]);
            self.pos = [Some(t[0]), Some(t[1]), Some(self.up)];
        } else if t[2] == self.up {
            // The next rapid's ^PU lifts first anyway.
            let next_moves_xy = self.path.moves.get(index + 1).is_some_and(|n| {
                n.kind == MoveKind::Rapid
                    && self.steps(n.end).is_ok_and(|e| Some(e[0]) != self.pos[0] || Some(e[1]) != self.pos[1])
            });
            if !next_moves_xy {
                self.lift();
            }
            return Ok(());
        }
        if t[2] != self.up && known(2) && self.pos[2] != Some(t[2]) {
            self.plunge_speed(index)?;
            self.z(t);
        }
        Ok(())
    }
}
