//! The machine file read from the disk (`--machine M.toml`): what it says
//! and its rules are kezuri-machine's (`crates/machine/src/machine.rs`
//! documents every section).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use kezuri_machine::tool_table::Notes;
use kezuri_machine::{Files, Machine};

/// `--machine M.toml` of the commands that make programs.
#[derive(clap::Args, Clone, Debug)]
pub struct MachineArg {
    /// Machine file (TOML): its [post] (how the program is written for the
    /// control) and tool table ([tools.T1] h = 1, length = 127.0: the register
    /// of G43 H and its value, mm); docs/machine.md has every key.
    #[arg(long, value_name = "M.toml")]
    pub machine: Option<PathBuf>,
}

impl MachineArg {
    /// The machine file read, or the default machine.
    pub fn load(&self) -> Result<Machine> {
        self.machine.as_deref().map_or_else(|| Ok(Machine::default()), load)
    }
}

/// The files on the disk: a machine file's imported tool table, the bits
/// of a FreeCAD library.
pub struct Disk;

impl Files for Disk {
    fn is_file(&self, path: &Path) -> bool {
        path.is_file()
    }

    fn read(&self, path: &Path) -> std::io::Result<Vec<u8>> {
        std::fs::read(path)
    }
}

/// Reads a machine file; what its imported tool table left out or lacks
/// is told on stderr, each on its line (the first few; `kezuri tool table
/// --machine` lists them all).
pub fn load(path: &Path) -> Result<Machine> {
    let (machine, notes) = read(path)?;
    for line in note_lines(&path.display().to_string(), &notes) {
        eprintln!("{line}");
    }
    Ok(machine)
}

/// The most notes of an import `load` tells one by one.
const NOTES_TOLD: usize = 5;

/// `warning: M.toml: imported table: …` for each note, the first
/// [`NOTES_TOLD`], then how many more there are and where to see them.
fn note_lines(file: &str, notes: &Notes) -> Vec<String> {
    let all: Vec<String> = (notes.skipped.iter().map(|s| format!("left out {s}")))
        .chain(notes.warnings.iter().cloned())
        .map(|s| format!("warning: {file}: imported tool table: {s}"))
        .collect();
    let more = all.len().saturating_sub(NOTES_TOLD);
    let mut out: Vec<String> = all.into_iter().take(NOTES_TOLD).collect();
    if more > 0 {
        out.push(format!(
            "warning: {file}: imported tool table: {more} more {} (kezuri tool table --machine {file} lists them)",
            if more == 1 { "note" } else { "notes" }
        ));
    }
    out
}

/// Reads a machine file, with what its imported tool table left out or lacks.
pub fn read(path: &Path) -> Result<(Machine, Notes)> {
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let (mut machine, notes) =
        Machine::parse(&text, dir, &Disk).with_context(|| format!("in machine file {}", path.display()))?;
    // A length the table lacks is warned of with the file to add it to.
    machine.settings.tool_file = Some(path.display().to_string());
    Ok((machine, notes))
}
