//! The block writer behind [`program`](super::program): what the control
//! knows at each point of the program, and the words of each block.

use std::f64::consts::PI;

use kezuri_geom::{Arc, Axes, AxisSet, Coolant, Frame, Move, Plane, Spindle, ToolState, Toolpath};

use super::gcode::{Dialect, WriteError, WriteOptions};
use super::post::{Arcs, CoolantChoice, Home, Retract, Setup};
use crate::interp::{EXTRA_OFFSETS, EXTRA_OFFSET_COUNT};

/// The words that differ between dialects ([`Dialect::codes`]), for
/// programs kezuri writes as text.
#[derive(Debug)]
pub struct Codes {
    /// Rapid, feed, clockwise and counter-clockwise arc (`G00`…`G03`).
    pub motion: [&'static str; 4],
    plane: [&'static str; 3],
    dwell: &'static str,
    probe: &'static str,
    spindle: [&'static str; 3],
    tool_change: &'static str,
    optional_stop: &'static str,
    /// Mist coolant, or the air blow (`M07`).
    pub mist: &'static str,
    flood: &'static str,
    /// Coolant off (`M09`).
    pub coolant_off: &'static str,
    home: &'static str,
    pub(super) length: [&'static str; 2],
    pub(super) length_cancel: &'static str,
    end: &'static str,
}

static FANUC: Codes = Codes {
    motion: ["G00", "G01", "G02", "G03"],
    plane: ["G17", "G18", "G19"],
    dwell: "G04",
    probe: "G31",
    spindle: ["M05", "M03", "M04"],
    tool_change: "M06",
    optional_stop: "M01",
    mist: "M07",
    flood: "M08",
    coolant_off: "M09",
    home: "G28",
    length: ["G43", "G44"],
    length_cancel: "G49",
    end: "M30",
};

static SHORT: Codes = Codes {
    motion: ["G0", "G1", "G2", "G3"],
    plane: ["G17", "G18", "G19"],
    dwell: "G4",
    probe: "G38.2",
    spindle: ["M5", "M3", "M4"],
    tool_change: "M6",
    optional_stop: "M1",
    mist: "M7",
    flood: "M8",
    coolant_off: "M9",
    home: "G28",
    length: ["G43", "G44"],
    length_cancel: "G49",
    end: "M2",
};

/// The safe start block after the units (`G21` or `G20`): absolute, XY
/// plane, feed per minute, no cutter compensation, no tool length offset, no
/// canned cycle, work offset G54 (the default [`Frame`]).
const SAFE_START: &str = "G90 G17 G94 G40 G49 G80 G54";

/// Largest `N` number a Fanuc control reads.
const MAX_SEQUENCE: u32 = 99_999;

/// Numbers must be smaller than this in size.
const LIMIT: f64 = 1e9;

pub(super) const AXIS_LETTERS: [char; 6] = ['X', 'Y', 'Z', 'A', 'B', 'C'];

const POW10: [u64; 7] = [1, 10, 100, 1_000, 10_000, 100_000, 1_000_000];

/// The motion modal group (group 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Motion {
    Rapid,
    Linear,
    Cw,
    Ccw,
}

/// The writer and what it knows of the control's state.
pub(super) struct Writer {
    pub(super) out: String,
    pub(super) dialect: Dialect,
    pub(super) codes: &'static Codes,
    digits: u32,
    /// 10^digits.
    scale: f64,
    /// Write a decimal point on every axis word (Fanuc).
    pub(super) point: bool,
    step: u32,
    sequence: u32,
    /// Which of X Y Z A B C the program writes.
    pub(super) used: [bool; 6],
    /// The control's position in units of the last digit (`None`: unknown).
    pub(super) pos: [Option<i64>; 6],
    /// Write motions in `G91` where every position is exact.
    incremental: bool,
    /// Whether the control is in `G91` (`None`: unknown, after a tool
    /// change in an incremental program).
    pub(super) relative: Option<bool>,
    /// Whether the control's position on each axis is exactly `pos`: the
    /// program wrote it, and nothing the writer cannot follow to the digit
    /// (a return to the reference point, `G53`, a probe, a new frame, a tool
    /// change) moved it since. Only incremental programs look at it.
    pub(super) exact: [bool; 6],
    pub(super) motion: Option<Motion>,
    plane: Option<Plane>,
    feed: Option<i64>,
    speed: Option<i64>,
    spindle: Spindle,
    coolant: Coolant,
    tool: u32,
    /// The frame the control is in.
    pub(super) frame: Option<Frame>,
    /// The origin of each work offset as the control has it: first as the
    /// toolpath shows it, then as the program's `G10` set it.
    pub(super) origins: Vec<Option<Axes>>,
    /// The move being written is a block of increments from a position
    /// the program never named ([`Move::relative`]): `G91`, whatever the
    /// writer's own choice.
    reckoned: bool,
    /// The program is in inches (`G20`).
    pub(super) inch: bool,
    /// A kept canned cycle is in force on the control: G80 before the next
    /// block that is not its next hole.
    pub(super) cycle_open: bool,
    /// The toolpath was made, not read from a program: its start is real
    /// ([`Toolpath::unknown_start`] is false).
    generated: bool,
    /// Words in the block being written.
    words: u32,
    /// Index and source line of the move being written.
    pub(super) at: (usize, u32),
    /// A made program's start, tool changes and end.
    setup: Option<Setup>,
    /// Write comments.
    comments: bool,
    arcs: Arcs,
    /// Dwell `P` in milliseconds.
    dwell_ms: bool,
    /// The length register to apply (`G43 H`) on the next block that moves
    /// Z: set by a made program's tool change.
    pending_length: Option<u32>,
    /// The tools of the toolpath in the order they are loaded, and how many
    /// of those changes are written: the next tool is pre-staged.
    loads: Vec<u32>,
    changes: usize,
    block_limit: Option<u32>,
    byte_limit: Option<u64>,
    /// `%` first and last.
    percent: bool,
    probe_code: Option<&'static str>,
    /// The tool in the spindle when the program starts (no pause for it
    /// on a control without a tool changer).
    loaded: Option<u32>,
    /// The height of the next move where it is a rapid, in program units:
    /// where a made program with no retract takes the new tool before its
    /// spindle starts.
    pub(super) next_rapid_z: Option<f64>,
}

impl Dialect {
    /// The dialect's words: `G00 M07` (Fanuc) or `G0 M7`.
    pub fn codes(self) -> &'static Codes {
        match self {
            Dialect::Fanuc => &FANUC,
            Dialect::LinuxCnc | Dialect::Grbl => &SHORT,
        }
    }
}

impl Writer {
    pub(super) fn new(toolpath: &Toolpath, o: &WriteOptions) -> Result<Writer, WriteError> {
        let range = |name, value: u32, min, max| {
            if (min..=max).contains(&value) {
                Ok(())
            } else {
                Err(WriteError::Option { name, value, min, max })
            }
        };
        range("digits", u32::from(o.digits), 0, POW10.len() as u32 - 1)?;
        if let Some(step) = o.line_numbers {
            range("line_numbers", step, 1, MAX_SEQUENCE)?;
        }
        if o.dialect == Dialect::Fanuc {
            range("program_number", o.program_number, 1, 9999)?;
        }
        let digits = u32::from(o.digits);
        let mut w = Writer {
            out: String::with_capacity(toolpath.moves.len() * 24 + 256),
            dialect: o.dialect,
            codes: o.dialect.codes(),
            digits,
            scale: POW10[digits as usize] as f64,
            point: true,
            step: o.line_numbers.unwrap_or(0),
            sequence: o.line_numbers.unwrap_or(0),
            used: [true, true, true, false, false, false],
            pos: [None, None, None, Some(0), Some(0), Some(0)],
            incremental: o.incremental,
            relative: Some(false),
            exact: [false; 6],
            motion: None,
            plane: Some(Plane::Xy),
            feed: None,
            speed: Some(0),
            spindle: Spindle::Off,
            coolant: Coolant::default(),
            tool: 0,
            frame: Some(Frame::default()),
            origins: vec![None; EXTRA_OFFSETS + EXTRA_OFFSET_COUNT],
            reckoned: false,
            inch: o.inch,
            cycle_open: false,
            generated: !toolpath.unknown_start,
            words: 0,
            at: (0, 0),
            setup: o.setup.clone(),
            comments: o.comments,
            arcs: o.arcs,
            dwell_ms: o.dwell_ms.unwrap_or(o.dialect == Dialect::Fanuc),
            pending_length: None,
            loads: Vec::new(),
            changes: 0,
            block_limit: o.block_limit,
            byte_limit: o.byte_limit,
            percent: o.percent.unwrap_or(o.dialect == Dialect::Fanuc),
            loaded: o.loaded_tool,
            probe_code: o.probe_code,
            next_rapid_z: None,
        };
        for m in toolpath.moves.iter().filter(|m| m.tool != 0) {
            if w.loads.last() != Some(&m.tool) {
                w.loads.push(m.tool);
            }
        }
        // Rotary axes are written only if the toolpath turns them, or (a
        // program read) names them: `G00 A0.` moves A from wherever it is.
        for (index, m) in toolpath.moves.iter().enumerate() {
            w.at = (index, m.line);
            let named = toolpath.unknown_start && m.named != AxisSet::ALL;
            for p in [m.start, m.end] {
                let v = p.to_array();
                for k in 3..6 {
                    let wanted = w.fixed(v[k], AXIS_LETTERS[k])? != 0 || (named && m.named.contains(k));
                    if !w.used[k] && wanted {
                        if w.dialect == Dialect::Grbl {
                            return Err(WriteError::RotaryAxis {
                                index,
                                line: m.line,
                                axis: AXIS_LETTERS[k],
                                dialect: w.dialect,
                            });
                        }
                        w.used[k] = true;
                        w.pos[k] = None;
                    }
                }
            }
        }
        Ok(w)
    }

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

    /// The last block and the closing line; the program text. An
    /// incremental program goes back to `G90` first.
    pub(super) fn finish(mut self) -> Result<String, WriteError> {
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
        self.check_limits()?;
        Ok(self.out)
    }

    /// Refuses a program longer than the control's memory, or with a block
    /// longer than its line buffer.
    fn check_limits(&self) -> Result<(), WriteError> {
        if let Some(limit) = self.block_limit {
            let kept = |l: &str| kept_length(l) as u64;
            if let Some((n, l)) = self.out.lines().enumerate().find(|(_, l)| kept(l) > u64::from(limit)) {
                return Err(WriteError::Limit {
                    what: format!("block {} of the program ('{l}')", n + 1),
                    length: kept(l),
                    limit: u64::from(limit),
                    unit: "characters",
                });
            }
        }
        match self.byte_limit {
            Some(limit) if self.out.len() as u64 > limit => Err(WriteError::Limit {
                what: "the program".into(),
                length: self.out.len() as u64,
                limit,
                unit: "bytes (drip-feed it, or cut it in parts)",
            }),
            _ => Ok(()),
        }
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

    /// A value in units of the last digit, or an error for a value no
    /// program can hold.
    pub(super) fn fixed(&self, v: f64, word: char) -> Result<i64, WriteError> {
        if !v.is_finite() || v.abs() >= LIMIT {
            return Err(self.number_error(word, v));
        }
        Ok((v * self.scale).round() as i64)
    }

    fn number_error(&self, word: char, value: f64) -> WriteError {
        WriteError::Number { index: self.at.0, line: self.at.1, word, value }
    }

    /// Like [`Writer::fixed`] for values that cannot be negative.
    fn non_negative(&self, v: f64, word: char) -> Result<i64, WriteError> {
        if v < 0.0 {
            return Err(self.number_error(word, v));
        }
        self.fixed(v, word)
    }

    /// The rounded position of the axes the program writes.
    pub(super) fn target(&self, p: Axes) -> Result<[i64; 6], WriteError> {
        let v = p.to_array();
        let mut t = [0; 6];
        for k in 0..6 {
            if self.used[k] {
                t[k] = self.fixed(v[k], AXIS_LETTERS[k])?;
            }
        }
        Ok(t)
    }

    /// Ends a kept canned cycle still in force (G80): before anything that
    /// moves, changes the tool or the frame, or ends the program. Spindle,
    /// coolant and M codes between its holes leave it on, as in the source.
    pub(super) fn end_cycle(&mut self) {
        if self.cycle_open {
            self.cycle_open = false;
            self.line("G80");
        }
    }

    /// Starts a block: its `N` word when blocks are numbered.
    pub(super) fn block(&mut self) {
        self.words = 0;
        if self.step > 0 {
            self.space();
            self.out.push('N');
            push_uint(&mut self.out, u64::from(self.sequence));
            self.sequence =
                if self.sequence > MAX_SEQUENCE - self.step { self.step } else { self.sequence + self.step };
        }
    }

    pub(super) fn space(&mut self) {
        if self.words > 0 {
            self.out.push(' ');
        }
        self.words += 1;
    }

    pub(super) fn code(&mut self, code: &str) {
        self.space();
        self.out.push_str(code);
    }

    /// A word whose value is `n` units of the last digit.
    pub(super) fn word(&mut self, letter: char, n: i64, point: bool) {
        self.space();
        self.out.push(letter);
        push_fixed(&mut self.out, n, self.digits, point);
    }

    /// The word `letter` `n` (units of the last digit) as text.
    pub(super) fn word_text(&self, letter: char, n: i64, point: bool) -> String {
        let mut out = letter.to_string();
        push_fixed(&mut out, n, self.digits, point);
        out
    }

    /// One block holding only `code`.
    pub(super) fn line(&mut self, code: &str) {
        self.block();
        self.code(code);
        self.out.push('\n');
    }

    /// In the block being written, `G91` (`relative`) or `G90` where the
    /// control is not in that mode already.
    pub(super) fn distance(&mut self, relative: bool) {
        if self.relative != Some(relative) {
            self.code(if relative { "G91" } else { "G90" });
            self.relative = Some(relative);
        }
    }

    /// A `G90` block where the control may be in `G91`.
    fn absolute_line(&mut self) {
        if self.relative != Some(false) {
            self.block();
            self.distance(false);
            self.out.push('\n');
        }
    }

    /// Whether the next motion block is written in `G91`: in an incremental
    /// program, where the position on every axis the program writes is
    /// known and exact.
    fn wants_relative(&self) -> bool {
        self.incremental && (0..6).all(|k| !self.used[k] || (self.pos[k].is_some() && self.exact[k]))
    }

    /// Starts a motion block: its `N` word and the `G90`/`G91` it needs.
    fn motion_block(&mut self) {
        self.end_cycle();
        self.block();
        let relative = self.reckoned || self.wants_relative();
        self.distance(relative);
    }

    /// Prepares move `m`, given in program coordinates: a move of
    /// increments from a position the program never named
    /// ([`Move::relative`]) is written in `G91` from its own start, so the
    /// increments are the toolpath's, not differences from a position the
    /// machine model reckoned.
    pub(super) fn reckon(&mut self, m: &Move) -> Result<(), WriteError> {
        self.reckoned = m.relative != AxisSet::NONE;
        if self.reckoned {
            let s = self.target(m.start)?;
            for k in (0..6).filter(|&k| self.used[k]) {
                self.pos[k] = Some(s[k]);
            }
        }
        Ok(())
    }

    /// Tool, spindle and coolant blocks that bring the control to state
    /// `m`.
    pub(super) fn state(&mut self, mut m: ToolState) -> Result<(), WriteError> {
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
        for k in 0..6 {
            if self.used[k] {
                self.pos[k] = None;
            }
        }
        self.motion = None;
        self.plane = None;
        self.feed = None;
        self.exact = [false; 6];
        if self.incremental {
            // The macro may leave the control in G91: G90 is written again.
            self.relative = None;
        }
    }

    /// A return to the reference point (`G91 G28` with the axes at zero
    /// travel to the intermediate point, then `G90`; an incremental program
    /// stays in `G91`); `end` is where the toolpath puts the tool after it,
    /// in program coordinates.
    pub(super) fn home(&mut self, axes: AxisSet, end: Axes) -> Result<(), WriteError> {
        self.end_cycle();
        let t = self.target(end)?;
        // Every axis the return names, even one the program never turns (a
        // `G28 C0` of the source): without axis words a G28 would return
        // every axis on Haas and LinuxCNC. GRBL has no rotary axes.
        let grbl = self.dialect == Dialect::Grbl;
        let named: Vec<usize> = (0..6).filter(|&k| axes.contains(k) && (k < 3 || !grbl)).collect();
        if named.is_empty() {
            return Ok(());
        }
        self.block();
        self.code("G91");
        self.relative = Some(true);
        self.code(self.codes.home);
        for k in named {
            self.word(AXIS_LETTERS[k], 0, self.point);
            if self.used[k] {
                self.pos[k] = Some(t[k]);
                self.exact[k] = false;
            }
        }
        self.out.push('\n');
        if !self.incremental {
            self.absolute_line();
        }
        Ok(())
    }

    /// Positioning in machine coordinates (`G53` at rapid): `gauge` is the
    /// spindle gauge line in machine coordinates, `end` the tool tip after
    /// it in program coordinates.
    pub(super) fn machine(&mut self, axes: AxisSet, gauge: Axes, end: Axes) -> Result<(), WriteError> {
        self.end_cycle();
        let (g, t) = (self.target(gauge)?, self.target(end)?);
        self.block();
        self.distance(false);
        self.code("G53");
        self.code(self.codes.motion[Motion::Rapid as usize]);
        self.motion = Some(Motion::Rapid);
        let used = self.used;
        for k in (0..6).filter(|&k| axes.contains(k) && used[k]) {
            self.word(AXIS_LETTERS[k], g[k], self.point);
            self.pos[k] = Some(t[k]);
            self.exact[k] = false;
        }
        self.out.push('\n');
        Ok(())
    }

    /// A straight move to `end`: `motion` is `None` for a probe move; `feed`
    /// is `None` for a rapid.
    pub(super) fn straight(
        &mut self,
        motion: Option<Motion>,
        end: Axes,
        feed: Option<f64>,
        named: AxisSet,
    ) -> Result<(), WriteError> {
        let t = self.target(end)?;
        let feed = feed.map(|f| self.non_negative(f, 'F')).transpose()?;
        // A made program's first rapid after a tool change never moves Z
        // from a height it does not know over a place it does not know:
        // after a retract, X Y first at the top (the made toolpath's end
        // is real, whichever axes the move names), then Z with the length
        // offset; without one (a hand change, the tool on the stock), Z
        // first.
        if let (Some(s), Some(Motion::Rapid), None) = (&self.setup, motion, self.pos[2]) {
            if self.writes(2, &t, named) {
                if s.retract != Retract::None && self.generated && (self.pos[0].is_none() || self.pos[1].is_none()) {
                    self.straight_to(motion, t, feed, AxisSet(0b011));
                } else if s.retract == Retract::None && (0..2).any(|k| self.writes(k, &t, named)) {
                    self.straight_to(motion, t, feed, AxisSet::NONE.with(2));
                }
            }
        }
        self.straight_to(motion, t, feed, named);
        Ok(())
    }

    fn straight_to(&mut self, motion: Option<Motion>, t: [i64; 6], feed: Option<i64>, named: AxisSet) {
        if !(0..6).any(|k| self.writes(k, &t, named)) {
            return;
        }
        self.motion_block();
        // A made program's length offset comes on with the first Z move
        // after the tool change, the motion code written with it (LinuxCNC
        // refuses G43 with Z and no motion mode).
        let length = if self.writes(2, &t, named) { self.pending_length.take() } else { None };
        if length.is_some() {
            self.motion = None;
        }
        match motion {
            Some(g) if self.motion != Some(g) => {
                self.code(self.codes.motion[g as usize]);
                self.motion = Some(g);
            }
            Some(_) => {}
            None => {
                self.code(self.probe_code.unwrap_or(self.codes.probe));
                self.motion = None;
            }
        }
        if let Some(h) = length {
            self.code(self.codes.length[0]);
            self.space();
            self.out.push('H');
            push_uint(&mut self.out, u64::from(h));
        }
        let moved = self.axis_words(&t, named);
        if motion.is_none() {
            // A probe stops where it touches, not at its end.
            for k in (0..6).filter(|&k| moved[k]) {
                self.exact[k] = false;
            }
        }
        if let Some(f) = feed {
            self.feed_word(f);
        }
        self.out.push('\n');
    }

    /// Whether a move to `t` naming `named` writes axis `k`: where the
    /// control's position is known, when it changes; where it is not (at the
    /// start, after a tool change), when the move names the axis, so that an
    /// axis the source program left alone is never commanded to the model's
    /// guess of where it is.
    fn writes(&self, k: usize, t: &[i64; 6], named: AxisSet) -> bool {
        match self.pos[k] {
            // Where the position is only reckoned (after a return, G53, a
            // new frame, a tool change), a named axis is written even at
            // the reckoned value: the control may be elsewhere.
            Some(p) => p != t[k] || (!self.exact[k] && self.used[k] && named.contains(k)),
            None => self.used[k] && named.contains(k),
        }
    }

    /// The axis words of `t` that [`Writer::writes`], absolute or, in
    /// `G91`, as the difference from the control's position; the control's
    /// position becomes `t` on those axes, exactly. Returns which axes were
    /// written.
    fn axis_words(&mut self, t: &[i64; 6], named: AxisSet) -> [bool; 6] {
        let relative = self.relative == Some(true);
        let mut moved = [false; 6];
        for k in 0..6 {
            if self.writes(k, t, named) {
                let n = match self.pos[k] {
                    // G91 is written only where every position is known.
                    Some(p) if relative => t[k] - p,
                    _ => t[k],
                };
                self.word(AXIS_LETTERS[k], n, self.point);
                self.pos[k] = Some(t[k]);
                // After increments from a reckoned position, the position is
                // the machine model's: only increments stay exact.
                self.exact[k] = !self.reckoned;
                moved[k] = true;
            }
        }
        moved
    }

    fn feed_word(&mut self, f: i64) {
        // A feed the program never gave is left to the control, not F0.
        if f == 0 && self.feed.is_none() {
            return;
        }
        if self.feed != Some(f) {
            self.word('F', f, self.point);
            self.feed = Some(f);
        }
    }

    pub(super) fn dwell(&mut self, seconds: f64) -> Result<(), WriteError> {
        self.end_cycle();
        if !(0.0..LIMIT).contains(&seconds) {
            return Err(self.number_error('P', seconds));
        }
        let ms = (seconds * 1000.0).round() as i64;
        self.block();
        self.code(self.codes.dwell);
        self.space();
        if self.dwell_ms {
            self.out.push('P');
            push_fixed(&mut self.out, ms, 0, false);
        } else if self.dialect == Dialect::Fanuc {
            // Fanuc's P is milliseconds: seconds are X.
            self.out.push('X');
            push_fixed(&mut self.out, ms, 3, true);
        } else {
            self.out.push('P');
            push_fixed(&mut self.out, ms, 3, false);
        }
        self.out.push('\n');
        Ok(())
    }

    pub(super) fn arc(&mut self, m: &Move, arc: Arc) -> Result<(), WriteError> {
        let feed = self.non_negative(m.feed, 'F')?;
        let start = self.target(m.start)?;
        let exact = m.start.to_array();
        // Where the control's position is unknown, a generated toolpath's
        // start is real and is reached; an NC program's arc starts wherever
        // the control is, as in the source (never a move to the model's
        // guess).
        let away = (0..6).any(|k| match self.pos[k] {
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
                for k in (3..6).chain([n]) {
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
    fn chords(&mut self, m: &Move, arc: Arc, feed: i64) -> Result<(), WriteError> {
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
                let mut p: [f64; 6] = std::array::from_fn(|a| s[a] + (e[a] - s[a]) * f);
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
    fn single_arc(&mut self, start: Axes, end: Axes, arc: Arc, feed: i64, named: AxisSet) -> Result<(), WriteError> {
        let (i, j, _) = arc.plane.axes();
        let mut t = self.target(end)?;
        // The start is the control's position where it is known, else the
        // toolpath's start (the centre is given from there, as the source
        // gave it).
        let from = self.target(start)?;
        let s: [i64; 6] = std::array::from_fn(|k| self.pos[k].unwrap_or(from[k]));
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
                let mut mid: [f64; 6] = std::array::from_fn(|k| (sv[k] + ev[k]) / 2.0);
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
    fn written_sweep(&self, arc: Arc, s: &[i64; 6], t: &[i64; 6], offset: [i64; 2]) -> f64 {
        let (i, j, _) = arc.plane.axes();
        let unit = |v: i64| v as f64 / self.scale;
        let point = |p: &[i64; 6]| Axes { x: unit(p[0]), y: unit(p[1]), z: unit(p[2]), ..Axes::ZERO };
        let mut center = [0.0; 3];
        center[i] = unit(s[i] + offset[0]);
        center[j] = unit(s[j] + offset[1]);
        Arc { center, ..arc }.sweep(point(s), point(t))
    }
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

/// Writes `n` units of the last of `digits` decimals: trailing zeros
/// trimmed, never `-0`, and with `point` a decimal point even on whole
/// numbers.
fn push_fixed(out: &mut String, n: i64, digits: u32, point: bool) {
    if n < 0 {
        out.push('-');
    }
    let a = n.unsigned_abs();
    let p = POW10[digits as usize];
    push_uint(out, a / p);
    let frac = a % p;
    if frac != 0 {
        out.push('.');
        push_padded(out, frac, digits);
        // Trailing zeros go; a non-zero digit stops it before the point.
        while out.ends_with('0') {
            out.pop();
        }
    } else if point {
        out.push('.');
    }
}

pub(super) fn push_uint(out: &mut String, v: u64) {
    push_padded(out, v, 1);
}

/// Writes `v` with at least `width` digits (leading zeros).
fn push_padded(out: &mut String, mut v: u64, width: u32) {
    let mut buf = [b'0'; 20];
    let mut i = buf.len();
    while v > 0 || buf.len() - i < width as usize {
        i -= 1;
        buf[i] = b'0' + (v % 10) as u8;
        v /= 10;
    }
    for &b in &buf[i..] {
        out.push(char::from(b));
    }
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
