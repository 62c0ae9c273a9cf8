//! What an error says besides itself: how a word without a decimal point
//! was read, where that may be behind it, and the reach of a move no
//! machine has.

use kezuri_geom::{Axes, Move};

use super::modal::Units;
use super::words::{Words, AXIS_LETTERS};
use super::{IntegerInput, State};
use crate::ast::{Program, WordValue};
use crate::source::{Diagnostic, Span};

/// Farthest a linear axis may go from machine zero, mm: 1 km, the largest
/// coordinate kezuri takes anywhere (`kezuri_geom::limits`), beyond the
/// travel of any machine; a position past it is a misread number (inches
/// read as mm, whole units as increments), and no page or program holds it.
const REACH_MM: f64 = kezuri_geom::limits::LONGEST_MM;

/// Farthest a rotary axis may turn from zero, degrees (what a program can hold).
const REACH_DEG: f64 = 1e9;

impl State {
    /// `d` with a note of the axis word without a decimal point that may be
    /// behind it, where words without one are read as least increments: the
    /// block's own, else (for a block that names an axis) the program's
    /// first. `Z10 was read as 0.010 mm (Fanuc increments); with
    /// --no-decimal units it is 10 mm`.
    pub(super) fn with_decimal_hint(&self, program: &Program, pc: u32, mut d: Diagnostic) -> Diagnostic {
        if self.settings.integer_input != IntegerInput::Increments || d.message.contains("--no-decimal") {
            return d;
        }
        let block = &program.blocks[pc as usize];
        let words = program.words(block);
        let own = words.iter().find_map(|w| match w.value() {
            WordValue::Number { value, decimal: false }
                if value != 0.0 && AXIS_LETTERS.contains(&w.letter) && w.letter != b'Q' =>
            {
                Some((w.span(block.span.file), w.letter, value))
            }
            _ => None,
        });
        let names_axis = words.iter().any(|w| b"XYZABCIJKR".contains(&w.letter));
        let Some((span, letter, value)) = own.or(if names_axis { self.first_integer } else { None }) else {
            return d;
        };
        let (counts, unit) = if b"ABC".contains(&letter) {
            (1000.0, "deg")
        } else if self.modal.units == Units::Mm {
            (1000.0, "mm")
        } else {
            (10_000.0, "inch")
        };
        let digits = if counts == 1000.0 { 3 } else { 4 };
        let at = if own.is_some() || span.file != block.span.file {
            String::new()
        } else {
            let mut before = (0..pc as usize).rev().filter_map(|i| program.blocks.get(i));
            let line = before.find(|b| b.span.file == span.file && b.span.start <= span.start);
            line.map_or(String::new(), |b| format!("line {}: ", b.line))
        };
        d.message += &format!(
            "; {at}{l}{value} was read as {:.digits$} {unit} (Fanuc increments); with --no-decimal units it is {value} {unit}",
            value / counts,
            l = letter as char,
        );
        d
    }

    /// An error where a move of this block (from move `first` on) goes
    /// farther than any machine reaches, at the axis word that sent it.
    #[inline(always)]
    pub(super) fn within_reach(&self, first: usize, w: &Words, span: Span) -> Result<(), Diagnostic> {
        let moves = &self.toolpath.moves[first.min(self.toolpath.moves.len())..];
        // One branch a move (NaN fails it too).
        let near = |e: &Axes| {
            let linear = (e.x.abs() <= REACH_MM) & (e.y.abs() <= REACH_MM) & (e.z.abs() <= REACH_MM);
            let parallel = (e.u.abs() <= REACH_MM) & (e.v.abs() <= REACH_MM) & (e.w.abs() <= REACH_MM);
            linear & parallel & (e.a.abs() <= REACH_DEG) & (e.b.abs() <= REACH_DEG) & (e.c.abs() <= REACH_DEG)
        };
        for m in moves {
            if !near(&m.end) {
                return Err(beyond_reach(moves, w, span));
            }
        }
        Ok(())
    }
}

/// The error of [`State::within_reach`]: the first axis of `moves` beyond
/// any machine's reach.
#[cold]
#[inline(never)]
fn beyond_reach(moves: &[Move], w: &Words, span: Span) -> Diagnostic {
    for m in moves {
        for (k, &v) in m.end.to_array().iter().enumerate() {
            let reach = if Axes::is_linear(k) { REACH_MM } else { REACH_DEG };
            if v.abs() <= reach {
                continue;
            }
            let letter = Axes::LETTERS[k];
            let at = if w.has(letter) { w.span(letter) } else { span };
            let (unit, limit) = if Axes::is_linear(k) { ("mm", "1 km") } else { ("deg", "10^9 deg") };
            return Diagnostic::error(
                at,
                format!(
                    "this move takes {} to {v:.3} {unit} from machine zero, beyond any machine's reach ({limit}): \
                     is a number misread?",
                    letter as char
                ),
            );
        }
    }
    Diagnostic::error(span, "this move goes beyond any machine's reach")
}
