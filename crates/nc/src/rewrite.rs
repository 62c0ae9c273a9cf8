//! Changing the numbers of words in a block's text and nothing else:
//! comments, other words, spacing and the order of the words stay as they
//! were (`kezuri thermal apply --keep-text`).

use crate::number::number;

/// A word of a line: its letter (upper case) and the byte range of its
/// number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Word {
    /// The address letter.
    pub letter: char,
    /// Where its number is in the line.
    pub number: (usize, usize),
}

/// The words of `line` outside comments (`( … )` and from `;` on).
pub fn words(line: &str) -> Vec<Word> {
    let b = line.as_bytes();
    let mut out = Vec::new();
    let (mut k, mut depth) = (0, 0usize);
    while k < b.len() {
        let c = b[k];
        match c {
            b'(' => depth += 1,
            b')' if depth > 0 => depth -= 1,
            b';' if depth == 0 => break,
            c if depth == 0 && c.is_ascii_alphabetic() => {
                let mut j = k + 1;
                while j < b.len() && b[j] == b' ' {
                    j += 1;
                }
                let start = j;
                while j < b.len() && (b[j].is_ascii_digit() || matches!(b[j], b'.' | b'+' | b'-')) {
                    j += 1;
                }
                if j > start {
                    out.push(Word { letter: (c as char).to_ascii_uppercase(), number: (start, j) });
                    k = j;
                    continue;
                }
            }
            _ => {}
        }
        k += 1;
    }
    out
}

/// `line` with the words `values` (letter, value) set: an existing word's
/// number replaced where it stands, a missing word appended after the last
/// word (before a comment), a space before it.
pub fn set_words(line: &str, values: &[(char, f64)], digits: usize) -> String {
    let found = words(line);
    let mut out = line.to_string();
    // From the right, so earlier ranges stay valid.
    let mut edits: Vec<(usize, usize, String)> = Vec::new();
    let mut missing = String::new();
    for &(letter, v) in values {
        match found.iter().find(|w| w.letter == letter) {
            Some(w) => edits.push((w.number.0, w.number.1, number(v, digits))),
            None => missing += &format!(" {letter}{}", number(v, digits)),
        }
    }
    let end = found.last().map_or(0, |w| w.number.1);
    if !missing.is_empty() {
        edits.push((end, end, missing));
    }
    edits.sort_by_key(|e| std::cmp::Reverse(e.0));
    for (from, to, text) in edits {
        out.replace_range(from..to, &text);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_are_changed_where_they_stand() {
        assert_eq!(
            set_words("G01 X10. Z-5. F300 (CUT)", &[('X', 10.0012), ('Y', -0.05), ('Z', -5.0)], 4),
            "G01 X10.0012 Z-5. F300 Y-0.05 (CUT)"
        );
        assert_eq!(set_words("Z-78.", &[('X', -2.0123), ('Z', -78.0125)], 4), "Z-78.0125 X-2.0123");
        assert_eq!(
            set_words("G02 X-8. Y9. I-4. J0. (ARC X1)", &[('I', -3.9999)], 4),
            "G02 X-8. Y9. I-3.9999 J0. (ARC X1)"
        );
        assert_eq!(words("G1X 1.5(Y2)Z3;X9").iter().map(|w| w.letter).collect::<String>(), "GXZ");
        assert_eq!(number(-0.00001, 4), "0.");
        assert_eq!(number(2.0, 4), "2.");
    }
}
