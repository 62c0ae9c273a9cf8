//! LinuxCNC O-words: the statement parser (`o100 sub`, `o<name> call …`)
//! and the matching of each O-word with its partners, stored as block
//! indices.
//!
//! Computed labels (`o#1 if [c]` … `o#1 endif`, `o[#2+1] while`): rs274ngc
//! reads a label when it reads the line, and matches by that name at run
//! time: a construct whose condition fails skips the lines after it up to
//! the next O-word whose label reads the same, whatever is written
//! (`o#1 if` … `o100 endif` pairs where #1 is 100), and a closing word
//! whose label names no open construct stops it ("undefined O-word
//! label"). kezuri keeps pairing at parse time: a computed label pairs by
//! nesting alone — a closing word closes the innermost open construct
//! where either label is computed, as equal written labels do — and the
//! interpreter checks, when it reaches the closing word or skips to it,
//! that both labels read the same number, stopping with a located error
//! where they do not (rs274's message in it). For every program rs274
//! runs whose constructs nest this is rs274's pairing; where a label
//! changes between its opener and its closer (`#1` set in the body),
//! rs274 stops too (`endif`, `endwhile`, `endrepeat`, `break`) or quietly
//! reads another structure (a `do`'s `while` opens a new loop), which
//! kezuri refuses. Two cases cannot wait for the run and are decided
//! here: a `while` closes the innermost open `do` where both labels are
//! written alike (`o#1 do` … `o#1 while`, or the same number), else it
//! opens a loop; a `break` or `continue` of a computed label, or of a
//! written one that names no loop around it where a loop of a computed
//! label is, finds its loop at run time by the label it reads.

use super::{named, refuse_block, LineParser, Result};
use crate::ast::{ExprId, Flow, OName, OWord, Program, Statement, UNLINKED};
use crate::source::Diagnostic;

