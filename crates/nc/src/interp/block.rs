//! One NC block: evaluate its words, then apply it completely.

use kezuri_geom::{Arc, Axes, AxisSet, Move, MoveKind, Spindle};

use super::modal::{Cycle, Distance, FeedMode, GCode, ModalCallKind, Motion, Units};
use super::value::Value;
use super::vars::Locals;
use super::words::Words;
use super::{Control, IntegerInput, ModalCall, State};
use crate::ast::Program;
use crate::offsets::{EXTRA_OFFSETS, EXTRA_OFFSET_COUNT};
use crate::source::{Diagnostic, Span};

/// What the block pointer does after a block.
pub(super) enum Action {
    Next,
    Call(Call),
    /// `M97 P<label> L<repeats>`: a Haas local subprogram call.
    LocalCall {
        label: u32,
        repeats: u32,
        span: Span,
    },
    Return(Option<u32>),
    End,
}

/// How a program was called.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum FrameKind {
    Main,
    Subprogram,
    /// `M97`: blocks of the calling program from an N label to M99.
    Local,
    Macro,
    ModalMacro,
    /// A LinuxCNC `o… call` of a subroutine.
    OSub,
}

impl FrameKind {
    pub(super) fn is_macro(self) -> bool {
        matches!(self, FrameKind::Macro | FrameKind::ModalMacro)
    }
}

pub(super) struct Call {
    pub program: u32,
    pub repeats: u32,
    pub kind: FrameKind,
    pub args: Option<Box<Locals>>,
    pub span: Span,
}

/// Largest difference (mm) between an I J K arc's start and end radius that
/// the control accepts: parameter 3410 of a Fanuc control, typically 0.02 mm.
const ARC_RADIUS_ALARM: f64 = 0.02;

/// Argument specification I: address to local variable number.
fn argument_slot(letter: u8) -> Option<usize> {
    Some(match letter {
        b'A' => 1,
        b'B' => 2,
        b'C' => 3,
        b'I' => 4,
        b'J' => 5,
        b'K' => 6,
        b'D' => 7,
        b'E' => 8,
        b'F' => 9,
        b'H' => 11,
        b'M' => 13,
        b'Q' => 17,
        b'R' => 18,
        b'S' => 19,
        b'T' => 20,
        b'U' => 21,
        b'V' => 22,
        b'W' => 23,
        b'X' => 24,
        b'Y' => 25,
        b'Z' => 26,
        _ => return None,
    })
}

