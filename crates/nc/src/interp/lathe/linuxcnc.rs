//! LinuxCNC's lathe codes: `G7` diameter mode and `G8` radius mode (how
//! X words are read) and `G33` spindle-synchronised motion, as LinuxCNC's
//! G-code reference describes them and its interpreter rs274 runs them.
//!
//! Under `G7` every X word is a diameter: the tool goes to half of it from
//! the spindle axis, whatever the block does with it (a move, `G92`, `G10`,
//! `G28`'s point). Arc centres `I` `K` stay radii; `G76`'s `I` `J` `K` are
//! diameters too (halved where `G76` reads them).

use kezuri_geom::{Axes, MoveKind, Spindle};

use super::super::modal::{GCode, Units};
use super::super::words::Words;
use super::super::State;
use super::{Lathe, Thread, Turning, XMode};
use crate::number::number;
use crate::source::{Diagnostic, Span};

impl State {
    /// `G7`, `G33`, `G96`, `G97`: LinuxCNC's codes, read here in the
    /// `linuxcnc` dialect (`G96`/`G97` elsewhere are the Fanuc lathe's).
    /// `G7` and `G96` make the control a lathe if the machine file did not:
    /// rs274 reads them on any machine.
    pub(in crate::interp) fn linuxcnc_lathe_code(
        &mut self,
        code: GCode,
        w: &Words,
        gspan: Span,
    ) -> Result<(), Diagnostic> {
        if self.settings.dialect != crate::Dialect::LinuxCnc {
            let what = match code {
                GCode::LatheDiameter => "G07 (lathe diameter mode)",
                _ => "G33 (spindle-synchronised motion)",
            };
            return Err(Diagnostic::error(gspan, format!("{what} is LinuxCNC's: not a code of this dialect")));
        }
        match code {
            GCode::LatheDiameter => {
                if !self.linuxcnc_diameter() {
                    self.ijk_rescaled = Some((self.blocks, 0.5));
                }
                self.linuxcnc_turning().x = XMode::Diameter;
            }
            GCode::ConstantSpeed => {
                // D: the spindle's top speed under constant surface speed
                // (rpm), in force until another G96 D.
                if let Some(d) = w.get(b'D') {
                    if d.is_nan() || d <= 0.0 {
                        return Err(Diagnostic::error(
                            w.span(b'D'),
                            format!("G96 D{d}: D is the top spindle speed in rpm, greater than 0"),
                        ));
                    }
                    self.linuxcnc_turning().clamp = Some(d);
                }
                self.linuxcnc_turning();
                self.constant_speed(true, gspan)?;
            }
            GCode::ConstantSpeedOff => {
                if self.turning.is_some() {
                    self.constant_speed(false, gspan)?;
                }
            }
            _ => {
                self.spindle_sync = true;
                self.rigid_tap = false;
                self.threading = false;
                self.end_cycle();
            }
        }
        Ok(())
    }

    /// The lathe state of a LinuxCNC control, made at its first lathe
    /// code: radius mode (`G8`, LinuxCNC's power-on mode).
    fn linuxcnc_turning(&mut self) -> &mut Turning {
        self.turning.get_or_insert_with(|| Turning::new(Lathe { x: XMode::Radius, ..Lathe::default() }, false))
    }

    /// `G8` (LinuxCNC): radius mode, X read as it is written.
    pub(in crate::interp) fn radius_mode(&mut self) {
        if self.linuxcnc_diameter() {
            self.ijk_rescaled = Some((self.blocks, 2.0));
        }
        self.set_x_mode(XMode::Radius);
    }

    /// Whether LinuxCNC's X words are diameters now (`G7`).
    pub(in crate::interp) fn linuxcnc_diameter(&self) -> bool {
        self.turning.as_ref().is_some_and(|t| !t.fanuc && t.x == XMode::Diameter)
    }

    /// The block's X word read as a radius under `G7`, in the mode after
    /// the block's own `G7`/`G8` (rs274 reads X in the mode in force and
    /// rescales it where the block changes the mode).
    pub(in crate::interp) fn diameter_words(&self, w: &mut Words) {
        if self.linuxcnc_diameter() {
            w.scale(b'X', 0.5);
        }
    }

