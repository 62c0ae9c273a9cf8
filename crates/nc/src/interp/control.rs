//! The block pointer: macro statements, loops, jumps, calls and returns.

use std::collections::HashMap;

use super::block::{Action, Call, FrameKind};
use super::value::{self, Value};
use super::{Library, Outcome, Settings, State};
use crate::ast::{CommentCommand, Expr, ExprId, Flow, OName, PrintItem, Program, Statement, WordValue};
use crate::parse::{parse, parse_as};
use crate::source::{Diagnostic, Sources, Span};
use crate::Dialect;

/// Most moves reserved before a run (a hint; the toolpath grows past it).
const MAX_RESERVED_MOVES: usize = 1 << 22;
/// Deepest nesting of M98 subprogram calls.
const MAX_SUBPROGRAM_DEPTH: usize = 4;
/// Deepest nesting of G65/G66 macro calls.
const MAX_MACRO_DEPTH: usize = 5;
/// Deepest nesting of LinuxCNC `o… call`s: rs274ngc runs nine levels
/// below the main program and refuses the tenth ("Too many subroutine
/// levels").
const MAX_OSUB_DEPTH: usize = 9;

struct Frame {
    unit: usize,
    pc: u32,
    /// Where each repetition starts: the unit's first block, or the N label
    /// of an M97 call.
    start: u32,
    kind: FrameKind,
    repeats_left: u32,
    call_span: Span,
    args: Option<Box<super::Locals>>,
    /// LinuxCNC `repeat` loops running in this frame: the `repeat` block
    /// and the turns left after this one, innermost last.
    repeats: Vec<(u32, u64)>,
    /// The LinuxCNC `if`, `while`, `do` and `repeat` blocks run in this
    /// frame, by label: a label opens one construct in a subroutine (or
    /// the main program).
    labels: HashMap<OName, u32>,
}

/// Sequence numbers and loop pairs of one program unit.
#[derive(Default)]
struct UnitIndex {
    labels: HashMap<u32, u32>,
    /// For each WHILE/DO block, its END; for each END, its WHILE/DO; or why
    /// it has none.
    loops: HashMap<u32, Result<u32, String>>,
}

pub(super) struct Interp<'a> {
    program: &'a mut Program,
    sources: &'a mut Sources,
    library: &'a mut dyn Library,
    st: State,
    frames: Vec<Frame>,
    index: HashMap<usize, UnitIndex>,
    statements: u64,
    completed: bool,
    last_back_jump: Option<u32>,
    /// LinuxCNC subroutines defined so far (their `sub` reached, or found
    /// by a call): the block of each `sub`.
    subs: HashMap<OName, u32>,
}

impl<'a> Interp<'a> {
    pub(super) fn new(
        program: &'a mut Program,
        sources: &'a mut Sources,
        library: &'a mut dyn Library,
        settings: Settings,
    ) -> Self {
        Interp {
            program,
            sources,
            library,
            st: State::new(settings),
            frames: Vec::new(),
            index: HashMap::new(),
            statements: 0,
            completed: false,
            last_back_jump: None,
            subs: HashMap::new(),
        }
    }

    pub(super) fn run(&mut self, main: usize) {
        let Some(unit) = self.program.units.get(main) else { return };
        if let Err(m) = self.st.settings.check() {
            self.st.diagnostics.push(Diagnostic::error(unit.span, format!("machine settings: {m}")));
            return;
        }
        self.st.load_kept_values();
        self.st.load_parameters();
        self.st.last.o = unit.number.unwrap_or(0) as f64;
        // Room for about a move per block up front: growing a large toolpath
        // step by step copies it. Untouched capacity costs no memory.
        self.st.toolpath.moves.reserve(unit.blocks.len().min(MAX_RESERVED_MOVES));
        self.frames.push(Frame {
            unit: main,
            pc: unit.blocks.start,
            start: unit.blocks.start,
            kind: FrameKind::Main,
            repeats_left: 0,
            call_span: unit.span,
            args: None,
            repeats: Vec::new(),
            labels: HashMap::new(),
        });
        loop {
            match self.step() {
                Ok(true) => {}
                Ok(false) => {
                    self.completed = true;
                    break;
                }
                Err(mut d) => {
                    d.call_chain = self.call_chain();
                    self.st.diagnostics.push(d);
                    break;
                }
            }
        }
    }

