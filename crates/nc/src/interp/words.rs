//! The words of one NC block, evaluated: G and M codes apart, every other
//! address once, integer axis words read as the control reads them.

use kezuri_geom::{Axes, AxisSet};

use super::modal::{GCode, Units};
use super::value::Value;
use super::{IntegerInput, State};
use crate::ast::{Program, Word, WordValue};
use crate::number::number;
use crate::source::{Diagnostic, FileId, Span};

/// The evaluated words of one block. Kept small and filled in place: it is
/// made for every block.
#[derive(Clone, Copy)]
pub(super) struct Words<'a> {
    /// The block's words and their file, for the spans of diagnostics.
    words: &'a [Word],
    file: FileId,
    /// By [`slot`]: A–Z, then LinuxCNC's polar `@` and `^`.
    value: [f64; SLOTS],
    present: u32,
    /// Where in `words` each present address is.
    index: [u32; SLOTS],
    pub(super) g: [(u32, Span); 8],
    pub(super) g_count: usize,
    pub(super) m: [(u32, Span); 4],
    pub(super) m_count: usize,
    /// In a macro call's block (G65, G66, G66.1), an M word that is no M
    /// code (`M0.070`, `M-1.`): argument #13 only.
    pub(super) m_argument: Option<f64>,
    /// The addresses that are axes, as `present` bits: X Y Z A B C
    /// ([`SIX_AXES`]), and U V W where the control has them ([`NINE_AXES`],
    /// [`State::axis_bits`]).
    pub(super) axis_bits: u32,
}

/// A–Z, `@` (the polar radius), `^` (the polar angle), and Fanuc's `,C`
/// and `,R` (kept as `c` and `r`).
const SLOTS: usize = 31;

/// Where an address is kept: A–Z in order, then `@`, `^`, `,C` and `,R`.
const fn slot(letter: u8) -> usize {
    match letter {
        b'@' => 26,
        b'^' => 27,
        b'c' => 28,
        b'r' => 29,
        b'a' => 30,
        _ => (letter - b'A') as usize,
    }
}

const fn bit(letter: u8) -> u32 {
    1 << slot(letter)
}

/// The addresses in `list` as one mask, for [`Words::has_any`]: a block's
/// rare words are looked for with one test.
pub(super) const fn letters(list: &[u8]) -> u32 {
    let mut mask = 0;
    let mut k = 0;
    while k < list.len() {
        mask |= bit(list[k]);
        k += 1;
    }
    mask
}

impl<'a> Words<'a> {
    pub(super) fn new(words: &'a [Word], file: FileId) -> Self {
        Words {
            words,
            file,
            value: [0.0; SLOTS],
            present: 0,
            index: [0; SLOTS],
            g: [(0, Span::default()); 8],
            g_count: 0,
            m: [(0, Span::default()); 4],
            m_count: 0,
            m_argument: None,
            axis_bits: SIX_AXES,
        }
    }

    pub(super) fn has(&self, letter: u8) -> bool {
        self.present & bit(letter) != 0
    }

    /// Whether the block has any address of `mask` (made by [`letters`]).
    pub(super) fn has_any(&self, mask: u32) -> bool {
        self.present & mask != 0
    }

    pub(super) fn get(&self, letter: u8) -> Option<f64> {
        self.has(letter).then(|| self.value[slot(letter)])
    }

    /// Whether the word of this address was written with a decimal point
    /// (an expression counts as one).
    pub(super) fn decimal(&self, letter: u8) -> bool {
        self.has(letter)
            && self.words.get(self.index[slot(letter)] as usize).is_none_or(|w| match w.value() {
                WordValue::Number { decimal, .. } => decimal,
                WordValue::Expr(_) => true,
            })
    }

    /// Where the word of this address is written; the default span when the
    /// block has none.
    pub(super) fn span(&self, letter: u8) -> Span {
        if !self.has(letter) {
            return Span::default();
        }
        self.words.get(self.index[slot(letter)] as usize).map_or(Span::default(), |w| w.span(self.file))
    }

