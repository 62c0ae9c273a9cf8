//! `kezuri run`: a program's motions written again, as a program, CSV or RML-1.

use anyhow::Result;

use crate::program::{
    located, model_notes, read_and_run, read_and_run_centre, write_program, written_path, Origin, RunOptions, WriteArgs,
};

/// `kezuri run`: the motions of the program, as a program again or as CSV.
///
/// With cutter radius compensation, Fanuc and LinuxCNC output is the
/// programmed contour with its G41/G42 D and G40 blocks; CSV, the SVG and
/// `--apply-comp` output the tool-centre path; GRBL and RML-1, which have
/// no compensation, need `--apply-comp`.
pub fn run(o: &RunOptions, w: &WriteArgs) -> Result<()> {
    let (mut ran, parse_diagnostics) = if w.apply_comp { read_and_run_centre(o)? } else { read_and_run(o)? };
    ran.shown(&parse_diagnostics, &o.file, "nothing written")?;
    let w = &w.for_program(&ran.machine, ran.dialect.dialect);
    let mut out = std::mem::take(&mut ran.outputs);
    let title = o.file.file_name().map_or_else(|| "-".into(), |n| n.to_string_lossy().to_uppercase());
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
