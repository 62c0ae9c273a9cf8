//! Text to program model: a hand-written, byte-level parser.
//!
//! One pass over the bytes, one block per line. Spaces are allowed anywhere
//! between words and inside expressions; letters may be lower case; comments
//! are `( … )` and `;` to the end of the line. The parser evaluates nothing
//! and never fails: a block it cannot read becomes an error diagnostic and an
//! empty block, and parsing goes on with the next line.

use crate::ast::{
    BinOp, Block, CommentCommand, Expr, ExprId, Flow, Func, Line, OName, OWord, PrintItem, Program, ProgramUnit,
    Statement, Word, WordValue, UNLINKED,
};
use crate::source::{Diagnostic, FileId, Span};
use crate::Dialect;

/// Deepest bracket nesting accepted (Fanuc allows five).
const MAX_DEPTH: u32 = 64;

/// Most operators in one block's expressions. Evaluation recurses along a
/// chain like `1+1+…+1`, so an unbounded chain would exhaust the stack.
const MAX_OPERATORS: u32 = 1000;

/// LinuxCNC O-word keywords (`o100 sub`, `o101 if [...]`), longer ones
/// before their prefixes.
const OWORD_KEYWORDS: [&str; 15] = [
    "ENDSUB",
    "ENDIF",
    "ENDWHILE",
    "ENDREPEAT",
    "ELSEIF",
    "ELSE",
    "SUB",
    "CALL",
    "RETURN",
    "IF",
    "WHILE",
    "DO",
    "REPEAT",
    "BREAK",
    "CONTINUE",
];

/// Most arguments of a LinuxCNC `call` (#1–#30).
pub(crate) const MAX_OWORD_ARGS: usize = 30;

/// Parses `text` (file `file` of the run) as a Fanuc program and appends its
/// program units to `program`: [`parse_as`] with [`Dialect::Fanuc`].
pub fn parse(program: &mut Program, file: FileId, text: &str) -> Vec<Diagnostic> {
    parse_as(program, file, text, Dialect::Fanuc)
}