    /// LinuxCNC's T word: a tool number, a whole number (within 0.0001 as
    /// rs274 reads one).
    pub(in crate::interp) fn linuxcnc_tool_word(&self, w: &Words) -> Result<(), Diagnostic> {
        match w.get(b'T') {
            Some(t) if self.settings.dialect == crate::Dialect::LinuxCnc && (t - t.round()).abs() > 0.0001 => {
                Err(Diagnostic::error(
                    w.span(b'T'),
                    format!("Non integer value for integer: T{t} is no tool number (LinuxCNC stops here)"),
                ))
            }
            _ => Ok(()),
        }
    }

    /// What G76's I J K are multiplied by in this block: ½ under G7, and,
    /// as rs274 (LinuxCNC 2.9) does where G7 or G8 in the block changes the
    /// mode, ½ again (G7) or 2 (G8), with a warning.
    pub(in crate::interp) fn g76_depth_scale(&mut self, span: Span) -> f64 {
        let half = if self.linuxcnc_diameter() { 0.5 } else { 1.0 };
        match self.ijk_rescaled {
            Some((block, k)) if block == self.blocks => {
                let code = if k < 1.0 { "G7" } else { "G8" };
                self.warn(
                    "g76-mode",
                    span,
                    format!(
                        "{code} in a G76 block: LinuxCNC (rs274 2.9) scales I J K for the mode change and again for \
                         the mode, so they are read {} of what is written; give {code} in a block of its own",
                        if k < 1.0 { "a quarter" } else { "twice" }
                    ),
                );
                half * k
            }
            _ => half,
        }
    }

    /// A thread cut from `start` to `end`, `lead` mm a turn, for the report.
    pub(in crate::interp) fn push_thread(&mut self, lead: f64, start: Axes, end: Axes, line: u32) {
        self.threads.push(Thread { lead: lead.abs(), start, end, line });
    }

    /// A block in `G33` mode: a feed from where the tool is to the end
    /// point, synchronised with the spindle so that the tool advances K
    /// along the move each turn (the feed K × rpm), one thread pass. Kept
    /// as its `G33` block for a written program. Returns whether the tool
    /// moved.
    pub(in crate::interp) fn spindle_sync_block(
        &mut self,
        w: &Words,
        span: Span,
        line: u32,
    ) -> Result<bool, Diagnostic> {
        if !w.any_axis() {
            return Ok(false);
        }
        // rs274's refusals, in its order.
        if w.has(b'F') {
            return Err(Diagnostic::error(
                w.span(b'F'),
                "F word used with G33: the feed follows from K and the spindle speed",
            ));
        }
        let Some(k) = w.get(b'K') else {
            return Err(Diagnostic::error(span, "K word missing with G33: give the distance a turn (the lead)"));
        };
        if self.spindle == Spindle::Off {
            return Err(Diagnostic::error(span, "Spindle not turning in G33: give M3 or M4 first"));
        }
        let rpm = self.spindle_rpm();
        if rpm <= 0.0 {
            return Err(Diagnostic::error(
                span,
                "G33 with spindle speed 0: the feed is 0 and the thread never ends; give S greater than 0",
            ));
        }
        let (start, first) = (self.tip, self.toolpath.moves.len());
        let end = self.target(w);
        let lead = self.mm(k);
        self.push_move(MoveKind::Feed, end, (lead * rpm).abs(), w.axes(), line);
        self.push_thread(lead, start, end, line);
        // The block in absolute program coordinates (X a radius), its units
        // with it.
        let unit = if self.modal.units == Units::Inch { 25.4 } else { 1.0 };
        let (e, o) = (end.to_array(), self.frame_offset().to_array());
        let mut text = String::from(if unit == 1.0 { "G21 G90 G33" } else { "G20 G90 G33" });
        for (i, letter) in Axes::LETTERS.into_iter().enumerate().filter(|&(i, _)| w.axes().contains(i)) {
            let v = if Axes::is_linear(i) { (e[i] - o[i]) / unit } else { e[i] - o[i] };
            text.push_str(&format!(" {}{}", letter as char, number(v, 6)));
        }
        text.push_str(&format!(" K{}", number(k, 6)));
        let mut kept = self.kept(first, 1, text, false, line);
        kept.state = kezuri_geom::ToolState::of(&self.toolpath.moves[first]);
        self.toolpath.kept.push(kept);
        Ok(true)
    }

    /// The spindle's turns a minute for a synchronised move.
    fn spindle_rpm(&self) -> f64 {
        self.speed
    }
}
