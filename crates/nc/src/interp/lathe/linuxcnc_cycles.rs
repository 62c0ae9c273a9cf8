//! LinuxCNC's lathe cycles `G70` (finishing), `G71` and `G72` (roughing
//! along Z, along X) and their `.1` and `.2`, the profile given by the
//! O-word subroutine `Q` (LinuxCNC's G-code reference, "G70 Lathe
//! finishing cycle", "G71 G72 Lathe roughing cycles").
//!
//! The cycle's block moves the tool to its X Z (a rapid), then calls the
//! subroutine: its blocks are read, not run — each `G0`–`G3` adds a piece
//! to the profile (`G0` cut as `G1`), `A` a fillet and `C` a chamfer at its
//! end, `U` and `W` incremental X and Z (`U` a diameter under `G7`); every
//! other code is left. When the subroutine returns the profile is cut
//! (`profile.rs`).

use kezuri_geom::{Arc, Axes, AxisSet, MoveKind, Plane};

use super::super::block::Action;
use super::super::modal::{Distance, GCode, Motion, Units};
use super::super::words::Words;
use super::super::State;
use super::linuxcnc_profile::{Corner, Out, Profile, Seg, P};
use crate::source::{Diagnostic, Span};

/// A cycle waiting for its subroutine's profile.
#[derive(Clone, Debug)]
pub(in crate::interp) struct Capture {
    /// 70, 71 or 72, and the kind (`G71.1`: 1).
    cycle: u32,
    kind: u8,
    /// The subroutine level the cycle was called from.
    level: u32,
    /// The cycle's words, program units (X a radius).
    x: f64,
    z: f64,
    d: f64,
    e: f64,
    i: f64,
    p: f64,
    r: f64,
    u: f64,
    w: f64,
    /// The profile so far and where it has got to; whether a block moved
    /// the position.
    at: P,
    moved: bool,
    segs: Vec<Seg>,
    /// The motion mode the profile's blocks are read in (0–3: G0–G3;
    /// `None`: another, whose blocks add nothing).
    motion: Option<u8>,
    /// G91 and G91.1 when the cycle began: how the profile's words read.
    incremental: bool,
    ijk_incremental: bool,
    /// Where the tool is: the profile's blocks move the position the
    /// program reads (`#<_x>`), not the tool.
    tool: Axes,
    span: Span,
    line: u32,
}

impl State {
    /// Whether a LinuxCNC lathe cycle is reading its profile.
    pub(in crate::interp) fn reading_profile(&self) -> bool {
        self.profile.is_some()
    }

    /// The program units of `v` mm.
    fn units_of(&self, v: f64) -> f64 {
        if self.modal.units == Units::Inch {
            v / 25.4
        } else {
            v
        }
    }

    /// A `G70`/`G71`/`G72` block (`tenths`: 700, 711 …): the rapid to its
    /// X Z, then the call of its subroutine Q, whose profile is read.
    pub(in crate::interp) fn profile_cycle(
        &mut self,
        tenths: u32,
        w: &Words,
        gspan: Span,
        line: u32,
    ) -> Result<Action, Diagnostic> {
        // The cycle's U W are its allowances, not axes.
        let w = &w.six_axes();
        let (cycle, kind) = (tenths / 10, (tenths % 10) as u8);
        let name = if kind == 0 { format!("G{cycle}") } else { format!("G{cycle}.{kind}") };
        if self.settings.dialect != crate::Dialect::LinuxCnc {
            return Err(Diagnostic::error(gspan, format!("{name} with Q (a profile subroutine) is LinuxCNC's")));
        }
        let Some(q) = w.get(b'Q') else {
            return Err(Diagnostic::error(gspan, format!("{name} requires a Q word: the profile's subroutine")));
        };
        if q.fract() != 0.0 || q < 0.0 || q > f64::from(u32::MAX) {
            return Err(Diagnostic::error(w.span(b'Q'), format!("{name}: Q{q} is no subroutine number")));
        }
        if self.comp_on() && cycle != 70 {
            return Err(Diagnostic::error(gspan, format!("{name} cannot be used with cutter compensation enabled")));
        }
        if self.modal.plane != Plane::Zx {
            return Err(Diagnostic::error(gspan, format!("{name} can only be used in XZ plane (G18)")));
        }
        let here = self.program_position();
        let (mut x, mut z) = (self.units_of(here.x), self.units_of(here.z));
        let incremental = self.modal.distance == Distance::Incremental;
        for (letter, v) in [(b'X', &mut x), (b'Z', &mut z)] {
            if let Some(n) = w.get(letter) {
                *v = if incremental { *v + n } else { n };
            }
        }
        if w.any_axis() {
            // rs274 reads the cycle's rapid in absolute distance mode, G91
            // or not (the cycle's X Z above are incremental under G91).
            let (o, mut end) = (self.frame_offset().to_array(), self.tip.to_array());
            for (k, v) in w.axis_words() {
                end[k] = if Axes::is_linear(k) { self.mm(v) } else { v } + o[k];
            }
            self.push_move(MoveKind::Rapid, Axes::from_array(end), 0.0, w.axes(), line);
        }
        self.modal.motion = Motion::Rapid;
        let get = |letter: u8, default: f64| w.get(letter).unwrap_or(default);
        self.profile = Some(Box::new(Capture {
            cycle,
            kind,
            level: self.call_level,
            x,
            z,
            d: get(b'D', 0.0),
            e: get(b'E', 0.0),
            i: get(b'I', 1.0),
            p: get(b'P', 1.0),
            r: get(b'R', 0.5),
            u: get(b'U', 0.0),
            w: get(b'W', 0.0),
            at: P::new(z, x),
            moved: false,
            segs: Vec::new(),
            // The cycle's rapid leaves G0 in force: the profile's first
            // block without a motion code is a line.
            motion: Some(0),
            incremental,
            ijk_incremental: !self.coords.arc_absolute,
            tool: self.tip,
            span: gspan,
            line,
        }));
        Ok(Action::OCall { number: q as u32, span: gspan })
    }

