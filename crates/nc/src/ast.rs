//! The program model: what the text says, with spans, evaluating nothing.
//!
//! Blocks, words and expressions live in flat arenas inside [`Program`] and
//! refer to each other by index, so parsing a million-block file makes a
//! handful of allocations rather than millions. Several files (a main program
//! and subprogram files) parse into one `Program`; `GOTO` and `WHILE` resolve
//! to block indices of the program unit they belong to.

mod pages;
use crate::paged::Paged;
use crate::source::{FileId, Span};
pub(crate) use pages::PageInfo;
pub use pages::PAGE_BLOCKS;

/// Index of an expression in [`Program::exprs`].
pub type ExprId = u32;

/// A Custom Macro B expression.
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    /// A literal number.
    Number(f64),
    /// `#n` or `#[expr]`: the variable whose number is the expression's value.
    Var(ExprId),
    /// `#<name>`: a LinuxCNC named parameter, its name in lower case
    /// without blanks (`#<_x>` reads a predefined one).
    Named(String),
    /// `EXISTS[#<name>]` (LinuxCNC): 1 when the named parameter is set.
    Exists(String),
    /// Unary minus.
    Neg(ExprId),
    /// A binary operator.
    Binary(BinOp, ExprId, ExprId),
    /// A function with one argument, or two (`ATAN[a]/[b]`, `ATAN[a,b]`, `POW[a,b]`).
    Call(Func, ExprId, Option<ExprId>),
}

/// Binary operators, by Fanuc precedence group.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinOp {
    /// `*`
    Mul,
    /// `/`
    Div,
    /// `AND` (bitwise on integers, logical on conditions)
    And,
    /// `MOD`
    Mod,
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `OR`
    Or,
    /// `XOR`
    Xor,
    /// `EQ`
    Eq,
    /// `NE`
    Ne,
    /// `GT`
    Gt,
    /// `GE`
    Ge,
    /// `LT`
    Lt,
    /// `LE`
    Le,
    /// `**` (LinuxCNC): power, binding tightest.
    Pow,
}

impl BinOp {
    /// Binding strength on a Fanuc control: 3 for `* / AND MOD`, 2 for
    /// `+ - OR XOR`, 1 for comparisons (`**` is LinuxCNC's: 4).
    pub fn precedence(self) -> u8 {
        use BinOp::*;
        match self {
            Pow => 4,
            Mul | Div | And | Mod => 3,
            Add | Sub | Or | Xor => 2,
            Eq | Ne | Gt | Ge | Lt | Le => 1,
        }
    }

    /// Binding strength in `dialect`. LinuxCNC (rs274ngc) binds `**`
    /// tightest (5), then `* / MOD` (4), `+ -` (3), the comparisons (2),
    /// and the logical `AND OR XOR` loosest (1); the others read as Fanuc.
    pub fn precedence_in(self, dialect: crate::Dialect) -> u8 {
        use BinOp::*;
        if dialect != crate::Dialect::LinuxCnc {
            return self.precedence();
        }
        match self {
            Pow => 5,
            Mul | Div | Mod => 4,
            Add | Sub => 3,
            Eq | Ne | Gt | Ge | Lt | Le => 2,
            And | Or | Xor => 1,
        }
    }

    /// The operator as written in a program.
    pub fn text(self) -> &'static str {
        use BinOp::*;
        match self {
            Mul => "*",
            Div => "/",
            And => "AND",
            Mod => "MOD",
            Add => "+",
            Sub => "-",
            Or => "OR",
            Xor => "XOR",
            Eq => "EQ",
            Ne => "NE",
            Gt => "GT",
            Ge => "GE",
            Lt => "LT",
            Le => "LE",
            Pow => "**",
        }
    }

    /// All operators spelled as keywords, with their spelling.
    pub const KEYWORDS: [(&'static str, BinOp); 10] = [
        ("AND", BinOp::And),
        ("MOD", BinOp::Mod),
        ("OR", BinOp::Or),
        ("XOR", BinOp::Xor),
        ("EQ", BinOp::Eq),
        ("NE", BinOp::Ne),
        ("GT", BinOp::Gt),
        ("GE", BinOp::Ge),
        ("LT", BinOp::Lt),
        ("LE", BinOp::Le),
    ];
}

