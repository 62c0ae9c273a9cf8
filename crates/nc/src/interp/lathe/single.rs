//! The single cycles of a Fanuc lathe: outer/inner diameter cutting (`G90`
//! in G code system A, `G77` in B, `G20` in C), threading (`G92`, `G78`,
//! `G21`) and end face cutting (`G94`, `G79`, `G24`), straight or with the
//! taper `R` (FANUC Series 0i-TF Plus Operator's Manual (B-64604EN), lathe
//! system, "Canned cycle (G90, G92, G94)"). Haas writes the
//! taper as `I` (G90, G92) and `K` (G94) (Haas Lathe Operator's Manual,
//! G-codes chapter).
//!
//! Each cycle is four moves from its start point A back to A. Positions are
//! the tool's: X a radius. X U Z W and the taper are modal while the cycle
//! is: a block with only some of them repeats the cycle with the others
//! as they were (the manual's "Usage of canned cycles").

use kezuri_geom::{Axes, AxisSet, MoveKind};

use super::super::modal::SingleCycle;
use super::super::words::Words;
use super::super::State;
use super::speed::thread_stretch;
use super::Thread;
use crate::source::{Diagnostic, Span};

/// What a move of a turning cycle is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum StepKind {
    /// At rapid rate.
    Rapid,
    /// At the cutting feed.
    Feed,
    /// Threading: the feed synchronised with the spindle, one lead a turn.
    Thread,
}

/// One move of a turning cycle, to (`x`, `z`): X the radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Step {
    pub(crate) kind: StepKind,
    pub(crate) x: f64,
    pub(crate) z: f64,
}

impl Step {
    pub(crate) fn rapid(x: f64, z: f64) -> Step {
        Step { kind: StepKind::Rapid, x, z }
    }
    pub(crate) fn feed(x: f64, z: f64) -> Step {
        Step { kind: StepKind::Feed, x, z }
    }
    pub(crate) fn thread(x: f64, z: f64) -> Step {
        Step { kind: StepKind::Thread, x, z }
    }
}

/// A cycle's geometry that the program cannot have meant: the word to
/// blame (its letter) and what is wrong.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Refusal {
    pub(crate) letter: Option<u8>,
    pub(crate) message: String,
}

impl Refusal {
    pub(crate) fn at(letter: u8, message: impl Into<String>) -> Refusal {
        Refusal { letter: Some(letter), message: message.into() }
    }
}

/// The moves of one single cycle from the start point (`x0`, `z0`) to the
/// end point (`x`, `z`) (radius, mm) with the taper `taper` (the manual's
/// R: the radius, for G94 the Z, where the cut starts less that of the end
/// point; 0 for a straight cut).
///
/// - Cutting (G90): rapid in X to `x + taper`, feed to (`x`, `z`), feed out
///   in X to `x0`, rapid back in Z to `z0`.
/// - Threading (G92): the same, the cut threaded and the way out in X at
///   rapid rate.
/// - Facing (G94): rapid in Z to `z + taper`, feed to (`x`, `z`), feed out
///   in Z to `z0`, rapid back in X to `x0`.
///
/// The taper's sign follows the manual's four figures: where R and U/2
/// (W for G94) have opposite signs, |R| ≤ |U/2| (|W|), or the cut would
/// begin beyond the start point.
pub(crate) fn single_pass(
    cycle: SingleCycle,
    (x0, z0): (f64, f64),
    (x, z): (f64, f64),
    taper: f64,
    taper_letter: u8,
) -> Result<[Step; 4], Refusal> {
    if !taper.is_finite() {
        return Err(Refusal::at(taper_letter, "the taper is not a number"));
    }
    // The move the taper is measured along: X for G90/G92, Z for G94.
    let along = if cycle == SingleCycle::Facing { z - z0 } else { x - x0 };
    if taper * along < 0.0 && taper.abs() > along.abs() + 1e-9 {
        let (letter, half) = if cycle == SingleCycle::Facing { ('W', "W") } else { ('U', "U/2") };
        let t = taper_letter as char;
        let (taper, along) = (crate::number::number(taper, 4), crate::number::number(along, 4));
        return Err(Refusal::at(
            taper_letter,
            format!(
                "the taper {t}{taper} is larger than the cycle's depth ({half} = {along}) with the opposite sign: \
                 the cut would begin beyond the start point (the manual allows |{t}| ≤ |{half}| there; {letter} \
                 is the end point less the start point)"
            ),
        ));
    }
    Ok(match cycle {
        SingleCycle::Cutting => [Step::rapid(x + taper, z0), Step::feed(x, z), Step::feed(x0, z), Step::rapid(x0, z0)],
        SingleCycle::Threading => {
            [Step::rapid(x + taper, z0), Step::thread(x, z), Step::rapid(x0, z), Step::rapid(x0, z0)]
        }
        SingleCycle::Facing => [Step::rapid(x0, z + taper), Step::feed(x, z), Step::feed(x, z0), Step::rapid(x0, z0)],
    })
}