impl State {
    /// Executes the NC block at `pc`.
    pub(super) fn exec_block(&mut self, program: &Program, pc: u32) -> Result<Action, Diagnostic> {
        let block = &program.blocks[pc as usize];
        let (span, line) = (block.span, block.line);
        self.comp_block(span, line);
        let mut w = Words::new(program.words(block), block.span.file);
        self.gather(program, &mut w)?;
        self.blocks += 1;
        let mut codes: [Option<(GCode, Span)>; 8] = [None; 8];
        for (k, &(tenths, gspan)) in w.g[..w.g_count].iter().enumerate() {
            let Some(code) = GCode::decode(tenths) else {
                return Err(Diagnostic::error(gspan, format!("{} is not supported", g_name(tenths))));
            };
            let group = code.group();
            if let Some(j) = codes[..k].iter().position(|c| c.is_some_and(|(c, _)| c.group() == group)) {
                if group == 0 {
                    return Err(Diagnostic::error(
                        gspan,
                        format!(
                            "{} and {} are both one-shot G codes (group 0): give them in two blocks",
                            g_name(w.g[j].0),
                            g_name(tenths)
                        ),
                    ));
                }
                // As on a Fanuc control, the last G code of a group in a block is the valid one.
                self.warn(
                    "same-group",
                    gspan,
                    format!(
                        "{} and {} are both in modal group {group}: the last one, {}, is used",
                        g_name(w.g[j].0),
                        g_name(tenths),
                        g_name(tenths)
                    ),
                );
                codes[j] = None;
            }
            codes[k] = Some((code, gspan));
        }
        let codes = &codes[..w.g_count];
        let has = |f: fn(&GCode) -> bool| codes.iter().flatten().find(|(c, _)| f(c)).map(|&(c, s)| (c, s));

        // G65: a macro call with arguments, and nothing else.
        if let Some((_, gspan)) = has(|c| *c == GCode::MacroCall) {
            return Ok(Action::Call(self.macro_call(&w, gspan, FrameKind::Macro)?));
        }

        // Modal G codes take effect first, so a modal macro sees them in #4001…
        for &(code, gspan) in codes.iter().flatten() {
            self.apply_modal(code, &w, gspan)?;
            match (code, self.settings.coords.control) {
                // LinuxCNC's G8 is lathe radius mode, its default: nothing to do.
                (GCode::Smoothing(80), Control::LinuxCnc) => continue,
                // LinuxCNC's G5 and G5.1 are splines.
                (GCode::Smoothing(tenths @ (50 | 51)), Control::LinuxCnc) => {
                    return Err(Diagnostic::error(
                        gspan,
                        format!("{} (a LinuxCNC spline) is not supported yet", g_name(tenths)),
                    ));
                }
                (GCode::Smoothing(tenths), Control::LinuxCnc) => {
                    return Err(Diagnostic::error(gspan, format!("{} is not a LinuxCNC code", g_name(tenths))));
                }
                _ => {}
            }
            if let GCode::Smoothing(tenths) | GCode::PathMode(tenths) = code {
                // How the control joins and smooths moves: the machine keeps it.
                let words = w.as_written(b"PQREL");
                let mut text = if words.is_empty() { g_name(tenths) } else { format!("{} {words}", g_name(tenths)) };
                if self.modal.path_tolerance.is_some() && code == GCode::PathMode(640) {
                    // LinuxCNC's P and Q are lengths in the program's units:
                    // the units go with them (the writer restores its own).
                    let units = if self.modal.units == Units::Inch { "G20" } else { "G21" };
                    text = format!("{units} {text}");
                }
                self.keep(text, 0, false, line);
            }
        }

        // G66.1 mode: every block calls the macro instead of moving.
        let in_modal_macro = self.modal_depth > 0;
        if let Some(call) = &self.modal_call {
            if self.modal.modal_call == Some(ModalCallKind::EveryBlock) && !in_modal_macro {
                if let Some((code, gspan)) = codes.iter().flatten().find(|(c, _)| c.group() == 0) {
                    return Err(Diagnostic::error(
                        *gspan,
                        format!("{code:?} cannot be given while G66.1 calls a macro on every block"),
                    ));
                }
                let mut args = [Value::Vacant; 33];
                fill_arguments(&w, &mut args);
                return Ok(Action::Call(Call {
                    program: call.program,
                    repeats: call.repeats,
                    kind: FrameKind::ModalMacro,
                    args: Some(Box::new(args)),
                    span,
                }));
            }
        }
        if has(|c| matches!(c, GCode::ModalCall(_))).is_some() {
            return Ok(Action::Next);
        }

        self.feed_speed_tool(&w);
        self.comp_register(w.get(b'D'), w.span(b'D'))?;
        let mut end = None;
        // Program stops act after the block's motion (Fanuc, LinuxCNC).
        let mut stops: [Option<u32>; 4] = [None; 4];
        for &(m, mspan) in &w.m[..w.m_count] {
            match m {
                3 => self.spindle = Spindle::Cw,
                4 => self.spindle = Spindle::Ccw,
                5 => self.spindle = Spindle::Off,
                6 => {
                    if self.settings.coords.control == Control::LinuxCnc {
                        if self.comp_on() {
                            return Err(Diagnostic::error(
                                mspan,
                                "Cannot change tools with cutter radius compensation on (LinuxCNC): give G40 first",
                            ));
                        }
                        // LinuxCNC reads the position back after the change:
                        // after G40 the tool centre, where compensation left it.
                        if let Some(p) = self.comp_resting_point() {
                            self.tip = p;
                        }
                    }
                    // The tool change macro may move any axis.
                    self.tool = self.pending_tool;
                    self.guessed = AxisSet::ALL;
                }
                7 => self.coolant.mist = true,
                8 => self.coolant.flood = true,
                9 => self.coolant = Default::default(),
                2 | 30 => end = Some(Action::End),
                97 => end = Some(local_call(&w, mspan)?),
                98 => end = Some(Action::Call(self.subprogram_call(&w, mspan)?)),
                99 => end = Some(Action::Return(w.get(b'P').map(|p| p as u32))),
                // Rigid tapping: written with each tapping cycle block.
                29 => self.hole.rigid = true,
                0 | 1 => stops[m as usize] = Some(m),
                // Spindle orientation, clamps, machine-specific
                // codes: the machine must get them as written.
                _ => {
                    // Its words with it (`M19 R90.`, `M62 P1`) where the
                    // block is the M code's alone.
                    let words = if w.g_count == 0 && !w.any_axis() { w.as_written(b"PQRLE") } else { String::new() };
                    let text = if words.is_empty() { format!("M{m:02}") } else { format!("M{m:02} {words}") };
                    self.keep(text, 0, false, line)
                }
            }
        }

        let moved = self.motion(codes, &w, span, line)?;
        for m in stops.into_iter().flatten() {
            let words = if w.g_count == 0 && !w.any_axis() { w.as_written(b"PQRLE") } else { String::new() };
            let text = if words.is_empty() { format!("M{m:02}") } else { format!("M{m:02} {words}") };
            self.keep(text, 0, false, line);
        }

        if moved && !in_modal_macro && self.modal.modal_call == Some(ModalCallKind::AfterMove) {
            if let Some(call) = &self.modal_call {
                return Ok(Action::Call(Call {
                    program: call.program,
                    repeats: call.repeats,
                    kind: FrameKind::ModalMacro,
                    args: Some(Box::new(call.args)),
                    span,
                }));
            }
        }
        Ok(end.unwrap_or(Action::Next))
    }

