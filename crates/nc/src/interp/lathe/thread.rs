//! `G32` (`G33` in systems B and C): a threading move, the feed tied to the
//! spindle. FANUC Series 0i-TF Plus Operator's Manual (B-64604EN), lathe
//! system, "Threading (G32)": `G32 X(U)_ Z(W)_ F_`, F the lead along the
//! longer axis (Z for a taper of up to 45°), in mm (inches under G20) per
//! revolution, whatever G98/G99.

use kezuri_geom::MoveKind;

use super::super::words::Words;
use super::super::State;
use super::speed::thread_stretch;
use super::Thread;
use crate::source::{Diagnostic, Span};

impl State {
    /// A block in threading mode: a feed move at lead × rpm (along the lead
    /// axis), and the thread it cuts. S0 or F0: a located error
    /// ([`State::thread_lead`]).
    pub(in super::super) fn lathe_thread(&mut self, w: &Words, span: Span, line: u32) -> Result<bool, Diagnostic> {
        if !w.any_axis() {
            return Ok(false);
        }
        let lead = self.thread_lead(w, span)?;
        let start = self.tip;
        let end = self.target(w);
        let axes = w.axes();
        self.push_move(MoveKind::Feed, end, 0.0, axes, line);
        let Some(m) = self.toolpath.moves.last_mut() else { return Ok(true) };
        // Under constant surface speed the feed is set after the block
        // (its time integrated with the speed along the move).
        m.feed = lead * self.speed * thread_stretch(m);
        self.threads.push(Thread { lead, start, end, line });
        Ok(true)
    }

    /// The lead of a threading block or cycle (F, mm a turn; Haas's E
    /// where the block has no F), refused where the tool would never move:
    /// F0, or S0 without constant surface speed (the control's threading
    /// waits for the spindle's one-revolution signal).
    pub(super) fn thread_lead(&mut self, w: &Words, span: Span) -> Result<f64, Diagnostic> {
        if let (Some(e), false, crate::Dialect::HaasLathe) = (w.get(b'E'), w.has(b'F'), self.settings.dialect) {
            if e > 0.0 {
                return Ok(self.mm(e));
            }
        }
        let lead = self.mm(self.feed_word);
        if !self.feed_set || lead.is_nan() || lead <= 0.0 {
            let at = if w.has(b'F') { w.span(b'F') } else { span };
            return Err(Diagnostic::error(
                at,
                format!(
                    "threading with lead F{}: the lead is how far the tool goes each revolution, and at 0 it never \
                     moves; give F, the thread's lead, greater than 0",
                    if self.feed_set { self.feed_word } else { 0.0 }
                ),
            ));
        }
        let css = self.turning.as_ref().is_some_and(|t| t.surface.is_some());
        if !css && (self.speed.is_nan() || self.speed <= 0.0) {
            // The S word that set the speed, where one did.
            let at = self.speed_span.unwrap_or(span);
            return Err(Diagnostic::error(
                at,
                format!(
                    "threading with spindle speed S{}: the feed follows the spindle, so at 0 rpm the tool never moves \
                     (the control waits for the spindle's revolution signal); give S greater than 0",
                    self.speed
                ),
            ));
        }
        Ok(lead)
    }
}