/// What the lathe's cycles remember from block to block: the single cycle
/// in force's modal words, and what the first blocks of `G74`/`G75` and
/// `G76` set (on the control, parameters 5139 to 5143).
#[derive(Clone, Debug, Default)]
pub(in super::super) struct CycleMemory {
    /// The single cycle's end point (machine coordinates) and taper, and
    /// the count of moves after its last block: a move since ends it.
    single: Option<(SingleCycle, Axes, f64, usize)>,
    /// G74/G75's return after each peck, mm (`G74 R(e);`).
    pub(super) groove_return: Option<f64>,
    /// G76's first block.
    pub(super) thread: Option<super::threading::ThreadSettings>,
}

impl State {
    /// A block in single cycle mode: the cycle from where the tool is to
    /// the block's X(U) Z(W), the taper R (Haas: I, for G94 K); an axis or
    /// taper the block leaves out is the last block's. Returns whether the
    /// tool moved. A block with no axis word repeats nothing.
    pub(in super::super) fn single_cycle(
        &mut self,
        cycle: SingleCycle,
        w: &Words,
        span: Span,
        line: u32,
    ) -> Result<bool, Diagnostic> {
        if !w.any_axis() && !w.has(b'U') && !w.has(b'W') {
            return Ok(false);
        }
        let haas = self.settings.dialect == crate::Dialect::HaasLathe;
        let taper_letter = match (haas, cycle) {
            (false, _) => b'R',
            (true, SingleCycle::Facing) => b'K',
            (true, _) => b'I',
        };
        let mut e = w.without(taper_letter);
        self.lathe_axes(&mut e)?;
        let mut end = self.target(&e);
        let moves = self.toolpath.moves.len();
        let last = self.cycles.single.filter(|&(c, _, _, after)| c == cycle && after == moves);
        let mut taper = 0.0;
        if let Some((_, at, r, _)) = last {
            if !e.has(b'X') {
                end.x = at.x;
            }
            if !e.has(b'Z') {
                end.z = at.z;
            }
            taper = r;
        }
        if let Some(r) = w.get(taper_letter) {
            taper = self.mm(r);
        }
        let (feed, lead) = match cycle {
            SingleCycle::Threading => (0.0, self.thread_lead(w, span)?),
            _ => (self.feed_mm_min(span)?, 0.0),
        };
        let steps = single_pass(cycle, (self.tip.x, self.tip.z), (end.x, end.z), taper, taper_letter)
            .map_err(|r| self.refused(r, w, span))?;
        self.run_steps(&steps, feed, lead, line);
        self.cycles.single = Some((cycle, end, taper, self.toolpath.moves.len()));
        Ok(true)
    }

    /// The G number of the multiple repetitive cycle that is `number` in G
    /// code system A: two more in system C (G74 is G76 there).
    pub(super) fn lathe_cycle_number(&self, number: u32) -> u32 {
        match self.turning.as_ref().map(|t| t.system) {
            Some(super::GCodeSystem::C) => number + 2,
            _ => number,
        }
    }

    /// A cycle's refusal, located at its word where the block has it.
    pub(super) fn refused(&self, r: Refusal, w: &Words, span: Span) -> Diagnostic {
        let at = match r.letter {
            Some(l) if w.has(l) => w.span(l),
            _ => span,
        };
        Diagnostic::error(at, r.message)
    }

