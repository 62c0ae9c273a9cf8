//! A program written as the run makes it: what `kezuri run` writes (G-code
//! through a post, or CSV) fed the run's path piece by piece, and `check`'s
//! trial of it. Nothing of the path is held but the piece at hand.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, Result};
use kezuri_geom::{PathSink, Toolpath};
use kezuri_machine::Machine;
use kezuri_nc::write::{CsvWriter, ProgramWriter, WriteOptions};

use super::emit::{comp_refusal, Emit, Origin, WriteArgs};
use super::tally::Tally;
use crate::files::Outputs;

/// The output `output` (`None`: standard output) as `fill` writes it while
/// it works (a file through its temporary file, renamed at the commit):
/// the outputs to commit and what `fill` returned, or the first error of
/// `fill` or of the writing, and then nothing is written.
pub fn staged<T>(
    output: Option<&Path>,
    fill: impl FnOnce(&mut (dyn Write + Send)) -> Result<T>,
) -> Result<(Outputs, T)> {
    let mut out = Outputs::new();
    let mut done: Option<Result<T>> = None;
    let staged = out.add_with(output, |to| {
        let result = fill(to);
        let failed = result.is_err();
        done = Some(result);
        if failed {
            return Err(std::io::Error::other("the output was not made"));
        }
        Ok(())
    });
    match (done, staged) {
        (Some(Ok(made)), Ok(())) => Ok((out, made)),
        (Some(Err(e)), _) | (_, Err(e)) => Err(e),
        (None, Ok(())) => Err(anyhow!("the output was not made")),
    }
}

/// What is written.
enum Writer {
    Gcode {
        writer: Box<ProgramWriter>,
        /// The control the output is for, where it has no cutter
        /// compensation (GRBL): a run that used it is refused.
        without_comp: Option<&'static str>,
        /// Write the tool-centre path rather than the programmed contour.
        centre: bool,
    },
    Csv(CsvWriter),
}

/// A program written piece by piece to `out`, and what its summary says.
pub struct Streamed<W: Write> {
    writer: Option<Writer>,
    out: W,
    file: PathBuf,
    /// The first error: nothing more is written after it.
    error: Option<anyhow::Error>,
    /// The written path's moves and tally, for the summary.
    moves: usize,
    tally: Tally,
}

impl<W: Write> Streamed<W> {
    /// The program `kezuri run` writes with `w` of the program `file` on
    /// `machine` to `out`, titled `title`. `uvw`: the CSV has U V W
    /// columns (the program names them).
    pub fn new(w: &WriteArgs, machine: &Machine, file: &Path, title: &str, uvw: bool, out: W) -> Streamed<W> {
        let options = w.options(machine, Origin::Transformed);
        let options = options.map(|o| WriteOptions { title: Some(title.to_string()), ..o });
        Streamed::with_options(w, machine, file, options, uvw, Vec::new(), out)
    }

    /// A program kezuri makes of `file` (a surface) with `w` on `machine`:
    /// the post's start, the tools `tools` loaded in order, its end;
    /// titled `title`, with `notes` in its header.
    pub fn made(
        w: &WriteArgs,
        machine: &Machine,
        file: &Path,
        (title, notes): (&str, &[String]),
        tools: Vec<u32>,
        out: W,
    ) -> Streamed<W> {
        let options = w.options(machine, Origin::Made);
        let options = options.map(|o| WriteOptions { title: Some(title.to_string()), notes: notes.to_vec(), ..o });
        Streamed::with_options(w, machine, file, options, false, tools, out)
    }

    fn with_options(
        w: &WriteArgs,
        machine: &Machine,
        file: &Path,
        options: Result<WriteOptions>,
        uvw: bool,
        tools: Vec<u32>,
        out: W,
    ) -> Streamed<W> {
        let tally = Tally::new(&machine.dynamics, &machine.kinematics, false);
        let mut streamed = Streamed { writer: None, out, file: file.to_path_buf(), error: None, moves: 0, tally };
        let writer = match w.emit {
            Some(Emit::Csv) => Ok(Writer::Csv(CsvWriter::new(uvw))),
            Some(Emit::Rml) => Err(anyhow!("RML-1 is written from the whole path")),
            _ => options.and_then(|options| {
                let without_comp = (options.dialect == kezuri_nc::write::Dialect::Grbl).then_some("GRBL");
                Ok(Writer::Gcode {
                    writer: Box::new(ProgramWriter::new(&options)?.with_tool_order(tools)),
                    without_comp,
                    centre: w.apply_comp,
                })
            }),
        };
        match writer {
            Ok(writer) => streamed.writer = Some(writer),
            Err(e) => streamed.error = Some(e),
        }
        streamed
    }

    /// The output, or the first error writing it met.
    pub fn finish(mut self) -> Result<(W, String)> {
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        let end = match self.writer.take() {
            Some(Writer::Gcode { writer, .. }) => writer.finish().map_err(anyhow::Error::from)?,
            Some(Writer::Csv(writer)) => writer.finish(),
            None => String::new(),
        };
        self.out.write_all(end.as_bytes())?;
        let summary = self.tally.summary(self.moves);
        Ok((self.out, summary))
    }

    fn write(&mut self, piece: &Toolpath, programmed: Option<&Toolpath>) -> Result<()> {
        let (text, written) = match self.writer.as_mut() {
            None => return Ok(()),
            Some(Writer::Csv(writer)) => (writer.piece(piece)?, piece),
            Some(Writer::Gcode { writer, without_comp, centre }) => {
                if let (Some(_), Some(control), false) = (programmed, *without_comp, *centre) {
                    return Err(comp_refusal(&self.file, control));
                }
                let programmed = programmed.filter(|_| !*centre);
                (writer.piece(piece, programmed)?, programmed.unwrap_or(piece))
            }
        };
        self.moves += written.moves.len();
        self.tally.take(written, None);
        self.out.write_all(text.as_bytes())?;
        Ok(())
    }
}

impl<W: Write> PathSink for Streamed<W> {
    fn take(&mut self, piece: &Toolpath, programmed: Option<&Toolpath>) {
        if self.error.is_none() {
            if let Err(e) = self.write(piece, programmed) {
                self.error = Some(e);
            }
        }
    }
}