    fn macro_call(&mut self, w: &Words, gspan: Span, kind: FrameKind) -> Result<Call, Diagnostic> {
        let program =
            w.get(b'P').ok_or_else(|| Diagnostic::error(gspan, "a macro call needs P, the program number"))?;
        let repeats = w.get(b'L').unwrap_or(1.0);
        let mut args = [Value::Vacant; 33];
        fill_arguments(w, &mut args);
        Ok(Call {
            program: whole(program, w.span(b'P'), "program number")?,
            repeats: whole(repeats, w.span(b'L'), "repeat count")?,
            kind,
            args: Some(Box::new(args)),
            span: gspan,
        })
    }

    fn subprogram_call(&mut self, w: &Words, mspan: Span) -> Result<Call, Diagnostic> {
        let p = w.get(b'P').ok_or_else(|| Diagnostic::error(mspan, "M98 needs P, the subprogram number"))?;
        let mut program = whole(p, w.span(b'P'), "subprogram number")?;
        let mut repeats = 1;
        match w.get(b'L') {
            Some(l) => repeats = whole(l, w.span(b'L'), "repeat count")?,
            // M98 P50010: five times O0010 (count in front of four digits);
            // LinuxCNC 2.9 reads program O50010, once.
            None if program > 9999 && self.settings.dialect != crate::Dialect::LinuxCnc => {
                repeats = program / 10_000;
                program %= 10_000;
            }
            None => {}
        }
        Ok(Call { program, repeats, kind: FrameKind::Subprogram, args: None, span: mspan })
    }

