//! Comments: those of a program's text ([`comments`]), and LinuxCNC's
//! comment commands, `(debug,…)`, `(msg,…)`, `(log,…)` …, with the
//! statement that runs one with its line.

use super::{named, LineParser};
use crate::ast::{CommentCommand, Expr, Line, PrintItem, Statement};

/// The comments of `text`, each with its line (from 1): the insides of
/// `( … )` (a comment not closed runs to the end of the line) and what
/// follows a `;`.
///
/// ```
/// let text = "G00 X0 (RAPID) ; ball:14\n(DIA 8MM\n";
/// let found: Vec<_> = kezuri_nc::comments(text).collect();
/// assert_eq!(found, [(1, "RAPID"), (1, " ball:14"), (2, "DIA 8MM")]);
/// ```
pub fn comments(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines().enumerate().flat_map(|(n, line)| {
        let mut rest = Some(line);
        std::iter::from_fn(move || {
            let r = rest?;
            let open = r.find(['(', ';'])?;
            if r[open..].starts_with(';') {
                rest = None;
                return Some(&r[open + 1..]);
            }
            let body = &r[open + 1..];
            let close = body.find(')').unwrap_or(body.len());
            rest = Some(&body[(close + 1).min(body.len())..]);
            Some(&body[..close])
        })
        .map(move |c| (n + 1, c))
    })
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
}
