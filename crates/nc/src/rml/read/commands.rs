//! What each RML-1 command does: modes, heights, feeds, the spindle and
//! the moves, in steps read and mm written.

use kezuri_geom::{Axes, AxisSet, Move, MoveKind, Spindle};

use super::{Command, DeviceCommand, Number, Prefix, Reader, Speed};
use crate::rml::MAX_STEPS;

impl Reader<'_> {
    /// Does what command `c` tells the machine to.
    pub(super) fn execute(&mut self, c: &Command) {
        let caret_or_none = matches!(c.prefix, Prefix::None | Prefix::Caret);
        match (c.prefix, c.name.as_str()) {
            (_, "IN") if caret_or_none => {
                if self.count(c, 0, 0) {
                    self.absolute = true;
                    self.tool_down = false;
                }
            }
            (_, "DF") if caret_or_none => {
                if self.count(c, 0, 0) {
                    self.absolute = true;
                }
            }
            (_, "PA" | "PR") if caret_or_none => {
                self.absolute = c.name == "PA";
                if let Some(pairs) = self.pairs(c) {
                    for p in pairs {
                        if self.tool_down {
                            self.plane_move(MoveKind::Feed, p, c);
                        } else {
                            self.lift(c);
                            self.plane_move(MoveKind::Rapid, p, c);
                        }
                    }
                }
            }
            (_, "PU") if caret_or_none => {
                if let Some(pairs) = self.pairs(c) {
                    self.tool_down = false;
                    self.lift(c);
                    for p in pairs {
                        self.plane_move(MoveKind::Rapid, p, c);
                    }
                }
            }
            (_, "PD") if caret_or_none => {
                if let Some(pairs) = self.pairs(c) {
                    self.tool_down = true;
                    self.plunge(c);
                    for p in pairs {
                        self.plane_move(MoveKind::Feed, p, c);
                    }
                }
            }
            (_, "VS") if caret_or_none => {
                if self.count(c, 1, 2) {
                    self.vs = self.speed(c, c.numbers[0]);
                }
            }
            (Prefix::None, "F") => {
                if self.count(c, 1, 1) {
                    self.vs = self.speed(c, c.numbers[0]);
                }
            }
            (Prefix::None, "V") => {
                if self.count(c, 1, 1) {
                    self.v = self.speed(c, c.numbers[0]);
                }
            }
            (Prefix::Bang, "VZ") => {
                if self.count(c, 1, 1) {
                    self.vz = self.speed(c, c.numbers[0]);
                }
            }
            (_, "PZ") => {
                if self.count(c, 1, 2) {
                    let z1 = self.coordinate(c.numbers[0]);
                    let z2 = c.numbers.get(1).and_then(|&n| self.coordinate(n));
                    if let Some(z1) = z1 {
                        self.z_down = Some(z1);
                    }
                    if let Some(z2) = z2 {
                        self.z_up = Some(z2);
                    }
                }
            }
            (Prefix::None, "Z") => {
                if self.count(c, 3, 3) {
                    let v: Vec<Option<f64>> = c.numbers.iter().map(|&n| self.coordinate(n)).collect();
                    if let [Some(x), Some(y), Some(z)] = v[..] {
                        let to = self.target([x, y, z], [true; 3], c);
                        let feed = self.feed(Speed::ThreeD, c);
                        self.push(MoveKind::Feed, to, AxisSet(0b111), feed, c);
                        self.tool_down = true;
                        self.z_down = Some(to[2]);
                    }
                }
            }
            (Prefix::None, "H") => {
                if self.count(c, 0, 0) {
                    self.warning(
                        c.span,
                        "H (home) is not converted: the machine's home is not known here; kept as a lift to the \
                         tool-up height",
                    );
                    self.tool_down = false;
                    self.lift(c);
                }
            }
            (Prefix::Bang, "MC") => {
                if self.count(c, 0, 1) {
                    let on = !c.numbers.first().is_some_and(|n| n.value == 0.0);
                    self.spindle = if on { Spindle::Cw } else { Spindle::Off };
                }
            }
            (Prefix::Bang, name) => self.device(c, name),
            _ => self.unknown(c),
        }
    }

    /// A `!` device command that is not motion: kept for the caller, and
    /// a warning the first time.
    fn device(&mut self, c: &Command, name: &str) {
        let text = self.snippet(c.span.start as usize, c.span.end as usize);
        let line = self.line_of(c.span.start as usize);
        self.out.device.push(DeviceCommand { text: text.clone(), span: c.span, line });
        if !self.warned.devices.iter().any(|n| n == name) {
            self.warned.devices.push(name.to_string());
            let what = match name {
                "RC" => "spindle rate (its scale depends on the model)",
                "NR" => "pause until the operator continues",
                "ZM" | "ZE" | "ZO" => "a Z or axis setting",
                _ => "a device setting",
            };
            self.warning(
                c.span,
                format!("device command {text} is not converted: {what} (later !{name} commands too)"),
            );
        }
    }

    /// A command RML-1 has not: an error, the rest of the line with it where
    /// it looks like G-code.
    fn unknown(&mut self, c: &Command) {
        let text = self.snippet(c.span.start as usize, c.span.end as usize);
        let hint = if matches!(c.name.as_str(), "G" | "M" | "N" | "O" | "X" | "Y" | "S" | "T") {
            " (this looks like G-code: a file is either RML-1 or G-code)"
        } else {
            ""
        };
        self.error(c.span, format!("unknown RML-1 command '{text}'{hint}"));
        // The rest of the line belongs to it.
        if !hint.is_empty() {
            while let Some(ch) = self.peek() {
                if ch == b'\n' || ch == b';' {
                    break;
                }
                self.i += 1;
            }
        }
    }

    /// Checks the count of numbers; reports and returns `false` otherwise.
    fn count(&mut self, c: &Command, min: usize, max: usize) -> bool {
        let n = c.numbers.len();
        if (min..=max).contains(&n) {
            return true;
        }
        let name = c.display();
        let want = match (min, max) {
            (0, 0) => "no numbers".to_string(),
            (a, b) if a == b => format!("{a} number{}", if a == 1 { "" } else { "s" }),
            (a, b) => format!("{a} to {b} numbers"),
        };
        self.error(c.span, format!("{name} takes {want}, found {n}"));
        false
    }

    /// The X,Y pairs of a plot command, or `None` after an error.
    fn pairs(&mut self, c: &Command) -> Option<Vec<[f64; 2]>> {
        if c.numbers.len() & 1 != 0 {
            self.error(c.span, format!("{} takes X,Y pairs, found {} numbers", c.display(), c.numbers.len()));
            return None;
        }
        let mut out = Vec::with_capacity(c.numbers.len() / 2);
        for p in c.numbers.chunks(2) {
            out.push([self.coordinate(p[0])?, self.coordinate(p[1])?]);
        }
        Some(out)
    }

    /// A coordinate in steps, checked.
    fn coordinate(&mut self, n: Number) -> Option<f64> {
        if !n.value.is_finite() || n.value.abs() > MAX_STEPS {
            self.error(n.span, format!("{} steps is out of range (at most ±{MAX_STEPS})", n.value));
            return None;
        }
        if n.value.fract() != 0.0 && !self.warned.fraction {
            self.warned.fraction = true;
            self.warning(
                n.span,
                format!(
                    "RML-1 coordinates are whole steps of {} mm: {} is read as a fraction of a step",
                    self.unit, n.value
                ),
            );
        }
        Some(n.value)
    }

    /// A speed in mm/s as mm/min, checked.
    fn speed(&mut self, c: &Command, n: Number) -> Option<f64> {
        if !(n.value.is_finite() && n.value > 0.0) {
            self.error(n.span, format!("{}: the speed must be more than 0 mm/s, found {}", c.display(), n.value));
            return None;
        }
        Some(n.value * 60.0)
    }

    /// The feed for a cutting move, reporting (once) when there is none.
    fn feed(&mut self, speed: Speed, c: &Command) -> f64 {
        let f = match speed {
            Speed::ThreeD => self.v,
            Speed::Plane => self.vs.or(self.v),
            Speed::Plunge => self.vz.or(self.v),
        }
        .or(self.default_feed);
        match f {
            Some(f) => f,
            None => {
                if !self.warned.no_feed {
                    self.warned.no_feed = true;
                    self.error(
                        c.span,
                        "no feed for this cutting move: the program sets no speed before it (V, ^VS or !VZ); give \
                         one (--feed MM/MIN)",
                    );
                }
                0.0
            }
        }
    }

    /// The target of a move in steps: absolute, or relative to the position.
    fn target(&mut self, v: [f64; 3], axes: [bool; 3], c: &Command) -> [f64; 3] {
        let mut to = self.at;
        for k in 0..3 {
            if axes[k] {
                to[k] = if self.absolute { v[k] } else { self.at[k] + v[k] };
            }
        }
        if !self.absolute && (0..3).any(|k| axes[k] && !self.known[k]) && !self.warned.relative_start {
            self.warned.relative_start = true;
            self.warning(c.span, "a relative move before the position is known: it is taken from X0 Y0 Z0");
        }
        to
    }

    fn up_steps(&mut self, c: &Command) -> Option<f64> {
        if let Some(z) = self.safe_z {
            return Some(z / self.unit);
        }
        if self.z_up.is_none() && !self.warned.no_up {
            self.warned.no_up = true;
            self.error(
                c.span,
                "no tool-up height for this move: the program sets none (!PZ z1,z2); give one (--safe-z Z)",
            );
        }
        self.z_up
    }

    /// Raises the tool to the up height, where it is not there.
    fn lift(&mut self, c: &Command) {
        let Some(up) = self.up_steps(c) else { return };
        if !self.known[2] || self.at[2] != up {
            let to = [self.at[0], self.at[1], up];
            self.push(MoveKind::Rapid, to, AxisSet(0b100), 0.0, c);
        }
    }

    /// Lowers the tool to the down height, where it is not there.
    fn plunge(&mut self, c: &Command) {
        let Some(down) = self.z_down else {
            if !self.warned.no_down {
                self.warned.no_down = true;
                self.error(
                    c.span,
                    "no tool-down height for ^PD: the program sets none before it (!PZ z1,z2 or a Z move)",
                );
            }
            return;
        };
        if !self.known[2] || self.at[2] != down {
            let feed = self.feed(Speed::Plunge, c);
            let to = [self.at[0], self.at[1], down];
            self.push(MoveKind::Feed, to, AxisSet(0b100), feed, c);
        }
    }

    /// An XY move of `^PA`/`^PR`/`^PU`/`^PD` at the current Z.
    fn plane_move(&mut self, kind: MoveKind, p: [f64; 2], c: &Command) {
        let to = self.target([p[0], p[1], 0.0], [true, true, false], c);
        let feed = if kind == MoveKind::Rapid { 0.0 } else { self.feed(Speed::Plane, c) };
        self.push(kind, to, AxisSet(0b011), feed, c);
    }

    /// Steps to mm: divided by the whole steps per mm where there are (so
    /// 700 steps of 0.01 mm are 7 mm exactly, 39 the double nearest 0.39),
    /// else times the unit.
    fn mm(&self, steps: f64) -> f64 {
        let per_mm = 1.0 / self.unit;
        if (per_mm - per_mm.round()).abs() < 1e-9 * per_mm {
            steps / per_mm.round()
        } else {
            steps * self.unit
        }
    }

    fn push(&mut self, kind: MoveKind, to: [f64; 3], named: AxisSet, feed: f64, c: &Command) {
        let mm = |v: [f64; 3]| Axes { x: self.mm(v[0]), y: self.mm(v[1]), z: self.mm(v[2]), ..Axes::ZERO };
        let m = Move {
            kind,
            start: mm(self.at),
            end: mm(to),
            feed,
            spindle: self.spindle,
            line: self.line_of(c.span.start as usize),
            named,
            ..Move::default()
        };
        self.out.toolpath.push(m);
        self.at = to;
        for k in 0..3 {
            self.known[k] |= named.contains(k);
        }
    }
}
