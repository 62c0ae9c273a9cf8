//! The grooving cycles of a lathe: `G74` end face peck drilling / face
//! grooving (pecks in Z, grooves side by side in X) and `G75` outer/inner
//! diameter grooving (pecks in X, grooves side by side in Z); `G76` and
//! `G77` in G code system C. Fanuc's two-block form (FANUC Series 0i-TF
//! Plus Operator's Manual (B-64604EN), lathe system, "Multiple repetitive
//! cycle": "End face peck drilling cycle (G74)", "Outer diameter / internal
//! diameter drilling cycle (G75)"):
//!
//! ```text
//! G74 R(e);
//! G74 X(U) Z(W) P(Δi) Q(Δk) R(Δd) F(f);
//! ```
//!
//! e the return after each peck (modal; parameter 5139), Δi the shift
//! between grooves in X and Δk the peck in Z (radius, in least increments
//! without a decimal point), Δd the relief at the bottom. `G75` swaps the
//! roles of X and Z. Haas's one-block form (Haas Lathe Operator's Manual,
//! G-codes: "G74 End Face Grooving Cycle", "G75 O.D./I.D. Grooving Cycle")
//! gives `I` the X step, `K` the Z step and `D` the clearance.

use super::super::modal::{g_name, GCode, SingleCycle};
use super::super::words::Words;
use super::super::State;
use super::single::{Refusal, Step};
use super::words::LatheCodes;
use super::LatheMotion;
use crate::source::{Diagnostic, Span};

/// Haas's return after each peck: Setting 22 (Can Cycle Delta Z), which
/// kezuri does not read from the machine; taken at 0.050 inch.
const HAAS_PECK_RETURN: f64 = 1.27;

/// Most moves one grooving block makes.
const MOST_STEPS: usize = 1_000_000;

/// A grooving cycle's figures, mm (X a radius).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Grooving {
    /// `true`: G74 (pecks in Z, across in X); `false`: G75 (pecks in X).
    pub(crate) face: bool,
    /// Where the tool is: the cycle's start point A (x, z).
    pub(crate) start: (f64, f64),
    /// The far corner: X of the last groove (G74) or its depth (G75), Z
    /// of the bottom (G74) or of the last groove (G75).
    pub(crate) end: (f64, f64),
    /// Each peck's depth (G74's Δk, G75's Δi), > 0 where the cycle pecks.
    pub(crate) peck: f64,
    /// The step from groove to groove (G74's Δi, G75's Δk).
    pub(crate) step: f64,
    /// The return after each peck (e).
    pub(crate) retract: f64,
    /// The relief at the bottom of each groove (Δd), toward the grooves
    /// already cut; where there is one groove only, in the direction of
    /// its sign.
    pub(crate) relief: f64,
}

/// (peck axis, step axis) of a point (x, z).
fn split(face: bool, (x, z): (f64, f64)) -> (f64, f64) {
    if face {
        (z, x)
    } else {
        (x, z)
    }
}

fn step_at(face: bool, rapid: bool, p: f64, q: f64) -> Step {
    let (x, z) = if face { (q, p) } else { (p, q) };
    if rapid {
        Step::rapid(x, z)
    } else {
        Step::feed(x, z)
    }
}

