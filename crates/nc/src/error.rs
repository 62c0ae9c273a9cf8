//! The errors of nc's stages that give up: writing a toolpath as a program
//! (G-code or RML-1), cutter compensation's alarms, the measuring programs'
//! plans and the names of dialects and posts. Reading a program never fails:
//! what it cannot read is a [`Diagnostic`](crate::Diagnostic).

use std::fmt;

/// What went wrong, for callers that act on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// An option of the writer out of its range (`digits`, an RML unit).
    Option,
    /// A number no program can hold: not finite, too large, or negative
    /// where that means nothing (a feed, a speed, a dwell).
    Number,
    /// An axis the language has not: a rotary axis turned for GRBL or
    /// RML-1, U V W moved for Fanuc, GRBL or RML-1.
    RotaryAxis,
    /// A block or move the language has no words for: a kept block the
    /// dialect has not, a tapping cycle or a change of work offset in RML-1.
    Unsupported,
    /// The program breaks a limit of the control: its line buffer or its
    /// memory.
    Limit,
    /// RML-1: a rapid down needs a speed for its Z move, and there is no
    /// feed to give it.
    NoFeed,
    /// RML-1: a cutting move before the program named X and Y.
    UnknownPosition,
    /// Cutter radius compensation stops, as the control would alarm.
    Compensation,
    /// A measuring program's plan with a value it cannot have.
    Plan,
    /// A dialect name that is not `fanuc`, `linuxcnc` or `grbl`.
    UnknownDialect,
    /// A post name that is not a preset.
    UnknownPost,
}

/// Where in the work an [`Error`] is; [`Error`]'s text begins with it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Place {
    /// Nowhere in particular: an option, a plan, the whole program.
    None,
    /// A move of the toolpath being written: its index in
    /// [`Toolpath::moves`](kezuri_geom::Toolpath::moves) and its source line
    /// (0 when generated). Written `move 2 (line 5): `, counted from 1.
    Move {
        /// Index of the move.
        index: usize,
        /// Source line of the move (0 when generated).
        line: u32,
    },
    /// A source line: `line 5: `.
    Line(u32),
    /// One of the moves given to cutter compensation, by its index from 0:
    /// `move 3: `.
    Compensated(usize),
}

/// An error of this crate: its kind and the message a machinist reads.
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    /// What went wrong.
    pub kind: ErrorKind,
    /// The message, after the place.
    pub message: String,
    /// Where it went wrong.
    pub place: Place,
}

impl Error {
    /// An error of `kind` that is nowhere in particular.
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Error {
        Error { kind, message: message.into(), place: Place::None }
    }

    /// The error at `place`.
    pub fn at(self, place: Place) -> Error {
        Error { place, ..self }
    }

    /// The index of the move the error is at, where it is at one.
    pub fn move_index(&self) -> Option<usize> {
        match self.place {
            Place::Move { index, .. } | Place::Compensated(index) => Some(index),
            Place::None | Place::Line(_) => None,
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.place {
            Place::None => {}
            Place::Move { index, line } => {
                write!(f, "move {}", index + 1)?;
                if line > 0 {
                    write!(f, " (line {line})")?;
                }
                f.write_str(": ")?;
            }
            Place::Line(line) => write!(f, "line {line}: ")?,
            Place::Compensated(index) => write!(f, "move {index}: ")?,
        }
        f.write_str(&self.message)
    }
}

impl std::error::Error for Error {}
