//! Level of detail: the path drawn within a tolerance, so that the page of
//! any program fits its budget.
//!
//! A [`Simplifier`] is fed the moves one at a time and hands on the
//! segments to draw. Consecutive moves of the same colour on the page (the
//! same page kind — rapid, feed, arc, plunge, probe — the same tool and
//! work zero, each starting where the last ended) form a run; arcs are
//! taken as their chords within half the tolerance, and each run is drawn
//! through the fewest of its own points that keep every dropped point within
//! the other half of the tolerance of the drawn line (Douglas–Peucker, as
//! `convert --shorten` merges). The band around a segment is convex, so the
//! original lines between two kept points are inside it too, and an arc is
//! within its chords' sagitta of them: every point of the path is within
//! the tolerance of the line drawn for it, and every drawn point lies on the
//! path. A run is drawn in windows of at most [`WINDOW`] points (each
//! window's last point is kept), so a simplifier holds a bounded number of
//! moves whatever the program's length.
//!
//! What keeps its place: moves of different colours, tools or work zeros
//! are never merged, a move that does not start where the last ended starts
//! a new run, and dwells, moves that turn a rotary axis, moves to or from a
//! place the program does not give (see [`super::pack::UNPLACED`]) and moves
//! with a coordinate that is not a number are drawn whole, as at full
//! detail.
//!
//! The tolerance is chosen before the page is built ([`super::stream`]):
//! as the path is fed, the full detail and every tolerance of
//! [`TOLERANCES`] are counted at once, each at its reckoned size
//! ([`MOVE_BYTES`], [`VERTEX_BYTES`]) and kept while that fits, and the
//! finest that fits is drawn. (Where a page still comes out larger, the
//! next coarser one kept is drawn.)

use kezuri_cam::shorten::douglas_peucker;
use kezuri_geom::{Move, MoveKind};

pub use super::pack::{kind, UNPLACED};

/// Most points of a run held at once.
pub const WINDOW: usize = 1024;

/// The tolerances a page may be simplified to, mm, finest first; the last is
/// the coarsest that still shows a toolpath.
pub const TOLERANCES: [f64; 12] = [0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0];

/// Bytes of the page a drawn move is reckoned to cost: its columns,
/// gzipped and in base64 (a move and its vertex take some 2 bytes on a
/// smooth raster, 6 to 8 where every coordinate changes unevenly).
pub const MOVE_BYTES: f64 = 6.0;

/// Bytes of the page a vertex is reckoned to cost (as [`MOVE_BYTES`]).
pub const VERTEX_BYTES: f64 = 4.0;

/// One move to draw: the move (a straight one where merged or cut from an
/// arc), its page kind and its seconds (those of the moves it stands for).
#[derive(Clone, Debug)]
pub struct Drawn {
    /// The move: its start and end, and the state of the last move it
    /// stands for (line, feed, tool, work zero).
    pub mv: Move,
    /// Its kind on the page (see [`kind`]): the kind of the moves it
    /// stands for.
    pub kind: u8,
    /// The seconds of the moves it stands for.
    pub seconds: f64,
}

/// The path simplified to a tolerance, fed move by move (see the module
/// documentation).
pub struct Simplifier {
    /// Douglas–Peucker's tolerance, mm (half the whole).
    lines: f64,
    /// The sagitta of the chords of arcs, mm (the other half).
    chords: f64,
    /// The current run: its page kind and its points (the first is where it
    /// starts, each later one the end of a move or of a chord, with the
    /// seconds since the point before).
    run_kind: u8,
    run: Vec<(Move, f64)>,
    /// Whether the next move starts where the program does not say.
    from_unknown: bool,
}

impl Simplifier {
    /// A simplifier to `tolerance` mm; `unknown_start`: the first move
    /// starts where the program does not say.
    pub fn new(tolerance: f64, unknown_start: bool) -> Simplifier {
        Simplifier {
            lines: tolerance / 2.0,
            chords: tolerance / 2.0,
            run_kind: 0,
            run: Vec::new(),
            from_unknown: unknown_start,
        }
    }

    /// Moves held now (never more than [`WINDOW`]).
    pub fn held(&self) -> usize {
        self.run.len()
    }

