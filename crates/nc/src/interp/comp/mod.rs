//! Cutter radius compensation (G41 / G42 / G40) as a pure function of a
//! toolpath: programmed tool-tip moves in, tool-centre moves out.
//!
//! The interpreter records, for every move, whether compensation was in
//! force ([`Comp`]) and hands the moves and those tags to [`compensate`].
//! Nothing here reads the interpreter's state. Two rule sets ([`Rules`]):
//! Fanuc cutter compensation C (start-up type A or B, the corner vectors of
//! type C, interference alarms) and LinuxCNC (entry move, arcs around
//! convex corners, the "gouging" errors). `docs/cutter-compensation.md`
//! lists every rule and where it comes from.
//!
//! # Runs
//! A run is a stretch of moves tagged with the same [`Comp`]. Its first move
//! that travels in the compensation plane is the start-up (entry) move; the
//! first untagged move after the run that is not a dwell is the cancel
//! (G40) move. Moves without travel in the plane (a Z plunge, a dwell) are
//! made at the tool centre's current offset point.
//!
//! # Example
//! ```
//! use kezuri_geom::{Axes, Move, MoveKind, Plane};
//! use kezuri_nc::interp::comp::{compensate, Comp, Rules, Side};
//! let at = |x: f64, y: f64| Axes { x, y, ..Axes::ZERO };
//! let line = |a: Axes, b: Axes| Move { kind: MoveKind::Feed, start: a, end: b, ..Move::default() };
//! // G42 D(r=1) G01 X10 Y0 (start-up, type A), Y10, then G40 X20: the
//! // start-up ends on the vector perpendicular to the next move.
//! let moves = [line(at(0.0, -5.0), at(10.0, 0.0)), line(at(10.0, 0.0), at(10.0, 10.0)), line(at(10.0, 10.0), at(20.0, 10.0))];
//! let comp = Comp { side: Side::Right, radius: 1.0, plane: Plane::Xy };
//! let out = compensate(&moves, &[Some(comp), Some(comp), None], Rules::default()).unwrap();
//! assert_eq!((out[0].end.x, out[0].end.y), (11.0, 0.0));
//! ```

mod alarm;
mod fanuc;
mod linuxcnc;
mod plane;

use std::f64::consts::TAU;

use kezuri_geom::{Arc, Axes, AxisSet, Move, MoveKind, Plane};

use crate::{Error, ErrorKind, Place};

use alarm::Alarm;
use plane::{in_plane, with_plane, wrap, Element, Path, SideSign, MIN_TRAVEL, V2};

/// The side of the programmed path the tool runs on, looking along the
/// direction of travel from the positive end of the plane's normal axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    /// G41: the tool on the left of the path.
    Left,
    /// G42: the tool on the right of the path.
    Right,
}

/// Fanuc's start-up and cancel type (a parameter on the control).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Approach {
    /// Type A: at an outside corner the start-up move ends on the vector
    /// perpendicular to the next move at its start (and the cancel move
    /// starts on the vector perpendicular to the last move at its end).
    #[default]
    A,
    /// Type B: at an outside corner the start-up and cancel moves get the
    /// corner vectors of an ordinary type C corner (the intersection, or
    /// the two extended vectors at an acute corner).
    B,
}

/// Which control's compensation to reproduce.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Rules {
    /// Fanuc cutter compensation C.
    Fanuc {
        /// Start-up and cancel type.
        startup: Approach,
    },
    /// LinuxCNC's interpreter (`interp_convert.cc`).
    LinuxCnc,
}

impl Default for Rules {
    fn default() -> Rules {
        Rules::Fanuc { startup: Approach::A }
    }
}

/// Cutter compensation in force for a move.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Comp {
    /// G41 or G42.
    pub side: Side,
    /// The radius register's value in mm, signed: a negative value puts the
    /// tool on the other side.
    pub radius: f64,
    /// The plane in force (G17, G18, G19).
    pub plane: Plane,
}

impl Comp {
    /// The side sign (+1 left, −1 right) and radius ≥ 0 after a negative
    /// register value has swapped the side.
    fn effective(&self) -> (SideSign, f64) {
        let s = if self.side == Side::Left { 1.0 } else { -1.0 };
        if self.radius < 0.0 {
            (-s, -self.radius)
        } else {
            (s, self.radius)
        }
    }
}

/// LinuxCNC's refusal of an entry move (an arc, with `arc`) whose travel
/// in the plane is not longer than the tool radius, in its words.
pub(crate) fn entry_too_short(arc: bool) -> String {
    Alarm::EntryTooShort { arc }.text(Rules::LinuxCnc)
}

