//! RML-1 text to a toolpath (see the module documentation for the
//! semantics).

use kezuri_geom::{Spindle, Toolpath};

mod commands;

use super::RmlOptions;
use crate::source::{Diagnostic, FileId, Severity, Span};

/// What [`read_rml`] made of a program.
#[derive(Clone, Debug, Default)]
pub struct RmlProgram {
    /// The motions, in mm and mm/min, one per command (plus lifts and
    /// plunges); [`Toolpath::unknown_start`] is set.
    pub toolpath: Toolpath,
    /// Errors (unknown commands, bad numbers, missing heights or feeds) and
    /// warnings (device commands, fractions of a step, …), located.
    pub diagnostics: Vec<Diagnostic>,
    /// The `!` device commands that are not motion (`!RC15`, `!NR`, …), in
    /// order, for a caller to pass on or report.
    pub device: Vec<DeviceCommand>,
    /// Commands read (empty ones not counted).
    pub commands: usize,
}

impl RmlProgram {
    /// Number of error diagnostics.
    pub fn errors(&self) -> usize {
        self.diagnostics.iter().filter(|d| d.is_error()).count()
    }
}

/// A device command the reader does not turn into motion.
#[derive(Clone, Debug, PartialEq)]
pub struct DeviceCommand {
    /// The command as written, without its `;` (`!RC15`).
    pub text: String,
    /// Where.
    pub span: Span,
    /// Its 1-based line.
    pub line: u32,
}

/// `true` when `text` reads as RML-1 rather than G-code: after blanks and
/// `;`, it starts with a `^` or `!` command, with `IN;`, `PA;` or `DF;`, or
/// with a `Z x,y,z` move (a number and a comma after the `Z`).
pub fn looks_like_rml(text: &str) -> bool {
    let t = text.trim_start_matches(|c: char| c.is_ascii_whitespace() || c == ';');
    let upper: String = t.chars().take(16).collect::<String>().to_ascii_uppercase();
    if upper.starts_with('^') || upper.starts_with('!') {
        return true;
    }
    let word: String = upper.chars().take_while(char::is_ascii_alphabetic).collect();
    let rest = upper[word.len()..].trim_start();
    if matches!(word.as_str(), "IN" | "PA" | "DF") && (rest.is_empty() || rest.starts_with(';')) {
        return true;
    }
    if word == "Z" {
        let number: String =
            rest.chars().take_while(|c| c.is_ascii_digit() || matches!(c, '-' | '+' | '.' | ' ')).collect();
        return !number.trim().is_empty() && rest[number.len()..].starts_with(',');
    }
    false
}

/// Reads an RML-1 program. Never fails: what cannot be read is a located
/// diagnostic, and a program with an error diagnostic must not be run or
/// converted.
///
/// ```
/// use kezuri_nc::rml::{read_rml, RmlOptions};
/// let options = RmlOptions { safe_z: Some(5.0), feed: Some(600.0), ..RmlOptions::default() };
/// let read = read_rml(0, "^PA;^PU0,0;Z0,0,-240;Z39,0,-240;", &options);
/// assert!(read.diagnostics.is_empty());
/// let last = read.toolpath.moves.last().unwrap();
/// assert_eq!((last.end.x, last.end.z, last.feed), (0.39, -2.4, 600.0));
/// ```
pub fn read_rml(file: FileId, text: &str, options: &RmlOptions) -> RmlProgram {
    let mut r = Reader::new(file, text, options);
    if let Some((name, value)) = options.invalid() {
        r.report(Diagnostic::error(r.span(0, 0), format!("RML option {name} {value} is out of range")));
    } else {
        r.run();
    }
    r.finish()
}

/// U+3000 in UTF-8.
const IDEOGRAPHIC_SPACE: &[u8] = "\u{3000}".as_bytes();

/// Most diagnostics kept; the rest are counted.
const MAX_DIAGNOSTICS: usize = 100;

/// Two-letter names read without a `^`.
const BARE_TWO: [&str; 8] = ["IN", "DF", "PA", "PR", "PU", "PD", "VS", "PZ"];

#[derive(Clone, Copy, PartialEq, Eq)]
enum Prefix {
    None,
    Caret,
    Bang,
}

#[derive(Clone, Copy)]
struct Number {
    value: f64,
    span: Span,
}

/// One command: its name (upper case), prefix, numbers and span.
struct Command {
    prefix: Prefix,
    name: String,
    numbers: Vec<Number>,
    span: Span,
}

impl Command {
    /// The name as written in messages: `^PU`, `!PZ`, `Z`.
    fn display(&self) -> String {
        let prefix = match self.prefix {
            Prefix::None => "",
            Prefix::Caret => "^",
            Prefix::Bang => "!",
        };
        format!("{prefix}{}", self.name)
    }
}

/// Which feed a cutting move runs at.
#[derive(Clone, Copy)]
enum Speed {
    /// `Z` moves: `V`.
    ThreeD,
    /// XY moves of `^PA`/`^PR`/`^PD`: `^VS`, else `V`.
    Plane,
    /// The plunge of `^PD`: `!VZ`, else `V`.
    Plunge,
}

