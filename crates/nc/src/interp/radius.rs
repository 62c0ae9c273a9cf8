//! Cutter radius compensation in the interpreter: G40 / G41 / G42 (and
//! LinuxCNC's G41.1 / G42.1) with the D register, recorded as a tag per
//! move while the program runs; at the end of the run
//! [`comp::compensate_traced`] turns the programmed tool-tip path into the
//! tool-centre path — or, in a run handed on in pieces, as soon as a
//! stretch is done with: compensation off and two moves made since
//! ([`State::comp_flush`]), so only one stretch is held.
//!
//! The run's [`Outcome::toolpath`](super::Outcome::toolpath) is the
//! tool-centre path (what a simulation, the bounds and a CSV dump need);
//! [`Outcome::programmed`](super::Outcome::programmed) keeps the programmed
//! contour with the G41/G42 D and G40 blocks as [`Kept`] blocks for a
//! G-code writer, so that the control applies its own D register (which
//! holds the wear). `docs/cutter-compensation.md` has the rules.
//!
//! On a lathe ([`Settings::lathe_conventions`](super::Settings::lathe_conventions))
//! G41/G42 are tool nose radius compensation: the radius and the imaginary
//! tip direction are the nose of the tool in use ([`Settings::noses`](super::Settings::noses)),
//! no D word; the toolpath is the imaginary tip's
//! ([`compensate_nose`]; `docs/lathe.md`, "Nose radius compensation").

use kezuri_geom::{Axes, Kept, Move, MoveKind, Toolpath};

use super::comp::{self, Comp, Rules, Side};
use super::lathe::nose::{compensate_nose, TipNumbers};
use super::lathe::Nose;
use super::modal::{RadiusComp, Units};
use super::State;
use crate::number::number;
use crate::source::{Diagnostic, Span};
use crate::Error;

/// What the interpreter records for cutter compensation.
#[derive(Clone, Debug, Default)]
pub(super) struct Radius {
    /// The block being executed: its span and 1-based line.
    block: (Span, u32),
    /// The compensation in force, while G41/G42 is.
    on: Option<On>,
    /// The modal D word (Fanuc: the offset number in force).
    d: Option<u32>,
    /// Index of the first recorded move: the first one made after
    /// compensation was first turned on. Nothing is recorded before, so a
    /// program without G41/G42 pays nothing.
    since: Option<usize>,
    /// The compensation in force for each move from `since` on.
    tags: Vec<Option<Comp>>,
    /// The lathe tool's tip vector (X, Z) for each move from `since` on:
    /// (0, 0) for a mill, and while compensation is off.
    tips: Vec<(f64, f64)>,
    /// The block that made each move from `since` on, for located alarms.
    spans: Vec<Span>,
    /// The multiple repetitive cycles' returns to their start points made
    /// while compensation was on: move indices from `since`, ascending.
    returns: Vec<usize>,
    /// LinuxCNC's jumps of the tool centre its compensation works from
    /// ([`State::comp_jump`]): before the move at each index from `since`,
    /// to the point given.
    jumps: Vec<(usize, Axes)>,
    /// The G41/G42 D and G40 blocks for the writer of the programmed
    /// contour, each with its place in `Toolpath::kept` when it was read.
    marks: Vec<(usize, Kept)>,
    /// Whether the entry move of the compensation in force has been made
    /// (LinuxCNC checks it as it is made).
    entered: bool,
    /// LinuxCNC's refusal of an entry move, found as the move was made,
    /// and the move's index in the toolpath: the block stops there ([`State::comp_entry_alarm`]).
    refused: Option<(Diagnostic, usize)>,
    /// A stretch could not be handed on before the end ([`State::comp_flush`]):
    /// the rest of the run is compensated at its end.
    held_to_end: bool,
}

impl Radius {
    /// Compensation has not been turned on in this run: no move or block
    /// is recorded for the centre path.
    pub(super) fn unused(&self) -> bool {
        self.since.is_none() && self.on.is_none() && self.marks.is_empty()
    }
}

/// Moves, each with the index of the input move it comes from.
type Traced = (Vec<Move>, Vec<usize>);