/// Why a toolpath cannot be compensated: the move in the input the control
/// would stop on, and what is wrong, worded as the control's alarm.
fn stop(move_index: usize, message: String) -> Error {
    Error::new(ErrorKind::Compensation, message).at(Place::Compensated(move_index))
}

/// Applies cutter radius compensation.
///
/// `tags[i]` is the compensation in force for `moves[i]`; `None` is off
/// (G40). `moves` are continuous tool-tip moves in machine coordinates.
/// The result is the tool-centre moves in order: more than the input where
/// corners get extra vectors or arcs, each keeping the `line`, feed, frame
/// and the rest of the input move it comes from (generated corner moves
/// take them from the move that owns the corner; compensated moves name
/// the plane's axes too). Uncompensated moves are copied unchanged.
///
/// # Errors
/// An [`Error`] of kind [`ErrorKind::Compensation`] at the offending
/// move ([`Place::Compensated`], its index in `moves`): interference (a
/// compensated move that runs backwards, an inside arc not larger than the
/// cutter), no intersection at a corner, an arc on a start-up or cancel
/// move (Fanuc) or after G40 (LinuxCNC), a probe or machine-coordinate move
/// while compensation is on, or a change of [`Comp`] without G40 between.
pub fn compensate(moves: &[Move], tags: &[Option<Comp>], rules: Rules) -> Result<Vec<Move>, Error> {
    compensate_traced(moves, tags, rules).map(|(out, _)| out)
}

/// [`compensate`], and for each output move the index of the input move
/// it comes from (the owner, for a corner move): non-decreasing, so that
/// anything placed by input index (a kept block) can be placed in the
/// output.
///
/// # Errors
/// As [`compensate`].
pub fn compensate_traced(
    moves: &[Move],
    tags: &[Option<Comp>],
    rules: Rules,
) -> Result<(Vec<Move>, Vec<usize>), Error> {
    compensate_with_returns(moves, tags, &[], &[], rules)
}

/// [`compensate_traced`], where `returns` (ascending input indices) are the
/// returns of Fanuc's multiple repetitive cycles (G70–G73) to their start
/// points: untagged moves after which compensation goes on. A run that
/// such a return ends leaves its last move on the vector perpendicular to
/// it, whatever the turn to the return (the cycle's offset ends with its
/// shape), and the return runs from there to the start point with the
/// offset cancelled; the next compensated move is a new start-up.
///
/// `jumps` (ascending input indices, each with a point) are LinuxCNC's
/// jumps of the tool centre its compensation works from: before move
/// `index` that point is taken to the point given, without a move, as
/// reading a G70's profile takes it to the profile's end ([`Rules::LinuxCnc`]
/// only; `docs/cutter-compensation.md`, "LinuxCNC's G70").
pub(crate) fn compensate_with_returns(
    moves: &[Move],
    tags: &[Option<Comp>],
    returns: &[usize],
    jumps: &[(usize, Axes)],
    rules: Rules,
) -> Result<(Vec<Move>, Vec<usize>), Error> {
    if tags.len() != moves.len() {
        let message = format!("{} compensation tags for {} moves", tags.len(), moves.len());
        return Err(stop(tags.len().min(moves.len()), message));
    }
    let mut out = Vec::with_capacity(moves.len() + moves.len() / 2);
    let mut origin = Vec::with_capacity(out.capacity());
    let mut cur = moves.first().map_or(Axes::ZERO, |m| m.start);
    let mut i = 0;
    while i < moves.len() {
        let Some(comp) = tags[i] else {
            out.push(moves[i]);
            origin.push(i);
            cur = moves[i].end;
            i += 1;
            continue;
        };
        let mut end = i;
        while end < moves.len() && tags[end] == Some(comp) {
            end += 1;
        }
        if end < moves.len() && tags[end].is_some() {
            return Err(Alarm::Changed.at(end, rules));
        }
        // Dwells after G40 happen where the tool is; the cancel move is the
        // first untagged move that is not one.
        let mut exit = end;
        while exit < moves.len() && tags[exit].is_none() && matches!(moves[exit].kind, MoveKind::Dwell(_)) {
            exit += 1;
        }
        let run = Run::new(moves, i..exit, (exit < moves.len() && tags[exit].is_none()).then_some(exit), comp, rules)?;
        let cycle_return = run.exit.is_some_and(|x| returns.binary_search(&x).is_ok());
        let jumps = jumps.iter().filter(|(k, _)| (i..exit).contains(k)).map(|&(k, p)| (k, in_plane(p, comp.plane)));
        let run = Run { start: in_plane(cur, comp.plane), cycle_return, jumps: jumps.collect(), ..run };
        let steps = if run.r == 0.0 {
            (i..exit).map(|index| Step::Keep { index }).chain(run.exit.map(|index| Step::Keep { index })).collect()
        } else {
            match rules {
                Rules::Fanuc { startup } => fanuc::plan(&run, startup)?,
                Rules::LinuxCnc => linuxcnc::plan(&run)?,
            }
        };
        emit(&run, &steps, &mut out, &mut origin, &mut cur)?;
        i = run.exit.map_or(exit, |x| x + 1);
    }
    Ok((out, origin))
}