    pub(super) fn finish(mut self) -> Outcome {
        let compensated = self.st.comp_finish();
        let programmed = compensated.map(|c| {
            if let Some(alarm) = c.alarm {
                self.st.diagnostics.push(alarm);
                self.completed = false;
            }
            c.programmed
        });
        let mut summary: Vec<_> = self.st.warned.iter().filter(|(_, &n)| n > super::WARNINGS_PER_KIND).collect();
        summary.sort();
        for (kind, n) in summary {
            let span = self.st.diagnostics.iter().rev().find(|d| !d.is_error()).map_or(Span::default(), |d| d.span);
            let more = n - super::WARNINGS_PER_KIND;
            self.st
                .diagnostics
                .push(Diagnostic::warning(span, format!("… and {more} more warnings like these ({kind})")));
        }
        Outcome {
            toolpath: self.st.toolpath,
            programmed,
            diagnostics: self.st.diagnostics,
            prints: self.st.prints,
            logs: self.st.logs,
            blocks: self.st.blocks,
            statements: self.statements,
            completed: self.completed,
            holes: self.st.holes,
            model_reads: self.st.model_reads,
        }
    }

    fn call_chain(&self) -> Vec<(String, Span)> {
        self.frames
            .iter()
            .skip(1)
            .map(|f| {
                let number = self.program.units[f.unit].number.unwrap_or(0);
                let how = match f.kind {
                    FrameKind::Local => {
                        let label = self.program.blocks[f.start as usize].number.unwrap_or(0);
                        return (format!("local subprogram N{label} of O{number:04} (M97)"), f.call_span);
                    }
                    FrameKind::Subprogram => "subprogram",
                    FrameKind::Macro => "macro",
                    FrameKind::ModalMacro => "modal macro",
                    FrameKind::Main => "program",
                    FrameKind::OSub => {
                        let name = match &self.program.blocks[f.start as usize - 1].statement {
                            Statement::OWord(o) => o.name.to_string(),
                            _ => String::from("o?"),
                        };
                        return (format!("subroutine {name}"), f.call_span);
                    }
                };
                (format!("{how} O{number:04}"), f.call_span)
            })
            .collect()
    }

    fn frame(&mut self) -> &mut Frame {
        self.frames.last_mut().expect("a frame while running")
    }

    /// Runs one statement. `Ok(false)` when the program has ended.
    fn step(&mut self) -> Result<bool, Diagnostic> {
        let (unit, pc) = {
            let f = self.frames.last().expect("a frame while running");
            (f.unit, f.pc)
        };
        let end = self.program.units[unit].blocks.end;
        if pc >= end {
            let span = self.program.units[unit].span;
            if self.frames.len() == 1 {
                self.st.warn("end", span, "the program ends without M30 or M02: is the file complete?");
                return Ok(false);
            }
            self.st.warn("end", span, "the subprogram ends without M99; returning");
            return self.return_from(None, span);
        }
        self.frame().pc = pc + 1;
        self.statements += 1;
        if self.statements > self.st.settings.step_limit || self.st.toolpath.moves.len() > self.st.settings.move_limit {
            return Err(self.runaway(pc));
        }
        let block = &self.program.blocks[pc as usize];
        if block.delete && self.st.settings.block_delete {
            return Ok(true);
        }
        let span = block.span;
        self.st.at = span;
        self.st.at_line = block.line;
        if let Some(n) = block.number {
            self.st.last.n = f64::from(n);
        }
        let located = |r: Result<Value, String>| r.map_err(|m| Diagnostic::error(span, m));
        match &block.statement {
            Statement::Empty => {}
            Statement::Words { .. } => {
                let action = self.st.exec_block(self.program, pc)?;
                return self.act(action, span);
            }
            &Statement::Assign { var, value } => {
                let v = self.setting_value(var, value, span)?;
                self.assign(var, v, pc)?;
            }
            &Statement::Goto(target) => {
                let n = located(self.st.eval(self.program, target))?;
                self.jump(unit, n, span, "GOTO")?;
            }
            &Statement::IfGoto { cond, target } => {
                if located(self.st.eval(self.program, cond))?.truth() {
                    let n = located(self.st.eval(self.program, target))?;
                    self.jump(unit, n, span, "GOTO")?;
                }
            }
            &Statement::IfThen { cond, var, value } => {
                if located(self.st.eval(self.program, cond))?.truth() {
                    let v = located(self.st.eval(self.program, value))?;
                    self.assign(var, v, pc)?;
                }
            }
            &Statement::While { cond, .. } => {
                let partner = self.loop_partner(unit, pc)?;
                if !located(self.st.eval(self.program, cond))?.truth() {
                    self.frame().pc = partner + 1;
                }
            }
            Statement::Do { .. } => {
                self.loop_partner(unit, pc)?;
            }
            Statement::End { .. } => {
                let partner = self.loop_partner(unit, pc)?;
                self.last_back_jump = Some(partner);
                self.frame().pc = partner;
            }
            Statement::Popen => self.st.print_open = true,
            Statement::Pclos => self.st.print_open = false,
            Statement::Dprnt(items) => {
                if !self.st.print_open {
                    self.st.warn("dprnt", span, "DPRNT without POPEN: the control would not print this line");
                }
                let line = self.st.format_print(self.program, items).map_err(|m| Diagnostic::error(span, m))?;
                self.st.prints.push(line);
            }
            Statement::Assigns(list) => {
                // rs274ngc reads every value of the line before it sets any.
                let list = list.clone();
                let mut values = Vec::with_capacity(list.len());
                for &(var, value) in &list {
                    values.push(self.setting_value(var, value, span)?);
                }
                for (&(var, _), v) in list.iter().zip(values) {
                    self.assign(var, v, pc)?;
                }
            }
            Statement::OWord(_) => return self.oword(pc, span),
            Statement::Comment(command) => {
                let command = command.clone();
                self.comment(&command, span);
            }
            Statement::Line(_) => return self.line(pc, span),
            Statement::Unsupported(what) => return Err(Diagnostic::error(span, what.clone())),
        }
        Ok(true)
    }

