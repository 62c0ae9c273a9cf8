//! Direct drawing dimension programming: FANUC Series 0i-TF Plus
//! Operator's Manual (B-64604EN), lathe system, "Direct drawing dimension
//! programming".
//!
//! A straight line (G01) may be given by its angle and one end coordinate,
//! as a drawing dimensions it: `X(U)_ ,A_` or `Z(W)_ ,A_`, the angle in
//! degrees from the +Z axis, counter-clockwise with +X up (the ZX plane as
//! the drawing shows it); the other coordinate is where that line through
//! the start point reaches the given one. Between two such lines (or any
//! two moves) `,C` chamfers and `,R` rounds the corner, as elsewhere. In G
//! code system A the addresses are written without the comma (`A`, `C`,
//! `R`), as on a control with direct drawing dimension programming on
//! (parameter 3405 bit 5, DDP): once a block gives `A`, kezuri reads the
//! program's `C` and `R` as the corners between any two moves, their size
//! the chamfer's leg or the radius, and a `C` or `R` waiting on the block
//! before goes to the corner between that block and this line.
//!
//! The manual's forms with an angle alone (`,A1;` then `X3 Z3 ,A2;`: the
//! corner where the two lines meet) are refused with a located error.

use super::super::modal::{Distance, Units};
use super::super::words::Words;
use super::super::State;
use crate::source::Diagnostic;

impl State {
    /// A G01 block's angle word on a Fanuc lathe: `,A` in any G code
    /// system, `A` in system A. With one of X and Z, the other is put in
    /// the words (X a radius, as [`State::lathe_axes`] leaves it). Returns
    /// whether the block gave an angle.
    pub(in super::super) fn drawing_angle(&mut self, w: &mut Words) -> Result<bool, Diagnostic> {
        let Some(turning) = &self.turning else { return Ok(false) };
        let system_a = turning.fanuc && turning.system == super::GCodeSystem::A;
        let letter = match (w.has(b'a'), system_a && w.has(b'A') && !self.settings.dialect.is_haas()) {
            (true, _) => b'a',
            (false, true) => b'A',
            (false, false) => return Ok(false),
        };
        let name = if letter == b'a' { ",A" } else { "A" };
        let (angle, span) = (w.get(letter).unwrap_or(0.0), w.span(letter));
        let (x, z) = (w.get(b'X'), w.get(b'Z'));
        if x.is_some() == z.is_some() {
            let why = if x.is_some() {
                format!(
                    "{name} with both X and Z: the end point is given twice; give the angle and one of X (U) and Z (W)"
                )
            } else {
                format!(
                    "{name} without X or Z: kezuri does not model the form whose end point is where this line meets \
                     the next block's; give the angle and one of X (U) and Z (W)"
                )
            };
            return Err(Diagnostic::error(span, why));
        }
        if !angle.is_finite() || angle.abs() > 360.0 {
            return Err(Diagnostic::error(span, format!("{name}{angle}: an angle is −360° to 360°")));
        }
        let unit = if self.modal.units == Units::Inch { 25.4 } else { 1.0 };
        let here = self.program_position();
        let incremental = self.modal.distance == Distance::Incremental;
        let (sin, cos) = angle.to_radians().sin_cos();
        // Along the line the X step is Z step · tan A.
        let (given, other, from, to, ratio) = match (x, z) {
            (Some(x), _) => (x, b'Z', here.x / unit, here.z / unit, (cos, sin)),
            (_, Some(z)) => (z, b'X', here.z / unit, here.x / unit, (sin, cos)),
            _ => unreachable!("one of X and Z, checked above"),
        };
        let step = if incremental { given } else { given - from };
        if ratio.1.abs() < 1e-9 && step.abs() > 1e-12 {
            let (along, axis) = if other == b'Z' { ("Z", "X") } else { ("X", "Z") };
            return Err(Diagnostic::error(
                span,
                format!("{name}{angle}: a line at this angle runs along {along} and never reaches the {axis} given (the control stops with an alarm)"),
            ));
        }
        let moved = if step.abs() > 1e-12 { step * ratio.0 / ratio.1 } else { 0.0 };
        w.put(other, if incremental { moved } else { to + moved }, letter);
        if let Some(t) = &mut self.turning {
            t.drawing |= letter == b'A';
        }
        Ok(true)
    }
}
