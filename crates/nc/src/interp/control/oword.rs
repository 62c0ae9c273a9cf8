//! LinuxCNC O-words run by the block pointer: subroutine definitions,
//! calls and returns, `if`, `while`, `do` and `repeat`.

use std::collections::HashMap;

use super::{Frame, Interp};
use crate::ast::{ExprId, Flow, OName, Statement};
use crate::interp::block::FrameKind;
use crate::interp::value::Value;
use crate::parse::parse_as;
use crate::source::{Diagnostic, Span};
use crate::Dialect;

/// Deepest nesting of LinuxCNC `o… call`s: rs274ngc runs nine levels
/// below the main program and refuses the tenth ("Too many subroutine
/// levels").
const MAX_OSUB_DEPTH: usize = 9;

impl Interp<'_> {
    /// Runs the LinuxCNC O-word of block `pc`.
    pub(super) fn oword(&mut self, pc: u32, span: Span) -> Result<bool, Diagnostic> {
        let Statement::OWord(o) = &self.program.blocks[pc as usize].statement else { return Ok(true) };
        let (name, flow) = (o.name.clone(), o.flow.clone());
        let located = |r: Result<Value, String>| r.map_err(|m| Diagnostic::error(span, m));
        match flow {
            Flow::Sub { end } => {
                // rs274ngc defines the sub where the run reaches it.
                match self.subs.get(&name) {
                    Some(&at) if at == pc => {
                        return Err(Diagnostic::error(
                            span,
                            format!(
                                "{name} sub is reached a second time (inside a loop, or after a call that found it \
                                 further on): LinuxCNC stops, \"found in illegal location\"; define it before the \
                                 loop or the call"
                            ),
                        ))
                    }
                    Some(&at) => {
                        let line = self.program.blocks[at as usize].line;
                        let file = self.sources.get(self.program.blocks[at as usize].span.file).name.clone();
                        return Err(Diagnostic::error(
                            span,
                            format!("{name} sub is defined a second time ({file} line {line} defines it)"),
                        ));
                    }
                    None => {
                        self.subs.insert(name.clone(), pc);
                    }
                }
                self.frame().pc = self.target(end, span)? + 1;
            }
            Flow::EndSub { value } | Flow::Return { value } => {
                if self.frames.last().map(|f| f.kind) != Some(FrameKind::OSub) {
                    return Err(Diagnostic::error(
                        span,
                        format!("{name} {} is reached without a call", flow.keyword()),
                    ));
                }
                self.st.returned = match value {
                    Some(e) => Some(located(self.st.eval(self.program, e))?.num()),
                    None => None,
                };
                return self.return_from(None, span);
            }
            Flow::Call { args, number } => {
                let name = match number {
                    Some(e) => computed_name(located(self.st.eval(self.program, e))?.num())
                        .map_err(|m| Diagnostic::error(span, m))?,
                    None => name,
                };
                self.o_call(&name, &args, pc, span)?;
            }
            Flow::If { .. } | Flow::While { .. } | Flow::Do { .. } | Flow::Repeat { .. }
                if self.frame().labels.get(&name).is_some_and(|&at| at != pc) =>
            {
                let at = self.frame().labels[&name];
                let block = &self.program.blocks[at as usize];
                let what = match &block.statement {
                    Statement::OWord(o) => o.flow.keyword(),
                    _ => "construct",
                };
                return Err(Diagnostic::error(
                    span,
                    format!(
                        "{name} {} reuses the label of {name} {what} (line {}) in the same subroutine or main program: \
                         LinuxCNC stops, \"duplicate O-word label\"",
                        flow.keyword(),
                        block.line
                    ),
                ));
            }
            Flow::If { cond, next, .. } => {
                self.frame().labels.insert(name.clone(), pc);
                if !located(self.st.eval(self.program, cond))?.truth() {
                    let to = self.branch(next, span)?;
                    self.frame().pc = to;
                }
            }
            Flow::ElseIf { cond, start, .. } => {
                // The end of the branch before: on to the endif. rs274ngc
                // reads the condition all the same (a division by zero
                // there stops it).
                located(self.st.eval(self.program, cond))?;
                self.frame().pc = self.end_of(start, span)? + 1;
            }
            Flow::Else { start } => self.frame().pc = self.end_of(start, span)? + 1,
            Flow::EndIf => {}
            Flow::Do { .. } => {
                self.frame().labels.insert(name.clone(), pc);
            }
            Flow::While { cond, end } => {
                self.frame().labels.insert(name.clone(), pc);
                if !located(self.st.eval(self.program, cond))?.truth() {
                    self.frame().pc = self.target(end, span)? + 1;
                }
            }
            Flow::EndWhile { start } => {
                self.last_back_jump = Some(start);
                self.frame().pc = self.target(start, span)?;
            }
            Flow::DoWhile { cond, start } => {
                if located(self.st.eval(self.program, cond))?.truth() {
                    self.last_back_jump = Some(start);
                    self.frame().pc = self.target(start, span)? + 1;
                }
            }
            Flow::Repeat { count, end } => {
                self.frame().labels.insert(name.clone(), pc);
                let n = located(self.st.eval(self.program, count))?.num().round();
                if n < 1.0 {
                    self.frame().pc = self.target(end, span)? + 1;
                } else {
                    self.frame().repeats.push((pc, n as u64 - 1));
                }
            }
            Flow::EndRepeat { start } => {
                let start = self.target(start, span)?;
                let f = self.frame();
                match f.repeats.last_mut() {
                    Some((s, left)) if *s == start && *left > 0 => {
                        *left -= 1;
                        f.pc = start + 1;
                        self.last_back_jump = Some(start);
                    }
                    Some((s, _)) if *s == start => {
                        f.repeats.pop();
                    }
                    _ => {
                        return Err(Diagnostic::error(span, format!("{name} endrepeat is reached without its repeat")))
                    }
                }
            }
            Flow::Break { start } => {
                let end = self.end_of(start, span)?;
                self.frame().repeats.retain(|&(s, _)| s < start);
                self.frame().pc = end + 1;
            }
            Flow::Continue { start } => {
                let end = self.end_of(start, span)?;
                self.frame().repeats.retain(|&(s, _)| s <= start);
                let to = match self.program.blocks[start as usize].statement {
                    // A while loop tests its condition again; do and repeat
                    // go to their closing block, which tests or counts.
                    Statement::OWord(ref o) if matches!(o.flow, Flow::While { .. }) => start,
                    _ => end,
                };
                self.last_back_jump = Some(start);
                self.frame().pc = to;
            }
        }
        Ok(true)
    }

    /// Checks a block index the parser linked.
    fn target(&self, at: u32, span: Span) -> Result<u32, Diagnostic> {
        if (at as usize) < self.program.blocks.len() {
            Ok(at)
        } else {
            Err(Diagnostic::error(span, "this O-word has no partner in its file"))
        }
    }

    /// The closing block of the O-word construct that block `start` opens.
    fn end_of(&self, start: u32, span: Span) -> Result<u32, Diagnostic> {
        let start = self.target(start, span)?;
        let end = match &self.program.blocks[start as usize].statement {
            Statement::OWord(o) => match o.flow {
                Flow::If { end, .. }
                | Flow::While { end, .. }
                | Flow::Do { end }
                | Flow::Repeat { end, .. }
                | Flow::Sub { end } => end,
                _ => u32::MAX,
            },
            _ => u32::MAX,
        };
        self.target(end, span)
    }

    /// Where an `if` whose condition is false goes on: the first branch
    /// from `next` on (an `elseif` whose condition holds, the `else`) or
    /// after the `endif`.
    fn branch(&mut self, mut next: u32, span: Span) -> Result<u32, Diagnostic> {
        loop {
            next = self.target(next, span)?;
            let block = &self.program.blocks[next as usize];
            let (at, line) = (block.span, block.line);
            match &block.statement {
                Statement::OWord(o) => match o.flow {
                    Flow::ElseIf { cond, next: after, .. } => {
                        self.statements += 1;
                        self.st.at = at;
                        self.st.at_line = line;
                        let holds = self.st.eval(self.program, cond).map_err(|m| Diagnostic::error(at, m))?;
                        if holds.truth() {
                            return Ok(next + 1);
                        }
                        next = after;
                    }
                    _ => return Ok(next + 1),
                },
                _ => return Ok(next + 1),
            }
        }
    }

    /// `o<name> call [a] [b] …`: finds the subroutine and runs it with the
    /// arguments in #1, #2, ….
    fn o_call(&mut self, name: &OName, args: &[ExprId], pc: u32, span: Span) -> Result<(), Diagnostic> {
        let mut locals = [Value::Vacant; 33];
        for (slot, &arg) in locals.iter_mut().zip(args) {
            *slot = Value::Num(self.st.eval(self.program, arg).map_err(|m| Diagnostic::error(span, m))?.num());
        }
        let sub = self.find_sub(name, pc, span)?;
        let depth = self.frames.iter().filter(|f| f.kind == FrameKind::OSub).count();
        if depth >= MAX_OSUB_DEPTH {
            return Err(Diagnostic::error(
                span,
                format!(
                    "subroutine calls nested deeper than {MAX_OSUB_DEPTH}, as LinuxCNC allows \
                     (a subroutine that calls itself without end?)"
                ),
            ));
        }
        let unit = self.program.units.iter().position(|u| u.blocks.contains(&sub)).unwrap_or(0);
        self.st.enter_level(&locals);
        self.st.call_level += 1;
        self.frames.push(Frame {
            unit,
            pc: sub + 1,
            start: sub + 1,
            kind: FrameKind::OSub,
            repeats_left: 0,
            call_span: span,
            args: Some(Box::new(locals)),
            repeats: Vec::new(),
            labels: HashMap::new(),
        });
        Ok(())
    }

    /// The `sub` block of subroutine `name`, called from block `pc`, as
    /// rs274ngc finds it: defined already (its `sub` reached), else further
    /// on in the calling file, else in `<name>.ngc` of the library.
    fn find_sub(&mut self, name: &OName, pc: u32, span: Span) -> Result<u32, Diagnostic> {
        if let Some(&sub) = self.subs.get(name) {
            return Ok(sub);
        }
        let file = self.program.blocks[pc as usize].span.file;
        let first = pc as usize + 1;
        if let Some(sub) = self.sub_in(name, first, |b| b.span.file == file) {
            return Ok(sub);
        }
        let stem = name.file_stem();
        let Some(source) = self.library.load_ngc(&stem) else {
            return Err(Diagnostic::error(
                span,
                format!(
                    "{name} is not defined before the call or after it in this file, and the subroutine library has \
                     no {stem}.ngc"
                ),
            ));
        };
        let file_name = source.name.clone();
        let id = self.sources.add(source);
        let text = self.sources.get(id).text.clone();
        let first = self.program.blocks.len();
        let diagnostics = parse_as(self.program, id, &text, Dialect::LinuxCnc);
        let errors: Vec<_> = diagnostics.iter().filter(|d| d.is_error()).cloned().collect();
        self.st.diagnostics.extend(diagnostics.into_iter().filter(|d| !d.is_error()));
        if let Some(first) = errors.into_iter().next() {
            return Err(first);
        }
        self.sub_in(name, first, |_| true)
            .ok_or_else(|| Diagnostic::error(span, format!("{file_name} does not define {name} sub")))
    }

    /// The first `sub` of `name` among the blocks from `first` on that
    /// `within` keeps (it stops at the first it does not), noted as defined.
    fn sub_in(&mut self, name: &OName, first: usize, within: impl Fn(&crate::ast::Block) -> bool) -> Option<u32> {
        let found = self.program.blocks[first.min(self.program.blocks.len())..]
            .iter()
            .take_while(|b| within(b))
            .position(|b| matches!(&b.statement, Statement::OWord(o) if o.name == *name && matches!(o.flow, Flow::Sub { .. })))
            .map(|k| (first + k) as u32)?;
        self.subs.insert(name.clone(), found);
        Some(found)
    }
}

/// The subroutine a computed O-word number names: a whole number within
/// 0.0001, as rs274ngc reads one ("Non integer value for integer").
fn computed_name(v: f64) -> Result<OName, String> {
    let n = v.round();
    if (v - n).abs() >= 0.0001 {
        return Err(format!(
            "o[{v}]: an O-word number is a whole number (LinuxCNC: \"Non integer value for integer\")"
        ));
    }
    if !(0.0..=f64::from(u32::MAX)).contains(&n) {
        return Err(format!("o[{v}]: no subroutine has this number (LinuxCNC looks for o<{n}> and finds none)"));
    }
    Ok(OName::Number(n as u32))
}