/// Compensation in force.
#[derive(Clone, Copy, Debug)]
struct On {
    side: Side,
    /// The signed radius in mm.
    radius: f64,
    /// Fanuc: the D register whose value `radius` is; a new D word changes
    /// it. `None` where the radius does not follow the D word (LinuxCNC,
    /// a lathe's nose).
    register: Option<u32>,
    /// A lathe tool's tip vector (X, Z): where the machine puts the
    /// imaginary tip from the nose centre. (0, 0) for a mill.
    tip: (f64, f64),
}

/// What the end of a run makes of the recorded moves.
pub(super) struct Compensated {
    /// The programmed contour with the compensation blocks kept.
    pub programmed: Toolpath,
    /// The alarm that stops the run, located at the block of its move.
    pub alarm: Option<Diagnostic>,
}

impl State {
    /// Hook: the block at `span` (line `line`) starts executing.
    pub(super) fn comp_block(&mut self, span: Span, line: u32) {
        self.radius.block = (span, line);
    }

    /// G40, G41, G42, or with `diameter` G41.1 / G42.1, with the block's D
    /// word `d` (written at `dspan`) and L word `l` (G41.1/G42.1: LinuxCNC's
    /// lathe tool orientation, with its span); `gspan` is the G word.
    pub(super) fn comp_code(
        &mut self,
        code: RadiusComp,
        diameter: bool,
        d: Option<f64>,
        dspan: Span,
        l: Option<(f64, Span)>,
        gspan: Span,
    ) -> Result<(), Diagnostic> {
        let rules = self.settings.comp_rules;
        let linuxcnc = rules == Rules::LinuxCnc;
        let side = match code {
            RadiusComp::Off => {
                if self.radius.on.take().is_some() {
                    self.comp_mark("G40".into());
                }
                self.modal.radius_comp = RadiusComp::Off;
                return Ok(());
            }
            RadiusComp::Left => Side::Left,
            RadiusComp::Right => Side::Right,
        };
        let name = format!("G4{}{}", if side == Side::Left { 1 } else { 2 }, if diameter { ".1" } else { "" });
        if diameter && !linuxcnc {
            return Err(Diagnostic::error(
                gspan,
                format!("{name} (cutter compensation by a diameter in D) is LinuxCNC's: these are Fanuc rules, where G41/G42 take the D register"),
            ));
        }
        if linuxcnc && self.radius.on.is_some() {
            return Err(Diagnostic::error(gspan, "Cannot turn cutter radius comp on when on"));
        }
        let at = if d.is_some() { dspan } else { gspan };
        // A lathe's G41/G42 compensate the nose of the tool in use; so do
        // LinuxCNC's, on any machine, for a tool with an orientation.
        if !diameter && (linuxcnc || self.settings.lathe_conventions().is_some()) {
            if let Some(nose) = self.nose_in_use(&name, d, gspan)? {
                // The noses are Fanuc's tips, whatever the dialect (the
                // machine file's `tip`; a tool table's Q turned into it).
                let tip = nose.tip_vector(TipNumbers::Fanuc);
                self.radius.on = Some(On { side, radius: nose.radius, register: None, tip });
                self.radius.entered = false;
                self.modal.radius_comp = code;
                self.comp_mark(name);
                return Ok(());
            }
        }
        // G41.1/G42.1 L: the orientation of the lathe tool whose nose
        // diameter D gives.
        let q = match l {
            Some((l, lspan)) if diameter => {
                let q = orientation(l, lspan)?;
                if self.modal.plane != kezuri_geom::Plane::Zx {
                    return Err(Diagnostic::error(
                        lspan,
                        format!("{name} with L word, but plane is not G18: a lathe tool's orientation is given in the XZ plane"),
                    ));
                }
                Some(q)
            }
            _ => None,
        };
        let (radius, register, text) = if diameter {
            let Some(d) = d else {
                return Err(Diagnostic::error(gspan, format!("{name} needs D, the cutter diameter")));
            };
            let units = if self.modal.units == Units::Inch { "G20" } else { "G21" };
            let mm = if self.modal.units == Units::Inch { d * 25.4 } else { d };
            (mm / 2.0, None, format!("{units} {name} D{}", number(d, 6)))
        } else {
            let n = d.map(|d| register_number(d, at, linuxcnc)).transpose()?;
            if !linuxcnc && n.is_some() {
                self.radius.d = n;
            }
            let register = match (linuxcnc, n) {
                (true, Some(n)) => n,
                // LinuxCNC without D: the loaded tool's radius.
                (true, None) => self.tool,
                (false, _) => {
                    match self.radius.d {
                        Some(n) => n,
                        None => {
                            self.warn("radius", gspan, format!("{name} without a D word, and none before: offset D00, radius 0, the programmed path"));
                            0
                        }
                    }
                }
            };
            let radius = self.register_radius(register, at, linuxcnc)?;
            let text = match n.or(self.radius.d.filter(|_| !linuxcnc)) {
                Some(n) => format!("{name} D{n}"),
                None => name,
            };
            (radius, (!linuxcnc).then_some(register), text)
        };
        let tip = match q {
            Some(q) => {
                Nose { radius: radius.abs(), tip: TipNumbers::LinuxCnc.fanuc_tip(q) }.tip_vector(TipNumbers::Fanuc)
            }
            None => (0.0, 0.0),
        };
        let text = match l {
            Some((l, _)) if diameter => format!("{text} L{}", number(l, 0)),
            _ => text,
        };
        self.radius.on = Some(On { side, radius, register, tip });
        self.radius.entered = false;
        self.modal.radius_comp = code;
        self.comp_mark(text);
        Ok(())
    }

