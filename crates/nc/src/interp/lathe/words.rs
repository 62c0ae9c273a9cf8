//! A Fanuc or Haas lathe's addresses: X a diameter, and in G code system A
//! U W H the incremental X Z C beside the absolute X Z C (FANUC Series
//! 0i-TF Plus Operator's Manual (B-64604EN), lathe system, "Absolute and
//! incremental programming" and "Diameter and radius programming").
//!
//! Every block's words are read here before the mill's machinery sees
//! them: X becomes the tool's radius, U (W, H) the absolute X (Z, C) it
//! reaches. A block whose code reads its own words (a cycle, the dwell:
//! [`GCode::takes_cycle_words`]) is left as written; its reader calls
//! [`State::lathe_axes`] on the words that are its end point.

use kezuri_geom::AxisSet;

use super::super::modal::{ContourCycle, GCode, Units};
use super::super::words::Words;
use super::super::State;
use super::{GCodeSystem, LatheMotion, XMode};
use crate::ast::{Word, WordValue};
use crate::source::{Diagnostic, Span};

/// What a lathe block's G codes make of its other words, decoded once a
/// block ([`State::lathe_codes`]) before its words are read: which of P, Q,
/// R, A and K are a cycle's counts or sequence numbers, not lengths.
#[derive(Clone, Copy, Debug, Default)]
pub(in super::super) struct LatheCodes {
    /// The first contour cycle (G70–G73) the block names.
    pub contour: Option<ContourCycle>,
    /// The first of the grooving cycles (G74, G75) and multiple threading
    /// (G76) the block names.
    pub cycle: Option<GCode>,
    /// The lathe motion the block's group 1 codes leave in force, where it
    /// names any (`Some(None)`: a motion that is no lathe cycle).
    pub motion: Option<Option<LatheMotion>>,
}

/// The absolute address, its incremental one (system A) and the axis.
const PAIRS: [(u8, u8, usize); 3] = [(b'X', b'U', 0), (b'Z', b'W', 2), (b'C', b'H', 5)];

impl State {
    /// The block's G codes as [`LatheCodes`] reads them: each G word written
    /// as a number, decoded in the lathe's G code system (none off a lathe).
    pub(in super::super) fn lathe_codes(&self, words: &[Word]) -> LatheCodes {
        let mut codes = LatheCodes::default();
        if self.turning.is_none() {
            return codes;
        }
        for w in words.iter().filter(|w| w.letter == b'G') {
            let WordValue::Number { value, .. } = w.value() else { continue };
            match self.decode_g((value * 10.0).round() as u32) {
                Some(GCode::Contour(c)) => {
                    codes.contour.get_or_insert(c);
                }
                Some(c @ (GCode::Grooving(_) | GCode::MultipleThreading)) => {
                    codes.cycle.get_or_insert(c);
                }
                Some(GCode::SingleCycle(c)) => codes.motion = Some(Some(LatheMotion::Single(c))),
                Some(c) if c.group() == 1 => codes.motion = Some(None),
                _ => {}
            }
        }
        codes
    }

