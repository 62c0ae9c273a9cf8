//! The one error type of `cam`: what went wrong and the message a
//! machinist reads.

use std::fmt;

/// What went wrong, for callers that act on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// A tool SPEC that cannot be a cutter.
    Spec,
    /// Numbers that are not a drop-cutter grid.
    Grid,
    /// An option out of its range.
    Option,
    /// The surface lies nowhere under the region: nothing to cut.
    NothingToCut,
    /// A mapping or a picture that cannot make a relief.
    Relief,
    /// A file that is not probe data.
    Data,
    /// Probe data that cannot be levelled.
    Level,
    /// Probe readings no surface can be made from.
    Surface,
    /// A capture's data file that does not continue this capture.
    Capture,
    /// A simulated reading where the stylus finds no model.
    OffModel,
    /// The simulation's cell size is not a length.
    Resolution,
    /// The chord tolerance is not a length.
    ChordTolerance,
    /// The stock box or solid is empty or not finite.
    Stock,
    /// The toolpath has no motion.
    EmptyToolpath,
    /// The simulation grid would have more cells than allowed.
    TooManyCells,
    /// The simulation grid's memory could not be had.
    OutOfMemory,
    /// A move goes lower than a simulation grid keeps heights.
    HeightRange,
    /// A move has a coordinate that is not finite.
    NonFinite,
    /// Arcs split into more chords than can be indexed.
    TooManySegments,
    /// A move is made by a tool the table does not give.
    NoTool,
    /// The program uses more tools than one simulation tells apart.
    TooManyTools,
    /// No flutes.
    Flutes,
    /// The helix angle is not in `[0, 90°)`.
    Helix,
    /// The plane's angle is not in `[0, 90°)`.
    Angle,
    /// The depth of cut is not a positive number.
    Depth,
    /// The pick feed is not a number in its range.
    PickFeed,
    /// The passes do not overlap: the pick feed leaves an uncut strip.
    NoOverlap,
    /// The feed per tooth is not a number in its range.
    FeedPerTooth,
    /// The teeth's cuts do not overlap.
    FeedPerToothTooWide,
    /// The chip rises above the flutes.
    Reach,
    /// No material is removed.
    NoChip,
    /// The target cusp is negative or not a finite number.
    Target,
    /// A positive target cusp below the resolution of the computation.
    TargetBelowResolution,
    /// No positive pick feed leaves a cusp this small.
    Unreachable,
}

/// An error of this crate: its kind and the message a machinist reads.
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    /// What went wrong.
    pub kind: ErrorKind,
    /// What is wrong, in words.
    pub message: String,
    /// The line of the input to blame (from 1), where one is.
    pub line: Option<usize>,
    /// The column of the field to blame (in characters, from 1), where one
    /// is.
    pub column: Option<usize>,
}

impl Error {
    /// An error of `kind` that says `message`.
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Error {
        Error { kind, message: message.into(), line: None, column: None }
    }

    /// An error of `kind` that says `message` about a line (from 1) and,
    /// where one is to blame, a column of it.
    pub fn at(kind: ErrorKind, line: Option<usize>, column: Option<usize>, message: impl Into<String>) -> Error {
        Error { kind, message: message.into(), line, column }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.line, self.column) {
            (Some(n), Some(c)) => write!(f, "line {n}, column {c}: {}", self.message),
            (Some(n), None) => write!(f, "line {n}: {}", self.message),
            _ => f.write_str(&self.message),
        }
    }
}

impl std::error::Error for Error {}
