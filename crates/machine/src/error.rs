//! The crate's one error type.

use std::fmt;

/// What went wrong, for callers that act on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// A file the machine file or a tool library names cannot be read.
    Unreadable,
    /// Text that is not what its format says: TOML, JSON, a zip archive,
    /// a line of a tool table.
    Syntax,
    /// A value the machine, its post or a tool table cannot have.
    Invalid,
    /// A tool file kezuri does not read: its name says no format kezuri
    /// knows, or it is another version or kind of file than its name says.
    UnknownFormat,
    /// A LinuxCNC tool table read without the units it does not carry.
    NoUnits,
    /// A post (controller preset) that does not exist.
    UnknownPost,
}

/// An error of this crate: its kind and the message a machinist reads.
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    /// What went wrong.
    pub kind: ErrorKind,
    /// The message, with where it happened in front (`tools.import: …`).
    pub message: String,
}

impl Error {
    /// An error of `kind` saying `message`.
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Error {
        Error { kind, message: message.into() }
    }

    /// This error under `what`: `what: message`, its kind kept.
    pub(crate) fn context(self, what: impl fmt::Display) -> Error {
        Error { kind: self.kind, message: format!("{what}: {}", self.message) }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Error {}

/// A result of this crate.
pub type Result<T> = std::result::Result<T, Error>;

/// An error of another crate and its sources, as one line (`error: source: …`).
pub(crate) fn with_sources(e: &dyn std::error::Error) -> String {
    let mut line = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        line += &format!(": {s}");
        source = s.source();
    }
    line
}

/// Returns an error of the kind named, its message formatted.
macro_rules! fail {
    ($kind:ident, $($message:tt)+) => {
        return Err($crate::Error::new($crate::ErrorKind::$kind, format!($($message)+)))
    };
}
pub(crate) use fail;