    /// Hook, after the block's words are applied: a Fanuc D word changes the
    /// offset number, and while compensation is on the radius.
    pub(super) fn comp_register(&mut self, d: f64, dspan: Span) -> Result<(), Diagnostic> {
        // LinuxCNC's D names a tool, read at G41/G42; a lathe's radius is
        // its tool's nose.
        if self.settings.comp_rules == Rules::LinuxCnc || self.settings.lathe_conventions().is_some() {
            return Ok(());
        }
        let n = register_number(d, dspan, false)?;
        self.radius.d = Some(n);
        if let Some(on) = self.radius.on {
            if on.register.is_some_and(|r| r != n) {
                let radius = self.register_radius(n, dspan, false)?;
                self.radius.on = Some(On { radius, register: Some(n), ..on });
                self.comp_mark(format!("D{n}"));
            }
        }
        Ok(())
    }

    /// Hook: the move `m` about to be pushed as `toolpath.moves[len]` is
    /// made with the compensation in force now.
    pub(super) fn comp_tag(&mut self) {
        let (tag, tip) = self.comp_in_force();
        if self.radius.since.is_none() {
            if tag.is_none() {
                return;
            }
            self.radius.since = Some(self.toolpath.moves.len());
        }
        self.radius.tags.push(tag);
        self.radius.tips.push(tip);
        self.radius.spans.push(self.radius.block.0);
    }

    /// The compensation a move made now is made with, and its tool's tip
    /// vector (X, Z).
    fn comp_in_force(&self) -> (Option<Comp>, (f64, f64)) {
        // A programmable mirror on one axis of the plane swaps G41 and G42.
        let tag = self.radius.on.map(|on| {
            let side = match (on.side, self.plane_reversed()) {
                (side, false) => side,
                (Side::Left, true) => Side::Right,
                (Side::Right, true) => Side::Left,
            };
            Comp { side, radius: on.radius, plane: self.modal.plane }
        });
        // The tip is off the centre in the ZX plane only (G18, a lathe's).
        let tip = match self.radius.on {
            Some(on) if self.modal.plane == kezuri_geom::Plane::Zx => on.tip,
            _ => (0.0, 0.0),
        };
        (tag, tip)
    }

    /// The imaginary tip's path of a roughing cycle's finishing shape
    /// `moves` (from the cycle's start point, its first block's moves
    /// first) compensated as the compensation in force says: the shape the
    /// roughing is made on (FANUC Series 0i-TF Plus Operator's Manual
    /// (B-64604EN), lathe system, "Multiple repetitive cycle", "Tool nose
    /// radius compensation"). Its offset starts up from the start point on
    /// the shape's first block and ends with the shape, as `G70`'s does.
    /// `None` where no compensation is in force, or with radius 0; else
    /// the moves, each with the index in `moves` it comes from.
    pub(super) fn comp_cycle_shape(&self, moves: &[Move]) -> Option<Result<Traced, Error>> {
        let (Some(tag), tip) = self.comp_in_force() else { return None };
        let (first, last) = (moves.first()?, moves.last()?);
        if tag.radius == 0.0 {
            return None;
        }
        let n = moves.len();
        // The return to the start point closes the run, with the offset
        // cancelled: the shape's end is on the vector perpendicular to it.
        let back = Move { kind: MoveKind::Rapid, start: last.end, end: first.start, ..*last };
        let all: Vec<Move> = moves.iter().copied().chain([back]).collect();
        let tags: Vec<Option<Comp>> = (0..=n).map(|k| (k < n).then_some(tag)).collect();
        let tips = vec![tip; n + 1];
        Some(compensate_nose(&all, &tags, &tips, &[n], &[], self.settings.comp_rules).map(|(out, origin)| {
            let keep = origin.iter().take_while(|&&o| o < n).count();
            (out[..keep].to_vec(), origin[..keep].to_vec())
        }))
    }

