//! Post-processor presets: how a program kezuri makes begins, changes
//! tools and ends on a given control ([`Setup`]), and how any program is
//! formatted for it (the other fields of [`WriteOptions`]); and the blocks
//! of a program's start, its tool changes and retracts, and its end.
//!
//! Where each preset's conventions come from is in `docs/post.md`.

use std::collections::BTreeMap;

use kezuri_geom::{Axes, AxisSet, Coolant, Spindle, ToolState};

use super::blocks::{Motion, Writer, N};
use super::dialect::Dialect;
use super::options::{CoolantChoice, Home, Retract, Setup, WriteOptions};
use crate::number::{push_padded, push_uint};
use crate::{Error, ErrorKind};

/// The presets `--post` names.
pub const PRESETS: [&str; 5] = ["fanuc", "haas", "linuxcnc", "grbl", "mach3"];

impl WriteOptions {
    /// The options of preset `name` (any letter case): its dialect,
    /// formatting and [`Setup`]. Digits, units, title and line numbers are
    /// the defaults; the caller sets them.
    ///
    /// ```
    /// use kezuri_nc::write::{Retract, WriteOptions};
    /// let haas = WriteOptions::preset("Haas").unwrap();
    /// let setup = haas.setup.unwrap();
    /// assert!(setup.prestage && setup.length_offset && setup.retract == Retract::MachineZero);
    /// assert!(WriteOptions::preset("okuma").is_err());
    /// ```
    pub fn preset(name: &str) -> Result<WriteOptions, Error> {
        let name = name.trim().to_ascii_lowercase();
        let fanuc = Setup {
            start: "G90 G17 G94 G40 G49 G80".into(),
            work_offset: "G54".into(),
            retract: Retract::Reference,
            prestage: false,
            optional_stop: true,
            length_offset: true,
            registers: BTreeMap::new(),
            spindle_dwell: 0.0,
            coolant: CoolantChoice::Flood,
            home: Home::Reference,
            end: "M30".into(),
        };
        let (dialect, setup, dwell_ms, block_limit) = match name.as_str() {
            "fanuc" => (Dialect::Fanuc, fanuc, None, None),
            "haas" => (
                Dialect::Fanuc,
                Setup {
                    start: "G00 G17 G40 G49 G80 G90 G94".into(),
                    prestage: true,
                    retract: Retract::MachineZero,
                    home: Home::Park([0.0, 0.0]),
                    ..fanuc
                },
                None,
                None,
            ),
            "linuxcnc" => (
                Dialect::LinuxCnc,
                Setup {
                    start: "G90 G17 G94 G40 G49 G80 G91.1".into(),
                    retract: Retract::MachineZero,
                    home: Home::None,
                    spindle_dwell: 2.0,
                    coolant: CoolantChoice::Off,
                    end: "M2".into(),
                    ..fanuc
                },
                None,
                None,
            ),
            "grbl" => (
                Dialect::Grbl,
                Setup {
                    start: "G90 G17 G94".into(),
                    retract: Retract::None,
                    optional_stop: false,
                    length_offset: false,
                    home: Home::None,
                    spindle_dwell: 3.0,
                    coolant: CoolantChoice::Off,
                    end: "M2".into(),
                    ..fanuc
                },
                None,
                Some(80),
            ),
            "mach3" => (
                Dialect::LinuxCnc,
                Setup {
                    start: "G90 G17 G94 G40 G49 G80 G91.1".into(),
                    spindle_dwell: 2.0,
                    coolant: CoolantChoice::Off,
                    ..fanuc
                },
                Some(false),
                None,
            ),
            _ => {
                let message = format!("unknown post '{name}': expected {}", PRESETS.join(", "));
                return Err(Error::new(ErrorKind::UnknownPost, message));
            }
        };
        // Mach3 probes with G31 (it has no G38.2).
        let probe_code = (name == "mach3").then_some("G31");
        Ok(WriteOptions { dialect, setup: Some(setup), dwell_ms, block_limit, probe_code, ..WriteOptions::default() })
    }
}

