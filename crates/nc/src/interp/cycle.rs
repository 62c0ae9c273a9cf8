//! Canned cycles G73, G74, G76, G81–G89 as a Fanuc or Haas control makes
//! them: each hole becomes the moves the control makes (position at rapid,
//! rapid to R, the cycle's own motions, return to the initial level under
//! G98 or to R under G99).
//!
//! The hole data (bottom, R, Q, P, shift) stay in force from block to block
//! until G80 or a group 1 code; a block that names a position in the plane,
//! the bottom or R drills a hole there. `K` (Fanuc) or `L` (Haas, Series 15)
//! repeats the hole, each repeat moving by the increment in G91; `K0` stores
//! the data without drilling. In G91, R is measured from the initial level
//! and the bottom from R. Tapping (G74, G84) is kept for the writer as a
//! cycle block: the control synchronises spindle and feed, which plain moves
//! cannot say. `docs/canned-cycles.md` gives each rule and where it came
//! from.

mod families;
mod kept;

use kezuri_geom::{Axes, AxisSet, MoveKind, Spindle};

use super::modal::{Cycle, CycleReturn, Distance};
use super::words::Words;
use super::{Control, FeedMode, IntegerInput, State};
use crate::source::{Diagnostic, Span};

/// LinuxCNC's fixed G73 retract and G83 clearance: 0.010 inch.
const LINUXCNC_PECK_CLEARANCE: f64 = 0.254;

/// Most pecks one cycle block may make (all its repeats together).
const MAX_PECKS: f64 = 1_000_000.0;

/// Settings of the canned cycles that a control keeps in parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CycleSettings {
    /// G73's retract after each peck, mm (Fanuc parameter 5114).
    pub peck_retract: f64,
    /// G83's clearance: how far above the last depth the rapid down stops,
    /// mm (Fanuc parameter 5115).
    pub peck_clearance: f64,
    /// Direction of the G76/G87 shift in the plane when it is given by Q
    /// (Fanuc parameter 5101 RD1/RD2): a unit vector along the plane's first
    /// and second axis; +X by default.
    pub shift_direction: [f64; 2],
    /// Write every canned cycle as a cycle block, not only tapping.
    pub keep: bool,
}

impl Default for CycleSettings {
    fn default() -> CycleSettings {
        CycleSettings { peck_retract: 0.1, peck_clearance: 0.1, shift_direction: [1.0, 0.0], keep: false }
    }
}

/// A hole of the cycle in force, and what its cycle block is made of: the
/// modal words as they were when it was drilled, its moves in the toolpath.
#[derive(Clone, Debug)]
struct RunHole {
    start: usize,
    moves: usize,
    line: u32,
    state: kezuri_geom::ToolState,
    cycle: Cycle,
    ret: CycleReturn,
    plane: kezuri_geom::Plane,
    inch: bool,
    /// The program's zero (work offset and shifts), machine coordinates.
    origin: [f64; kezuri_geom::Axes::COUNT],
    q: Option<f64>,
    dwell: f64,
    /// The spindle speed of rigid tapping (M29 S), if it is.
    rigid_speed: Option<f64>,
    /// P is written in seconds (LinuxCNC), not milliseconds.
    seconds: bool,
    initial: f64,
    /// LinuxCNC's G87: its shift I J (mm), written with the top K.
    back_shift: Option<[f64; 2]>,
}

/// The hole data in force, as the program gave them (mm, seconds).
#[derive(Clone, Debug, Default)]
pub(super) struct HoleData {
    /// The bottom: the depth axis word (Z in G17), and whether it was
    /// given in G91 (from R) or G90 (a level).
    bottom: Option<(f64, Distance)>,
    /// R, and whether it was given in G91 (from the initial level).
    r: Option<(f64, Distance)>,
    q: Option<f64>,
    /// Dwell at the bottom, seconds.
    dwell: f64,
    /// A P has been given in this cycle (LinuxCNC's G86 needs one).
    p_given: bool,
    /// G76/G87 shift given by I and J (plane axes), mm.
    shift: Option<[f64; 2]>,
    /// LinuxCNC's G87: K, the top of the back bore, and whether it was
    /// given in G91 (from the bottom) or G90 (a level).
    back_top: Option<(f64, Distance)>,
    /// Machine coordinate of the tool tip on the depth axis when the cycle
    /// began: the initial level.
    initial: f64,
    /// Whether the initial level is a position the program never named.
    initial_guessed: bool,
    /// M29 was given: tapping is rigid (spindle and feed synchronised).
    pub(super) rigid: bool,
    /// The holes of this cycle are kept as cycle blocks; the last ended
    /// before move `kept_end`.
    kept_open: bool,
    kept_end: usize,
    /// The holes of this cycle written as moves so far: kept after all if a
    /// later hole must be (a tap after drilled holes).
    run: Vec<RunHole>,
}