    /// LinuxCNC's rule for the entry move `m`, the first move after
    /// G41/G42 that is not a dwell, checked as the move is made: its travel
    /// in the compensation plane must be longer than the tool radius (the
    /// nose centre is put off its end by that radius, perpendicular to it).
    /// `rs274` stops there, before the blocks after it are read.
    #[inline(always)]
    pub(super) fn comp_entry(&mut self) {
        let Some(on) = self.radius.on else { return };
        let Some(m) = self.toolpath.moves.last() else { return };
        if self.radius.entered || matches!(m.kind, MoveKind::Dwell(_)) {
            return;
        }
        let (kind, a, b) = (m.kind, m.start.xyz(), m.end.xyz());
        self.radius.entered = true;
        if self.settings.comp_rules != Rules::LinuxCnc || on.radius == 0.0 {
            return;
        }
        let (i, j, _) = self.modal.plane.axes();
        let travel = (b[i] - a[i]).hypot(b[j] - a[j]);
        if travel <= on.radius.abs() {
            let arc = matches!(kind, MoveKind::Arc(_));
            let message = comp::entry_too_short(arc);
            let (mm, unit) = if self.modal.units == Units::Inch { (25.4, "in") } else { (1.0, "mm") };
            let why = format!(
                "{message}: the entry move travels {:.4} {unit} in the plane, the radius is {:.4} {unit} (LinuxCNC \
                 puts the tool centre off the entry move's end by the radius, square to it; make the entry move \
                 longer)",
                travel / mm,
                on.radius.abs() / mm,
            );
            let alarm = Diagnostic::error(self.radius.block.0, self.comp_alarm(&why));
            self.radius.refused = Some((alarm, self.toolpath.moves.len() - 1));
        }
    }

    /// The refusal of an entry move made by the block just executed: the
    /// move and what followed it in the block are taken back, as the
    /// control stops before making them.
    #[inline(always)]
    pub(super) fn comp_entry_alarm(&mut self) -> Result<(), Diagnostic> {
        // Tested before it is taken: a refusal is rare, and large to move.
        if self.radius.refused.is_none() {
            return Ok(());
        }
        let Some((alarm, end)) = self.radius.refused.take() else { return Ok(()) };
        if let Some(since) = self.radius.since {
            let k = end.saturating_sub(since);
            self.toolpath.moves.truncate(end);
            self.toolpath.kept.retain(|kept| kept.before <= end);
            self.radius.tags.truncate(k);
            self.radius.tips.truncate(k);
            self.radius.spans.truncate(k);
        }
        Err(alarm)
    }

    /// Hook: a move is added after the last with the compensation of the
    /// last (a lathe's corner splits a block's move in two).
    pub(super) fn comp_repeat_tag(&mut self) {
        if self.radius.since.is_none() {
            return;
        }
        if let (Some(&tag), Some(&tip), Some(&span)) =
            (self.radius.tags.last(), self.radius.tips.last(), self.radius.spans.last())
        {
            self.radius.tags.push(tag);
            self.radius.tips.push(tip);
            self.radius.spans.push(span);
        }
    }

    /// A multiple repetitive cycle's return to its start point, made by
    /// `make` (which pushes it): with compensation in force, the cycle's
    /// offset ends with its shape and the return is made with the offset
    /// cancelled (FANUC Series 0i-TF Plus Operator's Manual (B-64604EN),
    /// lathe system, "Multiple repetitive cycle", "Tool nose radius
    /// compensation"); compensation stays in force for the blocks after.
    pub(super) fn comp_cycle_return(&mut self, make: impl FnOnce(&mut State)) {
        let on = self.radius.on.take();
        let at = self.toolpath.moves.len();
        make(self);
        if let (Some(_), Some(since)) = (on, self.radius.since) {
            if self.toolpath.moves.len() > at {
                self.radius.returns.push(at - since);
            }
        }
        self.radius.on = on;
    }

