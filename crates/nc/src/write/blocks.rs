//! The block writer behind [`program`](super::program): what the control
//! knows at each point of the program, and the words of each block.

use kezuri_geom::{Axes, AxisSet, Coolant, Frame, Move, Plane, Spindle};

use super::dialect::{Codes, Dialect};
use super::options::{Arcs, Retract, Setup, WriteOptions};
use crate::number::{push_fixed, push_uint, POW10};
use crate::offsets::{EXTRA_OFFSETS, EXTRA_OFFSET_COUNT};
use crate::{Error, ErrorKind, Place};

/// Largest `N` number a Fanuc control reads.
pub(super) const MAX_SEQUENCE: u32 = 99_999;

/// Numbers must be smaller than this in size.
const LIMIT: f64 = 1e9;

/// How many axes a position has.
pub(super) const N: usize = Axes::COUNT;

pub(super) const AXIS_LETTERS: [char; N] = ['X', 'Y', 'Z', 'A', 'B', 'C', 'U', 'V', 'W'];

/// What a writer has handed on of the program, for the control's limits.
#[derive(Debug, Default)]
pub(super) struct Handed {
    /// Bytes.
    pub(super) bytes: u64,
    /// Blocks (lines).
    pub(super) blocks: u64,
    /// The first block longer than the control's line buffer.
    pub(super) too_long: Option<Error>,
}

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
    pub(super) digits: u32,
    /// 10^digits.
    pub(super) scale: f64,
    /// Write a decimal point on every axis word (Fanuc).
    pub(super) point: bool,
    pub(super) step: u32,
    pub(super) sequence: u32,
    /// Which of X Y Z A B C the program writes.
    pub(super) used: [bool; N],
    /// The control's position in units of the last digit (`None`: unknown).
    pub(super) pos: [Option<i64>; N],
    /// Write motions in `G91` where every position is exact.
    pub(super) incremental: bool,
    /// Whether the control is in `G91` (`None`: unknown, after a tool
    /// change in an incremental program).
    pub(super) relative: Option<bool>,
    /// Whether the control's position on each axis is exactly `pos`: the
    /// program wrote it, and nothing the writer cannot follow to the digit
    /// (a return to the reference point, `G53`, a probe, a new frame, a tool
    /// change) moved it since. Only incremental programs look at it.
    pub(super) exact: [bool; N],
    pub(super) motion: Option<Motion>,
    pub(super) plane: Option<Plane>,
    pub(super) feed: Option<i64>,
    pub(super) speed: Option<i64>,
    pub(super) spindle: Spindle,
    pub(super) coolant: Coolant,
    pub(super) tool: u32,
    /// The frame the control is in.
    pub(super) frame: Option<Frame>,
    /// The origin of each work offset as the control has it: first as the
    /// toolpath shows it, then as the program's `G10` set it.
    pub(super) origins: Vec<Option<Axes>>,
    /// The move being written is a block of increments from a position
    /// the program never named ([`Move::relative`]): `G91`, whatever the
    /// writer's own choice.
    pub(super) reckoned: bool,
    /// The program is in inches (`G20`).
    pub(super) inch: bool,
    /// A kept canned cycle is in force on the control: G80 before the next
    /// block that is not its next hole.
    pub(super) cycle_open: bool,
    /// The toolpath was made, not read from a program: its start is real
    /// ([`kezuri_geom::Toolpath::unknown_start`] is false).
    pub(super) generated: bool,
    /// Words in the block being written.
    pub(super) words: u32,
    /// Index and source line of the move being written.
    pub(super) at: (usize, u32),
    /// A made program's start, tool changes and end.
    pub(super) setup: Option<Setup>,
    /// Write comments.
    pub(super) comments: bool,
    pub(super) arcs: Arcs,
    /// Dwell `P` in milliseconds.
    pub(super) dwell_ms: bool,
    /// The length register to apply (`G43 H`) on the next block that moves
    /// Z: set by a made program's tool change.
    pub(super) pending_length: Option<u32>,
    /// The tools of the program in the order they are loaded, as the
    /// caller gave them, and how many of those changes are written: the
    /// next tool is pre-staged.
    pub(super) loads: Vec<u32>,
    pub(super) changes: usize,
    pub(super) block_limit: Option<u32>,
    pub(super) byte_limit: Option<u64>,
    /// What the writer has handed on of the program so far.
    pub(super) handed: Handed,
    /// `%` first and last.
    pub(super) percent: bool,
    pub(super) probe_code: Option<&'static str>,
    /// The tool in the spindle when the program starts (no pause for it
    /// on a control without a tool changer).
    pub(super) loaded: Option<u32>,
    /// The height of the next move where it is a rapid, in program units:
    /// where a made program with no retract takes the new tool before its
    /// spindle starts.
    pub(super) next_rapid_z: Option<f64>,
}

