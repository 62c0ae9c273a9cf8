//! `kezuri check`: a program read and run, and what it does reported.

use anyhow::{bail, Result};
use kezuri_nc::interp::{Control, Thread};
use kezuri_nc::{Diagnostic, Dialect};
use serde_json::json;

use crate::files::write_output;
use crate::program::{model_notes, read_and_run_into, whole_units, RunOptions, RunTrial, Tallied, Tally};
use crate::say;
use kezuri_machine::{Machine, ToolEntry};

mod batch;
pub use batch::run as run_many;

/// Whether `check` looks for Z moves without a length offset: on a Fanuc
/// or Haas control (length offsets are how their tools are set), unless
/// the machine file's `[post]` says otherwise (its `length_offset`, or its
/// preset's: GRBL has none). Never on a lathe, whose T word holds the
/// offset.
fn uses_length_offsets(dialect: Dialect, machine: &Machine) -> bool {
    // A lathe's T word carries its own offset (T0101): there is no G43.
    if dialect.is_lathe() || machine.settings.lathe.is_some() {
        return false;
    }
    machine
        .post
        .length_offset()
        .unwrap_or(!whole_units(dialect) && machine.settings.coords.control != Control::LinuxCnc)
}

/// How a report names tool `t`: `T5 ball:6 H5 D25 (name)`, `T5 (not in
/// the tool table)`, or `no tool (T0)`. On a Fanuc or Haas lathe (`lathe`,
/// the offset numbers its T words selected the tool with), which has no H
/// or D register, what the T word selected and the nose: `T0101 (tool 1,
/// offset 1) nose 0.8 mm tip 3 (name)`.
fn tool_line(t: u32, entry: &Option<ToolEntry>, lathe: Option<&[u32]>) -> String {
    let mut s = match lathe {
        _ if t == 0 => return "no tool (T0)".to_string(),
        Some(offsets) => lathe_selection(t, offsets),
        None => format!("T{t}"),
    };
    let Some(e) = entry else { return s + " (not in the tool table)" };
    if let Some(c) = e.shape {
        s += &format!(" {c}");
    }
    if lathe.is_none() {
        s += &format!(" H{}", e.h);
        if let Some(d) = e.d {
            s += &format!(" D{d}");
        }
    }
    if let Some(n) = e.nose {
        s += &format!(" nose {} mm tip {}", n.radius, n.tip);
    }
    if let Some(n) = &e.name {
        s += &format!(" ({n})");
    }
    s
}

/// What a lathe's T words selected tool `t` with: `T0101 (tool 1, offset
/// 1)`, `T0100 (tool 1, no offset)`, `T0101, T0111 (tool 1, offsets 1, 11)`,
/// or `tool 1` where no T word named it.
fn lathe_selection(t: u32, offsets: &[u32]) -> String {
    let words: Vec<String> = offsets.iter().map(|o| format!("T{t:02}{o:02}")).collect();
    let what = match offsets {
        [] => return format!("tool {t}"),
        [0] => "no offset".to_string(),
        [o] => format!("offset {o}"),
        _ => format!("offsets {}", offsets.iter().map(u32::to_string).collect::<Vec<_>>().join(", ")),
    };
    format!("{} (tool {t}, {what})", words.join(", "))
}

/// The threads as the text report says them: one line for each run of
/// passes with the same lead and block (a cycle's passes, whose starts may
/// step along the flank as G76's do), the Z of the last pass (the thread's
/// length), their X (a radius) from the first pass's to the last's.
fn thread_lines(threads: &[Thread]) -> Vec<String> {
    let same = |a: &Thread, b: &Thread| a.lead == b.lead && a.line == b.line;
    let mut out = Vec::new();
    let mut k = 0;
    while k < threads.len() {
        let first = &threads[k];
        let n = threads[k..].iter().take_while(|t| same(first, t)).count();
        let last = &threads[k + n - 1];
        let passes = if n == 1 { "1 pass".to_string() } else { format!("{n} passes") };
        let x = if n == 1 || first.start.x == last.start.x {
            format!("X {:.3}", first.start.x)
        } else {
            format!("X {:.3} → {:.3}", first.start.x, last.start.x)
        };
        out.push(format!(
            "thread lead {:.4} mm, Z {:.3} → {:.3}, {passes}, {x} (radius; line {})",
            first.lead, last.start.z, last.end.z, first.line
        ));
        k += n;
    }
    out
}

/// Runs `kezuri check` on one program.
pub fn run(o: &RunOptions, as_json: bool) -> Result<()> {
    let checked = check(o, as_json)?;
    eprint!("{}", checked.notes);
    write_output(None, checked.said().as_bytes())?;
    match checked.failure {
        Some(failure) => bail!(failure),
        None => Ok(()),
    }
}

