//! What the page's packed columns say of the path (the meta entries), and
//! each move's kind on the page; the columns themselves (one entry per
//! move: kind, tool, frame, line, feed, time, vertices; one per vertex:
//! position deltas in quanta, breaks) are written by
//! [`super::drawing`]. See [`super`] for the layout.

use kezuri_geom::{Move, MoveKind};

/// The kind of a move that ends where the program does not say (see
/// [`Move::unknown`]): not drawn, nor the tool there. A move from such a
/// place to a known one keeps its kind and is drawn as its end alone (one
/// vertex after a break): the tool is shown there, no line to it.
pub const UNPLACED: u8 = 6;

/// Position step of the packed coordinates, mm.
pub const QUANTUM_MM: f64 = 1e-4;

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