impl HoleData {
    /// No hole refers to a move already made: none waits to be kept, and no
    /// kept cycle goes on.
    pub(super) fn settled(&self) -> bool {
        self.run.is_empty() && !self.kept_open
    }
}

/// One hole's levels on the depth axis, machine coordinates.
#[derive(Clone, Copy, Debug)]
struct Levels {
    /// The R level.
    r: f64,
    /// The bottom.
    bottom: f64,
    /// Where the hole ends: the initial level (G98) or R (G99).
    up: f64,
}

impl State {
    /// The plane a canned cycle's holes lie in: the program's, but a Fanuc
    /// or Haas lathe's face drilling (G83, G84, G85) goes along Z whatever
    /// the plane, its X and C placing the hole, and a Fanuc lathe's side
    /// drilling (G87, G88, G89) along X, its Z and C placing the hole.
    pub(super) fn cycle_plane(&self) -> kezuri_geom::Plane {
        if !self.settings.dialect.is_lathe() {
            self.modal.plane
        } else if self.modal.cycle.is_some_and(Cycle::is_side) {
            kezuri_geom::Plane::Yz
        } else {
            kezuri_geom::Plane::Xy
        }
    }

    /// A canned cycle begins (from G80 or a motion mode): the initial level
    /// is where the tool is now.
    pub(super) fn begin_cycle(&mut self) {
        let (_, _, n) = self.cycle_plane().axes();
        self.hole = HoleData {
            initial: self.tip.to_array()[n],
            initial_guessed: self.guessed.contains(n),
            rigid: self.hole.rigid,
            ..HoleData::default()
        };
    }

    /// G80 or a group 1 code: the cycle and rigid tapping end.
    pub(super) fn end_cycle(&mut self) {
        self.modal.cycle = None;
        self.hole.rigid = false;
        self.hole.kept_open = false;
        self.hole.run.clear();
    }