    /// LinuxCNC: reading a lathe cycle's profile has left the position its
    /// compensation works from at `at`, the profile's last point, while
    /// the tool has not moved: the next move under compensation is
    /// compensated from there (`rs274ngc/interp_g7x.cc`, `convert_g7x`:
    /// each profile block read sets `current_x`/`current_z`, which under
    /// compensation are the tool centre's, and leaves `program_x`/`_z`).
    /// Only G70 runs under compensation, and its first pass's start rapid
    /// is that move (`docs/cutter-compensation.md`, "LinuxCNC's G70").
    pub(super) fn comp_jump(&mut self, at: Axes) {
        if self.radius.on.is_none() || self.settings.comp_rules != Rules::LinuxCnc {
            return;
        }
        let len = self.toolpath.moves.len();
        let since = *self.radius.since.get_or_insert(len);
        self.radius.jumps.push((len - since, at));
    }

    /// The cycles' returns and the jumps among the recorded moves `range`
    /// (indices from `since`), as indices from the range's start.
    fn comp_marks(&self, range: std::ops::Range<usize>) -> (Vec<usize>, Vec<(usize, Axes)>) {
        let returns = self.radius.returns.iter().filter(|&&k| range.contains(&k)).map(|&k| k - range.start);
        let jumps = self.radius.jumps.iter().filter(|(k, _)| range.contains(k)).map(|&(k, p)| (k - range.start, p));
        (returns.collect(), jumps.collect())
    }

    /// At the end of the run: replaces the toolpath by the tool-centre path
    /// and returns the programmed contour, or `None` when no move was made
    /// with compensation on. An alarm cuts both paths before its move.
    pub(super) fn comp_finish(&mut self) -> Option<Compensated> {
        let since = self.radius.since?;
        let rules = self.settings.comp_rules;
        let mut programmed = self.toolpath.clone();
        programmed.kept = merge(std::mem::take(&mut programmed.kept), std::mem::take(&mut self.radius.marks));
        let mut end = self.toolpath.moves.len();
        let mut alarm = None;
        let centre = loop {
            let (tags, tips) = (&self.radius.tags[..end - since], &self.radius.tips[..end - since]);
            let (returns, jumps) = self.comp_marks(0..end - since);
            match compensate_nose(&self.toolpath.moves[since..end], tags, tips, &returns, &jumps, rules) {
                Ok(done) => break Some(done),
                // A control stops at the alarm: nothing from its move on is
                // made. Where the moves before it fail in turn, the control
                // stops before, at theirs (found later: a corner's trim is
                // checked as the moves are made, after every corner is
                // planned).
                Err(e) => {
                    let k = e.move_index().unwrap_or_default();
                    let span = self.radius.spans.get(k).copied().unwrap_or(self.radius.block.0);
                    alarm = Some(Diagnostic::error(span, self.comp_alarm(&e.message)));
                    end = since + k;
                }
            }
        };
        if alarm.is_some() {
            programmed.moves.truncate(end);
            programmed.kept.retain(|k| k.before <= end);
            self.toolpath.moves.truncate(end);
            self.toolpath.kept.retain(|k| k.before <= end);
        }
        if let Some((moves, origin)) = centre {
            // Kept blocks are placed by programmed move index: place them in
            // the compensated moves by the move each comes from.
            let place = |b: usize| if b < since { b } else { since + origin.partition_point(|&o| o + since < b) };
            for k in &mut self.toolpath.kept {
                let (first, last) = (place(k.before), place(k.before + k.moves));
                (k.before, k.moves) = (first, last - first);
            }
            self.toolpath.moves.truncate(since);
            self.toolpath.moves.extend(moves);
        }
        Some(Compensated { programmed, alarm })
    }