    /// Reads the lathe's words of a block (after its modal codes, before
    /// its feed, speed and motion): the spindle clamp of `G50 S` (`G92 S`
    /// in systems B and C), then X U Z W C H as [`State::lathe_axes`] reads
    /// them, unless the block's code reads its own words. A `G50 S` with no
    /// axis word sets nothing else: its code is taken out of `codes`.
    pub(in super::super) fn lathe_block(
        &mut self,
        w: &mut Words,
        codes: &mut [Option<(GCode, Span)>],
        next: Option<&[Word]>,
    ) -> Result<(), Diagnostic> {
        let Some(turning) = &self.turning else { return Ok(()) };
        let in_force = turning.motion;
        // A macro call's words are its arguments, as written.
        let every_block = self.modal.modal_call == Some(super::super::ModalCallKind::EveryBlock)
            && self.modal_call.is_some()
            && self.modal_depth == 0;
        if every_block || codes.iter().flatten().any(|(c, _)| matches!(c, GCode::MacroCall | GCode::ModalCall(_))) {
            self.set_own_words(true);
            return Ok(());
        }
        if let Some(k) = codes.iter().position(|c| matches!(c, Some((GCode::LatheSetPosition, _)))) {
            if let Some(s) = w.get(b'S') {
                self.set_clamp(s, w.span(b'S'))?;
                *w = w.without(b'S');
            }
            if !w.any_axis() && !w.has(b'U') && !w.has(b'W') && !w.has(b'H') {
                codes[k] = None;
            }
        }
        let own = |c: &GCode| c.takes_cycle_words() || *c == GCode::SetOffsets;
        let named = codes.iter().flatten().map(|(c, _)| *c);
        let mut named_own = false;
        let mut named_motion = false;
        for c in named {
            named_own |= own(&c);
            named_motion |= c.group() == 1;
        }
        let cycle_in_force = !named_motion && matches!(in_force, Some(LatheMotion::Single(_)));
        if named_own || cycle_in_force {
            self.set_own_words(true);
            return Ok(());
        }
        self.set_own_words(false);
        let increments = self.lathe_axes(w)?;
        if let Some(t) = &mut self.turning {
            t.increments = increments;
        }
        self.corner_words(w, codes, next)
    }

    /// Reads the end point words of a lathe block into the words the mill's
    /// machinery reads: X halved where X is a diameter (so that X is the
    /// tool's radius, in program units, absolute or under G91 incremental);
    /// in system A, U W H (incremental X Z C; U halved where X is a
    /// diameter) become the absolute X Z C they reach, from the program
    /// position. Returns the axes given as increments. X and U (Z and W, C
    /// and H) in one block: a located error. Cycle readers call this on
    /// their end point's words (`G90 X(U) Z(W)`, the second block of `G74`
    /// `G75` `G76`).
    pub(in super::super) fn lathe_axes(&mut self, w: &mut Words) -> Result<AxisSet, Diagnostic> {
        let Some(turning) = &self.turning else { return Ok(AxisSet::NONE) };
        let diameter = turning.x == XMode::Diameter;
        let system_a = turning.fanuc && turning.system == GCodeSystem::A;
        if diameter {
            if let Some(x) = w.get(b'X') {
                w.put(b'X', x / 2.0, b'X');
            }
        }
        if !system_a {
            return Ok(AxisSet::NONE);
        }
        let mut increments = AxisSet::NONE;
        let position = self.program_position().to_array();
        for (absolute, incremental, axis) in PAIRS {
            let Some(step) = w.get(incremental) else { continue };
            if w.has(absolute) {
                return Err(Diagnostic::error(
                    w.span(incremental),
                    format!(
                        "{} and {} in one block: in G code system A {} is the absolute {} and {} the incremental {} \
                         of the same axis; the control stops with an alarm. Give one of them",
                        absolute as char,
                        incremental as char,
                        absolute as char,
                        absolute as char,
                        incremental as char,
                        absolute as char
                    ),
                ));
            }
            let step = if axis == 0 && diameter { step / 2.0 } else { step };
            // The program position is mm (degrees for C): back to the
            // program's units, where the reading goes on.
            let here = if axis < 3 && self.modal.units == Units::Inch { position[axis] / 25.4 } else { position[axis] };
            w.put(absolute, here + step, incremental);
            increments = increments.with(axis);
        }
        Ok(increments)
    }

    /// This block's words are its code's own (a cycle, the dwell, a macro
    /// call): U W are no axes in it, and none of them is an increment.
    fn set_own_words(&mut self, own: bool) {
        if let Some(t) = &mut self.turning {
            t.own_words = own;
            t.increments = AxisSet::NONE;
        }
    }

    /// Whether the block in progress reads its own words (U W are no axes
    /// in it): see [`GCode::takes_cycle_words`].
    pub(in super::super) fn lathe_own_words(&self) -> bool {
        self.turning.as_ref().is_some_and(|t| t.own_words)
    }

    /// The axes the block in progress gave as increments (U W H in system
    /// A): moves on them keep to increments for the writer, and an axis at
    /// a position the program never named stays unnamed.
    pub(in super::super) fn lathe_increments(&self) -> AxisSet {
        self.turning.as_ref().map_or(AxisSet::NONE, |t| t.increments)
    }
}
