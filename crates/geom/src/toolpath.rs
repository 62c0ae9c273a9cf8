//! The machine-neutral toolpath: a list of self-contained moves.

mod bounds;
pub use bounds::{AxisRanges, KnownBounds};
mod piece;
pub use piece::{PathSink, WholePath};
mod transform;

use std::f64::consts::TAU;

/// A position of all nine axes: X Y Z in mm, A B C in degrees, U V W in mm.
///
/// U V W are the linear axes parallel to X Y Z that LinuxCNC has (a foam
/// cutter's second wire end, a quill, a second head): they are not part of
/// the tool tip, which is X Y Z ([`Axes::xyz`], [`Axes::distance`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Axes {
    /// X in mm.
    pub x: f64,
    /// Y in mm.
    pub y: f64,
    /// Z in mm.
    pub z: f64,
    /// A (rotary about X) in degrees.
    pub a: f64,
    /// B (rotary about Y) in degrees.
    pub b: f64,
    /// C (rotary about Z) in degrees.
    pub c: f64,
    /// U (linear, parallel to X) in mm.
    pub u: f64,
    /// V (linear, parallel to Y) in mm.
    pub v: f64,
    /// W (linear, parallel to Z) in mm.
    pub w: f64,
}

impl Axes {
    /// All axes at zero.
    pub const ZERO: Axes = Axes { x: 0.0, y: 0.0, z: 0.0, a: 0.0, b: 0.0, c: 0.0, u: 0.0, v: 0.0, w: 0.0 };

    /// How many axes there are.
    pub const COUNT: usize = 9;

    /// The axes' letters in array order.
    pub const LETTERS: [u8; Axes::COUNT] = *b"XYZABCUVW";

    /// Whether axis `k` (in array order) is linear (mm): X Y Z and U V W;
    /// A B C are degrees.
    pub const fn is_linear(k: usize) -> bool {
        k < 3 || k >= 6
    }

    /// The axes as an array in the order X Y Z A B C U V W.
    pub fn to_array(self) -> [f64; Axes::COUNT] {
        [self.x, self.y, self.z, self.a, self.b, self.c, self.u, self.v, self.w]
    }

    /// Builds axes from an array in the order X Y Z A B C U V W.
    pub fn from_array(v: [f64; Axes::COUNT]) -> Axes {
        Axes { x: v[0], y: v[1], z: v[2], a: v[3], b: v[4], c: v[5], u: v[6], v: v[7], w: v[8] }
    }

    /// The X Y Z A B C part: what a machine's kinematics places the tool by.
    pub fn xyzabc(self) -> [f64; 6] {
        [self.x, self.y, self.z, self.a, self.b, self.c]
    }

    /// These axes with X Y Z A B C set from `v` (U V W kept).
    pub fn with_xyzabc(self, v: [f64; 6]) -> Axes {
        Axes { x: v[0], y: v[1], z: v[2], a: v[3], b: v[4], c: v[5], ..self }
    }

    /// The U V W part.
    pub fn uvw(self) -> [f64; 3] {
        [self.u, self.v, self.w]
    }

    /// The X Y Z part.
    pub fn xyz(self) -> [f64; 3] {
        [self.x, self.y, self.z]
    }

    /// Straight-line distance of the linear axes X Y Z to `other`, in mm.
    pub fn distance(self, other: Axes) -> f64 {
        let d = [other.x - self.x, other.y - self.y, other.z - self.z];
        (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
    }
}

/// The plane an arc turns in (G17, G18, G19).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Plane {
    /// G17: the XY plane, helical axis Z.
    #[default]
    Xy,
    /// G18: the ZX plane, helical axis Y.
    Zx,
    /// G19: the YZ plane, helical axis X.
    Yz,
}

impl Plane {
    /// Indices (into X Y Z) of the plane's first axis, second axis and normal
    /// axis. The pair is ordered so that counter-clockwise (G03) is the
    /// positive rotation seen from the positive normal axis.
    pub fn axes(self) -> (usize, usize, usize) {
        match self {
            Plane::Xy => (0, 1, 2),
            Plane::Zx => (2, 0, 1),
            Plane::Yz => (1, 2, 0),
        }
    }
}