    /// Takes the next move and its seconds; hands `out` what is drawn.
    pub fn push(&mut self, m: &Move, seconds: f64, out: &mut impl FnMut(Drawn)) {
        let page_kind = kind(m);
        let from_unknown = std::mem::replace(&mut self.from_unknown, m.unknown.0 & 0b111 != 0);
        let finite = m.start.to_array().iter().chain(&m.end.to_array()).all(|v| v.is_finite());
        let rotary = m.start.a != m.end.a || m.start.b != m.end.b || m.start.c != m.end.c;
        let whole = from_unknown
            || !finite
            || rotary
            || matches!(page_kind, UNPLACED | 5)
            || matches!(m.kind, MoveKind::Home | MoveKind::Machine);
        if whole {
            self.finish(out);
            out(Drawn { mv: *m, kind: page_kind, seconds });
            return;
        }
        let continues = self.run.last().is_some_and(|(last, _)| {
            self.run_kind == page_kind
                && last.end == m.start
                && last.tool == m.tool
                && last.frame == m.frame
                && last.unknown == m.unknown
        });
        if !continues {
            self.finish(out);
            self.run_kind = page_kind;
            self.run.push((Move { end: m.start, ..*m }, 0.0));
        }
        match m.kind {
            MoveKind::Arc(arc) => {
                let n = arc.chords(m.start, m.end, self.chords);
                for k in 1..=n {
                    let end = if k == n { m.end } else { arc.point_at(m.start, m.end, k as f64 / n as f64) };
                    self.point(Move { kind: MoveKind::Feed, end, ..*m }, seconds / n as f64, out);
                }
            }
            _ => self.point(*m, seconds, out),
        }
    }

    /// Adds a point to the run, drawing the window when it is full.
    fn point(&mut self, m: Move, seconds: f64, out: &mut impl FnMut(Drawn)) {
        self.run.push((m, seconds));
        if self.run.len() >= WINDOW {
            self.draw(out);
        }
    }

    /// Draws the run held so far, keeping its last point as the start of
    /// what follows.
    fn draw(&mut self, out: &mut impl FnMut(Drawn)) {
        if self.run.len() < 2 {
            return;
        }
        let points: Vec<[f64; 3]> = self.run.iter().map(|(m, _)| m.end.xyz()).collect();
        let kept = douglas_peucker(&points, 0, points.len() - 1, self.lines);
        for w in kept.windows(2) {
            let seconds = self.run[w[0] + 1..=w[1]].iter().map(|(_, s)| s).sum();
            let last = &self.run[w[1]].0;
            let straight = if matches!(last.kind, MoveKind::Arc(_)) { MoveKind::Feed } else { last.kind };
            let mv = Move { kind: straight, start: self.run[w[0]].0.end, ..*last };
            out(Drawn { mv, kind: self.run_kind, seconds });
        }
        let last = self.run.pop().map(|(m, _)| m);
        self.run.clear();
        self.run.extend(last.map(|m| (m, 0.0)));
    }

    /// Draws what is held: the end of the path, or of a run.
    pub fn finish(&mut self, out: &mut impl FnMut(Drawn)) {
        self.draw(out);
        self.run.clear();
    }
}

/// What a page of `moves` moves and `vertices` vertices costs, bytes.
pub(super) fn cost(moves: u64, vertices: u64) -> f64 {
    moves as f64 * MOVE_BYTES + vertices as f64 * VERTEX_BYTES
}

/// A count of drawn moves and vertices, as the page lays them out.
#[derive(Default)]
pub(super) struct Tally {
    pub(super) moves: u64,
    vertices: u64,
    last: Option<[f64; 3]>,
}

impl Tally {
    /// Counts one more move drawn.
    pub(super) fn add(&mut self, d: &Drawn, arc_tol: f64) {
        self.moves += 1;
        let m = &d.mv;
        let points = match m.kind {
            _ if d.kind == UNPLACED || d.kind == 5 => 0,
            MoveKind::Arc(arc) => arc.chords(m.start, m.end, arc_tol) as u64,
            _ => 1,
        };
        if points > 0 {
            self.vertices += points + u64::from(self.last != Some(m.start.xyz()));
            self.last = Some(m.end.xyz());
        }
    }

    /// What the moves counted cost, bytes.
    pub(super) fn cost(&self) -> f64 {
        cost(self.moves, self.vertices)
    }
}
