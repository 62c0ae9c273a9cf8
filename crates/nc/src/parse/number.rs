//! Number literals: the fast paths for plain words and numbers, and the
//! slow one for long numbers and numbers with blanks inside.

use super::{LineParser, Result};
use crate::ast::{Word, WordValue};
use crate::source::{Diagnostic, FileId, Span};

impl LineParser<'_> {
    /// The common case of a word's value, `X-12.345`: a sign and a number
    /// written right after the address. Gives what [`Self::word_value`]
    /// gives for it; `None`, with the cursor unmoved, for anything else.
    #[inline]
    pub(super) fn plain_number(&mut self) -> Option<WordValue> {
        let (value, len) = signed_number(&self.b[self.pos..self.end])?;
        let decimal = matches!(value, WordValue::Number { decimal: true, .. });
        if continues_after_blanks(&self.b[self.pos + len..self.end], decimal) {
            // A number with blanks inside: `word_value` reads it.
            return None;
        }
        self.pos += len;
        Some(value)
    }

    /// A number literal: digits with at most one decimal point. Returns the
    /// value and whether a decimal point was written; `None` if no digit.
    pub(super) fn number(&mut self) -> Result<Option<(f64, bool)>> {
        let start = self.pos;
        if let Some((value, decimal, len)) = short_number(&self.b[start..self.end]) {
            if !continues_after_blanks(&self.b[start + len..self.end], decimal) {
                self.pos += len;
                return Ok(Some((value, decimal)));
            }
            return self.spaced_number(start).map(Some);
        }
        // No digit at all, or more than 15: the standard library rounds those.
        let s = &self.b[start..self.end];
        let mut ignored = 0;
        let int_digits = digit_run(s, &mut ignored);
        let decimal = s.get(int_digits) == Some(&b'.');
        let fraction = if decimal { digit_run(&s[int_digits + 1..], &mut ignored) } else { 0 };
        if int_digits + fraction == 0 {
            return Ok(None);
        }
        self.pos = start + int_digits + fraction + usize::from(decimal);
        let text = std::str::from_utf8(&self.b[start..self.pos]).unwrap_or("0");
        let text = text.strip_suffix('.').unwrap_or(text);
        let value = text.parse::<f64>().map_err(|_| Diagnostic::error(self.span(start), "number cannot be read"))?;
        if !value.is_finite() || value > 1e15 {
            return Err(Diagnostic::error(self.span(start), "number is too large"));
        }
        Ok(Some((value, decimal)))
    }

    /// A number with blanks inside (`X1 0.5` is `X10.5`): a Fanuc control,
    /// like LinuxCNC, ignores spaces between the characters of a number.
    fn spaced_number(&mut self, start: usize) -> Result<(f64, bool)> {
        let mut text = String::new();
        let mut pos = start;
        while let Some(&c) = self.b[..self.end].get(pos) {
            match c {
                b'0'..=b'9' => text.push(c as char),
                b'.' if !text.contains('.') => text.push('.'),
                b' ' | b'\t' => {}
                _ => break,
            }
            pos += 1;
        }
        // Blanks after the last character belong to what follows.
        while matches!(self.b[pos - 1], b' ' | b'\t') {
            pos -= 1;
        }
        self.pos = pos;
        let decimal = text.contains('.');
        let value = text
            .strip_suffix('.')
            .unwrap_or(&text)
            .parse::<f64>()
            .map_err(|_| Diagnostic::error(self.span(start), "number cannot be read"))?;
        if !value.is_finite() || value > 1e15 {
            return Err(Diagnostic::error(self.span(start), "number is too large"));
        }
        Ok((value, decimal))
    }
}

/// The fast path of [`LineParser::words`]: reads the words of `line` from
/// `pos` on for as long as each is an address letter with a plain number
/// right after it (`X-12.345`) and only spaces come between them; pushes them
/// as the general loop would, and returns the position after the last one
/// (`pos` if none), where the general loop goes on.
/// Not inlined: on its own the loop keeps its state in registers.
#[inline(never)]
pub(super) fn plain_words(line: &[u8], pos: usize, file: FileId, words: &mut Vec<Word>) -> usize {
    let (mut done, mut pos) = (pos, pos);
    while let Some(&c) = line.get(pos) {
        let letter = c.to_ascii_uppercase();
        if !letter.is_ascii_alphabetic() || letter == b'O' {
            break;
        }
        let Some((value, len)) = signed_number(&line[pos + 1..]) else { break };
        let end = pos + 1 + len;
        let mut next = end;
        while line.get(next) == Some(&b' ') {
            next += 1;
        }
        if next > end && matches!(line.get(next), Some(b'0'..=b'9' | b'.')) {
            // A number with blanks inside (`X1 0.`): the general parser reads it.
            break;
        }
        words.push(Word::new(letter, value, Span::new(file, pos, end)));
        done = end;
        pos = next;
    }
    done
}

/// Whether a number that `rest` follows goes on after blanks: a digit, or a
/// decimal point when it has none yet.
#[inline(always)]
fn continues_after_blanks(rest: &[u8], decimal: bool) -> bool {
    let mut i = 0;
    while let Some(b' ' | b'\t') = rest.get(i) {
        i += 1;
    }
    i > 0
        && match rest.get(i) {
            Some(b'0'..=b'9') => true,
            Some(b'.') => !decimal,
            _ => false,
        }
}

/// A sign (or none) and a [`short_number`] at the start of `s`: the value as
/// [`LineParser::word_value`] gives it, and the length in bytes.
#[inline(always)]
fn signed_number(s: &[u8]) -> Option<(WordValue, usize)> {
    let (negative, unsigned) = match s.first() {
        Some(b'-') => (true, &s[1..]),
        Some(b'+') => (false, &s[1..]),
        _ => (false, s),
    };
    let (value, decimal, len) = short_number(unsigned)?;
    let value = WordValue::Number { value: if negative { -value } else { value }, decimal };
    Some((value, s.len() - unsigned.len() + len))
}

/// The number literal at the start of `s` when it has at most 15 digits:
/// its value, whether it has a decimal point, and its length in bytes.
/// `None` for anything else (no digit, too long), which
/// [`LineParser::number`] reads the slow way.
#[inline(always)]
fn short_number(s: &[u8]) -> Option<(f64, bool, usize)> {
    const POW10: [f64; 16] = [1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15];
    let mut mantissa: u64 = 0;
    let int_digits = digit_run(s, &mut mantissa);
    let decimal = s.get(int_digits) == Some(&b'.');
    let fraction = if decimal { digit_run(&s[int_digits + 1..], &mut mantissa) } else { 0 };
    let digits = int_digits + fraction;
    if digits == 0 || digits > 15 {
        return None;
    }
    // Exact: the mantissa (below 10^15) and the power of ten are both exact
    // doubles, and one IEEE division rounds correctly.
    Some((mantissa as f64 / POW10[fraction], decimal, digits + usize::from(decimal)))
}

/// Counts the ASCII digits at the start of `s`, accumulating them into
/// `mantissa` (wrapping: numbers of more than 15 digits are read again).
#[inline(always)]
fn digit_run(s: &[u8], mantissa: &mut u64) -> usize {
    let mut m = *mantissa;
    let mut n = 0;
    for &c in s {
        let d = c.wrapping_sub(b'0');
        if d > 9 {
            break;
        }
        m = m.wrapping_mul(10).wrapping_add(u64::from(d));
        n += 1;
    }
    *mantissa = m;
    n
}
