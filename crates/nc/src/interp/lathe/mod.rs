//! What a lathe is to the interpreter: how X is read (a diameter or a
//! radius), which of Fanuc's G code systems its codes follow, the spindle's
//! top speed, each tool's nose; and the threads a run cuts, for the report.
//!
//! Positions stay the tool's: X in a [`kezuri_geom::Move`] is always the
//! tool's distance from the spindle axis (a radius), whatever the program's
//! diameter mode, as LinuxCNC's rs274 prints it.

pub(super) mod contour;
mod corner;
mod corner_arc;
mod drawing;
mod grooving;
mod linuxcnc;
mod linuxcnc_cycles;
mod linuxcnc_profile;
pub mod nose;
mod profile;
mod roughing;
pub(super) mod single;
mod speed;
mod thread;
mod threading;
mod words;

use kezuri_geom::{Axes, AxisSet};

pub(super) use linuxcnc_cycles::Capture;

use super::modal::{GCode, SingleCycle};
use super::State;
pub(super) use corner::Corner;

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

/// The lathe motion mode in force besides G00–G03 (group 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum LatheMotion {
    /// A single cycle (G90 G92 G94 in system A).
    Single(SingleCycle),
    /// Threading (G32 in system A, G33 in B and C).
    Threading,
}

/// What a Fanuc or Haas lathe remembers besides a mill's state: how X is
/// read, the G code system, constant surface speed and its clamp, the
/// lathe's group 1 modes, a chamfer or corner waiting for its next block.
#[derive(Clone, Debug)]
pub(super) struct Turning {
    /// How X words are read now.
    pub x: XMode,
    /// The G code system.
    pub system: GCodeSystem,
    /// Whether the Fanuc lathe's addresses are read (U W H incremental in
    /// system A, the G code tables): Fanuc and Haas, not LinuxCNC.
    pub fanuc: bool,
    /// Constant surface speed (G96) in force: the surface speed in mm/min
    /// (the S word in m/min, or ft/min under G20).
    pub surface: Option<f64>,
    /// The last S word as written (the control's S register).
    pub s_word: f64,
    /// The spindle speed clamp of `G50 S` (`G92 S` in B, C), rpm.
    pub clamp: Option<f64>,
    /// A lathe group 1 mode in force (`None`: G00–G03's `Modal::motion`).
    pub motion: Option<LatheMotion>,
    /// The axes this block gave as increments (U W H), for the writer and
    /// the placing of axes.
    pub increments: AxisSet,
    /// The block in progress reads its own words (a cycle, the dwell).
    pub own_words: bool,
    /// The chamfer or corner R this block asks for (read before its motion).
    pub asked: Option<Corner>,
    /// A chamfer or corner R waiting for the next block's move.
    pub corner: Option<Corner>,
    /// The program has given a direct drawing angle `A` (system A): its
    /// `C` and `R` are the corners between any two moves.
    pub drawing: bool,
    /// The block before gave an angle alone and ended where its line meets
    /// this block's: this block's X, Z and angle are that line's.
    pub drawing_pending: bool,
    /// The tool's geometry and wear offset number (`T0101`: 1), 0 for none.
    pub offset: u32,
}

impl Turning {
    /// A lathe's power-on state with `conventions`.
    pub(super) fn new(conventions: Lathe, fanuc: bool) -> Turning {
        Turning {
            x: conventions.x,
            system: conventions.system,
            fanuc,
            surface: None,
            s_word: 0.0,
            clamp: None,
            motion: None,
            increments: AxisSet::NONE,
            own_words: false,
            asked: None,
            corner: None,
            drawing: false,
            drawing_pending: false,
            offset: 0,
        }
    }
}

impl State {
    /// Decodes a G number as this control reads it: a Fanuc or Haas
    /// lathe's table in its G code system ([`GCode::decode_lathe`]), else
    /// the mill's.
    pub(super) fn decode_g(&self, tenths: u32) -> Option<GCode> {
        match &self.turning {
            // A Haas lathe's G87 G88 G89 are boring cycles along Z, not
            // Fanuc's side cycles: not read.
            Some(t) if t.fanuc => match GCode::decode_lathe(tenths, t.system) {
                Some(GCode::CannedCycle(c)) if c.is_side() && self.settings.dialect.is_haas() => None,
                g => g,
            },
            _ => GCode::decode(tenths),
        }
    }

    /// What is said of a G code the control does not read: in a lathe's
    /// system A, G91 is no code (U W H are the increments).
    pub(super) fn unknown_code(&self, tenths: u32) -> String {
        let name = super::modal::g_name(tenths);
        match &self.turning {
            Some(t) if t.fanuc && t.system == GCodeSystem::A && tenths == 910 => format!(
                "{name} is no code of a lathe's G code system A: U, W and H are the incremental X, Z and C (G91 is \
                 in systems B and C)"
            ),
            _ => format!("{name} is not supported"),
        }
    }