fn sign(v: f64) -> f64 {
    if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// The moves of a grooving cycle: at each groove, pecks of `peck` toward
/// the end (each but the last followed by a rapid return of `retract`),
/// the relief at the bottom, a rapid back to the start level; the next
/// groove `step` further; at the end a rapid back to the start point.
/// `peck_letter` and `step_letter` name the words that gave them.
pub(crate) fn grooving(g: &Grooving, peck_letter: u8, step_letter: u8) -> Result<Vec<Step>, Refusal> {
    let (p0, q0) = split(g.face, g.start);
    let (pe, qe) = split(g.face, g.end);
    let (sp, sq) = (sign(pe - p0), sign(qe - q0));
    let (peck_axis, step_axis) = if g.face { ("Z", "X") } else { ("X", "Z") };
    let figures = [g.start.0, g.start.1, g.end.0, g.end.1, g.peck, g.step, g.retract, g.relief];
    if figures.iter().any(|v| !v.is_finite()) {
        return Err(Refusal { letter: None, message: "a figure of the cycle is not a number".into() });
    }
    let never = "the cycle would never reach the end; give it greater than 0";
    if sp != 0.0 && g.peck <= 0.0 {
        let p = crate::number::number(g.peck, 6);
        return Err(Refusal::at(peck_letter, format!("the depth of each peck in {peck_axis} is {p} mm: {never}")));
    }
    if sq != 0.0 && g.step <= 0.0 {
        let s = crate::number::number(g.step, 6);
        return Err(Refusal::at(step_letter, format!("the step between grooves in {step_axis} is {s} mm: {never}")));
    }
    if g.retract < 0.0 {
        return Err(Refusal::at(b'R', "the return after each peck must not be negative"));
    }
    let pecks = if sp == 0.0 { 1.0 } else { ((pe - p0).abs() / g.peck).ceil() };
    let grooves = if sq == 0.0 { 1.0 } else { ((qe - q0).abs() / g.step).ceil() + 1.0 };
    if pecks * grooves * 2.0 + grooves * 3.0 > MOST_STEPS as f64 {
        let letter = if pecks >= grooves { peck_letter } else { step_letter };
        return Err(Refusal::at(
            letter,
            format!("{pecks} pecks in each of {grooves} grooves is more than kezuri runs ({MOST_STEPS} moves): check the word's least increments"),
        ));
    }
    // Toward the grooves cut before; a lone groove's relief by its sign.
    let relief = if sq == 0.0 { g.relief } else { -sq * g.relief.abs() };
    let mut steps = Vec::new();
    let mut q = q0;
    loop {
        // The first groove is at the start point; the next ones are reached
        // at the start level.
        if q != q0 {
            steps.push(step_at(g.face, true, p0, q));
        }
        let mut p = p0;
        if sp != 0.0 {
            loop {
                let mut next = p + sp * g.peck;
                if sp * (next - pe) >= -1e-9 {
                    next = pe;
                }
                steps.push(step_at(g.face, false, next, q));
                if next == pe {
                    break;
                }
                if g.retract > 0.0 {
                    steps.push(step_at(g.face, true, next - sp * g.retract, q));
                }
                p = next;
            }
        }
        if relief != 0.0 {
            steps.push(step_at(g.face, true, pe, q + relief));
        }
        steps.push(step_at(g.face, true, p0, q + relief));
        if sq == 0.0 || q == qe {
            break;
        }
        q += sq * g.step;
        if sq * (q - qe) >= -1e-9 {
            q = qe;
        }
    }
    if q + relief != q0 {
        steps.push(step_at(g.face, true, p0, q0));
    }
    Ok(steps)
}

impl State {
    /// `G74` (`face`) or `G75` (G76, G77 in system C): the first block
    /// `G74 R(e);` sets the return after each peck; the second, with the
    /// end point, cuts (Haas: the one block `G74 X(U) Z(W) I K D F`).
    /// Returns whether the tool moved.
    pub(in super::super) fn grooving_block(
        &mut self,
        face: bool,
        w: &Words,
        gspan: Span,
        line: u32,
    ) -> Result<bool, Diagnostic> {
        let name = g_name(self.lathe_cycle_number(if face { 74 } else { 75 }) * 10);
        let haas = self.settings.dialect == crate::Dialect::HaasLathe;
        let axes = w.has(b'X') || w.has(b'Z') || w.has(b'U') || w.has(b'W');
        if !axes && !haas {
            let Some(e) = w.get(b'R') else {
                return Err(Diagnostic::error(
                    gspan,
                    format!(
                        "{name} needs R(e), the return after each peck (its first block, {name} R(e);), or the end \
                         point X(U) Z(W) with P Q R F (its second block)"
                    ),
                ));
            };
            if e < 0.0 {
                return Err(Diagnostic::error(
                    w.span(b'R'),
                    format!("{name} R{e}: the return after each peck must not be negative"),
                ));
            }
            self.cycles.groove_return = Some(self.mm(e));
            return Ok(false);
        }
        if !axes {
            return Err(Diagnostic::error(gspan, format!("{name} needs its end point: X(U) and/or Z(W)")));
        }
        let mut e = *w;
        for l in *b"PQRIKDA" {
            e = e.without(l);
        }
        self.lathe_axes(&mut e)?;
        let end = self.target(&e);
        let start = (self.tip.x, self.tip.z);
        // The peck's axis and the step's: Z and X for G74, X and Z for G75.
        let (peck_moves, step_moves) =
            if face { (end.z != self.tip.z, end.x != self.tip.x) } else { (end.x != self.tip.x, end.z != self.tip.z) };
        let (peck_letter, step_letter, retract, relief) = if haas {
            let (p, s) = if face { (b'K', b'I') } else { (b'I', b'K') };
            let d = w.get(b'D').map_or(0.0, |d| self.mm(d));
            (p, s, HAAS_PECK_RETURN, d)
        } else {
            let (p, s) = if face { (b'Q', b'P') } else { (b'P', b'Q') };
            let retract = match self.cycles.groove_return {
                Some(e) => e,
                None => {
                    self.warn(
                        "groove-return",
                        gspan,
                        format!(
                            "{name} without its first block ({name} R(e);): the return after each peck is the \
                             control's parameter 5139, which kezuri takes as 0 (no return between pecks)"
                        ),
                    );
                    0.0
                }
            };
            (p, s, retract, w.get(b'R').map_or(0.0, |r| self.mm(r)))
        };
        let (peck_axis, step_axis) = if face { ("Z", "X") } else { ("X", "Z") };
        let word = |l: u8, what: &str| {
            let c = l as char;
            let counts = if haas { String::new() } else { format!(" (radius, least increments: {c}2000 is 2 mm)") };
            format!("{name} needs {c}, {what}{counts}")
        };
        if peck_moves && !w.has(peck_letter) {
            return Err(Diagnostic::error(gspan, word(peck_letter, &format!("the depth of each peck in {peck_axis}"))));
        }
        if step_moves && !w.has(step_letter) {
            return Err(Diagnostic::error(
                gspan,
                word(step_letter, &format!("the step between grooves in {step_axis}")),
            ));
        }
        let read = |st: &mut State, l: u8| -> Option<f64> {
            if haas {
                w.get(l).map(|v| st.mm(v))
            } else {
                st.count_word(w, l, &name)
            }
        };
        let peck = read(self, peck_letter).unwrap_or(0.0);
        let step = read(self, step_letter).unwrap_or(0.0);
        let feed = self.feed_mm_min(gspan)?;
        let g = Grooving { face, start, end: (end.x, end.z), peck, step, retract, relief };
        let steps = grooving(&g, peck_letter, step_letter).map_err(|r| self.refused(r, w, gspan))?;
        self.run_steps(&steps, feed, 0.0, line);
        Ok(true)
    }
}

impl State {
    /// Whether the block (its G codes `codes`) names a lathe's G74 G75 or
    /// G76 (in its G code system), whose K (Haas) is a length, not the
    /// repeat count of the mill's drilling cycles of the same numbers.
    pub(in super::super) fn lathe_names_cycle(&self, codes: &LatheCodes) -> bool {
        self.turning.as_ref().is_some_and(|t| t.fanuc) && codes.cycle.is_some()
    }

    /// Whether `letter` of the block (its G codes `codes`) is a count its
    /// cycle reads itself ([`State::count_word`]), not an axis word in least
    /// increments: Q of Fanuc's G74 G75 G76 and of the threading cycle
    /// G92 (its start angle, 0.001°, also in the blocks that repeat it),
    /// Haas G76's A (the tool's angle) and Q (the start angle).
    pub(in super::super) fn lathe_cycle_count(&self, letter: u8, codes: &LatheCodes) -> bool {
        let Some(turning) = self.turning.as_ref().filter(|t| t.fanuc) else { return false };
        if !matches!(letter, b'Q' | b'A') {
            return false;
        }
        let haas = self.settings.dialect == crate::Dialect::HaasLathe;
        match codes.cycle {
            Some(GCode::MultipleThreading) => letter == b'Q' || haas,
            Some(_) => letter == b'Q',
            None => {
                let motion = codes.motion.unwrap_or(turning.motion);
                letter == b'Q' && motion == Some(LatheMotion::Single(SingleCycle::Threading))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peck_drilling_on_centre() {
        // G74 R1; G74 Z-10 Q4000 F..: from Z2, pecks to -2, -6, -10 with
        // returns of 1 between, then back to Z2.
        let g = Grooving {
            face: true,
            start: (0.0, 2.0),
            end: (0.0, -10.0),
            peck: 4.0,
            step: 0.0,
            retract: 1.0,
            relief: 0.0,
        };
        let s = grooving(&g, b'Q', b'P').unwrap();
        assert_eq!(
            s,
            vec![
                Step::feed(0.0, -2.0),
                Step::rapid(0.0, -1.0),
                Step::feed(0.0, -6.0),
                Step::rapid(0.0, -5.0),
                Step::feed(0.0, -10.0),
                Step::rapid(0.0, 2.0),
            ]
        );
    }

    #[test]
    fn od_grooves_side_by_side() {
        // G75: from (X r 15, Z -10) to r 10, Z -14, 3 mm pecks, 2 mm steps:
        // grooves at Z -10, -12, -14; pecks to 12, 10 (clamped).
        let g = Grooving {
            face: false,
            start: (15.0, -10.0),
            end: (10.0, -14.0),
            peck: 3.0,
            step: 2.0,
            retract: 0.5,
            relief: 0.0,
        };
        let s = grooving(&g, b'P', b'Q').unwrap();
        let expected = [
            Step::feed(12.0, -10.0),
            Step::rapid(12.5, -10.0),
            Step::feed(10.0, -10.0),
            Step::rapid(15.0, -10.0),
            Step::rapid(15.0, -12.0),
            Step::feed(12.0, -12.0),
            Step::rapid(12.5, -12.0),
            Step::feed(10.0, -12.0),
            Step::rapid(15.0, -12.0),
            Step::rapid(15.0, -14.0),
            Step::feed(12.0, -14.0),
            Step::rapid(12.5, -14.0),
            Step::feed(10.0, -14.0),
            Step::rapid(15.0, -14.0),
            Step::rapid(15.0, -10.0),
        ];
        assert_eq!(s, expected);
    }

    #[test]
    fn zero_peck_is_refused() {
        let g = Grooving {
            face: true,
            start: (0.0, 2.0),
            end: (0.0, -10.0),
            peck: 0.0,
            step: 0.0,
            retract: 1.0,
            relief: 0.0,
        };
        assert_eq!(grooving(&g, b'Q', b'P').unwrap_err().letter, Some(b'Q'));
    }
}
