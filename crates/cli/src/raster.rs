//! The rows of a raster on the command line: their direction and how they
//! are linked (`--direction`, `--pattern` of `mill` and `relief`).

use anyhow::{bail, Result};
use clap::ValueEnum;
use kezuri_cam::mill::{Direction, Pattern};
use kezuri_cam::Cutter;

/// The cutter of raster rows from its SPEC: a drill (`drill:D,ANGLE`) is
/// refused, as the rows would feed it sideways.
pub fn row_cutter(spec: &str) -> Result<Cutter> {
    let cutter: Cutter = spec.parse()?;
    if cutter.is_drill() {
        bail!(
            "tool '{spec}': a drill cuts along its axis only and the rows would feed it sideways: give an end mill \
             or a V-bit (v:D,ANGLE)"
        );
    }
    Ok(cutter)
}

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
