//! What the tests of the real-program corpora (`corpus/shop`,
//! `corpus/lathe`) share: the subprograms a program calls, read from
//! folders, and the program files a corpus holds.

use std::path::{Path, PathBuf};

use kezuri_nc::interp::Library;
use kezuri_nc::SourceFile;

/// Subprograms `O####.nc` (or `O#`, `####`, `#`, with `.nc`, `.txt`, `.min`
/// or no extension, as `kezuri`'s library folder) from the first of these
/// folders that has one: the program's own folder first.
pub struct Folder(pub Vec<PathBuf>);

impl Library for Folder {
    fn load(&mut self, number: u32) -> Option<SourceFile> {
        let stems = [format!("O{number:04}"), format!("O{number}"), format!("{number:04}"), format!("{number}")];
        for dir in &self.0 {
            let Ok(entries) = std::fs::read_dir(dir) else { continue };
            let mut found: Vec<PathBuf> = entries
                .flatten()
                .map(|e| e.path())
                .filter(|p| p.is_file())
                .filter(|p| {
                    let stem = p.file_stem().map(|s| s.to_string_lossy().to_uppercase()).unwrap_or_default();
                    let ext = p.extension().map(|s| s.to_string_lossy().to_lowercase());
                    stems.contains(&stem) && matches!(ext.as_deref(), None | Some("nc") | Some("txt") | Some("min"))
                })
                .collect();
            found.sort();
            if let Some(path) = found.into_iter().next() {
                let text = String::from_utf8_lossy(&std::fs::read(&path).ok()?).into_owned();
                return Some(SourceFile::new(path.display().to_string(), text));
            }
        }
        None
    }
}

/// The program files of a corpus (`corpus/<name>`): `folder/file` for every
/// file of each of its folders but the `.upstream` originals, sorted, to
/// hold against the rows of its `SOURCES.tsv`.
pub fn programs(corpus: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let folders = std::fs::read_dir(corpus).unwrap_or_else(|e| panic!("{}: {e}", corpus.display()));
    for dir in folders.flatten().filter(|e| e.path().is_dir()) {
        let files = std::fs::read_dir(dir.path()).unwrap_or_else(|e| panic!("{}: {e}", dir.path().display()));
        for file in files.flatten().filter(|f| f.path().is_file()) {
            let name = file.file_name().to_string_lossy().into_owned();
            if !name.ends_with(".upstream") {
                out.push(format!("{}/{name}", dir.file_name().to_string_lossy()));
            }
        }
    }
    out.sort();
    out
}