/// A circular (or helical) arc: the geometry beyond start and end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arc {
    /// Centre in X Y Z (mm); its coordinate along the plane normal is the
    /// start's.
    pub center: [f64; 3],
    /// The plane the arc turns in.
    pub plane: Plane,
    /// `true` for counter-clockwise (G03) seen from the positive normal axis.
    pub ccw: bool,
    /// Extra full turns beyond the first sweep (helical `P` turns), usually 0.
    pub turns: u32,
}

impl Arc {
    /// Radius measured at the start point.
    pub fn radius(&self, start: Axes) -> f64 {
        let (i, j, _) = self.plane.axes();
        let s = start.xyz();
        (s[i] - self.center[i]).hypot(s[j] - self.center[j])
    }

    /// Swept angle in radians, always positive, in (0, 2π] plus the extra
    /// turns: equal start and end make a full circle.
    pub fn sweep(&self, start: Axes, end: Axes) -> f64 {
        let (i, j, _) = self.plane.axes();
        let (s, e) = (start.xyz(), end.xyz());
        let a0 = (s[j] - self.center[j]).atan2(s[i] - self.center[i]);
        let a1 = (e[j] - self.center[j]).atan2(e[i] - self.center[i]);
        let mut d = if self.ccw { a1 - a0 } else { a0 - a1 };
        while d <= 1e-12 {
            d += TAU;
        }
        while d > TAU + 1e-12 {
            d -= TAU;
        }
        d + TAU * f64::from(self.turns)
    }

    /// Path length of the arc (helix included) in mm.
    pub fn length(&self, start: Axes, end: Axes) -> f64 {
        let (_, _, n) = self.plane.axes();
        let planar = self.radius(start) * self.sweep(start, end);
        let rise = end.xyz()[n] - start.xyz()[n];
        planar.hypot(rise)
    }

    /// How many equal chords follow the arc within `tol` (the largest
    /// sagitta, mm): at least 1, at most 10⁷; an arc no wider than `tol`
    /// gets one chord per half turn.
    pub fn chords(&self, start: Axes, end: Axes, tol: f64) -> usize {
        let (radius, sweep) = (self.radius(start), self.sweep(start, end));
        if radius <= tol {
            return ((sweep / std::f64::consts::PI).ceil() as usize).max(1);
        }
        let step = 2.0 * (1.0 - tol / radius).acos();
        ((sweep / step).ceil().max(1.0) as usize).min(10_000_000)
    }

    /// The point at parameter `t` in [0, 1] along the arc (rotary axes, U V W
    /// and the helical axis vary linearly).
    pub fn point_at(&self, start: Axes, end: Axes, t: f64) -> Axes {
        let (i, j, n) = self.plane.axes();
        let s = start.xyz();
        let r = self.radius(start);
        let a0 = (s[j] - self.center[j]).atan2(s[i] - self.center[i]);
        let sweep = self.sweep(start, end);
        let a = if self.ccw { a0 + sweep * t } else { a0 - sweep * t };
        let lerp = |p: f64, q: f64| p + (q - p) * t;
        let mut p = [0.0; 3];
        p[i] = self.center[i] + r * a.cos();
        p[j] = self.center[j] + r * a.sin();
        p[n] = lerp(s[n], end.xyz()[n]);
        Axes {
            x: p[0],
            y: p[1],
            z: p[2],
            a: lerp(start.a, end.a),
            b: lerp(start.b, end.b),
            c: lerp(start.c, end.c),
            u: lerp(start.u, end.u),
            v: lerp(start.v, end.v),
            w: lerp(start.w, end.w),
        }
    }
}

/// What a move does.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum MoveKind {
    /// Positioning at rapid rate (G00).
    Rapid,
    /// Straight cutting move at the feed (G01).
    #[default]
    Feed,
    /// Circular or helical cutting move (G02/G03).
    Arc(Arc),
    /// Probing (skip) move toward the end point (G31).
    Probe,
    /// A pause at the start point, in seconds (G04); start equals end.
    Dwell(f64),
    /// Return of the named axes ([`Move::named`]) to the machine's
    /// reference point (G28) at rapid rate. `end` is where the machine model
    /// puts the tool tip; the control knows the real point, so writers
    /// command the return, not the position.
    Home,
    /// Positioning of the named axes in machine coordinates (G53) at rapid
    /// rate. Writers command it in machine coordinates again.
    Machine,
}

/// A set of the axes X Y Z A B C U V W: bit k for the k-th. The default is
/// all nine.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AxisSet(pub u16);