    fn apply_modal(&mut self, code: GCode, w: &Words, gspan: Span) -> Result<(), Diagnostic> {
        if self.coords_modal(code, w, gspan)? {
            return Ok(());
        }
        match code {
            GCode::Motion(m) => {
                // A group 1 code ends a canned cycle.
                self.modal.motion = m;
                self.rigid_tap = false;
                self.threading = false;
                self.end_cycle();
            }
            GCode::RigidTap if self.settings.coords.control != Control::LinuxCnc => {
                return Err(Diagnostic::error(
                    gspan,
                    "G33.1 (rigid tapping) is LinuxCNC's: not a code of this dialect",
                ));
            }
            GCode::RigidTap => {
                self.rigid_tap = true;
                self.threading = false;
                self.end_cycle();
            }
            GCode::Plane(p) => self.modal.plane = p,
            GCode::Distance(d) => self.modal.distance = d,
            GCode::FeedMode(f) => self.modal.feed_mode = f,
            GCode::Units(u) => self.modal.units = u,
            GCode::RadiusComp(c) => self.comp_code(c, false, w.get(b'D'), w.span(b'D'), gspan)?,
            GCode::RadiusCompDiameter(c) => self.comp_code(c, true, w.get(b'D'), w.span(b'D'), gspan)?,
            GCode::LengthComp(_) | GCode::LengthGiven | GCode::LengthAdded | GCode::LengthCompOff
                if self.settings.coords.control == Control::LinuxCnc && self.comp_on() =>
            {
                return Err(Diagnostic::error(
                    gspan,
                    "Cannot change tool offset with cutter radius compensation on (LinuxCNC): give G40 first",
                ));
            }
            GCode::LengthComp(positive) => {
                let before = self.length_offset();
                // LinuxCNC: G43 without H takes the tool in the spindle.
                // An M6 in the block comes first (LinuxCNC's order of execution).
                let changed = w.m[..w.m_count].iter().any(|m| m.0 == 6);
                let in_spindle = match w.get(b'T') {
                    Some(t) if changed && t.fract() == 0.0 && (0.0..=99_999_999.0).contains(&t) => t as u32,
                    _ if changed => self.pending_tool,
                    _ => self.tool,
                };
                let default = if self.settings.coords.control == Control::LinuxCnc { in_spindle } else { 0 };
                let h = w.get(b'H').map_or(Ok(default), |h| whole(h, w.span(b'H'), "H number"))?;
                // H0 is no offset on every control: it always reads 0.
                if h != 0 && self.tool_length(h).is_none() {
                    let at = if w.has(b'H') { w.span(b'H') } else { gspan };
                    self.warn("offset", at, format!("tool length offset H{h} is not in the tool table: it reads 0"));
                }
                self.last.h = f64::from(h);
                self.modal.length_comp = Some((if positive { 1.0 } else { -1.0 }, h));
                // LinuxCNC loads the table's length now: a later G10 L1/L10/L11
                // changes it only at the next G43.
                self.length_loaded = (self.settings.coords.control == Control::LinuxCnc).then(|| {
                    if h == 0 {
                        0.0
                    } else {
                        self.tool_length(h).unwrap_or(0.0)
                    }
                });
                self.length_given = None;
                self.length_added = [0; kezuri_geom::LengthOffset::ADDED];
                self.length_units = self.modal.units;
                self.length_changed(before);
            }
            GCode::LengthGiven => self.length_given(w, gspan)?,
            GCode::LengthAdded => self.length_added(w, gspan)?,
            GCode::LengthCompOff => {
                let before = self.length_offset();
                self.modal.length_comp = None;
                self.length_loaded = None;
                self.length_changed(before);
            }
            GCode::WorkOffset(i) => self.select_work_offset(i),
            GCode::ExtraWorkOffset => {
                let p = match w.get(b'P') {
                    Some(p) if p.fract() == 0.0 && (1.0..=EXTRA_OFFSET_COUNT as f64).contains(&p) => p as usize,
                    _ => {
                        return Err(Diagnostic::error(
                            if w.has(b'P') { w.span(b'P') } else { gspan },
                            format!(
                                "{} needs the additional work offset's number P1 to P{EXTRA_OFFSET_COUNT}",
                                g_name(w.g.iter().find(|g| g.0 == 541 || g.0 == 1540).map_or(541, |g| g.0))
                            ),
                        ))
                    }
                };
                self.select_work_offset(EXTRA_OFFSETS + p - 1);
            }
            GCode::CycleOff => {
                self.rigid_tap = false;
                self.threading = false;
                self.end_cycle();
            }
            GCode::CycleReturn(r) => self.modal.cycle_return = r,
            GCode::PathMode(g) => {
                self.modal.path_mode = g;
                let lcnc = self.settings.coords.control == Control::LinuxCnc;
                self.modal.path_tolerance = match w.get(b'P') {
                    Some(p) if g == 640 && lcnc => Some((self.mm(p), w.get(b'Q').map(|q| self.mm(q)))),
                    _ => None,
                };
            }
            // LinuxCNC's G76 is a lathe threading cycle, its own motion mode.
            GCode::CannedCycle(Cycle::FineBore) if self.settings.coords.control == Control::LinuxCnc => {
                self.threading = true;
                self.rigid_tap = false;
                self.end_cycle();
            }
            GCode::CannedCycle(cycle) => {
                self.rigid_tap = false;
                self.threading = false;
                if self.modal.cycle.is_none() {
                    self.begin_cycle();
                }
                self.modal.cycle = Some(cycle);
            }
            GCode::ModalCall(kind) => {
                let call = self.macro_call(w, gspan, FrameKind::ModalMacro)?;
                self.modal.modal_call = Some(kind);
                self.modal_call = Some(ModalCall {
                    program: call.program,
                    repeats: call.repeats,
                    args: *call.args.expect("macro arguments"),
                });
            }
            GCode::ModalCallOff => {
                self.modal.modal_call = None;
                self.modal_call = None;
            }
            GCode::Dwell
            | GCode::SetOffsets
            | GCode::Home
            | GCode::OtherHome
            | GCode::LocalOffset
            | GCode::Rotation(_)
            | GCode::Scaling(_)
            | GCode::Mirror(_)
            | GCode::Polar(_)
            | GCode::ArcCentre(_)
            | GCode::Skip
            | GCode::MachineCoords
            | GCode::MacroCall
            | GCode::SetPosition
            | GCode::ResetShift
            | GCode::Smoothing(_)
            | GCode::ExactStop
            | GCode::ConstantSpeedOff => {}
        }
        Ok(())
    }

    fn feed_speed_tool(&mut self, w: &Words) {
        if let Some(f) = w.get(b'F') {
            self.feed_word = f;
            self.feed_set = true;
        }
        if let Some(s) = w.get(b'S') {
            self.speed = s;
        }
        if let Some(t) = w.get(b'T') {
            self.pending_tool = t.max(0.0) as u32;
        }
        for (letter, slot) in [(b'B', &mut self.last.b), (b'D', &mut self.last.d), (b'E', &mut self.last.e)] {
            if let Some(v) = w.get(letter) {
                *slot = v;
            }
        }
    }

    /// The feed in mm/min for the current modal state.
    pub(super) fn feed_mm_min(&mut self, span: Span) -> f64 {
        if !self.feed_set {
            self.warn("no-feed", span, "a cutting move before any F word: the feed is unknown (0)");
        }
        let f = if self.modal.units == Units::Inch { self.feed_word * 25.4 } else { self.feed_word };
        match self.modal.feed_mode {
            FeedMode::PerMinute => f,
            // Set per move from its length (see `motion`).
            FeedMode::InverseTime => 0.0,
            FeedMode::PerRev => {
                if self.speed == 0.0 {
                    self.warn("no-speed", span, "feed per revolution (G95) with spindle speed 0");
                }
                f * self.speed
            }
        }
    }

