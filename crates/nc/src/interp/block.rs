//! One NC block: evaluate its words, then apply it completely.

use kezuri_geom::{AxisSet, Spindle};

use super::modal::{g_name, Cycle, GCode, ModalCallKind, Units};
use super::value::Value;
use super::words::{letters, Words};
use super::{Control, ModalCall, State};
use crate::ast::Program;
use crate::offsets::{EXTRA_OFFSETS, EXTRA_OFFSET_COUNT};
use crate::source::{Diagnostic, Span};

mod call;
use call::{fill_arguments, local_call, whole};
pub(super) use call::{Call, FrameKind};

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
    /// Go on at this block (of the same program): after a lathe cycle's
    /// shape that follows the cycle block.
    Resume(u32),
    Return(Option<u32>),
    /// A LinuxCNC O-word subroutine called by number (a lathe cycle's
    /// profile, `G71 Q100`).
    OCall {
        number: u32,
        span: Span,
    },
    End,
}

impl State {
    /// Executes the NC block at `pc`. An error in a block that a word
    /// without a decimal point may be behind says how it was read.
    pub(super) fn exec_block(&mut self, program: &Program, pc: u32) -> Result<Action, Diagnostic> {
        let action = self.exec_words(program, pc).map_err(|d| self.with_decimal_hint(program, pc, d))?;
        self.comp_entry_alarm()?;
        Ok(action)
    }

