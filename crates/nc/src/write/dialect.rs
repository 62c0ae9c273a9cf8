//! The dialects the writer speaks and the words that differ between them.

use std::fmt;
use std::str::FromStr;

use crate::{Error, ErrorKind};

/// An NC dialect the writer speaks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Dialect {
    /// Fanuc (ISO): `%` first and last line, `O` number, two-digit codes
    /// (`G01`, `M03`), `G04 P` in ms, `G31`.
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

impl FromStr for Dialect {
    type Err = Error;

    /// Reads `fanuc`, `linuxcnc` or `grbl`, in any letter case.
    fn from_str(s: &str) -> Result<Dialect, Error> {
        Dialect::ALL.into_iter().find(|d| d.name().eq_ignore_ascii_case(s)).ok_or_else(|| {
            Error::new(ErrorKind::UnknownDialect, format!("unknown dialect '{s}': expected fanuc, linuxcnc or grbl"))
        })
    }
}

/// The words that differ between dialects ([`Dialect::codes`]), for
/// programs kezuri writes as text.
#[derive(Debug)]
pub struct Codes {
    /// Rapid, feed, clockwise and counter-clockwise arc (`G00`…`G03`).
    pub motion: [&'static str; 4],
    pub(super) plane: [&'static str; 3],
    pub(super) dwell: &'static str,
    pub(super) probe: &'static str,
    pub(super) spindle: [&'static str; 3],
    pub(super) tool_change: &'static str,
    pub(super) optional_stop: &'static str,
    /// Mist coolant, or the air blow (`M07`).
    pub mist: &'static str,
    pub(super) flood: &'static str,
    /// Coolant off (`M09`).
    pub coolant_off: &'static str,
    pub(super) home: &'static str,
    pub(super) length: [&'static str; 2],
    pub(super) length_cancel: &'static str,
    pub(super) end: &'static str,
}

static FANUC: Codes = Codes {
    motion: ["G00", "G01", "G02", "G03"],
    plane: ["G17", "G18", "G19"],
    dwell: "G04",
    probe: "G31",
    spindle: ["M05", "M03", "M04"],
    tool_change: "M06",
    optional_stop: "M01",
    mist: "M07",
    flood: "M08",
    coolant_off: "M09",
    home: "G28",
    length: ["G43", "G44"],
    length_cancel: "G49",
    end: "M30",
};

static SHORT: Codes = Codes {
    motion: ["G0", "G1", "G2", "G3"],
    plane: ["G17", "G18", "G19"],
    dwell: "G4",
    probe: "G38.2",
    spindle: ["M5", "M3", "M4"],
    tool_change: "M6",
    optional_stop: "M1",
    mist: "M7",
    flood: "M8",
    coolant_off: "M9",
    home: "G28",
    length: ["G43", "G44"],
    length_cancel: "G49",
    end: "M2",
};

impl Dialect {
    /// The dialect's words: `G00 M07` (Fanuc) or `G0 M7`.
    pub fn codes(self) -> &'static Codes {
        match self {
            Dialect::Fanuc => &FANUC,
            Dialect::LinuxCnc | Dialect::Grbl => &SHORT,
        }
    }
}
