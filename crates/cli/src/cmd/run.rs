//! `kezuri run`: a program's motions written again, as a program, CSV or RML-1.

use anyhow::{anyhow, Result};

use std::sync::Arc;

use kezuri_nc::source::TextStore;

use crate::files::read_program_text;
use crate::program::{
    located, model_notes, program_title, run_store, run_text_into, staged, write_program, written_path, Origin,
    RunOptions, Streamed, WriteArgs,
};

/// `kezuri run`: the motions of the program, as a program again or as CSV.
///
/// With cutter radius compensation, Fanuc and LinuxCNC output is the
/// programmed contour with its G41/G42 D and G40 blocks; CSV, the SVG and
/// `--apply-comp` output the tool-centre path; GRBL and RML-1, which have
/// no compensation, need `--apply-comp`.
pub fn run(o: &RunOptions, w: &WriteArgs) -> Result<()> {
    // A program or CSV alone is written as the run makes it; a drawing, a
    // page or RML-1 needs the whole path. The text is read once (standard
    // input cannot be read twice) for both.
    let text = read_program_text(&o.file)?;
    if w.streams() {
        if let Some(done) = run_streamed(o, w, Arc::clone(&text)) {
            return done;
        }
    }
    let (mut ran, parse_diagnostics) = run_store(o, text, w.apply_comp)?;
    ran.shown(&parse_diagnostics, &o.file, "nothing written")?;
    let w = &w.for_program(&ran.machine, ran.dialect.dialect);
    let mut out = std::mem::take(&mut ran.outputs);
    let title = program_title(&o.file);
    let centre = &ran.outcome.toolpath;
    let written = written_path(&ran, w, &o.file)?;
    let notes = model_notes(&ran.outcome);
    for note in &notes {
        eprintln!("warning: {}: {note}", o.file.display());
    }
    write_program(&mut out, written, centre, &title, &notes, w, &ran.machine, Origin::Transformed, &[])
        .map_err(|e| located(&ran, e))?;
    out.commit()?;
    crate::say::wrote_program(w.output(), "", written, &ran.machine);
    Ok(())
}

/// [`run`] writing the program (or CSV) as the run hands its path on, so
/// that a program of any length is never held. `None` where it must be
/// written from the whole path after all: the run read values from the
/// machine file, which the written program's header notes.
fn run_streamed(o: &RunOptions, w: &WriteArgs, text: Arc<dyn TextStore>) -> Option<Result<()>> {
    let mut whole = false;
    let done = staged(w.output(), |to| {
        let title = program_title(&o.file);
        let (mut ran, parse_diagnostics, written) =
            run_text_into(o, text, w.apply_comp, |machine, dialect, program| {
                let w = w.for_program(machine, dialect);
                let uvw = kezuri_nc::write::may_move_uvw(program, dialect);
                Streamed::new(&w, machine, &o.file, &title, uvw, &mut *to)
            })?;
        // Before anything is said: the whole path's run says it all.
        if !model_notes(&ran.outcome).is_empty() {
            whole = true;
            return Err(anyhow!("written from the whole path"));
        }
        ran.shown(&parse_diagnostics, &o.file, "nothing written")?;
        let (_, summary) = written.finish().map_err(|e| located(&ran, e))?;
        Ok((std::mem::take(&mut ran.outputs), summary))
    });
    if whole {
        return None;
    }
    Some(done.and_then(|(mut out, (dprnt, summary))| {
        out.append(dprnt);
        out.commit().map(|()| crate::say::note!("wrote {}: {summary}", crate::say::shown(w.output())))
    }))
}