impl Default for AxisSet {
    fn default() -> AxisSet {
        AxisSet::ALL
    }
}

impl AxisSet {
    /// No axis.
    pub const NONE: AxisSet = AxisSet(0);
    /// X Y Z A B C U V W.
    pub const ALL: AxisSet = AxisSet(0b1_1111_1111);
    /// U V W.
    pub const UVW: AxisSet = AxisSet(0b1_1100_0000);

    /// Whether axis `k` (0 = X … 5 = C, 6 = U … 8 = W) is in the set.
    pub fn contains(self, k: usize) -> bool {
        k < Axes::COUNT && self.0 & (1 << k) != 0
    }

    /// The set with axis `k` added.
    pub fn with(self, k: usize) -> AxisSet {
        AxisSet(self.0 | (1 << k))
    }
}

/// The coordinate frame the control had when it made a move: the work offset
/// and the tool length offset in effect.
///
/// Toolpath positions are machine coordinates of the tool tip, so that
/// moves made under different offsets share one frame (what a simulation
/// needs). A writer gets program coordinates back by subtracting
/// [`Frame::zero`], and commands the offsets again so the control applies
/// its own values; the shifts the program made itself (G92, G52, the
/// external offset) it gives again as the program wrote them (kept
/// blocks), since they depend on where the machine was.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Frame {
    /// Work offset: 0 to 5 for G54 to G59.
    pub work: u8,
    /// Machine coordinates of that work offset's zero.
    pub origin: Axes,
    /// The shifts in force on top of the work offset: the external offset,
    /// G92 and G52.
    pub shift: Axes,
    /// Tool length offset (G43/G44 H); `None` for none (G49).
    pub length: Option<LengthOffset>,
}

impl Frame {
    /// Machine coordinates of the program's zero: the work offset's zero
    /// and the shifts.
    pub fn zero(&self) -> Axes {
        let (o, s) = (self.origin.to_array(), self.shift.to_array());
        Axes::from_array(std::array::from_fn(|k| o[k] + s[k]))
    }
}

/// A tool length offset in effect.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LengthOffset {
    /// The offset register, the H number.
    pub register: u32,
    /// `true` for G44 (subtract), `false` for G43 (add).
    pub negative: bool,
    /// The offset in force in mm as the machine model has it: the
    /// register's value, or what LinuxCNC's G43.1 and G43.2 made it.
    pub value: f64,
    /// LinuxCNC's G43.1 Z: the offset the program gave (mm) in place of a
    /// register's (`register` is then 0); `None` for G43/G44 H.
    pub given: Option<f64>,
    /// LinuxCNC's G43.2 H: the registers whose lengths were added to it
    /// since, in order; 0 ends the list.
    pub added: [u32; LengthOffset::ADDED],
}

impl LengthOffset {
    /// How many G43.2 additions an offset keeps.
    pub const ADDED: usize = 4;

    /// Whether LinuxCNC's G43.1 or G43.2 made it: only LinuxCNC (and,
    /// by its value, GRBL) can apply it.
    pub fn dynamic(&self) -> bool {
        self.given.is_some() || self.added[0] != 0
    }

    /// How far the gauge line is above the tool tip, in mm.
    pub fn signed(&self) -> f64 {
        if self.negative {
            -self.value
        } else {
            self.value
        }
    }
}

/// Spindle state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Spindle {
    /// Stopped (M05).
    #[default]
    Off,
    /// Clockwise (M03).
    Cw,
    /// Counter-clockwise (M04).
    Ccw,
}

/// Coolant state (M07 mist, M08 flood, M09 off).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Coolant {
    /// Mist or air blow (M07).
    pub mist: bool,
    /// Flood (M08).
    pub flood: bool,
}

