//! A toolpath handed on piece by piece as a run makes it, so that a program
//! of any size is never held whole.
//!
//! A run cuts its path only between blocks, never inside a kept block's
//! moves (a tapping cycle), never while cutter radius compensation or a
//! canned cycle is in force. Joined again in order ([`Toolpath::append`])
//! the pieces are the whole path, move for move and block for block: a
//! consumer fed the pieces must say exactly what it says of the whole.

use super::Toolpath;

/// What takes the pieces of a run's toolpath.
pub trait PathSink {
    /// The next piece, in order. `piece.moves` follow the last piece's;
    /// `piece.kept` count `before` from this piece's first move (a block
    /// after the piece's last move comes with the next piece, or with the
    /// last piece at the end); `piece.frames` are every frame made so far,
    /// which `Move::frame` indexes; `piece.unknown_start` is the whole
    /// path's. `programmed`: with cutter radius compensation, the
    /// programmed contour of the same stretch (the tool tip as programmed,
    /// with the G41/G42 and G40 blocks kept for a G-code writer); it comes
    /// only with the last piece, and `None` means the stretch is its own
    /// programmed path.
    fn take(&mut self, piece: &Toolpath, programmed: Option<&Toolpath>);

    /// [`PathSink::take`] of a piece the caller has no more use for: a sink
    /// that keeps or sends its pieces takes it without a copy.
    fn take_owned(&mut self, piece: Toolpath, programmed: Option<&Toolpath>) {
        self.take(&piece, programmed);
    }
}

/// Two sinks fed the same pieces.
impl<A: PathSink, B: PathSink> PathSink for (A, B) {
    fn take(&mut self, piece: &Toolpath, programmed: Option<&Toolpath>) {
        self.0.take(piece, programmed);
        self.1.take(piece, programmed);
    }
}

/// A sink that keeps the whole path: what a caller that needs it all gets.
#[derive(Clone, Debug, Default)]
pub struct WholePath {
    /// The pieces joined.
    pub path: Toolpath,
    /// The programmed contour joined, where a piece came with one (a piece
    /// without one is its own programmed contour).
    pub programmed: Option<Toolpath>,
}

impl PathSink for WholePath {
    fn take(&mut self, piece: &Toolpath, programmed: Option<&Toolpath>) {
        match (&mut self.programmed, programmed) {
            (Some(whole), p) => whole.append(p.unwrap_or(piece)),
            (None, Some(p)) => {
                // The stretches before were their own programmed path.
                let mut whole = Toolpath { frames: Vec::new(), ..self.path.clone() };
                whole.append(p);
                self.programmed = Some(whole);
            }
            (None, None) => {}
        }
        self.path.append(piece);
    }
}

impl Toolpath {
    /// Appends `piece` (the next piece of the same run) to this path: its
    /// moves after these, its kept blocks counted from here, its frames
    /// (every frame so far) in place of these.
    pub fn append(&mut self, piece: &Toolpath) {
        let base = self.moves.len();
        if self.moves.is_empty() && self.kept.is_empty() {
            self.unknown_start = piece.unknown_start;
        }
        self.moves.extend_from_slice(&piece.moves);
        self.kept.extend(piece.kept.iter().map(|k| super::Kept { before: k.before + base, ..k.clone() }));
        if piece.frames.len() >= self.frames.len() {
            self.frames.clone_from(&piece.frames);
        }
    }

    /// This path cut before move `at`: the moves before it and the kept
    /// blocks before them are taken out and returned (with every frame and
    /// the start's knowledge), the rest stays, counted from `at`. `at` must
    /// not fall inside a kept block's moves.
    pub fn split_before(&mut self, at: usize) -> Toolpath {
        let at = at.min(self.moves.len());
        let rest_moves = self.moves.split_off(at);
        let head_moves = std::mem::replace(&mut self.moves, rest_moves);
        let first_after = self.kept.partition_point(|k| k.before < at);
        let rest_kept: Vec<_> = self.kept.split_off(first_after);
        let head_kept = std::mem::replace(
            &mut self.kept,
            rest_kept.into_iter().map(|k| super::Kept { before: k.before - at, ..k }).collect(),
        );
        Toolpath { moves: head_moves, frames: self.frames.clone(), unknown_start: self.unknown_start, kept: head_kept }
    }

    /// The latest place at or before move `at` where the path may be cut:
    /// not inside a kept block's moves (a tapping cycle standing for them).
    pub fn cut_at_or_before(&self, at: usize) -> usize {
        let mut at = at.min(self.moves.len());
        for k in self.kept.iter().rev() {
            if k.before < at && at < k.before + k.moves {
                at = k.before;
            }
        }
        at
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Axes, Kept, Move, MoveKind};

    fn path(n: usize) -> Toolpath {
        let mut p = Toolpath { unknown_start: true, ..Toolpath::default() };
        for i in 0..n {
            let end = Axes { x: i as f64, ..Axes::ZERO };
            p.push(Move { kind: MoveKind::Feed, end, feed: 100.0, line: i as u32 + 1, ..Move::default() });
        }
        for (before, moves) in [(0, 0), (3, 2), (5, 0), (n, 0)] {
            p.kept.push(Kept { before, moves, text: format!("M{before}"), ..Kept::default() });
        }
        p
    }

    #[test]
    fn pieces_joined_are_the_whole() {
        let whole = path(9);
        for cuts in [vec![1, 3, 5, 8], vec![9], vec![0, 2, 7], vec![6]] {
            let mut rest = whole.clone();
            let mut joined = WholePath::default();
            let mut done = 0;
            for &c in &cuts {
                assert_eq!(rest.cut_at_or_before(c - done), c - done);
                let piece = rest.split_before(c - done);
                joined.take(&piece, None);
                done = c;
            }
            joined.take(&rest, None);
            assert_eq!(joined.path.moves, whole.moves, "{cuts:?}");
            assert_eq!(joined.path.kept, whole.kept, "{cuts:?}");
            assert!(joined.path.unknown_start);
        }
    }

    #[test]
    fn a_cut_inside_a_tapping_block_is_moved_before_it() {
        let p = path(9);
        assert_eq!(p.cut_at_or_before(4), 3);
        assert_eq!((p.cut_at_or_before(3), p.cut_at_or_before(5), p.cut_at_or_before(20)), (3, 5, 9));
    }
}