/// Parses `text` (file `file` of the run) in `dialect` and appends its
/// program units to `program`. Returns the diagnostics; the program is
/// usable for the blocks that parsed.
pub fn parse_as(program: &mut Program, file: FileId, text: &str, dialect: Dialect) -> Vec<Diagnostic> {
    let mut diagnostics = Vec::new();
    let bytes = text.as_bytes();
    let units_before = program.units.len();
    // Room for the whole file up front (a block per line, a word per 8
    // bytes): growing the arenas step by step copies them. Capacity that is
    // never touched costs no memory.
    program.blocks.reserve(memchr::memchr_iter(b'\n', bytes).count() + 1);
    program.words.reserve(bytes.len() / 8);
    let mut unit = ProgramUnit {
        number: None,
        title: None,
        span: Span::new(file, 0, 0),
        blocks: program.blocks.len() as u32..program.blocks.len() as u32,
    };
    let mut percent_seen = 0;
    // After M30/M02 a unit's lines that are not NC blocks are notes: the
    // first such line and how many there are, for one warning at the end.
    let mut after_end = false;
    let mut notes: Option<(Span, u32)> = None;
    let mut pos = 0;
    let mut line = 0u32;
    // LinuxCNC O-words opened and not closed yet.
    let mut open_owords: Vec<OpenOWord> = Vec::new();
    while pos < bytes.len() {
        line += 1;
        let end = memchr::memchr(b'\n', &bytes[pos..]).map_or(bytes.len(), |i| pos + i);
        let mut p = LineParser { b: bytes, pos, end, file, program, depth: 0, operators: 0, dialect };
        p.skip_blanks();
        if p.pos < end && p.b[p.pos] == b'%' {
            percent_seen += 1;
        } else if percent_seen >= 2 {
            if p.pos < end && !text[p.pos..end].trim().is_empty() {
                diagnostics
                    .push(Diagnostic::warning(Span::new(file, p.pos, end), "text after the closing '%' is ignored"));
                break;
            }
        } else if let Some(header) = p.program_header(&mut diagnostics) {
            finish_unit(program, &mut unit);
            after_end = false;
            unit = ProgramUnit {
                number: Some(header.0),
                title: header.1,
                span: Span::new(file, pos, end),
                blocks: program.blocks.len() as u32..program.blocks.len() as u32,
            };
        } else {
            let words_mark = p.program.words.len();
            let exprs_mark = p.program.exprs.len();
            let block = match p.block(line) {
                Ok(mut block) => {
                    if dialect == Dialect::LinuxCnc && !matches!(block.statement, Statement::OWord(_)) {
                        if let Some(command) = p.comment_command(pos) {
                            block.statement =
                                with_comment(std::mem::replace(&mut block.statement, Statement::Empty), command);
                        }
                    }
                    after_end |= ends_program(program, &block);
                    block
                }
                Err(d) => {
                    program.words.truncate(words_mark);
                    program.exprs.truncate(exprs_mark);
                    let span = Span::new(file, pos, end);
                    let statement = if after_end {
                        // Haas M97 targets live after M30, and so do notes
                        // about the setup: such a line is no error unless
                        // a jump reaches it.
                        notes.get_or_insert((span, 0)).1 += 1;
                        Statement::Unsupported(format!(
                            "this line after M30 was read as a note, not an NC block ({})",
                            d.message
                        ))
                    } else {
                        diagnostics.push(d);
                        Statement::Empty
                    };
                    Block { span, line, number: None, delete: false, statement }
                }
            };
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
    finish_unit(program, &mut unit);
    for o in open_owords {
        let (name, closer) = (&o.name, o.kind.closer());
        let message = format!("{name} {} has no {name} {closer} after it in this file", o.kind.opener());
        refuse_block(program, o.at, message, &mut diagnostics);
    }
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
    if percent_seen == 1 && text.trim_start().starts_with('%') {
        // A tape that opens with '%' ends with one (LinuxCNC refuses a file
        // without it); a missing one means the file was cut short.
        diagnostics.push(Diagnostic::error(at_end, "the file ends before its closing '%': is it complete?"));
    } else if program.units.len() == units_before && !diagnostics.iter().any(Diagnostic::is_error) {
        diagnostics.push(Diagnostic::error(at_end, "the file holds no program: no blocks to run"));
    }
    diagnostics
}

/// `statement` with the comment command of its line: run after the line's
/// settings and before its words, as LinuxCNC runs them.
fn with_comment(statement: Statement, command: CommentCommand) -> Statement {
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

/// Whether `block` ends the program: an `M30` or `M02` word written as a
/// number (`M#1` is not looked at before the run).
fn ends_program(program: &Program, block: &Block) -> bool {
    program.words(block).iter().any(|w| {
        w.letter == b'M' && matches!(w.value(), WordValue::Number { value, .. } if value == 30.0 || value == 2.0)
    })
}

fn finish_unit(program: &mut Program, unit: &mut ProgramUnit) {
    unit.blocks.end = program.blocks.len() as u32;
    let anonymous_and_empty = unit.number.is_none()
        && program.blocks[unit.blocks.start as usize..unit.blocks.end as usize]
            .iter()
            .all(|b| b.statement == Statement::Empty);
    if !anonymous_and_empty {
        program.units.push(unit.clone());
    }
}

/// Replaces block `at` by an error that the run stops on, and reports it.
fn refuse_block(program: &mut Program, at: u32, message: String, diagnostics: &mut Vec<Diagnostic>) {
    let block = &mut program.blocks[at as usize];
    diagnostics.push(Diagnostic::error(block.span, message.clone()));
    block.statement = Statement::Unsupported(message);
}

/// A LinuxCNC O-word that opens a construct, waiting for its partner.
struct OpenOWord {
    name: OName,
    /// Its block.
    at: u32,
    /// Its line, for messages.
    line: u32,
    kind: OpenKind,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum OpenKind {
    Sub,
    /// `if`, with the last of its branches (the `if`, an `elseif` or the
    /// `else`) and whether that is the `else`.
    If {
        last: u32,
        has_else: bool,
    },
    While,
    Do,
    Repeat,
}

impl OpenKind {
    fn opener(self) -> &'static str {
        match self {
            OpenKind::Sub => "sub",
            OpenKind::If { .. } => "if",
            OpenKind::While => "while",
            OpenKind::Do => "do",
            OpenKind::Repeat => "repeat",
        }
    }

    fn closer(self) -> &'static str {
        match self {
            OpenKind::Sub => "endsub",
            OpenKind::If { .. } => "endif",
            OpenKind::While => "endwhile",
            OpenKind::Do => "while",
            OpenKind::Repeat => "endrepeat",
        }
    }

    fn is_loop(self) -> bool {
        matches!(self, OpenKind::While | OpenKind::Do | OpenKind::Repeat)
    }
}

fn oword_mut(program: &mut Program, at: u32) -> Option<&mut OWord> {
    match &mut program.blocks[at as usize].statement {
        Statement::OWord(o) => Some(o),
        _ => None,
    }
}

/// Pops the construct that the closing O-word `closer` of `name` ends,
/// which must be the innermost one open and of the kind `wanted` tells.
fn close_oword(
    open: &mut Vec<OpenOWord>,
    name: &OName,
    closer: &str,
    opener: &str,
    wanted: fn(OpenKind) -> bool,
) -> std::result::Result<OpenOWord, String> {
    match open.last() {
        Some(o) if o.name == *name && wanted(o.kind) => Ok(open.pop().expect("an open O-word")),
        Some(o) if open.iter().any(|x| x.name == *name && wanted(x.kind)) => Err(format!(
            "{name} {closer} comes before the {} that ends {} {} (line {}): O-word constructs must nest",
            o.kind.closer(),
            o.name,
            o.kind.opener(),
            o.line
        )),
        _ => Err(format!("{name} {closer} has no {name} {opener} before it")),
    }
}

/// Links the O-word of block `at` with the constructs open before it:
/// checks that it matches, and fills in the block indices of its partners.
fn link_oword(program: &mut Program, open: &mut Vec<OpenOWord>, at: u32) -> std::result::Result<(), String> {
    let line = program.blocks[at as usize].line;
    let Some(o) = oword_mut(program, at) else { return Ok(()) };
    let name = o.name.clone();
    let mut flow = o.flow.clone();
    let push = |open: &mut Vec<OpenOWord>, kind| open.push(OpenOWord { name: name.clone(), at, line, kind });
    let keyword = flow.keyword();
    let is_else = matches!(flow, Flow::Else { .. });
    match &mut flow {
        Flow::Sub { .. } => {
            // rs274ngc defines a sub inside an if or a loop where the run
            // reaches it, but never inside another sub.
            if let Some(outer) = open.iter().find(|o| o.kind == OpenKind::Sub) {
                return Err(format!(
                    "{name} sub is inside {} sub (line {}): a subroutine is not defined inside another",
                    outer.name, outer.line
                ));
            }
            push(open, OpenKind::Sub);
        }
        Flow::EndSub { .. } => {
            let sub = close_oword(open, &name, "endsub", "sub", |k| k == OpenKind::Sub)?;
            if let Some(OWord { flow: Flow::Sub { end }, .. }) = oword_mut(program, sub.at) {
                *end = at;
            }
        }
        Flow::Return { .. } => {
            if !open.iter().any(|s| s.kind == OpenKind::Sub && s.name == name) {
                return Err(format!("{name} return is not inside {name} sub … {name} endsub"));
            }
        }
        Flow::Call { .. } => {}
        Flow::If { .. } => push(open, OpenKind::If { last: at, has_else: false }),
        Flow::ElseIf { start, .. } | Flow::Else { start } => {
            let top = match open.last_mut() {
                Some(top) if top.name == name && matches!(top.kind, OpenKind::If { .. }) => top,
                _ => {
                    close_oword(open, &name, keyword, "if", |k| matches!(k, OpenKind::If { .. }))?;
                    unreachable!("close_oword fails where the innermost construct is not this if")
                }
            };
            let OpenKind::If { last, has_else } = top.kind else { unreachable!("an if") };
            if has_else {
                return Err(format!("{name} {keyword} comes after {name} else: else is the last branch"));
            }
            *start = top.at;
            top.kind = OpenKind::If { last: at, has_else: is_else };
            set_next(program, last, at);
        }
        Flow::EndIf => {
            let o = close_oword(open, &name, "endif", "if", |k| matches!(k, OpenKind::If { .. }))?;
            let OpenKind::If { last, .. } = o.kind else { unreachable!("an if") };
            set_next(program, last, at);
            if let Some(OWord { flow: Flow::If { end, .. }, .. }) = oword_mut(program, o.at) {
                *end = at;
            }
        }
        Flow::While { cond, .. } => {
            if open.last().is_some_and(|d| d.name == name && d.kind == OpenKind::Do) {
                let d = open.pop().expect("the do");
                flow = Flow::DoWhile { cond: *cond, start: d.at };
                if let Some(OWord { flow: Flow::Do { end }, .. }) = oword_mut(program, d.at) {
                    *end = at;
                }
            } else {
                push(open, OpenKind::While);
            }
        }
        Flow::EndWhile { start } => {
            let w = close_oword(open, &name, "endwhile", "while", |k| k == OpenKind::While)?;
            *start = w.at;
            if let Some(OWord { flow: Flow::While { end, .. }, .. }) = oword_mut(program, w.at) {
                *end = at;
            }
        }
        Flow::Do { .. } => push(open, OpenKind::Do),
        Flow::Repeat { .. } => push(open, OpenKind::Repeat),
        Flow::EndRepeat { start } => {
            let r = close_oword(open, &name, "endrepeat", "repeat", |k| k == OpenKind::Repeat)?;
            *start = r.at;
            if let Some(OWord { flow: Flow::Repeat { end, .. }, .. }) = oword_mut(program, r.at) {
                *end = at;
            }
        }
        Flow::Break { start } | Flow::Continue { start } => {
            let found = open.iter().rev().take_while(|x| x.kind != OpenKind::Sub).find(|x| x.name == name);
            match found {
                Some(l) if l.kind == OpenKind::Repeat => {
                    // rs274ngc (LinuxCNC 2.9) refuses these too: "no matching while/do label".
                    return Err(format!(
                        "{name} {keyword}: LinuxCNC leaves or continues while and do loops only, not {name} repeat \
                         (line {})",
                        l.line
                    ));
                }
                Some(l) if l.kind.is_loop() => *start = l.at,
                Some(l) => {
                    return Err(format!(
                        "{name} {keyword} names {name} {} (line {}), which is not a loop",
                        l.kind.opener(),
                        l.line
                    ))
                }
                None => {
                    return Err(format!("{name} {keyword} is not inside a loop named {name} (while, do or repeat)"))
                }
            }
        }
        Flow::DoWhile { .. } => {}
    }
    if let Some(o) = oword_mut(program, at) {
        o.flow = flow;
    }
    Ok(())
}

/// Points the `if` or `elseif` of block `at` to its next branch `next`.
fn set_next(program: &mut Program, at: u32, next: u32) {
    if let Some(OWord { flow: Flow::If { next: n, .. } | Flow::ElseIf { next: n, .. }, .. }) = oword_mut(program, at) {
        *n = next;
    }
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
            b'$' => Ok(self.unsupported("GRBL '$' system commands are not run by kezuri")),
            b'O' => {
                let word = String::from_utf8_lossy(&self.b[self.pos..self.end]).trim().to_string();
                Ok(self.unsupported(&format!("LinuxCNC O-word '{word}' is not supported yet")))
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

    /// A LinuxCNC O-word: `o100 sub`, `o<name> call [1] [2]`, `o1 if [#1 GT 0]` …
    fn oword(&mut self) -> Result<Statement> {
        let start = self.pos;
        self.pos += 1;
        self.skip_blanks();
        let name = match self.peek() {
            Some(b'<') => {
                let Some(close) = self.b[self.pos..self.end].iter().position(|&c| c == b'>') else {
                    return Err(Diagnostic::error(self.span(start), "O-word name is missing its closing '>'"));
                };
                let name = named(&self.b[self.pos + 1..self.pos + close]);
                self.pos += close + 1;
                if name.is_empty() {
                    return Err(Diagnostic::error(self.span(start), "an O-word name o<…> is empty"));
                }
                OName::Named(name)
            }
            Some(b'#' | b'[') => {
                // rs274ngc computes the number: kezuri does so for a call,
                // whose subroutine is found when it is made.
                let number = self.operand()?;
                self.skip_blanks();
                if !self.eat_keyword("CALL") {
                    return Err(Diagnostic::error(
                        self.span(start),
                        "kezuri reads a computed O-word number (o#1, o[…]) in a call only: write the number here",
                    ));
                }
                self.skip_blanks();
                return Ok(Statement::OWord(Box::new(OWord {
                    name: OName::Number(0),
                    flow: Flow::Call { args: self.call_args()?, number: Some(number) },
                })));
            }
            Some(b'0'..=b'9') => {
                let digits = self.b[self.pos..self.end].iter().take_while(|c| c.is_ascii_digit()).count();
                let text = std::str::from_utf8(&self.b[self.pos..self.pos + digits]).unwrap_or("");
                self.pos += digits;
                OName::Number(
                    text.parse().map_err(|_| Diagnostic::error(self.span(start), "O-word number is too large"))?,
                )
            }
            _ => return Err(self.error_here("an O-word is o<name> or o and a number, then sub, call, if, while …")),
        };
        self.skip_blanks();
        let keyword = OWORD_KEYWORDS
            .iter()
            .find(|k| self.at_keyword(k) && !self.b.get(self.pos + k.len()).is_some_and(|c| c.is_ascii_alphanumeric()));
        let Some(&keyword) = keyword else {
            return Err(self.error_here(format!(
                "expected sub, endsub, call, return, if, elseif, else, endif, while, endwhile, do, repeat, \
                 endrepeat, break or continue after {name}"
            )));
        };
        self.pos += keyword.len();
        self.skip_blanks();
        let flow = match keyword {
            "SUB" => Flow::Sub { end: UNLINKED },
            "ENDSUB" => Flow::EndSub { value: self.optional_bracketed()? },
            "RETURN" => Flow::Return { value: self.optional_bracketed()? },
            "CALL" => Flow::Call { args: self.call_args()?, number: None },
            "IF" => Flow::If { cond: self.condition(keyword)?, next: UNLINKED, end: UNLINKED },
            "ELSEIF" => Flow::ElseIf { cond: self.condition(keyword)?, start: UNLINKED, next: UNLINKED },
            "ELSE" => Flow::Else { start: UNLINKED },
            "ENDIF" => Flow::EndIf,
            "WHILE" => Flow::While { cond: self.condition(keyword)?, end: UNLINKED },
            "ENDWHILE" => Flow::EndWhile { start: UNLINKED },
            "DO" => Flow::Do { end: UNLINKED },
            "REPEAT" => Flow::Repeat { count: self.condition(keyword)?, end: UNLINKED },
            "ENDREPEAT" => Flow::EndRepeat { start: UNLINKED },
            "BREAK" => Flow::Break { start: UNLINKED },
            _ => Flow::Continue { start: UNLINKED },
        };
        Ok(Statement::OWord(Box::new(OWord { name, flow })))
    }

    /// A call's arguments `[a] [b] …`.
    fn call_args(&mut self) -> Result<Vec<ExprId>> {
        let mut args = Vec::new();
        while self.peek() == Some(b'[') {
            if args.len() == MAX_OWORD_ARGS {
                return Err(self.error_here(format!("a call passes at most {MAX_OWORD_ARGS} arguments (#1–#30)")));
            }
            args.push(self.bracketed()?);
            self.skip_blanks();
        }
        Ok(args)
    }

    /// The `[…]` an O-word needs after `keyword`.
    fn condition(&mut self, keyword: &str) -> Result<ExprId> {
        if self.peek() != Some(b'[') {
            return Err(self.error_here(format!("{} needs its expression in brackets: [ … ]", keyword.to_lowercase())));
        }
        self.bracketed()
    }

    fn optional_bracketed(&mut self) -> Result<Option<ExprId>> {
        if self.peek() == Some(b'[') {
            Ok(Some(self.bracketed()?))
        } else {
            Ok(None)
        }
    }

    /// The LinuxCNC comment command of this line: its last comment (before
    /// a `;`), where that is `(debug,…)`, `(print,…)`, `(msg,…)`,
    /// `(logopen,…)`, `(logappend,…)`, `(logclose)` or `(log,…)` — rs274ngc
    /// reads the last comment of a line only.
    fn comment_command(&mut self, from: usize) -> Option<CommentCommand> {
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
        self.pos = plain_words(&self.b[..self.end], self.pos, self.file, &mut self.program.words);
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

    /// The common case of a word's value, `X-12.345`: a sign and a number
    /// written right after the address. Gives what [`Self::word_value`]
    /// gives for it; `None`, with the cursor unmoved, for anything else.
    #[inline]
    fn plain_number(&mut self) -> Option<WordValue> {
        let (value, len) = signed_number(&self.b[self.pos..self.end])?;
        let decimal = matches!(value, WordValue::Number { decimal: true, .. });
        if continues_after_blanks(&self.b[self.pos + len..self.end], decimal) {
            // A number with blanks inside: `word_value` reads it.
            return None;
        }
        self.pos += len;
        Some(value)
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

    /// A number literal: digits with at most one decimal point. Returns the
    /// value and whether a decimal point was written; `None` if no digit.
    fn number(&mut self) -> Result<Option<(f64, bool)>> {
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

    /// `#n`, `#[expr]` or `#<name>`: returns the variable-number expression
    /// (for `#<name>`, a `Named` expression).
    fn variable_number(&mut self) -> Result<ExprId> {
        let start = self.pos;
        self.pos += 1; // '#'
        self.skip_blanks();
        match self.peek() {
            Some(b'0'..=b'9') => {
                let (v, _) = self.number()?.unwrap_or((0.0, false));
                Ok(self.push(Expr::Number(v)))
            }
            Some(b'[') => self.bracketed(),
            Some(b'<') => {
                let close = self.b[self.pos..self.end].iter().position(|&c| c == b'>');
                let Some(close) = close else {
                    return Err(Diagnostic::error(self.span(start), "named parameter is missing its closing '>'"));
                };
                let name = named(&self.b[self.pos + 1..self.pos + close]);
                self.pos += close + 1;
                Ok(self.push(Expr::Named(name)))
            }
            Some(b'#') => Err(self.error_here("write #[#n] for an indirect variable, not ##n")),
            _ => Err(Diagnostic::error(self.span(start), "expected a variable number or '[' after '#'")),
        }
    }

    fn bracketed(&mut self) -> Result<ExprId> {
        self.skip_blanks();
        let open = self.pos;
        if self.peek() != Some(b'[') {
            return Err(self.error_here("expected '['"));
        }
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(self.error_here(format!("brackets nested deeper than {MAX_DEPTH}")));
        }
        self.pos += 1;
        self.skip_blanks();
        let e = self.expr(0)?;
        self.skip_blanks();
        if self.peek() != Some(b']') {
            let mut d = self.error_here("expected ']' to close this '['");
            if self.pos >= self.end {
                d.span = Span::new(self.file, open, open + 1);
                d.message = "'[' is not closed before the end of the line".into();
            }
            return Err(d);
        }
        self.pos += 1;
        self.depth -= 1;
        Ok(e)
    }

    /// An operand of a statement such as `GOTO`: a number, a variable, or a
    /// bracketed expression, with an optional sign.
    fn operand(&mut self) -> Result<ExprId> {
        self.skip_blanks();
        let e = self.unary()?;
        Ok(e)
    }

    fn expr(&mut self, min_prec: u8) -> Result<ExprId> {
        let mut lhs = self.unary()?;
        loop {
            self.skip_blanks();
            let Some((op, len)) = self.binop() else { break };
            let precedence = op.precedence_in(self.dialect);
            if precedence < min_prec.max(1) {
                break;
            }
            self.operators += 1;
            if self.operators > MAX_OPERATORS {
                return Err(self.error_here(format!("more than {MAX_OPERATORS} operators in one block")));
            }
            self.pos += len;
            self.skip_blanks();
            let rhs = self.expr(precedence + 1)?;
            lhs = self.push(Expr::Binary(op, lhs, rhs));
        }
        Ok(lhs)
    }

    fn binop(&self) -> Option<(BinOp, usize)> {
        match self.peek()? {
            b'*' if self.dialect == Dialect::LinuxCnc && self.b.get(self.pos + 1) == Some(&b'*') => {
                Some((BinOp::Pow, 2))
            }
            b'*' => Some((BinOp::Mul, 1)),
            b'/' => Some((BinOp::Div, 1)),
            b'+' => Some((BinOp::Add, 1)),
            b'-' => Some((BinOp::Sub, 1)),
            _ => BinOp::KEYWORDS.iter().find(|(k, _)| self.at_keyword(k)).map(|&(k, op)| (op, k.len())),
        }
    }

    fn unary(&mut self) -> Result<ExprId> {
        self.skip_blanks();
        match self.peek() {
            Some(b'-') => {
                self.pos += 1;
                self.depth += 1;
                if self.depth > MAX_DEPTH {
                    return Err(self.error_here("too many signs in a row"));
                }
                let e = self.unary()?;
                self.depth -= 1;
                Ok(self.push(Expr::Neg(e)))
            }
            Some(b'+') => {
                while self.peek() == Some(b'+') {
                    self.pos += 1;
                    self.skip_blanks();
                }
                self.unary()
            }
            _ => self.primary(),
        }
    }

    fn primary(&mut self) -> Result<ExprId> {
        self.skip_blanks();
        match self.peek() {
            Some(b'0'..=b'9' | b'.') => {
                let (v, _) = self.number()?.ok_or_else(|| self.error_here("expected digits"))?;
                Ok(self.push(Expr::Number(v)))
            }
            Some(b'#') => {
                let n = self.variable_number()?;
                match self.program.exprs[n as usize] {
                    Expr::Named(_) => Ok(n),
                    _ => Ok(self.push(Expr::Var(n))),
                }
            }
            Some(b'[') => self.bracketed(),
            Some(b'E') if self.dialect == Dialect::LinuxCnc && self.at_keyword("EXISTS") => self.exists(),
            Some(b'A'..=b'Z') => {
                let Some(&(name, func)) = Func::ALL.iter().find(|(n, _)| self.at_keyword(n)) else {
                    return Err(self.error_here("expected a number, a variable, '[' or a function"));
                };
                let start = self.pos;
                self.pos += name.len();
                if self.dialect == Dialect::LinuxCnc && matches!(func, Func::Pow | Func::Bin | Func::Bcd) {
                    let hint = if func == Func::Pow { ": write a ** b" } else { "" };
                    return Err(Diagnostic::error(
                        self.span(start),
                        format!("{name} is a Fanuc function, not a LinuxCNC one{hint}"),
                    ));
                }
                self.skip_blanks();
                if self.peek() != Some(b'[') {
                    return Err(Diagnostic::error(
                        self.span(start),
                        format!("{name} needs its argument in brackets: {name}[…]"),
                    ));
                }
                self.pos += 1;
                self.depth += 1;
                if self.depth > MAX_DEPTH {
                    return Err(self.error_here(format!("brackets nested deeper than {MAX_DEPTH}")));
                }
                let a = self.expr(0)?;
                self.skip_blanks();
                let mut b = None;
                if self.peek() == Some(b',') {
                    self.pos += 1;
                    b = Some(self.expr(0)?);
                    self.skip_blanks();
                }
                if self.peek() != Some(b']') {
                    return Err(self.error_here(format!("expected ']' to close {name}[")));
                }
                self.pos += 1;
                self.depth -= 1;
                if func == Func::Atan && b.is_none() {
                    let save = self.pos;
                    self.skip_blanks();
                    if self.peek() == Some(b'/') {
                        self.pos += 1;
                        self.skip_blanks();
                        if self.peek() == Some(b'[') {
                            b = Some(self.bracketed()?);
                        } else {
                            self.pos = save;
                        }
                    } else {
                        self.pos = save;
                    }
                }
                match (func, b) {
                    (Func::Pow, None) => {
                        Err(Diagnostic::error(self.span(start), "POW needs two arguments: POW[base, exponent]"))
                    }
                    (Func::Atan | Func::Pow, _) | (_, None) => Ok(self.push(Expr::Call(func, a, b))),
                    _ => Err(Diagnostic::error(self.span(start), format!("{name} takes one argument"))),
                }
            }
            Some(_) => Err(self.error_here(format!("expected a value, found '{}'", self.char_here()))),
            None => Err(self.error_here("expected a value at the end of the line")),
        }
    }
}

impl LineParser<'_> {
    /// `EXISTS[#<name>]`.
    fn exists(&mut self) -> Result<ExprId> {
        let start = self.pos;
        self.pos += "EXISTS".len();
        self.skip_blanks();
        let wrong = |p: &Self| Diagnostic::error(p.span(start), "EXISTS takes a named parameter: EXISTS[#<name>]");
        if self.peek() != Some(b'[') {
            return Err(wrong(self));
        }
        self.pos += 1;
        self.skip_blanks();
        if self.peek() != Some(b'#') {
            return Err(wrong(self));
        }
        let var = self.variable_number()?;
        let Expr::Named(name) = self.program.exprs[var as usize].clone() else { return Err(wrong(self)) };
        self.skip_blanks();
        if self.peek() != Some(b']') {
            return Err(self.error_here("expected ']' to close EXISTS["));
        }
        self.pos += 1;
        Ok(self.push(Expr::Exists(name)))
    }
}

/// The fast path of [`LineParser::words`]: reads the words of `line` from
/// `pos` on for as long as each is an address letter with a plain number
/// right after it (`X-12.345`) and only spaces come between them; pushes them
/// as the general loop would, and returns the position after the last one
/// (`pos` if none), where the general loop goes on.
/// Not inlined: on its own the loop keeps its state in registers.
#[inline(never)]
fn plain_words(line: &[u8], pos: usize, file: FileId, words: &mut Vec<Word>) -> usize {
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