    /// A block of the profile's subroutine: its piece of the profile.
    pub(in crate::interp) fn profile_block(
        &mut self,
        w: &Words,
        codes: &[Option<(GCode, Span)>],
        span: Span,
    ) -> Result<(), Diagnostic> {
        let half = if self.linuxcnc_diameter() { 0.5 } else { 1.0 };
        let Some(c) = self.profile.as_deref_mut() else { return Ok(()) };
        let fault = |span: Span, m: &str| Err(Diagnostic::error(span, format!("G7x error: {m}")));
        let start = c.at;
        let mut end = if c.incremental { P::new(0.0, 0.0) } else { start };
        for (inc, abs, is_x) in [(b'U', b'X', true), (b'W', b'Z', false)] {
            let v = if let Some(step) = w.get(inc) {
                if c.incremental {
                    return fault(w.span(inc), &format!("Cannot use {} in incremental mode (G91)", inc as char));
                }
                if w.has(abs) {
                    return fault(
                        w.span(inc),
                        &format!("Cannot use {} and {} in the same block", inc as char, abs as char),
                    );
                }
                let step = if is_x { step * half } else { step };
                Some(if is_x { end.x + step } else { end.z + step })
            } else {
                w.get(abs).map(|v| if is_x { v * half } else { v })
            };
            match (v, is_x) {
                (Some(v), true) => end.x = v,
                (Some(v), false) => end.z = v,
                _ => {}
            }
        }
        let mut centre = P::new(w.get(b'K').unwrap_or(0.0), w.get(b'I').unwrap_or(0.0));
        if c.incremental {
            end = end + start;
        }
        for (code, _) in codes.iter().flatten() {
            match code {
                GCode::Motion(m) => c.motion = Some(*m as u8),
                other if other.group() == 1 => c.motion = None,
                _ => {}
            }
        }
        if start == end {
            return Ok(());
        }
        let seg = match c.motion {
            // Another motion mode: the position moves, the profile has no piece.
            None => None,
            Some(0 | 1) => Some(Seg::line(start, end)),
            Some(mode) => {
                if let Some(r) = w.get(b'R') {
                    if w.has(b'I') || w.has(b'K') {
                        return fault(w.span(b'R'), "both R and I or K flag used for arc");
                    }
                    let chord = end - start;
                    let n = chord.z * chord.z + chord.x * chord.x;
                    if r * r < n / 4.0 || r.is_nan() {
                        return fault(w.span(b'R'), &format!("the arc's radius R{r} is less than half its chord"));
                    }
                    let k = ((r * r - n / 4.0) / n).sqrt();
                    let mid = P::new((start.z + end.z) / 2.0, (start.x + end.x) / 2.0);
                    // The chord turned a quarter, times k, to the centre.
                    let d = P::new(-chord.x * k, chord.z * k);
                    centre = if mode == 3 { mid + d } else { mid - d };
                } else {
                    if !w.has(b'I') && !w.has(b'K') {
                        return fault(span, "either I or K must be present for arc");
                    }
                    if c.ijk_incremental {
                        centre = centre + start;
                    }
                }
                Some(Seg::arc(mode == 3, start, centre, end))
            }
        };
        if let Some(seg) = seg {
            c.segs.push(seg);
            match (w.get(b'A'), w.get(b'C')) {
                (Some(_), Some(_)) => return fault(w.span(b'C'), "Both A and C parameters on a corner"),
                (Some(a), None) => c.segs.push(Seg::corner(Corner::Fillet(a), end)),
                (None, Some(k)) => c.segs.push(Seg::corner(Corner::Chamfer(k), end)),
                _ => {}
            }
        }
        (c.at, c.moved) = (end, true);
        // rs274 reads the profile's point as the position (#<_x>, #<_z>).
        let o = self.frame_offset();
        (self.tip.x, self.tip.z) = (self.mm(end.x) + o.x, self.mm(end.z) + o.z);
        Ok(())
    }

