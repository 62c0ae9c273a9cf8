//! Expressions: variables, brackets, operators and functions.

use super::{named, LineParser, Result};
use crate::ast::{BinOp, Expr, ExprId, Func};
use crate::source::{Diagnostic, Span};
use crate::Dialect;

/// Deepest bracket nesting accepted (Fanuc allows five).
const MAX_DEPTH: u32 = 64;

/// Most operators in one block's expressions. Evaluation recurses along a
/// chain like `1+1+…+1`, so an unbounded chain would exhaust the stack.
const MAX_OPERATORS: u32 = 1000;

impl LineParser<'_> {
    /// `#n`, `#[expr]` or `#<name>`: returns the variable-number expression
    /// (for `#<name>`, a `Named` expression).
    pub(super) fn variable_number(&mut self) -> Result<ExprId> {
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
            // LinuxCNC reads `##n` as `#[#n]` (a parameter's number in
            // another parameter), to any depth; Fanuc needs the brackets.
            Some(b'#') if self.dialect == Dialect::LinuxCnc => {
                let n = self.variable_number()?;
                Ok(match self.program.exprs[n as usize] {
                    Expr::Named(_) => n,
                    _ => self.push(Expr::Var(n)),
                })
            }
            Some(b'#') => Err(self.error_here("write #[#n] for an indirect variable, not ##n")),
            _ => Err(Diagnostic::error(self.span(start), "expected a variable number or '[' after '#'")),
        }
    }

    pub(super) fn bracketed(&mut self) -> Result<ExprId> {
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
    pub(super) fn operand(&mut self) -> Result<ExprId> {
        self.skip_blanks();
        let e = self.unary()?;
        Ok(e)
    }

    pub(super) fn expr(&mut self, min_prec: u8) -> Result<ExprId> {
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

    pub(super) fn primary(&mut self) -> Result<ExprId> {
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