/// What checking one program says: its report (standard output), the
/// diagnostics and warnings (standard error), and why it fails, if it does.
struct Checked {
    report: Said,
    notes: String,
    failure: Option<String>,
}

/// A check's report: text, or the JSON object of `--json`.
enum Said {
    Text(String),
    Json(serde_json::Value),
}

impl Checked {
    /// The report as standard output has it (JSON on one line).
    fn said(&self) -> String {
        match &self.report {
            Said::Text(text) => text.clone(),
            Said::Json(value) => value.to_string() + "\n",
        }
    }
}

/// Checks one program; an error only where it cannot be read or run at all.
fn check(o: &RunOptions, as_json: bool) -> Result<Checked> {
    let mut notes = String::new();
    // The run hands its path, piece by piece, to the tally and to a trial
    // of what `kezuri run` writes: a program of any length is never held.
    let (mut ran, parse_diagnostics, (tally, trial)) = read_and_run_into(o, false, |machine, dialect, _| {
        let tally = Tally::new(&machine.dynamics, &machine.kinematics, uses_length_offsets(dialect, machine));
        (tally, RunTrial::new(machine, dialect, &o.file))
    })?;
    std::mem::take(&mut ran.outputs).commit()?;
    // What `kezuri run` refuses of a program that ran is an error here too.
    let refusal = if ran.errors() == 0 { trial.refusal(&ran) } else { None };
    let errors = ran.errors() + usize::from(refusal.is_some());
    let Tallied { report, missing_axes, unoffset_z } = tally.finish(&ran.outcome, &ran.machine.tools);
    let all: Vec<&Diagnostic> = parse_diagnostics.iter().chain(&ran.outcome.diagnostics).collect();
    // Axes the program commands that the machine file's chains lack.
    let missing = match &o.machine {
        Some(file) => missing_axes
            .into_iter()
            .map(|(axis, line)| {
                format!("{}: the machine has no {axis} axis, and the program commands it (line {line})", file.display())
            })
            .collect(),
        None => Vec::new(),
    };
    let file = o.file.display();
    let missing: Vec<String> =
        missing.into_iter().chain(unoffset_z.into_iter().map(|w| format!("{file}: {w}"))).collect();
    let said = if as_json {
        // An axis no position of the program gives: null.
        let lo: Vec<Option<f64>> = report.bounds.iter().map(|r| r.map(|r| r.0)).collect();
        let hi: Vec<Option<f64>> = report.bounds.iter().map(|r| r.map(|r| r.1)).collect();
        let headlines = |errors: bool| -> Vec<String> {
            all.iter().filter(|d| d.is_error() == errors).map(|d| d.headline(&ran.sources)).collect()
        };
        let value = json!({
            "file": o.file.display().to_string(),
            "dialect": ran.dialect.dialect.name(),
            "dialect_reason": ran.dialect.reason,
            "completed": ran.outcome.completed && errors == 0,
            "blocks": report.blocks,
            "statements": report.statements,
            "motions": report.motions,
            "holes": report.holes,
            "feed_length_mm": report.feed_length_mm,
            "rapid_length_mm": report.rapid_length_mm,
            "time_s": report.time_s,
            "bounds": {"min": lo, "max": hi},
            "uvw_bounds": report.uvw_bounds.iter().any(Option::is_some).then(|| json!({
                "min": report.uvw_bounds.iter().map(|r| r.map(|r| r.0)).collect::<Vec<_>>(),
                "max": report.uvw_bounds.iter().map(|r| r.map(|r| r.1)).collect::<Vec<_>>(),
            })),
            "machine_moves": report.machine_moves,
            "spindle_rpm": report.spindle_rpm.map(|(lo, hi)| [lo, hi]),
            "threads": report.threads.iter().map(|t| json!({
                "lead": t.lead,
                "start": [t.start.x, t.start.y, t.start.z],
                "end": [t.end.x, t.end.y, t.end.z],
                "line": t.line,
            })).collect::<Vec<_>>(),
            "tools": report.tools.iter().map(|(t, e)| json!({
                "number": t,
                "shape": e.as_ref().and_then(|e| e.shape).map(|c| c.to_string()),
                "h": e.as_ref().map(|e| e.h),
                "d": e.as_ref().and_then(|e| e.d),
                "name": e.as_ref().and_then(|e| e.name.clone()),
                "nose_radius_mm": e.as_ref().and_then(|e| e.nose).map(|n| n.radius),
                "tip": e.as_ref().and_then(|e| e.nose).map(|n| n.tip),
            })).collect::<Vec<_>>(),
            "errors": headlines(true).into_iter().chain(refusal.iter().cloned()).collect::<Vec<_>>(),
            "warnings": headlines(false).into_iter().chain(missing.iter().cloned()).collect::<Vec<_>>(),
            "machine_values": model_notes(&ran.outcome),
        });
        Said::Json(value)
    } else {
        notes += &ran.rendered_diagnostics(&parse_diagnostics);
        let mut text = format!(
            "{}: {} blocks ({} statements), {} motions\n  feed  {:.3} mm\n  rapid {:.3} mm\n  time  {} ({:.1} s)\n",
            o.file.display(),
            report.blocks,
            report.statements,
            report.motions,
            report.feed_length_mm,
            report.rapid_length_mm,
            crate::say::hms(report.time_s),
            report.time_s
        );
        text += &format!("  {}\n", ran.dialect);
        if report.holes > 0 {
            text += &format!("  holes {} (canned cycles)\n", report.holes);
        }
        match report.spindle_rpm {
            Some((lo, hi)) if format!("{lo:.0}") == format!("{hi:.0}") => {
                text += &format!("  spindle {hi:.0} rpm (cutting)\n")
            }
            Some((lo, hi)) => text += &format!("  spindle {lo:.0} … {hi:.0} rpm (cutting)\n"),
            None => {}
        }
        for line in thread_lines(&report.threads) {
            text += &format!("  {line}\n");
        }
        let lathe = ran.dialect.dialect.is_lathe();
        for (t, e) in &report.tools {
            let offsets: Vec<u32> =
                ran.outcome.tool_offsets.iter().filter(|(tool, _)| tool == t).map(|&(_, o)| o).collect();
            text += &format!("  tool  {}\n", tool_line(*t, e, lathe.then_some(&offsets[..])));
        }
        if report.motions > 0 {
            // On a lathe X is the tool's radius, and Y is said only where
            // the program places it (a mill-turn's).
            for (axis, range) in ["X", "Y", "Z"].iter().zip(report.bounds) {
                let radius = if lathe && *axis == "X" { " (radius)" } else { "" };
                text += &match range {
                    Some((lo, hi)) => format!("  {axis} {lo:>10.3} … {hi:>10.3}{radius}\n"),
                    None if lathe && *axis == "Y" => String::new(),
                    None => format!("  {axis}     not placed by the program\n"),
                };
            }
            // LinuxCNC's U V W, where the program places them.
            for (axis, range) in ["U", "V", "W"].iter().zip(report.uvw_bounds) {
                if let Some((lo, hi)) = range {
                    text += &format!("  {axis} {lo:>10.3} … {hi:>10.3}\n");
                }
            }
        }
        if report.machine_moves > 0 {
            let n = report.machine_moves;
            let s = if n == 1 { "move" } else { "moves" };
            text += &format!("  {n} {s} in machine coordinates (G28/G30/G53), not in the bounds\n");
        }
        for m in &missing {
            notes += &format!("warning: {m}\n");
        }
        for note in model_notes(&ran.outcome) {
            text += &format!("  note: {note}\n");
        }
        if let Some(r) = &refusal {
            notes += &format!("{r}\n\n");
        }
        let warnings = parse_diagnostics.iter().filter(|d| !d.is_error()).count() as u64
            + ran.outcome.warnings
            + missing.len() as u64;
        text += &format!("  {}, {}\n", say::count(errors as u64, "error"), say::count(warnings, "warning"));
        Said::Text(text)
    };
    let failure = (errors > 0).then(|| format!("{}: {}", o.file.display(), say::count(errors as u64, "error")));
    Ok(Checked { report: said, notes, failure })
}

