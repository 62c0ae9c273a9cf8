//! Text to program model: a hand-written, byte-level parser.
//!
//! One pass over the bytes, one block per line. Spaces are allowed anywhere
//! between words and inside expressions; letters may be lower case; comments
//! are `( … )` and `;` to the end of the line. The parser evaluates nothing
//! and never fails: a block it cannot read becomes an error diagnostic and an
//! empty block, and parsing goes on with the next line.

mod comment;
mod ends;
mod expr;
mod lines;
mod number;
mod oword;

pub use comment::{comments, comments_forgetting, Comments};
use ends::{finish_unit, program_ends};
pub(crate) use lines::read_page_again;
use number::plain_words;
use oword::{link_oword, OpenOWord, OWORD_KEYWORDS};

use crate::ast::{Block, Expr, ExprId, Func, Line, PrintItem, Program, ProgramUnit, Statement, Word, WordValue};
use crate::source::{Diagnostic, FileId, Span};
use crate::Dialect;
use std::sync::atomic::{AtomicU64, Ordering};

/// Parses `text` (file `file` of the run) as a Fanuc program and appends its
/// program units to `program`: [`parse_as`] with [`Dialect::Fanuc`].
pub fn parse(program: &mut Program, file: FileId, text: &str) -> Vec<Diagnostic> {
    parse_as(program, file, text, Dialect::Fanuc)
}

/// Parses `text` (file `file` of the run) in `dialect` and appends its
/// program units to `program`. Returns the diagnostics; the program is
/// usable for the blocks that parsed.
pub fn parse_as(program: &mut Program, file: FileId, text: &str, dialect: Dialect) -> Vec<Diagnostic> {
    parse_reporting(program, file, text, dialect, None)
}

/// [`parse_as`], storing in `done` how many bytes of `text` it has read:
/// every 64 KiB, and the whole length at the end (for a progress bar
/// another thread draws).
pub fn parse_counting(
    program: &mut Program,
    file: FileId,
    text: &str,
    dialect: Dialect,
    done: &AtomicU64,
) -> Vec<Diagnostic> {
    parse_reporting(program, file, text, dialect, Some(done))
}

/// Bytes read between two stores of the count of bytes read.
const REPORT_EVERY: usize = 1 << 16;

