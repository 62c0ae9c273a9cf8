//! The motion of a block, by its kind: dwells, returns to the reference
//! point, machine-coordinate and skip moves, the shifts that move nothing,
//! and straight and circular moves (canned cycles are `cycle.rs`'s).

use kezuri_geom::{Arc, Axes, AxisSet, Move, MoveKind};

use super::block::first_code;
use super::modal::{g_name, Distance, FeedMode, GCode, Motion, Units};
use super::words::Words;
use super::{Control, IntegerInput, State};
use crate::source::{Diagnostic, Span};

/// Largest difference (mm) between an I J K arc's start and end radius that
/// a Fanuc or Haas control accepts by default: parameter 3410, typically
/// 0.02 mm (the machine file's `[coordinates] arc_tolerance_mm` sets it).
const ARC_RADIUS_ALARM: f64 = 0.02;

/// LinuxCNC's default absolute part of the rule (`CENTER_ARC_RADIUS_TOLERANCE`
/// in its interpreter): 0.02·√2 mm under G21, 0.002·√2 inch under G20.
const LINUXCNC_ARC_MM: f64 = 0.02 * std::f64::consts::SQRT_2;
const LINUXCNC_ARC_INCH: f64 = 0.002 * std::f64::consts::SQRT_2;

/// LinuxCNC's relative part: a difference past the absolute tolerance is
/// refused where it is also past 0.1 % of the larger radius (and any past
/// 100 times the absolute tolerance), as rs274 2.9 runs it.
const LINUXCNC_ARC_RELATIVE: f64 = 0.001;

/// GRBL's rule: off by more than 0.005 mm and more than 0.1 % of the
/// radius, or by more than 0.5 mm.
const GRBL_ARC_MM: f64 = 0.005;
const GRBL_ARC_LIMIT_MM: f64 = 0.5;