    /// What `#4000+group` reads on a Fanuc or Haas lathe where its G code
    /// list numbers the groups otherwise than a mill's ("G code list",
    /// lathe system): 01 the lathe's cycles and threading too, 02 G96/G97,
    /// 05 G98/G99 in system A (G94/G95 in B, C), 16 the plane. `None`: the
    /// mill's reading.
    pub(super) fn lathe_group(&self, group: u32) -> Option<f64> {
        let t = self.turning.as_ref().filter(|t| t.fanuc)?;
        let per_rev = self.modal.feed_mode == super::FeedMode::PerRev;
        Some(match group {
            1 => match t.motion? {
                LatheMotion::Single(cycle) => f64::from(cycle.number(t.system)),
                LatheMotion::Threading if t.system == GCodeSystem::A => 32.0,
                LatheMotion::Threading => 33.0,
            },
            2 if t.surface.is_some() => 96.0,
            2 => 97.0,
            5 if t.system == GCodeSystem::A => {
                if per_rev {
                    99.0
                } else {
                    98.0
                }
            }
            16 => match self.modal.plane {
                kezuri_geom::Plane::Xy => 17.0,
                kezuri_geom::Plane::Zx => 18.0,
                kezuri_geom::Plane::Yz => 19.0,
            },
            _ => return None,
        })
    }

    /// Sets how X words are read from now on (LinuxCNC's G7 and G8).
    pub(super) fn set_x_mode(&mut self, x: XMode) {
        if let Some(t) = &mut self.turning {
            t.x = x;
        }
    }

    /// Whether constant surface speed (G96) is in force.
    pub(super) fn surface_speed_on(&self) -> bool {
        self.turning.as_ref().is_some_and(|t| t.surface.is_some())
    }

    /// The code of feed per revolution as the program writes it: G99 on a
    /// Fanuc or Haas lathe in system A, G95 elsewhere.
    pub(super) fn per_rev_code(&self) -> &'static str {
        match &self.turning {
            Some(t) if t.fanuc && t.system == GCodeSystem::A => "G99",
            _ => "G95",
        }
    }

    /// Sets the lathe's group 1 mode (`None`: G00–G03, a mill's mode).
    pub(super) fn lathe_motion(&mut self, motion: Option<LatheMotion>) {
        if let Some(t) = &mut self.turning {
            t.motion = motion;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::modal::{CycleReturn, Distance, FeedMode, GCode, SingleCycle, Units};
    use super::GCodeSystem::{self, A, B, C};

    fn code(g: u32, system: GCodeSystem) -> Option<GCode> {
        GCode::decode_lathe(g * 10, system)
    }

    // FANUC Series 0i-TF Plus Operator's Manual (B-64604EN), lathe system,
    // "G code list": the single cycles, threading, the coordinate setting
    // and the feed modes in each system.
    #[test]
    fn the_code_tables_of_systems_a_b_c() {
        use SingleCycle::*;
        for (system, numbers) in [(A, [90, 92, 94]), (B, [77, 78, 79]), (C, [20, 21, 24])] {
            for (g, cycle) in numbers.into_iter().zip([Cutting, Threading, Facing]) {
                assert_eq!(code(g, system), Some(GCode::SingleCycle(cycle)), "G{g} in {system:?}");
                assert_eq!(cycle.number(system), g);
            }
        }
        assert_eq!(code(32, A), Some(GCode::Threading));
        assert_eq!(code(33, B), Some(GCode::Threading));
        assert_eq!(code(33, C), Some(GCode::Threading));
        assert_eq!(code(50, A), Some(GCode::LatheSetPosition));
        assert_eq!(code(92, B), Some(GCode::LatheSetPosition));
        assert_eq!(code(92, C), Some(GCode::LatheSetPosition));
        assert_eq!(code(98, A), Some(GCode::FeedMode(FeedMode::PerMinute)));
        assert_eq!(code(99, A), Some(GCode::FeedMode(FeedMode::PerRev)));
        for s in [B, C] {
            assert_eq!(code(94, s), Some(GCode::FeedMode(FeedMode::PerMinute)));
            assert_eq!(code(95, s), Some(GCode::FeedMode(FeedMode::PerRev)));
            assert_eq!(code(90, s), Some(GCode::Distance(Distance::Absolute)));
            assert_eq!(code(91, s), Some(GCode::Distance(Distance::Incremental)));
            assert_eq!(code(98, s), Some(GCode::CycleReturn(CycleReturn::Initial)));
            assert_eq!(code(99, s), Some(GCode::CycleReturn(CycleReturn::R)));
        }
        assert_eq!(code(91, A), None);
        assert_eq!(code(20, A), Some(GCode::Units(Units::Inch)));
        assert_eq!(code(70, C), Some(GCode::Units(Units::Inch)));
        assert_eq!(code(71, C), Some(GCode::Units(Units::Mm)));
        for s in [A, B, C] {
            assert_eq!(code(96, s), Some(GCode::ConstantSpeed));
            assert_eq!(code(97, s), Some(GCode::ConstantSpeedOff));
            // A mill's drilling cycles are never run in a lathe's: its G73 is
            // a cycle of a finishing shape (pattern repeating; system C's
            // stock removal in turning).
            assert!(matches!(code(73, s), Some(GCode::Contour(_))), "G73 in {s:?}");
            assert_eq!(code(81, s), None);
        }
    }
}
