//! Post-processor presets: how a program kezuri makes begins, changes
//! tools and ends on a given control ([`Setup`]), and how any program is
//! formatted for it (the other fields of [`WriteOptions`]).
//!
//! Where each preset's conventions come from is in `docs/post.md`.

use std::collections::BTreeMap;
use std::fmt;

use super::gcode::{Dialect, WriteOptions};

/// How arcs are written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Arcs {
    /// `I J K`: the centre relative to the start.
    #[default]
    Ijk,
    /// `R`: the radius, negative for an arc of more than half a turn; a
    /// full circle is written as two half circles.
    Radius,
    /// Straight moves within one unit of the last digit of the arc.
    Lines,
}

/// How the tool is taken up before a tool change and at the end.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Retract {
    /// `G91 G28 Z0.` then `G90`: to the reference point through the
    /// present position.
    Reference,
    /// `G53 G00 Z0.` (in `G90`): to machine zero in Z.
    MachineZero,
    /// Nothing: the control's tool change takes the tool up itself, or the
    /// machine has no reference point (GRBL without homing).
    None,
}

/// Where X and Y go at the end of the program.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Home {
    /// `G91 G28 X0. Y0.` then `G90`.
    Reference,
    /// `G53 G00 X… Y…`: a park position in machine coordinates, mm.
    Park([f64; 2]),
    /// Left where the last move put them.
    None,
}

/// The coolant a made program turns on with the spindle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoolantChoice {
    /// `M08`.
    Flood,
    /// `M07`.
    Mist,
    /// None.
    Off,
}

/// How a program kezuri makes begins, changes tools and ends. Programs
/// kezuri transforms keep their own.
#[derive(Clone, Debug, PartialEq)]
pub struct Setup {
    /// The safe start codes, written after the units (`G21`/`G20`) on the
    /// first block.
    pub start: String,
    /// The work offset, written on the same block (`G54`; empty: none).
    pub work_offset: String,
    /// The retract before each tool change and at the end; `G90` always
    /// follows a `G91 G28`.
    pub retract: Retract,
    /// `T<next>` after each `M06`, so the changer fetches the next tool
    /// while this one cuts.
    pub prestage: bool,
    /// `M01` before each tool change after the first.
    pub optional_stop: bool,
    /// `G43 H<register>` on the first Z move after each tool change.
    pub length_offset: bool,
    /// The length register of each tool that has one other than its own
    /// number (H = T otherwise).
    pub registers: BTreeMap<u32, u32>,
    /// Dwell after the spindle starts, before the first move, seconds.
    pub spindle_dwell: f64,
    /// The coolant turned on with the spindle.
    pub coolant: CoolantChoice,
    /// Where X and Y go at the end.
    pub home: Home,
    /// The program end (`M30`, `M02`).
    pub end: String,
}

impl Setup {
    /// The length register (`H`) of `tool`.
    pub fn register(&self, tool: u32) -> u32 {
        self.registers.get(&tool).copied().unwrap_or(tool)
    }
}

/// The presets `--post` names.
pub const PRESETS: [&str; 5] = ["fanuc", "haas", "linuxcnc", "grbl", "mach3"];

/// A post name that is not a preset.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownPost(pub String);

impl fmt::Display for UnknownPost {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "unknown post '{}': expected {}", self.0, PRESETS.join(", "))
    }
}

impl std::error::Error for UnknownPost {}

impl WriteOptions {
    /// The options of preset `name` (any letter case): its dialect,
    /// formatting and [`Setup`]. Digits, units, title and line numbers are
    /// the defaults; the caller sets them.
    ///
    /// ```
    /// use kezuri_nc::write::{Retract, WriteOptions};
    /// let haas = WriteOptions::preset("Haas").unwrap();
    /// let setup = haas.setup.unwrap();
    /// assert!(setup.prestage && setup.length_offset && setup.retract == Retract::MachineZero);
    /// assert!(WriteOptions::preset("okuma").is_err());
    /// ```
    pub fn preset(name: &str) -> Result<WriteOptions, UnknownPost> {
        let name = name.trim().to_ascii_lowercase();
        let fanuc = Setup {
            start: "G90 G17 G94 G40 G49 G80".into(),
            work_offset: "G54".into(),
            retract: Retract::Reference,
            prestage: false,
            optional_stop: true,
            length_offset: true,
            registers: BTreeMap::new(),
            spindle_dwell: 0.0,
            coolant: CoolantChoice::Flood,
            home: Home::Reference,
            end: "M30".into(),
        };
        let (dialect, setup, dwell_ms, block_limit) = match name.as_str() {
            "fanuc" => (Dialect::Fanuc, fanuc, None, None),
            "haas" => (
                Dialect::Fanuc,
                Setup {
                    start: "G00 G17 G40 G49 G80 G90 G94".into(),
                    prestage: true,
                    retract: Retract::MachineZero,
                    home: Home::Park([0.0, 0.0]),
                    ..fanuc
                },
                None,
                None,
            ),
            "linuxcnc" => (
                Dialect::LinuxCnc,
                Setup {
                    start: "G90 G17 G94 G40 G49 G80 G91.1".into(),
                    retract: Retract::MachineZero,
                    home: Home::None,
                    spindle_dwell: 2.0,
                    coolant: CoolantChoice::Off,
                    end: "M2".into(),
                    ..fanuc
                },
                None,
                None,
            ),
            "grbl" => (
                Dialect::Grbl,
                Setup {
                    start: "G90 G17 G94".into(),
                    retract: Retract::None,
                    optional_stop: false,
                    length_offset: false,
                    home: Home::None,
                    spindle_dwell: 3.0,
                    coolant: CoolantChoice::Off,
                    end: "M2".into(),
                    ..fanuc
                },
                None,
                Some(80),
            ),
            "mach3" => (
                Dialect::LinuxCnc,
                Setup {
                    start: "G90 G17 G94 G40 G49 G80 G91.1".into(),
                    spindle_dwell: 2.0,
                    coolant: CoolantChoice::Off,
                    ..fanuc
                },
                Some(false),
                None,
            ),
            _ => return Err(UnknownPost(name)),
        };
        // Mach3 probes with G31 (it has no G38.2).
        let probe_code = (name == "mach3").then_some("G31");
        Ok(WriteOptions { dialect, setup: Some(setup), dwell_ms, block_limit, probe_code, ..WriteOptions::default() })
    }
}