/// Macro functions. Angles are in degrees, as on the control.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Func {
    /// `SIN`
    Sin,
    /// `COS`
    Cos,
    /// `TAN`
    Tan,
    /// `ASIN`
    Asin,
    /// `ACOS`
    Acos,
    /// `ATAN` (one argument, or two: `ATAN[y]/[x]` or `ATAN[y,x]`)
    Atan,
    /// `SQRT`
    Sqrt,
    /// `ABS`
    Abs,
    /// `ROUND` (half away from zero)
    Round,
    /// `FIX` (toward zero)
    Fix,
    /// `FUP` (away from zero)
    Fup,
    /// `LN`
    Ln,
    /// `EXP`
    Exp,
    /// `POW[base, exponent]`
    Pow,
    /// `BIN` (BCD to binary)
    Bin,
    /// `BCD` (binary to BCD)
    Bcd,
}

impl Func {
    /// Every function with its spelling; longer names first where one is a
    /// prefix of another.
    pub const ALL: [(&'static str, Func); 16] = [
        ("ASIN", Func::Asin),
        ("ACOS", Func::Acos),
        ("ATAN", Func::Atan),
        ("SIN", Func::Sin),
        ("COS", Func::Cos),
        ("TAN", Func::Tan),
        ("SQRT", Func::Sqrt),
        ("ABS", Func::Abs),
        ("ROUND", Func::Round),
        ("FIX", Func::Fix),
        ("FUP", Func::Fup),
        ("LN", Func::Ln),
        ("EXP", Func::Exp),
        ("POW", Func::Pow),
        ("BIN", Func::Bin),
        ("BCD", Func::Bcd),
    ];

    /// The function's name as written.
    pub fn name(self) -> &'static str {
        Func::ALL.iter().find(|(_, f)| *f == self).map_or("?", |(n, _)| n)
    }
}

/// The value part of a word.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WordValue {
    /// A literal; `decimal` tells whether it was written with a decimal point.
    Number {
        /// The number as written (not yet scaled by any input increment).
        value: f64,
        /// Written with a decimal point.
        decimal: bool,
    },
    /// A macro expression (`#1`, `-#1`, `[#1+2]`).
    Expr(ExprId),
}

/// An address letter with its value: `X10.`, `G#1`, `F[#9*2]`.
///
/// Stored in 16 bytes: a million-block program holds millions of words, and
/// where fresh memory is slow to touch (as on the benchmark machine, see
/// BENCHMARKS.md) their size shows in the parse time. So the value is read
/// through [`Word::value`], and the span through [`Word::span`] with the file
/// of the block the word belongs to.
#[derive(Clone, Copy)]
pub struct Word {
    /// The address, an upper-case ASCII letter (or LinuxCNC's polar `@`, `^`).
    pub letter: u8,
    kind: WordKind,
    /// Length of the word's text in bytes (capped at `u16::MAX`).
    len: u16,
    /// Offset of the word's first byte in its file.
    start: u32,
    /// The number's bits, or the expression id.
    bits: u64,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum WordKind {
    Integer,
    Decimal,
    Expr,
}

impl Word {
    /// A word from its address, value and span (whose file is not kept).
    pub fn new(letter: u8, value: WordValue, span: Span) -> Word {
        let (bits, kind) = match value {
            WordValue::Number { value, decimal: false } => (value.to_bits(), WordKind::Integer),
            WordValue::Number { value, decimal: true } => (value.to_bits(), WordKind::Decimal),
            WordValue::Expr(e) => (u64::from(e), WordKind::Expr),
        };
        let len = span.end.saturating_sub(span.start).min(u32::from(u16::MAX)) as u16;
        Word { letter, kind, len, start: span.start, bits }
    }

    /// The value.
    #[inline]
    pub fn value(&self) -> WordValue {
        match self.kind {
            WordKind::Expr => WordValue::Expr(self.bits as ExprId),
            kind => WordValue::Number { value: f64::from_bits(self.bits), decimal: kind == WordKind::Decimal },
        }
    }

    /// Where the word is written, in `file`: the file of its block.
    #[inline]
    pub fn span(&self, file: FileId) -> Span {
        Span { file, start: self.start, end: self.start + u32::from(self.len) }
    }
}

impl PartialEq for Word {
    fn eq(&self, other: &Word) -> bool {
        self.letter == other.letter
            && self.value() == other.value()
            && (self.start, self.len) == (other.start, other.len)
    }
}

impl std::fmt::Debug for Word {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Word")
            .field("letter", &self.letter)
            .field("value", &self.value())
            .field("bytes", &(self.start..self.start + u32::from(self.len)))
            .finish()
    }
}