    /// Whether the block names an axis (a polar word names X and Y).
    pub(super) fn any_axis(&self) -> bool {
        self.present & self.axis_bits != 0 || self.polar()
    }

    /// Whether the block has LinuxCNC's polar `@` (radius) or `^` (angle).
    pub(super) fn polar(&self) -> bool {
        self.has(b'@') || self.has(b'^')
    }

    /// The evaluated words that `keep` accepts (by letter and value), in the block's
    /// order, as program text: axis words with a decimal point (the value
    /// in program units), whole numbers elsewhere without one.
    pub(super) fn text(&self, keep: impl Fn(u8, f64) -> bool) -> String {
        let (mut g, mut m) = (0, 0);
        let mut out = String::new();
        for (k, word) in self.words.iter().enumerate() {
            let letter = word.letter;
            let value = match letter {
                b'G' if g < self.g_count && self.g[g].1 == word.span(self.file) => {
                    g += 1;
                    f64::from(self.g[g - 1].0) / 10.0
                }
                b'M' if m < self.m_count && self.m[m].1 == word.span(self.file) => {
                    m += 1;
                    f64::from(self.m[m - 1].0)
                }
                b'A'..=b'Z' | b'@' | b'^' if self.has(letter) && self.index[slot(letter)] as usize == k => {
                    self.value[slot(letter)]
                }
                _ => continue,
            };
            if !keep(letter, value) {
                continue;
            }
            if !out.is_empty() {
                out.push(' ');
            }
            out.push(letter as char);
            if AXIS_LETTERS.contains(&letter) || value.fract() != 0.0 {
                out.push_str(&number(value, 6));
            } else if letter == b'G' {
                out.push_str(&format!("{value:02}"));
            } else {
                out.push_str(&format!("{value}"));
            }
        }
        out
    }

    /// The words of `letters` as the block wrote them (a literal as
    /// written, an expression's value): for words that are no lengths,
    /// such as G05.1's Q, which a writer must not scale.
    pub(super) fn as_written(&self, letters: &[u8]) -> String {
        let mut out = Vec::new();
        for (k, word) in self.words.iter().enumerate() {
            let letter = word.letter;
            if !letters.contains(&letter) || !self.has(letter) || self.index[slot(letter)] as usize != k {
                continue;
            }
            let text = match word.value() {
                WordValue::Number { value, decimal: true } => number(value, 6),
                WordValue::Number { value, decimal: false } => format!("{value}"),
                WordValue::Expr(_) => number(self.value[slot(letter)], 6),
            };
            out.push(format!("{}{text}", letter as char));
        }
        out.join(" ")
    }

    /// The word of `letter`, if the block has it, multiplied by `factor`
    /// (a diameter read as the radius).
    pub(super) fn scale(&mut self, letter: u8, factor: f64) {
        if self.has(letter) {
            self.value[slot(letter)] *= factor;
        }
    }

    /// Gives address `letter` the value `value`, as if written where the
    /// word of `from` is (for the spans of diagnostics); the word of `from`
    /// is taken out where it is another address. A lathe's `U` read as an
    /// incremental X becomes the X it reaches.
    pub(super) fn put(&mut self, letter: u8, value: f64, from: u8) {
        let (i, f) = (slot(letter), slot(from));
        self.value[i] = value;
        self.index[i] = self.index[f];
        if letter != from {
            self.present &= !bit(from);
        }
        self.present |= bit(letter);
    }

