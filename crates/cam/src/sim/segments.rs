//! A toolpath as straight segments, each with the tool that cuts it.

use kezuri_geom::{Move, MoveKind, Toolpath};

use super::sweep::{Prep, Shape};
use super::tools::{Slots, ToolCut, Tooling};
use super::{empty_toolpath, SimReport};
use crate::error::{Error, ErrorKind};

/// A straight piece of a move.
#[derive(Clone, Copy, Debug)]
pub(super) struct Segment {
    pub prep: Prep,
    /// Index of the move it belongs to.
    pub index: u32,
    /// The move's source line.
    pub line: u32,
    /// The move's lowest end (what a move too deep for the grid is said by).
    pub low: f64,
    /// The tool that cuts it: its index in [`Slots`].
    pub slot: u8,
    pub rapid: bool,
    /// A drill's feed that moves in X or Y: judged on what it cuts, as a
    /// rapid is.
    pub side: bool,
    /// The slab `from ≤ s ≤ to` of along-track distances whose cells this
    /// segment evaluates (see [`continuations`]).
    pub from: f64,
    pub to: f64,
    a: [f64; 3],
    b: [f64; 3],
}

/// Narrows each cutting segment's slab where the path runs straight on.
///
/// Where a cell lies behind a segment's start (`s < 0`) and the tip does
/// not descend (`Δz ≥ 0`), the envelope's minimum over the segment is at
/// its start: the derivative `−g + height'(ρ)·σ/ρ` is ≤ 0 for every
/// `σ ≤ s ≤ 0`. Likewise ahead of its end when it does not climb. For the
/// closed-form shapes the bound is sharper: the minimum is at the start
/// when `s ≤ q·k`, so when `s ≤ min(0, k·R)`. So where the previous segment
/// ends exactly at this one's start and runs in the same XY direction, the
/// cells behind `min(0, k·R)` (−R when descending, for the general shapes;
/// for a measured tool the bound from its flattest slope,
/// [`MeasuredTool::monotone_beyond`]) are cut at least as deep by the
/// previous segment through that shared point, and the same holds ahead of
/// the end. Following such cells from
/// segment to segment always ends at one that evaluates them (the same
/// direction means "behind this one's start" is never "ahead of the
/// previous one's end"), so the result is unchanged while a raster move
/// of 0.1 mm with a 6 mm ball evaluates a slab of about 0.7 mm instead of
/// its whole 6.1 mm footprint. Rapids and a drill's sideways feeds are never
/// narrowed, so each is judged on everything it cuts, and segments of two
/// tools never joined.
pub(super) fn continuations(segs: &mut [Segment], shapes: &[Shape<'_>]) {
    let joined = |p: &Segment, q: &Segment| {
        p.slot == q.slot
            && !p.rapid
            && !q.rapid
            && !p.side
            && !q.side
            && p.b == q.a
            && p.prep.len > 0.0
            && q.prep.len > 0.0
            && (p.prep.ux - q.prep.ux).abs() <= 1e-12
            && (p.prep.uy - q.prep.uy).abs() <= 1e-12
    };
    for k in 0..segs.len() {
        let p = segs[k].prep;
        let shape = &shapes[segs[k].slot as usize];
        let r = shape.radius();
        let eps = 1e-9 * (1.0 + r);
        let (back, ahead) = match shape {
            Shape::Closed { .. } => ((p.k * r).min(0.0), (p.k * r).max(0.0)),
            Shape::General(_) => (if p.dz < 0.0 { -r } else { 0.0 }, if p.dz > 0.0 { r } else { 0.0 }),
            Shape::Measured(m) => {
                let d = if p.dz == 0.0 { 0.0 } else { m.monotone_beyond(p.dz.abs() * p.inv_len) };
                (if p.dz < 0.0 { -d } else { 0.0 }, if p.dz > 0.0 { d } else { 0.0 })
            }
        };
        if k > 0 && joined(&segs[k - 1], &segs[k]) {
            segs[k].from = back - eps;
        }
        if k + 1 < segs.len() && joined(&segs[k], &segs[k + 1]) {
            segs[k].to = p.len + ahead + eps;
        }
    }
}

/// Most straight segments one piece of moves splits into (some 200 bytes
/// each): the whole path, where it is cut whole.
pub(super) const MAX_SEGMENTS: usize = 10_000_000;

/// A rapid whose start is not known but whose end Z is (see
/// [`SimReport::unplaced_moves`]): judged on where it ends.
#[derive(Clone, Copy, Debug)]
pub(super) struct Unplaced {
    pub index: u32,
    pub line: u32,
    pub end: [f64; 3],
}

/// Moves made into straight segments as they come, piece by piece: the
/// report so far (with [`SimReport::tools`] but no volumes yet) and the
/// tools' shapes by slot. Fed the whole path at once or in pieces, it
/// makes the same segments.
pub(super) struct Segmenter<'a> {
    tol: f64,
    pub slots: Slots<'a>,
    pub report: SimReport,
    /// The tool in the spindle (the first the program loads for the moves
    /// before it, as `cutting_tools` says); `None` before the first tool
    /// change where that tool is not known yet.
    current: Option<u32>,
    /// Axes (X Y Z bits) whose position is known; `None` before the first
    /// piece, which says whether the start is known.
    known: Option<u16>,
    /// Moves taken so far.
    moves: usize,
}

