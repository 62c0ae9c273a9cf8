//! LinuxCNC lines: settings of numbered and named parameters mixed with
//! words, and comment commands; the end of a LinuxCNC file.

use super::Interp;
use crate::ast::{CommentCommand, Expr, ExprId, PrintItem, Program, Statement, WordValue};
use crate::interp::value::Value;
use crate::interp::{LogFile, State};
use crate::source::{Diagnostic, Span};

impl Interp<'_> {
    /// The main program `unit` has run off its last block without M2 or
    /// M30. LinuxCNC reads on to the end of the file and refuses it there
    /// (its interpreter's read of the next line), unless the file opened
    /// with `%` and this one closed it. Other dialects end with a warning.
    pub(super) fn linuxcnc_file_end(&self, unit: usize) -> Result<(), Diagnostic> {
        let unit = &self.program.units[unit];
        if self.st.settings.dialect != crate::Dialect::LinuxCnc || unit.closed_by_percent {
            return Ok(());
        }
        let last = unit.blocks.clone().last().map_or(unit.span, |b| self.program.blocks[b as usize].span);
        Err(Diagnostic::error(
            last,
            "File ended with no percent sign or program end: LinuxCNC refuses a program that runs off its end; \
             end it with M2 or M30 (or open and close the file with '%')",
        ))
    }

    /// The value of the setting `#var=value` of a line, read with the
    /// line's other values before any is set. A named parameter that is not
    /// set is made (reading 0) where the line sets it, before its value is
    /// read, as rs274ngc does: `#<a>=1 #<b>=[#<a>+1]` sets #<b> to 1 and
    /// `#<c>=[#<c>+1]` #<c> to 1 where #<a> and #<c> were not set before.
    pub(super) fn setting_value(&mut self, var: ExprId, value: ExprId, span: Span) -> Result<Value, Diagnostic> {
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
    pub(super) fn line(&mut self, pc: u32, span: Span) -> Result<bool, Diagnostic> {
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
    pub(super) fn comment(&mut self, command: &CommentCommand, span: Span) {
        match command {
            CommentCommand::Debug(items) => {
                let line = self.st.format_message(self.program, items);
                self.st.prints.push(line);
            }
            CommentCommand::Msg(text) => self.st.prints.push(text.clone()),
            CommentCommand::LogOpen { file, append } => {
                self.st.logs.push(LogFile { name: file.clone(), append: *append, lines: Vec::new() });
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
}

impl State {
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
}