    /// After a subroutine returns to `level`: the cycle that called it for
    /// its profile cuts it.
    pub(in crate::interp) fn profile_returned(&mut self, level: u32) -> Result<(), Diagnostic> {
        let Some(c) = self.profile.take_if(|c| c.level == level) else { return Ok(()) };
        let c = *c;
        // rs274 read the profile by moving its position, not the tool: it
        // compensates the cycle's next move from the profile's end (G70:
        // the first pass's start rapid, which goes there).
        if c.moved {
            self.comp_jump(self.tip);
        }
        self.tip = c.tool;
        if c.segs.len() <= 1 {
            return Ok(());
        }
        let error = |m: String| Diagnostic::error(c.span, format!("G7X error: {m}"));
        if c.i <= 0.0 {
            return Err(error("I must be greater than zero.".into()));
        }
        let profile = Profile::new(c.segs.clone());
        let moves = match c.cycle {
            70 => profile.finish(c.x, c.z, c.d, c.e, c.p),
            _ => profile.rough(c.cycle == 72, c.kind, (c.x, c.z), (c.u, c.w), c.d, c.i, c.r),
        }
        .map_err(error)?;
        self.cut_profile(&moves, c.span, c.line)
    }

    /// The cycle's moves, from program coordinates to the machine's.
    fn cut_profile(&mut self, moves: &[Out], span: Span, line: u32) -> Result<(), Diagnostic> {
        let finite = |p: &P| p.z.is_finite() && p.x.is_finite();
        if !moves.iter().all(|m| match m {
            Out::Rapid(p) | Out::Feed(p) => finite(p),
            Out::Arc(p, c, _) => finite(p) && finite(c),
        }) {
            return Err(Diagnostic::error(span, "G7X error: the profile's pieces do not meet where they are moved"));
        }
        let xz = AxisSet::NONE.with(0).with(2);
        let first = self.toolpath.moves.len();
        let o = self.frame_offset();
        let place = |s: &State, p: P| Axes { x: s.mm(p.x) + o.x, z: s.mm(p.z) + o.z, ..s.tip };
        for m in moves {
            match *m {
                Out::Rapid(p) => {
                    self.push_move(MoveKind::Rapid, place(self, p), 0.0, xz, line);
                    self.modal.motion = Motion::Rapid;
                }
                Out::Feed(p) => {
                    let feed = self.feed_mm_min(span)?;
                    self.push_move(MoveKind::Feed, place(self, p), feed, xz, line);
                    self.modal.motion = Motion::Linear;
                }
                Out::Arc(p, c, ccw) => {
                    let end = place(self, p);
                    // rs274 makes no arc to where the tool is.
                    if (end.x - self.tip.x).abs() < 1e-4 && (end.z - self.tip.z).abs() < 1e-4 {
                        continue;
                    }
                    let centre = place(self, c);
                    let r0 = (self.tip.x - centre.x).hypot(self.tip.z - centre.z);
                    let r1 = (end.x - centre.x).hypot(end.z - centre.z);
                    if let Some(limit) = self.arc_radius_refused(r0, r1) {
                        return Err(Diagnostic::error(
                            span,
                            format!(
                                "Radius to end of arc differs from radius to start: the cycle's arc is {:.4} mm off \
                                 its circle (radius {r0:.4} at the start, {r1:.4} at the end), more than {limit}",
                                (r1 - r0).abs()
                            ),
                        ));
                    }
                    let arc = Arc { center: [centre.x, self.tip.y, centre.z], plane: Plane::Zx, ccw, turns: 0 };
                    let feed = self.feed_mm_min(span)?;
                    self.push_move(MoveKind::Arc(arc), end, feed, xz, line);
                    self.modal.motion = if ccw { Motion::Ccw } else { Motion::Cw };
                }
            }
        }
        // Under constant surface speed: each move's speed and time.
        self.lathe_moves(first, true, &Words::new(&[], span.file), span)
    }
}
