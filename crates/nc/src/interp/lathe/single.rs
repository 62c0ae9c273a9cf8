//! The single cycles: G90 G92 G94 (system A), G77 G78 G79 (B), G20 G21 G24
//! (C). FANUC Series 0i-TF Plus Operator's Manual (B-64604EN), lathe
//! system, "Single repetitive cycle".

use super::super::modal::SingleCycle;
use super::super::words::Words;
use super::super::State;
use crate::source::{Diagnostic, Span};

impl State {
    /// A block in single cycle mode: the cycle's moves from the block's
    /// words (read as written: [`super::super::modal::GCode::takes_cycle_words`];
    /// the end point by [`State::lathe_axes`]). Returns whether the tool
    /// moved. A block with no axis word repeats nothing.
    pub(in super::super) fn single_cycle(
        &mut self,
        cycle: SingleCycle,
        w: &Words,
        span: Span,
        line: u32,
    ) -> Result<bool, Diagnostic> {
        let _ = line;
        if !w.any_axis() && !w.has(b'U') && !w.has(b'W') {
            return Ok(false);
        }
        let system = self.turning.as_ref().map(|t| t.system).unwrap_or_default();
        Err(Diagnostic::error(
            span,
            format!("G{:02} ({cycle:?} single cycle) is not yet read by kezuri", cycle.number(system)),
        ))
    }
}