/// One item of a `DPRNT[...]` statement.
#[derive(Clone, Debug, PartialEq)]
pub enum PrintItem {
    /// Literal characters.
    Text(String),
    /// `#var[ab]`: a variable printed with `a` integer and `b` fraction digits.
    Var {
        /// The variable number expression.
        var: ExprId,
        /// Integer digits.
        int_digits: u8,
        /// Fraction digits.
        frac_digits: u8,
    },
}

/// What a block says.
#[derive(Clone, Debug, PartialEq)]
pub enum Statement {
    /// A block of NC words; `words` indexes [`Program::words`].
    Words {
        /// First word.
        start: u32,
        /// Number of words.
        len: u32,
    },
    /// `#var = value`.
    Assign {
        /// The variable number expression (the part after `#`).
        var: ExprId,
        /// The value.
        value: ExprId,
    },
    /// `GOTO n`.
    Goto(ExprId),
    /// `IF [cond] GOTO n`.
    IfGoto {
        /// The condition.
        cond: ExprId,
        /// The sequence number to jump to.
        target: ExprId,
    },
    /// `IF [cond] THEN #var = value`.
    IfThen {
        /// The condition.
        cond: ExprId,
        /// The variable number expression.
        var: ExprId,
        /// The value.
        value: ExprId,
    },
    /// `WHILE [cond] DO m`.
    While {
        /// The condition.
        cond: ExprId,
        /// The loop identifier m (1..3).
        label: u8,
    },
    /// `DO m` without `WHILE`: an endless loop.
    Do {
        /// The loop identifier m (1..3).
        label: u8,
    },
    /// `END m`.
    End {
        /// The loop identifier m (1..3).
        label: u8,
    },
    /// `POPEN`: open the output channel.
    Popen,
    /// `PCLOS`: close the output channel.
    Pclos,
    /// `DPRNT[...]`: print a line.
    Dprnt(Vec<PrintItem>),
    /// Several LinuxCNC parameter settings on one line (`#1=2 #2=[#1+1]`):
    /// every value is read before any is set, as rs274ngc does.
    Assigns(Vec<(ExprId, ExprId)>),
    /// A LinuxCNC O-word: subroutines and structured control flow.
    OWord(Box<OWord>),
    /// A LinuxCNC comment command alone on its line: `(debug,…)`,
    /// `(msg,…)`, `(log,…)` ….
    Comment(CommentCommand),
    /// A LinuxCNC line of more than one kind of thing: parameter settings,
    /// words and a comment command. rs274ngc reads every value of the line
    /// first (the words' and the settings', left to right), then sets the
    /// parameters, then runs the comment, then the words.
    Line(Box<Line>),
    /// Something recognised but not executed yet (LinuxCNC O-words, GRBL `$`
    /// commands, `BPRNT`); the text says what.
    Unsupported(String),
    /// Nothing but comments, a sequence number or an empty line.
    Empty,
}

/// A LinuxCNC comment that does something: the last comment of a line is
/// the one LinuxCNC reads.
#[derive(Clone, Debug, PartialEq)]
pub enum CommentCommand {
    /// `(debug,…)` or `(print,…)`: a line for the report, with `#n` and
    /// `#<name>` replaced by their values.
    Debug(Vec<PrintItem>),
    /// `(msg,…)`: a line for the report, as written.
    Msg(String),
    /// `(logopen,FILE)` (`append` false) or `(logappend,FILE)`.
    LogOpen {
        /// The file name, as written.
        file: String,
        /// `logappend`: add to the file rather than start it afresh.
        append: bool,
    },
    /// `(logclose)`.
    LogClose,
    /// `(log,…)`: a line for the open log file, parameters replaced as in
    /// `debug`.
    Log(Vec<PrintItem>),
}

/// A LinuxCNC line of settings, words and a comment command.
#[derive(Clone, Debug, PartialEq)]
pub struct Line {
    /// The parameter settings `#n=…`, `#<name>=…`, in order, each with
    /// the number of the line's words written before it.
    pub settings: Vec<(ExprId, ExprId, u32)>,
    /// The first word in [`Program::words`].
    pub start: u32,
    /// Number of words.
    pub len: u32,
    /// The comment command, if the line's last comment is one.
    pub comment: Option<CommentCommand>,
}

