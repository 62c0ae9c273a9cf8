//! LinuxCNC comment commands: `(debug,…)`, `(msg,…)`, `(log,…)` …, and
//! the statement that runs one with its line.

use super::{named, LineParser};
use crate::ast::{CommentCommand, Expr, Line, PrintItem, Statement};

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
