//! A toolpath as straight segments, each with the tool that cuts it.

use kezuri_geom::{MoveKind, Toolpath};

use super::sweep::{Prep, Shape};
use super::tools::{cutting_tools, Slots, ToolCut, Tooling};
use super::{empty_toolpath, SimReport};
use crate::error::{Error, ErrorKind};

/// A straight piece of a move.
#[derive(Clone, Copy, Debug)]
pub(super) struct Segment {
    pub prep: Prep,
    /// Index of the move it belongs to.
    pub index: u32,
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
fn continuations(segs: &mut [Segment], shapes: &[Shape<'_>]) {
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

/// Most straight segments a simulation holds (some 200 bytes each).
pub(super) const MAX_SEGMENTS: usize = 10_000_000;

/// The straight segments to simulate (program order), the report so far
/// (with [`SimReport::tools`] but no volumes yet), the tools' shapes by
/// slot, and the rapids whose start is not known but whose end Z is (see
/// [`SimReport::unplaced_moves`]).
#[allow(clippy::type_complexity)]
pub(super) fn segments<'a>(
    path: &Toolpath,
    tooling: Tooling<'a>,
    tol: f64,
) -> Result<(Vec<Segment>, SimReport, Slots<'a>, Vec<usize>), Error> {
    // Weighed before the work: every arc's chords at `tol`.
    let total = path
        .moves
        .iter()
        .map(|m| match m.kind {
            MoveKind::Arc(arc) => arc.chords(m.start, m.end, tol),
            _ => 1,
        })
        .fold(0usize, usize::saturating_add);
    if total > MAX_SEGMENTS {
        return Err(too_many_segments(total));
    }
    let mut out = Vec::with_capacity(path.moves.len());
    let mut report = SimReport::default();
    let mut slots = Slots::new(tooling);
    // Axes (X Y Z bits) whose position is known: none at the start of an
    // NC program, where the start is only the interpreter's assumption.
    let mut known = if path.unknown_start { 0u16 } else { 0b111 };
    let mut unplaced_rapids = Vec::new();
    for ((index, m), number) in path.moves.iter().enumerate().zip(cutting_tools(path)) {
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
        if !placed {
            report.unplaced_moves += 1;
            // Its end is judged where its Z is known: a guessed Z is no depth.
            if m.is_rapid() && !to_machine && known & 0b100 != 0 {
                unplaced_rapids.push(index);
            }
            continue;
        }
        if (m.start.a, m.start.b, m.start.c) != (m.end.a, m.end.b, m.end.c) {
            report.rotary_moves += 1;
        }
        let index32 = u32::try_from(index).map_err(|_| too_many_segments(index))?;
        let rapid = m.is_rapid();
        let shape = &slots.shapes[slot as usize];
        let drill = slots.drills[slot as usize];
        let r = shape.radius();
        let before = out.len();
        let mut push = |a: [f64; 3], b: [f64; 3]| {
            let prep = Prep::new(a, b, shape);
            let side = drill && !rapid && (a[0] != b[0] || a[1] != b[1]);
            out.push(Segment { prep, index: index32, slot, rapid, side, from: -r, to: prep.len + r, a, b })
        };
        match m.kind {
            MoveKind::Arc(arc) => {
                let n = arc.chords(m.start, m.end, tol);
                let mut a = m.start.xyz();
                for k in 1..=n {
                    let b = if k == n { m.end.xyz() } else { arc.point_at(m.start, m.end, k as f64 / n as f64).xyz() };
                    push(a, b);
                    a = b;
                }
            }
            _ => push(m.start.xyz(), m.end.xyz()),
        }
        cut.segments += out.len() - before;
    }
    if report.moves == 0 {
        return Err(empty_toolpath());
    }
    report.segments = out.len();
    continuations(&mut out, &slots.shapes);
    Ok((out, report, slots, unplaced_rapids))
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
