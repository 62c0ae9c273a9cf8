//! The toolpath as the page's packed columns: one entry per move (kind,
//! tool, frame, line, feed, time, vertices) and one per vertex (position
//! deltas in quanta, breaks). See [`super`] for the layout.

use kezuri_geom::{AxisSet, Move, MoveKind, Toolpath};
use serde_json::{json, Value};

use super::blob::Blob;
use crate::{Error, ErrorKind};

/// The kind of a move that ends where the program does not say (see
/// [`Move::unknown`]): not drawn, nor the tool there. A move from such a
/// place to a known one keeps its kind and is drawn as its end alone (one
/// vertex after a break): the tool is shown there, no line to it.
pub const UNPLACED: u8 = 6;

/// Position step of the packed coordinates, mm.
pub const QUANTUM_MM: f64 = 1e-4;

/// Largest distance from the packing origin, in quanta (±107 m), so that a
/// difference of two positions fits an `i32`.
const REACH: i64 = 1 << 30;

/// How a tool looks on the page.
pub struct ToolLook {
    /// Tool number (0: the program loads none).
    pub number: u32,
    /// `T2 ball:6`.
    pub label: String,
    /// The shape spec, where known.
    pub shape: Option<String>,
    /// The outline from the tip up, `(z, r)` in mm, z increasing; `None`
    /// where the shape is not known.
    pub profile: Option<Vec<[f64; 2]>>,
}

/// What [`pack`] found: the meta entries of the path.
pub struct Packed {
    /// Moves packed.
    pub moves: usize,
    /// Vertices packed.
    pub vertices: usize,
    /// Where the vertex deltas start, mm.
    pub origin: [f64; 3],
    /// The box of the path as drawn (positions the program gives), mm,
    /// where it draws any.
    pub bounds: Option<([f64; 3], [f64; 3])>,
    /// Whether a move turns a rotary axis.
    pub rotary: bool,
    /// The work zeros, by the index the moves give.
    pub frames: Vec<[f64; 3]>,
    /// The tools, by the index the moves give.
    pub tools: Vec<ToolLook>,
}

impl Packed {
    /// The meta entries the path gives.
    pub fn meta(&self) -> Value {
        let tools: Vec<Value> = self
            .tools
            .iter()
            .map(|t| json!({"number": t.number, "label": t.label, "shape": t.shape, "profile": t.profile}))
            .collect();
        json!({
            "moves": self.moves,
            "vertices": self.vertices,
            "quantum_mm": QUANTUM_MM,
            "origin_mm": self.origin,
            "frames": self.frames,
            "tools": tools,
            "rotary": self.rotary,
        })
    }
}

/// The page's kind of a move: 0 rapid, 1 feed, 2 arc, 3 plunge, 4 probe,
/// 5 dwell, 6 [`UNPLACED`].
pub fn kind(m: &Move) -> u8 {
    if m.unknown.0 & 0b111 != 0 {
        return UNPLACED;
    }
    match m.kind {
        MoveKind::Rapid | MoveKind::Home | MoveKind::Machine => 0,
        MoveKind::Feed if m.start.x == m.end.x && m.start.y == m.end.y && m.end.z < m.start.z => 3,
        MoveKind::Feed => 1,
        MoveKind::Arc(_) => 2,
        MoveKind::Probe => 4,
        MoveKind::Dwell(_) => 5,
    }
}

/// The points a move is drawn through after its start: the end, or an
/// arc's chords within `tol`; none for a move of kind [`UNPLACED`], and
/// only the end for one whose start is not known (`from_unknown`).
fn points(m: &Move, kind: u8, from_unknown: bool, tol: f64, out: &mut Vec<[f64; 3]>) {
    out.clear();
    match m.kind {
        _ if kind == UNPLACED => {}
        MoveKind::Dwell(_) => {}
        _ if from_unknown => out.push(m.end.xyz()),
        MoveKind::Arc(arc) => {
            let n = arc.chords(m.start, m.end, tol);
            out.extend((1..n).map(|k| arc.point_at(m.start, m.end, k as f64 / n as f64).xyz()));
            out.push(m.end.xyz());
        }
        _ => out.push(m.end.xyz()),
    }
}