    /// A block in canned cycle mode: stores its hole data and drills the
    /// hole(s) it asks for: a block that names a position in the plane, the
    /// bottom or R drills. Returns whether the tool moved.
    pub(super) fn cycle_block(&mut self, cycle: Cycle, w: &Words, span: Span, line: u32) -> Result<bool, Diagnostic> {
        let (i, j, n) = self.cycle_plane().axes();
        let depth_letter = b"XYZ"[n];
        let plane_letters = [b"XYZ"[i], b"XYZ"[j]];
        // LinuxCNC's G87 reads K as the top of the back bore.
        let lcnc_back = cycle == Cycle::BackBore && self.settings.dialect == crate::Dialect::LinuxCnc;
        // LinuxCNC's canned cycles in the XYZ planes take no U V W words.
        if let Some(letter) = b"UVW".iter().copied().find(|&l| w.has(l) && w.is_axis(l)) {
            return Err(Diagnostic::error(
                w.span(letter),
                format!(
                    "{} in a canned cycle (G{}): in the XY, ZX and YZ planes the cycle takes X Y Z, not U V W \
                     (LinuxCNC stops too)",
                    letter as char,
                    cycle.number()
                ),
            ));
        }
        self.hole_data(w, depth_letter, lcnc_back)?;
        let drills =
            plane_letters.iter().chain(b"ABC").any(|&l| w.has(l)) || w.polar() || w.has(depth_letter) || w.has(b'R');
        let repeats = match (w.get(b'K'), w.get(b'L')) {
            (_, Some(l)) if lcnc_back => whole_count(l, w.span(b'L'))?,
            (Some(_), Some(_)) => {
                return Err(Diagnostic::error(w.span(b'L'), "give the repeat count in K or in L, not both"))
            }
            (Some(k), None) if !lcnc_back => whole_count(k, w.span(b'K'))?,
            (None, Some(l)) => whole_count(l, w.span(b'L'))?,
            _ => 1,
        };
        if !drills || repeats == 0 {
            return Ok(false);
        }
        let g = cycle.number();
        self.cycle_refusals(cycle, span)?;
        let bottom = self.hole.bottom.ok_or_else(|| {
            Diagnostic::error(
                span,
                format!("G{g} needs the bottom of the hole ({}) before its first hole", depth_letter as char),
            )
        })?;
        let r = self.hole.r.ok_or_else(|| Diagnostic::error(span, format!("G{g} needs the R level")))?;
        let peck = match cycle {
            Cycle::Peck | Cycle::HighSpeedPeck | Cycle::SideDrill => match self.hole.q {
                Some(q) if q > 0.0 => Some(q),
                Some(q) => {
                    let at = if w.has(b'Q') { w.span(b'Q') } else { span };
                    return Err(Diagnostic::error(at, format!("G{g} needs a peck depth Q greater than 0, not {q}")));
                }
                // A lathe's G83 or G87 without Q drills in one feed.
                None if self.settings.dialect.is_lathe() => None,
                None => return Err(Diagnostic::error(span, format!("G{g} needs the peck depth Q"))),
            },
            _ => None,
        };
        let shift = match cycle {
            Cycle::BackBore if lcnc_back => self.linuxcnc_back_bore_words(span)?,
            Cycle::FineBore | Cycle::BackBore => self.boring_shift(w, span, g)?,
            _ => [0.0, 0.0],
        };
        // A peck far smaller than the hole, repeated: bounded, never a
        // runaway (each peck is up to four moves).
        if let (Some(q), Some((b, _)), Some((r, _))) = (peck, self.hole.bottom, self.hole.r) {
            let pecks = ((r - b).abs() / q).ceil() * f64::from(repeats);
            if pecks > MAX_PECKS {
                let at = if w.has(b'Q') { w.span(b'Q') } else { span };
                return Err(Diagnostic::error(
                    at,
                    format!("G{g} with Q{q} makes {pecks} pecks, more than {MAX_PECKS}: is Q in the right units?"),
                ));
            }
        }
        // The position words without the depth axis: the hole's place.
        let place = w.without(depth_letter);
        for _ in 0..repeats {
            let start = self.toolpath.moves.len();
            // LinuxCNC's polar words under G91 turn or step out from where
            // the last hole was: none from the XY zero.
            self.polar_from_origin(&place, span)?;
            let mut hole = self.target(&place);
            // Each level as it was given: a level in G90, in G91 R from the
            // initial level and the bottom from R.
            let offset = self.frame_offset().to_array()[n];
            let r_level = match r {
                (v, Distance::Absolute) => v + offset,
                (v, Distance::Incremental) => self.hole.initial + v,
            };
            let bottom_level = match bottom {
                (v, Distance::Absolute) => v + offset,
                (v, Distance::Incremental) => r_level + v,
            };
            // Fanuc's G87 bores upward from R below the part; LinuxCNC's
            // goes down past R to the bottom like any hole.
            let back = cycle == Cycle::BackBore && !lcnc_back;
            if !back && bottom_level > r_level {
                let at = if w.has(depth_letter) { w.span(depth_letter) } else { span };
                if cycle.is_side() {
                    return Err(Diagnostic::error(
                        at,
                        format!(
                            "the hole's bottom X is farther from the spindle axis than its R level: G{g} drills in \
                             from R toward the axis"
                        ),
                    ));
                }
                return Err(Diagnostic::error(
                    at,
                    format!(
                        "the hole's bottom {} is above its R level: G{g} drills down from R (with G99 the tool would return into the part)",
                        depth_letter as char
                    ),
                ));
            }
            if back && bottom_level < r_level {
                return Err(Diagnostic::error(span, "G87 bores upward: its R level must be below the bottom Z"));
            }
            let to_initial = back || self.modal.cycle_return == CycleReturn::Initial;
            let linuxcnc = self.settings.coords.control == Control::LinuxCnc;
            // (A lathe's R above the initial level is only air above the face.)
            if to_initial
                && !linuxcnc
                && !self.settings.dialect.is_lathe()
                && self.hole.initial < r_level.max(bottom_level)
            {
                self.warn(
                    "initial-level",
                    span,
                    format!("G98 returns to the initial level, which is below the R level of this G{g}: the tool returns into the hole"),
                );
            }
            // LinuxCNC rises to R first when the tool is below it.
            if linuxcnc && self.tip.to_array()[n] < r_level {
                self.along(MoveKind::Rapid, r_level, 0.0, line);
            }
            // Position in the plane at the current level.
            let mut p = hole.to_array();
            p[n] = self.tip.to_array()[n];
            hole = Axes::from_array(p);
            if hole != self.tip {
                self.push_move(MoveKind::Rapid, hole, 0.0, place.axes(), line);
            }
            let feed = self.feed_mm_min(span)?;
            let spindle = self.spindle;
            // LinuxCNC never returns below R (G98 from an initial level
            // below it goes to R).
            let up = match to_initial {
                true if linuxcnc => self.hole.initial.max(r_level),
                true => self.hole.initial,
                false => r_level,
            };
            let levels = Levels { r: r_level, bottom: bottom_level, up };
            if back {
                self.back_bore(shift, levels, feed, line);
            } else {
                if self.tip.to_array()[n] != r_level {
                    self.along(MoveKind::Rapid, r_level, 0.0, line);
                }
                if lcnc_back {
                    let top = match self.hole.back_top {
                        Some((v, Distance::Absolute)) => v + offset,
                        Some((v, Distance::Incremental)) => bottom_level + v,
                        None => bottom_level,
                    };
                    self.linuxcnc_back_bore(shift, levels, top, feed, line);
                } else {
                    self.hole_motion(cycle, levels, feed, peck, shift, span, line);
                }
            }
            self.spindle = spindle;
            self.end_hole(cycle, start, line);
        }
        Ok(true)
    }