    /// The words with only the one of `letter`.
    pub(super) fn only(&self, letter: u8) -> Words<'a> {
        Words { present: self.present & bit(letter), ..*self }
    }

    /// The words without the one of `letter`.
    pub(super) fn without(&self, letter: u8) -> Words<'a> {
        Words { present: self.present & !bit(letter), ..*self }
    }

    /// The words with X Y Z A B C as their only axes: where U V W are a
    /// code's own parameters (LinuxCNC's lathe cycles).
    pub(super) fn six_axes(&self) -> Words<'a> {
        Words { axis_bits: SIX_AXES, ..*self }
    }

    /// Whether `letter` is an axis address of this block's control.
    pub(super) fn is_axis(&self, letter: u8) -> bool {
        self.axis_bits & bit(letter) != 0
    }

    /// Whether the control has U V W as axes (LinuxCNC).
    pub(super) fn has_uvw(&self) -> bool {
        self.axis_bits & UVW_BITS == UVW_BITS
    }

    /// The axes whose own words the block has (a polar word names none).
    fn axis_words_named(&self) -> AxisSet {
        // Slots: A B C are 0–2, U V W 20–22, X Y Z 23–25.
        let p = self.present & self.axis_bits;
        AxisSet((((p >> 23) & 0b111) | ((p & 0b111) << 3) | (((p >> 20) & 0b111) << 6)) as u16)
    }

    /// The block's axis words: the axis (in [`Axes::LETTERS`] order) and
    /// the value, as written (program units).
    pub(super) fn axis_words(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        let mut left = self.axis_words_named().0;
        std::iter::from_fn(move || {
            if left == 0 {
                return None;
            }
            let k = left.trailing_zeros() as usize;
            left &= left - 1;
            Some((k, self.value[AXIS_SLOTS[k]]))
        })
    }

    /// The axes the block names.
    pub(super) fn axes(&self) -> AxisSet {
        let named = self.axis_words_named();
        if self.polar() {
            named.with(0).with(1)
        } else {
            named
        }
    }
}

/// The slot of each axis, in [`Axes::LETTERS`] order.
const AXIS_SLOTS: [usize; Axes::COUNT] = [23, 24, 25, 0, 1, 2, 20, 21, 22];

/// The `present` bits of U V W.
const UVW_BITS: u32 = 0b111 << 20;
/// The axis addresses of a control with X Y Z A B C, as `present` bits.
pub(super) const SIX_AXES: u32 = (0b111 << 23) | 0b111;
/// The axis addresses of a control with U V W as well (LinuxCNC).
pub(super) const NINE_AXES: u32 = SIX_AXES | UVW_BITS;

/// Addresses whose integer values count least input increments.
pub(super) const AXIS_LETTERS: &[u8] = b"XYZABCIJKRUVWQ@cr";

