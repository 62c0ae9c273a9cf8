//! Comments: those of a program's text ([`comments`]), and LinuxCNC's
//! comment commands, `(debug,…)`, `(msg,…)`, `(log,…)` …, with the
//! statement that runs one with its line.

use std::ops::Range;

use super::{named, LineParser};
use crate::ast::{CommentCommand, Expr, Line, PrintItem, Statement};
use crate::source::FORGET_EVERY;

/// The comments of `text`, each with its line (from 1): the insides of
/// `( … )` (a comment not closed runs to the end of the line) and what
/// follows a `;`.
///
/// ```
/// let text = "G00 X0 (RAPID) ; ball:14\n(DIA 8MM\n";
/// let found: Vec<_> = kezuri_nc::comments(text).collect();
/// assert_eq!(found, [(1, "RAPID"), (1, " ball:14"), (2, "DIA 8MM")]);
/// ```
pub fn comments(text: &str) -> Comments<'_> {
    comments_forgetting(text, &|_| {})
}

/// [`comments`], telling `forget` of the text read through, a few
/// megabytes at a time (to let go of a mapped file's pages as it goes).
pub fn comments_forgetting<'a>(text: &'a str, forget: &'a dyn Fn(Range<usize>)) -> Comments<'a> {
    Comments { text, pos: 0, line: 0, counted: 0, line_end: 0, forget, forgotten: 0 }
}

/// The comments of a text ([`comments`]): the text is searched for `(` and
/// `;` and only the lines holding one are looked at.
#[derive(Clone)]
pub struct Comments<'a> {
    text: &'a str,
    /// Told of the text read through, and how far it has been told.
    forget: &'a dyn Fn(Range<usize>),
    forgotten: usize,
    /// Where the search goes on.
    pos: usize,
    /// Lines before byte `counted`.
    line: usize,
    counted: usize,
    /// Where the line of the last comment ends (without its `\r`).
    line_end: usize,
}

impl<'a> Iterator for Comments<'a> {
    type Item = (usize, &'a str);

    fn next(&mut self) -> Option<(usize, &'a str)> {
        let b = self.text.as_bytes();
        let open = loop {
            if self.pos - self.forgotten >= FORGET_EVERY {
                (self.forget)(self.forgotten..self.pos);
                self.forgotten = self.pos;
            }
            let window = (self.pos + FORGET_EVERY).min(b.len());
            match memchr::memchr2(b'(', b';', &b[self.pos.min(window)..window]) {
                Some(i) => break self.pos + i,
                None if window == b.len() => {
                    (self.forget)(self.forgotten..b.len());
                    self.pos = b.len();
                    self.forgotten = b.len();
                    return None;
                }
                None => self.pos = window,
            }
        };
        if open >= self.line_end {
            // A new line: count the lines before it, find its end.
            let start = memchr::memrchr(b'\n', &b[..open]).map_or(0, |i| i + 1);
            self.line += memchr::memchr_iter(b'\n', &b[self.counted..start]).count();
            self.counted = start;
            let end = memchr::memchr(b'\n', &b[open..]).map_or(b.len(), |i| open + i);
            // As `str::lines` gives a line: without the '\r' of a "\r\n".
            self.line_end = if end < b.len() && b[end - 1] == b'\r' { end - 1 } else { end };
        }
        let (body, line_end) = (open + 1, self.line_end);
        let closed = if b[open] == b'(' { memchr::memchr(b')', &b[body..line_end]) } else { None };
        let close = match closed {
            Some(i) => {
                self.pos = body + i + 1;
                body + i
            }
            // After a ';', or a comment left open, the line is done.
            None => {
                self.pos = memchr::memchr(b'\n', &b[line_end..]).map_or(b.len(), |i| line_end + i + 1);
                line_end
            }
        };
        Some((self.line + 1, &self.text[body..close]))
    }
}

/// `statement` with the comment command of its line: run after the line's
/// settings and before its words, as LinuxCNC runs them.
pub(super) fn with_comment(statement: Statement, command: CommentCommand) -> Statement {
    match statement {
        Statement::Empty => Statement::Comment(command),
        Statement::Words { start, len } => {
            Statement::Line(Box::new(Line { settings: Vec::new(), start, len, comment: Some(command) }))
        }
        Statement::Assign { var, value } => Statement::Line(Box::new(Line {
            settings: vec![(var, value, 0)],
            start: 0,
            len: 0,
            comment: Some(command),
        })),
        Statement::Assigns(list) => Statement::Line(Box::new(Line {
            settings: list.into_iter().map(|(var, value)| (var, value, 0)).collect(),
            start: 0,
            len: 0,
            comment: Some(command),
        })),
        Statement::Line(mut line) => {
            line.comment = Some(command);
            Statement::Line(line)
        }
        // A Fanuc statement read in this dialect (IF, GOTO …): its comment
        // is a comment.
        other => other,
    }
}

impl LineParser<'_> {
    /// The LinuxCNC comment command of this line: its last comment (before
    /// a `;`), where that is `(debug,…)`, `(print,…)`, `(msg,…)`,
    /// `(logopen,…)`, `(logappend,…)`, `(logclose)` or `(log,…)` — rs274ngc
    /// reads the last comment of a line only.
    pub(super) fn comment_command(&mut self, from: usize) -> Option<CommentCommand> {
        let line = &self.b[from..self.end];
        let mut last = None;
        let mut i = 0;
        while i < line.len() {
            match line[i] {
                b';' => break,
                b'(' => {
                    let close = i + line[i..].iter().position(|&c| c == b')')?;
                    last = Some(&line[i + 1..close]);
                    i = close + 1;
                }
                _ => i += 1,
            }
        }
        let inner = last?;
        let skip = inner.iter().take_while(|c| matches!(c, b' ' | b'\t')).count();
        let inner = &inner[skip..];
        let lower = inner.to_ascii_lowercase();
        let after = |k: &[u8]| lower.starts_with(k).then(|| &inner[k.len()..]);
        let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
        if let Some(rest) = after(b"debug,").or_else(|| after(b"print,")) {
            return Some(CommentCommand::Debug(self.print_items(rest)));
        }
        if let Some(rest) = after(b"msg,") {
            return Some(CommentCommand::Msg(text(rest)));
        }
        if let Some(rest) = after(b"logopen,") {
            return Some(CommentCommand::LogOpen { file: text(rest).trim().to_string(), append: false });
        }
        if let Some(rest) = after(b"logappend,") {
            return Some(CommentCommand::LogOpen { file: text(rest).trim().to_string(), append: true });
        }
        if lower.trim_ascii_end() == b"logclose" {
            return Some(CommentCommand::LogClose);
        }
        after(b"log,").map(|rest| CommentCommand::Log(self.print_items(rest)))
    }