/// The safe start block after the units (`G21` or `G20`): absolute, XY
/// plane, feed per minute, no cutter compensation, no tool length offset, no
/// canned cycle, work offset G54 (the default [`Frame`]).
const SAFE_START: &str = "G90 G17 G94 G40 G49 G80 G54";

impl Writer {
    pub(super) fn header(&mut self, o: &WriteOptions) {
        let title = o.title.as_deref().map(str::trim).filter(|t| !t.is_empty() && o.comments);
        if self.percent {
            self.out.push_str("%\n");
        }
        if self.dialect == Dialect::Fanuc {
            self.out.push('O');
            push_padded(&mut self.out, u64::from(o.program_number), 4);
            if let Some(t) = title {
                self.out.push(' ');
                push_comment(&mut self.out, t);
            }
            self.out.push('\n');
        } else if let Some(t) = title {
            push_comment(&mut self.out, t);
            self.out.push('\n');
        }
        for note in o.notes.iter().filter(|_| o.comments) {
            push_comment(&mut self.out, note);
            self.out.push('\n');
        }
        let units = if o.inch { "G20" } else { "G21" };
        match &o.setup {
            // The units, the safe start and the work offset each on a block
            // of its own: a control reads only so many G codes in one.
            Some(s) => {
                for code in [units, &s.start, &s.work_offset].into_iter().filter(|c| !c.trim().is_empty()) {
                    self.line(code.trim());
                }
            }
            None => {
                self.block();
                self.code(units);
                self.code(SAFE_START);
                self.out.push('\n');
            }
        }
    }

    /// The last block and the closing line: the rest of the program's
    /// text. An incremental program goes back to `G90` first. The
    /// control's limits are checked over the whole program handed on.
    pub(super) fn finish(&mut self) -> Result<String, Error> {
        self.end_cycle();
        self.absolute_line();
        let end = match self.setup.clone() {
            Some(setup) => {
                self.stop_spindle_and_coolant();
                self.retract(setup.retract);
                match setup.home {
                    Home::Reference => self.reference_return("X0. Y0."),
                    Home::Park(p) => {
                        // mm in the machine file; the program's units here.
                        let unit = if self.inch { 1.0 / 25.4 } else { 1.0 };
                        let (x, y) = (self.fixed(p[0] * unit, 'X')?, self.fixed(p[1] * unit, 'Y')?);
                        self.block();
                        self.code("G53");
                        self.code(self.codes.motion[Motion::Rapid as usize]);
                        self.word('X', x, self.point);
                        self.word('Y', y, self.point);
                        self.out.push('\n');
                    }
                    Home::None => {}
                }
                setup.end.trim().to_string()
            }
            None => self.codes.end.to_string(),
        };
        self.block();
        self.code(&end);
        self.out.push('\n');
        if self.percent {
            self.out.push_str("%\n");
        }
        let text = self.hand_out();
        if let Some(e) = self.handed.too_long.take() {
            return Err(e);
        }
        match self.byte_limit {
            Some(limit) if self.handed.bytes > limit => {
                let unit = "bytes (drip-feed it, or cut it in parts)";
                Err(limit_error("the program", self.handed.bytes, limit, unit))
            }
            _ => Ok(text),
        }
    }

    /// The text written since the last call, taken and counted: its
    /// blocks are checked against the control's line buffer (the first
    /// too long is refused at the end, as a whole program's would be).
    pub(super) fn hand_out(&mut self) -> String {
        let text = std::mem::take(&mut self.out);
        if let Some(limit) = self.block_limit {
            if self.handed.too_long.is_none() {
                let kept = |l: &str| kept_length(l) as u64;
                if let Some((n, l)) = text.lines().enumerate().find(|(_, l)| kept(l) > u64::from(limit)) {
                    let what = format!("block {} of the program ('{l}')", self.handed.blocks + n as u64 + 1);
                    self.handed.too_long = Some(limit_error(&what, kept(l), u64::from(limit), "characters"));
                }
            }
            self.handed.blocks += text.lines().count() as u64;
        }
        self.handed.bytes += text.len() as u64;
        text
    }

