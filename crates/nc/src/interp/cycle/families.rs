//! The motions of one hole, by the cycle's family: drilling (G81, G82,
//! G73, G83), boring (G85, G86, G88, G89, G76, G87) and tapping (G84,
//! G74).

use kezuri_geom::{Axes, AxisSet, MoveKind, Spindle};

use super::{Levels, LINUXCNC_PECK_CLEARANCE};
use crate::interp::modal::Cycle;
use crate::interp::words::Words;
use crate::interp::State;
use crate::source::{Diagnostic, Span};

impl State {
    /// The motions of one hole of `cycle` from the R level (where the tool
    /// is) and back up; `peck` is the peck depth of G73 and G83, `shift` the
    /// G76 shift away from the wall.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn hole_motion(
        &mut self,
        cycle: Cycle,
        levels: Levels,
        feed: f64,
        peck: Option<f64>,
        shift: [f64; 2],
        span: Span,
        line: u32,
    ) {
        match cycle {
            Cycle::Drill | Cycle::DrillDwell => self.drill(cycle, levels, feed, line),
            // A lathe's drilling cycle with no peck depth: to the bottom in
            // one feed, the dwell P there, rapid out.
            Cycle::Peck | Cycle::SideDrill if peck.is_none() => self.drill(Cycle::DrillDwell, levels, feed, line),
            Cycle::Peck | Cycle::HighSpeedPeck => self.peck(cycle, levels, feed, peck, line),
            Cycle::Bore | Cycle::BoreDwell => self.bore(cycle, levels, feed, line),
            Cycle::BoreStop | Cycle::BoreManual => self.bore_stop(cycle, levels, feed, span, line),
            Cycle::FineBore => self.fine_bore(shift, levels, feed, line),
            Cycle::BackBore => self.back_bore(shift, levels, feed, line),
            Cycle::Tap | Cycle::LeftTap => self.tap(cycle, levels, feed, line),
            // A lathe's side cycles: the face cycles' motions along X (G89
            // with the dwell P at the bottom).
            Cycle::SideDrill => self.peck(Cycle::Peck, levels, feed, peck, line),
            Cycle::SideTap => self.tap(Cycle::Tap, levels, feed, line),
            Cycle::SideBore => self.bore(Cycle::BoreDwell, levels, feed, line),
        }
    }

    /// G81, G82: feed to the bottom, the dwell there (G82), rapid out.
    fn drill(&mut self, cycle: Cycle, l: Levels, feed: f64, line: u32) {
        self.along(MoveKind::Feed, l.bottom, feed, line);
        if cycle == Cycle::DrillDwell {
            self.dwell_here(line);
        }
        self.along(MoveKind::Rapid, l.up, 0.0, line);
    }

    /// G83: pecks of `peck`, each back to R and down to the clearance above
    /// the last depth (on a lathe the dwell P at the bottom, and G87 the
    /// same along X); G73: each back by the retract only.
    fn peck(&mut self, cycle: Cycle, l: Levels, feed: f64, peck: Option<f64>, line: u32) {
        let q = peck.unwrap_or(l.bottom - l.r);
        let (clearance, retract) = if self.settings.dialect == crate::Dialect::LinuxCnc {
            (LINUXCNC_PECK_CLEARANCE, LINUXCNC_PECK_CLEARANCE)
        } else {
            (self.settings.cycles.peck_clearance, self.settings.cycles.peck_retract)
        };
        let mut depth = l.r;
        while depth > l.bottom {
            let next = (depth - q).max(l.bottom);
            if depth < l.r {
                if cycle == Cycle::Peck {
                    // Back to R, then down to the clearance above the last depth.
                    self.along(MoveKind::Rapid, l.r, 0.0, line);
                    self.along(MoveKind::Rapid, depth + clearance, 0.0, line);
                } else {
                    self.along(MoveKind::Rapid, depth + retract, 0.0, line);
                }
            }
            self.along(MoveKind::Feed, next, feed, line);
            depth = next;
        }
        // A lathe's G83 and G87 dwell P at the bottom.
        if self.settings.dialect.is_lathe() {
            self.dwell_here(line);
        }
        self.along(MoveKind::Rapid, l.up, 0.0, line);
    }

    /// G85, G89: feed in, the dwell (G89), feed out to R (LinuxCNC's G89 to
    /// the clear level), rapid the rest.
    fn bore(&mut self, cycle: Cycle, l: Levels, feed: f64, line: u32) {
        self.along(MoveKind::Feed, l.bottom, feed, line);
        if cycle == Cycle::BoreDwell {
            self.dwell_here(line);
        }
        let lcnc_rules = self.settings.dialect == crate::Dialect::LinuxCnc;
        let out = if lcnc_rules && cycle == Cycle::BoreDwell { l.up } else { l.r };
        self.along(MoveKind::Feed, out, feed, line);
        self.rapid_up(l, line);
    }

    /// G86, G88: feed in, the dwell, the spindle stopped, rapid out (G88's
    /// operator retracts by hand).
    fn bore_stop(&mut self, cycle: Cycle, l: Levels, feed: f64, span: Span, line: u32) {
        self.along(MoveKind::Feed, l.bottom, feed, line);
        self.dwell_here(line);
        self.spindle = Spindle::Off;
        if cycle == Cycle::BoreManual {
            self.warn(
                "g88",
                span,
                "G88 stops for the operator to retract by hand: kezuri retracts at rapid with the spindle stopped",
            );
        }
        self.along(MoveKind::Rapid, l.up, 0.0, line);
    }

    /// G76 (Fanuc): feed in, the dwell, an oriented stop, then away from the
    /// wall before the rapid out, and back on the centre.
    fn fine_bore(&mut self, shift: [f64; 2], l: Levels, feed: f64, line: u32) {
        self.along(MoveKind::Feed, l.bottom, feed, line);
        self.dwell_here(line);
        self.spindle = Spindle::Off;
        self.shift_by(shift, 1.0, line);
        self.along(MoveKind::Rapid, l.up, 0.0, line);
        self.shift_by(shift, -1.0, line);
    }

    /// G87: shifted past the wall, down to R below the part, back on the
    /// centre, bore upward to the bottom level, shift, out to the initial
    /// level, back on the centre.
    pub(super) fn back_bore(&mut self, shift: [f64; 2], l: Levels, feed: f64, line: u32) {
        let spindle = self.spindle;
        self.spindle = Spindle::Off;
        self.shift_by(shift, 1.0, line);
        self.along(MoveKind::Rapid, l.r, 0.0, line);
        self.shift_by(shift, -1.0, line);
        self.spindle = if spindle == Spindle::Off { Spindle::Cw } else { spindle };
        self.along(MoveKind::Feed, l.bottom, feed, line);
        self.dwell_here(line);
        self.spindle = Spindle::Off;
        self.shift_by(shift, 1.0, line);
        self.along(MoveKind::Rapid, self.hole.initial, 0.0, line);
        self.shift_by(shift, -1.0, line);
    }

    /// LinuxCNC's G87, from R above the hole, as rs274 runs it: shifted by
    /// I J with the spindle stopped, down to the bottom Z, back on the
    /// centre, the spindle on, feed up to the top K and back down, stopped
    /// again, shifted, out to the clear level, back on the centre.
    pub(super) fn linuxcnc_back_bore(&mut self, shift: [f64; 2], l: Levels, top: f64, feed: f64, line: u32) {
        let spindle = self.spindle;
        self.spindle = Spindle::Off;
        self.shift_by(shift, 1.0, line);
        self.along(MoveKind::Rapid, l.bottom, 0.0, line);
        self.shift_by(shift, -1.0, line);
        self.spindle = spindle;
        self.along(MoveKind::Feed, top, feed, line);
        self.along(MoveKind::Feed, l.bottom, feed, line);
        self.spindle = Spindle::Off;
        self.shift_by(shift, 1.0, line);
        self.along(MoveKind::Rapid, l.up, 0.0, line);
        self.shift_by(shift, -1.0, line);
    }

    /// LinuxCNC's G87 needs I, J (the shift, always incremental) and K (the
    /// top of the back bore) when the cycle begins; later holes keep them.
    pub(super) fn linuxcnc_back_bore_words(&self, span: Span) -> Result<[f64; 2], Diagnostic> {
        match (self.hole.shift, self.hole.back_top) {
            (Some(shift), Some(_)) => Ok(shift),
            _ => Err(Diagnostic::error(
                span,
                "G87 needs I and J (the shift that lets the tool through the hole) and K (the top of the back bore) in LinuxCNC",
            )),
        }
    }

    /// G84, G74: the spindle cutting into the hole, feed in, the dwell, the
    /// spindle reversed, feed out to R (LinuxCNC: to the clear level), the
    /// spindle as it cut.
    fn tap(&mut self, cycle: Cycle, l: Levels, feed: f64, line: u32) {
        let (cut, out) = if cycle == Cycle::Tap { (Spindle::Cw, Spindle::Ccw) } else { (Spindle::Ccw, Spindle::Cw) };
        self.spindle = cut;
        self.along(MoveKind::Feed, l.bottom, feed, line);
        self.dwell_here(line);
        self.spindle = out;
        let lcnc_rules = self.settings.dialect == crate::Dialect::LinuxCnc;
        self.along(MoveKind::Feed, if lcnc_rules { l.up } else { l.r }, feed, line);
        self.spindle = cut;
        self.rapid_up(l, line);
    }

    /// A rapid to the level the hole ends at, where the tool is not there.
    fn rapid_up(&mut self, l: Levels, line: u32) {
        let (_, _, n) = self.cycle_plane().axes();
        if self.tip.to_array()[n] != l.up {
            self.along(MoveKind::Rapid, l.up, 0.0, line);
        }
    }

    /// The G76/G87 shift in the plane: I J as given, or Q along the
    /// machine's shift direction.
    pub(super) fn boring_shift(&self, w: &Words, span: Span, g: u32) -> Result<[f64; 2], Diagnostic> {
        if let Some(s) = self.hole.shift {
            return Ok(s);
        }
        match self.hole.q {
            Some(q) if q > 0.0 => {
                let d = self.settings.cycles.shift_direction;
                Ok([d[0] * q, d[1] * q])
            }
            Some(q) => Err(Diagnostic::error(
                if w.has(b'Q') { w.span(b'Q') } else { span },
                format!("G{g}'s shift Q must be greater than 0 (its direction is the machine's), not {q}"),
            )),
            None => Err(Diagnostic::error(span, format!("G{g} needs the shift away from the wall: Q, or I and J"))),
        }
    }

    /// A rapid move by `sign` × `shift` in the plane.
    fn shift_by(&mut self, shift: [f64; 2], sign: f64, line: u32) {
        if shift == [0.0, 0.0] {
            return;
        }
        let (i, j, _) = self.cycle_plane().axes();
        let mut a = self.tip.to_array();
        a[i] += sign * shift[0];
        a[j] += sign * shift[1];
        self.push_move(MoveKind::Rapid, Axes::from_array(a), 0.0, AxisSet::NONE.with(i).with(j), line);
    }
}
