//! `kezuri convert` of G-code into G-code as the run makes its path: each
//! piece filled (`--feed`, `--speed`), scaled and written as it comes, so
//! that a program of any size is never held. What the whole path's
//! conversion checks first (motion at all, the spindle's speed, blocks
//! that scaling cannot reach) is gathered on the way and judged at the
//! end, before anything is written: the output is staged.

use std::io::Write;
use std::sync::Arc;

use anyhow::{anyhow, bail, Result};
use kezuri_geom::{Kept, Move, MoveKind, PathSink, Spindle, Toolpath};
use kezuri_nc::source::TextStore;
use kezuri_nc::write::ProgramWriter;
use kezuri_nc::Dialect;

use super::{
    fill_feed_and_speed, format_name, holds_positions, unscalable, warn_cutters, warn_no_speed, write_options,
    ConvertArgs, Format,
};
use crate::program::{run_options, run_text_into, staged, DialectArg, Tally};

/// Converts the G-code program `a.input` (`name`), read in `dialect`, into
/// the G-code `to`. `None` where it must be converted from the whole path
/// after all: the machine file's lathe reads it in another dialect than
/// `convert` does.
pub fn convert(
    a: &ConvertArgs,
    name: &str,
    dialect: Dialect,
    to: Format,
    text: Arc<dyn TextStore>,
) -> Option<Result<()>> {
    let mut whole = false;
    let done = staged(a.output.as_deref(), |out| {
        let mut o = run_options(&a.input)?;
        o.lib.clone_from(&a.lib);
        o.machine.clone_from(&a.machine.machine);
        o.dialect = Some(DialectArg::from(dialect));
        let (ran, parse_diagnostics, sink) = run_text_into(&o, text, false, |machine, read_in, _| {
            let writer = if read_in == dialect {
                write_options(a, to, machine).and_then(|o| Ok(ProgramWriter::new(&o)?))
            } else {
                Err(anyhow!("read as {read_in}"))
            };
            let scale = (a.scale_xy != 1.0 || a.scale_z != 1.0).then_some((a.scale_xy, a.scale_z));
            Converting::new(scale, a.feed, a.speed, writer, machine, out)
        })?;
        // A lathe's machine file reads the program as a lathe's: `convert`
        // reads it as it says.
        if ran.dialect.dialect != dialect {
            whole = true;
            bail!("converted from the whole path");
        }
        let sources = &ran.sources;
        let print = |d: &kezuri_nc::Diagnostic| eprintln!("{}\n", d.render(sources));
        parse_diagnostics.iter().for_each(print);
        if ran.parse_errors > 0 {
            bail!("{name}: parse errors; nothing written");
        }
        ran.outcome.diagnostics.iter().for_each(print);
        let errors = ran.outcome.diagnostics.iter().filter(|d| d.is_error()).count();
        if errors > 0 {
            bail!("{name}: {}; nothing written", crate::say::count(errors as u64, "error"));
        }
        sink.finish(a, name, ran.sources.get(0).text.clone())
    });
    if whole {
        return None;
    }
    Some(done.and_then(|(out, summary)| {
        out.commit()?;
        crate::say::note!("wrote {}: {}; {summary}", crate::say::shown(a.output.as_deref()), format_name(to));
        Ok(())
    }))
}

/// The sink of a streamed conversion.
struct Converting<W: Write> {
    /// `--scale-xy`, `--scale-z`, where either is not 1.
    scale: Option<(f64, f64)>,
    feed: Option<f64>,
    speed: Option<f64>,
    /// The writer, or why there is none (the post's options).
    writer: Result<ProgramWriter>,
    out: W,
    /// The written path's tally, for the summary.
    tally: Tally,
    moves: usize,
    /// Whether a move other than a dwell came.
    motion: bool,
    /// Whether the spindle turned with no speed (after `--speed`).
    no_speed: bool,
    /// The first block kept that scaling cannot reach.
    unscalable: Option<Kept>,
    /// The last move of the pieces so far, as the run made it.
    last: Option<Move>,
    /// The first error of the writing: nothing more is written.
    error: Option<anyhow::Error>,
}

impl<W: Write> Converting<W> {
    /// The conversion `scale`d (`--scale-xy`, `--scale-z`) with `feed`
    /// and `speed` where the program has none, by `writer` into `out`,
    /// summed up on `machine`.
    fn new(
        scale: Option<(f64, f64)>,
        feed: Option<f64>,
        speed: Option<f64>,
        writer: Result<ProgramWriter>,
        machine: &kezuri_machine::Machine,
        out: W,
    ) -> Converting<W> {
        Converting {
            scale,
            feed,
            speed,
            writer,
            out,
            tally: Tally::new(&machine.dynamics, &machine.kinematics, false),
            moves: 0,
            motion: false,
            no_speed: false,
            unscalable: None,
            last: None,
            error: None,
        }
    }

    fn write(&mut self, piece: &Toolpath) -> Result<()> {
        // Without a writer nothing is written: why is said at the end.
        let Ok(writer) = self.writer.as_mut() else { return Ok(()) };
        let text = writer.piece(piece, None)?;
        self.out.write_all(text.as_bytes())?;
        self.moves += piece.moves.len();
        self.tally.take(piece, None);
        Ok(())
    }

