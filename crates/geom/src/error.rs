//! The one error type of `geom`: what went wrong and the message a
//! machinist reads.

use std::fmt;

/// What went wrong, for callers that act on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// Numbers that are not a tool profile.
    Profile,
    /// Numbers that are not a height grid.
    Heightfield,
    /// Bytes that are not an STL mesh (or one with no triangle that has an
    /// area).
    Stl,
}

/// An error of this crate: its kind and the message a machinist reads.
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    /// What went wrong.
    pub kind: ErrorKind,
    /// What is wrong, in words.
    pub message: String,
    /// The sample of a tool profile to blame (0-based), where one is.
    pub sample: Option<usize>,
    /// The line and column (from 1) of a text file to blame, where one is.
    pub at: Option<(usize, usize)>,
}

impl Error {
    /// An error of `kind` that says `message`.
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Error {
        Error { kind, message: message.into(), sample: None, at: None }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.sample, self.at) {
            (Some(i), _) => write!(f, "sample {}: {}", i + 1, self.message),
            (None, Some((line, column))) => write!(f, "line {line}, column {column}: {}", self.message),
            (None, None) => f.write_str(&self.message),
        }
    }
}

impl std::error::Error for Error {}