impl State {
    /// The feed in mm/min for the current modal state, for a cutting move
    /// of the block at `span`. A feed of zero is an error in every dialect
    /// (LinuxCNC refuses it; a Fanuc axis would wait forever): `F0` in
    /// G94, or G95 with spindle speed 0. No F word at all is a warning.
    pub(super) fn feed_mm_min(&mut self, span: Span) -> Result<f64, Diagnostic> {
        if !self.feed_set {
            self.warn("no-feed", span, "a cutting move before any F word: the feed is unknown (0)");
        }
        let f = if self.modal.units == Units::Inch { self.feed_word * 25.4 } else { self.feed_word };
        // The word that set the zero where this block has it, else the block.
        let at = |set: Span| {
            if set.file == span.file && set.start >= span.start && set.end <= span.end {
                set
            } else {
                span
            }
        };
        let earlier = |set: Span| if at(set) == set { "" } else { " (given in an earlier block)" };
        match self.modal.feed_mode {
            FeedMode::PerMinute if self.feed_set && f <= 0.0 => Err(Diagnostic::error(
                at(self.feed_span),
                format!(
                    "a cutting move at F{}{}: at feed 0 the move never ends; give F greater than 0",
                    self.feed_word,
                    earlier(self.feed_span)
                ),
            )),
            FeedMode::PerMinute => Ok(f),
            // Set per move from its length (see `motion`).
            FeedMode::InverseTime => Ok(0.0),
            // Under constant surface speed the speed is reckoned along the
            // move (lathe/speed.rs): 0 here only where X is not known yet.
            FeedMode::PerRev if self.feed_set && self.speed <= 0.0 && !self.surface_speed_on() => {
                let (place, what) = match self.speed_span {
                    Some(s) => (at(s), format!("spindle speed S{}{}", self.speed, earlier(s))),
                    None => (span, "no spindle speed (S) given".to_string()),
                };
                Err(Diagnostic::error(
                    place,
                    format!("feed per revolution ({}) with {what}: the feed is 0 and the move never ends; give S greater than 0", self.per_rev_code()),
                ))
            }
            FeedMode::PerRev if self.feed_set && f <= 0.0 => Err(Diagnostic::error(
                at(self.feed_span),
                format!(
                    "a cutting move at F{} per revolution{}: at feed 0 the move never ends; give F greater than 0",
                    self.feed_word,
                    earlier(self.feed_span)
                ),
            )),
            FeedMode::PerRev => Ok(f * self.speed),
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
        // A lathe's U W H (system A) are increments in an absolute block.
        let stepped = match self.modal.distance {
            Distance::Incremental => named,
            Distance::Absolute => AxisSet(named.0 & self.lathe_increments().0),
        };
        let relative = match kind {
            MoveKind::Rapid | MoveKind::Feed | MoveKind::Arc(_) | MoveKind::Probe
                if stepped.0 & self.guessed.0 != 0 =>
            {
                stepped
            }
            _ => AxisSet::NONE,
        };
        match kind {
            MoveKind::Home | MoveKind::Machine => self.guessed = AxisSet(self.guessed.0 | named.0),
            MoveKind::Dwell(_) => {}
            _ => self.guessed = AxisSet(self.guessed.0 & !(named.0 & !stepped.0)),
        }
        self.place(kind, named);
        // (A state cloned for a scratch run has no frames yet: it builds one.)
        if !self.frame_known || self.toolpath.frames.is_empty() {
            let frame = self.frame();
            if self.toolpath.frames.last() != Some(&frame) {
                self.toolpath.frames.push(frame);
            }
            self.frame_known = self.block_plain;
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
            unknown: AxisSet(self.unplaced.0 | self.at_machine.0),
        };
        self.comp_tag();
        self.toolpath.push(m);
        self.comp_entry();
        self.tip = end;
        self.settle_program(kind, start);
    }

    /// Applies the one-shot codes and the motion of a block. Returns whether
    /// an axis moved.
    #[inline(always)]
    pub(super) fn motion(
        &mut self,
        codes: &[Option<(GCode, Span)>],
        w: &Words,
        span: Span,
        line: u32,
    ) -> Result<bool, Diagnostic> {
        // A LinuxCNC spline is its block's motion only.
        let spline = self.spline.take();
        if first_code(codes, |c| *c == GCode::LengthGiven).is_some() {
            // G43.1's axis words are its offset: nothing moves.
            return Ok(false);
        }
        let one_shot = first_code(codes, |c| c.group() == 0);
        if let Some((GCode::MachineCoords | GCode::Skip, gspan)) = one_shot {
            let has = |g: GCode| first_code(codes, |c| *c == g).is_some();
            if has(GCode::MachineCoords) && has(GCode::Skip) {
                return self.machine_skip(w, gspan, span, line);
            }
        }
        if w.polar() {
            self.polar_rules(one_shot, w)?;
        }
        match one_shot {
            Some((GCode::Dwell, gspan)) => {
                let then_moves = self.dwell(codes, w, gspan, line)?;
                if !then_moves {
                    return Ok(false);
                }
            }
            Some((code @ (GCode::Home | GCode::OtherHome), gspan)) => {
                return self.reference_return(code, w, gspan, line);
            }
            Some((code @ (GCode::ResetShift | GCode::SetPosition | GCode::LocalOffset), _)) => {
                self.shift(code, w, line);
                return Ok(false);
            }
            // A lathe's G50 (G92 in systems B and C) with axis words: the
            // coordinate setting (its S, the clamp, is read apart).
            Some((GCode::LatheSetPosition, _)) => {
                self.shift(GCode::SetPosition, w, line);
                return Ok(false);
            }
            Some((GCode::MachineCoords, gspan)) if self.modal.distance == Distance::Incremental => {
                // Fanuc: G53 ignored, an ordinary incremental move follows.
                self.g53_incremental(gspan)?;
            }
            Some((GCode::MachineCoords, _)) => return Ok(self.machine_move(w, line)),
            Some((GCode::Skip, gspan)) => return self.skip(w, gspan, span, line),
            Some((GCode::Pocket(cw), gspan)) => return self.circular_pocket(cw, w, gspan, line),
            Some((GCode::Grooving(face), gspan)) => return self.grooving_block(face, w, gspan, line),
            Some((GCode::MultipleThreading, gspan)) => return self.threading_block(w, gspan, line),
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
        if let Some(code) = spline {
            return self.spline_block(code, w, span, line);
        }
        if let Some(motion) = self.turning.as_ref().and_then(|t| t.motion) {
            return match motion {
                super::lathe::LatheMotion::Single(cycle) => self.single_cycle(cycle, w, span, line),
                super::lathe::LatheMotion::Threading => self.lathe_thread(w, span, line),
            };
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
        if self.spindle_sync {
            return self.spindle_sync_block(w, span, line);
        }
        self.modal_motion(w, span, line)
    }

    /// `G04`: the dwell. Returns whether the block's motion follows it.
    fn dwell(
        &mut self,
        codes: &[Option<(GCode, Span)>],
        w: &Words,
        gspan: Span,
        line: u32,
    ) -> Result<bool, Diagnostic> {
        let lcnc = self.settings.dialect == crate::Dialect::LinuxCnc;
        if lcnc && !w.has(b'P') {
            return Err(Diagnostic::error(gspan, "G4 needs P, the dwell in seconds (LinuxCNC reads no X dwell)"));
        }
        // A lathe's G04 U is seconds as X is (Fanuc lathe system A).
        let u = if self.turning.is_some() && !lcnc { w.get(b'U') } else { None };
        let seconds = match (w.get(b'P'), w.get(b'X').or(u)) {
            // P is milliseconds on a Fanuc control, seconds on LinuxCNC and GRBL.
            (Some(p), _) if self.settings.integer_input == IntegerInput::Units => p,
            (Some(p), _) => p / 1000.0,
            (None, Some(x)) => x,
            (None, None) if u.is_none() && self.turning.is_some() && !lcnc => {
                return Err(Diagnostic::error(gspan, "G04 needs the dwell time: X or U (seconds) or P (milliseconds)"))
            }
            (None, None) => {
                return Err(Diagnostic::error(gspan, "G04 needs the dwell time: X (seconds) or P (milliseconds)"))
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
        let motion_code = first_code(codes, |c| matches!(c, GCode::Motion(_))).is_some();
        Ok(w.has(b'P') && (motion_code || lcnc) && (w.any_axis() || (lcnc && w.has(b'R'))))
    }

    /// `G28`, `G30`: a return to the reference point, through the point the
    /// axis words give. Returns whether an axis moved.
    fn reference_return(&mut self, code: GCode, w: &Words, gspan: Span, line: u32) -> Result<bool, Diagnostic> {
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
            let axes = (3..Axes::COUNT).filter(|&k| tip[k] != 0.0).fold(AxisSet(0b111), |set, k| set.with(k));
            if code == GCode::OtherHome {
                let p = w.get(b'P').filter(|&p| p != 2.0).map_or(String::new(), |p| format!(" P{p}"));
                let words: String = (0..Axes::COUNT)
                    .filter(|&k| axes.contains(k))
                    .map(|k| format!(" {}0.", Axes::LETTERS[k] as char))
                    .collect();
                self.keep(format!("G91 G30{p}{words}"), 1, false, line);
            }
            self.push_move(MoveKind::Home, home, 0.0, axes, line);
            self.placed_if(self.reference_given(code, w), axes);
            return Ok(true);
        }
        let via = self.target(w);
        let (h, mut v) = (self.reference_point(code, w)?.to_array(), self.tip.to_array());
        let lz = self.length_offset();
        for (i, _) in w.axis_words() {
            v[i] = h[i] - if i == 2 { lz } else { 0.0 };
        }
        let home = Axes::from_array(v);
        // `G91 G28 Z0` has no intermediate move (nor does a via point a
        // rounding away from the tool).
        let (v, t) = (via.to_array(), self.tip.to_array());
        if (0..Axes::COUNT).any(|k| (v[k] - t[k]).abs() > 1e-9) {
            self.push_move(MoveKind::Rapid, via, 0.0, w.axes(), line);
        }
        if code == GCode::OtherHome {
            self.keep_other_return(w, line);
        }
        self.push_move(MoveKind::Home, home, 0.0, w.axes(), line);
        self.placed_if(self.reference_given(code, w), w.axes());
        Ok(true)
    }

    /// `G92.1` (`G92.2`), `G92`, `G52`: shifts that move nothing, kept for
    /// the control as given.
    fn shift(&mut self, code: GCode, w: &Words, line: u32) {
        match code {
            GCode::ResetShift => {
                // The G92 shift is cancelled: on the named axes (Fanuc's
                // preset), on every axis when none is named (LinuxCNC).
                let mut g = self.g92_shift.to_array();
                let named = w.axes();
                for (i, g) in g.iter_mut().enumerate() {
                    if !w.any_axis() || named.contains(i) {
                        *g = 0.0;
                    }
                }
                self.g92_shift = Axes::from_array(g);
            }
            GCode::SetPosition => {
                self.set_position(w);
                self.placed_by_g92(w);
            }
            _ => self.local_offset(w),
        }
        self.guessed = AxisSet::ALL;
        self.keep_as_given(w, false, line);
    }

    /// `G53` in absolute: a rapid in machine coordinates. Returns whether an
    /// axis moved.
    fn machine_move(&mut self, w: &Words, line: u32) -> bool {
        let mut p = self.tip.to_array();
        let lz = self.length_offset();
        for (i, v) in w.axis_words() {
            p[i] = if Axes::is_linear(i) { self.mm(v) } else { v } - if i == 2 { lz } else { 0.0 };
        }
        // G53 positions at rapid traverse whatever the group 1 mode.
        if w.any_axis() {
            self.push_move(MoveKind::Machine, Axes::from_array(p), 0.0, w.axes(), line);
            self.placed_if(self.settings.reference_given[0], w.axes());
        }
        w.any_axis()
    }

    /// `G31`: a skip (probe) move, and where it stops. Returns whether an
    /// axis moved.
    fn skip(&mut self, w: &Words, gspan: Span, span: Span, line: u32) -> Result<bool, Diagnostic> {
        if !w.any_axis() {
            return Ok(false);
        }
        if self.modal.feed_mode == FeedMode::InverseTime {
            return Err(Diagnostic::error(gspan, "a skip move in inverse time feed (G93): give G94 first"));
        }
        let end = self.target(w);
        let feed = self.feed_mm_min(span)?;
        self.push_move(MoveKind::Probe, end, feed, w.axes(), line);
        self.record_skip();
        Ok(true)
    }

    /// Where a skip (probe) move ended, as #5061… read it. Fanuc: in work
    /// coordinates with the tool length offset on Z, as #5041… are.
    /// LinuxCNC: the tip's program position in the program's units when
    /// it was made, kept as they were (its interpreter's `set_probe_data`
    /// stores emccanon's `GET_EXTERNAL_PROBE_POSITION`, the tool offset
    /// taken off and turned into program units; rs274 alone stores the
    /// same numbers).
    fn record_skip(&mut self) {
        let work = self.work_position();
        if !super::params::linuxcnc_numbering(self.settings.dialect) {
            self.skip_position = Axes { z: work.z + self.length_offset(), ..work };
            return;
        }
        let inch = self.modal.units == Units::Inch;
        let mut p = work.to_array();
        for (i, v) in p.iter_mut().enumerate() {
            if inch && Axes::is_linear(i) {
                *v /= 25.4;
            }
        }
        self.skip_position = Axes::from_array(p);
    }

    /// `G53 G31` (Fanuc, Haas): a skip move to a machine position, the
    /// length offset ignored as for G53 (the gauge line goes there); under
    /// G91 the G53 is ignored (a warning) and the skip moves by increments.
    fn machine_skip(&mut self, w: &Words, gspan: Span, span: Span, line: u32) -> Result<bool, Diagnostic> {
        if self.modal.distance == Distance::Incremental {
            self.g53_incremental(gspan)?;
            return self.skip(w, gspan, span, line);
        }
        if !w.any_axis() {
            return Ok(false);
        }
        if self.modal.feed_mode == FeedMode::InverseTime {
            return Err(Diagnostic::error(gspan, "a skip move in inverse time feed (G93): give G94 first"));
        }
        let mut p = self.tip.to_array();
        let lz = self.length_offset();
        for (i, v) in w.axis_words() {
            p[i] = if Axes::is_linear(i) { self.mm(v) } else { v } - if i == 2 { lz } else { 0.0 };
        }
        let feed = self.feed_mm_min(span)?;
        self.push_move(MoveKind::Probe, Axes::from_array(p), feed, w.axes(), line);
        self.record_skip();
        Ok(true)
    }

    /// A move in the motion mode in force: rapid, feed or arc. Returns
    /// whether an axis moved.
    #[inline(always)]
    fn modal_motion(&mut self, w: &Words, span: Span, line: u32) -> Result<bool, Diagnostic> {
        let is_arc = matches!(self.modal.motion, Motion::Cw | Motion::Ccw);
        if !w.any_axis() && !(is_arc && (w.has(b'I') || w.has(b'J') || w.has(b'K'))) {
            return Ok(false);
        }
        let end = self.target(w);
        match self.modal.motion {
            Motion::Rapid => self.push_move(MoveKind::Rapid, end, 0.0, w.axes(), line),
            Motion::Linear => {
                let feed = self.feed_mm_min(span)?;
                self.push_move(MoveKind::Feed, end, feed, w.axes(), line);
            }
            Motion::Cw | Motion::Ccw => {
                let arc = self.arc(w, end, span)?;
                let feed = self.feed_mm_min(span)?;
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
            if let Some(limit) = self.arc_radius_refused(r0, r1) {
                // The control stops here (Fanuc alarm PS0020, over tolerance
                // of radius; LinuxCNC "Radius to end of arc differs from
                // radius to start").
                return Err(Diagnostic::error(
                    span,
                    format!("the arc's end point is {off:.4} mm off its circle (radius {r0:.4} at the start, {r1:.4} at the end): more than {limit}, the control stops with an alarm"),
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

    /// Whether the control refuses an I J K arc whose radius is `r0` at the
    /// start and `r1` at the end (mm): what it allows, in words, if it does.
    /// Fanuc and Haas: the difference past parameter 3410 (0.02 mm unless
    /// the machine file says). LinuxCNC: past its absolute tolerance and
    /// 0.1 % of the larger radius, both, or past 100 times the absolute
    /// tolerance. GRBL: past 0.005 mm and 0.1 %,
    /// both, or past 0.5 mm.
    pub(super) fn arc_radius_refused(&self, r0: f64, r1: f64) -> Option<String> {
        let off = (r1 - r0).abs();
        let given = self.settings.arc_tolerance;
        match self.settings.dialect {
            crate::Dialect::Grbl if given.is_none() => {
                let relative = LINUXCNC_ARC_RELATIVE * r0;
                (off > GRBL_ARC_LIMIT_MM || (off > GRBL_ARC_MM && off > relative))
                    .then(|| format!("GRBL allows ({GRBL_ARC_MM} mm and 0.1 % of the radius, {relative:.4} mm, both)"))
            }
            _ if self.settings.coords.control == Control::LinuxCnc => {
                let absolute = given.unwrap_or(if self.modal.units == Units::Inch {
                    LINUXCNC_ARC_INCH * 25.4
                } else {
                    LINUXCNC_ARC_MM
                });
                let relative = LINUXCNC_ARC_RELATIVE * r0.max(r1);
                (off > 100.0 * absolute || (off > absolute && off > relative)).then(|| {
                    format!(
                        "LinuxCNC allows ({absolute:.4} mm and 0.1 % of the radius, {relative:.4} mm, both; {:.4} mm at most)",
                        100.0 * absolute
                    )
                })
            }
            _ => {
                let limit = given.unwrap_or(ARC_RADIUS_ALARM);
                (off > limit).then(|| format!("{limit} mm"))
            }
        }
    }
}
