//! The one error of the crate: what went wrong, the message a machinist
//! reads, and, for a program's moves, the line of the move.

use std::fmt;

/// What went wrong, for callers that act on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// A line-sensor profile has fewer points than two sides need.
    TooFewPoints,
    /// A point of a profile is not a finite number.
    NotFinite,
    /// The given split leaves a side of the profile with fewer than 3 points.
    BadSplit,
    /// The profile's two sides are parallel: no corner.
    NoCorner,
    /// Too few measurements for the polynomial degree asked.
    TooFewMeasurements,
    /// A measurement is not finite, names no linear axis or its state is
    /// neither cold nor warm.
    BadMeasurement,
    /// A warm measurement has no cold one at the same axis, angle and command.
    NoColdMeasurement,
    /// A model file is not one `kezuri thermal fit` writes.
    NotAModel,
    /// The thermal model has no error function for an axis at a B angle.
    NoErrorFunction,
    /// The linear axes do not span space at a command.
    Singular,
    /// Newton's method did not reach the corrected command to 1 nm.
    NotConverged,
    /// The kinematic chains are not a machine.
    BadKinematics,
    /// The microscope's pictures are missing, too small or of mixed sizes.
    BadPictures,
    /// The pictures show no tool.
    NoTool,
    /// The tool's edges leave the pictures at its tip.
    ToolOutOfView,
    /// The tool-length reference row is outside the pictures.
    TipRowOutside,
    /// The silhouette gives no tool profile.
    BadProfile,
    /// The stitching search asked for would take too long.
    SearchTooWide,
    /// Fields of view do not overlap.
    NoOverlap,
    /// The measured tool's profile is shorter than the part of the tool that cuts.
    ProfileTooShort,
    /// A work or tool offset is in force where the surface is in program coordinates.
    OffsetInForce,
    /// More of a program's points than allowed lie beyond the measured range
    /// of their axis's error function.
    Extrapolated,
    /// A thermal model was fitted on a machine with other kinematic chains.
    OtherMachine,
    /// No command puts the tool where the correction asks.
    Unreachable,
}

/// An error of this crate: its kind and the message a machinist reads.
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    /// What went wrong.
    pub kind: ErrorKind,
    /// What the machinist reads.
    pub message: String,
    /// The program line of the move it concerns, where a program's moves
    /// are corrected.
    pub line: Option<u32>,
}

impl Error {
    /// An error of `kind` saying `message`.
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Error {
        Error { kind, message: message.into(), line: None }
    }

    /// The same error, about the move of program line `line`.
    pub fn at_line(self, line: u32) -> Error {
        Error { line: Some(line), ..self }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Error {}