    /// The value of the setting `#var=value` of a line, read with the
    /// line's other values before any is set. A named parameter that is not
    /// set is made (reading 0) where the line sets it, before its value is
    /// read, as rs274ngc does: `#<a>=1 #<b>=[#<a>+1]` sets #<b> to 1 and
    /// `#<c>=[#<c>+1]` #<c> to 1 where #<a> and #<c> were not set before.
    fn setting_value(&mut self, var: ExprId, value: ExprId, span: Span) -> Result<Value, Diagnostic> {
        if let Expr::Named(name) = &self.program.exprs[var as usize] {
            if !self.st.named_exists(name) {
                self.st.write_named(name, Value::Num(0.0)).map_err(|m| Diagnostic::error(span, m))?;
            }
        }
        self.st.eval(self.program, value).map_err(|m| Diagnostic::error(span, m))
    }

    /// A LinuxCNC line of settings, words and a comment command, run as
    /// rs274ngc runs it: every value of the line read left to right (the
    /// words' with the parameters as they were before the line), then the
    /// settings made, then the comment run, then the words.
    fn line(&mut self, pc: u32, span: Span) -> Result<bool, Diagnostic> {
        let Statement::Line(line) = &self.program.blocks[pc as usize].statement else { return Ok(true) };
        let line = (**line).clone();
        let mut values = Vec::with_capacity(line.settings.len());
        let mut words = Vec::new();
        let mut settings = line.settings.iter().peekable();
        for k in 0..=line.len {
            while let Some(&(var, value, _)) = settings.next_if(|s| s.2 <= k) {
                values.push(self.setting_value(var, value, span)?);
            }
            let at = (line.start + k) as usize;
            if k == line.len {
                break;
            }
            let word = self.program.words[at];
            if let WordValue::Expr(e) = word.value() {
                let v = self.st.eval(self.program, e).map_err(|m| Diagnostic::error(word.span(span.file), m))?;
                words.push((at, word, v.num()));
            }
        }
        for (&(var, _, _), v) in line.settings.iter().zip(values) {
            self.assign(var, v, pc)?;
        }
        if let Some(command) = &line.comment {
            self.comment(command, span);
        }
        if line.len == 0 {
            return Ok(true);
        }
        // The words run with the values read above: each expression stands
        // in as its number while the block runs.
        for &(at, word, v) in &words {
            self.program.words[at] =
                crate::ast::Word::new(word.letter, WordValue::Number { value: v, decimal: true }, word.span(span.file));
        }
        let action = self.st.exec_block(self.program, pc);
        for &(at, word, _) in &words {
            self.program.words[at] = word;
        }
        self.act(action?, span)
    }

