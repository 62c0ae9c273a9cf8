//! Files in and out: reading inputs (`-` is stdin), writing outputs whole or
//! not at all, and the subprogram library folder.

mod live;
mod mapped;
mod outputs;
mod same;

use std::io::Read;
use std::path::{Path, PathBuf};

pub use outputs::{cannot_write, Outputs};
pub use same::{refuse_same_files, Usage};

use anyhow::{Context, Result};
use kezuri_nc::interp::Library;
use kezuri_nc::SourceFile;

/// Reads an input whole; `-` is stdin.
pub fn read_bytes(path: &Path) -> Result<Vec<u8>> {
    if path == Path::new("-") {
        let mut bytes = Vec::new();
        std::io::stdin().read_to_end(&mut bytes).context("cannot read standard input")?;
        Ok(bytes)
    } else {
        std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))
    }
}

/// Reads a text input; `-` is stdin. Bytes that are not UTF-8 (Shift-JIS
/// comments in old programs, say) become U+FFFD instead of failing. A
/// UTF-8 byte-order mark (as Windows editors write) is skipped; UTF-16 text
/// is refused, named.
pub fn read_text(path: &Path) -> Result<String> {
    let bytes = read_bytes(path)?;
    text_of(&bytes).map_err(|why| anyhow::anyhow!("{}: {why}", path.display()))
}

/// A program's text as [`read_text`] reads it, a large file mapped into
/// memory instead (read page by page as the parser and the run need it),
/// and large standard input spooled to a temporary file and mapped.
pub fn read_program_text(path: &Path) -> Result<std::sync::Arc<dyn kezuri_nc::source::TextStore>> {
    if path == Path::new("-") {
        return match mapped::spool_stdin()? {
            Ok(mapped) => Ok(std::sync::Arc::new(mapped)),
            Err(bytes) => Ok(std::sync::Arc::new(text_of(&bytes).map_err(|why| anyhow::anyhow!("-: {why}"))?)),
        };
    }
    match mapped::map_text(path)? {
        Some(mapped) => Ok(std::sync::Arc::new(mapped)),
        None => Ok(std::sync::Arc::new(read_text(path)?)),
    }
}

/// The text of `bytes`, as [`read_text`] reads it.
fn text_of(bytes: &[u8]) -> std::result::Result<String, String> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let utf16 = match bytes {
        [0xFF, 0xFE, ..] => Some("little-endian, with the byte-order mark FF FE"),
        [0xFE, 0xFF, ..] => Some("big-endian, with the byte-order mark FE FF"),
        // ASCII text in UTF-16 without a mark: every other byte is zero.
        [a, 0, b, 0, ..] | [0, a, 0, b, ..] if a.is_ascii() && b.is_ascii() && *a != 0 && *b != 0 => {
            Some("without a byte-order mark")
        }
        _ => None,
    };
    if let Some(how) = utf16 {
        return Err(format!("the file is UTF-16 text ({how}): save it as UTF-8 or ASCII text"));
    }
    Ok(String::from_utf8_lossy(bytes).into_owned())
}

/// Writes `data` to `path`, or to stdout when `path` is `None` or `-`:
/// an [`Outputs`] of one.
pub fn write_output(path: Option<&Path>, data: &[u8]) -> Result<()> {
    let mut out = Outputs::new();
    out.add(path, data)?;
    out.commit()
}

/// Writes the file `path`, whole or not at all.
pub fn write_atomic(path: &Path, data: &[u8]) -> Result<()> {
    write_output(Some(path), data)
}

/// A folder of subprogram files named `O1234.nc` (also `O1234`, `o1234.nc`,
/// `O1234.NC`, `1234.nc`), and of LinuxCNC subroutine files `name.ngc`.
pub struct Folder {
    dir: PathBuf,
}

impl Folder {
    /// The library in `dir`.
    pub fn new(dir: PathBuf) -> Folder {
        Folder { dir }
    }
}

impl Library for Folder {
    fn load(&mut self, number: u32) -> Option<SourceFile> {
        let stems = [format!("O{number:04}"), format!("O{number}"), format!("{number:04}"), format!("{number}")];
        let entries = std::fs::read_dir(&self.dir).ok()?;
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
        let path = found.into_iter().next()?;
        let text = read_text(&path).ok()?;
        Some(SourceFile::new(path.display().to_string(), text))
    }

    /// LinuxCNC's `<stem>.ngc` (SUBROUTINE_PATH): the name as the program
    /// gives it, in lower case.
    fn load_ngc(&mut self, stem: &str) -> Option<SourceFile> {
        let path = self.dir.join(format!("{stem}.ngc"));
        let text = read_text(&path).ok()?;
        Some(SourceFile::new(path.display().to_string(), text))
    }
}