/// One move of the toolpath, complete in itself.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Move {
    /// What the move does.
    pub kind: MoveKind,
    /// Tool tip position at the start.
    pub start: Axes,
    /// Tool tip position at the end.
    pub end: Axes,
    /// Feed in mm/min (the modal feed; unused by rapids and dwells).
    pub feed: f64,
    /// Spindle speed in rpm.
    pub speed: f64,
    /// Spindle direction.
    pub spindle: Spindle,
    /// Coolant state.
    pub coolant: Coolant,
    /// Tool number in the spindle.
    pub tool: u32,
    /// 1-based source line that made the move (0 when generated).
    pub line: u32,
    /// Index of the move's [`Frame`] in [`Toolpath::frames`] (0, the
    /// default frame, when there are none).
    pub frame: u32,
    /// The axes the block named. An axis it did not name stays wherever the
    /// control has it, which a writer must not turn into a command: after a
    /// tool change the model's position of an unnamed axis is only a guess.
    /// Generated moves name every axis (the default).
    pub named: AxisSet,
    /// The axes the move reaches by an increment from a position the
    /// program never named: an incremental block after the start, a return
    /// to the reference point, a `G53` move or a change of frame, where the
    /// end is reckoned from the machine model's offsets and reference point.
    /// A writer commands such a block as increments (`G91`), never as a
    /// position computed from the model: on a machine whose offsets differ,
    /// that position is somewhere else. Empty for generated moves (the
    /// default).
    pub relative: AxisSet,
    /// The axes whose end is not a position the program gave, so that no
    /// picture or figure may place the tool there: where the machine
    /// happened to be at the start of an NC program (until a move names
    /// the axis), and a reference point (G28, G30) or `G53` position the
    /// machine file does not place in work coordinates (until a move names
    /// the axis in absolute, or a `G92` names the place where this move
    /// left it). Empty for generated moves (the default).
    pub unknown: AxisSet,
}

impl Default for Move {
    fn default() -> Move {
        Move {
            kind: MoveKind::default(),
            start: Axes::ZERO,
            end: Axes::ZERO,
            feed: 0.0,
            speed: 0.0,
            spindle: Spindle::Off,
            coolant: Coolant::default(),
            tool: 0,
            line: 0,
            frame: 0,
            named: AxisSet::ALL,
            relative: AxisSet::NONE,
            unknown: AxisSet::NONE,
        }
    }
}

impl Move {
    /// Length of the path the tool tip travels, in mm (0 for a dwell).
    pub fn length(&self) -> f64 {
        match self.kind {
            MoveKind::Arc(arc) => arc.length(self.start, self.end),
            MoveKind::Dwell(_) => 0.0,
            _ => self.start.distance(self.end),
        }
    }

    /// The distance the feed rate applies to: the tool tip's path with the
    /// rotary axes' turns added as if degrees were millimetres,
    /// `√(L² + ΔA² + ΔB² + ΔC²)`, as a Fanuc control feeds a move that turns
    /// a rotary axis (F in mm/min and deg/min at once; a rotary-only move is
    /// fed at F deg/min).
    ///
    /// U V W count as LinuxCNC counts them (its G-code reference, "Feed
    /// Rate"): where X Y Z move, F is along the X Y Z path and U V W follow
    /// in step; where only U V W move (rotary axes beside them or not), F
    /// is along the straight U V W path.
    pub fn feed_distance(&self) -> f64 {
        let (s, e) = (self.start, self.end);
        let turn = (e.a - s.a).powi(2) + (e.b - s.b).powi(2) + (e.c - s.c).powi(2);
        let length = self.length();
        if length == 0.0 && s.uvw() != e.uvw() {
            let d = [e.u - s.u, e.v - s.v, e.w - s.w];
            return (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        }
        if turn == 0.0 {
            length
        } else {
            (length.powi(2) + turn).sqrt()
        }
    }

    /// `true` for rapids, `false` for every move that cuts or dwells.
    pub fn is_rapid(&self) -> bool {
        matches!(self.kind, MoveKind::Rapid | MoveKind::Home | MoveKind::Machine)
    }
}

/// A sequence of moves, in execution order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Toolpath {
    /// The moves.
    pub moves: Vec<Move>,
    /// The frames the moves refer to; empty means every move is in the
    /// default frame (G54 at machine zero, no tool length offset).
    pub frames: Vec<Frame>,
    /// `true` when the first move's start is only an assumption (an NC
    /// program starts wherever the machine is; the interpreter puts it at
    /// zero): an axis is then where it is said to be only once a move has
    /// named it ([`Move::named`]). Generated toolpaths start where they say.
    pub unknown_start: bool,
    /// Blocks an NC writer must give the control as the program wrote them,
    /// in order: what the motion model does not describe (an M code, a
    /// `G10`, a signal written) or must not be written as plain moves (a
    /// tapping cycle).
    pub kept: Vec<Kept>,
}