    /// Runs a LinuxCNC comment command.
    fn comment(&mut self, command: &CommentCommand, span: Span) {
        match command {
            CommentCommand::Debug(items) => {
                let line = self.st.format_message(self.program, items);
                self.st.prints.push(line);
            }
            CommentCommand::Msg(text) => self.st.prints.push(text.clone()),
            CommentCommand::LogOpen { file, append } => {
                self.st.logs.push(super::LogFile { name: file.clone(), append: *append, lines: Vec::new() });
                self.st.log_open = true;
            }
            CommentCommand::LogClose => self.st.log_open = false,
            CommentCommand::Log(items) => {
                let line = self.st.format_message(self.program, items);
                match self.st.logs.last_mut().filter(|_| self.st.log_open) {
                    Some(log) => log.lines.push(line),
                    None => self.st.warn(
                        "log",
                        span,
                        "(log,…) with no log file open: LinuxCNC writes the line nowhere (open one with (logopen,FILE))",
                    ),
                }
            }
        }
    }

    /// Runs the LinuxCNC O-word of block `pc`.
    fn oword(&mut self, pc: u32, span: Span) -> Result<bool, Diagnostic> {
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

    fn assign(&mut self, var: ExprId, value: Value, pc: u32) -> Result<(), Diagnostic> {
        let block = &self.program.blocks[pc as usize];
        let span = block.span;
        if let Expr::Named(name) = &self.program.exprs[var as usize] {
            return self.st.write_named(name, value).map_err(|m| Diagnostic::error(span, m));
        }
        let number = self.st.var_number(self.program, var).map_err(|m| Diagnostic::error(span, m))?;
        if self.st.settings.dialect == Dialect::LinuxCnc {
            return self.st.write_var(number, value).map_err(|m| Diagnostic::error(span, m));
        }
        if number == 3000.0 {
            let text = &self.sources.get(span.file).text[span.start as usize..span.end as usize];
            let message =
                text.find('(').and_then(|o| text[o + 1..].find(')').map(|c| text[o + 1..o + 1 + c].trim().to_string()));
            let alarm = 3000.0 + value.num();
            return Err(Diagnostic::error(
                span,
                format!("macro alarm {alarm}: {}", message.unwrap_or_else(|| "(no message)".into())),
            ));
        }
        if number == 3006.0 {
            // A stop with a message for the operator: M00 where the control
            // has no macros.
            let text = &self.sources.get(span.file).text[span.start as usize..span.end as usize];
            let message = text.find('(').and_then(|o| text[o + 1..].find(')').map(|c| text[o + 1..o + 1 + c].trim()));
            let kept = match message {
                Some(m) if !m.is_empty() => format!("M00 ({})", m.replace(['(', ')'], "")),
                _ => "M00".to_string(),
            };
            self.st.keep(kept, 0, false, block.line);
            return Ok(());
        }
        self.st.write_var(number, value).map_err(|m| Diagnostic::error(span, m))
    }

    /// Jumps to block `N<target>` of `unit`; `what` names the statement
    /// (`GOTO`, `M99 P`) in messages.
    fn jump(&mut self, unit: usize, target: Value, span: Span, what: &str) -> Result<(), Diagnostic> {
        let n = target.num();
        if n.fract() != 0.0 || !(1.0..=99_999_999.0).contains(&n) {
            return Err(Diagnostic::error(
                span,
                format!("{what}{n}: a sequence number is a whole number from 1 to 99999999"),
            ));
        }
        let to = self.unit_index(unit).labels.get(&(n as u32)).copied();
        let Some(to) = to else {
            let number = self.program.units[unit].number.map_or(String::from("this program"), |o| format!("O{o:04}"));
            return Err(Diagnostic::error(span, format!("{what}{n}: there is no block N{n} in {number}")));
        };
        let from = self.frames.last().map_or(0, |f| f.pc);
        // The jumping block is `from - 1`. A Fanuc control alarms on a jump
        // from outside a DO loop into its body.
        let into = self.unit_index(unit).loops.iter().find_map(|(&start, end)| match end {
            Ok(end) if start < *end && start < to && to <= *end && !(start < from && from - 1 <= *end) => Some(start),
            _ => None,
        });
        if let Some(start) = into {
            let label = match self.program.blocks[start as usize].statement {
                Statement::While { label, .. } | Statement::Do { label } => label,
                _ => 0,
            };
            return Err(Diagnostic::error(
                span,
                format!("{what}{n} jumps into the DO{label} loop from outside it; a jump may only leave a loop"),
            ));
        }
        if to < from {
            self.last_back_jump = Some(from - 1);
        }
        self.frame().pc = to;
        Ok(())
    }

    fn unit_index(&mut self, unit: usize) -> &UnitIndex {
        let program = &*self.program;
        self.index.entry(unit).or_insert_with(|| build_index(program, unit))
    }

    fn loop_partner(&mut self, unit: usize, pc: u32) -> Result<u32, Diagnostic> {
        let span = self.program.blocks[pc as usize].span;
        match self.unit_index(unit).loops.get(&pc) {
            Some(Ok(p)) => Ok(*p),
            Some(Err(m)) => Err(Diagnostic::error(span, m.clone())),
            None => Err(Diagnostic::error(span, "loop statement without a partner")),
        }
    }

    fn runaway(&self, pc: u32) -> Diagnostic {
        let moves = self.st.settings.move_limit;
        let (stopped, raise) = if self.st.toolpath.moves.len() > moves {
            (format!("stopped after {moves} moves, the most a run keeps (some 300 bytes each)"), "")
        } else {
            (
                format!("stopped after {} statements", self.st.settings.step_limit),
                " (raise the step limit if it should run longer)",
            )
        };
        let at = self.last_back_jump.unwrap_or(pc);
        let block = &self.program.blocks[at as usize];
        let what = match block.statement {
            Statement::While { label, .. } => format!("the WHILE … DO{label} loop"),
            Statement::Do { label } => format!("the DO{label} loop"),
            Statement::OWord(ref o) => format!("the {} {} loop", o.name, o.flow.keyword()),
            _ if self.last_back_jump.is_some() => "the backward GOTO here".to_string(),
            _ => "this program".to_string(),
        };
        Diagnostic::error(block.span, format!("{stopped}: {what} does not seem to end{raise}"))
    }

    fn act(&mut self, action: Action, span: Span) -> Result<bool, Diagnostic> {
        match action {
            Action::Next => Ok(true),
            Action::End => Ok(false),
            Action::Call(call) => {
                self.call(call)?;
                Ok(true)
            }
            Action::LocalCall { label, repeats, span } => {
                self.local_call(label, repeats, span)?;
                Ok(true)
            }
            Action::Return(target) => self.return_from(target, span),
        }
    }

    fn find_unit(&mut self, number: u32, span: Span) -> Result<usize, Diagnostic> {
        if let Some(u) = self.program.unit(number) {
            return Ok(u);
        }
        let Some(file) = self.library.load(number) else {
            return Err(Diagnostic::error(
                span,
                format!("program O{number:04} is not in the file or the program library"),
            ));
        };
        let name = file.name.clone();
        let id = self.sources.add(file);
        let text = self.sources.get(id).text.clone();
        let diagnostics = parse(self.program, id, &text);
        let errors: Vec<_> = diagnostics.iter().filter(|d| d.is_error()).cloned().collect();
        self.st.diagnostics.extend(diagnostics.into_iter().filter(|d| !d.is_error()));
        if let Some(first) = errors.into_iter().next() {
            return Err(first);
        }
        self.program
            .unit(number)
            .ok_or_else(|| Diagnostic::error(span, format!("{name} does not contain program O{number:04}")))
    }

    /// Refuses a call of `kind` that would nest deeper than the control allows.
    fn check_depth(&self, kind: FrameKind, span: Span) -> Result<(), Diagnostic> {
        let depth =
            self.frames.iter().filter(|f| f.kind.is_macro() == kind.is_macro() && f.kind != FrameKind::Main).count();
        let (limit, what) =
            if kind.is_macro() { (MAX_MACRO_DEPTH, "macro calls") } else { (MAX_SUBPROGRAM_DEPTH, "subprogram calls") };
        if depth >= limit {
            return Err(Diagnostic::error(
                span,
                format!("{what} nested deeper than {limit} (a program that calls itself without end?)"),
            ));
        }
        Ok(())
    }

    /// `M97 P<label> L<repeats>`: runs the blocks of the current program
    /// from `N<label>` to M99, `repeats` times, then goes on after the M97.
    fn local_call(&mut self, label: u32, repeats: u32, span: Span) -> Result<(), Diagnostic> {
        let unit = self.frames.last().map_or(0, |f| f.unit);
        let Some(start) = self.unit_index(unit).labels.get(&label).copied() else {
            let number = self.program.units[unit].number.map_or(String::from("this program"), |o| format!("O{o:04}"));
            return Err(Diagnostic::error(span, format!("M97 P{label}: there is no block N{label} in {number}")));
        };
        self.check_depth(FrameKind::Local, span)?;
        if repeats == 0 {
            return Ok(());
        }
        self.frames.push(Frame {
            unit,
            pc: start,
            start,
            kind: FrameKind::Local,
            repeats_left: repeats - 1,
            call_span: span,
            args: None,
            repeats: Vec::new(),
            labels: HashMap::new(),
        });
        Ok(())
    }

    fn call(&mut self, call: Call) -> Result<(), Diagnostic> {
        let unit = self.find_unit(call.program, call.span)?;
        self.check_depth(call.kind, call.span)?;
        if call.repeats == 0 {
            return Ok(());
        }
        if let Some(args) = &call.args {
            self.st.enter_level(args);
        }
        if call.kind == FrameKind::ModalMacro {
            self.st.modal_depth += 1;
        }
        let start = self.program.units[unit].blocks.start;
        self.frames.push(Frame {
            unit,
            pc: start,
            start,
            kind: call.kind,
            repeats_left: call.repeats - 1,
            call_span: call.span,
            args: call.args,
            repeats: Vec::new(),
            labels: HashMap::new(),
        });
        Ok(())
    }

    fn return_from(&mut self, target: Option<u32>, span: Span) -> Result<bool, Diagnostic> {
        if self.frames.len() == 1 {
            self.st.warn("m99-main", span, "M99 in the main program restarts it on the control; the run stops here");
            return Ok(false);
        }
        let f = self.frame();
        if f.repeats_left > 0 {
            // The next repetition goes on with the same local variables: the
            // arguments are set on the first one only (G65 P… L…).
            f.repeats_left -= 1;
            f.pc = f.start;
            return Ok(true);
        }
        let done = self.frames.pop().expect("a frame to return from");
        if done.args.is_some() {
            self.st.leave_level();
        }
        if done.kind == FrameKind::ModalMacro {
            self.st.modal_depth -= 1;
        }
        if done.kind == FrameKind::OSub {
            self.st.call_level -= 1;
        }
        if let Some(n) = target {
            let caller = self.frames.last().map_or(0, |f| f.unit);
            self.jump(caller, Value::Num(f64::from(n)), span, "M99 P")?;
        }
        Ok(true)
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

fn build_index(program: &Program, unit: usize) -> UnitIndex {
    let mut index = UnitIndex::default();
    let mut open: Vec<(u8, u32)> = Vec::new();
    for i in program.units[unit].blocks.clone() {
        let block = &program.blocks[i as usize];
        if let Some(n) = block.number {
            index.labels.entry(n).or_insert(i);
        }
        match block.statement {
            Statement::While { label, .. } | Statement::Do { label } => open.push((label, i)),
            Statement::End { label } => match open.last() {
                Some(&(l, start)) if l == label => {
                    open.pop();
                    index.loops.insert(start, Ok(i));
                    index.loops.insert(i, Ok(start));
                }
                Some(&(l, _)) => {
                    let crossing =
                        format!("END{label} comes before END{l}: the DO{label} and DO{l} loops cross; loops must nest");
                    if let Some(&(_, start)) = open.iter().rev().find(|(o, _)| *o == label) {
                        index.loops.insert(start, Err(crossing.clone()));
                    }
                    index.loops.insert(i, Err(crossing));
                }
                None => {
                    index.loops.insert(i, Err(format!("END{label} has no WHILE … DO{label} before it")));
                }
            },
            _ => {}
        }
    }
    for (label, start) in open {
        index
            .loops
            .entry(start)
            .or_insert_with(|| Err(format!("DO{label} has no END{label} after it in this program")));
    }
    index
}

impl State {
    /// Evaluates an expression.
    pub(super) fn eval(&mut self, program: &Program, id: ExprId) -> Result<Value, String> {
        Ok(match &program.exprs[id as usize] {
            &Expr::Number(v) => Value::Num(v),
            &Expr::Var(n) => {
                let number = self.var_number(program, n)?;
                let v = self.read_var(number)?;
                if self.settings.dialect == Dialect::LinuxCnc {
                    // A LinuxCNC parameter is never vacant: unset, it reads 0.
                    Value::Num(v.num())
                } else {
                    v
                }
            }
            Expr::Named(name) => Value::Num(self.read_named(name)?),
            Expr::Exists(name) => Value::Num(if self.named_exists(name) { 1.0 } else { 0.0 }),
            &Expr::Neg(e) => match self.eval(program, e)? {
                Value::Vacant => Value::Vacant,
                Value::Num(v) => Value::Num(-v),
            },
            &Expr::Binary(op, a, b) => {
                let (a, b) = (self.eval(program, a)?, self.eval(program, b)?);
                if self.settings.dialect == Dialect::LinuxCnc {
                    value::binary_linuxcnc(op, a, b)?
                } else {
                    value::binary(op, a, b)?
                }
            }
            &Expr::Call(func, a, b) => {
                let a = self.eval(program, a)?;
                let b = match b {
                    Some(b) => Some(self.eval(program, b)?),
                    None => None,
                };
                if self.settings.dialect == Dialect::LinuxCnc {
                    value::call_linuxcnc(func, a, b)?
                } else {
                    value::call(func, a, b)?
                }
            }
        })
    }

    /// The variable number an `#…` expression names.
    pub(super) fn var_number(&mut self, program: &Program, id: ExprId) -> Result<f64, String> {
        if let Expr::Named(name) = &program.exprs[id as usize] {
            return Err(format!("#<{name}> names a parameter, not a number: write #<{name}>, not #[#<{name}>]"));
        }
        let v = self.eval(program, id)?.num();
        // Fanuc rounds a computed variable number to the nearest whole number.
        Ok(value::round_half_away(v))
    }

    fn enter_level(&mut self, args: &super::Locals) {
        self.level += 1;
        self.locals.truncate(self.level);
        self.locals.push(*args);
        self.named.truncate(self.level);
        self.named.push(HashMap::new());
    }

    fn leave_level(&mut self) {
        self.locals.truncate(self.level);
        self.named.truncate(self.level);
        self.level -= 1;
    }

    /// A LinuxCNC `(debug,…)` or `(print,…)` line: each parameter as
    /// rs274ngc prints it (six decimals), `######` for a named parameter
    /// that is not set.
    fn format_message(&mut self, program: &Program, items: &[PrintItem]) -> String {
        let mut line = String::new();
        for item in items {
            match item {
                PrintItem::Text(t) => line.push_str(t),
                &PrintItem::Var { var, .. } => {
                    let value = match &program.exprs[var as usize] {
                        Expr::Named(name) => self.read_named(name).ok(),
                        &Expr::Number(n) => self.read_var(n).ok().map(Value::num),
                        _ => None,
                    };
                    match value {
                        Some(v) => line.push_str(&format!("{v:.6}")),
                        None => line.push_str("######"),
                    }
                }
            }
        }
        line
    }

    fn format_print(&mut self, program: &Program, items: &[PrintItem]) -> Result<String, String> {
        let mut line = String::new();
        for item in items {
            match item {
                PrintItem::Text(t) => line.extend(t.chars().map(|c| if c == '*' { ' ' } else { c })),
                &PrintItem::Var { var, frac_digits, .. } => {
                    let number = self.var_number(program, var)?;
                    let v = self.read_var(number)?.num();
                    let text = format!("{:.*}", frac_digits as usize, v);
                    // A value that rounds to zero prints without a sign.
                    let negative_zero = text.starts_with('-') && text[1..].bytes().all(|b| b == b'0' || b == b'.');
                    line.push_str(if negative_zero { &text[1..] } else { &text });
                }
            }
        }
        Ok(line)
    }
}