/// Packs `path` into `blob` (sections 1 to 9): `kinds` is each move's
/// page kind (see [`kind`]), `seconds` its time, `looks` the tools by
/// number, arcs as chords within `tol` mm.
pub fn pack(
    path: &Toolpath,
    kinds: &[u8],
    seconds: &[f64],
    looks: Vec<ToolLook>,
    tol: f64,
    blob: &mut Blob,
) -> Result<Packed, Error> {
    let moves = &path.moves;
    // Whether each move starts where the program does not say.
    let first = if path.unknown_start { AxisSet::ALL } else { AxisSet::NONE };
    let from_unknown: Vec<bool> =
        std::iter::once(first).chain(moves.iter().map(|m| m.unknown)).map(|u| u.0 & 0b111 != 0).collect();
    // The box of what is drawn: every point below.
    let mut through = Vec::new();
    let mut bounds: Option<([f64; 3], [f64; 3])> = None;
    for ((m, &k), &unknown) in moves.iter().zip(kinds).zip(&from_unknown) {
        points(m, k, unknown, tol, &mut through);
        let start = (!unknown && !through.is_empty()).then(|| m.start.xyz());
        for p in start.iter().chain(&through) {
            let (lo, hi) = bounds.get_or_insert((*p, *p));
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    let origin = match bounds {
        Some((lo, hi)) => std::array::from_fn(|k| ((lo[k] + hi[k]) / 2.0 / QUANTUM_MM).round() * QUANTUM_MM),
        None => [0.0; 3],
    };
    let quantize = |p: [f64; 3]| -> Result<[i64; 3], Error> {
        let mut q = [0i64; 3];
        for k in 0..3 {
            let v = ((p[k] - origin[k]) / QUANTUM_MM).round();
            if !v.is_finite() || v.abs() >= REACH as f64 {
                return Err(Error::new(
                    ErrorKind::PositionOutOfReach,
                    format!("a position {:.3} mm from the middle of the program cannot be shown", p[k] - origin[k]),
                ));
            }
            q[k] = v as i64;
        }
        Ok(q)
    };

    // Tools by first use; frames by their zero.
    let mut tools: Vec<ToolLook> = Vec::new();
    let mut looks = looks;
    let mut frames: Vec<[f64; 3]> = Vec::new();
    let mut frame_of: Vec<Option<u16>> = vec![None; path.frames.len().max(1)];
    let mut tool_column = Vec::with_capacity(moves.len());
    let mut frame_column = Vec::with_capacity(moves.len());
    for m in moves {
        let tool = match tools.iter().position(|t| t.number == m.tool) {
            Some(i) => i as u16,
            None if tools.len() < usize::from(u16::MAX) => {
                let look = match looks.iter().position(|l| l.number == m.tool) {
                    Some(i) => looks.swap_remove(i),
                    None => ToolLook { number: m.tool, label: format!("T{}", m.tool), shape: None, profile: None },
                };
                tools.push(look);
                (tools.len() - 1) as u16
            }
            None => {
                return Err(Error::new(
                    ErrorKind::TooManyTools,
                    format!("the program uses more than {} tools: too many to show", u16::MAX),
                ))
            }
        };
        tool_column.push(tool);
        let f = (m.frame as usize).min(frame_of.len() - 1);
        let index = match frame_of[f] {
            Some(i) => i,
            None => {
                let zero = path.frames.get(f).map_or([0.0; 3], |fr| fr.zero().xyz());
                let i = match frames.iter().position(|z| *z == zero) {
                    Some(i) => i,
                    None => {
                        frames.push(zero);
                        frames.len() - 1
                    }
                };
                let i = u16::try_from(i).unwrap_or(u16::MAX);
                frame_of[f] = Some(i);
                i
            }
        };
        frame_column.push(index);
    }
    if frames.is_empty() {
        frames.push([0.0; 3]);
    }

    // Vertices: each move's start where the one before ended elsewhere,
    // then its points.
    let mut counts = Vec::with_capacity(moves.len());
    let mut deltas: [Vec<i32>; 3] = Default::default();
    let mut breaks: Vec<u8> = Vec::new();
    let mut last: Option<[i64; 3]> = None;
    let mut rotary = false;
    let mut push = |q: [i64; 3], brk: bool, last: &mut Option<[i64; 3]>| {
        let before = last.unwrap_or([0; 3]);
        for k in 0..3 {
            deltas[k].push((q[k] - before[k]) as i32);
        }
        breaks.push(u8::from(brk));
        *last = Some(q);
    };
    for ((m, &k), &unknown) in moves.iter().zip(kinds).zip(&from_unknown) {
        rotary |= m.start.a != m.end.a || m.start.b != m.end.b || m.start.c != m.end.c;
        points(m, k, unknown, tol, &mut through);
        let mut count = 0u32;
        if unknown && !through.is_empty() {
            // Arrived at a known place from an unknown one: no segment.
            push(quantize(through[0])?, true, &mut last);
            count += 1;
        } else if !through.is_empty() {
            let start = quantize(m.start.xyz())?;
            if last != Some(start) {
                push(start, true, &mut last);
                count += 1;
            }
            for p in &through {
                push(quantize(*p)?, false, &mut last);
                count += 1;
            }
        }
        counts.push(count);
    }

    blob.bytes(kinds.iter().copied());
    blob.u16s(tool_column);
    blob.u16s(frame_column);
    let mut line = 0i64;
    blob.i32s(moves.iter().map(|m| {
        let d = i64::from(m.line) - line;
        line = i64::from(m.line);
        d as i32
    }));
    blob.f32s(moves.iter().zip(kinds).map(|(m, &k)| if k == 0 || k == 5 { 0.0 } else { m.feed as f32 }));
    blob.f32s(seconds.iter().map(|&s| s as f32));
    blob.u32s(counts);
    let vertices = breaks.len();
    for d in deltas {
        blob.i32s(d);
    }
    blob.bytes(breaks);
    Ok(Packed { moves: moves.len(), vertices, origin, bounds, rotary, frames, tools })
}