    /// `G91 G28` of `axes` (`Z0.`), then `G90`: every return is followed
    /// by absolute before any motion.
    fn reference_return(&mut self, axes: &str) {
        self.block();
        self.code("G91");
        self.code(self.codes.home);
        self.code(axes);
        self.out.push('\n');
        self.relative = Some(true);
        self.absolute_line();
    }

    /// The words that apply the length offset a made program's tool change
    /// left to do (`G43 H1`), taken: the caller writes them.
    pub(super) fn take_pending_length(&mut self) -> Option<String> {
        self.pending_length.take().map(|h| format!("{} H{h}", self.codes.length[0]))
    }

    /// A made program's retract before a tool change and at the end.
    fn retract(&mut self, retract: Retract) {
        match retract {
            Retract::Reference => self.reference_return("Z0."),
            Retract::MachineZero => {
                self.absolute_line();
                self.block();
                self.code("G53");
                self.code(self.codes.motion[Motion::Rapid as usize]);
                self.code("Z0.");
                self.out.push('\n');
                self.motion = Some(Motion::Rapid);
            }
            Retract::None => {}
        }
        if retract != Retract::None {
            self.pos[2] = None;
            self.exact[2] = false;
        }
    }

    /// `M05` and `M09` where the spindle or the coolant is on.
    fn stop_spindle_and_coolant(&mut self) {
        if self.spindle != Spindle::Off {
            self.line(self.codes.spindle[0]);
            self.spindle = Spindle::Off;
        }
        if self.coolant != Coolant::default() {
            self.line(self.codes.coolant_off);
            self.coolant = Coolant::default();
        }
    }

    /// Tool, spindle and coolant blocks that bring the control to state
    /// `m`.
    pub(super) fn state(&mut self, mut m: ToolState) -> Result<(), Error> {
        if m.tool != self.tool {
            self.tool_change(m.tool);
            // After a hand change the tip may rest on the stock: up to the
            // next rapid's height before the spindle starts.
            let by_hand = self.setup.as_ref().is_some_and(|s| s.retract == Retract::None);
            if let (true, Some(z)) = (by_hand, self.next_rapid_z) {
                self.straight(Some(Motion::Rapid), Axes { z, ..Axes::ZERO }, None, AxisSet::NONE.with(2))?;
            }
        }
        // A made program's coolant comes on with the spindle.
        let dwell = match &self.setup {
            Some(s) => {
                if m.spindle != Spindle::Off {
                    m.coolant =
                        Coolant { flood: s.coolant == CoolantChoice::Flood, mist: s.coolant == CoolantChoice::Mist };
                }
                s.spindle_dwell
            }
            None => 0.0,
        };
        let speed = self.non_negative(m.speed, 'S')?;
        let turns_on = m.spindle != Spindle::Off && m.spindle != self.spindle;
        // A speed of 0 is no speed (an M03 without S, RML-1's !MC1): S0
        // would stop the spindle, so the control keeps the S it has.
        let new_speed = speed != 0 && (turns_on || Some(speed) != self.speed);
        if new_speed || m.spindle != self.spindle {
            self.block();
            if new_speed {
                self.word('S', speed, false);
                self.speed = Some(speed);
            }
            if m.spindle != self.spindle {
                let code = match m.spindle {
                    Spindle::Off => self.codes.spindle[0],
                    Spindle::Cw => self.codes.spindle[1],
                    Spindle::Ccw => self.codes.spindle[2],
                };
                self.code(code);
                self.spindle = m.spindle;
            }
            self.out.push('\n');
            // Time to come up to speed before the first move.
            if turns_on && dwell > 0.0 {
                self.dwell(dwell)?;
            }
        }
        let (was, now) = (self.coolant, m.coolant);
        if was != now {
            if (was.mist && !now.mist) || (was.flood && !now.flood) {
                self.line(self.codes.coolant_off);
                self.coolant = Coolant::default();
            }
            if now.mist && !self.coolant.mist {
                self.line(self.codes.mist);
            }
            if now.flood && !self.coolant.flood {
                self.line(self.codes.flood);
            }
            self.coolant = now;
        }
        Ok(())
    }