    /// Program units of a linear word, in mm.
    pub(super) fn mm(&self, v: f64) -> f64 {
        if self.modal.units == Units::Inch {
            v * 25.4
        } else {
            v
        }
    }

    /// The end point, in machine coordinates, that the axis words ask for
    /// (through the transforms of `coords.rs`).
    pub(super) fn target(&mut self, w: &Words) -> Axes {
        self.program_target(w)
    }

    /// A dwell of the same block again, with nothing between (a wait
    /// loop): the last dwell made longer, so that waiting takes no memory.
    /// False where it must be a move of its own.
    fn longer_dwell(&mut self, seconds: f64, line: u32) -> bool {
        let moves = self.toolpath.moves.len();
        let kept_after = self.toolpath.kept.last().is_some_and(|k| k.before >= moves);
        let frame = self.frame();
        let same = self.toolpath.frames.last() == Some(&frame) && !self.comp_on() && !kept_after;
        match self.toolpath.moves.last_mut() {
            Some(m) if same && m.line == line && m.end == self.tip && m.tool == self.tool => match &mut m.kind {
                MoveKind::Dwell(s) => {
                    *s += seconds;
                    true
                }
                _ => false,
            },
            _ => false,
        }
    }

    pub(super) fn push_move(&mut self, kind: MoveKind, end: Axes, feed: f64, named: AxisSet, line: u32) {
        let named = self.moved_axes(named, self.tip, end);
        let start = self.tip;
        // An increment from a position the program never named is reckoned
        // from the machine model: the writer must keep it an increment.
        let relative = match kind {
            MoveKind::Rapid | MoveKind::Feed | MoveKind::Arc(_) | MoveKind::Probe
                if self.modal.distance == Distance::Incremental && named.0 & self.guessed.0 != 0 =>
            {
                named
            }
            _ => AxisSet::NONE,
        };
        match kind {
            MoveKind::Home | MoveKind::Machine => self.guessed = AxisSet(self.guessed.0 | named.0),
            MoveKind::Dwell(_) => {}
            _ if self.modal.distance == Distance::Absolute => self.guessed = AxisSet(self.guessed.0 & !named.0),
            _ => {}
        }
        let frame = self.frame();
        if self.toolpath.frames.last() != Some(&frame) {
            self.toolpath.frames.push(frame);
        }
        let m = Move {
            kind,
            start: self.tip,
            end,
            feed,
            speed: self.speed,
            spindle: self.spindle,
            coolant: self.coolant,
            tool: self.tool,
            line,
            frame: (self.toolpath.frames.len() - 1) as u32,
            named,
            relative,
        };
        self.comp_tag();
        self.toolpath.push(m);
        self.tip = end;
        self.settle_program(kind, start);
    }