fn parse_reporting(
    program: &mut Program,
    file: FileId,
    text: &str,
    dialect: Dialect,
    done: Option<&AtomicU64>,
) -> Vec<Diagnostic> {
    let mut diagnostics = Vec::new();
    // The next offset at which `done` is told (one comparison a line).
    let mut next_report = if done.is_some() { 0 } else { usize::MAX };
    let bytes = text.as_bytes();
    let units_before = program.units.len();
    // Room for the whole file up front (a block per line, a word per 8
    // bytes): growing the arenas step by step copies them. Capacity that is
    // never touched costs no memory. Read in pages: a page at a time.
    let paging = program.paging();
    program.page_begin(file, 0, 0, dialect);
    let page_lines = program.pages.lines;
    if paging {
        program.blocks.reserve(page_lines);
        program.words.reserve(page_lines * 4);
    } else {
        program.blocks.reserve(memchr::memchr_iter(b'\n', bytes).count() + 1);
        program.words.reserve(bytes.len() / 8);
    }
    let mut page_start = program.blocks.len();
    let mut unit = ProgramUnit {
        number: None,
        title: None,
        span: Span::new(file, 0, 0),
        blocks: program.blocks.len() as u32..program.blocks.len() as u32,
        closed_by_percent: false,
    };
    let mut percent_seen = 0;
    // Whether a block that is not blank was read (before a '%', the tape's
    // leader may only have blank lines), the unit's blocks are all empty,
    // and the file's first program end (M02, M30, M99) and its line.
    let mut content = false;
    let mut unit_empty = true;
    let mut first_end: Option<(u32, u32)> = None;
    // After M30/M02 a unit's lines that are not NC blocks are notes: the
    // first such line and how many there are, for one warning at the end.
    let mut after_end = false;
    let mut notes: Option<(Span, u32)> = None;
    let mut pos = 0;
    let mut line = 0u32;
    // LinuxCNC O-words opened and not closed yet.
    let mut open_owords: Vec<OpenOWord> = Vec::new();
    while pos < bytes.len() {
        if pos >= next_report {
            done.inspect(|d| d.store(pos as u64, Ordering::Relaxed));
            next_report = pos + REPORT_EVERY;
        }
        if paging && program.blocks.len() - page_start >= page_lines {
            program.page_begin(file, pos, line, dialect);
            page_start = program.blocks.len();
        }
        line += 1;
        let end = memchr::memchr(b'\n', &bytes[pos..]).map_or(bytes.len(), |i| pos + i);
        let mut p = LineParser { b: bytes, pos, end, file, program, depth: 0, operators: 0, dialect };
        p.skip_blanks();
        if p.pos < end && p.b[p.pos] == b'%' {
            let at = Span::new(file, p.pos, p.pos + 1);
            program.pin_page();
            // Blank lines before the tape's leader are not a program.
            if percent_seen == 0 && content && !after_end {
                // Not the tape's leader: the file did not open with '%'.
                diagnostics.push(Diagnostic::error(
                    at,
                    "a '%' in the middle of the program, which did not open with one: a control stops reading \
                     here (LinuxCNC refuses it); remove it, or begin the file with '%'",
                ));
                break;
            }
            percent_seen += 1;
            if percent_seen == 2 {
                unit.closed_by_percent = true;
                let after = text[(end + 1).min(text.len())..].lines().filter(|l| !l.trim().is_empty()).count();
                if after > 0 {
                    let lines =
                        if after == 1 { "line after it is".to_string() } else { format!("{after} lines after it are") };
                    diagnostics.push(Diagnostic::warning(at, format!("this '%' ends the tape: the {lines} not read")));
                }
                break;
            }
        } else if let Some(header) = p.program_header(&mut diagnostics) {
            program.pin_page();
            finish_unit(program, &mut unit, unit_empty);
            unit_empty = true;
            after_end = false;
            unit = ProgramUnit {
                number: Some(header.0),
                title: header.1,
                span: Span::new(file, pos, end),
                blocks: program.blocks.len() as u32..program.blocks.len() as u32,
                closed_by_percent: false,
            };
        } else {
            let block = p.read_block(line, pos, after_end, &mut notes, &mut diagnostics);
            let (ends, end) = program_ends(program, &block);
            after_end |= ends;
            if percent_seen == 1 && first_end.is_none() {
                first_end = end.map(|m| (m, block.line));
            }
            content |= block.number.is_some()
                || !matches!(block.statement, Statement::Empty | Statement::Words { len: 0, .. });
            unit_empty &= block.statement == Statement::Empty;
            if unit.blocks.is_empty() && unit.number.is_none() {
                unit.span = block.span;
            }
            let linked = matches!(block.statement, Statement::OWord(_));
            program.blocks.push(block);
            if linked {
                let at = program.blocks.len() as u32 - 1;
                if let Err(message) = link_oword(program, &mut open_owords, at) {
                    refuse_block(program, at, message, &mut diagnostics);
                }
            }
        }
        pos = end + 1;
    }
    finish_unit(program, &mut unit, unit_empty);
    program.page_end(bytes.len());
    oword::refuse_unclosed(program, open_owords, &mut diagnostics);
    if let Some((span, lines)) = notes {
        let more = match lines {
            1 => String::new(),
            2 => " (and 1 more line like it)".to_string(),
            n => format!(" (and {} more lines like it)", n - 1),
        };
        diagnostics
            .push(Diagnostic::warning(span, format!("text after M30/M02 that is not an NC block is ignored{more}")));
    }
    let at_end = Span::new(file, bytes.len(), bytes.len());
    // A '%' inside a line was refused where it stands: not again at the end.
    let stray_percent = diagnostics.iter().any(|d| d.is_error() && d.message.contains("'%'"));
    if percent_seen == 1 && text.trim_start().starts_with('%') && !stray_percent {
        // A tape that opens with '%' ends with one. LinuxCNC refuses a file
        // without it. A Fanuc or Haas control reading a program into memory
        // takes its program end (M02, M30 or M99) as the end of the program
        // (FANUC parameter No. 3201 #6 NPE at 0, as shipped): with one, the
        // program is whole and only the '%' is missing; without one the file
        // was cut short.
        match first_end {
            Some((m, line)) if dialect.is_fanuc() => diagnostics.push(Diagnostic::warning(
                at_end,
                format!(
                    "the file has no closing '%': a Fanuc or Haas control loads the program up to its end \
                     (M{m:02} on line {line}) all the same; LinuxCNC would refuse it"
                ),
            )),
            _ => diagnostics.push(Diagnostic::error(at_end, "the file ends before its closing '%': is it complete?")),
        }
    } else if program.units.len() == units_before && !diagnostics.iter().any(Diagnostic::is_error) {
        diagnostics.push(Diagnostic::error(at_end, "the file holds no program: no blocks to run"));
    }
    done.inspect(|d| d.store(bytes.len() as u64, Ordering::Relaxed));
    diagnostics
}