/// The name of a LinuxCNC O-word: `o100`, `o<name>`, or `o#1`, `o[#2+1]`
/// computed when the block runs.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum OName {
    /// `o100`; a computed label may read a negative number (rs274ngc's
    /// labels are C `int`s).
    Number(i64),
    /// `o<name>`, in lower case without blanks (as rs274ngc reads it).
    Named(String),
    /// `o#1`, `o[#2+1]`: the expression (in [`OWord::label`]) as written,
    /// in lower case without blanks, for messages and for telling whether
    /// a `while` closes a `do` (their labels written the same). Never a
    /// key of the interpreter's tables: it reads the number first.
    Computed(String),
}

impl OName {
    /// The stem of the file that holds the subroutine in the library:
    /// `name` for `o<name>`, `123` for `o123`.
    pub fn file_stem(&self) -> String {
        match self {
            OName::Number(n) => n.to_string(),
            OName::Named(s) | OName::Computed(s) => s.clone(),
        }
    }

    /// Whether the label is computed when its block runs (`o#1`, `o[…]`).
    pub fn is_computed(&self) -> bool {
        matches!(self, OName::Computed(_))
    }

    /// Whether two labels may name the same construct once the run reads
    /// them: equal, or one of them computed.
    pub fn may_match(&self, other: &OName) -> bool {
        self == other || self.is_computed() || other.is_computed()
    }
}

impl std::fmt::Display for OName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            OName::Number(n) => write!(f, "o{n}"),
            OName::Named(s) => write!(f, "o<{s}>"),
            OName::Computed(s) => write!(f, "o{s}"),
        }
    }
}

/// Block index of a partner not known yet (patched when it is read).
pub const UNLINKED: u32 = u32::MAX;

/// A LinuxCNC O-word statement. The block indices of its partners (the
/// `endsub` of a `sub`, the `endif` of an `if`, …) are found by the parser
/// within the file, so a program whose O-words do not match is refused
/// before it runs. A computed label (`o#1 if`) is paired by nesting and
/// checked against its partner's when the run reads it (`parse::oword`
/// tells how).
#[derive(Clone, Debug, PartialEq)]
pub struct OWord {
    /// `o100`, `o<name>`, or `o#1` computed.
    pub name: OName,
    /// The expression of a computed label (`o#1 call`, `o[#2+1] if`), read
    /// when the block runs, as rs274ngc reads it; `name` is then
    /// [`OName::Computed`].
    pub label: Option<ExprId>,
    /// What it does.
    pub flow: Flow,
}

/// What an O-word does; `u32` fields are block indices in [`Program::blocks`].
#[derive(Clone, Debug, PartialEq)]
pub enum Flow {
    /// `sub`: the start of a definition, skipped to after its `endsub`
    /// where it is read.
    Sub {
        /// The `endsub`.
        end: u32,
    },
    /// `endsub [value]`: the end of a definition, a return.
    EndSub {
        /// The value returned (`#<_value>`).
        value: Option<ExprId>,
    },
    /// `return [value]`.
    Return {
        /// The value returned (`#<_value>`).
        value: Option<ExprId>,
    },
    /// `call [a] [b] …`: the arguments go to #1, #2, … of the subroutine.
    Call {
        /// The arguments, at most 30.
        args: Vec<ExprId>,
    },
    /// `if [cond]`.
    If {
        /// The condition.
        cond: ExprId,
        /// The first `elseif`, `else` or the `endif`.
        next: u32,
        /// The `endif`.
        end: u32,
    },
    /// `elseif [cond]`.
    ElseIf {
        /// The condition.
        cond: ExprId,
        /// The `if` it belongs to.
        start: u32,
        /// The next `elseif`, `else` or the `endif`.
        next: u32,
    },
    /// `else`.
    Else {
        /// The `if` it belongs to.
        start: u32,
    },
    /// `endif`.
    EndIf {
        /// The `if` it ends.
        start: u32,
    },
    /// `while [cond]` that opens a loop.
    While {
        /// The condition.
        cond: ExprId,
        /// The `endwhile`.
        end: u32,
    },
    /// `endwhile`.
    EndWhile {
        /// The `while`.
        start: u32,
    },
    /// `do`.
    Do {
        /// The closing `while`.
        end: u32,
    },
    /// `while [cond]` that closes a `do` loop.
    DoWhile {
        /// The condition.
        cond: ExprId,
        /// The `do`.
        start: u32,
    },
    /// `repeat [count]`.
    Repeat {
        /// How many times (rounded to the nearest whole number).
        count: ExprId,
        /// The `endrepeat`.
        end: u32,
    },
    /// `endrepeat`.
    EndRepeat {
        /// The `repeat`.
        start: u32,
    },
    /// `break`: leaves the loop of the same name.
    Break {
        /// The loop's first block (`while`, `do` or `repeat`), or
        /// [`UNLINKED`] where the run finds it by the label it reads: a
        /// computed label, or a written one that names no loop written
        /// around it while a loop of a computed label is.
        start: u32,
    },
    /// `continue`: the next turn of the loop of the same name.
    Continue {
        /// The loop's first block, or [`UNLINKED`] as for `break`.
        start: u32,
    },
}

