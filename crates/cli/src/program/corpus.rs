//! Every program of the repository, run whole and ready to be run again
//! handing its path on in pieces of one move: what the tests of the
//! commands that take a run's path piece by piece compare.

use std::path::{Path, PathBuf};

use kezuri_geom::PathSink;
use kezuri_machine::Machine;
use kezuri_nc::interp::{self, Outcome, Settings};
use kezuri_nc::{detect, parse_as, Program, SourceFile, Sources};

use crate::files::Folder;
use crate::program::dialect_settings;

/// A program of the repository, parsed and run whole.
pub struct Case {
    pub name: String,
    /// The run of the whole program.
    pub whole: Outcome,
    program: Program,
    sources: Sources,
    settings: Settings,
    folder: PathBuf,
}

impl Case {
    /// The program run again, its path handed to `sink` in pieces of one
    /// move (where it may be cut).
    pub fn run_into(&mut self, sink: &mut dyn PathSink) -> Outcome {
        let mut library = Folder::new(self.folder.clone());
        interp::run_into(&mut self.program, &mut self.sources, 0, &mut library, &self.settings, sink)
    }
}

/// Every program file under `dir`, in order.
fn programs(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let mut paths: Vec<PathBuf> = entries.flatten().map(|e| e.path()).collect();
    paths.sort();
    for p in paths {
        let ext = p.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
        if p.is_dir() {
            programs(&p, out);
        } else if ["nc", "ngc", "gcode", "tap", "cnc"].contains(&ext.as_str()) {
            out.push(p);
        }
    }
}

/// `each` of every program of the repository (corpus, testdata, samples,
/// bench) that parses without an error, run on `machine`.
pub fn each_case(machine: &Machine, mut each: impl FnMut(Case)) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files = Vec::new();
    for dir in ["corpus", "crates/nc/testdata", "samples", "bench/programs"] {
        programs(&root.join(dir), &mut files);
    }
    for file in &files {
        let text = String::from_utf8_lossy(&std::fs::read(file).unwrap()).into_owned();
        let name = file.display().to_string();
        let Ok(detected) = detect(None, &name, &text) else { continue };
        let mut sources = Sources::default();
        let id = sources.add(SourceFile::new(name.clone(), text.clone()));
        let mut program = Program::default();
        if parse_as(&mut program, id, &text, detected.dialect).iter().any(|d| d.is_error()) || program.units.is_empty()
        {
            continue;
        }
        let settings =
            Settings { piece_moves: 1, step_limit: 200_000, ..dialect_settings(detected.dialect, None, machine) };
        let folder = file.parent().unwrap().to_path_buf();
        let whole =
            interp::run(&mut program.clone(), &mut sources.clone(), 0, &mut Folder::new(folder.clone()), &settings);
        each(Case { name, whole, program, sources, settings, folder });
    }
}
