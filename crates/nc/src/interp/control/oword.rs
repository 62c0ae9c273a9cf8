//! LinuxCNC O-words run by the block pointer: subroutine definitions,
//! calls and returns, `if`, `while`, `do` and `repeat`.

use std::collections::HashMap;

use super::{Frame, Interp};
use crate::ast::{ExprId, Flow, OName, Statement, UNLINKED};
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
    ///
    /// A computed label (`o#1 if`) is read here, as rs274ngc reads it when
    /// it reads the line; the parser paired it by nesting, and each
    /// closing word reached or skipped to is checked against its opener
    /// (`check_partner`), the labels of skipped blocks read on the way
    /// (`read_skipped`): see `parse::oword`.
    pub(super) fn oword(&mut self, pc: u32, span: Span) -> Result<bool, Diagnostic> {
        let Statement::OWord(o) = &self.program.blocks[pc as usize].statement else { return Ok(true) };
        let (written, flow) = (o.name.clone(), o.flow.clone());
        let name = self.label_of(pc)?;
        if written.is_computed()
            && matches!(
                flow,
                Flow::Sub { .. } | Flow::If { .. } | Flow::While { .. } | Flow::Do { .. } | Flow::Repeat { .. }
            )
        {
            self.frame().read_labels.insert(pc, name.clone());
        }
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
                let end = self.target(end, span)?;
                self.skip_to_end(pc, pc, end)?;
                self.frame().pc = end + 1;
            }
            // rs274ngc reads the label of an endsub or return and returns
            // whatever it reads (as whatever is written).
            Flow::EndSub { value } | Flow::Return { value } => {
                if self.frames.last().map(|f| f.kind) != Some(FrameKind::OSub) {
                    return Err(Diagnostic::error(
                        span,
                        format!("{written} {} is reached without a call", flow.keyword()),
                    ));
                }
                self.st.returned = match value {
                    Some(e) => Some(located(self.st.eval(self.program, e))?.num()),
                    None => None,
                };
                return self.return_from(None, span);
            }
            Flow::Call { args } => {
                if let OName::Number(n) = name {
                    if u32::try_from(n).is_err() {
                        return Err(Diagnostic::error(
                            span,
                            format!("{written} reads {name}: no subroutine has this number (LinuxCNC looks for o<{n}> and finds none)"),
                        ));
                    }
                }
                self.o_call(&name, &args, pc, span)?;
            }
            Flow::If { .. } | Flow::While { .. } | Flow::Do { .. } | Flow::Repeat { .. }
                if self.frame().labels.get(&name).is_some_and(|&at| at != pc) =>
            {
                let at = self.frame().labels[&name];
                let block = &self.program.blocks[at as usize];
                let what = match &block.statement {
                    Statement::OWord(o) if o.name != name => {
                        format!("{} {} (read as {name})", o.name, o.flow.keyword())
                    }
                    Statement::OWord(o) => format!("{name} {}", o.flow.keyword()),
                    _ => "construct".to_string(),
                };
                let this = if written.is_computed() {
                    format!("{written} {} (read as {name})", flow.keyword())
                } else {
                    format!("{name} {}", flow.keyword())
                };
                return Err(Diagnostic::error(
                    span,
                    format!(
                        "{this} reuses the label of {what} (line {}) in the same subroutine or main program: \
                         LinuxCNC stops, \"duplicate O-word label\"",
                        block.line
                    ),
                ));
            }
            Flow::If { cond, next, .. } => {
                self.frame().labels.insert(name.clone(), pc);
                if !located(self.st.eval(self.program, cond))?.truth() {
                    let to = self.branch(pc, next, span)?;
                    self.read_skipped(pc + 1, to)?;
                    self.frame().pc = to;
                }
            }
            Flow::ElseIf { cond, start, .. } => {
                // The end of the branch before: on to the endif. rs274ngc
                // reads the condition all the same (a division by zero
                // there stops it).
                located(self.st.eval(self.program, cond))?;
                self.check_partner(start, pc, false)?;
                let end = self.end_of(start, span)?;
                self.skip_to_end(pc, start, end)?;
                self.frame().pc = end + 1;
            }
            Flow::Else { start } => {
                self.check_partner(start, pc, false)?;
                let end = self.end_of(start, span)?;
                self.skip_to_end(pc, start, end)?;
                self.frame().pc = end + 1;
            }
            Flow::EndIf { start } => self.check_partner(start, pc, false)?,
            Flow::Do { .. } => {
                self.frame().labels.insert(name.clone(), pc);
            }
            Flow::While { cond, end } => {
                self.frame().labels.insert(name.clone(), pc);
                if !located(self.st.eval(self.program, cond))?.truth() {
                    let end = self.target(end, span)?;
                    self.skip_to_end(pc, pc, end)?;
                    self.frame().pc = end + 1;
                }
            }
            Flow::EndWhile { start } => {
                self.check_partner(start, pc, false)?;
                self.last_back_jump = Some(start);
                self.frame().pc = self.target(start, span)?;
            }
            Flow::DoWhile { cond, start } => {
                self.check_partner(start, pc, false)?;
                if located(self.st.eval(self.program, cond))?.truth() {
                    self.last_back_jump = Some(start);
                    self.frame().pc = self.target(start, span)? + 1;
                }
            }
            Flow::Repeat { count, end } => {
                self.frame().labels.insert(name.clone(), pc);
                let n = located(self.st.eval(self.program, count))?.num().round();
                if n < 1.0 {
                    let end = self.target(end, span)?;
                    self.skip_to_end(pc, pc, end)?;
                    self.frame().pc = end + 1;
                } else {
                    self.frame().repeats.push((pc, n as u64 - 1));
                }
            }
            Flow::EndRepeat { start } => {
                self.check_partner(start, pc, false)?;
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
                        return Err(Diagnostic::error(
                            span,
                            format!("{written} endrepeat is reached without its repeat"),
                        ))
                    }
                }
            }
            Flow::Break { start } => {
                let start = if start == UNLINKED { self.find_loop(pc, &name, span)? } else { start };
                let end = self.end_of(start, span)?;
                self.skip_to_end(pc, start, end)?;
                self.frame().repeats.retain(|&(s, _)| s < start);
                self.frame().pc = end + 1;
            }
            Flow::Continue { start } => {
                let start = if start == UNLINKED { self.find_loop(pc, &name, span)? } else { start };
                let end = self.end_of(start, span)?;
                self.frame().repeats.retain(|&(s, _)| s <= start);
                let to = match self.program.blocks[start as usize].statement {
                    // A while loop tests its condition again, once rs274
                    // has skipped to its endwhile; do and repeat go to
                    // their closing block, which tests or counts.
                    Statement::OWord(ref o) if matches!(o.flow, Flow::While { .. }) => {
                        self.skip_to_end(pc, start, end)?;
                        start
                    }
                    _ => {
                        self.read_skipped(pc + 1, end)?;
                        end
                    }
                };
                self.last_back_jump = Some(start);
                self.frame().pc = to;
            }
        }
        Ok(true)
    }

    /// The label of the O-word of block `at` as the run reads it: the one
    /// written, or the number a computed one reads now (a whole number
    /// within 0.0001, as rs274ngc reads one: "Non integer value for
    /// integer").
    fn label_of(&mut self, at: u32) -> Result<OName, Diagnostic> {
        let block = &self.program.blocks[at as usize];
        let Statement::OWord(o) = &block.statement else { return Ok(OName::Number(0)) };
        let Some(e) = o.label else { return Ok(o.name.clone()) };
        let (written, span, line) = (o.name.clone(), block.span, block.line);
        let was = (self.st.at, self.st.at_line);
        (self.st.at, self.st.at_line) = (span, line);
        let v = self.st.eval(self.program, e).map_err(|m| Diagnostic::error(span, m));
        (self.st.at, self.st.at_line) = was;
        let v = v?.num();
        let n = v.round();
        if !v.is_finite() || (v - n).abs() >= 0.0001 {
            return Err(Diagnostic::error(
                span,
                format!("{written} reads {v}: an O-word label is a whole number (LinuxCNC: \"Non integer value for integer\")"),
            ));
        }
        if n.abs() > f64::from(i32::MAX) {
            return Err(Diagnostic::error(
                span,
                format!("{written} reads {v}: LinuxCNC's labels are whole numbers up to {}", i32::MAX),
            ));
        }
        Ok(OName::Number(n as i64))
    }

    /// Skips from block `from` past the closing block `end` of the
    /// construct that block `start` opens, as rs274ngc skips: it reads the
    /// labels on the way and stops at `end` only where `end`'s label reads
    /// what `start`'s read.
    fn skip_to_end(&mut self, from: u32, start: u32, end: u32) -> Result<(), Diagnostic> {
        self.read_skipped(from + 1, end)?;
        self.check_partner(start, end, true)
    }

    /// Reads the computed labels of the blocks from `from` to before `to`,
    /// which the run skips: rs274ngc reads the label of each line it passes
    /// over (not its other expressions), and stops at one it cannot read.
    fn read_skipped(&mut self, from: u32, to: u32) -> Result<(), Diagnostic> {
        if !self.computed_labels {
            return Ok(());
        }
        for at in from..to.min(self.program.blocks.len() as u32) {
            // (O-words are never on a dropped page.)
            if matches!(self.program.blocks.get(at as usize).map(|b| &b.statement), Some(Statement::OWord(o)) if o.label.is_some())
            {
                self.label_of(at)?;
            }
        }
        Ok(())
    }

    /// Checks that the closing word of block `at` reads the label its
    /// opener, block `start`, read, where either is computed (`reached`
    /// false: the run skips to it).
    fn check_partner(&mut self, start: u32, at: u32, skipped: bool) -> Result<(), Diagnostic> {
        let computed = |b: u32| matches!(self.program.blocks.get(b as usize).map(|b| &b.statement), Some(Statement::OWord(o)) if o.label.is_some());
        if !computed(start) && !computed(at) {
            return Ok(());
        }
        let read = self.frames.last().and_then(|f| f.read_labels.get(&start)).cloned();
        let opened = match read {
            Some(name) => name,
            None => self.label_of(start)?,
        };
        let closing = self.label_of(at)?;
        if opened == closing {
            return Ok(());
        }
        let describe = |b: &crate::ast::Block| match &b.statement {
            Statement::OWord(o) => format!("{} {}", o.name, o.flow.keyword()),
            _ => String::from("this block"),
        };
        let (opener, line) = (describe(&self.program.blocks[start as usize]), self.program.blocks[start as usize].line);
        let block = &self.program.blocks[at as usize];
        let (closer, span) = (describe(block), block.span);
        let why = if skipped {
            format!(
                "LinuxCNC skips on past it, to the next O-word that reads {opened}; kezuri pairs constructs by \
                 nesting and stops here"
            )
        } else {
            "LinuxCNC stops, \"undefined O-word label\"".to_string()
        };
        Err(Diagnostic::error(
            span,
            format!("{closer} reads {closing}, where {opener} (line {line}) read {opened}: {why}"),
        ))
    }

    /// The loop that the `break` or `continue` of block `pc`, its label
    /// read as `name`, leaves or turns, where the parser could not tell
    /// (a computed label): the loop of that label run in this subroutine
    /// or main program, around the block — rs274ngc looks the label up
    /// among those it has read.
    fn find_loop(&mut self, pc: u32, name: &OName, span: Span) -> Result<u32, Diagnostic> {
        let this = match &self.program.blocks[pc as usize].statement {
            Statement::OWord(o) if o.name.is_computed() => format!("{} {} (read as {name})", o.name, o.flow.keyword()),
            Statement::OWord(o) => format!("{} {}", o.name, o.flow.keyword()),
            _ => String::from("this block"),
        };
        let Some(at) = self.frames.last().and_then(|f| f.labels.get(name)).copied() else {
            return Err(Diagnostic::error(
                span,
                format!("{this} is not inside a loop named {name}: LinuxCNC stops, \"undefined O-word label\""),
            ));
        };
        let block = &self.program.blocks[at as usize];
        let line = block.line;
        let (kind, is_loop) = match &block.statement {
            Statement::OWord(o) => (o.flow.keyword(), matches!(o.flow, Flow::While { .. } | Flow::Do { .. })),
            _ => ("construct", false),
        };
        if kind == "repeat" {
            // As the parser refuses a written one.
            return Err(Diagnostic::error(
                span,
                format!(
                    "{this}: LinuxCNC leaves or continues while and do loops only, not {name} repeat (line {line})"
                ),
            ));
        }
        if !is_loop {
            return Err(Diagnostic::error(
                span,
                format!("{this} names {name} {kind} (line {line}), which is not a loop"),
            ));
        }
        let end = self.end_of(at, span)?;
        if !(at < pc && pc < end) {
            return Err(Diagnostic::error(
                span,
                format!("{this} is not inside {name} {kind} (line {line}), the loop of that label"),
            ));
        }
        Ok(at)
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
    fn branch(&mut self, start: u32, mut next: u32, span: Span) -> Result<u32, Diagnostic> {
        loop {
            next = self.target(next, span)?;
            self.check_partner(start, next, true)?;
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

    /// `o<number> call` without arguments, from the block just run (a lathe
    /// cycle's `Q`: its profile's subroutine).
    pub(super) fn call_by_number(&mut self, number: u32, span: Span) -> Result<bool, Diagnostic> {
        let pc = self.frame().pc.saturating_sub(1);
        self.o_call(&OName::Number(i64::from(number)), &[], pc, span)?;
        Ok(true)
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
            read_labels: HashMap::new(),
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
        if let Some(sub) = self.sub_in(name, first, Some(file)) {
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
        let blocks = &self.program.blocks;
        self.computed_labels |= computed_labels((first..blocks.len()).filter_map(|i| blocks.get(i)));
        self.sub_in(name, first, None)
            .ok_or_else(|| Diagnostic::error(span, format!("{file_name} does not define {name} sub")))
    }

    /// The first `sub` of `name` among the blocks from `first` on (in file
    /// `within` only, where given: it stops at the first block of another),
    /// noted as defined. A dropped page holds no `sub`.
    fn sub_in(&mut self, name: &OName, first: usize, within: Option<crate::source::FileId>) -> Option<u32> {
        let program = &*self.program;
        let found = (first..program.blocks.len())
            .take_while(|&i| within.is_none_or(|file| program.block_file(i as u32) == file))
            .find(|&i| {
                program.blocks.get(i).is_some_and(|b| {
                    matches!(&b.statement, Statement::OWord(o) if o.name == *name && matches!(o.flow, Flow::Sub { .. }))
                })
            })? as u32;
        self.subs.insert(name.clone(), found);
        Some(found)
    }
}

/// Whether a LinuxCNC O-word among `blocks` has a computed label.
/// Whether a LinuxCNC O-word among `blocks` has a computed label (the
/// blocks held: O-words are never on a dropped page).
pub(super) fn computed_labels<'b>(mut blocks: impl Iterator<Item = &'b crate::ast::Block>) -> bool {
    blocks.any(|b| matches!(&b.statement, Statement::OWord(o) if o.label.is_some()))
}