    /// Applies the one-shot codes and the motion of a block. Returns whether
    /// an axis moved.
    fn motion(
        &mut self,
        codes: &[Option<(GCode, Span)>],
        w: &Words,
        span: Span,
        line: u32,
    ) -> Result<bool, Diagnostic> {
        if codes.iter().flatten().any(|(c, _)| *c == GCode::LengthGiven) {
            // G43.1's axis words are its offset: nothing moves.
            return Ok(false);
        }
        let one_shot = codes.iter().flatten().find(|(c, _)| c.group() == 0).copied();
        if w.polar() {
            self.polar_rules(one_shot, w)?;
        }
        let lcnc = self.settings.dialect == crate::Dialect::LinuxCnc;
        match one_shot {
            Some((GCode::Dwell, gspan)) if lcnc && !w.has(b'P') => {
                return Err(Diagnostic::error(gspan, "G4 needs P, the dwell in seconds (LinuxCNC reads no X dwell)"));
            }
            Some((GCode::Dwell, gspan)) => {
                let seconds = match (w.get(b'P'), w.get(b'X')) {
                    // P is milliseconds on a Fanuc control, seconds on LinuxCNC and GRBL.
                    (Some(p), _) if self.settings.integer_input == IntegerInput::Units => p,
                    (Some(p), _) => p / 1000.0,
                    (None, Some(x)) => x,
                    (None, None) => {
                        return Err(Diagnostic::error(
                            gspan,
                            "G04 needs the dwell time: X (seconds) or P (milliseconds)",
                        ))
                    }
                };
                if seconds < 0.0 {
                    return Err(Diagnostic::error(gspan, "a dwell time cannot be negative"));
                }
                if !self.longer_dwell(seconds, line) {
                    self.push_move(MoveKind::Dwell(seconds), self.tip, self.feed_word, AxisSet::NONE, line);
                }
                // `G04 P.001 G00 X1. Y1.` (LinuxCNC programs write it): the
                // dwell, then the block's motion. With X the dwell time,
                // nothing moves.
                // LinuxCNC dwells first in every block (its order of
                // execution), then makes the block's motion in the motion
                // mode in force: a canned cycle's holes too.
                let motion_code = codes.iter().flatten().any(|(c, _)| matches!(c, GCode::Motion(_)));
                if !(w.has(b'P') && (motion_code || lcnc) && (w.any_axis() || (lcnc && w.has(b'R')))) {
                    return Ok(false);
                }
            }
            Some((code @ (GCode::Home | GCode::OtherHome), gspan)) => {
                let control = self.settings.coords.control;
                if code == GCode::Home && control == Control::Haas {
                    // Haas: G28 cancels the tool length offset.
                    self.modal.length_comp = None;
                    self.length_loaded = None;
                }
                let every_axis = match code {
                    GCode::Home => control != Control::Fanuc,
                    _ => control == Control::LinuxCnc,
                };
                if !w.any_axis() {
                    if !every_axis {
                        self.warn("bare-g28", gspan, format!("{} without axis words moves nothing on this control (LinuxCNC returns every axis; Haas too for G28): name the axes, e.g. G91 {} Z0", g_name(if code == GCode::Home { 280 } else { 300 }), g_name(if code == GCode::Home { 280 } else { 300 })));
                        return Ok(false);
                    }
                    // Haas and LinuxCNC: every axis to the reference point, at
                    // once: X Y Z and the rotary axes the program has turned,
                    // named so that any control's written program does the same.
                    let h = self.reference_point(code, w)?.to_array();
                    let lz = self.length_offset();
                    let home = Axes::from_array(std::array::from_fn(|i| h[i] - if i == 2 { lz } else { 0.0 }));
                    let tip = self.tip.to_array();
                    let axes = (3..6).filter(|&k| tip[k] != 0.0).fold(AxisSet(0b111), |set, k| set.with(k));
                    if code == GCode::OtherHome {
                        let p = w.get(b'P').filter(|&p| p != 2.0).map_or(String::new(), |p| format!(" P{p}"));
                        let words: String = (0..6)
                            .filter(|&k| axes.contains(k))
                            .map(|k| format!(" {}0.", b"XYZABC"[k] as char))
                            .collect();
                        self.keep(format!("G91 G30{p}{words}"), 1, false, line);
                    }
                    self.push_move(MoveKind::Home, home, 0.0, axes, line);
                    return Ok(true);
                }
                let via = self.target(w);
                let mut home = self.tip;
                let (h, mut v) = (self.reference_point(code, w)?.to_array(), home.to_array());
                let lz = self.length_offset();
                for (i, &letter) in b"XYZABC".iter().enumerate() {
                    if w.has(letter) {
                        v[i] = h[i] - if i == 2 { lz } else { 0.0 };
                    }
                }
                home = Axes::from_array(v);
                if w.any_axis() {
                    // `G91 G28 Z0` has no intermediate move (nor does a via
                    // point a rounding away from the tool).
                    let (v, t) = (via.to_array(), self.tip.to_array());
                    if (0..6).any(|k| (v[k] - t[k]).abs() > 1e-9) {
                        self.push_move(MoveKind::Rapid, via, 0.0, w.axes(), line);
                    }
                    if code == GCode::OtherHome {
                        self.keep_other_return(w, line);
                    }
                    self.push_move(MoveKind::Home, home, 0.0, w.axes(), line);
                }
                return Ok(w.any_axis());
            }
            Some((GCode::ResetShift, _)) => {
                // The G92 shift is cancelled: on the named axes (Fanuc's
                // preset), on every axis when none is named (LinuxCNC).
                let mut g = self.g92_shift.to_array();
                for (i, &letter) in b"XYZABC".iter().enumerate() {
                    if !w.any_axis() || w.has(letter) {
                        g[i] = 0.0;
                    }
                }
                self.g92_shift = Axes::from_array(g);
                self.guessed = AxisSet::ALL;
                self.keep_as_given(w, false, line);
                return Ok(false);
            }
            Some((GCode::SetPosition, _)) => {
                self.set_position(w);
                self.guessed = AxisSet::ALL;
                self.keep_as_given(w, false, line);
                return Ok(false);
            }
            Some((GCode::LocalOffset, _)) => {
                self.local_offset(w);
                self.guessed = AxisSet::ALL;
                self.keep_as_given(w, false, line);
                return Ok(false);
            }
            Some((GCode::MachineCoords, gspan)) if self.modal.distance == Distance::Incremental => {
                // Fanuc: G53 ignored, an ordinary incremental move follows.
                self.g53_incremental(gspan)?;
            }
            Some((GCode::MachineCoords, _)) => {
                let mut p = self.tip.to_array();
                let lz = self.length_offset();
                for (i, &letter) in b"XYZABC".iter().enumerate() {
                    if let Some(v) = w.get(letter) {
                        p[i] = if i < 3 { self.mm(v) } else { v } - if i == 2 { lz } else { 0.0 };
                    }
                }
                // G53 positions at rapid traverse whatever the group 1 mode.
                if w.any_axis() {
                    self.push_move(MoveKind::Machine, Axes::from_array(p), 0.0, w.axes(), line);
                }
                return Ok(w.any_axis());
            }
            Some((GCode::Skip, gspan)) => {
                if !w.any_axis() {
                    return Ok(false);
                }
                if self.modal.feed_mode == FeedMode::InverseTime {
                    return Err(Diagnostic::error(gspan, "a skip move in inverse time feed (G93): give G94 first"));
                }
                let end = self.target(w);
                let feed = self.feed_mm_min(span);
                self.push_move(MoveKind::Probe, end, feed, w.axes(), line);
                // #5061… include the tool length offset, as #5041… do.
                let work = self.work_position();
                self.skip_position = Axes { z: work.z + self.length_offset(), ..work };
                return Ok(true);
            }
            Some((GCode::SetOffsets, gspan)) => {
                self.set_offsets(w, gspan)?;
                // LinuxCNC's G10 ignores G91: kept as absolute for any control.
                let absolute = self.settings.coords.control == Control::LinuxCnc;
                self.keep_as_given(w, absolute, line);
                return Ok(false);
            }
            _ => {}
        }
        // G68, G51, G51.1, G50.1: their axis words are centres, not moves.
        if codes
            .iter()
            .flatten()
            .any(|(c, _)| matches!(c, GCode::Rotation(true) | GCode::Scaling(true) | GCode::Mirror(_)))
        {
            return Ok(false);
        }
        if let Some(cycle) = self.modal.cycle {
            return self.cycle_block(cycle, w, span, line);
        }
        if self.rigid_tap {
            return self.rigid_tap_block(w, span, line);
        }
        if self.threading {
            return self.thread_block(w, span, line);
        }
        let is_arc = matches!(self.modal.motion, Motion::Cw | Motion::Ccw);
        if !w.any_axis() && !(is_arc && (w.has(b'I') || w.has(b'J') || w.has(b'K'))) {
            return Ok(false);
        }
        let end = self.target(w);
        match self.modal.motion {
            Motion::Rapid => self.push_move(MoveKind::Rapid, end, 0.0, w.axes(), line),
            Motion::Linear => {
                let feed = self.feed_mm_min(span);
                self.push_move(MoveKind::Feed, end, feed, w.axes(), line);
            }
            Motion::Cw | Motion::Ccw => {
                let arc = self.arc(w, end, span)?;
                let feed = self.feed_mm_min(span);
                self.push_move(MoveKind::Arc(arc), end, feed, w.axes(), line);
            }
        }
        if self.modal.feed_mode == FeedMode::InverseTime && self.modal.motion != Motion::Rapid {
            // G93: F is 1 / the move's time in minutes, given on every move.
            let Some(f) = w.get(b'F').filter(|f| *f > 0.0) else {
                return Err(Diagnostic::error(
                    span,
                    "in inverse time feed (G93) every cutting move needs its F (1/minutes), greater than 0",
                ));
            };
            if let Some(m) = self.toolpath.moves.last_mut() {
                m.feed = m.feed_distance() * f;
            }
        }
        Ok(true)
    }

