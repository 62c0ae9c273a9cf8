//! What wrapping a program in the texture macro's calls must know of it,
//! read from its parsed blocks: where it already calls a macro on its blocks
//! or another program, where it moves in G91, which program numbers it has,
//! and what in its cutting section the macro cannot pass on.

use crate::ast::{Block, Program, Statement, Word, WordValue};
use crate::parse;

/// The G codes the macro passes on in the cutting section: the motions, the
/// planes and G90.
const MOTION_G: [f64; 8] = [0.0, 1.0, 2.0, 3.0, 17.0, 18.0, 19.0, 90.0];

/// The blocks of a program's text, parsed as Fanuc's.
pub struct Blocks<'a> {
    text: &'a str,
    program: Program,
}

impl<'a> Blocks<'a> {
    /// Parses `text`. What does not parse is left out (the run reports it).
    pub fn parse(text: &'a str) -> Blocks<'a> {
        let mut program = Program::default();
        parse(&mut program, 0, text);
        Blocks { text, program }
    }

    /// The first line that calls a macro on its blocks (G66, G66.1).
    pub fn modal_macro_line(&self) -> Option<usize> {
        self.first_line(usize::MAX, |w| is(w, b'G', 66))
    }

    /// The first line up to `last` that goes incremental (G91, G91.1).
    pub fn incremental_line(&self, last: usize) -> Option<usize> {
        self.first_line(last, |w| is(w, b'G', 91))
    }

    /// The first line that calls another program (M98, M198, G65).
    pub fn call_line(&self) -> Option<usize> {
        self.first_line(usize::MAX, |w| is(w, b'M', 98) || is(w, b'M', 198) || is(w, b'G', 65))
    }

    /// Whether the text has program `O<number>`.
    pub fn has_program(&self, number: u32) -> bool {
        self.program.units.iter().any(|u| u.number == Some(number))
    }

    /// The first word on lines `first..=last` that is not a motion word the
    /// macro passes on (X Y Z I J K R F with a number, N, the motion and
    /// plane G codes and G90): its line and the word as written (`M08`,
    /// `G04`; `#1` for an assignment).
    pub fn foreign_word(&self, first: usize, last: usize) -> Option<(usize, String)> {
        let lines = first..=last;
        self.program.blocks.iter().filter(|b| lines.contains(&(b.line as usize))).find_map(|b| {
            let foreign = match b.statement {
                Statement::Empty | Statement::Comment(_) => None,
                _ if b.delete => Some("/".to_string()),
                Statement::Words { .. } => {
                    self.program.words(b).iter().map(|w| self.written(b, w)).find(|w| !passed_on(w))
                }
                _ => Some(self.statement_head(b)),
            };
            foreign.map(|w| (b.line as usize, w))
        })
    }

    /// The first line up to `last` with a word that `wanted`.
    fn first_line(&self, last: usize, wanted: impl Fn(&Word) -> bool) -> Option<usize> {
        let found = self.program.blocks.iter().find(|b| self.program.words(b).iter().any(&wanted))?;
        Some(found.line as usize).filter(|&line| line <= last)
    }

    /// Word `w` of block `b` as written: its letter and the number after
    /// it, upper case, without spaces (`G04`, `X` for `X#1`).
    fn written(&self, b: &Block, w: &Word) -> String {
        let span = w.span(b.span.file);
        let text: String = self.text[span.start as usize..span.end as usize]
            .chars()
            .filter(|c| !c.is_whitespace())
            .map(|c| c.to_ascii_uppercase())
            .collect();
        leading(&text)
    }

    /// The head of a block that is not words (`#1` of `#1=2`, `I` of an
    /// `IF`), after its `N` number.
    fn statement_head(&self, b: &Block) -> String {
        let text: String = self.text[b.span.start as usize..b.span.end as usize]
            .chars()
            .filter(|c| !c.is_whitespace())
            .map(|c| c.to_ascii_uppercase())
            .collect();
        let rest = match b.number {
            Some(_) => text.trim_start_matches('N').trim_start_matches(|c: char| c.is_ascii_digit()),
            None => &text,
        };
        leading(rest)
    }
}

/// Whether `w` is the word `letter` with the whole number `n` (`G66`,
/// `G066`, `G66.1` for 66).
fn is(w: &Word, letter: u8, n: u32) -> bool {
    w.letter == letter
        && matches!(w.value(), WordValue::Number { value, .. } if value >= 0.0 && value.trunc() == f64::from(n))
}

/// Whether the macro passes on the word written `w`.
fn passed_on(w: &str) -> bool {
    let (letter, value) = w.split_at(1);
    match letter {
        "X" | "Y" | "Z" | "I" | "J" | "K" | "R" | "F" | "N" => !value.is_empty(),
        "G" => value.parse::<f64>().is_ok_and(|g| MOTION_G.contains(&g)),
        _ => false,
    }
}

/// The first character of `text` and the number written after it.
fn leading(text: &str) -> String {
    let mut chars = text.chars();
    let Some(first) = chars.next() else { return String::new() };
    std::iter::once(first).chain(chars.take_while(|c| c.is_ascii_digit() || matches!(c, '.' | '-' | '+'))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modal_calls_and_subprogram_calls_are_found() {
        let modal_macro_line = |text: &str| Blocks::parse(text).modal_macro_line();
        let call_line = |text: &str| Blocks::parse(text).call_line();
        let foreign_word = |text: &str, first, last| Blocks::parse(text).foreign_word(first, last);
        assert_eq!(modal_macro_line("G01 X1\nG66.1 P7023 X106.\n"), Some(2));
        assert_eq!(modal_macro_line("g0 x1 (G66.1 IN A COMMENT)\n#166=1\nG660\n"), None);
        assert_eq!(modal_macro_line("N10 G066 P9\n"), Some(1));
        assert_eq!(call_line("G01 X1\nM98 P1000\n"), Some(2));
        assert_eq!(call_line("G65 P9 A1\n"), Some(1));
        assert_eq!(call_line("M9\nM980\n"), None);
        let section = "G90\nG01 X1. F300 (CUT)\nG02 X2. R1.\nY5. M08\nX0\n";
        assert_eq!(foreign_word(section, 2, 3), None);
        assert_eq!(foreign_word(section, 2, 5), Some((4, "M08".into())));
        assert_eq!(foreign_word("G04 X1.\n", 1, 1), Some((1, "G04".into())));
        assert_eq!(foreign_word("#1=2\n", 1, 1), Some((1, "#1".into())));
    }
}
