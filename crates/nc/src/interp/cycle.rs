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

use kezuri_geom::{Axes, AxisSet, CycleBlock, MoveKind, Spindle};

use super::modal::{Cycle, CycleReturn, Distance, Units};
use super::words::Words;
use super::{Control, IntegerInput, State};
use crate::number::number;
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
    origin: [f64; 6],
    q: Option<f64>,
    dwell: f64,
    /// The spindle speed of rigid tapping (M29 S), if it is.
    rigid_speed: Option<f64>,
    /// P is written in seconds (LinuxCNC), not milliseconds.
    seconds: bool,
    initial: f64,
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

impl State {
    /// A canned cycle begins (from G80 or a motion mode): the initial level
    /// is where the tool is now.
    pub(super) fn begin_cycle(&mut self) {
        let (_, _, n) = self.modal.plane.axes();
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

    /// A block in LinuxCNC's G33.1 mode (rigid tapping): from where the
    /// tool is, a feed to the end point synchronised with the spindle (K
    /// the distance a turn), the spindle reversed, the same feed back to
    /// the start, the spindle as it was. Kept as its G33.1 block for a
    /// written program; its two moves are the simulation's. Returns whether
    /// the tool moved.
    pub(super) fn rigid_tap_block(&mut self, w: &Words, span: Span, line: u32) -> Result<bool, Diagnostic> {
        if !w.any_axis() {
            return Ok(false);
        }
        // rs274's refusals (K is not modal: each block gives it).
        let Some(k) = w.get(b'K') else {
            return Err(Diagnostic::error(span, "K word missing with G33.1: give the pitch, the distance a turn"));
        };
        let reverse = match self.spindle {
            Spindle::Cw => Spindle::Ccw,
            Spindle::Ccw => Spindle::Cw,
            Spindle::Off => return Err(Diagnostic::error(span, "Spindle not turning in G33.1: give M3 or M4 first")),
        };
        if self.comp_on() {
            return Err(Diagnostic::error(span, "G33.1 with cutter compensation on (G41/G42): give G40 first"));
        }
        if self.speed <= 0.0 {
            self.warn("no-speed", span, "G33.1 with spindle speed 0: the feed is 0");
        }
        let (start, first, spindle) = (self.tip, self.toolpath.moves.len(), self.spindle);
        let end = self.target(w);
        let feed = (self.mm(k) * self.speed).abs();
        self.push_move(MoveKind::Feed, end, feed, w.axes(), line);
        self.spindle = reverse;
        self.push_move(MoveKind::Feed, start, feed, w.axes(), line);
        self.spindle = spindle;
        // The block in absolute program coordinates, its units with it.
        let unit = if self.modal.units == Units::Inch { 25.4 } else { 1.0 };
        let (e, o) = (end.to_array(), self.frame_offset().to_array());
        let mut text = String::from(if unit == 1.0 { "G21 G90 G33.1" } else { "G20 G90 G33.1" });
        for (i, &letter) in b"XYZABC".iter().enumerate().filter(|&(i, _)| w.axes().contains(i)) {
            let v = if i < 3 { (e[i] - o[i]) / unit } else { e[i] - o[i] };
            text.push_str(&format!(" {}{}", letter as char, number(v, 6)));
        }
        text.push_str(&format!(" K{}", number(k, 6)));
        let mut kept = self.kept(first, 2, text, false, line);
        kept.state = kezuri_geom::ToolState::of(&self.toolpath.moves[first]);
        self.toolpath.kept.push(kept);
        Ok(true)
    }

    /// A block in LinuxCNC's G76 mode (lathe threading, in XZ whatever the
    /// plane): from where the tool is (x₀, z₀), with d the sign of I and s
    /// that of the travel in Z, passes at the depths δₙ = J·n^(1/R) while
    /// under K, one at K, then H spring passes at K. Each pass: a rapid to
    /// (x₀ − d(K−δ), z₀ + s·δ·tan Q), a rapid to x₀ + I + d·δ, a feed
    /// synchronised with the spindle (P the distance a turn) to
    /// Z − s(K−δ)·tan Q, a rapid back to x₀ − d(K−δ); then a rapid to the
    /// block's end point. A tapered end (L1 the entry, L2 the exit, L3
    /// both) cuts E along Z from K shallower than the pass to its depth:
    /// at the entry the rapid in becomes a feed in to that shallower x and
    /// a feed along the taper, at the exit the last E of the feed rises
    /// back to it; both at the pitch P·√(E² + K²)/E, so that Z still
    /// advances P a turn. rs274's `G76`, motion for motion. Kept as its
    /// block for a written program. Returns whether the tool moved.
    pub(super) fn thread_block(&mut self, w: &Words, span: Span, line: u32) -> Result<bool, Diagnostic> {
        let given_here = w.g[..w.g_count].iter().any(|g| g.0 == 760);
        if !w.any_axis() {
            if given_here {
                return Err(Diagnostic::error(span, "All axes missing with G76: give Z, the end of the thread"));
            }
            return Ok(false);
        }
        // rs274's refusals. P, I, J, K are not modal: each block gives them.
        let pitch = match w.get(b'P') {
            Some(p) if p > 0.0 => p,
            _ => return Err(Diagnostic::error(span, "P word missing with G76: give the pitch, the distance a turn")),
        };
        let (Some(i), Some(j), Some(k)) = (w.get(b'I'), w.get(b'J'), w.get(b'K')) else {
            return Err(Diagnostic::error(span, "I J or K words missing with G76"));
        };
        if i == 0.0 {
            return Err(Diagnostic::error(w.span(b'I'), "In G76, I must not be 0"));
        }
        if j <= 0.0 {
            return Err(Diagnostic::error(w.span(b'J'), "In G76, J must be greater than 0"));
        }
        if k <= j {
            return Err(Diagnostic::error(w.span(b'K'), "In G76, K must be greater than J"));
        }
        if let Some(l) = b"ABC".iter().find(|&&l| w.has(l)) {
            return Err(Diagnostic::error(w.span(*l), "Cannot move rotary axes with G76"));
        }
        if self.spindle == Spindle::Off {
            return Err(Diagnostic::error(span, "Spindle not turning in G76: give M3 or M4 first"));
        }
        if self.comp_on() {
            return Err(Diagnostic::error(span, "G76 with cutter compensation on (G41/G42): give G40 first"));
        }
        // rs274 also takes R ≤ 0 and H < 0; refused here rather than guessed.
        let r = w.get(b'R').unwrap_or(1.0);
        if r <= 0.0 {
            return Err(Diagnostic::error(w.span(b'R'), "G76 needs a depth degression R greater than 0"));
        }
        // rs274 cuts an R below 1 as R1 (R0.5 and R0.8 make R1's passes).
        let r = r.max(1.0);
        let h = w.get(b'H').unwrap_or(0.0);
        if h < 0.0 || h.fract() != 0.0 {
            return Err(Diagnostic::error(w.span(b'H'), "G76 needs a whole number of spring passes H, 0 or more"));
        }
        let q = w.get(b'Q').unwrap_or(0.0);
        // The tapered ends: L an integer as rs274 reads one (within
        // 0.0001); rs274 takes L over 3 bit by bit and E < 0 as no taper,
        // both refused here.
        const ENDS: &str = "G76 L is the tapered ends: 0 none, 1 entry, 2 exit, 3 both";
        let ends = match w.get(b'L') {
            None => 0,
            Some(l) if (l - l.round()).abs() > 0.0001 => {
                return Err(Diagnostic::error(w.span(b'L'), format!("Non integer value for integer: {ENDS}")))
            }
            Some(l) if l.round() < 0.0 => {
                return Err(Diagnostic::error(w.span(b'L'), format!("Negative L word used: {ENDS}")))
            }
            Some(l) if l.round() > 3.0 => return Err(Diagnostic::error(w.span(b'L'), format!("{ENDS}, not {l}"))),
            Some(l) => l.round() as u8,
        };
        let taper = w.get(b'E').unwrap_or(0.0);
        if taper < 0.0 {
            return Err(Diagnostic::error(w.span(b'E'), "G76 needs a taper length E of 0 or more"));
        }
        let (entry, exit) = if taper > 0.0 { (ends & 1 != 0, ends & 2 != 0) } else { (false, false) };
        // The passes, bounded.
        const MOST_PASSES: usize = 10_000;
        let mut depths = Vec::new();
        for n in 1.. {
            let depth = j * f64::from(n).powf(1.0 / r);
            if depth >= k {
                break;
            }
            if depths.len() >= MOST_PASSES {
                return Err(Diagnostic::error(span, format!("G76 would make more than {MOST_PASSES} passes")));
            }
            depths.push(self.mm(depth));
        }
        if depths.len() as f64 + h >= MOST_PASSES as f64 {
            return Err(Diagnostic::error(span, format!("G76 would make more than {MOST_PASSES} passes")));
        }
        depths.extend(std::iter::repeat_n(self.mm(k), 1 + h as usize));
        if self.speed <= 0.0 {
            self.warn("no-speed", span, "G76 with spindle speed 0: the feed is 0");
        }
        let (start, first) = (self.tip, self.toolpath.moves.len());
        let end = self.target(w);
        let (x0, z0) = (start.x, start.z);
        let (i_mm, k_mm) = (self.mm(i), self.mm(k));
        let d = i.signum();
        // rs274: toward -Z unless Z is above the start (Z at the start too).
        let s = if end.z > z0 { 1.0 } else { -1.0 };
        let tan = q.to_radians().tan();
        let feed = (self.mm(pitch) * self.speed).abs();
        // Along Z each pass runs s(Z − z₀) − K·tan Q; the tapers fit in it.
        let e_mm = self.mm(taper);
        let tapers = f64::from(u8::from(entry) + u8::from(exit)) * e_mm;
        if tapers > 0.0 && tapers > s * (end.z - z0) - k_mm * tan {
            return Err(Diagnostic::error(
                w.span(b'E'),
                "G76's tapers (E at each tapered end) are longer than the thread",
            ));
        }
        let taper_feed = if taper > 0.0 { feed * e_mm.hypot(k_mm) / e_mm } else { feed };
        let xz = AxisSet::NONE.with(0).with(2);
        let at = |x: f64, z: f64| Axes { x, z, ..start };
        for depth in depths {
            let out = x0 - d * (k_mm - depth);
            let (z_in, z_end) = (z0 + s * depth * tan, end.z - s * (k_mm - depth) * tan);
            let cut = x0 + i_mm + d * depth;
            // Where a taper starts or ends: K shallower than the pass.
            let shallow = cut - d * k_mm;
            self.push_move(MoveKind::Rapid, at(out, z_in), 0.0, xz, line);
            if entry {
                self.push_move(MoveKind::Feed, at(shallow, z_in), taper_feed, xz, line);
                self.push_move(MoveKind::Feed, at(cut, z_in + s * e_mm), taper_feed, xz, line);
            } else {
                self.push_move(MoveKind::Rapid, at(cut, z_in), 0.0, xz, line);
            }
            if exit {
                self.push_move(MoveKind::Feed, at(cut, z_end - s * e_mm), feed, xz, line);
                self.push_move(MoveKind::Feed, at(shallow, z_end), taper_feed, xz, line);
            } else {
                self.push_move(MoveKind::Feed, at(cut, z_end), feed, xz, line);
            }
            self.push_move(MoveKind::Rapid, at(out, z_end), 0.0, xz, line);
        }
        self.push_move(MoveKind::Rapid, end, 0.0, w.axes(), line);
        // The block in absolute program coordinates, its units with it (Q
        // always: LinuxCNC versions differ in its default).
        let unit = if self.modal.units == Units::Inch { 25.4 } else { 1.0 };
        let (e, o) = (end.to_array(), self.frame_offset().to_array());
        let mut text = String::from(if unit == 1.0 { "G21 G90 G76" } else { "G20 G90 G76" });
        // Z always (the end of the thread), X and Y as given.
        for (n, &letter) in b"XYZ".iter().enumerate() {
            if w.has(letter) || letter == b'Z' {
                text.push_str(&format!(" {}{}", letter as char, number((e[n] - o[n]) / unit, 6)));
            }
        }
        for (letter, v) in [(b'P', Some(pitch)), (b'I', Some(i)), (b'J', Some(j)), (b'K', Some(k))].into_iter().chain([
            (b'R', w.get(b'R')),
            (b'Q', Some(q)),
            (b'H', w.get(b'H')),
            (b'E', w.get(b'E')),
        ]) {
            if let Some(v) = v {
                text.push_str(&format!(" {}{}", letter as char, number(v, 6)));
            }
        }
        if w.has(b'L') {
            text.push_str(&format!(" L{ends}"));
        }
        let moves = self.toolpath.moves.len() - first;
        let mut kept = self.kept(first, moves, text, false, line);
        kept.state = kezuri_geom::ToolState::of(&self.toolpath.moves[first]);
        self.toolpath.kept.push(kept);
        Ok(true)
    }

    /// A block in canned cycle mode: stores its hole data and drills the
    /// hole(s) it asks for: a block that names a position in the plane, the
    /// bottom or R drills. Returns whether the tool moved.
    pub(super) fn cycle_block(&mut self, cycle: Cycle, w: &Words, span: Span, line: u32) -> Result<bool, Diagnostic> {
        let (i, j, n) = self.modal.plane.axes();
        let depth_letter = b"XYZ"[n];
        let plane_letters = [b"XYZ"[i], b"XYZ"[j]];
        let mode = self.modal.distance;
        if let Some(v) = w.get(depth_letter) {
            self.hole.bottom = Some((self.mm(v), mode));
        }
        if let Some(v) = w.get(b'R') {
            self.hole.r = Some((self.mm(v), mode));
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
        if w.has(b'I') || w.has(b'J') {
            let shift = [w.get(b'I').map_or(0.0, |v| self.mm(v)), w.get(b'J').map_or(0.0, |v| self.mm(v))];
            self.hole.shift = Some(shift);
        }
        let drills =
            plane_letters.iter().chain(b"ABC").any(|&l| w.has(l)) || w.polar() || w.has(depth_letter) || w.has(b'R');
        let repeats = match (w.get(b'K'), w.get(b'L')) {
            (Some(_), Some(_)) => {
                return Err(Diagnostic::error(w.span(b'L'), "give the repeat count in K or in L, not both"))
            }
            (Some(k), None) => whole_count(k, w.span(b'K'))?,
            (None, Some(l)) => whole_count(l, w.span(b'L'))?,
            (None, None) => 1,
        };
        if !drills || repeats == 0 {
            return Ok(false);
        }
        let g = cycle.number();
        let lcnc_rules = self.settings.dialect == crate::Dialect::LinuxCnc;
        if lcnc_rules && matches!(cycle, Cycle::BackBore | Cycle::BoreManual) {
            return Err(Diagnostic::error(
                span,
                format!("G{g} is not defined in LinuxCNC (its manual: accepted, behaviour undefined): refused in the linuxcnc dialect"),
            ));
        }
        if lcnc_rules && cycle == Cycle::BoreStop && !self.hole.p_given {
            return Err(Diagnostic::error(span, "G86 needs the dwell P in LinuxCNC (P0 for none)"));
        }
        if self.comp_on() {
            // LinuxCNC stops here; on Fanuc the holes would land off the
            // compensated path: refused rather than guessed.
            return Err(Diagnostic::error(span, format!("G{g} with cutter compensation on (G41/G42): give G40 first")));
        }
        if self.modal.feed_mode == super::FeedMode::InverseTime {
            return Err(Diagnostic::error(span, format!("G{g} in inverse time feed (G93): give G94 first")));
        }
        let bottom = self.hole.bottom.ok_or_else(|| {
            Diagnostic::error(
                span,
                format!("G{g} needs the bottom of the hole ({}) before its first hole", depth_letter as char),
            )
        })?;
        let r = self.hole.r.ok_or_else(|| Diagnostic::error(span, format!("G{g} needs the R level")))?;
        let peck = match cycle {
            Cycle::Peck | Cycle::HighSpeedPeck => match self.hole.q {
                Some(q) if q > 0.0 => Some(q),
                Some(q) => {
                    let at = if w.has(b'Q') { w.span(b'Q') } else { span };
                    return Err(Diagnostic::error(at, format!("G{g} needs a peck depth Q greater than 0, not {q}")));
                }
                None => return Err(Diagnostic::error(span, format!("G{g} needs the peck depth Q"))),
            },
            _ => None,
        };
        let shift = match cycle {
            Cycle::FineBore | Cycle::BackBore => Some(self.boring_shift(w, span, g)?),
            _ => None,
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
            let back = cycle == Cycle::BackBore;
            if !back && bottom_level > r_level {
                let at = if w.has(depth_letter) { w.span(depth_letter) } else { span };
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
            if to_initial && !linuxcnc && self.hole.initial < r_level.max(bottom_level) {
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
            let feed = self.feed_mm_min(span);
            let spindle = self.spindle;
            // LinuxCNC never returns below R (G98 from an initial level
            // below it goes to R).
            let up = match to_initial {
                true if self.settings.coords.control == Control::LinuxCnc => self.hole.initial.max(r_level),
                true => self.hole.initial,
                false => r_level,
            };
            if back {
                self.back_bore(shift.unwrap_or_default(), r_level, bottom_level, feed, line);
                self.spindle = spindle;
                self.end_hole(cycle, start, line);
                continue;
            }
            if self.tip.to_array()[n] != r_level {
                self.along(MoveKind::Rapid, r_level, 0.0, line);
            }
            match cycle {
                Cycle::Drill => {
                    self.along(MoveKind::Feed, bottom_level, feed, line);
                    self.along(MoveKind::Rapid, up, 0.0, line);
                }
                Cycle::DrillDwell | Cycle::BoreStop | Cycle::BoreManual => {
                    self.along(MoveKind::Feed, bottom_level, feed, line);
                    self.dwell_here(line);
                    if cycle != Cycle::DrillDwell {
                        self.spindle = Spindle::Off;
                    }
                    if cycle == Cycle::BoreManual {
                        self.warn("g88", span, "G88 stops for the operator to retract by hand: kezuri retracts at rapid with the spindle stopped");
                    }
                    self.along(MoveKind::Rapid, up, 0.0, line);
                }
                Cycle::Bore | Cycle::BoreDwell => {
                    self.along(MoveKind::Feed, bottom_level, feed, line);
                    if cycle == Cycle::BoreDwell {
                        self.dwell_here(line);
                    }
                    // LinuxCNC's G89 feeds out to the clear level; G85 and
                    // Fanuc's G89 to R.
                    let out = if lcnc_rules && cycle == Cycle::BoreDwell { up } else { r_level };
                    self.along(MoveKind::Feed, out, feed, line);
                    if self.tip.to_array()[n] != up {
                        self.along(MoveKind::Rapid, up, 0.0, line);
                    }
                }
                Cycle::Tap | Cycle::LeftTap => {
                    let (cut, out) =
                        if cycle == Cycle::Tap { (Spindle::Cw, Spindle::Ccw) } else { (Spindle::Ccw, Spindle::Cw) };
                    self.spindle = cut;
                    self.along(MoveKind::Feed, bottom_level, feed, line);
                    self.dwell_here(line);
                    self.spindle = out;
                    // LinuxCNC feeds out to the clear level, Fanuc to R.
                    self.along(MoveKind::Feed, if lcnc_rules { up } else { r_level }, feed, line);
                    self.spindle = cut;
                    if self.tip.to_array()[n] != up {
                        self.along(MoveKind::Rapid, up, 0.0, line);
                    }
                }
                Cycle::Peck | Cycle::HighSpeedPeck => {
                    let q = peck.unwrap_or(bottom_level - r_level);
                    let (clearance, retract) = if lcnc_rules {
                        (LINUXCNC_PECK_CLEARANCE, LINUXCNC_PECK_CLEARANCE)
                    } else {
                        (self.settings.cycles.peck_clearance, self.settings.cycles.peck_retract)
                    };
                    let mut depth = r_level;
                    while depth > bottom_level {
                        let next = (depth - q).max(bottom_level);
                        if depth < r_level {
                            if cycle == Cycle::Peck {
                                // Back to R, then down to the clearance above the last depth.
                                self.along(MoveKind::Rapid, r_level, 0.0, line);
                                self.along(MoveKind::Rapid, depth + clearance, 0.0, line);
                            } else {
                                self.along(MoveKind::Rapid, depth + retract, 0.0, line);
                            }
                        }
                        self.along(MoveKind::Feed, next, feed, line);
                        depth = next;
                    }
                    self.along(MoveKind::Rapid, up, 0.0, line);
                }
                Cycle::FineBore => {
                    let s = shift.unwrap_or_default();
                    self.along(MoveKind::Feed, bottom_level, feed, line);
                    self.dwell_here(line);
                    // Oriented stop, then away from the wall before the retract.
                    self.spindle = Spindle::Off;
                    self.shift_by(s, 1.0, line);
                    self.along(MoveKind::Rapid, up, 0.0, line);
                    self.shift_by(s, -1.0, line);
                }
                Cycle::BackBore => unreachable!("handled above"),
            }
            self.spindle = spindle;
            self.end_hole(cycle, start, line);
        }
        Ok(true)
    }

    /// The dwell at the bottom, if the hole data have one.
    fn dwell_here(&mut self, line: u32) {
        if self.hole.dwell > 0.0 {
            self.push_move(MoveKind::Dwell(self.hole.dwell), self.tip, self.feed_word, AxisSet::NONE, line);
        }
    }

    /// The G76/G87 shift in the plane: I J as given, or Q along the
    /// machine's shift direction.
    fn boring_shift(&self, w: &Words, span: Span, g: u32) -> Result<[f64; 2], Diagnostic> {
        if let Some(s) = self.hole.shift {
            return Ok(s);
        }
        match self.hole.q {
            Some(q) if q > 0.0 => {
                let d = self.settings.cycles.shift_direction;
                Ok([d[0] * q, d[1] * q])
            }
            Some(q) => Err(Diagnostic::error(
                if w.has(b'Q') { w.span(b'Q') } else { span },
                format!("G{g}'s shift Q must be greater than 0 (its direction is the machine's), not {q}"),
            )),
            None => Err(Diagnostic::error(span, format!("G{g} needs the shift away from the wall: Q, or I and J"))),
        }
    }

    /// A rapid move by `sign` × `shift` in the plane.
    fn shift_by(&mut self, shift: [f64; 2], sign: f64, line: u32) {
        if shift == [0.0, 0.0] {
            return;
        }
        let (i, j, _) = self.modal.plane.axes();
        let mut a = self.tip.to_array();
        a[i] += sign * shift[0];
        a[j] += sign * shift[1];
        self.push_move(MoveKind::Rapid, Axes::from_array(a), 0.0, AxisSet::NONE.with(i).with(j), line);
    }

    /// G87: shifted past the wall, down to R below the part, back on the
    /// centre, bore upward to the bottom level, shift, out to the initial
    /// level, back on the centre.
    fn back_bore(&mut self, shift: [f64; 2], r_level: f64, bottom_level: f64, feed: f64, line: u32) {
        let spindle = self.spindle;
        self.spindle = Spindle::Off;
        self.shift_by(shift, 1.0, line);
        self.along(MoveKind::Rapid, r_level, 0.0, line);
        self.shift_by(shift, -1.0, line);
        self.spindle = if spindle == Spindle::Off { Spindle::Cw } else { spindle };
        self.along(MoveKind::Feed, bottom_level, feed, line);
        self.dwell_here(line);
        self.spindle = Spindle::Off;
        self.shift_by(shift, 1.0, line);
        self.along(MoveKind::Rapid, self.hole.initial, 0.0, line);
        self.shift_by(shift, -1.0, line);
    }

    /// A move along the depth axis to machine coordinate `level`.
    fn along(&mut self, kind: MoveKind, level: f64, feed: f64, line: u32) {
        let (_, _, n) = self.modal.plane.axes();
        let mut a = self.tip.to_array();
        a[n] = level;
        self.push_move(kind, Axes::from_array(a), feed, AxisSet::NONE.with(n), line);
    }

    /// After a hole: tapping (and every cycle with `keep`, or a return to an
    /// initial level the program never named) is kept for the writer as one
    /// cycle block standing for the hole's moves.
    fn end_hole(&mut self, cycle: Cycle, start: usize, line: u32) {
        self.holes += 1;
        let moves = self.toolpath.moves.len() - start;
        if moves == 0 {
            return;
        }
        let to_initial = cycle == Cycle::BackBore || self.modal.cycle_return == CycleReturn::Initial;
        // What its block is made of, written only if the hole is kept.
        let hole = RunHole {
            start,
            moves,
            line,
            // The state the hole began in (a tap's spindle reversals are its own).
            state: kezuri_geom::ToolState::of(&self.toolpath.moves[start]),
            cycle,
            ret: self.modal.cycle_return,
            plane: self.modal.plane,
            inch: self.modal.units == Units::Inch,
            origin: self.frame_offset().to_array(),
            q: self.hole.q,
            dwell: self.hole.dwell,
            rigid_speed: (cycle.is_tapping() && self.hole.rigid).then_some(self.speed),
            seconds: self.settings.integer_input == IntegerInput::Units,
            initial: self.hole.initial,
        };
        let keep = cycle.is_tapping()
            || self.settings.cycles.keep
            || (to_initial && self.hole.initial_guessed)
            || self.hole.kept_open;
        if !keep {
            self.hole.run.push(hole);
            return;
        }
        // Once one hole of a cycle is kept, all are: the cycle and with it
        // its initial level go on from the first hole (and rigid tapping
        // from its M29), so a G98 hole returns where the cycle began.
        let earlier = std::mem::take(&mut self.hole.run);
        let sorted = earlier.is_empty();
        let mut last_end = if self.hole.kept_open { self.hole.kept_end } else { usize::MAX };
        for h in earlier.into_iter().chain([hole]) {
            // A hole right after the last one goes on in its cycle.
            let next = h.start == last_end;
            let (head, body) = self.cycle_text(&h);
            let text = if next { body } else { head + &body };
            let mut kept = self.kept(h.start, h.moves, text, false, h.line);
            kept.state = h.state;
            kept.cycle = Some(if next { CycleBlock::Next } else { CycleBlock::Start });
            self.toolpath.kept.push(kept);
            last_end = h.start + h.moves;
        }
        if !sorted {
            // The earlier holes' blocks go before what was kept since.
            self.toolpath.kept.sort_by_key(|k| k.before);
        }
        self.hole.kept_open = true;
        self.hole.kept_end = last_end;
    }

    /// The hole as a cycle block in absolute program coordinates (the
    /// writer's: machine less the program's zero): the head the first hole
    /// of a cycle has (units, G90, and `M29 S` for rigid tapping), and the
    /// cycle's words.
    fn cycle_text(&self, h: &RunHole) -> (String, String) {
        let (i, j, n) = h.plane.axes();
        let unit = if h.inch { 25.4 } else { 1.0 };
        let moves = &self.toolpath.moves[h.start..h.start + h.moves];
        let first = moves.iter().find(|m| !matches!(m.kind, MoveKind::Dwell(_))).map_or(moves[0].start, |m| m.end);
        let place = first.to_array();
        let r_level = hole_r_level(moves, n);
        let levels = moves.iter().map(|m| m.end.to_array()[n]);
        let bottom = if h.cycle == Cycle::BackBore {
            levels.fold(f64::NEG_INFINITY, f64::max).min(h.initial)
        } else {
            levels.fold(f64::INFINITY, f64::min)
        };
        let value = |v: f64, k: usize| number((v - h.origin[k]) / unit, 6);
        let letters = ['X', 'Y', 'Z'];
        let units = if h.inch { "G20" } else { "G21" };
        let ret = match h.ret {
            CycleReturn::Initial => "G98",
            CycleReturn::R => "G99",
        };
        let head = match h.rigid_speed {
            Some(s) => format!("M29 S{}\n{units} G90 ", number(s, 0).trim_end_matches('.')),
            None => format!("{units} G90 "),
        };
        let mut text = format!(
            "{ret} G{} {}{} {}{} {}{} R{}",
            h.cycle.number(),
            letters[i],
            value(place[i], i),
            letters[j],
            value(place[j], j),
            letters[n],
            value(bottom, n),
            value(r_level, n),
        );
        if let Some(q) = h.q {
            text.push_str(&format!(" Q{}", number(q / unit, 6)));
        }
        if h.dwell > 0.0 {
            let p = if h.seconds { number(h.dwell, 3) } else { format!("{}", (h.dwell * 1000.0).round()) };
            text.push_str(&format!(" P{p}"));
        }
        let feed = moves.iter().find(|m| m.kind == MoveKind::Feed).map_or(0.0, |m| m.feed);
        text.push_str(&format!(" F{}", number(feed / unit, 4)));
        (head, text)
    }
}

/// The R level of a hole's moves: where its first rapid along the depth
/// axis `n` ends (or where its first feed along it starts).
fn hole_r_level(moves: &[kezuri_geom::Move], n: usize) -> f64 {
    let depth_move = moves.iter().find(|m| {
        let (s, e) = (m.start.to_array(), m.end.to_array());
        (0..3).all(|k| k == n || s[k] == e[k]) && s[n] != e[n]
    });
    match depth_move {
        Some(m) if m.kind == MoveKind::Rapid => m.end.to_array()[n],
        Some(m) => m.start.to_array()[n],
        None => moves[0].start.to_array()[n],
    }
}

fn whole_count(v: f64, span: Span) -> Result<u32, Diagnostic> {
    if v.fract() != 0.0 || !(0.0..=9999.0).contains(&v) {
        return Err(Diagnostic::error(span, format!("a repeat count is a whole number from 0 to 9999, not {v}")));
    }
    Ok(v as u32)
}