    /// The text of a debug or log comment, each `#n` and `#<name>` an item.
    fn print_items(&mut self, rest: &[u8]) -> Vec<PrintItem> {
        let mut items = Vec::new();
        let mut text = Vec::new();
        let mut i = 0;
        while i < rest.len() {
            let var = match (rest[i], rest.get(i + 1)) {
                (b'#', Some(b'<')) => rest[i + 2..].iter().position(|&c| c == b'>').map(|n| {
                    let name = named(&rest[i + 2..i + 2 + n]);
                    (Expr::Named(name), i + 3 + n)
                }),
                (b'#', Some(b'0'..=b'9')) => {
                    let n = rest[i + 1..].iter().take_while(|c| c.is_ascii_digit()).count();
                    let v = std::str::from_utf8(&rest[i + 1..i + 1 + n]).unwrap_or("0").parse::<f64>().unwrap_or(0.0);
                    Some((Expr::Number(v), i + 1 + n))
                }
                _ => None,
            };
            match var {
                Some((e, next)) => {
                    if !text.is_empty() {
                        items.push(PrintItem::Text(String::from_utf8_lossy(&std::mem::take(&mut text)).into_owned()));
                    }
                    let var = self.push(e);
                    items.push(PrintItem::Var { var, int_digits: 0, frac_digits: 6 });
                    i = next;
                }
                None => {
                    text.push(rest[i]);
                    i += 1;
                }
            }
        }
        if !text.is_empty() {
            items.push(PrintItem::Text(String::from_utf8_lossy(&text).into_owned()));
        }
        items
    }
}

#[cfg(test)]
mod tests {
    use super::comments;

    #[test]
    fn comments_with_their_lines() {
        let text = "(T1 D=6. CR=0. - FLAT END MILL)\nG00 X0 ; ball:14 for the relief\n(DIA 8MM)\n(TOOL Ø3 BALL)\n\
                    (ID=5)(DIAMETER: 12.5)\n(HEIGHT 10)\n(φ14)\nG01 X1. (OPEN\n";
        let found: Vec<(usize, &str)> = comments(text).collect();
        let want = [
            (1, "T1 D=6. CR=0. - FLAT END MILL"),
            (2, " ball:14 for the relief"),
            (3, "DIA 8MM"),
            (4, "TOOL Ø3 BALL"),
            (5, "ID=5"),
            (5, "DIAMETER: 12.5"),
            (6, "HEIGHT 10"),
            (7, "φ14"),
            (8, "OPEN"),
        ];
        assert_eq!(found, want);
    }

    /// The comments line by line, as `str::lines` gives the lines: what
    /// [`comments`] must find.
    fn line_by_line(text: &str) -> Vec<(usize, &str)> {
        let mut out = Vec::new();
        for (n, line) in text.lines().enumerate() {
            let mut rest = line;
            while let Some(open) = rest.find(['(', ';']) {
                if rest[open..].starts_with(';') {
                    out.push((n + 1, &rest[open + 1..]));
                    break;
                }
                let body = &rest[open + 1..];
                let close = body.find(')').unwrap_or(body.len());
                out.push((n + 1, &body[..close]));
                rest = &body[(close + 1).min(body.len())..];
            }
        }
        out
    }

    proptest::proptest! {
        #[test]
        fn comments_are_those_of_every_line(
            pieces in proptest::collection::vec(
                proptest::sample::select(vec!["(", ")", ";", "\n", "\r", "\r\n", "G1", " ", "T1 D=6.", "Ø", "()"]),
                0..24,
            )
        ) {
            let text = pieces.concat();
            proptest::prop_assert_eq!(comments(&text).collect::<Vec<_>>(), line_by_line(&text));
        }
    }

    #[test]
    fn a_long_text_is_let_go_of_as_it_is_read_through() {
        let mut text = String::from("(T1 D=6.)\n");
        while text.len() < 2 * crate::source::FORGET_EVERY + 1_000_000 {
            text.push_str("X1.5 Y2.25 Z-0.5\n");
        }
        text.push_str("G0 Z5. ; up\n");
        let told = std::cell::RefCell::new(Vec::new());
        let forget = |r| told.borrow_mut().push(r);
        let found: Vec<(usize, &str)> = super::comments_forgetting(&text, &forget).collect();
        assert_eq!(found, comments(&text).collect::<Vec<_>>());
        assert_eq!(found.len(), 2);
        let told = told.into_inner();
        assert!(told.len() >= 3, "{told:?}");
        assert_eq!((told[0].start, told.last().unwrap().end), (0, text.len()));
        assert!(told.windows(2).all(|w| w[0].end <= w[1].start), "{told:?}");
        assert!(told.iter().all(|r| r.len() <= crate::source::FORGET_EVERY + 64), "{told:?}");
    }
}