/// A block kept for the writer: text of the NC language the moves came
/// from, opaque to everything but that language's writer.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Kept {
    /// Index of the first move the block comes before (the number of moves
    /// when it comes after the last).
    pub before: usize,
    /// How many moves from `before` on the block stands for: a G-code
    /// writer writes the block instead of them (a tapping cycle's motions,
    /// there for the simulation). 0 for a block that makes no move.
    pub moves: usize,
    /// The words, evaluated, in the program's units (`M13`, `G10 L2 P1 X10.`,
    /// `G84 X10. Y5. Z-8. R2. F1.25`); several blocks are several lines.
    pub text: String,
    /// The block sets work offsets (`G10 L2`): the frames after it have the
    /// origins it gave them, which a writer must not set again from the
    /// machine model.
    pub sets_offsets: bool,
    /// 1-based source line of the block.
    pub line: u32,
    /// A canned cycle's hole: the block leaves the cycle in force, and a
    /// writer ends it (G80) before anything but the next hole's block.
    pub cycle: Option<CycleBlock>,
    /// Tool, spindle and coolant when the block came: a writer brings the
    /// control to this state before the block, so that it keeps its place
    /// among tool changes and spindle and coolant codes.
    pub state: ToolState,
}

/// A kept canned-cycle block.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CycleBlock {
    /// The first hole: the cycle begins here (its initial level is where
    /// the tool is).
    Start,
    /// A further hole of the same cycle, right after the last one: the
    /// cycle and its initial level go on.
    Next,
}

/// The tool in the spindle, the spindle and the coolant.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ToolState {
    /// Tool number in the spindle.
    pub tool: u32,
    /// Spindle speed in rpm.
    pub speed: f64,
    /// Spindle direction.
    pub spindle: Spindle,
    /// Coolant state.
    pub coolant: Coolant,
}

impl ToolState {
    /// The state a move was made in.
    pub fn of(m: &Move) -> ToolState {
        ToolState { tool: m.tool, speed: m.speed, spindle: m.spindle, coolant: m.coolant }
    }
}

impl From<Vec<Move>> for Toolpath {
    fn from(moves: Vec<Move>) -> Toolpath {
        Toolpath { moves, ..Toolpath::default() }
    }
}

impl Toolpath {
    /// The frame `m` was made in.
    pub fn frame(&self, m: &Move) -> Frame {
        self.frames.get(m.frame as usize).copied().unwrap_or_default()
    }

    /// Appends a move.
    #[inline]
    pub fn push(&mut self, m: Move) {
        self.moves.push(m);
    }

    /// The kept blocks placed in a toolpath made from this one move by
    /// move: `first[i]` is the index there of the first move made from move
    /// `i`, `first[moves.len()]` the new number of moves. A transform that
    /// changes the number of moves keeps every block in its place so.
    pub fn kept_in(&self, first: &[usize]) -> Vec<Kept> {
        let n = self.moves.len();
        let at = |i: usize| first.get(i.min(n)).copied().unwrap_or_else(|| first.last().copied().unwrap_or(0));
        self.kept
            .iter()
            .map(|k| {
                let before = at(k.before);
                Kept { before, moves: at(k.before + k.moves) - before, ..k.clone() }
            })
            .collect()
    }

    /// For each move, whether a kept block stands for it (a tapping cycle's
    /// motions): transforms leave such moves as they are.
    pub fn covered(&self) -> Vec<bool> {
        let mut covered = vec![false; self.moves.len()];
        for k in &self.kept {
            let end = (k.before + k.moves).min(covered.len());
            covered[k.before.min(end)..end].iter_mut().for_each(|c| *c = true);
        }
        covered
    }

    /// Total length of non-rapid motion (feed, arc, probe), in mm.
    pub fn feed_length(&self) -> f64 {
        self.moves.iter().filter(|m| !m.is_rapid()).map(Move::length).fold(0.0, |a, b| a + b)
    }

    /// Total length of rapid motion, in mm.
    pub fn rapid_length(&self) -> f64 {
        self.moves.iter().filter(|m| m.is_rapid()).map(Move::length).fold(0.0, |a, b| a + b)
    }

    /// Smallest box holding every point the tool tip passes through (arcs
    /// included exactly at their quadrant points), or `None` without moves.
    pub fn bounds(&self) -> Option<([f64; 3], [f64; 3])> {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        let mut add = |p: [f64; 3]| {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        };
        for m in &self.moves {
            m.extreme_points(&mut add);
        }
        (!self.moves.is_empty()).then_some((lo, hi))
    }
}

