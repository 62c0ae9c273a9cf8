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
    /// control) and tool table ([tools.T1] h = 1: the length register of G43 H).
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
/// is told in one line on stderr (`kezuri tool table --machine` lists it).
pub fn load(path: &Path) -> Result<Machine> {
    let (machine, notes) = read(path)?;
    if !notes.is_empty() {
        eprintln!(
            "warning: {}: the imported tool table left out {} entries and has {} warnings \
             (kezuri tool table --machine {0} lists them)",
            path.display(),
            notes.skipped.len(),
            notes.warnings.len()
        );
    }
    Ok(machine)
}

/// Reads a machine file, with what its imported tool table left out or lacks.
pub fn read(path: &Path) -> Result<(Machine, Notes)> {
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let dir = path.parent().unwrap_or(Path::new(""));
    Machine::parse(&text, dir, &Disk).with_context(|| format!("in machine file {}", path.display()))
}