/// Replaces block `at` by an error that the run stops on, and reports it.
fn refuse_block(program: &mut Program, at: u32, message: String, diagnostics: &mut Vec<Diagnostic>) {
    let block = &mut program.blocks[at as usize];
    diagnostics.push(Diagnostic::error(block.span, message.clone()));
    block.statement = Statement::Unsupported(message);
}

struct LineParser<'a> {
    b: &'a [u8],
    pos: usize,
    end: usize,
    file: FileId,
    program: &'a mut Program,
    depth: u32,
    /// Binary operators read so far in this block.
    operators: u32,
    /// The language the program is read in.
    dialect: Dialect,
}

type Result<T> = std::result::Result<T, Diagnostic>;

impl LineParser<'_> {
    fn span(&self, start: usize) -> Span {
        Span::new(self.file, start, self.pos.max(start))
    }

    fn error_here(&self, message: impl Into<String>) -> Diagnostic {
        let end = (self.pos + 1).min(self.end).max(self.pos);
        Diagnostic::error(Span::new(self.file, self.pos, end), message)
    }

    fn peek(&self) -> Option<u8> {
        (self.pos < self.end).then(|| self.b[self.pos].to_ascii_uppercase())
    }

    /// Skips spaces, tabs, carriage returns and `( … )` comments. A `;`
    /// ends the block.
    #[inline]
    fn skip_blanks(&mut self) {
        // Fast path: between words there is at most a space or two.
        while self.pos < self.end && self.b[self.pos] == b' ' {
            self.pos += 1;
        }
        if self.pos < self.end && matches!(self.b[self.pos], b'\t' | b'\r' | b'(' | b';') {
            self.skip_blanks_slow();
        }
    }

    #[inline(never)]
    fn skip_blanks_slow(&mut self) {
        while self.pos < self.end {
            match self.b[self.pos] {
                b' ' | b'\t' | b'\r' => self.pos += 1,
                b'(' => match self.b[self.pos..self.end].iter().position(|&c| c == b')') {
                    Some(i) => self.pos += i + 1,
                    None => return,
                },
                b';' => self.pos = self.end,
                _ => return,
            }
        }
    }

    /// Is the keyword (upper case) at the cursor, case-insensitively?
    fn at_keyword(&self, kw: &str) -> bool {
        let k = kw.as_bytes();
        self.pos + k.len() <= self.end && self.b[self.pos..self.pos + k.len()].eq_ignore_ascii_case(k)
    }

    fn eat_keyword(&mut self, kw: &str) -> bool {
        let yes = self.at_keyword(kw);
        if yes {
            self.pos += kw.len();
            self.skip_blanks();
        }
        yes
    }

    fn expect(&mut self, c: u8, what: &str) -> Result<()> {
        self.skip_blanks();
        if self.peek() == Some(c) {
            self.pos += 1;
            self.skip_blanks();
            Ok(())
        } else {
            Err(self.error_here(format!("expected {what}")))
        }
    }

    fn push(&mut self, e: Expr) -> ExprId {
        self.program.push_expr(e)
    }

    /// `O1234 (TITLE)` or `:1234`: returns the number and title.
    fn program_header(&mut self, diagnostics: &mut Vec<Diagnostic>) -> Option<(u32, Option<String>)> {
        let start = self.pos;
        if !matches!(self.peek(), Some(b'O' | b':')) {
            return None;
        }
        self.pos += 1;
        let digits_start = self.pos;
        while self.pos < self.end && self.b[self.pos].is_ascii_digit() {
            self.pos += 1;
        }
        let after_number = self.pos;
        self.skip_blanks();
        // In LinuxCNC a number alone is a program for M98 (2.9 reads them);
        // a number with a word after it is an O-word.
        let words_follow = self.dialect == Dialect::LinuxCnc
            && self.pos < self.end
            && !matches!(self.b[self.pos], b'(' | b';' | b'\r');
        if after_number == digits_start || words_follow || OWORD_KEYWORDS.iter().any(|k| self.at_keyword(k)) {
            self.pos = start;
            return None;
        }
        let text = std::str::from_utf8(&self.b[digits_start..after_number]).unwrap_or("");
        let Ok(number) = text.parse::<u32>() else {
            diagnostics
                .push(Diagnostic::error(Span::new(self.file, start, after_number), "program number is too large"));
            return Some((0, None));
        };
        let line = &self.b[after_number..self.end];
        let title = line
            .iter()
            .position(|&c| c == b'(')
            .and_then(|open| line[open..].iter().position(|&c| c == b')').map(|close| (open, open + close)))
            .map(|(open, close)| String::from_utf8_lossy(&line[open + 1..close]).trim().to_string());
        if self.pos < self.end {
            diagnostics.push(Diagnostic::warning(
                Span::new(self.file, self.pos, self.end),
                "words after a program number are ignored; put them on the next line",
            ));
        }
        Some((number, title))
    }

    fn block(&mut self, line: u32) -> Result<Block> {
        let start = self.pos;
        let mut delete = false;
        if self.peek() == Some(b'/') {
            delete = true;
            self.pos += 1;
            while self.pos < self.end && self.b[self.pos].is_ascii_digit() {
                self.pos += 1;
            }
            self.skip_blanks();
        }
        let mut number = None;
        if self.peek() == Some(b'N') && self.b.get(self.pos + 1).is_some_and(|c| c.is_ascii_digit() || *c == b' ') {
            let n_start = self.pos;
            self.pos += 1;
            self.skip_blanks();
            let (value, decimal) =
                self.number()?.ok_or_else(|| self.error_here("expected a sequence number after N"))?;
            if decimal || value > 99_999_999.0 {
                return Err(Diagnostic::error(
                    self.span(n_start),
                    "a sequence number is a whole number of at most 8 digits",
                ));
            }
            number = Some(value as u32);
            self.skip_blanks();
        }
        let statement = self.statement()?;
        self.skip_blanks();
        if self.pos < self.end {
            if self.b[self.pos] == b'(' {
                return Err(self.error_here("comment is not closed before the end of the line"));
            }
            return Err(self.error_here(format!("unexpected '{}'", self.char_here())));
        }
        let line_end = if self.end > start && self.b[self.end - 1] == b'\r' { self.end - 1 } else { self.end };
        Ok(Block { span: Span::new(self.file, start, line_end), line, number, delete, statement })
    }

    fn statement(&mut self) -> Result<Statement> {
        let Some(c) = self.peek() else { return Ok(Statement::Empty) };
        match c {
            b'#' if self.dialect == Dialect::LinuxCnc => self.words(),
            b'O' if self.dialect == Dialect::LinuxCnc => self.oword(),
            b'#' => {
                let var = self.variable_number()?;
                self.expect(b'=', "'=' after the variable of an assignment")?;
                let value = self.expr(0)?;
                Ok(Statement::Assign { var, value })
            }
            b'$' if self.dialect.is_fanuc() => Ok(self.unsupported(&format!(
                "a '$' line is not an NC block of a {} control: kezuri does not run it",
                if self.dialect.is_haas() { "Haas" } else { "Fanuc" }
            ))),
            b'$' => Ok(self.unsupported("GRBL '$' system commands are not run by kezuri")),
            b'O' => {
                let word = String::from_utf8_lossy(&self.b[self.pos..self.end]).trim().to_string();
                Ok(self
                    .unsupported(&format!("'{word}' is a LinuxCNC O-word: read the program with --dialect linuxcnc")))
            }
            // Most blocks are plain words: skip the keyword tests below when
            // the first letter starts none of them (keep this list in step).
            _ if !matches!(c, b'I' | b'G' | b'W' | b'D' | b'E' | b'P' | b'B') => self.words(),
            b'G' if !self.at_keyword("GOTO") => self.words(),
            _ if self.eat_keyword("IF") => self.if_statement(),
            _ if self.eat_keyword("GOTO") => Ok(Statement::Goto(self.operand()?)),
            _ if self.eat_keyword("WHILE") || self.eat_while_abbreviation() => {
                let cond = self.bracketed()?;
                self.skip_blanks();
                if !self.eat_keyword("DO") {
                    return Err(self.error_here("expected DO after the WHILE condition"));
                }
                Ok(Statement::While { cond, label: self.loop_label()? })
            }
            _ if self.at_keyword("DO")
                && self.b.get(self.pos + 2).is_some_and(|c| c.is_ascii_digit() || *c == b' ') =>
            {
                self.pos += 2;
                self.skip_blanks();
                Ok(Statement::Do { label: self.loop_label()? })
            }
            _ if self.at_keyword("END") && !self.at_keyword("ENDSUB") => {
                self.pos += 3;
                self.skip_blanks();
                Ok(Statement::End { label: self.loop_label()? })
            }
            _ if self.eat_keyword("POPEN") => Ok(Statement::Popen),
            _ if self.eat_keyword("PCLOS") => Ok(Statement::Pclos),
            _ if self.eat_keyword("DPRNT") => self.dprnt(),
            _ if self.at_keyword("BPRNT") => Ok(self.unsupported("BPRNT (binary output) is not supported yet")),
            _ => self.words(),
        }
    }

    /// `WH[`: the short form of `WHILE` that Haas and Fanuc programs use.
    /// Only a `[` (after blanks) makes it one: `W` alone is an axis address.
    fn eat_while_abbreviation(&mut self) -> bool {
        if !self.at_keyword("WH") {
            return false;
        }
        let after = self.b[self.pos + 2..self.end].iter().find(|c| !matches!(c, b' ' | b'\t'));
        if after != Some(&b'[') {
            return false;
        }
        self.pos += 2;
        self.skip_blanks();
        true
    }

    fn unsupported(&mut self, what: &str) -> Statement {
        self.pos = self.end;
        Statement::Unsupported(what.to_string())
    }

    fn loop_label(&mut self) -> Result<u8> {
        let start = self.pos;
        match self.number()? {
            Some((v, false)) if (1.0..=3.0).contains(&v) => Ok(v as u8),
            _ => Err(Diagnostic::error(self.span(start), "a loop number (after DO or END) must be 1, 2 or 3")),
        }
    }

    fn if_statement(&mut self) -> Result<Statement> {
        let cond = self.bracketed()?;
        self.skip_blanks();
        if self.eat_keyword("GOTO") {
            return Ok(Statement::IfGoto { cond, target: self.operand()? });
        }
        if self.eat_keyword("THEN") {
            if self.peek() != Some(b'#') {
                return Err(self.error_here("only an assignment '#n = …' may follow THEN"));
            }
            let var = self.variable_number()?;
            self.expect(b'=', "'=' after the variable of an assignment")?;
            let value = self.expr(0)?;
            return Ok(Statement::IfThen { cond, var, value });
        }
        Err(self.error_here("expected GOTO or THEN after the IF condition"))
    }

    fn dprnt(&mut self) -> Result<Statement> {
        if self.peek() != Some(b'[') {
            return Err(self.error_here("expected '[' after DPRNT"));
        }
        self.pos += 1;
        let mut items = Vec::new();
        let mut text = String::new();
        loop {
            let Some(&c) = self.b.get(self.pos).filter(|_| self.pos < self.end) else {
                return Err(self.error_here("DPRNT is missing its closing ']'"));
            };
            match c {
                b']' => {
                    self.pos += 1;
                    break;
                }
                b'#' => {
                    if !text.is_empty() {
                        items.push(PrintItem::Text(std::mem::take(&mut text)));
                    }
                    let var = self.variable_number()?;
                    let fmt_start = self.pos;
                    let digits = if self.peek() == Some(b'[') {
                        self.pos += 1;
                        let d = self.b[self.pos..self.end].iter().take_while(|c| c.is_ascii_digit()).count();
                        self.pos += d;
                        let ok = self.peek() == Some(b']') && (1..=2).contains(&d);
                        self.pos += 1;
                        if !ok {
                            return Err(Diagnostic::error(
                                self.span(fmt_start),
                                "DPRNT format must be [ab]: a integer and b fraction digits",
                            ));
                        }
                        let f = &self.b[fmt_start + 1..fmt_start + 1 + d];
                        if d == 1 {
                            (f[0] - b'0', 0)
                        } else {
                            (f[0] - b'0', f[1] - b'0')
                        }
                    } else {
                        (8, 3)
                    };
                    items.push(PrintItem::Var { var, int_digits: digits.0, frac_digits: digits.1 });
                }
                _ => {
                    let ch_len = utf8_len(c);
                    text.push_str(&String::from_utf8_lossy(&self.b[self.pos..(self.pos + ch_len).min(self.end)]));
                    self.pos += ch_len;
                }
            }
        }
        if !text.is_empty() {
            items.push(PrintItem::Text(text));
        }
        Ok(Statement::Dprnt(items))
    }

    fn words(&mut self) -> Result<Statement> {
        let start = self.program.words.len() as u32;
        self.pos = plain_words(&self.b[..self.end], self.pos, self.file, self.program.words.writing_mut());
        self.skip_blanks();
        // LinuxCNC parameter settings among the words, each with the number
        // of words before it.
        let mut settings = Vec::new();
        while let Some(c) = self.peek() {
            let word_start = self.pos;
            if c == b'(' {
                return Err(self.error_here("comment is not closed before the end of the line"));
            }
            if c == b'#' && self.dialect == Dialect::LinuxCnc {
                let var = self.variable_number()?;
                self.expect(b'=', "'=' after the parameter of a setting")?;
                let value = self.expr(0)?;
                settings.push((var, value, self.program.words.len() as u32 - start));
                self.skip_blanks();
                continue;
            }
            if c == b'O' && self.dialect == Dialect::LinuxCnc {
                return Err(self.error_here(
                    "an O-word begins its line (LinuxCNC stops with \"Bad character 'o' used\"): put it on a line of \
                     its own",
                ));
            }
            // `,C` and `,R` (Fanuc): the chamfer and the corner radius
            // between this block's move and the next's, kept as the
            // addresses `c` and `r`; `,A` the angle of a straight line
            // (direct drawing dimensions), `a`.
            if c == b',' && self.dialect.is_fanuc() && self.pos + 1 < self.end {
                if let l @ (b'C' | b'R' | b'A') = self.b[self.pos + 1].to_ascii_uppercase() {
                    self.pos += 2;
                    let value = match self.plain_number() {
                        Some(value) => value,
                        None => {
                            self.skip_blanks();
                            self.word_value(l)?
                        }
                    };
                    self.program.words.push(Word::new(l.to_ascii_lowercase(), value, self.span(word_start)));
                    self.skip_blanks();
                    continue;
                }
            }
            let polar = matches!(c, b'@' | b'^');
            if polar && self.dialect != Dialect::LinuxCnc {
                let what = if c == b'@' { "radius" } else { "angle" };
                return Err(self.error_here(format!(
                    "'{}' (a polar {what}) is a LinuxCNC word: give --dialect linuxcnc to read it",
                    c as char
                )));
            }
            if !c.is_ascii_alphabetic() && !polar {
                return Err(self.error_here(format!("expected an address letter, found '{}'", self.char_here())));
            }
            if c == b'O' {
                return Err(self.error_here("a program number 'O' must be on a line of its own"));
            }
            self.pos += 1;
            let value = match self.plain_number() {
                Some(value) => value,
                None => {
                    self.skip_blanks();
                    self.word_value(c)?
                }
            };
            self.program.words.push(Word::new(c, value, self.span(word_start)));
            self.skip_blanks();
        }
        let len = self.program.words.len() as u32 - start;
        Ok(match settings[..] {
            [] => Statement::Words { start, len },
            [(var, value, _)] if len == 0 => Statement::Assign { var, value },
            _ if len == 0 => Statement::Assigns(settings.into_iter().map(|(var, value, _)| (var, value)).collect()),
            _ => Statement::Line(Box::new(Line { settings, start, len, comment: None })),
        })
    }

    /// The character at the cursor, for a message: control characters
    /// (binary garbage) escaped so that they can be seen.
    fn char_here(&self) -> String {
        let c = std::str::from_utf8(&self.b[self.pos..self.end.min(self.pos + 4)])
            .ok()
            .and_then(|s| s.chars().next())
            .or_else(|| String::from_utf8_lossy(&self.b[self.pos..self.end]).chars().next())
            .unwrap_or('?');
        if c.is_control() {
            c.escape_default().to_string()
        } else {
            c.to_string()
        }
    }

    fn word_value(&mut self, letter: u8) -> Result<WordValue> {
        let sign_start = self.pos;
        let mut negative = false;
        if let Some(s @ (b'-' | b'+')) = self.peek() {
            negative = s == b'-';
            self.pos += 1;
            self.skip_blanks();
        }
        match self.peek() {
            Some(b'0'..=b'9' | b'.') => {
                let (value, decimal) = self.number()?.ok_or_else(|| self.error_here("expected digits"))?;
                Ok(WordValue::Number { value: if negative { -value } else { value }, decimal })
            }
            Some(b'#' | b'[') => {
                let e = self.primary()?;
                Ok(WordValue::Expr(if negative { self.push(Expr::Neg(e)) } else { e }))
            }
            Some(b'A'..=b'Z') if Func::ALL.iter().any(|(n, _)| self.at_keyword(n)) => {
                let e = self.primary()?;
                Ok(WordValue::Expr(if negative { self.push(Expr::Neg(e)) } else { e }))
            }
            _ => Err(self.missing_value(letter, sign_start)),
        }
    }

    fn missing_value(&self, letter: u8, at: usize) -> Diagnostic {
        let end = (at + 1).min(self.end).max(at);
        Diagnostic::error(
            Span::new(self.file, at.saturating_sub(1), end),
            format!("address {} has no value", letter as char),
        )
    }
}
/// A LinuxCNC name as rs274ngc reads it: lower case, blanks removed.
fn named(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).chars().filter(|c| !c.is_whitespace()).flat_map(char::to_lowercase).collect()
}

fn utf8_len(first: u8) -> usize {
    match first {
        0xF0..=0xFF => 4,
        0xE0..=0xEF => 3,
        0xC0..=0xDF => 2,
        _ => 1,
    }
}
