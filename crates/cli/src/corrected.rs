//! Writing a corrected program (`thermal apply`, `wear apply`): the run's
//! toolpath with new end points, written expanded in any dialect, or the
//! program's own text with only its axis numbers changed (`--keep-text`).

use std::io::Write;

use anyhow::{bail, Result};
use kezuri_geom::{MoveKind, PathSink, Toolpath};

use crate::files::{read_text, Outputs};
use crate::program::{
    comp_refused, read_and_run_into, run_text, stage_toolpath, staged, MissingAxes, Origin, Ran, RunOptions, Streamed,
    WriteArgs,
};

/// The program to correct, read and run: its text and the run, refused
/// with its errors shown, where `check` refuses it, or where it moves an
/// axis the machine lacks.
pub fn run_to_correct(run: &RunOptions, check: impl FnOnce(&Ran) -> Result<()>) -> Result<(String, Ran)> {
    let name = run.file.display().to_string();
    let text = read_text(&run.file)?;
    let (ran, parse_diagnostics) = run_text(run, text.clone())?;
    ran.shown(&parse_diagnostics, &run.file, "nothing written")?;
    crate::program::refuse_comp(&ran, &run.file, "a correction moves")?;
    check(&ran)?;
    if let Some((axis, line)) = crate::program::missing_axes(&ran.outcome.toolpath, &ran.machine.kinematics).first() {
        bail!("{name}: line {line}: the program moves {axis}, which the machine has not");
    }
    Ok((text, ran))
}

/// A correction made piece by piece as the run hands its path on.
pub trait Correction: Send {
    /// `piece`, the next piece of the run's path, corrected; its moves
    /// follow the last piece's.
    fn correct(&mut self, piece: &Toolpath) -> Result<Toolpath, kezuri_correct::Error>;
}

/// Whether the corrected program is written as the run hands its path on:
/// expanded G-code or CSV alone (not `--keep-text`, which rewrites the
/// program's text, and not with a drawing, a page or RML-1).
pub fn streams(write: &WriteArgs, keep_text: bool) -> bool {
    !keep_text && write.streams()
}

/// The program `run` corrected by the correction `make` gives (from the
/// machine) and written, titled with `what`, as the run hands its path on:
/// nothing of the path is held but the piece at hand. It is refused as
/// [`run_to_correct`] refuses it, then where the correction fails, then
/// where `judge` refuses the correction done; nothing is written then.
/// Returns the outputs to commit (the program, the DPRNT file) and the
/// correction after its last piece.
pub fn stream_corrected<C: Correction>(
    run: &RunOptions,
    write: &WriteArgs,
    what: &str,
    make: impl FnOnce(&kezuri_machine::Machine) -> C,
    check: impl FnOnce(&Ran) -> Result<()>,
    judge: impl FnOnce(&C) -> Result<()>,
) -> Result<(Outputs, C)> {
    let name = run.file.display().to_string();
    let mut write = write.clone();
    write.digits = Some(write_digits(&write));
    let title = format!("{} {what}", crate::program::program_title(&run.file));
    let (outputs, made) = staged(write.output(), |to| {
        let (mut ran, parse_diagnostics, sink) = read_and_run_into(run, false, |machine, dialect, program| {
            let uvw = kezuri_nc::write::may_move_uvw(program, dialect);
            Correcting {
                correction: make(machine),
                writer: Streamed::new(&write, machine, &run.file, &title, uvw, to),
                axes: MissingAxes::new(&machine.kinematics),
                error: None,
                compensated: false,
            }
        })?;
        ran.shown(&parse_diagnostics, &run.file, "nothing written")?;
        if sink.compensated {
            return Err(comp_refused(&run.file, "a correction moves"));
        }
        check(&ran)?;
        if let Some((axis, line)) = sink.axes.found.first() {
            bail!("{name}: line {line}: the program moves {axis}, which the machine has not");
        }
        if let Some(e) = sink.error {
            return Err(in_program(&name, e));
        }
        judge(&sink.correction)?;
        sink.writer.finish()?;
        let dprnt = std::mem::take(&mut ran.outputs);
        Ok((sink.correction, dprnt))
    })?;
    let (mut outputs, (correction, dprnt)) = (outputs, made);
    outputs.append(dprnt);
    Ok((outputs, correction))
}

/// The sink of a streamed correction: each piece corrected, then written.
struct Correcting<C, W: Write> {
    correction: C,
    writer: Streamed<W>,
    axes: MissingAxes,
    /// The correction's first error: nothing more is corrected or written.
    error: Option<kezuri_correct::Error>,
    /// Whether the run came with a programmed contour (G41/G42).
    compensated: bool,
}

impl<C: Correction, W: Write> PathSink for Correcting<C, W> {
    fn take(&mut self, piece: &Toolpath, programmed: Option<&Toolpath>) {
        self.compensated |= programmed.is_some();
        self.axes.add(piece);
        if self.error.is_some() {
            return;
        }
        match self.correction.correct(piece) {
            Ok(corrected) => self.writer.take(&corrected, None),
            Err(e) => self.error = Some(e),
        }
    }
}

/// A correction's error in the program `name`: `{name}: line {n}: …` for
/// one about a move.
pub fn in_program(name: &str, e: kezuri_correct::Error) -> anyhow::Error {
    match e.line {
        Some(line) => anyhow::Error::new(e).context(format!("{name}: line {line}")),
        None => e.into(),
    }
}