/// LinuxCNC O-word keywords (`o100 sub`, `o101 if [...]`), longer ones
/// before their prefixes.
pub(super) const OWORD_KEYWORDS: [&str; 15] = [
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

/// Refuses each O-word construct still open at the end of the file.
pub(super) fn refuse_unclosed(program: &mut Program, open_owords: Vec<OpenOWord>, diagnostics: &mut Vec<Diagnostic>) {
    // A while that was to close a do, one of their labels computed and
    // written otherwise (`o#1 do` … `o10 while`), opened a loop: both are
    // left open. The last do before such a while is the one it was for.
    let unclosed_do = |w: &OpenOWord| {
        open_owords
            .iter()
            .rev()
            .find(|d| d.kind == OpenKind::Do && d.at < w.at)
            .filter(|d| w.kind == OpenKind::While && (d.name.is_computed() || w.name.is_computed()))
    };
    let mut hints = std::collections::HashMap::new();
    for w in &open_owords {
        if let Some(d) = unclosed_do(w) {
            hints.insert(
                d.at,
                format!(" (a while closes a do whose label is written alike: {0} do … {0} while)", d.name),
            );
            hints.insert(
                w.at,
                format!(" (to close {0} do (line {1}), write its label alike: {0} while)", d.name, d.line),
            );
        }
    }
    for o in &open_owords {
        let (name, closer) = (&o.name, o.kind.closer());
        let mut message = format!("{name} {} has no {name} {closer} after it in this file", o.kind.opener());
        if let Some(hint) = hints.get(&o.at) {
            message += hint;
        }
        refuse_block(program, o.at, message, diagnostics);
    }
}

/// A LinuxCNC O-word that opens a construct, waiting for its partner.
pub(super) struct OpenOWord {
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
/// which must be the innermost one open and of the kind `wanted` tells,
/// its label the same or one of the two computed.
fn close_oword(
    open: &mut Vec<OpenOWord>,
    name: &OName,
    closer: &str,
    opener: &str,
    wanted: fn(OpenKind) -> bool,
) -> std::result::Result<OpenOWord, String> {
    match open.last() {
        Some(o) if o.name.may_match(name) && wanted(o.kind) => Ok(open.pop().expect("an open O-word")),
        Some(o) if open.iter().any(|x| x.name.may_match(name) && wanted(x.kind)) => Err(format!(
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
pub(super) fn link_oword(program: &mut Program, open: &mut Vec<OpenOWord>, at: u32) -> std::result::Result<(), String> {
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
        // rs274 returns from the subroutine it is in, whatever the label
        // (LinuxCNC's retval.ngc returns with its if's label).
        Flow::Return { .. } => {
            if !open.iter().any(|s| s.kind == OpenKind::Sub) {
                return Err(format!("{name} return is not inside a subroutine (sub … endsub)"));
            }
        }
        Flow::Call { .. } => {}
        Flow::If { .. } => push(open, OpenKind::If { last: at, has_else: false }),
        Flow::ElseIf { start, .. } | Flow::Else { start } => {
            let top = match open.last_mut() {
                Some(top) if top.name.may_match(&name) && matches!(top.kind, OpenKind::If { .. }) => top,
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
        Flow::EndIf { start } => {
            let o = close_oword(open, &name, "endif", "if", |k| matches!(k, OpenKind::If { .. }))?;
            let OpenKind::If { last, .. } = o.kind else { unreachable!("an if") };
            *start = o.at;
            set_next(program, last, at);
            if let Some(OWord { flow: Flow::If { end, .. }, .. }) = oword_mut(program, o.at) {
                *end = at;
            }
        }
        Flow::While { cond, .. } => {
            // Labels written alike: both the same number or name, or both
            // the same expression (`o#1 do` … `o#1 while`).
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
            let around = || open.iter().rev().take_while(|x| x.kind != OpenKind::Sub);
            let found = around().find(|x| x.name == name && !name.is_computed());
            let computed = |x: &&OpenOWord| x.kind.is_loop() && (name.is_computed() || x.name.is_computed());
            match found {
                // The run finds the loop by the label it reads.
                None if around().any(|x| computed(&x)) => {}
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
                None if name.is_computed() => {
                    return Err(format!("{name} {keyword} is not inside a loop (while, do or repeat)"))
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

impl LineParser<'_> {
    /// A LinuxCNC O-word: `o100 sub`, `o<name> call [1] [2]`, `o1 if [#1 GT 0]` …
    pub(super) fn oword(&mut self) -> Result<Statement> {
        let start = self.pos;
        self.pos += 1;
        self.skip_blanks();
        let mut label = None;
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
                // rs274ngc computes the label when it reads the line: so does
                // the interpreter, with this expression.
                let from = self.pos;
                label = Some(self.operand()?);
                let text: String = String::from_utf8_lossy(&self.b[from..self.pos])
                    .chars()
                    .filter(|c| !c.is_whitespace())
                    .flat_map(char::to_lowercase)
                    .collect();
                OName::Computed(text)
            }
            Some(b'0'..=b'9') => {
                let digits = self.b[self.pos..self.end].iter().take_while(|c| c.is_ascii_digit()).count();
                let text = std::str::from_utf8(&self.b[self.pos..self.pos + digits]).unwrap_or("");
                self.pos += digits;
                OName::Number(i64::from(
                    text.parse::<u32>()
                        .map_err(|_| Diagnostic::error(self.span(start), "O-word number is too large"))?,
                ))
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
            "CALL" => Flow::Call { args: self.call_args()? },
            "IF" => Flow::If { cond: self.condition(keyword)?, next: UNLINKED, end: UNLINKED },
            "ELSEIF" => Flow::ElseIf { cond: self.condition(keyword)?, start: UNLINKED, next: UNLINKED },
            "ELSE" => Flow::Else { start: UNLINKED },
            "ENDIF" => Flow::EndIf { start: UNLINKED },
            "WHILE" => Flow::While { cond: self.condition(keyword)?, end: UNLINKED },
            "ENDWHILE" => Flow::EndWhile { start: UNLINKED },
            "DO" => Flow::Do { end: UNLINKED },
            "REPEAT" => Flow::Repeat { count: self.condition(keyword)?, end: UNLINKED },
            "ENDREPEAT" => Flow::EndRepeat { start: UNLINKED },
            "BREAK" => Flow::Break { start: UNLINKED },
            _ => Flow::Continue { start: UNLINKED },
        };
        Ok(Statement::OWord(Box::new(OWord { name, label, flow })))
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
}
