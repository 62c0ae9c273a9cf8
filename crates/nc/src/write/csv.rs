//! The CSV motion dump (`kezuri run --emit csv`): one row per motion end
//! point, full precision, the same text the golden tests compare; whole,
//! or piece by piece as a run makes the path ([`CsvWriter`]).

use std::fmt::Write;

use kezuri_geom::{Move, MoveKind, Toolpath};

use crate::{Error, ErrorKind, Place, Program};

/// The header of the CSV dump.
pub const CSV_HEADER: &str = "line,kind,x,y,z,a,b,c,feed";

/// The columns a toolpath that moves U V W has after [`CSV_HEADER`]'s.
pub const CSV_UVW: &str = ",u,v,w";

/// Writes `line,kind,x,y,z,a,b,c,feed` rows: `kind` is `rapid`, `feed`,
/// `cw`, `ccw` or `probe`; dwells give no row; numbers are the shortest text
/// that reads back to the same double; `feed` is in mm/min and empty for
/// rapids. A toolpath that moves U V W (LinuxCNC's) has the columns
/// `u,v,w` after `feed`; any other keeps the header as it is.
pub fn csv(toolpath: &Toolpath) -> String {
    let uvw = toolpath.moves.iter().any(|m| moved_uvw(m).is_some());
    let mut out = String::with_capacity(64 * toolpath.moves.len() + 32);
    push_header(&mut out, uvw);
    push_rows(&mut out, &toolpath.moves, uvw);
    out
}

/// The CSV dump written as the toolpath comes, piece by piece (a run's
/// [`PathSink`](kezuri_geom::PathSink) pieces, in order): its columns are
/// chosen before the first move, by the caller ([`may_move_uvw`]). Where
/// the columns are those of [`csv`] of the whole path, the texts joined
/// are its text; a move that moves U V W where the CSV has no columns
/// for them is refused, never dropped.
///
/// ```
/// use kezuri_geom::{Axes, Move, MoveKind, Toolpath};
/// use kezuri_nc::write::{csv, CsvWriter};
/// let at = |x, u| Axes { x, u, ..Axes::ZERO };
/// let path = Toolpath::from(vec![
///     Move { kind: MoveKind::Feed, end: at(1.0, 0.0), feed: 60.0, line: 1, ..Move::default() },
///     Move { kind: MoveKind::Feed, end: at(2.0, 3.0), feed: 60.0, line: 2, ..Move::default() },
/// ]);
/// let mut writer = CsvWriter::new(true);
/// let mut rest = path.clone();
/// let mut text = writer.piece(&rest.split_before(1)).unwrap();
/// text += &writer.piece(&rest).unwrap();
/// text += &writer.finish();
/// assert_eq!(text, csv(&path));
/// // Without the columns, the move of U is refused.
/// let err = CsvWriter::new(false).piece(&path).unwrap_err();
/// assert!(err.to_string().starts_with("move 2 (line 2): the CSV has no u,v,w columns"), "{err}");
/// ```
#[derive(Debug)]
pub struct CsvWriter {
    /// The columns `u,v,w`.
    uvw: bool,
    /// Whether the header is written.
    started: bool,
    /// The moves of the pieces so far: the index of the next piece's first.
    done: usize,
}

impl CsvWriter {
    /// A writer of the CSV dump, with the columns `u,v,w` where `uvw`.
    pub fn new(uvw: bool) -> CsvWriter {
        CsvWriter { uvw, started: false, done: 0 }
    }

    /// The rows of `piece`, the next piece of the toolpath; the first
    /// piece's text begins with the header.
    pub fn piece(&mut self, piece: &Toolpath) -> Result<String, Error> {
        if !self.uvw {
            for (i, m) in piece.moves.iter().enumerate() {
                if let Some(axis) = moved_uvw(m) {
                    let message = format!("the CSV has no u,v,w columns, but the toolpath moves {axis}");
                    let place = Place::Move { index: self.done + i, line: m.line };
                    return Err(Error::new(ErrorKind::RotaryAxis, message).at(place));
                }
            }
        }
        let mut out = String::with_capacity(64 * piece.moves.len() + 32);
        if !self.started {
            push_header(&mut out, self.uvw);
            self.started = true;
        }
        push_rows(&mut out, &piece.moves, self.uvw);
        self.done += piece.moves.len();
        Ok(out)
    }

    /// The rest of the text: the header, where no piece came.
    pub fn finish(self) -> String {
        let mut out = String::new();
        if !self.started {
            push_header(&mut out, self.uvw);
        }
        out
    }
}

/// Whether a run of `program`, read in `dialect`, may move U V W, known
/// before it runs: the CSV's columns `u,v,w` ([`CsvWriter::new`]). Only
/// the LinuxCNC dialect has U V W axes, and only their own words move
/// them (an offset or a reference point moves no axis; a `G28` without
/// axis words moves nothing): where the program, read in it, has a U, V
/// or W word. Such a program whose path never leaves U V W at zero
/// (`G0 U0`; U as a lathe cycle's own word) has the columns, of zeros,
/// where [`csv`] of the whole path has not. A subprogram read from the
/// library during the run is not in `program`: where it moves U V W, the
/// move is refused.
pub fn may_move_uvw(program: &Program, dialect: crate::Dialect) -> bool {
    dialect == crate::Dialect::LinuxCnc && program.words.iter().any(|w| matches!(w.letter, b'U' | b'V' | b'W'))
}

/// The first of U V W move `m` has away from zero, by letter.
fn moved_uvw(m: &Move) -> Option<char> {
    let (s, e) = (m.start.uvw(), m.end.uvw());
    (0..3).find(|&k| s[k] != 0.0 || e[k] != 0.0).map(|k| ['U', 'V', 'W'][k])
}

fn push_header(out: &mut String, uvw: bool) {
    out.push_str(CSV_HEADER);
    if uvw {
        out.push_str(CSV_UVW);
    }
    out.push('\n');
}

fn push_rows(out: &mut String, moves: &[Move], uvw: bool) {
    for m in moves {
        let kind = match m.kind {
            // G28 and G53 moves are rapids too.
            MoveKind::Rapid | MoveKind::Home | MoveKind::Machine => "rapid",
            MoveKind::Feed => "feed",
            MoveKind::Arc(arc) if arc.ccw => "ccw",
            MoveKind::Arc(_) => "cw",
            MoveKind::Probe => "probe",
            MoveKind::Dwell(_) => continue,
        };
        let e = m.end;
        let _ = write!(out, "{},{kind},{},{},{},{},{},{},", m.line, e.x, e.y, e.z, e.a, e.b, e.c);
        if !m.is_rapid() {
            let _ = write!(out, "{}", m.feed);
        }
        if uvw {
            let _ = write!(out, ",{},{},{}", e.u, e.v, e.w);
        }
        out.push('\n');
    }
}
