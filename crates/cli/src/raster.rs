//! The rows of a raster on the command line: their direction and how they
//! are linked (`--direction`, `--pattern` of `mill` and `relief`).

use clap::ValueEnum;
use kezuri_cam::mill::{Direction, Pattern};

/// Row directions on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum RowDirection {
    /// Rows along X.
    X,
    /// Rows along Y.
    Y,
    /// X rows, then Y rows.
    Both,
}

impl From<RowDirection> for Direction {
    fn from(d: RowDirection) -> Direction {
        match d {
            RowDirection::X => Direction::X,
            RowDirection::Y => Direction::Y,
            RowDirection::Both => Direction::Both,
        }
    }
}

/// Row linking on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum RowPattern {
    /// Alternate directions, linked along the surface.
    Zigzag,
    /// One direction, retract between rows.
    Oneway,
}

impl From<RowPattern> for Pattern {
    fn from(p: RowPattern) -> Pattern {
        match p {
            RowPattern::Zigzag => Pattern::ZigZag,
            RowPattern::Oneway => Pattern::OneWay,
        }
    }
}
