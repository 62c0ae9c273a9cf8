//! `kezuri run`: a program's motions written again, as a program, CSV or RML-1.

use anyhow::{bail, Result};

use crate::program::{
    model_notes, read_and_run, read_and_run_centre, write_program, Emit, Origin, RunOptions, WriteArgs,
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
    let title = o.file.file_name().map_or_else(|| "-".into(), |n| n.to_string_lossy().to_uppercase());
    let centre = &ran.outcome.toolpath;
    // Which of the programmed contour and the tool-centre path is written.
    let without_comp = match w.emit {
        Some(Emit::Csv) => None,
        Some(Emit::Rml) => Some("RML-1"),
        _ => {
            (w.options(&ran.machine, Origin::Transformed)?.dialect == kezuri_nc::write::Dialect::Grbl).then_some("GRBL")
        }
    };
    let written = match (&ran.outcome.programmed, without_comp) {
        (Some(_), Some(control)) if !w.apply_comp => bail!(
            "{}: the program uses cutter radius compensation (G41/G42), which {control} has not: give --apply-comp to \
             write the tool centre path (radii from the machine file's [tools] radii)",
            o.file.display(),
        ),
        (Some(p), None) if !w.apply_comp && w.is_gcode() => p,
        _ => centre,
    };
    let notes = model_notes(&ran.outcome);
    for note in &notes {
        eprintln!("warning: {}: {note}", o.file.display());
    }
    let mut out = std::mem::take(&mut ran.outputs);
    write_program(&mut out, written, centre, &title, &notes, w, &ran.machine, Origin::Transformed, &[])?;
    out.commit()?;
    crate::say::wrote_program(w.output(), "", written, &ran.machine);
    Ok(())
}