    #[inline(always)]
    fn exec_words(&mut self, program: &Program, pc: u32) -> Result<Action, Diagnostic> {
        let block = &program.blocks[pc as usize];
        let (span, line) = (block.span, block.line);
        self.comp_block(span, line);
        let mut w = Words::new(program.words(block), block.span.file);
        w.axis_bits = self.axis_bits();
        self.gather(program, &mut w)?;
        self.blocks += 1;
        let mut codes: [Option<(GCode, Span)>; 8] = [None; 8];
        self.g_codes(&w, &mut codes)?;
        self.block_plain = plain(&w, &codes[..w.g_count]);
        self.frame_known &= self.block_plain;
        // A LinuxCNC lathe cycle's profile: the block is read, not run.
        if self.reading_profile() {
            let n = w.g_count;
            self.profile_block(&w, &codes[..n], span)?;
            return Ok(Action::Next);
        }
        // A Fanuc or Haas lathe's words (LinuxCNC's X: `diameter_words`).
        if self.turning.as_ref().is_some_and(|t| t.fanuc) {
            let n = w.g_count;
            // The next block's words: a line given by its angle alone ends
            // where it meets the next block's line.
            // (A lathe's program is read whole: every block is held.)
            let next = (pc as usize + 1..program.blocks.len())
                .map_while(|i| program.blocks.get(i))
                .find(|b| !matches!(b.statement, crate::ast::Statement::Empty))
                .filter(|b| matches!(b.statement, crate::ast::Statement::Words { .. }))
                .map(|b| program.words(b));
            self.lathe_block(&mut w, &mut codes[..n], next)?;
        }
        let codes = &codes[..w.g_count];
        let has = |f: fn(&GCode) -> bool| first_code(codes, f);

        // G65: a macro call with arguments, and nothing else.
        if let Some((_, gspan)) = has(|c| *c == GCode::MacroCall) {
            return Ok(Action::Call(self.macro_call(&w, gspan, FrameKind::Macro)?));
        }

        // Modal G codes take effect first, so a modal macro sees them in #4001…
        for &(code, gspan) in codes.iter().flatten() {
            self.apply_modal(code, &w, gspan)?;
            self.path_code(code, &w, gspan, line)?;
        }
        self.diameter_words(&mut w);
        if let Some((GCode::LatheProfile(tenths), gspan)) = has(|c| matches!(c, GCode::LatheProfile(_))) {
            self.feed_speed_tool(&w);
            return self.profile_cycle(tenths, &w, gspan, line);
        }

        // G66.1 mode: every block calls the macro instead of moving.
        let in_modal_macro = self.modal_depth > 0;
        if let Some(call) = &self.modal_call {
            if self.modal.modal_call == Some(ModalCallKind::EveryBlock) && !in_modal_macro {
                if let Some((code, gspan)) = first_code(codes, |c| c.group() == 0) {
                    return Err(Diagnostic::error(
                        gspan,
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
        // An axis the machine model has not would lose its motion: never
        // dropped in silence. G10 sets its offset, which moves nothing.
        if self.turning.is_none() && w.has_any(letters(b"cra")) {
            if let Some(letter) = [b'c', b'r', b'a'].into_iter().find(|&l| w.has(l)) {
                let what = match letter {
                    b'c' => "a chamfer between two moves",
                    b'r' => "a corner R between two moves",
                    _ => "the angle of a straight line",
                };
                return Err(Diagnostic::error(
                    w.span(letter),
                    format!(
                        ",{} ({what}) is read on a lathe only: kezuri does not run it on a mill",
                        letter.to_ascii_uppercase() as char,
                    ),
                ));
            }
        }
        if w.has_any(letters(b"UVW"))
            && !w.has_uvw()
            && has(|c| *c == GCode::SetOffsets).is_none()
            && !self.lathe_own_words()
        {
            if let Some(letter) = b"UVW".iter().copied().find(|&l| w.has(l)) {
                return Err(Diagnostic::error(
                    w.span(letter),
                    format!(
                        "{} is an axis this control does not have (X Y Z A B C; LinuxCNC has U V W too): its \
                         motion would be lost, so the program is not run",
                        letter as char
                    ),
                ));
            }
        }

        self.linuxcnc_tool_word(&w)?;
        self.feed_speed_tool(&w);
        if self.turning.is_some() {
            self.lathe_speed_tool(&w, codes)?;
        }
        // LinuxCNC's G96 D is the spindle's top speed, not an offset number;
        // in a lathe cycle's block D is the cycle's (Haas: a depth of cut).
        let top_speed =
            self.settings.dialect == crate::Dialect::LinuxCnc && has(|c| *c == GCode::ConstantSpeed).is_some();
        if let Some(d) = w.get(b'D') {
            if !top_speed && !self.lathe_own_words() {
                self.comp_register(d, w.span(b'D'))?;
            }
        }
        let mut stops: [Option<u32>; 4] = [None; 4];
        let end = self.m_codes(&w, line, &mut stops)?;
        let first_move = self.toolpath.moves.len();
        let x_known = !self.unplaced.contains(0) && !self.at_machine.contains(0);
        // A lathe's G70–G73: the whole cycle, the shape read from its blocks;
        // the program may go on after the shape.
        let mut resume = None;
        let mut own_moves = first_move;
        let moved = match if self.turning.is_some() { has(|c| matches!(c, GCode::Contour(_))) } else { None } {
            Some((GCode::Contour(cycle), gspan)) => {
                (resume, own_moves) = self.contour_cycle(program, pc, cycle, &w, gspan, line)?;
                true
            }
            _ => self.motion(codes, &w, span, line)?,
        };
        if self.turning.is_some() {
            let changed = self.corner_moves(own_moves, span)?;
            self.lathe_moves(changed, x_known || changed < own_moves, &w, span)?;
            if matches!(end, Some(Action::End)) {
                self.corner_left()?;
            }
        }
        self.within_reach(first_move, &w, span)?;
        for m in stops.into_iter().flatten() {
            self.keep_m_code(&w, m, line);
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
        match (end, resume) {
            (Some(end), _) => Ok(end),
            (None, Some(pc)) => Ok(Action::Resume(pc)),
            (None, None) => Ok(Action::Next),
        }
    }

    /// The block's G codes, decoded, a code overridden by a later one of its
    /// modal group taken out (as on a Fanuc control, the last of a group in
    /// a block is the valid one).
    // g_codes, path_code, m_codes, motion and modal_motion are exec_block's seams, each called
    // once on the hot path: inlined, the interpreter runs as it did whole (the raster bench's
    // 100,000 blocks: 140.4 M instructions; 141.5 M without the inlining, 156.0 M with the
    // codes returned by value).
    #[inline(always)]
    fn g_codes(&mut self, w: &Words, codes: &mut [Option<(GCode, Span)>; 8]) -> Result<(), Diagnostic> {
        for (k, &(tenths, gspan)) in w.g[..w.g_count].iter().enumerate() {
            let Some(code) = self.decode_g(tenths) else {
                return Err(Diagnostic::error(gspan, self.unknown_code(tenths)));
            };
            let group = code.group();
            if let Some(j) = codes[..k].iter().position(|c| c.is_some_and(|(c, _)| c.group() == group)) {
                // A skip to a machine position: G53 with G31 (Fanuc, Haas).
                let pair = [code, codes[j].map_or(code, |(c, _)| c)];
                let machine_skip = pair.contains(&GCode::MachineCoords) && pair.contains(&GCode::Skip);
                if group == 0 && machine_skip && self.settings.coords.control != Control::LinuxCnc {
                    codes[k] = Some((code, gspan));
                    continue;
                }
                if group == 0 && machine_skip {
                    return Err(Diagnostic::error(
                        gspan,
                        "Must use G0 or G1 with G53 (LinuxCNC stops here): no probe move in machine coordinates",
                    ));
                }
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
        Ok(())
    }

    /// How the control joins and smooths moves (G05, G08, G61, G64 …): the
    /// machine keeps it, as written; LinuxCNC's splines are refused.
    #[inline(always)]
    fn path_code(&mut self, code: GCode, w: &Words, gspan: Span, line: u32) -> Result<(), Diagnostic> {
        match (code, self.settings.coords.control) {
            // LinuxCNC's G8 is lathe radius mode, its default.
            (GCode::Smoothing(80), Control::LinuxCnc) => {
                self.radius_mode();
                return Ok(());
            }
            // LinuxCNC's G5 and G5.1 are splines, of their block only:
            // rs274 2.9 leaves the motion mode as it was.
            (GCode::Smoothing(tenths @ (50 | 51)), Control::LinuxCnc) => {
                self.spline = Some(tenths);
                return Ok(());
            }
            (GCode::Smoothing(tenths), Control::LinuxCnc) => {
                return Err(Diagnostic::error(gspan, format!("{} is not a LinuxCNC code", g_name(tenths))));
            }
            _ => {}
        }
        if let GCode::Smoothing(tenths) | GCode::PathMode(tenths) = code {
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
        Ok(())
    }

    /// The block's M codes: spindle, tool change, coolant, and those the
    /// machine gets as written. Returns what the block pointer does after the
    /// block (an end, a call, a return) and the program stops (`M00`, `M01`),
    /// which act after the block's motion (Fanuc, LinuxCNC).
    #[inline(always)]
    fn m_codes(&mut self, w: &Words, line: u32, stops: &mut [Option<u32>; 4]) -> Result<Option<Action>, Diagnostic> {
        let mut end = None;
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
                97 => end = Some(local_call(w, mspan)?),
                98 => end = Some(Action::Call(self.subprogram_call(w, mspan)?)),
                99 => end = Some(Action::Return(w.get(b'P').map(|p| p as u32))),
                // Rigid tapping: written with each tapping cycle block.
                29 => self.hole.rigid = true,
                0 | 1 => stops[m as usize] = Some(m),
                // Spindle orientation, clamps, machine-specific
                // codes: the machine must get them as written.
                _ => self.keep_m_code(w, m, line),
            }
        }
        Ok(end)
    }

    /// M code `m` kept for the machine as written, with its words (`M19
    /// R90.`, `M62 P1`) where the block is the M code's alone.
    fn keep_m_code(&mut self, w: &Words, m: u32, line: u32) {
        let words = if w.g_count == 0 && !w.any_axis() { w.as_written(b"PQRLE") } else { String::new() };
        let text = if words.is_empty() { format!("M{m:02}") } else { format!("M{m:02} {words}") };
        self.keep(text, 0, false, line);
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
                self.spindle_sync = false;
                self.end_cycle();
                self.lathe_motion(None);
            }
            GCode::SingleCycle(cycle) => {
                self.rigid_tap = false;
                self.threading = false;
                self.end_cycle();
                self.lathe_motion(Some(super::lathe::LatheMotion::Single(cycle)));
            }
            GCode::Threading => {
                self.rigid_tap = false;
                self.threading = false;
                self.end_cycle();
                self.lathe_motion(Some(super::lathe::LatheMotion::Threading));
            }
            GCode::ConstantSpeed | GCode::ConstantSpeedOff if self.settings.dialect == crate::Dialect::LinuxCnc => {
                self.linuxcnc_lathe_code(code, w, gspan)?
            }
            GCode::ConstantSpeed => self.constant_speed(true, gspan)?,
            GCode::ConstantSpeedOff if self.turning.is_some() => self.constant_speed(false, gspan)?,
            GCode::RigidTap if self.settings.coords.control != Control::LinuxCnc => {
                return Err(Diagnostic::error(
                    gspan,
                    "G33.1 (rigid tapping) is LinuxCNC's: not a code of this dialect",
                ));
            }
            GCode::RigidTap => {
                self.lathe_motion(None);
                self.rigid_tap = true;
                self.threading = false;
                self.spindle_sync = false;
                self.end_cycle();
            }
            GCode::SpindleSync | GCode::LatheDiameter => self.linuxcnc_lathe_code(code, w, gspan)?,
            GCode::LatheProfile(_) => {
                self.rigid_tap = false;
                self.threading = false;
                self.spindle_sync = false;
                self.end_cycle();
            }
            GCode::Plane(p) => self.modal.plane = p,
            GCode::Distance(d) => self.modal.distance = d,
            GCode::FeedMode(f) => self.modal.feed_mode = f,
            GCode::Units(u) => self.modal.units = u,
            GCode::RadiusComp(c) => self.comp_code(c, false, w.get(b'D'), w.span(b'D'), None, gspan)?,
            GCode::RadiusCompDiameter(c) => {
                let l = w.get(b'L').map(|l| (l, w.span(b'L')));
                self.comp_code(c, true, w.get(b'D'), w.span(b'D'), l, gspan)?
            }
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
                    self.warn("offset", at, self.missing_length(h));
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
                self.spindle_sync = false;
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
                self.spindle_sync = false;
                self.end_cycle();
            }
            GCode::CannedCycle(cycle) => {
                self.rigid_tap = false;
                self.threading = false;
                self.spindle_sync = false;
                // A lathe's side cycle after a face cycle drills along
                // another axis: its initial level is taken afresh.
                let fresh = self.modal.cycle.is_none_or(|c| c.is_side() != cycle.is_side());
                self.modal.cycle = Some(cycle);
                if fresh {
                    self.begin_cycle();
                }
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
            | GCode::Pocket(_)
            | GCode::Grooving(_)
            | GCode::MultipleThreading
            | GCode::Contour(_)
            | GCode::LatheSetPosition
            | GCode::ConstantSpeedOff => {}
        }
        Ok(())
    }

    #[inline(always)]
    fn feed_speed_tool(&mut self, w: &Words) {
        if let Some(f) = w.get(b'F') {
            self.feed_word = f;
            self.feed_set = true;
            self.feed_span = w.span(b'F');
        }
        if let Some(s) = w.get(b'S') {
            self.speed = s;
            self.speed_span = Some(w.span(b'S'));
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
}

/// Whether a block has motion words only: G00–G03, axis and arc words,
/// F and S, no M code. Such a block cannot change the work offset, the
/// shifts or the tool length offset (an H or T word, a G10, a macro
/// statement can), so its moves keep the frame of the move before.
#[inline(always)]
fn plain(w: &Words, codes: &[Option<(GCode, Span)>]) -> bool {
    const MOTION_WORDS: u32 = letters(b"XYZABCUVWIJKRFS");
    if w.m_count > 0 || w.has_any(!MOTION_WORDS) {
        return false;
    }
    for (code, _) in codes.iter().flatten() {
        if !matches!(code, GCode::Motion(_)) {
            return false;
        }
    }
    true
}

/// The first of a block's decoded G codes that `is` accepts, with its
/// word's span (a plain loop: the iterator adapters' fold is not inlined
/// into the block function, and this runs a few times a block).
#[inline(always)]
pub(super) fn first_code(codes: &[Option<(GCode, Span)>], is: impl Fn(&GCode) -> bool) -> Option<(GCode, Span)> {
    for &(code, span) in codes.iter().flatten() {
        if is(&code) {
            return Some((code, span));
        }
    }
    None
}