    /// The moves of a cycle, X a radius, in machine coordinates: feeds at
    /// `feed` (mm/min), threading at `lead` a turn. The first threading
    /// move is the thread this call cuts (a chamfer's pull-out belongs to
    /// it). Moves of no length are left out.
    pub(super) fn run_steps(&mut self, steps: &[Step], feed: f64, lead: f64, line: u32) {
        let mut threaded = false;
        for s in steps {
            let end = Axes { x: s.x, z: s.z, ..self.tip };
            if end == self.tip {
                continue;
            }
            let mut named = AxisSet::NONE;
            if end.x != self.tip.x {
                named = named.with(0);
            }
            if end.z != self.tip.z {
                named = named.with(2);
            }
            match s.kind {
                StepKind::Rapid => self.push_move(MoveKind::Rapid, end, 0.0, named, line),
                StepKind::Feed => self.push_move(MoveKind::Feed, end, feed, named, line),
                StepKind::Thread => {
                    let start = self.tip;
                    self.push_move(MoveKind::Feed, end, 0.0, named, line);
                    let speed = self.speed;
                    if let Some(m) = self.toolpath.moves.last_mut() {
                        m.feed = lead * speed * thread_stretch(m);
                    }
                    if !threaded {
                        self.threads.push(Thread { lead, start, end, line });
                        threaded = true;
                    }
                }
            }
        }
    }

    /// A word of a multiple repetitive cycle given in least increments
    /// without a decimal point (`Q500`: 0.5 mm; 0.0001 inch under G20), in
    /// mm. One with a decimal point is read as written, with a warning:
    /// the control reads these words as counts.
    pub(super) fn count_word(&mut self, w: &Words, letter: u8, cycle: &str) -> Option<f64> {
        let v = w.get(letter)?;
        if w.decimal(letter) {
            self.warn(
                "cycle-decimal",
                w.span(letter),
                format!(
                    "{} of {cycle} is given in least increments without a decimal point ({}500 is 0.5 mm); \
                     {}{} is read as {} mm, but the control may refuse it or read it otherwise",
                    letter as char,
                    letter as char,
                    letter as char,
                    crate::number::number(v, 6),
                    crate::number::number(self.mm(v), 6)
                ),
            );
            return Some(self.mm(v));
        }
        let counts = if self.modal.units == super::super::modal::Units::Inch { 10_000.0 } else { 1000.0 };
        Some(self.mm(v / counts))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straight_turning_is_four_moves_back_to_the_start() {
        // From (30, 2) to X radius 20, Z -40: in, along, out, back.
        let s = single_pass(SingleCycle::Cutting, (30.0, 2.0), (20.0, -40.0), 0.0, b'R').unwrap();
        assert_eq!(
            s,
            [Step::rapid(20.0, 2.0), Step::feed(20.0, -40.0), Step::feed(30.0, -40.0), Step::rapid(30.0, 2.0)]
        );
    }

    #[test]
    fn taper_starts_the_cut_r_from_the_end_radius() {
        // OD taper toward the chuck: U < 0, W < 0, R < 0 (the manual's
        // first figure): the cut starts at radius 20 - 3 = 17.
        let s = single_pass(SingleCycle::Cutting, (30.0, 2.0), (20.0, -40.0), -3.0, b'R').unwrap();
        assert_eq!(s[0], Step::rapid(17.0, 2.0));
        assert_eq!(s[1], Step::feed(20.0, -40.0));
        // The third figure: U < 0, R > 0, |R| <= |U/2|.
        assert!(single_pass(SingleCycle::Cutting, (30.0, 2.0), (20.0, -40.0), 10.0, b'R').is_ok());
        let e = single_pass(SingleCycle::Cutting, (30.0, 2.0), (20.0, -40.0), 10.5, b'R').unwrap_err();
        assert_eq!(e.letter, Some(b'R'));
    }

    #[test]
    fn facing_tapers_in_z() {
        let s = single_pass(SingleCycle::Facing, (30.0, 2.0), (5.0, -3.0), -1.5, b'R').unwrap();
        assert_eq!(s, [Step::rapid(30.0, -4.5), Step::feed(5.0, -3.0), Step::feed(5.0, 2.0), Step::rapid(30.0, 2.0)]);
    }

    #[test]
    fn threading_leaves_at_rapid() {
        let s = single_pass(SingleCycle::Threading, (15.0, 5.0), (9.0, -30.0), 0.0, b'R').unwrap();
        assert_eq!(s[1].kind, StepKind::Thread);
        assert_eq!(s[2], Step::rapid(15.0, -30.0));
    }
}