/// Points where an arc reaches its extreme in the plane's axes.
fn arc_extremes(arc: &Arc, start: Axes, end: Axes) -> Vec<[f64; 3]> {
    let (i, j, _) = arc.plane.axes();
    let s = start.xyz();
    let r = arc.radius(start);
    let a0 = (s[j] - arc.center[j]).atan2(s[i] - arc.center[i]);
    let sweep = arc.sweep(start, end);
    let mut out = Vec::new();
    for q in 0..4 {
        let target = f64::from(q) * TAU / 4.0;
        // Angle travelled from the start to reach `target` in the arc's direction.
        let raw = if arc.ccw { target - a0 } else { a0 - target };
        let travel = raw.rem_euclid(TAU);
        if travel <= sweep {
            let t = travel / sweep;
            let mut p = arc.point_at(start, end, t).xyz();
            p[i] = arc.center[i] + r * target.cos();
            p[j] = arc.center[j] + r * target.sin();
            out.push(p);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(x: f64, y: f64, z: f64) -> Axes {
        Axes { x, y, z, ..Axes::ZERO }
    }

    #[test]
    fn empty_lengths_are_plus_zero() {
        // `Iterator::sum` of no floats is -0.0, which reports print as "-0".
        let path = Toolpath::default();
        assert!(path.feed_length().is_sign_positive() && path.rapid_length().is_sign_positive());
    }

    #[test]
    fn quarter_arc_length_and_bounds() {
        let arc = Arc { center: [0.0, 0.0, 0.0], plane: Plane::Xy, ccw: true, turns: 0 };
        let m =
            Move { kind: MoveKind::Arc(arc), start: at(10.0, 0.0, 0.0), end: at(0.0, 10.0, 0.0), ..Move::default() };
        assert!((m.length() - 5.0 * std::f64::consts::PI).abs() < 1e-12);
        let path = Toolpath::from(vec![m]);
        let (lo, hi) = path.bounds().unwrap();
        assert_eq!(lo, [0.0, 0.0, 0.0]);
        assert_eq!(hi, [10.0, 10.0, 0.0]);
    }

    #[test]
    fn full_circle_cw_reaches_all_quadrants() {
        let arc = Arc { center: [5.0, 0.0, 0.0], plane: Plane::Xy, ccw: false, turns: 0 };
        let m = Move { kind: MoveKind::Arc(arc), start: at(0.0, 0.0, 0.0), end: at(0.0, 0.0, -3.0), ..Move::default() };
        let len = m.length();
        assert!((len - (10.0 * std::f64::consts::PI).hypot(3.0)).abs() < 1e-9);
        let (lo, hi) = Toolpath::from(vec![m]).bounds().unwrap();
        assert!((lo[1] + 5.0).abs() < 1e-12 && (hi[1] - 5.0).abs() < 1e-12);
        assert!((hi[0] - 10.0).abs() < 1e-12 && lo[2] == -3.0);
    }

    #[test]
    fn kept_blocks_follow_a_transform_that_splits_moves() {
        // Moves 0 1 2 3; an M code before move 2, a cycle standing for
        // moves 1 and 2. Made again with move 1 split in three: 0 | 1 2 3 | 4 | 5.
        let mut path = Toolpath::from(vec![Move::default(); 4]);
        path.kept = vec![
            Kept { before: 2, moves: 0, text: "M01".into(), ..Kept::default() },
            Kept { before: 1, moves: 2, text: "G84".into(), ..Kept::default() },
        ];
        let kept = path.kept_in(&[0, 1, 4, 5, 6]);
        assert_eq!((kept[0].before, kept[0].moves), (4, 0));
        assert_eq!((kept[1].before, kept[1].moves), (1, 4));
        assert_eq!(path.covered(), [false, true, true, false]);
    }

    #[test]
    fn zx_plane_ccw_direction() {
        // G18: counter-clockwise seen from +Y goes from +Z toward +X.
        let arc = Arc { center: [0.0, 0.0, 0.0], plane: Plane::Zx, ccw: true, turns: 0 };
        let p = arc.point_at(at(0.0, 0.0, 10.0), at(10.0, 0.0, 0.0), 0.5);
        assert!(p.x > 7.0 && p.z > 7.0);
    }
}
