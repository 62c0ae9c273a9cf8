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

use super::single::{Refusal, Step};

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
    if sp != 0.0 && g.peck <= 0.0 {
        return Err(Refusal::at(
            peck_letter,
            format!("the depth of each peck in {peck_axis} is 0: the cycle would never reach the end; give it greater than 0"),
        ));
    }
    if sq != 0.0 && g.step <= 0.0 {
        return Err(Refusal::at(
            step_letter,
            format!("the step between grooves in {step_axis} is 0: the cycle would never reach the end; give it greater than 0"),
        ));
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
        if steps.is_empty() {
            // The first groove is at the start point.
        } else {
            steps.push(step_at(g.face, true, p0, q));
        }
        let mut p = p0;
        while sp != 0.0 {
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
