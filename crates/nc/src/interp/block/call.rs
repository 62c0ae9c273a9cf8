//! How a block calls: a macro (G65, G66) with its arguments, a subprogram
//! (M98), a local subprogram (M97), and what kind of call a frame is.

use super::super::value::Value;
use super::super::vars::Locals;
use super::super::words::Words;
use super::super::State;
use super::Action;
use crate::source::{Diagnostic, Span};

/// How a program was called.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(in crate::interp) enum FrameKind {
    Main,
    Subprogram,
    /// `M97`: blocks of the calling program from an N label to M99.
    Local,
    Macro,
    ModalMacro,
    /// A LinuxCNC `o… call` of a subroutine.
    OSub,
}

impl FrameKind {
    pub(in crate::interp) fn is_macro(self) -> bool {
        matches!(self, FrameKind::Macro | FrameKind::ModalMacro)
    }
}

pub(in crate::interp) struct Call {
    pub program: u32,
    pub repeats: u32,
    pub kind: FrameKind,
    pub args: Option<Box<Locals>>,
    pub span: Span,
}

/// Argument specification I: address to local variable number.
fn argument_slot(letter: u8) -> Option<usize> {
    Some(match letter {
        b'A' => 1,
        b'B' => 2,
        b'C' => 3,
        b'I' => 4,
        b'J' => 5,
        b'K' => 6,
        b'D' => 7,
        b'E' => 8,
        b'F' => 9,
        b'H' => 11,
        b'M' => 13,
        b'Q' => 17,
        b'R' => 18,
        b'S' => 19,
        b'T' => 20,
        b'U' => 21,
        b'V' => 22,
        b'W' => 23,
        b'X' => 24,
        b'Y' => 25,
        b'Z' => 26,
        _ => return None,
    })
}

impl State {
    pub(super) fn macro_call(&mut self, w: &Words, gspan: Span, kind: FrameKind) -> Result<Call, Diagnostic> {
        let program =
            w.get(b'P').ok_or_else(|| Diagnostic::error(gspan, "a macro call needs P, the program number"))?;
        let repeats = w.get(b'L').unwrap_or(1.0);
        let mut args = [Value::Vacant; 33];
        fill_arguments(w, &mut args);
        Ok(Call {
            program: whole(program, w.span(b'P'), "program number")?,
            repeats: whole(repeats, w.span(b'L'), "repeat count")?,
            kind,
            args: Some(Box::new(args)),
            span: gspan,
        })
    }

    pub(super) fn subprogram_call(&mut self, w: &Words, mspan: Span) -> Result<Call, Diagnostic> {
        let p = w.get(b'P').ok_or_else(|| Diagnostic::error(mspan, "M98 needs P, the subprogram number"))?;
        let mut program = whole(p, w.span(b'P'), "subprogram number")?;
        let mut repeats = 1;
        match w.get(b'L') {
            Some(l) => repeats = whole(l, w.span(b'L'), "repeat count")?,
            // M98 P50010: five times O0010 (count in front of four digits);
            // LinuxCNC 2.9 reads program O50010, once.
            None if program > 9999 && self.settings.dialect != crate::Dialect::LinuxCnc => {
                repeats = program / 10_000;
                program %= 10_000;
            }
            None => {}
        }
        Ok(Call { program, repeats, kind: FrameKind::Subprogram, args: None, span: mspan })
    }
}

pub(super) fn fill_arguments(w: &Words, args: &mut Locals) {
    for letter in b'A'..=b'Z' {
        if let (Some(v), Some(slot)) = (w.get(letter), argument_slot(letter)) {
            args[slot - 1] = Value::Num(v);
        }
    }
    // M words are kept apart as M codes; the first one is argument #13,
    // which may have a fraction (`M0.070`).
    if w.m_count > 0 {
        args[12] = Value::Num(f64::from(w.m[0].0));
    } else if let Some(m) = w.m_argument {
        args[12] = Value::Num(m);
    }
}

/// `M97 P<label> L<repeats>` (Haas): the N label to run to M99, how often.
pub(super) fn local_call(w: &Words, mspan: Span) -> Result<Action, Diagnostic> {
    let p = w.get(b'P').ok_or_else(|| Diagnostic::error(mspan, "M97 needs P, the N number to call"))?;
    let label = whole(p, w.span(b'P'), "sequence number")?;
    let repeats = w.get(b'L').map_or(Ok(1), |l| whole(l, w.span(b'L'), "repeat count"))?;
    Ok(Action::LocalCall { label, repeats, span: mspan })
}

pub(super) fn whole(v: f64, span: Span, what: &str) -> Result<u32, Diagnostic> {
    if v.fract() != 0.0 || !(0.0..=99_999_999.0).contains(&v) {
        return Err(Diagnostic::error(span, format!("{what} must be a whole number, got {v}")));
    }
    Ok(v as u32)
}
