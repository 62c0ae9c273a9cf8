//! The one error type of this crate.

use std::fmt;

/// What went wrong, for callers that act on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// A picture wider or taller than the largest side a PNG may have.
    PictureTooLarge,
    /// A picture with no pixels (a side of zero).
    EmptyPicture,
    /// SVG text that cannot be read as a picture.
    BadSvg,
    /// The PNG encoder failed.
    PngEncoding,
    /// A position too far from the middle of the program to be packed.
    PositionOutOfReach,
    /// More tools than the page can tell apart.
    TooManyTools,
    /// A page larger than the largest page allowed.
    PageTooLarge,
}

/// An error of this crate: its kind and the message a machinist reads.
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    /// What went wrong.
    pub kind: ErrorKind,
    /// What went wrong, in words.
    pub message: String,
}

impl Error {
    /// An error of `kind` saying `message`.
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Error {
        Error { kind, message: message.into() }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Error {}