    /// After the run: what the whole path's conversion would refuse, in
    /// its order, else the end of the program written and its summary.
    fn finish(mut self, a: &ConvertArgs, name: &str, text: kezuri_nc::source::Text) -> Result<String> {
        if !self.motion {
            bail!("{name}: the program has no motion to convert; nothing written");
        }
        if self.no_speed {
            warn_no_speed(name);
        }
        if self.scale.is_some() {
            warn_cutters(a, Some(&text));
            if let Some(k) = &self.unscalable {
                return Err(unscalable(name, k));
            }
        }
        let writer = self.writer?;
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        let end = writer.finish()?;
        self.out.write_all(end.as_bytes())?;
        Ok(self.tally.summary(self.moves))
    }
}

impl<W: Write> PathSink for Converting<W> {
    fn take(&mut self, piece: &Toolpath, _programmed: Option<&Toolpath>) {
        let mut path = piece.clone();
        fill_feed_and_speed(&mut path, self.feed, self.speed);
        self.motion |= path.moves.iter().any(|m| !matches!(m.kind, MoveKind::Dwell(_)));
        self.no_speed |= path.moves.iter().any(|m| m.spindle != Spindle::Off && m.speed == 0.0);
        if let Some((k, s)) = self.scale {
            if self.unscalable.is_none() {
                self.unscalable = path.kept.iter().find(|k| holds_positions(k)).cloned();
            }
            let before = self.last;
            self.last = path.moves.last().copied().or(before);
            path = path.scaled_after(k, s, before.as_ref());
        }
        if self.unscalable.is_some() || self.error.is_some() {
            return;
        }
        if let Err(e) = self.write(&path) {
            self.error = Some(e);
        }
    }
}

#[cfg(test)]
mod tests {
    use kezuri_machine::Machine;
    use kezuri_nc::write::{program, WriteOptions};

    use super::*;
    use crate::program::corpus::each_case;

    #[test]
    fn every_program_converted_in_pieces_is_converted_whole() {
        // Every program of the repository, run whole and converted as
        // `convert` converts the whole path, and run again handing its path
        // on in pieces of one move to the streamed conversion: the same
        // text to the byte, the same summary, the same refusals.
        let machine = Machine::default();
        let ways: [Way; 3] = [
            (None, None, None, "fanuc"),
            (Some((2.0, 0.5)), Some(300.0), None, "linuxcnc"),
            (None, None, Some(900.0), "haas"),
        ];
        let (mut compared, mut cut, mut refused) = (0, 0, 0);
        each_case(&machine, |mut case| {
            for (scale, feed, speed, post) in ways {
                let options =
                    WriteOptions { title: Some("T".into()), setup: None, ..WriteOptions::preset(post).unwrap() };
                let mut path = case.whole.toolpath.clone();
                fill_feed_and_speed(&mut path, feed, speed);
                let kept = path.kept.iter().find(|k| holds_positions(k)).map(|k| k.line);
                let expected = match (scale, kept) {
                    (Some(_), Some(_)) => None,
                    (Some((k, s)), None) => Some(path.scaled(k, s)),
                    (None, _) => Some(path.clone()),
                }
                .map(|p| (program(&p, &options).map_err(|e| e.to_string()), crate::say::program_summary(&p, &machine)));
                let writer = ProgramWriter::new(&options).map_err(anyhow::Error::from);
                let mut streamed = Converting::new(scale, feed, speed, writer, &machine, Vec::new());
                let mut pieces = Counting { sink: &mut streamed, pieces: 0 };
                case.run_into(&mut pieces);
                cut += usize::from(pieces.pieces > 2);
                let name = &case.name;
                assert_eq!(streamed.motion, path.moves.iter().any(|m| !matches!(m.kind, MoveKind::Dwell(_))), "{name}");
                assert_eq!(streamed.no_speed, path.moves.iter().any(|m| m.spindle != Spindle::Off && m.speed == 0.0));
                assert_eq!(streamed.unscalable.as_ref().map(|k| k.line), kept.filter(|_| scale.is_some()), "{name}");
                let Some((text, summary)) = expected else {
                    refused += 1;
                    continue;
                };
                let moves = streamed.moves;
                let written = match (streamed.error, streamed.writer) {
                    (Some(e), _) => Err(e.to_string()),
                    (None, Ok(w)) => {
                        w.finish().map(|end| String::from_utf8(streamed.out).unwrap() + &end).map_err(|e| e.to_string())
                    }
                    (None, Err(e)) => Err(e.to_string()),
                };
                assert_eq!(written, text, "{name} {post}");
                if text.is_ok() {
                    assert_eq!(streamed.tally.summary(moves), summary, "{name} {post}");
                }
                compared += 1;
            }
        });
        // Pinned, so that the test cannot pass by comparing nothing.
        assert!(compared >= 500 && cut >= 300 && refused >= 3, "{compared} compared, {cut} cut, {refused} refused");
    }

    /// A conversion: the scale, `--feed`, `--speed` and the post.
    type Way = (Option<(f64, f64)>, Option<f64>, Option<f64>, &'static str);

    /// A sink that counts the pieces it hands on.
    struct Counting<'a, S> {
        sink: &'a mut S,
        pieces: usize,
    }

    impl<S: PathSink> PathSink for Counting<'_, S> {
        fn take(&mut self, piece: &Toolpath, programmed: Option<&Toolpath>) {
            self.sink.take(piece, programmed);
            self.pieces += 1;
        }
    }
}