    fn tool_change(&mut self, tool: u32) {
        self.end_cycle();
        // The macro runs in absolute.
        self.absolute_line();
        let setup = self.setup.clone();
        self.stop_spindle_and_coolant();
        if let Some(s) = &setup {
            self.retract(s.retract);
            // An optional stop to look at the last tool's work, the tool
            // up and everything off.
            if s.optional_stop && self.changes > 0 {
                self.line(self.codes.optional_stop);
            }
        }
        if self.dialect == Dialect::Grbl {
            if self.loaded == Some(tool) {
                // The operator started the program with it in.
            } else {
                if self.comments {
                    self.out.push_str("(TOOL CHANGE: PUT IN TOOL ");
                    push_uint(&mut self.out, u64::from(tool));
                    // Without a length offset in the program (a made one),
                    // the new tip must be set to the program's Z zero by
                    // hand; a program's own G43.1 sets it.
                    if setup.as_ref().is_some_and(|s| !s.length_offset) {
                        self.out.push_str(", SET Z ZERO ON ITS TIP AT THE PROGRAM'S Z ZERO");
                    }
                    self.out.push_str(", THEN RESUME)\n");
                }
                self.line("M0");
            }
        } else {
            self.block();
            self.space();
            self.out.push('T');
            push_uint(&mut self.out, u64::from(tool));
            self.code(self.codes.tool_change);
            self.out.push('\n');
            let next = self.loads.get(self.changes + 1).copied().filter(|&t| t != tool);
            if let (Some(next), true) = (next, setup.as_ref().is_some_and(|s| s.prestage)) {
                self.block();
                self.space();
                self.out.push('T');
                push_uint(&mut self.out, u64::from(next));
                self.out.push('\n');
            }
        }
        if tool != 0 {
            self.changes += 1;
        }
        self.pending_length = setup.as_ref().filter(|s| s.length_offset && tool != 0).map(|s| s.register(tool));
        // A tool change macro may move the axes and change modal words.
        self.tool = tool;
        for k in 0..N {
            if self.used[k] {
                self.pos[k] = None;
            }
        }
        self.motion = None;
        self.plane = None;
        self.feed = None;
        self.exact = [false; N];
        if self.incremental {
            // The macro may leave the control in G91: G90 is written again.
            self.relative = None;
        }
    }
}

/// `what` is `length` `unit`, more than the control's `limit`.
fn limit_error(what: &str, length: u64, limit: u64, unit: &str) -> Error {
    Error::new(ErrorKind::Limit, format!("{what} is {length} {unit}, more than the {limit} the control takes"))
}

/// The characters of block `line` a control keeps in its line buffer: its
/// words, without spaces and comments.
fn kept_length(line: &str) -> usize {
    let mut depth = 0;
    let mut n = 0;
    for c in line.chars() {
        match c {
            ';' if depth == 0 => break,
            '(' => depth += 1,
            ')' if depth > 0 => depth -= 1,
            c if depth == 0 && !c.is_whitespace() => n += 1,
            _ => {}
        }
    }
    n
}

/// Writes `text` as a comment `( … )`, with characters that would end it
/// or the tape replaced.
fn push_comment(out: &mut String, text: &str) {
    out.push('(');
    for c in text.chars() {
        out.push(match c {
            '(' => '[',
            ')' => ']',
            '%' => '_',
            c if c == ' ' || c.is_ascii_graphic() => c,
            _ => '_',
        });
    }
    out.push(')');
}