impl<'a> Segmenter<'a> {
    /// Before the first move; `first` is the first tool the program loads
    /// (0 for none), which cuts the moves before it is loaded; `None`: not
    /// known before the run, the moves before it cut by tool 0 (the one
    /// tool of [`Tooling::One`]) and named for it when it comes.
    pub fn new(tooling: Tooling<'a>, tol: f64, first: Option<u32>) -> Segmenter<'a> {
        let report = SimReport::default();
        Segmenter { tol, slots: Slots::new(tooling), report, current: first, known: None, moves: 0 }
    }

    /// The segments of the next `moves` of a path whose start is known
    /// unless `unknown_start`, added to `out` (program order), and the
    /// rapids from an unknown position to `unplaced`.
    pub fn add(
        &mut self,
        moves: &[Move],
        unknown_start: bool,
        out: &mut Vec<Segment>,
        unplaced: &mut Vec<Unplaced>,
    ) -> Result<(), Error> {
        // Weighed before the work: every arc's chords at `tol`.
        let tol = self.tol;
        let total = moves
            .iter()
            .map(|m| match m.kind {
                MoveKind::Arc(arc) => arc.chords(m.start, m.end, tol),
                _ => 1,
            })
            .fold(0usize, usize::saturating_add);
        if total > MAX_SEGMENTS {
            return Err(too_many_segments(total));
        }
        out.reserve(moves.len());
        // None known at the start of an NC program, where the start is only
        // the interpreter's assumption.
        let mut known = self.known.unwrap_or(if unknown_start { 0 } else { 0b111 });
        let (report, slots) = (&mut self.report, &mut self.slots);
        for (k, m) in moves.iter().enumerate() {
            let index = self.moves + k;
            if m.tool != 0 {
                if self.current.is_none() {
                    // The first tool loaded: the moves before were its own.
                    slots.name_first(m.tool);
                    if let Some(first) = report.tools.first_mut() {
                        first.number = m.tool;
                    }
                }
                self.current = Some(m.tool);
            }
            let number = self.current.unwrap_or(0);
            if matches!(m.kind, MoveKind::Dwell(_)) {
                continue;
            }
            if !m.start.to_array().iter().chain(&m.end.to_array()).all(|v| v.is_finite()) {
                return Err(Error::new(
                    ErrorKind::NonFinite,
                    format!("move {index} (line {}) has a coordinate that is not a finite number", m.line),
                ));
            }
            let slot = slots.slot(number, m.line)?;
            if slot as usize == report.tools.len() {
                report.tools.push(ToolCut { number, ..ToolCut::default() });
            }
            let cut = &mut report.tools[slot as usize];
            cut.moves += 1;
            report.moves += 1;
            // A return to the reference point (G28, G30) and a move in machine
            // coordinates (G53) go where the machine's setup puts them, which
            // the model only guesses: not simulated, and the axes they move
            // are unknown until the program names them again.
            let to_machine = matches!(m.kind, MoveKind::Home | MoveKind::Machine);
            let placed = known & 0b111 == 0b111 && !to_machine;
            known = if to_machine { known & !m.named.0 } else { known | m.named.0 };
            let index32 = u32::try_from(index).map_err(|_| too_many_segments(index))?;
            if !placed {
                report.unplaced_moves += 1;
                // Its end is judged where its Z is known: a guessed Z is no depth.
                if m.is_rapid() && !to_machine && known & 0b100 != 0 {
                    unplaced.push(Unplaced { index: index32, line: m.line, end: m.end.xyz() });
                }
                continue;
            }
            if (m.start.a, m.start.b, m.start.c) != (m.end.a, m.end.b, m.end.c) {
                report.rotary_moves += 1;
            }
            let rapid = m.is_rapid();
            let shape = &slots.shapes[slot as usize];
            let drill = slots.drills[slot as usize];
            let r = shape.radius();
            let before = out.len();
            let (line, low) = (m.line, m.start.z.min(m.end.z));
            let mut push = |a: [f64; 3], b: [f64; 3]| {
                let prep = Prep::new(a, b, shape);
                let side = drill && !rapid && (a[0] != b[0] || a[1] != b[1]);
                let (index, from, to) = (index32, -r, prep.len + r);
                out.push(Segment { prep, index, line, low, slot, rapid, side, from, to, a, b })
            };
            match m.kind {
                MoveKind::Arc(arc) => {
                    let n = arc.chords(m.start, m.end, tol);
                    let mut a = m.start.xyz();
                    for k in 1..=n {
                        let b =
                            if k == n { m.end.xyz() } else { arc.point_at(m.start, m.end, k as f64 / n as f64).xyz() };
                        push(a, b);
                        a = b;
                    }
                }
                _ => push(m.start.xyz(), m.end.xyz()),
            }
            cut.segments += out.len() - before;
            report.segments += out.len() - before;
        }
        self.known = Some(known);
        self.moves += moves.len();
        Ok(())
    }

    /// The report of every move taken; an error where none moved.
    pub fn finish(&self) -> Result<SimReport, Error> {
        if self.report.moves == 0 {
            return Err(empty_toolpath());
        }
        Ok(self.report.clone())
    }
}

/// The first tool `path` loads (0 for none): it cuts the moves before.
pub(super) fn first_tool(path: &Toolpath) -> u32 {
    path.moves.iter().map(|m| m.tool).find(|&t| t != 0).unwrap_or(0)
}

/// Arcs split into `n` chords, more than can be indexed.
fn too_many_segments(n: usize) -> Error {
    Error::new(
        ErrorKind::TooManySegments,
        format!(
            "the moves split into {n} straight segments (arcs in chords), more than {MAX_SEGMENTS}: raise the chord \
             tolerance"
        ),
    )
}