    /// LinuxCNC's rules for the polar words `@` and `^`: they name X and Y
    /// (neither may be given with them) in the XY plane, on a motion or a
    /// canned cycle's hole (with a dwell before it, but with no other
    /// one-shot code: G53, G28, G92, G10 …).
    fn polar_rules(&self, one_shot: Option<(GCode, Span)>, w: &Words) -> Result<(), Diagnostic> {
        let at = if w.has(b'@') { w.span(b'@') } else { w.span(b'^') };
        for letter in [b'X', b'Y'] {
            if w.has(letter) {
                return Err(Diagnostic::error(
                    w.span(letter),
                    format!("{} with a polar word (@ ^): give the point in X Y or in @ ^, not both", letter as char),
                ));
            }
        }
        match one_shot {
            None | Some((GCode::Dwell, _)) => {}
            Some((GCode::MachineCoords, gspan)) => {
                return Err(Diagnostic::error(gspan, "G53 cannot take polar words (@ ^): give X Y"))
            }
            Some((_, gspan)) => {
                return Err(Diagnostic::error(gspan, "polar words (@ ^) are for motion only: give this code its X Y"))
            }
        }
        if self.modal.plane != kezuri_geom::Plane::Xy {
            return Err(Diagnostic::error(at, "polar words (@ ^) need the XY plane (G17)"));
        }
        if self.modal.cycle.is_none() {
            self.polar_from_origin(w, at)?;
        }
        Ok(())
    }

