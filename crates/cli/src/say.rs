//! What a command says on standard error besides its errors and warnings:
//! how it read the program, a one-line summary of what it wrote, and
//! progress bars. `--quiet` silences these; errors and warnings always show.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use kezuri_geom::{cycle_time, Toolpath};
use kezuri_machine::Machine;

static QUIET: AtomicBool = AtomicBool::new(false);

/// Sets `--quiet` for the rest of the process.
pub fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
}

/// Whether `--quiet` was given.
pub fn quiet() -> bool {
    QUIET.load(Ordering::Relaxed)
}

/// Prints a line on standard error unless `--quiet`: a summary or a note,
/// never an error or a warning.
macro_rules! note {
    ($($arg:tt)*) => {
        if !$crate::say::quiet() {
            eprintln!($($arg)*);
        }
    };
}
pub(crate) use note;

/// An output as a summary names it: its path, or standard output.
pub fn shown(output: Option<&Path>) -> String {
    match output {
        Some(p) if p != Path::new("-") => p.display().to_string(),
        _ => "standard output".into(),
    }
}

/// A count and its noun, the noun plural unless the count is one: `1
/// error`, `0 errors`, `12 warnings`.
pub fn count(n: u64, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// `h:mm:ss`.
pub fn hms(s: f64) -> String {
    let t = s.round() as u64;
    format!("{}:{:02}:{:02}", t / 3600, t / 60 % 60, t % 60)
}

/// What a written program does: its moves, lengths and cycle time on the
/// machine file's rapids, feeds and acceleration.
pub fn program_summary(path: &Toolpath, machine: &Machine) -> String {
    let (time, _) = cycle_time(path, &machine.dynamics);
    summary_line(path.moves.len(), path.feed_length(), path.rapid_length(), time)
}

/// The summary of a written program of `moves` moves, its lengths and its
/// cycle time in seconds.
pub fn summary_line(moves: usize, feed_mm: f64, rapid_mm: f64, time_s: f64) -> String {
    format!("{moves} moves, feed {feed_mm:.1} mm, rapid {rapid_mm:.1} mm, cycle time {}", hms(time_s))
}

/// The one-line summary of a command that wrote the program `path` to
/// `output`, `what` first (empty, or ending in "; ").
pub fn wrote_program(output: Option<&Path>, what: &str, path: &Toolpath, machine: &Machine) {
    note!("wrote {}: {what}{}", shown(output), program_summary(path, machine));
}
