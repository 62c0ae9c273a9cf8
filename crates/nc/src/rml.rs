//! Roland RML-1: the command language of CAMM-3 engravers and MODELA (MDX)
//! mills, read into a [`Toolpath`](kezuri_geom::Toolpath) and written from
//! one.
//!
//! The relief paper's CAM wrote RML-1 (`camm.3.dat`) and converted it to G-code:
//! `Z x,y,z` → `G01 X Y Z`, `^PU x,y` → `G00 X Y` at a preset safe Z. This
//! module does that conversion both ways, with units: coordinates in RML-1
//! are whole *steps* of the machine's resolution ([`RmlOptions::unit`],
//! 0.01 mm by default; the MDX-20 steps 0.025 mm), never millimetres (the
//! paper's listing prints raw counts as if they were).
//!
//! # The language as read here
//! A program is a list of commands, each a name and comma-separated numbers,
//! ended by `;`. Spaces and line breaks may stand anywhere between tokens;
//! a space also separates two numbers; a missing `;` is accepted where the
//! next command or the end of the file follows (CAMM-GL II allows omitting
//! the terminator when another instruction follows), and empty commands
//! (`;;^IN;`, as Roland's drivers begin) are skipped. Names are read in any
//! letter case. Mode-2 commands are read with or without the `^` that calls
//! them from mode 1 (`^PA` and `PA` alike).
//!
//! | command | what the machine does | read as |
//! |---|---|---|
//! | `^IN` | initialize: defaults, absolute mode, tool up | absolute mode, tool up (it lifts at the next up move) |
//! | `^DF` | default settings | absolute mode |
//! | `^PA [x,y…]` | absolute mode; with pairs, moves there (cutting if the tool is down) | the pairs move at the current Z: rapids with the tool up, feeds with it down |
//! | `^PR [dx,dy…]` | relative mode; with pairs, moves by them | as `^PA`, relative |
//! | `^PU [x,y…]` | tool up (to the up height Z2); with pairs, moves there with the tool up | a rapid straight up to the tool-up height (when not there), then rapids in XY |
//! | `^PD [x,y…]` | tool down (to the down height Z1); with pairs, cuts to them | a feed straight down to the down height (when not there), then feeds in XY |
//! | `Z x,y,z` | three-axis linear move at the `V` speed | a feed to (x, y, z) |
//! | `V v` | speed of `Z` moves, mm/s | feed v · 60 mm/min |
//! | `^VS v` (`F v`) | speed of the XY moves of `^PA`/`^PR`/`^PD`, mm/s | feed v · 60 mm/min for those |
//! | `!VZ v` | speed of the tool-down (Z) motion, mm/s | feed of `^PD`'s plunge |
//! | `!PZ z1[,z2]` (`^PZ`) | down height Z1 and up height Z2 for `^PD`/`^PU` | the heights, in steps |
//! | `!MC n` | spindle motor: 0 off, otherwise (or none) on | spindle off / on (clockwise) |
//! | `H` | home | a lift to the tool-up height, with a warning |
//! | other `!xx` | device settings (`!RC` spindle rate, `!NR` pause, …) | kept in [`RmlProgram::device`] and reported as warnings: they are not motion |
//!
//! Any other command is an error located by line and column: it may move
//! the tool, and a converted program that silently skipped it would cut
//! something else.
//!
//! Decisions a reader might not guess:
//! - **The tool-up height.** `^PU` on a 3-axis machine travels at the up
//!   height. It is [`RmlOptions::safe_z`] when given (the paper's "preset
//!   Z offset height", `--safe-z`), else the program's `!PZ` Z2; a `^PU`
//!   with neither is an error, not a guess.
//! - **The tool-down height.** `^PD` cuts in XY at the *current down Z*: the
//!   latest of `!PZ`'s Z1 and the Z of the last `Z` command (a 3-axis
//!   program that sets its depth with `Z` and then draws with `^PD` cuts at
//!   that depth). A `^PD` with neither is an error.
//! - **Feeds.** `Z` moves use `V`; the XY moves of `^PD`/`^PA`/`^PR` use
//!   `^VS`, else `V`; the plunge of `^PD` uses `!VZ`, else `V`. Where the
//!   program has set none, [`RmlOptions::feed`] (`--feed`) is used; a
//!   cutting move with no feed at all is an error. `^IN` does not forget
//!   the speeds (the machine's defaults after `^IN` are not known here).
//! - **Coordinates** are counted in steps; `!PZ` heights are absolute work
//!   coordinates (Z1 0 and Z2 above it in every program seen). A number
//!   with a fraction is read as a fraction of a step, with one warning.
//!   Numbers beyond ±2³¹ steps are errors.
//! - **The start is unknown**
//!   ([`kezuri_geom::Toolpath::unknown_start`]): moves name the axes they
//!   command (a lift names Z, `^PU x,y` names X and Y, `Z` names all
//!   three), so a G-code writer never invents a position for an axis the
//!   program has not commanded. A relative move before a position is
//!   known is taken from X0 Y0 Z0, with a warning.
//! - Every move keeps the 1-based line of its command in
//!   [`Move::line`](kezuri_geom::Move::line); one command makes one move,
//!   plus the lift of a `^PU` or the plunge of a `^PD` where the tool has
//!   to change height first.
//!
//! # Writing
//! [`write_rml`] writes `;;^IN;` and `^PA;` (absolute steps: rounding each
//! point on its own to the step grid cannot drift), `!PZ0,Z2` with the
//! tool-up height, then one command per move:
//! - a feed is `Z x,y,z;` at the feed of `V` (mm/min ÷ 60, two decimals,
//!   written when it changes);
//! - a rapid that moves in XY is `^PU x,y;` (the machine lifts to Z2 and
//!   travels), followed by a `Z x,y,z;` feed down (or up) to its end when
//!   that is not the up height: rapids travel only at the up height, and a
//!   rapid down becomes a fed plunge;
//! - a vertical rapid is `^PU;` when it ends at the up height (or before the
//!   program has named X and Y), else a `Z` feed;
//! - an arc becomes `Z` chords within [`RmlOptions::tolerance`] of it (the
//!   chord error `r(1 − cos(Δ/2))` of each of `n` equal steps, `n` the
//!   fewest that keep it within the tolerance; RML-1 has no arc command the
//!   3-axis machines share);
//! - a return to the reference point (`G28`) or a machine-coordinate move
//!   (`G53`) becomes a lift to the up height, `^PU;`;
//! - the spindle is `!MC1;`/`!MC0;` where it changes (one direction); a
//!   change from one tool to another lifts the tool, stops the spindle and
//!   pauses with `!NR;` for the operator to change the tool by hand;
//! - spindle speed and coolant are not written (`!RC`'s scale differs
//!   from model to model), nor are dwells or probing moves: those are
//!   errors ([`Error`](crate::Error)), as are a turned rotary axis and a toolpath
//!   in several work offsets;
//! - the program ends with the tool up (`^PU;` where it is not), `!MC0;`
//!   when the spindle runs, and `^IN;`.
//!
//! Up height when [`RmlOptions::safe_z`] is `None`: the highest point any
//! rapid of the toolpath ends at (program coordinates), else the highest
//! point of the toolpath.
//!
//! # Sources
//! Roland's RML-1 and CAMM-GL II programmer's guides define the commands;
//! they are quoted by the implementations this module was checked against:
//! - the CAMM-GL II quick reference condensed from Roland's programmer's
//!   guide (repository `Ti-Ion/EGX-300-USB-Drive`, `CAMM-GL2_REFERENCE.md`):
//!   syntax and terminators, `PA`/`PR`/`PU`/`PD` (moves with the tool up or
//!   down, absolute or relative), `VS`, `!PZ z1,z2` (Z1 cutting depth, Z2
//!   tool-up height), `!VZ` (Z speed, mm/s), `!MC` (0 off, else on), `!NR`
//!   (pause until the operator continues), `^` calling a mode-2 command
//!   from mode 1;
//! - `10maurycy10/gcode2rml` (`README.md`, "RML-1 Format", tested on an
//!   MDX-540): coordinates in 0.01 mm, `V` in mm/s for `Z` moves, `F` for
//!   2-D moves, `Z x,y,z`, `^PA`/`^PR` modes, `!MC`, `!RC`;
//! - Roland driver output as reproduced by HeeksCNC (`nc/hpgl3d.py`) and
//!   `akito914/gcode2rml` (`output.prn`): `;;^IN;` … `V15.0;` … `Z x,y,z;` …
//!   `!MC0;^IN;`;
//! - FreeCAD's `rml_post.py` (citing Roland's "RML-1 Programming
//!   Guidelines"): `PU x,y` travel, `Z x,y,z` feeds, arcs written as chords.
//!
//! `^PZ` as a synonym of `!PZ` follows this project's issue; no source above
//! lists it.

