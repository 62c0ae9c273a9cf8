//! Toolpath to G-code program text: Fanuc, LinuxCNC and GRBL.
//!
//! [`program`] writes one block per line and only what changes: modal words
//! (the motion G code, the plane, `F`, `S`) are written when their value
//! changes, axis words when the rounded coordinate changes. Numbers are
//! rounded to [`WriteOptions::digits`] decimals and trailing zeros trimmed;
//! a Fanuc axis word always carries a decimal point (`X10.`, `X0.`), because
//! a Fanuc control reads `X10` as 10 increments (0.010 mm); LinuxCNC and
//! GRBL get `X10`. A rounded zero is written `0`, never `-0`. Programs are
//! in mm (`G21`), absolute (`G90`), feed per minute (`G94`).
//!
//! Decisions a reader might not guess:
//! - The program starts where a reader of it assumes the tool is: at zero on
//!   every axis, as kezuri's interpreter assumes. So the first move writes
//!   only the axes it moves from there, and an axis the source program never
//!   commanded is not commanded either (an expanded program whose first
//!   block was `G00 X.. Y..` does not gain a `Z0.` that would dive from
//!   wherever the spindle is). The first move after a tool change writes
//!   every axis the program uses, and the motion code, the plane and `F`
//!   again: a Fanuc tool change macro may have moved the axes and changed
//!   modal words.
//! - Straight moves (rapid, feed, probe) go from wherever the tool is to
//!   their end: their start is not written. An arc needs its start, so an arc
//!   that does not start where the tool is (as the first move, after a tool
//!   change, or after a gap in the toolpath) is preceded by a straight feed
//!   move to its start.
//! - Arc centres are written as `I J K` relative to the start, as Fanuc,
//!   LinuxCNC and GRBL read them, rounded; when the rounded end then misses
//!   the circle by more than half a unit of the last digit or 0.001 mm, the
//!   centre is the one of the nine grid points around it that puts the end
//!   best on the circle (GRBL rejects an arc whose radii differ by 0.005 mm
//!   and 0.1 %).
//!   An arc whose rounded end equals its start is a full circle if it sweeps
//!   more than half a turn, otherwise it is too small for the digits and is
//!   written as a straight move; so is an arc that rounding would turn the
//!   other way round. Extra helical turns ([`kezuri_geom::Arc::turns`]) are
//!   written as one full circle per turn.
//! - A move that changes nothing at the written precision writes nothing.
//! - Spindle, coolant and tool changes are written on their own blocks before
//!   the move that needs them, one M code per block (a Fanuc control without
//!   the multiple-M option accepts only one). A tool change stops the spindle
//!   and the coolant first (`M05`, `M09`) and they are switched on again for
//!   the next move. GRBL has no tool changer: there a tool change is a
//!   comment naming the tool and an `M0` pause, to change the tool by hand
//!   and resume.
//! - Mist coolant is `M07`; GRBL accepts `M7` only when built with
//!   `ENABLE_M7`.
//! - Probe moves are `G31` (Fanuc) or `G38.2` (LinuxCNC, GRBL); the motion G
//!   code is written again on the move after.
//! - Dwells are `G04 P<milliseconds>` (Fanuc) or `G4 P<seconds>`.
//! - `N` numbers, when asked for, count up by their step and start again at
//!   the step after 99999, the largest a Fanuc control reads.

use std::fmt;
use std::str::FromStr;

use kezuri_geom::{MoveKind, Toolpath};

use super::blocks::{Motion, Writer};

/// An NC dialect the writer speaks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Dialect {
    /// Fanuc (ISO): `%` first and last line, `O` number, a decimal point on
    /// every axis word, two-digit codes (`G01`, `M03`), `G04 P` in ms, `G31`.
    #[default]
    Fanuc,
    /// LinuxCNC: short codes (`G1`, `M3`), `G4 P` in seconds, `G38.2`.
    LinuxCnc,
    /// GRBL 1.1: as LinuxCNC, without rotary axes and without a tool changer.
    Grbl,
}

impl Dialect {
    /// Every dialect, in the order of their names in the documentation.
    pub const ALL: [Dialect; 3] = [Dialect::Fanuc, Dialect::LinuxCnc, Dialect::Grbl];

    /// The lower-case name: `fanuc`, `linuxcnc` or `grbl`.
    pub fn name(self) -> &'static str {
        match self {
            Dialect::Fanuc => "fanuc",
            Dialect::LinuxCnc => "linuxcnc",
            Dialect::Grbl => "grbl",
        }
    }
}

impl fmt::Display for Dialect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A dialect name that is not `fanuc`, `linuxcnc` or `grbl`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownDialect(pub String);

impl fmt::Display for UnknownDialect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "unknown dialect '{}': expected fanuc, linuxcnc or grbl", self.0)
    }
}

impl std::error::Error for UnknownDialect {}

impl FromStr for Dialect {
    type Err = UnknownDialect;