    fn arc(&mut self, w: &Words, end: Axes, span: Span) -> Result<Arc, Diagnostic> {
        let plane = self.modal.plane;
        let (i, j, _) = plane.axes();
        // A mirror image (or a negative scale) on one axis of the plane
        // reverses the direction; an R arc's radius is scaled.
        let ccw = (self.modal.motion == Motion::Ccw) != self.plane_reversed();
        let scale = self.arc_scale(span)?;
        let s = self.tip.xyz();
        let e = end.xyz();
        let mut center = s;
        if let Some(r) = w.get(b'R') {
            let r = self.mm(r) * scale;
            let (dx, dy) = (e[i] - s[i], e[j] - s[j]);
            let chord = dx.hypot(dy);
            if chord < 1e-9 {
                return Err(Diagnostic::error(
                    w.span(b'R'),
                    "an R arc cannot end where it starts: give I J K for a full circle",
                ));
            }
            let half = chord / 2.0;
            if r.abs() < half - 1e-6 {
                return Err(Diagnostic::error(
                    w.span(b'R'),
                    format!(
                        "the radius R, {:.4} mm, is smaller than half the distance to the end point ({half:.4} mm)",
                        r.abs()
                    ),
                ));
            }
            let h = (r * r - half * half).max(0.0).sqrt();
            // Centre to the left of the chord for a short CCW arc.
            let left = (ccw == (r > 0.0)) as i32 as f64 * 2.0 - 1.0;
            center[i] = s[i] + dx / 2.0 - left * h * dy / chord;
            center[j] = s[j] + dy / 2.0 + left * h * dx / chord;
        } else {
            match self.arc_centre(w, span)? {
                Some(c) => center = c,
                None => return Err(Diagnostic::error(span, "an arc needs its centre (I J K) or its radius (R)")),
            }
            let r0 = (s[i] - center[i]).hypot(s[j] - center[j]);
            let r1 = (e[i] - center[i]).hypot(e[j] - center[j]);
            if r0 < 1e-9 {
                return Err(Diagnostic::error(span, "the arc's centre is its start point (radius 0)"));
            }
            let off = (r1 - r0).abs();
            if off > ARC_RADIUS_ALARM {
                // The control stops here (Fanuc alarm PS0020, over tolerance of radius).
                return Err(Diagnostic::error(
                    span,
                    format!("the arc's end point is {off:.4} mm off its circle (radius {r0:.4} at the start, {r1:.4} at the end): more than {ARC_RADIUS_ALARM} mm, the control stops with an alarm"),
                ));
            }
            if off > 0.002 {
                self.warn(
                    "arc-radius",
                    span,
                    format!("the arc's end point is {:.4} mm off its circle (radius {r0:.4} at the start, {r1:.4} at the end)", (r1 - r0).abs()),
                );
            }
        }
        let (_, _, n) = plane.axes();
        center[n] = s[n];
        // LinuxCNC: P is the number of turns (P1 the arc itself).
        let turns = match w.get(b'P') {
            Some(p) if self.settings.coords.control == Control::LinuxCnc => {
                if p.fract() != 0.0 || !(1.0..=10_000.0).contains(&p) {
                    return Err(Diagnostic::error(
                        w.span(b'P'),
                        format!("P{p}: the number of turns of an arc is a whole number from 1"),
                    ));
                }
                p as u32 - 1
            }
            _ => 0,
        };
        Ok(Arc { center, plane, ccw, turns })
    }
}

/// `G01`, `G66.1`: a G code as written, from ten times its number.
fn g_name(tenths: u32) -> String {
    if tenths.is_multiple_of(10) {
        format!("G{:02}", tenths / 10)
    } else {
        format!("G{:02}.{}", tenths / 10, tenths % 10)
    }
}

fn fill_arguments(w: &Words, args: &mut Locals) {
    for letter in b'A'..=b'Z' {
        if let (Some(v), Some(slot)) = (w.get(letter), argument_slot(letter)) {
            args[slot - 1] = Value::Num(v);
        }
    }
    // M words are kept apart as M codes; the first one is argument #13.
    if w.m_count > 0 {
        args[12] = Value::Num(f64::from(w.m[0].0));
    }
}

/// `M97 P<label> L<repeats>` (Haas): the N label to run to M99, how often.
fn local_call(w: &Words, mspan: Span) -> Result<Action, Diagnostic> {
    let p = w.get(b'P').ok_or_else(|| Diagnostic::error(mspan, "M97 needs P, the N number to call"))?;
    let label = whole(p, w.span(b'P'), "sequence number")?;
    let repeats = w.get(b'L').map_or(Ok(1), |l| whole(l, w.span(b'L'), "repeat count"))?;
    Ok(Action::LocalCall { label, repeats, span: mspan })
}

fn whole(v: f64, span: Span, what: &str) -> Result<u32, Diagnostic> {
    if v.fract() != 0.0 || !(0.0..=99_999_999.0).contains(&v) {
        return Err(Diagnostic::error(span, format!("{what} must be a whole number, got {v}")));
    }
    Ok(v as u32)
}