mod read;
mod write;

pub use read::{looks_like_rml, read_rml, DeviceCommand, RmlProgram};
pub use write::write_rml;

/// Units and heights for reading and writing RML-1.
#[derive(Clone, Debug, PartialEq)]
pub struct RmlOptions {
    /// Millimetres per step: the machine's resolution (0.01 mm on most
    /// CAMM-3 and MDX machines, 0.025 mm on the MDX-20).
    pub unit: f64,
    /// The tool-up height in mm. Reading: where `^PU` travels (instead of
    /// the program's `!PZ` Z2). Writing: where rapids travel (instead of
    /// the highest rapid of the toolpath).
    pub safe_z: Option<f64>,
    /// Feed in mm/min. Reading: for cutting moves before the program sets a
    /// speed (`V`, `^VS`, `!VZ`). Writing: for the `Z` plunge of a rapid
    /// when the toolpath has no cutting feed to take it from.
    pub feed: Option<f64>,
    /// Writing: largest distance of the chords from an arc, mm.
    pub tolerance: f64,
}

impl Default for RmlOptions {
    /// 0.01 mm steps, no preset heights or feed, arcs within 0.005 mm.
    fn default() -> RmlOptions {
        RmlOptions { unit: 0.01, safe_z: None, feed: None, tolerance: 0.005 }
    }
}

impl RmlOptions {
    /// The first option out of range, as `(name, value)`: the unit and the
    /// tolerance must be positive, the height finite, the feed positive.
    pub fn invalid(&self) -> Option<(&'static str, f64)> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !positive(self.unit) || self.unit > 1000.0 {
            return Some(("unit", self.unit));
        }
        if !positive(self.tolerance) {
            return Some(("tolerance", self.tolerance));
        }
        if let Some(z) = self.safe_z.filter(|z| !z.is_finite()) {
            return Some(("safe_z", z));
        }
        if let Some(f) = self.feed.filter(|&f| !positive(f)) {
            return Some(("feed", f));
        }
        None
    }
}

/// Largest coordinate in steps either way: RML-1 machines count in 32 bits.
const MAX_STEPS: f64 = 2_147_483_647.0;