impl State {
    /// Evaluates the words of `w` (made by [`Words::new`]) into it.
    pub(super) fn gather(&mut self, program: &Program, w: &mut Words) -> Result<(), Diagnostic> {
        // A lathe block's G codes, decoded once where a word needs them.
        let mut lathe_codes = None;
        for (k, word) in w.words.iter().enumerate() {
            let word_span = word.span(w.file);
            let (v, decimal) = match word.value() {
                WordValue::Number { value, decimal } => (value, decimal),
                WordValue::Expr(e) => match self.eval(program, e).map_err(|m| Diagnostic::error(word_span, m))? {
                    Value::Vacant => continue,
                    Value::Num(v) => (v, true),
                },
            };
            let letter = word.letter;
            match letter {
                b'G' => {
                    let tenths = (v * 10.0).round();
                    if !(0.0..=9999.0).contains(&tenths) || (v * 10.0 - tenths).abs() > 1e-6 {
                        return Err(Diagnostic::error(word_span, format!("G{v} is not a G code")));
                    }
                    if w.g_count == w.g.len() {
                        return Err(Diagnostic::error(word_span, "more than 8 G codes in one block"));
                    }
                    w.g[w.g_count] = (tenths as u32, word_span);
                    w.g_count += 1;
                }
                b'M' => {
                    if v.fract() != 0.0 || !(0.0..=99_999_999.0).contains(&v) {
                        // In a macro call M is argument #13, any number.
                        if self.calls_macro(w.words) {
                            if w.m_argument.is_some() {
                                return Err(Diagnostic::error(word_span, "address M appears twice in this block"));
                            }
                            w.m_argument = Some(v);
                            continue;
                        }
                        return Err(Diagnostic::error(word_span, format!("M{v} is not an M code")));
                    }
                    if w.m_count == w.m.len() {
                        return Err(Diagnostic::error(word_span, "more than 4 M codes in one block"));
                    }
                    w.m[w.m_count] = (v as u32, word_span);
                    w.m_count += 1;
                    self.last.m = v;
                }
                _ => {
                    if w.has(letter) {
                        return Err(Diagnostic::error(
                            word_span,
                            format!("address {} appears twice in this block", letter as char),
                        ));
                    }
                    let mut v = v;
                    // In a canned cycle K is a repeat count, not an arc centre.
                    // (A lathe's G74 G75 G76 are no drilling cycles: their K is a length.)
                    let mut codes = || *lathe_codes.get_or_insert_with(|| self.lathe_codes(w.words));
                    let count = letter == b'K'
                        && (self.modal.cycle.is_some() || names_cycle(w.words))
                        && !self.lathe_names_cycle(&codes());
                    // A lathe cycle's sequence numbers and counts (Q, R) are no lengths.
                    if !decimal
                        && !count
                        && AXIS_LETTERS.contains(&letter)
                        && self.settings.integer_input == IntegerInput::Increments
                        && !self.contour_count(letter, &codes(), w.words)
                        && !self.lathe_cycle_count(letter, &codes())
                    {
                        // Counts per unit: 0.001 mm or degree, 0.0001 inch. Dividing by
                        // the exact power of ten gives the nearest double (X-26 is -0.026).
                        let counts =
                            if b"ABC".contains(&letter) || self.modal.units == Units::Mm { 1000.0 } else { 10_000.0 };
                        if v != 0.0 {
                            self.first_integer.get_or_insert((word_span, letter, v));
                            let dwell = letter == b'X' && w.g[..w.g_count].iter().any(|&(g, _)| g == 40);
                            let unit = match self.modal.units {
                                _ if dwell => "s",
                                _ if b"ABC".contains(&letter) => "deg",
                                Units::Mm => "mm",
                                Units::Inch => "inch",
                            };
                            self.warn(
                                "decimal",
                                word_span,
                                format!(
                                    "{}{} has no decimal point: read as {} increments = {} {unit}; write {}{}. if you meant {} {unit}",
                                    letter as char,
                                    v,
                                    v,
                                    v / counts,
                                    letter as char,
                                    v,
                                    v
                                ),
                            );
                        }
                        v /= counts;
                    }
                    let i = slot(letter);
                    w.value[i] = v;
                    w.index[i] = k as u32;
                    w.present |= bit(letter);
                }
            }
        }
        Ok(())
    }
}

impl State {
    /// Whether the block of `words` calls a macro with its words as
    /// arguments: G65, G66 or G66.1 written in it, or G66.1 in force.
    fn calls_macro(&self, words: &[Word]) -> bool {
        let every_block = self.modal.modal_call == Some(super::modal::ModalCallKind::EveryBlock)
            && self.modal_call.is_some()
            && self.modal_depth == 0;
        every_block
            || words.iter().any(|w| {
                w.letter == b'G'
                    && matches!(w.value(), WordValue::Number { value, .. }
                        if matches!(GCode::decode((value * 10.0).round() as u32), Some(GCode::MacroCall | GCode::ModalCall(_))))
            })
    }
}

/// Whether `words` name a canned cycle with a literal G number.
fn names_cycle(words: &[Word]) -> bool {
    words.iter().any(|w| {
        w.letter == b'G'
            && matches!(w.value(), WordValue::Number { value, .. }
                if matches!(GCode::decode((value * 10.0).round() as u32), Some(GCode::CannedCycle(_))))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_slots_and_bits_follow_the_letters() {
        for (k, &letter) in Axes::LETTERS.iter().enumerate() {
            assert_eq!(AXIS_SLOTS[k], slot(letter), "{}", letter as char);
            assert_eq!(NINE_AXES & bit(letter), bit(letter));
            assert_eq!(SIX_AXES & bit(letter) != 0, k < 6);
        }
    }
}