struct Reader<'a> {
    file: FileId,
    text: &'a str,
    b: &'a [u8],
    i: usize,
    line_starts: Vec<usize>,
    unit: f64,
    safe_z: Option<f64>,
    default_feed: Option<f64>,
    out: RmlProgram,
    suppressed: usize,
    suppressed_errors: usize,
    /// Position in steps; `known[k]` once a move has named axis `k`.
    at: [f64; 3],
    known: [bool; 3],
    absolute: bool,
    tool_down: bool,
    /// Feeds in mm/min.
    v: Option<f64>,
    vs: Option<f64>,
    vz: Option<f64>,
    /// Down height (steps): `!PZ` Z1 or the last `Z` command's Z.
    z_down: Option<f64>,
    /// Up height (steps) from `!PZ` Z2.
    z_up: Option<f64>,
    spindle: Spindle,
    warned: Warned,
}

#[derive(Default)]
struct Warned {
    fraction: bool,
    relative_start: bool,
    no_feed: bool,
    no_up: bool,
    no_down: bool,
    devices: Vec<String>,
}

impl<'a> Reader<'a> {
    fn new(file: FileId, text: &'a str, options: &RmlOptions) -> Reader<'a> {
        let mut line_starts = vec![0];
        line_starts.extend(text.bytes().enumerate().filter(|&(_, b)| b == b'\n').map(|(i, _)| i + 1));
        Reader {
            file,
            text,
            b: text.as_bytes(),
            i: 0,
            line_starts,
            unit: options.unit,
            safe_z: options.safe_z,
            default_feed: options.feed,
            out: RmlProgram {
                toolpath: Toolpath { unknown_start: true, ..Toolpath::default() },
                ..RmlProgram::default()
            },
            suppressed: 0,
            suppressed_errors: 0,
            at: [0.0; 3],
            known: [false; 3],
            absolute: true,
            tool_down: false,
            v: None,
            vs: None,
            vz: None,
            z_down: None,
            z_up: None,
            spindle: Spindle::Off,
            warned: Warned::default(),
        }
    }

    fn span(&self, start: usize, end: usize) -> Span {
        Span::new(self.file, start, end)
    }

    fn line_of(&self, offset: usize) -> u32 {
        self.line_starts.partition_point(|&s| s <= offset) as u32
    }

    fn report(&mut self, d: Diagnostic) {
        if self.out.diagnostics.len() < MAX_DIAGNOSTICS {
            self.out.diagnostics.push(d);
        } else {
            self.suppressed += 1;
            self.suppressed_errors += usize::from(d.is_error());
        }
    }

    fn error(&mut self, span: Span, message: impl Into<String>) {
        self.report(Diagnostic::error(span, message));
    }

    fn warning(&mut self, span: Span, message: impl Into<String>) {
        self.report(Diagnostic::warning(span, message));
    }

    fn finish(mut self) -> RmlProgram {
        if self.suppressed > 0 {
            let end = self.span(self.b.len(), self.b.len());
            let message = format!("{} more diagnostics not shown", self.suppressed);
            let severity = if self.suppressed_errors > 0 { Severity::Error } else { Severity::Warning };
            self.out.diagnostics.push(Diagnostic { severity, ..Diagnostic::warning(end, message) });
        }
        self.out
    }

    // ---- scanning ----

    fn peek(&self) -> Option<u8> {
        self.b.get(self.i).copied()
    }

    /// Skips blanks: ASCII white space and the ideographic space U+3000
    /// that Japanese editors type.
    fn skip_blanks(&mut self) {
        loop {
            match self.peek() {
                Some(b' ' | b'\t' | b'\r' | b'\n' | b'\x0c') => self.i += 1,
                Some(0xE3) if self.b[self.i..].starts_with(IDEOGRAPHIC_SPACE) => self.i += 3,
                _ => return,
            }
        }
    }

    /// Skips to just after the next `;`, or to the next line break, after an
    /// error.
    fn recover(&mut self) {
        while let Some(c) = self.peek() {
            self.i += 1;
            if c == b';' {
                return;
            }
            if c == b'\n' {
                return;
            }
        }
    }

    /// The text of `start..end` for a message, shortened.
    fn snippet(&self, start: usize, end: usize) -> String {
        let s = String::from_utf8_lossy(&self.b[start..end.min(self.b.len())]);
        let s: String = s.split_whitespace().collect::<Vec<_>>().join(" ");
        if s.chars().count() > 40 {
            s.chars().take(40).collect::<String>() + "…"
        } else {
            s
        }
    }

    fn run(&mut self) {
        loop {
            self.skip_blanks();
            while self.peek() == Some(b';') {
                self.i += 1;
                self.skip_blanks();
            }
            if self.i >= self.b.len() {
                break;
            }
            if let Some(command) = self.command() {
                self.out.commands += 1;
                self.execute(&command);
            }
        }
    }

    /// Reads one command, or reports why it cannot and skips it.
    fn command(&mut self) -> Option<Command> {
        let start = self.i;
        let prefix = match self.peek() {
            Some(b'^') => Prefix::Caret,
            Some(b'!') => Prefix::Bang,
            _ => Prefix::None,
        };
        if prefix != Prefix::None {
            self.i += 1;
            self.skip_blanks();
        }
        let letters = self.b[self.i..].iter().take_while(|c| c.is_ascii_alphabetic()).count();
        let take = match prefix {
            _ if letters == 0 => 0,
            Prefix::None => {
                let two = self.text.get(self.i..self.i + 2).map(str::to_ascii_uppercase);
                if letters >= 2 && two.as_deref().is_some_and(|t| BARE_TWO.contains(&t)) {
                    2
                } else {
                    1
                }
            }
            _ if letters >= 2 => 2,
            _ => 0,
        };
        if take == 0 && prefix == Prefix::Bang && self.peek().is_some_and(|c| c.is_ascii_digit()) {
            // The relief paper's converter ends the data at `!0`.
            let end = self.b[self.i..].iter().position(|c| !c.is_ascii_digit()).map_or(self.b.len(), |p| self.i + p);
            let span = self.span(start, end);
            let rest = self.text[end..].trim_matches(|c: char| c.is_ascii_whitespace() || c == ';');
            let note = if rest.is_empty() { "" } else { "; what follows it is not read" };
            self.warning(
                span,
                format!(
                    "'{}' read as the end of the data, as the original RML-1 converter does{note}",
                    self.snippet(start, end)
                ),
            );
            self.i = self.b.len();
            return None;
        }
        if take == 0 {
            let end =
                self.b[self.i..].iter().position(|&c| c == b';' || c == b'\n').map_or(self.b.len(), |p| self.i + p);
            let what = self.snippet(start, end.max(self.i + 1));
            let message = match prefix {
                Prefix::None => format!("expected an RML-1 command, found '{what}'"),
                _ => format!("expected a two-letter command name in '{what}'"),
            };
            self.error(self.span(start, end.max(start + 1)), message);
            self.recover();
            return None;
        }
        let name = self.text[self.i..self.i + take].to_ascii_uppercase();
        self.i += take;
        let mut numbers = Vec::new();
        let mut expect = false;
        loop {
            self.skip_blanks();
            let at = self.i;
            match self.peek() {
                None | Some(b';') if !expect => {
                    let end = self.i;
                    if self.peek() == Some(b';') {
                        self.i += 1;
                    }
                    return Some(Command { prefix, name, numbers, span: self.span(start, end) });
                }
                Some(c) if !expect && (c.is_ascii_alphabetic() || c == b'^' || c == b'!') => {
                    // The next command follows without a `;`.
                    let end = self.b[..at].iter().rposition(|c| !c.is_ascii_whitespace()).map_or(at, |p| p + 1);
                    return Some(Command { prefix, name, numbers, span: self.span(start, end) });
                }
                Some(b',') if !expect && !numbers.is_empty() => {
                    self.i += 1;
                    expect = true;
                }
                _ => match self.number() {
                    Some(n) => {
                        numbers.push(n);
                        expect = false;
                    }
                    None => {
                        let len = self.b[at..]
                            .iter()
                            .position(|&c| matches!(c, b';' | b',' | b'\n' | b' ' | b'\r' | b'\t'))
                            .unwrap_or(self.b.len() - at);
                        let end = at + len.max(1).min(self.b.len() - at);
                        let found = if at >= self.b.len() {
                            "the end of the file".to_string()
                        } else {
                            format!("'{}'", self.snippet(at, end))
                        };
                        let after = if expect { " after ','" } else { "" };
                        let command = self.snippet(start, at);
                        self.error(
                            self.span(at, end),
                            format!("expected a number{after} in '{command}', found {found}"),
                        );
                        self.recover();
                        return None;
                    }
                },
            }
        }
    }

    /// `[+-] digits [. digits]` (blanks after the sign allowed).
    fn number(&mut self) -> Option<Number> {
        let start = self.i;
        let mut j = start;
        let negative = match self.b.get(j) {
            Some(b'-') => true,
            Some(b'+') => false,
            _ => false,
        };
        if matches!(self.b.get(j), Some(b'-' | b'+')) {
            j += 1;
            while matches!(self.b.get(j), Some(b' ' | b'\t')) {
                j += 1;
            }
        }
        let digits_start = j;
        let digits = |j: &mut usize| {
            let from = *j;
            while self.b.get(*j).is_some_and(u8::is_ascii_digit) {
                *j += 1;
            }
            *j - from
        };
        let mut count = digits(&mut j);
        if self.b.get(j) == Some(&b'.') {
            j += 1;
            count += digits(&mut j);
        }
        if count == 0 {
            return None;
        }
        let magnitude: f64 = self.text[digits_start..j].parse().ok()?;
        self.i = j;
        Some(Number { value: if negative { -magnitude } else { magnitude }, span: self.span(start, j) })
    }
}