    /// Reads `fanuc`, `linuxcnc` or `grbl`, in any letter case.
    fn from_str(s: &str) -> Result<Dialect, UnknownDialect> {
        Dialect::ALL.into_iter().find(|d| d.name().eq_ignore_ascii_case(s)).ok_or_else(|| UnknownDialect(s.to_string()))
    }
}

/// How [`program`] writes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WriteOptions {
    /// The dialect.
    pub dialect: Dialect,
    /// Decimals of mm (and degree) values, 0 to 6; trailing zeros are trimmed.
    pub digits: u8,
    /// `Some(step)`: number the blocks `N<step>`, `N<2·step>`, …;
    /// `None`: no `N` words.
    pub line_numbers: Option<u32>,
    /// The Fanuc program number `O…`, 1 to 9999 (other dialects have none).
    pub program_number: u32,
    /// A title: the comment on the `O` line (Fanuc) or the first line.
    pub title: Option<String>,
}

impl Default for WriteOptions {
    /// Fanuc, 3 decimals, no `N` words, `O0001`, no title.
    fn default() -> WriteOptions {
        WriteOptions { dialect: Dialect::Fanuc, digits: 3, line_numbers: None, program_number: 1, title: None }
    }
}

/// Why a toolpath could not be written.
#[derive(Clone, Debug, PartialEq)]
pub enum WriteError {
    /// A [`WriteOptions`] field out of its range.
    Option {
        /// The field.
        name: &'static str,
        /// Its value.
        value: u32,
        /// Smallest value allowed.
        min: u32,
        /// Largest value allowed.
        max: u32,
    },
    /// A number no program can hold: not finite, 10⁹ or more in size, or
    /// negative where that means nothing (feed `F`, speed `S`, dwell `P`).
    Number {
        /// Index of the move in [`Toolpath::moves`].
        index: usize,
        /// Source line of the move (0 when generated).
        line: u32,
        /// The address the number was for (`X`, `I`, `F`, …).
        word: char,
        /// The number.
        value: f64,
    },
    /// A rotary axis is used in a dialect without rotary axes (GRBL).
    RotaryAxis {
        /// Index of the move in [`Toolpath::moves`].
        index: usize,
        /// Source line of the move (0 when generated).
        line: u32,
        /// `A`, `B` or `C`.
        axis: char,
        /// The dialect.
        dialect: Dialect,
    },
}

impl fmt::Display for WriteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let at = |f: &mut fmt::Formatter<'_>, index: usize, line: u32| {
            write!(f, "move {}", index + 1)?;
            if line > 0 {
                write!(f, " (line {line})")?;
            }
            Ok(())
        };
        match self {
            WriteError::Option { name, value, min, max } => {
                write!(f, "{name} {value} is out of range: it must be {min} to {max}")
            }
            WriteError::Number { index, line, word, value } => {
                at(f, *index, *line)?;
                write!(f, ": {word}{value} cannot be written in a program")
            }
            WriteError::RotaryAxis { index, line, axis, dialect } => {
                at(f, *index, *line)?;
                write!(f, ": {dialect} has no rotary axis {axis}, but the toolpath turns it")
            }
        }
    }
}

impl std::error::Error for WriteError {}

/// Writes `toolpath` as a program in `options.dialect`.
///
/// ```
/// use kezuri_geom::{Axes, Move, MoveKind, Toolpath};
/// use kezuri_nc::write::{program, Dialect, WriteOptions};
/// let at = |x, y, z| Axes { x, y, z, ..Axes::ZERO };
/// let mut path = Toolpath::default();
/// path.push(Move { kind: MoveKind::Rapid, end: at(10.0, 0.0, 5.0), ..Move::default() });
/// let (start, end) = (at(10.0, 0.0, 5.0), at(10.0, 0.0, -0.5));
/// path.push(Move { kind: MoveKind::Feed, start, end, feed: 300.0, ..Move::default() });
/// let text = program(&path, &WriteOptions::default()).unwrap();
/// assert!(text.contains("G00 X10. Z5.\nG01 Z-0.5 F300.\n"));
/// let grbl = program(&path, &WriteOptions { dialect: Dialect::Grbl, ..WriteOptions::default() }).unwrap();
/// assert!(grbl.contains("G0 X10 Z5\nG1 Z-0.5 F300\n"));
/// ```
pub fn program(toolpath: &Toolpath, options: &WriteOptions) -> Result<String, WriteError> {
    let mut w = Writer::new(toolpath, options)?;
    w.header(options);
    for (index, m) in toolpath.moves.iter().enumerate() {
        w.at = (index, m.line);
        w.state(m)?;
        match m.kind {
            MoveKind::Rapid => w.straight(Some(Motion::Rapid), m.end, None)?,
            MoveKind::Feed => w.straight(Some(Motion::Linear), m.end, Some(m.feed))?,
            MoveKind::Probe => w.straight(None, m.end, Some(m.feed))?,
            MoveKind::Dwell(seconds) => w.dwell(seconds)?,
            MoveKind::Arc(arc) => w.arc(m, arc)?,
        }
    }
    Ok(w.finish())
}
