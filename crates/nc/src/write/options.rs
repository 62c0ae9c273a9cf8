//! How a toolpath is written: [`WriteOptions`], and the [`Setup`] of a
//! program kezuri makes (its start, tool changes and end).

use std::collections::BTreeMap;

use super::dialect::Dialect;

/// How [`program`](super::program) writes. [`WriteOptions::preset`] gives a control's.
#[derive(Clone, Debug, PartialEq)]
pub struct WriteOptions {
    /// The dialect.
    pub dialect: Dialect,
    /// Decimals of length (and degree) values, 0 to 6; trailing zeros are
    /// trimmed. 3 suits mm, 4 inch.
    pub digits: u8,
    /// Write in inches (`G20`) instead of mm (`G21`).
    pub inch: bool,
    /// `Some(step)`: number the blocks `N<step>`, `N<2·step>`, …;
    /// `None`: no `N` words.
    pub line_numbers: Option<u32>,
    /// The Fanuc program number `O…`, 1 to 9999 (other dialects have none).
    pub program_number: u32,
    /// A title: the comment on the `O` line (Fanuc) or the first line.
    pub title: Option<String>,
    /// Comment lines after the title: what the reader of the program must
    /// know (values the expansion took from the machine file).
    pub notes: Vec<String>,
    /// Write the motions in incremental coordinates (`G91`) from the first
    /// block at which every axis is known on: see the module documentation.
    pub incremental: bool,
    /// How arcs are written.
    pub arcs: Arcs,
    /// Write comments (the title, notes, a GRBL tool change's message):
    /// some controls stop on them.
    pub comments: bool,
    /// Dwell `P` in milliseconds (`Some(true)`) or seconds (`Some(false)`);
    /// `None`: the dialect's (Fanuc milliseconds, the others seconds).
    pub dwell_ms: Option<bool>,
    /// The most characters a block may have (the control's line buffer).
    pub block_limit: Option<u32>,
    /// The most bytes the program may have (the control's memory).
    pub byte_limit: Option<u64>,
    /// `%` as the first and last line; `None`: the dialect's (Fanuc yes,
    /// the others no).
    pub percent: Option<bool>,
    /// The straight-probe code where the control's is not its dialect's
    /// (Mach3 reads LinuxCNC's words but probes with `G31`).
    pub probe_code: Option<&'static str>,
    /// The tool the operator has in the spindle when the program starts
    /// (the later parts of a program split in parts): on GRBL, which has
    /// no tool changer, no pause to put it in.
    pub loaded_tool: Option<u32>,
    /// For a program kezuri makes: its start, tool changes and end. `None`
    /// for a program kezuri transforms, which keeps its own.
    pub setup: Option<Setup>,
}

impl Default for WriteOptions {
    /// Fanuc, mm with 3 decimals, absolute, no `N` words, `O0001`, no
    /// title, `I J K` arcs, comments, no limits, no [`Setup`].
    fn default() -> WriteOptions {
        WriteOptions {
            dialect: Dialect::Fanuc,
            digits: 3,
            inch: false,
            line_numbers: None,
            program_number: 1,
            title: None,
            notes: Vec::new(),
            incremental: false,
            arcs: Arcs::Ijk,
            comments: true,
            dwell_ms: None,
            block_limit: None,
            byte_limit: None,
            percent: None,
            loaded_tool: None,
            probe_code: None,
            setup: None,
        }
    }
}

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
