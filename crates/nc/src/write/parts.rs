//! A program in parts, for a control with little memory: each part a whole
//! program of at most so many bytes, which starts from the safe height.

use kezuri_geom::{Axes, AxisSet, Move, MoveKind, Toolpath};

use super::gcode::program;
use super::options::WriteOptions;
use crate::error::{Error, ErrorKind};

/// `toolpath` written with `options` as programs of at most `limit` bytes:
/// one program where the whole fits, else parts. Part `k` of `n` (from 1)
/// is numbered `k − 1` after `options.program_number`, titled
/// `… PART k/n`, and those after the first begin with the tool in the
/// spindle (the tool of the part before). Each part after the first starts
/// at `safe_z`, over its first point, and plunges to it at `plunge_feed`;
/// each ends at `safe_z`.
pub fn parts(
    toolpath: &Toolpath,
    options: &WriteOptions,
    limit: usize,
    safe_z: f64,
    plunge_feed: f64,
) -> Result<Vec<String>, Error> {
    let whole = program(toolpath, options)?;
    if whole.len() <= limit {
        return Ok(vec![whole]);
    }
    let fail = |message: String| Err(Error::new(ErrorKind::Limit, message));
    let overhead = program(&Toolpath::from(toolpath.moves[..1].to_vec()), options)?.len() + 200;
    if limit <= overhead + 200 {
        return fail(format!("--split-bytes {limit} is too small: a part's frame alone takes about {overhead} bytes"));
    }
    let per_move = whole.len() as f64 / toolpath.moves.len() as f64;
    let mut factor = 0.95;
    for _ in 0..20 {
        let chunk = (((limit - overhead) as f64 / per_move * factor) as usize).max(1);
        let pieces: Vec<&[Move]> = toolpath.moves.chunks(chunk).collect();
        let n = pieces.len();
        let mut texts = Vec::with_capacity(n);
        for (k, piece) in pieces.iter().enumerate() {
            let mut moves = Vec::with_capacity(piece.len() + 4);
            let first = piece[0];
            if k > 0 {
                let start = first.start;
                let up = Axes { z: safe_z, ..start };
                let base = Move { kind: MoveKind::Rapid, feed: 0.0, ..first };
                moves.push(Move { start: up, end: up, named: AxisSet(0b100), ..base });
                moves.push(Move { start: up, end: up, named: AxisSet(0b011), ..base });
                if start.z < safe_z {
                    moves.push(Move { kind: MoveKind::Feed, start: up, end: start, feed: plunge_feed, ..first });
                }
            }
            moves.extend_from_slice(piece);
            let last = *moves.last().expect("a part has moves");
            if last.end.z < safe_z {
                let up = Axes { z: safe_z, ..last.end };
                moves.push(Move { kind: MoveKind::Rapid, start: last.end, end: up, feed: 0.0, ..last });
            }
            let part = WriteOptions {
                program_number: options.program_number + k as u32,
                loaded_tool: if k > 0 { pieces[k - 1].last().map(|m| m.tool) } else { options.loaded_tool },
                title: options
                    .title
                    .as_ref()
                    .map(|t| if n > 1 { format!("{t} PART {}/{n}", k + 1) } else { t.clone() }),
                ..options.clone()
            };
            let text = program(&Toolpath::from(moves), &part)?;
            if text.len() > limit {
                texts.clear();
                break;
            }
            texts.push(text);
        }
        if texts.len() == n {
            return Ok(texts);
        }
        factor *= 0.85;
    }
    fail(format!("cannot split the program into parts of {limit} bytes"))
}
