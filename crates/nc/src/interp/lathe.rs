//! What a lathe is to the interpreter: how X is read (a diameter or a
//! radius), which of Fanuc's G code systems its codes follow, the spindle's
//! top speed, each tool's nose; and the threads a run cuts, for the report.
//!
//! Positions stay the tool's: X in a [`kezuri_geom::Move`] is always the
//! tool's distance from the spindle axis (a radius), whatever the program's
//! diameter mode, as LinuxCNC's rs274 prints it.

pub mod nose;

use kezuri_geom::Axes;

/// How the program's X words are read.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum XMode {
    /// X is a diameter (Fanuc lathes; LinuxCNC after `G7`): the tool is at
    /// half of it from the spindle axis.
    #[default]
    Diameter,
    /// X is the radius.
    Radius,
}

/// Fanuc's lathe G code systems (Fanuc Series 0i-TF / 30i lathe operator's
/// manual, "G code list"): A is the default; B and C renumber the single
/// cycles and add `G90`/`G91` absolute/incremental.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GCodeSystem {
    /// `U W H` incremental, `G90 G92 G94` single cycles, `G50` coordinate
    /// set, `G98 G99` feed per minute / per revolution.
    #[default]
    A,
    /// `G90 G91`, `G92` coordinate set, `G94 G95` feed modes, `G77 G78 G79`
    /// single cycles, `G98 G99` drilling return levels.
    B,
    /// System B with `G20 G21 G24` the single cycles and `G70 G71` inch/mm.
    C,
}

/// A lathe's conventions, from the machine file (`[machine] kind = "lathe"`
/// or `"mill-turn"`) or from a lathe dialect's defaults.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Lathe {
    /// How X is read at power-on.
    pub x: XMode,
    /// The G code system (Fanuc lathes).
    pub system: GCodeSystem,
}

/// A turning tool's nose: what tool nose radius compensation (`G41`/`G42`)
/// and the simulation need.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nose {
    /// The nose radius, mm.
    pub radius: f64,
    /// The imaginary tool tip direction, 0–9 (0 and 9: the nose centre is
    /// the programmed point).
    pub tip: u8,
}

/// A thread the program cuts: one threading pass (`G32`, `G33`, `G76`, a
/// `G92` threading cycle) from its start to its end.
#[derive(Clone, Debug, PartialEq)]
pub struct Thread {
    /// Lead, mm per revolution along the thread.
    pub lead: f64,
    /// Where the pass starts (the tool's position, X a radius).
    pub start: Axes,
    /// Where it ends.
    pub end: Axes,
    /// The source line of the block.
    pub line: u32,
}