impl Flow {
    /// The keyword, as written.
    pub fn keyword(&self) -> &'static str {
        match self {
            Flow::Sub { .. } => "sub",
            Flow::EndSub { .. } => "endsub",
            Flow::Return { .. } => "return",
            Flow::Call { .. } => "call",
            Flow::If { .. } => "if",
            Flow::ElseIf { .. } => "elseif",
            Flow::Else { .. } => "else",
            Flow::EndIf { .. } => "endif",
            Flow::While { .. } | Flow::DoWhile { .. } => "while",
            Flow::EndWhile { .. } => "endwhile",
            Flow::Do { .. } => "do",
            Flow::Repeat { .. } => "repeat",
            Flow::EndRepeat { .. } => "endrepeat",
            Flow::Break { .. } => "break",
            Flow::Continue { .. } => "continue",
        }
    }
}

/// One line of the program.
#[derive(Clone, Debug, PartialEq)]
pub struct Block {
    /// The whole block.
    pub span: Span,
    /// 1-based line in its file.
    pub line: u32,
    /// The `N` sequence number, if any.
    pub number: Option<u32>,
    /// Starts with `/` (optional block skip).
    pub delete: bool,
    /// What it says.
    pub statement: Statement,
}

/// One `O` program (or the unnamed main program before the first `O`).
#[derive(Clone, Debug, PartialEq)]
pub struct ProgramUnit {
    /// The program number, `None` for the unnamed program at the top of a file.
    pub number: Option<u32>,
    /// The comment on the `O` line, if any.
    pub title: Option<String>,
    /// Where the `O` word is (or the first block).
    pub span: Span,
    /// Its blocks: indices into [`Program::blocks`].
    pub blocks: std::ops::Range<u32>,
    /// Whether the tape's closing `%` ends it (the file opened with `%`):
    /// a program that runs to that `%` ends there, M2 or not.
    pub closed_by_percent: bool,
}

/// Everything parsed so far: one or more files of program units.
///
/// A program read whole holds every block. One read in pages
/// ([`Program::read_in_pages`]) holds those its pages of plain blocks
/// (words only) need now, and reads a dropped page again from its text
/// when the run comes back to it ([`Program::ensure`]); numbers of blocks,
/// words and expressions never change.
#[derive(Clone, Debug, Default)]
pub struct Program {
    /// Program units in the order they were parsed.
    pub units: Vec<ProgramUnit>,
    /// All blocks.
    pub blocks: Paged<Block>,
    /// All words of all `Words` blocks.
    pub words: Paged<Word>,
    /// All expressions.
    pub exprs: Paged<Expr>,
    /// Where each page was read from, and which may be dropped.
    pub(crate) pages: pages::Pages,
}

impl Program {
    /// The words of a block (empty for macro statements).
    pub fn words(&self, block: &Block) -> &[Word] {
        match block.statement {
            Statement::Words { start, len } => self.words.slice(start as usize..(start + len) as usize),
            Statement::Line(ref l) => self.words.slice(l.start as usize..(l.start + l.len) as usize),
            _ => &[],
        }
    }

    /// The unit with program number `number`.
    pub fn unit(&self, number: u32) -> Option<usize> {
        self.units.iter().position(|u| u.number == Some(number))
    }

    /// Appends an expression and returns its id.
    pub fn push_expr(&mut self, e: Expr) -> ExprId {
        self.exprs.push(e);
        (self.exprs.len() - 1) as ExprId
    }
}
