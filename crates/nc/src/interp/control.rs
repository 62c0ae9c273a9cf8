//! The block pointer: macro statements, loops, jumps, calls and returns.

mod finish;
mod index;
mod line;
mod oword;

use std::collections::HashMap;

use index::{build_index, UnitIndex};

use super::block::{Action, Call, FrameKind};
use super::value::{self, Value};
use super::{Library, Settings, State};
use crate::ast::{Expr, ExprId, OName, PrintItem, Program, Statement};
use crate::parse::parse;
use crate::source::{Diagnostic, Sources, Span};
use crate::Dialect;
use kezuri_geom::PathSink;

/// Most moves reserved before a run that keeps its whole path (a hint; the
/// toolpath grows past it).
const MAX_RESERVED_MOVES: usize = 1 << 22;
/// Deepest nesting of M98 subprogram calls.
const MAX_SUBPROGRAM_DEPTH: usize = 4;
/// Deepest nesting of G65/G66 macro calls.
const MAX_MACRO_DEPTH: usize = 5;

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
    /// The number each LinuxCNC opener of a computed label (`o#1 if`) read
    /// when it last ran here, by block: its closing word must read the same.
    read_labels: HashMap<u32, OName>,
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
    /// Whether a LinuxCNC O-word of the program has a computed label
    /// (`o#1 if`): the run then reads the labels of the blocks it skips.
    computed_labels: bool,
    /// Where the toolpath goes piece by piece; `None`: it is kept whole.
    sink: Option<&'a mut dyn PathSink>,
    /// A program read in pages: the N numbers searched for, by unit, and
    /// the block found.
    found_labels: HashMap<(usize, u32), Option<u32>>,
    /// Statements run again ([`Settings::step_limit`](super::Settings)).
    repeated: u64,
    /// Each program unit's furthest block run so far (one past it): a block
    /// before it runs again.
    reached: Vec<u32>,
}

impl<'a> Interp<'a> {
    pub(super) fn new(
        program: &'a mut Program,
        sources: &'a mut Sources,
        library: &'a mut dyn Library,
        settings: Settings,
        sink: Option<&'a mut dyn PathSink>,
    ) -> Self {
        let computed_labels = oword::computed_labels(program.blocks.iter());
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
            computed_labels,
            sink,
            found_labels: HashMap::new(),
            repeated: 0,
            reached: Vec::new(),
        }
    }

    pub(super) fn run(&mut self, main: usize) {
        let Some(unit) = self.program.units.get(main) else { return };
        if let Err(m) = self.st.settings.check() {
            self.st.diagnostics.push(Diagnostic::error(unit.span, format!("machine settings: {m}")));
            return;
        }
        self.st.load_kept_values();
        if let Err(m) = self.st.load_parameters() {
            self.st.diagnostics.push(Diagnostic::error(unit.span, format!("starting parameters (--var): {m}")));
            return;
        }
        self.st.last.o = unit.number.unwrap_or(0) as f64;
        // Room for about a move per block up front: growing a large toolpath
        // step by step copies it. Untouched capacity costs no memory.
        let room = if self.sink.is_some() { self.st.settings.piece_moves + 1 } else { MAX_RESERVED_MOVES };
        self.st.toolpath.moves.reserve(unit.blocks.len().min(room));
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
            read_labels: HashMap::new(),
        });
        loop {
            match self.step() {
                Ok(true) => {
                    if self.sink.is_some() && self.st.toolpath.moves.len() > self.st.settings.piece_moves {
                        self.hand_on();
                    }
                }
                Ok(false) => {
                    self.completed = true;
                    break;
                }
                Err(mut d) => {
                    // The blocks the chain names (a local subprogram's N)
                    // held again where their pages were dropped.
                    for k in 0..self.frames.len() {
                        if self.frames[k].kind == FrameKind::Local {
                            self.program.ensure(self.frames[k].start, self.sources);
                        }
                    }
                    d.call_chain = self.call_chain();
                    self.st.diagnostics.push(d);
                    break;
                }
            }
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
                        let sub = f.start - 1;
                        let name = match &self.program.blocks[sub as usize].statement {
                            // `o[#1*10] sub`: the name it read.
                            Statement::OWord(o) if o.name.is_computed() => self
                                .subs
                                .iter()
                                .find(|&(_, &at)| at == sub)
                                .map_or_else(|| o.name.to_string(), |(name, _)| name.to_string()),
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
                if let Some(last) = self.program.units[unit].blocks.clone().last() {
                    self.program.ensure(last, self.sources);
                }
                self.linuxcnc_file_end(unit)?;
                self.st.warn("end", span, "the program ends without M30 or M02: is the file complete?");
                return Ok(false);
            }
            self.st.warn("end", span, "the subprogram ends without M99; returning");
            return self.return_from(None, span);
        }
        self.program.run_at(pc, self.sources);
        self.frame().pc = pc + 1;
        self.statements += 1;
        let furthest = match self.reached.get_mut(unit) {
            Some(f) => f,
            None => {
                self.reached.resize(unit + 1, 0);
                &mut self.reached[unit]
            }
        };
        let again = pc < *furthest;
        if !again {
            *furthest = pc + 1;
        } else {
            self.repeated += 1;
            if self.repeated > self.st.settings.step_limit {
                self.program.ensure(self.last_back_jump.unwrap_or(pc), self.sources);
                return Err(self.runaway(pc));
            }
        }
        let block = &self.program.blocks[pc as usize];
        self.st.settings.reached(block.span, || self.program.units[self.frames[0].unit].span.file);
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
        // A statement may set what the frame is made of (#5221…, #2001…).
        if !matches!(block.statement, Statement::Empty | Statement::Words { .. }) {
            self.st.frame_known = false;
        }
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
        let to = self.label_block(unit, n as u32);
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

    /// The first block numbered N`n` in `unit`. A program read in pages is
    /// searched page by page (only those whose numbers may hold it), as a
    /// control searches its memory, and what was found is remembered.
    fn label_block(&mut self, unit: usize, n: u32) -> Option<u32> {
        if !self.program.paging() {
            return self.unit_index(unit).labels.get(&n).copied();
        }
        if let Some(&found) = self.found_labels.get(&(unit, n)) {
            return found;
        }
        let blocks = self.program.units[unit].blocks.clone();
        let mut found = None;
        let mut i = blocks.start;
        while i < blocks.end && found.is_none() {
            let page = self.program.page_of_block(i);
            let page_end = (self.program.blocks.page_range(page).end as u32).min(blocks.end);
            if self.program.page_may_hold(page, n) {
                self.program.ensure(i, self.sources);
                found = (i..page_end).find(|&k| self.program.blocks[k as usize].number == Some(n));
            }
            i = page_end;
        }
        self.found_labels.insert((unit, n), found);
        found
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
        let (stopped, raise) = (
            format!("stopped after {} statements", self.st.settings.step_limit),
            " (raise the step limit if it should run longer)",
        );
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
            Action::OCall { number, span } => self.call_by_number(number, span),
            Action::Resume(pc) => {
                self.frame().pc = pc;
                Ok(true)
            }
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
        let Some(start) = self.label_block(unit, label) else {
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
            read_labels: HashMap::new(),
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
            read_labels: HashMap::new(),
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
            self.st.profile_returned(self.st.call_level)?;
        }
        if let Some(n) = target {
            let caller = self.frames.last().map_or(0, |f| f.unit);
            self.jump(caller, Value::Num(f64::from(n)), span, "M99 P")?;
        }
        Ok(true)
    }
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