/// One compensated run and what the planners need of it.
struct Run<'a> {
    moves: &'a [Move],
    /// The run's moves in order: plane elements and moves made in place.
    items: Vec<Item>,
    /// The cancel move.
    exit: Option<usize>,
    s: SideSign,
    r: f64,
    plane: Plane,
    rules: Rules,
    /// The tool's plane position before the run.
    start: V2,
    /// The cancel move is a repetitive cycle's return to its start point:
    /// the last move ends on its perpendicular vector.
    cycle_return: bool,
    /// LinuxCNC: before move `index`, the tool centre the compensation
    /// works from is taken to the plane point given, without a move.
    jumps: Vec<(usize, V2)>,
}

/// A move of a run.
#[derive(Clone, Copy, Debug)]
enum Item {
    /// A move with travel in the plane.
    Plane(Element),
    /// A move without (a plunge, a dwell), made at the current point.
    Pass(usize),
}

impl<'a> Run<'a> {
    fn new(
        moves: &'a [Move],
        range: std::ops::Range<usize>,
        exit: Option<usize>,
        comp: Comp,
        rules: Rules,
    ) -> Result<Run<'a>, Error> {
        let (s, r) = comp.effective();
        if rules == Rules::LinuxCnc && comp.plane == Plane::Yz && r > 0.0 {
            return Err(Alarm::PlaneUnsupported.at(range.start, rules));
        }
        let mut items = Vec::with_capacity(range.len());
        for index in range {
            let m = &moves[index];
            match m.kind {
                MoveKind::Probe => return Err(Alarm::Probe.at(index, rules)),
                MoveKind::Home => return Err(Alarm::Home.at(index, rules)),
                MoveKind::Machine => return Err(Alarm::Machine.at(index, rules)),
                MoveKind::Arc(arc) if arc.plane != comp.plane => return Err(Alarm::ArcOtherPlane.at(index, rules)),
                MoveKind::Arc(arc) if arc.radius(m.start) < MIN_TRAVEL || arc.radius(m.end) < MIN_TRAVEL => {
                    return Err(Alarm::ZeroRadiusArc.at(index, rules))
                }
                _ => {}
            }
            items.push(Element::of(m, index, comp.plane).map_or(Item::Pass(index), Item::Plane));
        }
        let start = V2::new(0.0, 0.0);
        Ok(Run { moves, items, exit, s, r, plane: comp.plane, rules, start, cycle_return: false, jumps: Vec::new() })
    }

    /// The offset path of `e`, refusing an inside arc not larger than the
    /// cutter.
    fn path(&self, e: &Element) -> Result<Path, Error> {
        match e.arc {
            Some(c) if e.tool_inside(self.s) && c.radius <= self.r => {
                Err(Alarm::InsideArcTooSmall.at(e.index, self.rules))
            }
            _ => Ok(e.offset_path(self.s, self.r)),
        }
    }

    /// The compensated move for element `e` ending at `end`; `forward` is
    /// the direction a straight move must not run against.
    fn cut(&self, e: &Element, end: V2, forward: Option<V2>) -> Step {
        match e.arc {
            None => Step::Line { index: e.index, end, forward },
            Some(c) => Step::Arc { index: e.index, end, centre: c.centre, check: true },
        }
    }

    /// Where the tool centre is taken just before move `index`, if it is.
    fn jump_before(&self, index: usize) -> Option<V2> {
        self.jumps.iter().find(|(k, _)| *k == index).map(|&(_, p)| p)
    }

    /// The cancel move, when it is a straight move with travel in the plane.
    fn exit_element(&self) -> Option<Element> {
        let x = self.exit?;
        Element::of(&self.moves[x], x, self.plane).filter(|e| e.arc.is_none())
    }
}