impl Writer {
    /// A writer for `o`, its options checked; it knows nothing of the
    /// program yet.
    pub(super) fn new(o: &WriteOptions) -> Result<Writer, Error> {
        let range = |name, value: u32, min, max| {
            if (min..=max).contains(&value) {
                Ok(())
            } else {
                Err(Error::new(ErrorKind::Option, format!("{name} {value} is out of range: it must be {min} to {max}")))
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
        Ok(Writer {
            out: String::with_capacity(256),
            dialect: o.dialect,
            codes: o.dialect.codes(),
            digits,
            scale: POW10[digits as usize] as f64,
            point: true,
            step: o.line_numbers.unwrap_or(0),
            sequence: o.line_numbers.unwrap_or(0),
            used: [true, true, true, false, false, false, false, false, false],
            pos: [None, None, None, Some(0), Some(0), Some(0), Some(0), Some(0), Some(0)],
            incremental: o.incremental,
            relative: Some(false),
            exact: [false; N],
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
            generated: true,
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
            handed: Handed::default(),
            percent: o.percent.unwrap_or(o.dialect == Dialect::Fanuc),
            loaded: o.loaded_tool,
            probe_code: o.probe_code,
            next_rapid_z: None,
        })
    }

    /// Takes in the axes move `m` (machine coordinates; the move being
    /// written, [`Writer::at`]) turns or names. Rotary axes and U V W are
    /// written from the first move that turns them, or (a program read)
    /// names them: `G00 A0.` moves A from wherever it is. Until then the
    /// program leaves them where they are. An axis the dialect has not is
    /// refused at that move.
    pub(super) fn take_axes(&mut self, m: &Move) -> Result<(), Error> {
        for p in [m.start.to_array(), m.end.to_array()] {
            for (k, letter) in AXIS_LETTERS.iter().enumerate().skip(3) {
                if !self.used[k] && self.turns(m, &p, k, !self.generated)? {
                    if !self.has_axis(k) {
                        let message = format!(
                            "{} has no {} {letter}, but the toolpath {} it",
                            self.dialect,
                            if k < 6 { "rotary axis" } else { "axis" },
                            if k < 6 { "turns" } else { "moves" }
                        );
                        let place = Place::Move { index: self.at.0, line: self.at.1 };
                        return Err(Error::new(ErrorKind::RotaryAxis, message).at(place));
                    }
                    self.use_axis(k);
                }
            }
        }
        Ok(())
    }

    /// The axes beyond X Y Z that `moves` turn or (`read`: moves of a
    /// program read) name, of those the dialect has: what
    /// [`Writer::take_axes`] would take in over them.
    pub(super) fn axes_ahead(&self, moves: &[Move], read: bool) -> AxisSet {
        let mut axes = AxisSet::NONE;
        for m in moves {
            let (start, end) = (m.start.to_array(), m.end.to_array());
            for k in 3..N {
                // A number no program can hold is refused at its move.
                let turns = |p| self.turns(m, p, k, read).unwrap_or(false);
                if self.has_axis(k) && !axes.contains(k) && (turns(&start) || turns(&end)) {
                    axes = axes.with(k);
                }
            }
        }
        axes
    }

    /// Writes axis `k` (beyond X Y Z) from here on, from a position not
    /// known until the program writes it.
    pub(super) fn use_axis(&mut self, k: usize) {
        if !self.used[k] {
            self.used[k] = true;
            self.pos[k] = None;
        }
    }

    /// Whether position `p` of move `m` turns axis `k` away from zero, or
    /// `m`, a move of a program read (`read`), names it.
    fn turns(&self, m: &Move, p: &[f64; N], k: usize, read: bool) -> Result<bool, Error> {
        let v = p[k];
        // A zero is written as 0 whatever the digits.
        let turned = v != 0.0 && self.fixed(v, AXIS_LETTERS[k])? != 0;
        Ok(turned || (read && m.named != AxisSet::ALL && m.named.contains(k)))
    }

    /// Whether the dialect has axis `k` (in [`AXIS_LETTERS`] order): X Y
    /// Z always, A B C but on GRBL, U V W on LinuxCNC only.
    pub(super) fn has_axis(&self, k: usize) -> bool {
        match k {
            0..3 => true,
            3..6 => self.dialect != Dialect::Grbl,
            _ => self.dialect == Dialect::LinuxCnc,
        }
    }

    /// A value in units of the last digit, or an error for a value no
    /// program can hold.
    pub(super) fn fixed(&self, v: f64, word: char) -> Result<i64, Error> {
        if !v.is_finite() || v.abs() >= LIMIT {
            return Err(self.number_error(word, v));
        }
        Ok((v * self.scale).round() as i64)
    }

    pub(super) fn number_error(&self, word: char, value: f64) -> Error {
        let place = Place::Move { index: self.at.0, line: self.at.1 };
        Error::new(ErrorKind::Number, format!("{word}{value} cannot be written in a program")).at(place)
    }

    /// Like [`Writer::fixed`] for values that cannot be negative.
    pub(super) fn non_negative(&self, v: f64, word: char) -> Result<i64, Error> {
        if v < 0.0 {
            return Err(self.number_error(word, v));
        }
        self.fixed(v, word)
    }

    /// The rounded position of the axes the program writes.
    pub(super) fn target(&self, p: Axes) -> Result<[i64; N], Error> {
        let v = p.to_array();
        let mut t = [0; N];
        for k in 0..N {
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
    pub(super) fn absolute_line(&mut self) {
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
        self.incremental && (0..N).all(|k| !self.used[k] || (self.pos[k].is_some() && self.exact[k]))
    }

    /// Starts a motion block: its `N` word and the `G90`/`G91` it needs.
    pub(super) fn motion_block(&mut self) {
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
    pub(super) fn reckon(&mut self, m: &Move) -> Result<(), Error> {
        self.reckoned = m.relative != AxisSet::NONE;
        if self.reckoned {
            let s = self.target(m.start)?;
            for k in (0..N).filter(|&k| self.used[k]) {
                self.pos[k] = Some(s[k]);
            }
        }
        Ok(())
    }

    /// A return to the reference point (`G91 G28` with the axes at zero
    /// travel to the intermediate point, then `G90`; an incremental program
    /// stays in `G91`); `end` is where the toolpath puts the tool after it,
    /// in program coordinates.
    pub(super) fn home(&mut self, axes: AxisSet, end: Axes) -> Result<(), Error> {
        self.end_cycle();
        let t = self.target(end)?;
        // Every axis the return names, even one the program never turns (a
        // `G28 C0` of the source): without axis words a G28 would return
        // every axis on Haas and LinuxCNC. GRBL has no rotary axes, only
        // LinuxCNC has U V W.
        let named: Vec<usize> = (0..N).filter(|&k| axes.contains(k) && self.has_axis(k)).collect();
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
    pub(super) fn machine(&mut self, axes: AxisSet, gauge: Axes, end: Axes) -> Result<(), Error> {
        self.end_cycle();
        let (g, t) = (self.target(gauge)?, self.target(end)?);
        self.block();
        self.distance(false);
        self.code("G53");
        self.code(self.codes.motion[Motion::Rapid as usize]);
        self.motion = Some(Motion::Rapid);
        let used = self.used;
        for k in (0..N).filter(|&k| axes.contains(k) && used[k]) {
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
    ) -> Result<(), Error> {
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

    pub(super) fn straight_to(&mut self, motion: Option<Motion>, t: [i64; N], feed: Option<i64>, named: AxisSet) {
        if !(0..N).any(|k| self.writes(k, &t, named)) {
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
            for k in (0..N).filter(|&k| moved[k]) {
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
    fn writes(&self, k: usize, t: &[i64; N], named: AxisSet) -> bool {
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
    pub(super) fn axis_words(&mut self, t: &[i64; N], named: AxisSet) -> [bool; N] {
        let relative = self.relative == Some(true);
        let mut moved = [false; N];
        for k in 0..N {
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

    pub(super) fn feed_word(&mut self, f: i64) {
        // A feed the program never gave is left to the control, not F0.
        if f == 0 && self.feed.is_none() {
            return;
        }
        if self.feed != Some(f) {
            self.word('F', f, self.point);
            self.feed = Some(f);
        }
    }

    pub(super) fn dwell(&mut self, seconds: f64) -> Result<(), Error> {
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
}

/// A block the program must give the control as written, at source line
/// `line`, that `dialect` has not.
pub(super) fn unsupported(dialect: Dialect, line: u32, text: &str) -> Error {
    let message = format!("{dialect} has no '{text}', which the machine must get as written");
    Error::new(ErrorKind::Unsupported, message).at(Place::Line(line))
}
