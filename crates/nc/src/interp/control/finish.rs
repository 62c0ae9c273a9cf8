//! The end of a run, and the pieces of its path handed on before it.

use kezuri_geom::Toolpath;

use super::Interp;
use crate::interp::Outcome;
use crate::source::{Diagnostic, Span};

impl Interp<'_> {
    /// Hands the moves made so far but the last to the sink, where the
    /// path may be cut here (see [`PathSink`]).
    pub(super) fn hand_on(&mut self) {
        let Some(sink) = self.sink.as_deref_mut() else { return };
        if !self.st.radius.unused() {
            // A stretch compensated and done with: handed on with its
            // programmed contour.
            if let Some((piece, programmed)) = self.st.comp_flush() {
                sink.take_owned(piece, Some(&programmed));
            }
        }
        if !self.st.may_hand_on() {
            return;
        }
        // The last move stays: a block may still lengthen it or place its end.
        let at = self.st.toolpath.cut_at_or_before(self.st.toolpath.moves.len() - 1);
        if at > 0 {
            let piece = self.st.toolpath.split_before(at);
            // The moves to come get the room the piece had, at once.
            self.st.toolpath.moves.reserve(piece.moves.capacity());
            sink.take_owned(piece, None);
        }
    }

    pub(in crate::interp) fn finish(mut self) -> Outcome {
        let compensated = self.st.comp_finish();
        let programmed = compensated.map(|c| {
            if let Some(alarm) = c.alarm {
                self.st.diagnostics.push(alarm);
                self.completed = false;
            }
            c.programmed
        });
        let shown = self.st.diagnostics.iter().filter(|d| !d.is_error()).count() as u64;
        let mut summary: Vec<_> =
            self.st.warned.iter().filter(|(_, &n)| n > crate::interp::WARNINGS_PER_KIND).collect();
        let warnings =
            shown + summary.iter().map(|(_, &n)| u64::from(n - crate::interp::WARNINGS_PER_KIND)).sum::<u64>();
        summary.sort();
        for (kind, n) in summary {
            let span = self.st.diagnostics.iter().rev().find(|d| !d.is_error()).map_or(Span::default(), |d| d.span);
            let more = n - crate::interp::WARNINGS_PER_KIND;
            self.st
                .diagnostics
                .push(Diagnostic::warning(span, format!("… and {more} more warnings like these ({kind})")));
        }
        let (toolpath, programmed) = match self.sink {
            Some(sink) => {
                sink.take(&self.st.toolpath, programmed.as_ref());
                (Toolpath::default(), None)
            }
            None => (self.st.toolpath, programmed),
        };
        Outcome {
            toolpath,
            programmed,
            diagnostics: self.st.diagnostics,
            prints: self.st.prints,
            logs: self.st.logs,
            blocks: self.st.blocks,
            statements: self.statements,
            completed: self.completed,
            holes: self.st.holes,
            inch: self.st.modal.units == crate::interp::Units::Inch,
            model_reads: self.st.model_reads,
            warnings,
            threads: self.st.threads,
            tool_offsets: self.st.tool_offsets,
        }
    }
}
