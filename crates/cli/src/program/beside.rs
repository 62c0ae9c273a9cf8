//! The run's path taken on the other core: the interpreter hands each piece
//! over a short queue to a thread where the sink (the report, the writer)
//! takes it, so that running the program and using its path go on at once.

use std::sync::mpsc::{sync_channel, Receiver, SyncSender};

use kezuri_geom::{Frame, PathSink, Toolpath};

/// Pieces waiting for the sink's thread at most (each some 4,096 moves).
const WAITING: usize = 2;

/// A piece as it crosses: its moves and kept blocks, the frames made since
/// the last piece, and the programmed contour with the last piece.
struct Crossing {
    piece: Toolpath,
    programmed: Option<Toolpath>,
}

/// What the interpreter hands its pieces to: the queue to the sink's
/// thread.
struct Handing {
    queue: SyncSender<Crossing>,
    /// Frames sent so far (a piece carries every frame; only the new ones
    /// cross).
    frames: usize,
}

impl PathSink for Handing {
    fn take(&mut self, piece: &Toolpath, programmed: Option<&Toolpath>) {
        let frames = piece.frames.get(self.frames..).unwrap_or_default().to_vec();
        let crossing = Toolpath { moves: piece.moves.clone(), frames, kept: piece.kept.clone(), ..*piece };
        self.send(crossing, piece.frames.len(), programmed);
    }

    fn take_owned(&mut self, mut piece: Toolpath, programmed: Option<&Toolpath>) {
        let made = piece.frames.len();
        piece.frames = piece.frames.split_off(self.frames.min(made));
        self.send(piece, made, programmed);
    }
}

impl Handing {
    /// Sends `piece`, which holds the frames made since the last piece
    /// (`made` in all).
    fn send(&mut self, piece: Toolpath, made: usize, programmed: Option<&Toolpath>) {
        self.frames = self.frames.max(made);
        // A sink's thread that stopped has said why (its panic is raised
        // where it is joined); nothing more to hand it.
        let _ = self.queue.send(Crossing { piece, programmed: programmed.cloned() });
    }
}

/// Takes the pieces off the queue and gives them, whole frames and all, to
/// `sink`; returns it when the queue closes.
fn take_all<S: PathSink>(queue: Receiver<Crossing>, mut sink: S) -> S {
    let mut frames: Vec<Frame> = Vec::new();
    for Crossing { mut piece, programmed } in queue {
        frames.append(&mut piece.frames);
        piece.frames = std::mem::take(&mut frames);
        sink.take(&piece, programmed.as_ref());
        frames = std::mem::take(&mut piece.frames);
    }
    sink
}

/// Runs `run` handing its pieces to `sink` on a thread of its own, and
/// returns what `run` returned and the sink.
pub fn with_sink_beside<S: PathSink + Send, T>(sink: S, run: impl FnOnce(&mut dyn PathSink) -> T) -> (T, S) {
    std::thread::scope(|scope| {
        let (queue, taken) = sync_channel(WAITING);
        let taker = scope.spawn(move || take_all(taken, sink));
        let mut handing = Handing { queue, frames: 0 };
        let result = run(&mut handing);
        drop(handing);
        let sink = match taker.join() {
            Ok(sink) => sink,
            Err(panic) => std::panic::resume_unwind(panic),
        };
        (result, sink)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use kezuri_geom::{Axes, Kept, LengthOffset, Move, MoveKind, WholePath};

    #[test]
    fn the_pieces_arrive_whole_with_their_frames() {
        let mut whole = Toolpath { unknown_start: true, ..Toolpath::default() };
        for i in 0..20u32 {
            if i % 6 == 0 {
                let length = LengthOffset { register: i, ..LengthOffset::default() };
                whole.frames.push(Frame { length: Some(length), ..Frame::default() });
            }
            let end = Axes { x: f64::from(i), ..Axes::ZERO };
            let frame = whole.frames.len() as u32 - 1;
            whole.push(Move { kind: MoveKind::Feed, end, feed: 100.0, frame, ..Move::default() });
        }
        whole.kept.push(Kept { before: 7, text: "M08".into(), ..Kept::default() });
        let ((), joined) = with_sink_beside(WholePath::default(), |sink| {
            let mut rest = whole.clone();
            // Frames as the run has them when it hands each piece on.
            // Handed by reference and handed over, as the run hands them.
            for (k, at) in [5, 6, 9].into_iter().enumerate() {
                let mut piece = rest.split_before(at);
                let made = piece.moves.last().map_or(0, |m| m.frame as usize + 1);
                piece.frames.truncate(made);
                if k == 1 {
                    sink.take(&piece, None);
                } else {
                    sink.take_owned(piece, None);
                }
            }
            sink.take(&rest, None);
        });
        assert_eq!(joined.path, whole);
    }
}