    /// Stores the hole data a cycle block gives: the bottom (the depth axis
    /// `depth_letter`), R, Q, the dwell P and the shift I J.
    fn hole_data(&mut self, w: &Words, depth_letter: u8, lcnc_back: bool) -> Result<(), Diagnostic> {
        let mode = self.modal.distance;
        if let Some(v) = w.get(depth_letter) {
            self.hole.bottom = Some((self.mm(v), mode));
        }
        if let Some(v) = w.get(b'R') {
            // A Fanuc lathe in G code system A gives R from the initial level
            // (parameter 5102#6 RAB at its default, 0).
            let fanuc_a = self.settings.dialect == crate::Dialect::FanucLathe
                && self.turning.as_ref().is_some_and(|t| t.system == super::GCodeSystem::A);
            self.hole.r = Some((self.mm(v), if fanuc_a { Distance::Incremental } else { mode }));
        }
        if let Some(q) = w.get(b'Q') {
            self.hole.q = Some(self.mm(q));
        }
        if let Some(p) = w.get(b'P') {
            // P is milliseconds on a Fanuc control, seconds on LinuxCNC.
            let seconds = if self.settings.integer_input == IntegerInput::Units { p } else { p / 1000.0 };
            if seconds < 0.0 {
                return Err(Diagnostic::error(w.span(b'P'), "a dwell time cannot be negative"));
            }
            self.hole.dwell = seconds;
            self.hole.p_given = true;
        }
        if let Some(k) = w.get(b'K').filter(|_| lcnc_back) {
            self.hole.back_top = Some((self.mm(k), mode));
        }
        if w.has(b'I') || w.has(b'J') {
            let shift = [w.get(b'I').map_or(0.0, |v| self.mm(v)), w.get(b'J').map_or(0.0, |v| self.mm(v))];
            self.hole.shift = Some(shift);
        }
        Ok(())
    }

    /// The cycles this control has not, or not in this state.
    fn cycle_refusals(&self, cycle: Cycle, span: Span) -> Result<(), Diagnostic> {
        let g = cycle.number();
        let lcnc_rules = self.settings.dialect == crate::Dialect::LinuxCnc;
        if lcnc_rules && matches!(cycle, Cycle::BoreStop | Cycle::BoreManual) && !self.hole.p_given {
            return Err(Diagnostic::error(span, format!("G{g} needs the dwell P in LinuxCNC (P0 for none)")));
        }
        if lcnc_rules && matches!(cycle, Cycle::BackBore | Cycle::BoreManual) && self.spindle == Spindle::Off {
            return Err(Diagnostic::error(span, format!("G{g} needs the spindle turning (M3 or M4) in LinuxCNC")));
        }
        if self.comp_on() {
            // LinuxCNC stops here; on Fanuc the holes would land off the
            // compensated path: refused rather than guessed.
            return Err(Diagnostic::error(span, format!("G{g} with cutter compensation on (G41/G42): give G40 first")));
        }
        if self.modal.feed_mode == FeedMode::InverseTime {
            return Err(Diagnostic::error(span, format!("G{g} in inverse time feed (G93): give G94 first")));
        }
        Ok(())
    }

    /// The dwell at the bottom, if the hole data have one.
    fn dwell_here(&mut self, line: u32) {
        if self.hole.dwell > 0.0 {
            self.push_move(MoveKind::Dwell(self.hole.dwell), self.tip, self.feed_word, AxisSet::NONE, line);
        }
    }

    /// A move along the depth axis to machine coordinate `level`.
    fn along(&mut self, kind: MoveKind, level: f64, feed: f64, line: u32) {
        let (_, _, n) = self.cycle_plane().axes();
        let mut a = self.tip.to_array();
        a[n] = level;
        self.push_move(kind, Axes::from_array(a), feed, AxisSet::NONE.with(n), line);
    }
}

fn whole_count(v: f64, span: Span) -> Result<u32, Diagnostic> {
    if v.fract() != 0.0 || !(0.0..=9999.0).contains(&v) {
        return Err(Diagnostic::error(span, format!("a repeat count is a whole number from 0 to 9999, not {v}")));
    }
    Ok(v as u32)
}