    /// With the run's path handed on in pieces: once compensation is off
    /// and the last two moves were made without it, the moves recorded are
    /// made the centre path at once, as [`State::comp_finish`] makes them,
    /// and all but the last are returned with their programmed contour to
    /// be handed on; the record starts again empty. `None` where the
    /// stretch must wait: compensation on, a cycle or a lathe's contour
    /// unsettled, a kept block over the last move, or an alarm (then it
    /// waits for the end of the run, as a run not handed on does).
    pub(super) fn comp_flush(&mut self) -> Option<(Toolpath, Toolpath)> {
        let since = self.radius.since?;
        let n = self.radius.tags.len();
        let len = self.toolpath.moves.len();
        let off = self.radius.on.is_none() && n >= 2 && self.radius.tags[n - 2..].iter().all(Option::is_none);
        let settled = self.hole.settled() && self.turning.is_none() && self.profile.is_none();
        if !off || !settled || self.radius.held_to_end || self.radius.refused.is_some() || since + n != len {
            return None;
        }
        if self.toolpath.cut_at_or_before(len - 1) != len - 1 {
            return None;
        }
        let before = (self.toolpath.clone(), self.radius.clone());
        let Compensated { mut programmed, alarm } = self.comp_finish()?;
        let (centre_last, programmed_last) = (self.toolpath.moves.len() - 1, programmed.moves.len() - 1);
        let piece = self.toolpath.split_before(centre_last);
        let programmed_piece = programmed.split_before(programmed_last);
        if alarm.is_some() || programmed != self.toolpath {
            (self.toolpath, self.radius) = before;
            self.radius.held_to_end = true;
            return None;
        }
        self.radius = Radius { block: self.radius.block, d: self.radius.d, ..Radius::default() };
        Some((piece, programmed_piece))
    }

    /// The radius in register `n` (a D number, or a LinuxCNC tool number);
    /// 0 for register 0. One the tool table lacks reads 0 with a warning, or
    /// is an error where the compensated path is needed.
    pub(super) fn register_radius(&mut self, n: u32, at: Span, linuxcnc: bool) -> Result<f64, Diagnostic> {
        if n == 0 {
            return Ok(0.0);
        }
        if let Some(r) = self.tool_radius(n) {
            return Ok(r);
        }
        let what = if linuxcnc { format!("tool {n}") } else { format!("D{n}") };
        if self.settings.radii_required {
            return Err(Diagnostic::error(
                at,
                format!("{what} has no radius in the tool table (machine file [tools] radii): the tool centre path cannot be made"),
            ));
        }
        self.warn(
            "radius",
            at,
            format!("{what} has no radius in the tool table (machine file [tools] radii): compensation with radius 0, the programmed path"),
        );
        Ok(0.0)
    }

    /// Where the tool centre rests when compensation was turned off (G40)
    /// and nothing has moved since: the end of the last compensated move,
    /// off the programmed point by the radius. `None` where the tool is on
    /// the programmed point (compensation on, never on, or a move since).
    /// LinuxCNC re-reads the position after a tool change and finds the
    /// tool there.
    pub(super) fn comp_resting_point(&self) -> Option<Axes> {
        if self.radius.on.is_some() {
            return None;
        }
        let since = self.radius.since?;
        let (moves, tags) = (&self.toolpath.moves[since..], &self.radius.tags);
        // Dwells after G40 are made where the tool is.
        let mut end = tags.len().min(moves.len());
        while end > 0 && tags[end - 1].is_none() && matches!(moves[end - 1].kind, MoveKind::Dwell(_)) {
            end -= 1;
        }
        if end == 0 || tags[end - 1].is_none() {
            return None;
        }
        let start = tags[..end].iter().rposition(Option::is_none).map_or(0, |k| k + 1);
        let tips = &self.radius.tips[start..end];
        let (returns, jumps) = self.comp_marks(start..end);
        let rules = self.settings.comp_rules;
        let (centre, _) = compensate_nose(&moves[start..end], &tags[start..end], tips, &returns, &jumps, rules).ok()?;
        centre.last().map(|m| m.end)
    }

    /// A compensation alarm's text: a lathe's G41/G42 compensate the nose.
    pub(super) fn comp_alarm(&self, message: &str) -> String {
        if self.settings.lathe_conventions().is_some() {
            let message = message
                .replace("cutter compensation", "nose radius compensation")
                .replace("cutter radius", "nose radius");
            format!("tool nose radius compensation: {message}")
        } else {
            format!("cutter compensation: {message}")
        }
    }

