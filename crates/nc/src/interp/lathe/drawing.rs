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
//! A line given by its angle alone (`,A1;` then `X3 Z3 ,A2;`) ends where
//! it meets the next block's line, the one through X3 Z3 at the angle A2;
//! the next block then runs from there to X3 Z3. kezuri reads that next
//! block's X, Z and angle ahead as plain numbers, X and Z absolute.

use super::super::modal::{Distance, Units};
use super::super::words::Words;
use super::super::State;
use crate::ast::{Word, WordValue};
use crate::interp::IntegerInput;
use crate::source::{Diagnostic, Span};

impl State {
    /// A G01 block's angle word on a Fanuc lathe: `,A` in any G code
    /// system, `A` in system A. With one of X and Z, the other is put in
    /// the words (X a radius, as [`State::lathe_axes`] leaves it); with
    /// neither, both, where this line meets the next block's (`next`, its
    /// words). Returns whether the block gave an angle.
    pub(in super::super) fn drawing_angle(&mut self, w: &mut Words, next: Option<&[Word]>) -> Result<bool, Diagnostic> {
        let Some(turning) = &mut self.turning else { return Ok(false) };
        let pending = std::mem::take(&mut turning.drawing_pending);
        let system_a = turning.fanuc && turning.system == super::GCodeSystem::A;
        let letter = match (w.has(b'a'), system_a && w.has(b'A') && !self.settings.dialect.is_haas()) {
            (true, _) => b'a',
            (false, true) => b'A',
            (false, false) => return Ok(false),
        };
        let name = if letter == b'a' { ",A" } else { "A" };
        let (angle, span) = (w.get(letter).unwrap_or(0.0), w.span(letter));
        if !angle.is_finite() || angle.abs() > 360.0 {
            return Err(Diagnostic::error(span, format!("{name}{angle}: an angle is −360° to 360°")));
        }
        if let Some(t) = &mut self.turning {
            t.drawing |= letter == b'A';
        }
        let (x, z) = (w.get(b'X'), w.get(b'Z'));
        match (x, z) {
            // The second block of the intersection form: its line runs from
            // where the block before ended (on it) to X Z.
            (Some(_), Some(_)) if pending => {
                *w = w.without(letter);
                return Ok(true);
            }
            (Some(_), Some(_)) => {
                return Err(Diagnostic::error(
                    span,
                    format!(
                    "{name} with both X and Z: the end point is given twice; give the angle and one of X (U) and Z (W)"
                ),
                ))
            }
            (None, None) => {
                let (px, pz) = self.meeting_point(angle, name, span, next)?;
                w.put(b'X', px, letter);
                w.put(b'Z', pz, letter);
                if let Some(t) = &mut self.turning {
                    t.drawing_pending = true;
                }
                return Ok(true);
            }
            _ => {}
        }
        let unit = if self.modal.units == Units::Inch { 25.4 } else { 1.0 };
        let here = self.program_position();
        let incremental = self.modal.distance == Distance::Incremental;
        let (sin, cos) = angle.to_radians().sin_cos();
        // Along the line the X step is Z step · tan A.
        let (given, other, from, to, ratio) = match (x, z) {
            (Some(x), _) => (x, b'Z', here.x / unit, here.z / unit, (cos, sin)),
            (_, Some(z)) => (z, b'X', here.z / unit, here.x / unit, (sin, cos)),
            _ => unreachable!("one of X and Z, matched above"),
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
        Ok(true)
    }

    /// Where the line from the tool at `angle` meets the next block's line
    /// (through its X Z at its own angle), as absolute (X radius, Z) in
    /// program units.
    fn meeting_point(
        &self,
        angle: f64,
        name: &str,
        span: Span,
        next: Option<&[Word]>,
    ) -> Result<(f64, f64), Diagnostic> {
        let form = format!(
            "{name} without X or Z ends where its line meets the next block's: the next block must give X, Z and its \
             angle as plain numbers (`X… Z… {name}…`)"
        );
        let refuse = |why: &str| Diagnostic::error(span, format!("{form}; {why}"));
        if self.modal.distance == Distance::Incremental {
            return Err(refuse("kezuri reads it in absolute (G90) only"));
        }
        let turning = self.turning.as_ref().expect("a lathe's block");
        let letters: &[u8] = if name == "A" { b"aA" } else { b"a" };
        let value = |letter: u8| -> Option<Result<f64, ()>> {
            let word = next?.iter().find(|w| w.letter == letter)?;
            Some(match word.value() {
                WordValue::Number { value, decimal } => {
                    let counts = if letter == b'X' || letter == b'Z' {
                        if self.modal.units == Units::Mm {
                            1000.0
                        } else {
                            10_000.0
                        }
                    } else {
                        1000.0
                    };
                    let increments = !decimal && self.settings.integer_input == IntegerInput::Increments;
                    Ok(if increments { value / counts } else { value })
                }
                WordValue::Expr(_) => Err(()),
            })
        };
        let (x2, z2) = (value(b'X'), value(b'Z'));
        let a2 = letters.iter().find_map(|&l| value(l));
        let (Some(Ok(x2)), Some(Ok(z2)), Some(Ok(a2))) = (x2, z2, a2) else {
            return Err(refuse("it does not"));
        };
        let x2 = if turning.x == super::XMode::Diameter { x2 / 2.0 } else { x2 };
        let unit = if self.modal.units == Units::Inch { 25.4 } else { 1.0 };
        let here = self.program_position();
        // In (Z, X): the line from the tool S along d1, the next one
        // through E along d2.
        let s = [here.z / unit, here.x / unit];
        let (d1, d2) = (angle.to_radians(), a2.to_radians());
        let (d1, d2) = ([d1.cos(), d1.sin()], [d2.cos(), d2.sin()]);
        let den = d1[0] * d2[1] - d1[1] * d2[0];
        if den.abs() < 1e-9 {
            return Err(Diagnostic::error(
                span,
                format!("{name}{angle} and the next block's {name}{a2} are parallel: the two lines never meet (the control stops with an alarm)"),
            ));
        }
        let e = [z2 - s[0], x2 - s[1]];
        let t = (e[0] * d2[1] - e[1] * d2[0]) / den;
        Ok((s[1] + t * d1[1], s[0] + t * d1[0]))
    }
}
