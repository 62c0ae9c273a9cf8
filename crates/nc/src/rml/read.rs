//! RML-1 text to a toolpath (see the module documentation for the
//! semantics).

use kezuri_geom::{Axes, AxisSet, Move, MoveKind, Spindle, Toolpath};

use super::{RmlOptions, MAX_STEPS};
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

    // ---- meaning ----

    fn execute(&mut self, c: &Command) {
        let caret_or_none = matches!(c.prefix, Prefix::None | Prefix::Caret);
        match (c.prefix, c.name.as_str()) {
            (_, "IN") if caret_or_none => {
                if self.count(c, 0, 0) {
                    self.absolute = true;
                    self.tool_down = false;
                }
            }
            (_, "DF") if caret_or_none => {
                if self.count(c, 0, 0) {
                    self.absolute = true;
                }
            }
            (_, "PA" | "PR") if caret_or_none => {
                self.absolute = c.name == "PA";
                if let Some(pairs) = self.pairs(c) {
                    for p in pairs {
                        if self.tool_down {
                            self.plane_move(MoveKind::Feed, p, c);
                        } else {
                            self.lift(c);
                            self.plane_move(MoveKind::Rapid, p, c);
                        }
                    }
                }
            }
            (_, "PU") if caret_or_none => {
                if let Some(pairs) = self.pairs(c) {
                    self.tool_down = false;
                    self.lift(c);
                    for p in pairs {
                        self.plane_move(MoveKind::Rapid, p, c);
                    }
                }
            }
            (_, "PD") if caret_or_none => {
                if let Some(pairs) = self.pairs(c) {
                    self.tool_down = true;
                    self.plunge(c);
                    for p in pairs {
                        self.plane_move(MoveKind::Feed, p, c);
                    }
                }
            }
            (_, "VS") if caret_or_none => {
                if self.count(c, 1, 2) {
                    self.vs = self.speed(c, c.numbers[0]);
                }
            }
            (Prefix::None, "F") => {
                if self.count(c, 1, 1) {
                    self.vs = self.speed(c, c.numbers[0]);
                }
            }
            (Prefix::None, "V") => {
                if self.count(c, 1, 1) {
                    self.v = self.speed(c, c.numbers[0]);
                }
            }
            (Prefix::Bang, "VZ") => {
                if self.count(c, 1, 1) {
                    self.vz = self.speed(c, c.numbers[0]);
                }
            }
            (_, "PZ") => {
                if self.count(c, 1, 2) {
                    let z1 = self.coordinate(c.numbers[0]);
                    let z2 = c.numbers.get(1).and_then(|&n| self.coordinate(n));
                    if let Some(z1) = z1 {
                        self.z_down = Some(z1);
                    }
                    if let Some(z2) = z2 {
                        self.z_up = Some(z2);
                    }
                }
            }
            (Prefix::None, "Z") => {
                if self.count(c, 3, 3) {
                    let v: Vec<Option<f64>> = c.numbers.iter().map(|&n| self.coordinate(n)).collect();
                    if let [Some(x), Some(y), Some(z)] = v[..] {
                        let to = self.target([x, y, z], [true; 3], c);
                        let feed = self.feed(Speed::ThreeD, c);
                        self.push(MoveKind::Feed, to, AxisSet(0b111), feed, c);
                        self.tool_down = true;
                        self.z_down = Some(to[2]);
                    }
                }
            }
            (Prefix::None, "H") => {
                if self.count(c, 0, 0) {
                    self.warning(
                        c.span,
                        "H (home) is not converted: the machine's home is not known here; kept as a lift to the \
                         tool-up height",
                    );
                    self.tool_down = false;
                    self.lift(c);
                }
            }
            (Prefix::Bang, "MC") => {
                if self.count(c, 0, 1) {
                    let on = !c.numbers.first().is_some_and(|n| n.value == 0.0);
                    self.spindle = if on { Spindle::Cw } else { Spindle::Off };
                }
            }
            (Prefix::Bang, name) => {
                let text = self.snippet(c.span.start as usize, c.span.end as usize);
                let line = self.line_of(c.span.start as usize);
                self.out.device.push(DeviceCommand { text: text.clone(), span: c.span, line });
                if !self.warned.devices.iter().any(|n| n == name) {
                    self.warned.devices.push(name.to_string());
                    let what = match name {
                        "RC" => "spindle rate (its scale depends on the model)",
                        "NR" => "pause until the operator continues",
                        "ZM" | "ZE" | "ZO" => "a Z or axis setting",
                        _ => "a device setting",
                    };
                    self.warning(
                        c.span,
                        format!("device command {text} is not converted: {what} (later !{name} commands too)"),
                    );
                }
            }
            _ => {
                let text = self.snippet(c.span.start as usize, c.span.end as usize);
                let hint = if matches!(c.name.as_str(), "G" | "M" | "N" | "O" | "X" | "Y" | "S" | "T") {
                    " (this looks like G-code: a file is either RML-1 or G-code)"
                } else {
                    ""
                };
                self.error(c.span, format!("unknown RML-1 command '{text}'{hint}"));
                // The rest of the line belongs to it.
                if !hint.is_empty() {
                    while let Some(ch) = self.peek() {
                        if ch == b'\n' || ch == b';' {
                            break;
                        }
                        self.i += 1;
                    }
                }
            }
        }
    }

    /// Checks the count of numbers; reports and returns `false` otherwise.
    fn count(&mut self, c: &Command, min: usize, max: usize) -> bool {
        let n = c.numbers.len();
        if (min..=max).contains(&n) {
            return true;
        }
        let name = c.display();
        let want = match (min, max) {
            (0, 0) => "no numbers".to_string(),
            (a, b) if a == b => format!("{a} number{}", if a == 1 { "" } else { "s" }),
            (a, b) => format!("{a} to {b} numbers"),
        };
        self.error(c.span, format!("{name} takes {want}, found {n}"));
        false
    }

    /// The X,Y pairs of a plot command, or `None` after an error.
    fn pairs(&mut self, c: &Command) -> Option<Vec<[f64; 2]>> {
        if c.numbers.len() & 1 != 0 {
            self.error(c.span, format!("{} takes X,Y pairs, found {} numbers", c.display(), c.numbers.len()));
            return None;
        }
        let mut out = Vec::with_capacity(c.numbers.len() / 2);
        for p in c.numbers.chunks(2) {
            out.push([self.coordinate(p[0])?, self.coordinate(p[1])?]);
        }
        Some(out)
    }

    /// A coordinate in steps, checked.
    fn coordinate(&mut self, n: Number) -> Option<f64> {
        if !n.value.is_finite() || n.value.abs() > MAX_STEPS {
            self.error(n.span, format!("{} steps is out of range (at most ±{MAX_STEPS})", n.value));
            return None;
        }
        if n.value.fract() != 0.0 && !self.warned.fraction {
            self.warned.fraction = true;
            self.warning(
                n.span,
                format!(
                    "RML-1 coordinates are whole steps of {} mm: {} is read as a fraction of a step",
                    self.unit, n.value
                ),
            );
        }
        Some(n.value)
    }

    /// A speed in mm/s as mm/min, checked.
    fn speed(&mut self, c: &Command, n: Number) -> Option<f64> {
        if !(n.value.is_finite() && n.value > 0.0) {
            self.error(n.span, format!("{}: the speed must be more than 0 mm/s, found {}", c.display(), n.value));
            return None;
        }
        Some(n.value * 60.0)
    }

    /// The feed for a cutting move, reporting (once) when there is none.
    fn feed(&mut self, speed: Speed, c: &Command) -> f64 {
        let f = match speed {
            Speed::ThreeD => self.v,
            Speed::Plane => self.vs.or(self.v),
            Speed::Plunge => self.vz.or(self.v),
        }
        .or(self.default_feed);
        match f {
            Some(f) => f,
            None => {
                if !self.warned.no_feed {
                    self.warned.no_feed = true;
                    self.error(
                        c.span,
                        "no feed for this cutting move: the program sets no speed before it (V, ^VS or !VZ); give \
                         one (--feed MM/MIN)",
                    );
                }
                0.0
            }
        }
    }

    /// The target of a move in steps: absolute, or relative to the position.
    fn target(&mut self, v: [f64; 3], axes: [bool; 3], c: &Command) -> [f64; 3] {
        let mut to = self.at;
        for k in 0..3 {
            if axes[k] {
                to[k] = if self.absolute { v[k] } else { self.at[k] + v[k] };
            }
        }
        if !self.absolute && (0..3).any(|k| axes[k] && !self.known[k]) && !self.warned.relative_start {
            self.warned.relative_start = true;
            self.warning(c.span, "a relative move before the position is known: it is taken from X0 Y0 Z0");
        }
        to
    }

    fn up_steps(&mut self, c: &Command) -> Option<f64> {
        if let Some(z) = self.safe_z {
            return Some(z / self.unit);
        }
        if self.z_up.is_none() && !self.warned.no_up {
            self.warned.no_up = true;
            self.error(
                c.span,
                "no tool-up height for this move: the program sets none (!PZ z1,z2); give one (--safe-z Z)",
            );
        }
        self.z_up
    }

    /// Raises the tool to the up height, where it is not there.
    fn lift(&mut self, c: &Command) {
        let Some(up) = self.up_steps(c) else { return };
        if !self.known[2] || self.at[2] != up {
            let to = [self.at[0], self.at[1], up];
            self.push(MoveKind::Rapid, to, AxisSet(0b100), 0.0, c);
        }
    }

    /// Lowers the tool to the down height, where it is not there.
    fn plunge(&mut self, c: &Command) {
        let Some(down) = self.z_down else {
            if !self.warned.no_down {
                self.warned.no_down = true;
                self.error(
                    c.span,
                    "no tool-down height for ^PD: the program sets none before it (!PZ z1,z2 or a Z move)",
                );
            }
            return;
        };
        if !self.known[2] || self.at[2] != down {
            let feed = self.feed(Speed::Plunge, c);
            let to = [self.at[0], self.at[1], down];
            self.push(MoveKind::Feed, to, AxisSet(0b100), feed, c);
        }
    }

    /// An XY move of `^PA`/`^PR`/`^PU`/`^PD` at the current Z.
    fn plane_move(&mut self, kind: MoveKind, p: [f64; 2], c: &Command) {
        let to = self.target([p[0], p[1], 0.0], [true, true, false], c);
        let feed = if kind == MoveKind::Rapid { 0.0 } else { self.feed(Speed::Plane, c) };
        self.push(kind, to, AxisSet(0b011), feed, c);
    }

    /// Steps to mm: divided by the whole steps per mm where there are (so
    /// 700 steps of 0.01 mm are 7 mm exactly, 39 the double nearest 0.39),
    /// else times the unit.
    fn mm(&self, steps: f64) -> f64 {
        let per_mm = 1.0 / self.unit;
        if (per_mm - per_mm.round()).abs() < 1e-9 * per_mm {
            steps / per_mm.round()
        } else {
            steps * self.unit
        }
    }

    fn push(&mut self, kind: MoveKind, to: [f64; 3], named: AxisSet, feed: f64, c: &Command) {
        let mm = |v: [f64; 3]| Axes { x: self.mm(v[0]), y: self.mm(v[1]), z: self.mm(v[2]), ..Axes::ZERO };
        let m = Move {
            kind,
            start: mm(self.at),
            end: mm(to),
            feed,
            spindle: self.spindle,
            line: self.line_of(c.span.start as usize),
            named,
            ..Move::default()
        };
        self.out.toolpath.push(m);
        self.at = to;
        for k in 0..3 {
            self.known[k] |= named.contains(k);
        }
    }
}