    /// The nose of the tool a lathe's G41/G42
    /// (`name`, the G word at `gspan`) compensates: the tool in use, or
    /// with LinuxCNC's rules the tool its D word names. `None` where
    /// LinuxCNC's tool has no nose but may have a radius in the tool table
    /// (its mill rule then applies, tip 0). A tip direction outside 0–9 or
    /// a radius that is no length is an error; a tool with no nose a
    /// warning and radius 0, or an error where the nose centre path is
    /// needed.
    fn nose_in_use(&mut self, name: &str, d: Option<f64>, gspan: Span) -> Result<Option<Nose>, Diagnostic> {
        let linuxcnc = self.settings.comp_rules == Rules::LinuxCnc;
        let tool = match d {
            Some(d) if linuxcnc && d >= 0.0 && d.fract() == 0.0 => d as u32,
            _ => self.tool,
        };
        let nose = self.settings.noses.get(&tool).copied();
        match nose {
            Some(nose) => {
                nose.check().map_err(|why| {
                    Diagnostic::error(gspan, format!("{name}: tool {tool}'s {why}: the nose centre path cannot be made"))
                })?;
                Ok(Some(nose))
            }
            None if linuxcnc => Ok(None),
            None if self.settings.radii_required => Err(Diagnostic::error(
                gspan,
                format!(
                    "{name}: tool {tool} has no nose radius and tip direction (machine file [tools.T{tool}] nose_radius \
                     and tip): the nose centre path cannot be made"
                ),
            )),
            None => {
                self.warn(
                    "radius",
                    gspan,
                    format!(
                        "{name}: tool {tool} has no nose radius and tip direction (machine file [tools.T{tool}] \
                         nose_radius and tip): compensation with radius 0, the programmed path"
                    ),
                );
                Ok(Some(Nose { radius: 0.0, tip: 0 }))
            }
        }
    }

    /// Whether cutter compensation is on.
    pub(super) fn comp_on(&self) -> bool {
        self.radius.on.is_some()
    }

    /// Keeps a compensation block for the writer of the programmed contour.
    fn comp_mark(&mut self, text: String) {
        let before = self.toolpath.moves.len();
        let kept = self.kept(before, 0, text, false, self.radius.block.1);
        self.radius.marks.push((self.toolpath.kept.len(), kept));
    }
}

/// LinuxCNC's lathe tool orientation: the `L` of `G41.1`/`G42.1`, a whole
/// number 0–9 (`rs274` refuses a fraction and a negative number, and runs
/// one above 9 as the nose centre: kezuri refuses it, a number no tool
/// table holds).
fn orientation(l: f64, at: Span) -> Result<u8, Diagnostic> {
    if l.fract() != 0.0 {
        return Err(Diagnostic::error(
            at,
            format!("Non integer value for integer: L{l}, the tool's orientation, is a whole number 0 to 9"),
        ));
    }
    if l < 0.0 {
        return Err(Diagnostic::error(at, format!("Negative l word used: L{l}, the tool's orientation, is 0 to 9")));
    }
    if l > 9.0 {
        return Err(Diagnostic::error(
            at,
            format!("L{l}: a lathe tool's orientation is 0 to 9 (1–8 round the nose, 0 and 9 the nose centre)"),
        ));
    }
    Ok(l as u8)
}

/// A D word's value as a register number.
fn register_number(d: f64, at: Span, linuxcnc: bool) -> Result<u32, Diagnostic> {
    if linuxcnc && d < 0.0 {
        return Err(Diagnostic::error(at, "Negative D word tool radius index used"));
    }
    if d.fract() != 0.0 || !(0.0..=999.0).contains(&d) {
        return Err(Diagnostic::error(at, format!("D{d}: an offset number is a whole number from 0 to 999")));
    }
    Ok(d as u32)
}

/// `kept` with each mark inserted at the place it was read at.
fn merge(kept: Vec<Kept>, marks: Vec<(usize, Kept)>) -> Vec<Kept> {
    let mut out = Vec::with_capacity(kept.len() + marks.len());
    let mut marks = marks.into_iter().peekable();
    for (i, k) in kept.into_iter().enumerate() {
        while let Some((_, m)) = marks.next_if(|(at, _)| *at <= i) {
            out.push(m);
        }
        out.push(k);
    }
    out.extend(marks.map(|(_, m)| m));
    out
}