/// Writes the corrected `path` of the program `text` (run with `run`):
/// expanded, titled with `what`, or with `keep_text` the program's text.
pub fn write_corrected(
    run: &RunOptions,
    write: &WriteArgs,
    keep_text: bool,
    text: &str,
    path: &Toolpath,
    what: &str,
    ran: &mut Ran,
) -> Result<()> {
    let name = run.file.display().to_string();
    // With the run's own outputs (the DPRNT file).
    let mut out = std::mem::take(&mut ran.outputs);
    if keep_text {
        let text = rewritten(&name, text, path, usize::from(write_digits(write)))?;
        out.add(write.output(), text.as_bytes())?;
    } else {
        let mut write = write.clone();
        let title = crate::program::program_title(&run.file);
        write.digits = Some(write_digits(&write));
        stage_toolpath(&mut out, path, &format!("{title} {what}"), &write, &ran.machine, Origin::Transformed, &[])?;
    }
    out.commit()
}

/// The decimals a corrected program is written with: 4 unless given
/// (three cannot hold 0.1 µm).
fn write_digits(w: &WriteArgs) -> u8 {
    w.digits.unwrap_or(4)
}

/// `text` with the axis words of every moving block set to the corrected
/// `path` (see `--keep-text`), or why it cannot be.
fn rewritten(name: &str, text: &str, path: &Toolpath, digits: usize) -> Result<String> {
    use kezuri_nc::rewrite::{set_words, words};
    let lines: Vec<&str> = text.lines().collect();
    for (k, line) in lines.iter().enumerate() {
        let ws = words(line);
        let code = |letter: char, n: f64| {
            ws.iter().any(|w| w.letter == letter && line[w.number.0..w.number.1].parse::<f64>() == Ok(n))
        };
        if [('G', 91.0), ('G', 92.0), ('G', 10.0), ('G', 65.0), ('G', 66.0), ('M', 98.0), ('M', 198.0)]
            .iter()
            .any(|&(l, n)| code(l, n))
        {
            bail!(
                "{name}: line {}: --keep-text rewrites G90 programs without calls, G91, G92 or G10; leave it out to \
                 write the expanded program",
                k + 1
            );
        }
    }
    let mut per_line: std::collections::BTreeMap<u32, usize> = std::collections::BTreeMap::new();
    for (i, m) in path.moves.iter().enumerate() {
        if matches!(m.kind, MoveKind::Home | MoveKind::Dwell(_)) {
            continue;
        }
        if path.frame(m) != kezuri_geom::Frame::default() {
            bail!("{name}: line {}: a work or tool offset is in force; --keep-text writes program coordinates only without them", m.line);
        }
        if per_line.insert(m.line, i).is_some() {
            bail!("{name}: line {}: one block makes several moves; leave --keep-text out", m.line);
        }
    }
    // Macro statements that make no move are left as they are; a moving
    // block whose numbers come from variables cannot be corrected in place.
    let variables =
        |l: u32| lines.get(l as usize - 1).is_some_and(|t| t.split(['(', ';']).next().is_some_and(|t| t.contains('#')));
    if let Some(&line) = per_line.keys().find(|&&l| variables(l)) {
        bail!(
            "{name}: line {line}: this block's move comes from macro variables: it cannot be corrected in place; leave \
             --keep-text out"
        );
    }
    let mut out = String::with_capacity(text.len() + text.len() / 4);
    for (k, line) in lines.iter().enumerate() {
        match per_line.get(&(k as u32 + 1)) {
            Some(&i) => {
                let m = &path.moves[i];
                let mut values = vec![('X', m.end.x), ('Y', m.end.y), ('Z', m.end.z)];
                if let MoveKind::Arc(arc) = m.kind {
                    let present = |c: char| words(line).iter().any(|w| w.letter == c);
                    let start = m.start.xyz();
                    for (k, c) in ['I', 'J', 'K'].into_iter().enumerate() {
                        if present(c) {
                            values.push((c, arc.center[k] - start[k]));
                        }
                    }
                    // R keeps its sign (negative: more than half a turn).
                    if let Some(w) = words(line).iter().find(|w| w.letter == 'R') {
                        let negative = line[w.number.0..w.number.1].trim_start().starts_with('-');
                        let r = arc.radius(m.start);
                        values.push(('R', if negative { -r } else { r }));
                    }
                }
                out += &set_words(line, &values, digits);
            }
            None => out += line,
        }
        out.push('\n');
    }
    Ok(out)
}

/// The corrected pieces of a run joined, or the correction's first error:
/// what the tests of a [`Correction`] compare with the whole path's.
#[cfg(test)]
pub struct Joined<C> {
    pub correction: C,
    pub path: kezuri_geom::WholePath,
    pub error: Option<String>,
    pub pieces: usize,
}

#[cfg(test)]
impl<C> Joined<C> {
    pub fn new(correction: C) -> Joined<C> {
        Joined { correction, path: kezuri_geom::WholePath::default(), error: None, pieces: 0 }
    }
}

#[cfg(test)]
impl<C: Correction> kezuri_geom::PathSink for Joined<C> {
    fn take(&mut self, piece: &Toolpath, _programmed: Option<&Toolpath>) {
        self.pieces += 1;
        if self.error.is_none() {
            match self.correction.correct(piece) {
                Ok(corrected) => self.path.take(&corrected, None),
                Err(e) => self.error = Some(e.to_string()),
            }
        }
    }
}