#[cfg(test)]
mod tests {
    use kezuri_geom::Axes;

    use super::*;

    fn pass(lead: f64, x: f64, z: [f64; 2], line: u32) -> Thread {
        let at = |z| Axes { x, z, ..Axes::ZERO };
        Thread { lead, start: at(z[0]), end: at(z[1]), line }
    }

    #[test]
    fn a_cycles_passes_are_one_line() {
        // Four passes of one cycle going deeper, starting along the flank
        // (G76), then a finishing pass of another block, then a thread of
        // another lead.
        let threads = [
            pass(1.5, 9.7, [2.3, -30.0], 14),
            pass(1.5, 9.5, [2.2, -30.0], 14),
            pass(1.5, 9.3, [2.1, -30.0], 14),
            pass(1.5, 9.08, [2.0, -30.0], 14),
            pass(1.5, 9.08, [2.0, -30.0], 15),
            pass(2.0, 15.0, [-40.0, -60.0], 20),
        ];
        assert_eq!(
            thread_lines(&threads),
            [
                "thread lead 1.5000 mm, Z 2.000 → -30.000, 4 passes, X 9.700 → 9.080 (radius; line 14)",
                "thread lead 1.5000 mm, Z 2.000 → -30.000, 1 pass, X 9.080 (radius; line 15)",
                "thread lead 2.0000 mm, Z -40.000 → -60.000, 1 pass, X 15.000 (radius; line 20)",
            ]
        );
        assert!(thread_lines(&[]).is_empty());
    }
}