/// What the emitter makes, in order.
#[derive(Clone, Copy, Debug)]
enum Step {
    /// Input move `index` unchanged (compensation with radius 0).
    Keep { index: usize },
    /// Straight move `index` compensated, from the current point to `end`.
    Line { index: usize, end: V2, forward: Option<V2> },
    /// Arc `index` compensated, from the current point to `end` around
    /// `centre`; `check`: refuse it if it now runs backwards.
    Arc { index: usize, end: V2, centre: V2, check: bool },
    /// A corner move made for input move `owner`: straight, or an arc
    /// around `(centre, ccw)`.
    Link { owner: usize, to: V2, around: Option<(V2, bool)> },
    /// Input move `index` made at the current plane point.
    Pass { index: usize },
    /// The cancel move: from the current point to its programmed end.
    Exit { index: usize },
}

fn emit(run: &Run, steps: &[Step], out: &mut Vec<Move>, origin: &mut Vec<usize>, cur: &mut Axes) -> Result<(), Error> {
    let plane = run.plane;
    let (i, j, _) = plane.axes();
    let named = |m: &Move| AxisSet(m.named.0 | (1 << i) | (1 << j));
    for step in steps {
        let start = *cur;
        let here = in_plane(start, plane);
        let m = match *step {
            Step::Keep { index } => run.moves[index],
            Step::Line { index, end, forward } => {
                let m = &run.moves[index];
                if forward.is_some_and(|f| end.sub(here).dot(f) < 0.0) {
                    return Err(Alarm::Backwards { arc: false, rapid: m.kind == MoveKind::Rapid }.at(index, run.rules));
                }
                Move { start, end: with_plane(m.end, plane, end), named: named(m), ..*m }
            }
            Step::Arc { index, end, centre, check } => {
                let m = &run.moves[index];
                let MoveKind::Arc(arc) = m.kind else { unreachable!("arc steps come from arcs") };
                let c = plane::Element::of(m, index, plane).and_then(|e| e.arc).expect("an arc is an element");
                let turns = if check {
                    // The sweep followed continuously from the programmed
                    // ends to the compensated ones.
                    let k = if arc.ccw { 1.0 } else { -1.0 };
                    let moved = |p: V2, q: V2| wrap(k * (p.sub(centre).angle() - q.sub(c.centre).angle()));
                    let sweep = c.sweep - moved(here, in_plane(m.start, plane)) + moved(end, in_plane(m.end, plane));
                    if sweep < -MIN_TRAVEL {
                        return Err(Alarm::Backwards { arc: true, rapid: false }.at(index, run.rules));
                    }
                    if sweep <= MIN_TRAVEL {
                        // Nothing of the arc is left: keep its other axes' travel.
                        out.push(Move { kind: MoveKind::Feed, start, end: with_plane(m.end, plane, end), ..*m });
                        origin.push(index);
                        *cur = out.last().expect("pushed").end;
                        continue;
                    }
                    ((sweep - MIN_TRAVEL) / TAU).floor() as u32
                } else {
                    arc.turns
                };
                let mut center = start.xyz();
                (center[i], center[j]) = (centre.u, centre.v);
                let kind = MoveKind::Arc(Arc { center, turns, ..arc });
                Move { kind, start, end: with_plane(m.end, plane, end), named: named(m), ..*m }
            }
            Step::Link { owner, to, around } => {
                if to.dist(here) <= 1e-12 {
                    continue;
                }
                let m = &run.moves[owner];
                let kind = match around {
                    Some((c, ccw)) => {
                        let mut center = start.xyz();
                        (center[i], center[j]) = (c.u, c.v);
                        MoveKind::Arc(Arc { center, plane, ccw, turns: 0 })
                    }
                    None if m.kind == MoveKind::Rapid => MoveKind::Rapid,
                    None => MoveKind::Feed,
                };
                Move { kind, start, end: with_plane(start, plane, to), named: named(m), ..*m }
            }
            Step::Pass { index } => {
                let m = &run.moves[index];
                Move { start, end: with_plane(m.end, plane, here), ..*m }
            }
            Step::Exit { index } => {
                let m = &run.moves[index];
                Move { start, named: named(m), ..*m }
            }
        };
        let index = step_index(step);
        let finite = |a: Axes| a.to_array().iter().all(|v| v.is_finite());
        let centre_ok = match m.kind {
            MoveKind::Arc(a) => a.center.iter().all(|v| v.is_finite()),
            _ => true,
        };
        if !(finite(m.start) && finite(m.end) && centre_ok) {
            return Err(Alarm::Numeric.at(index, run.rules));
        }
        out.push(m);
        origin.push(index);
        *cur = m.end;
    }
    Ok(())
}

fn step_index(step: &Step) -> usize {
    match *step {
        Step::Keep { index }
        | Step::Line { index, .. }
        | Step::Arc { index, .. }
        | Step::Pass { index }
        | Step::Exit { index } => index,
        Step::Link { owner, .. } => owner,
    }
}
