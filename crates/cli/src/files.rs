//! Files in and out: reading inputs (`-` is stdin), writing outputs whole or
//! not at all, and the subprogram library folder.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};

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
/// comments in old programs, say) become U+FFFD instead of failing.
pub fn read_text(path: &Path) -> Result<String> {
    Ok(String::from_utf8_lossy(&read_bytes(path)?).into_owned())
}

/// Writes `data` to `path`, or to stdout when `path` is `None` or `-`.
/// A file is written to a temporary name in the same folder and renamed, so
/// no half-written output is ever left behind.
pub fn write_output(path: Option<&Path>, data: &[u8]) -> Result<()> {
    write_output_with(path, |w| w.write_all(data))
}

/// As [`write_output`], with the bytes made by `fill` as it goes (through
/// a buffer): an output larger than memory, a large surface's STL, is never
/// held whole.
pub fn write_output_with(path: Option<&Path>, fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> Result<()> {
    match path {
        None => write_stdout(fill),
        Some(p) if p == Path::new("-") => write_stdout(fill),
        Some(p) => write_atomic_with(p, fill),
    }
}

fn write_stdout(fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> Result<()> {
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    match fill(&mut out).and_then(|_| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        r => r.context("cannot write to standard output"),
    }
}

/// Writes a file through a temporary file and a rename.
pub fn write_atomic(path: &Path, data: &[u8]) -> Result<()> {
    write_atomic_with(path, |w| w.write_all(data))
}

/// Writes a file through a temporary file and a rename, its bytes made by
/// `fill` as it goes; when `fill` fails, the temporary file is removed and
/// `path` is left as it was.
///
/// A path that is not a regular file — `/dev/null`, `/dev/stdout`, a named
/// pipe — is written straight into: renaming a file over it would put a
/// plain file where the device was (and a later reader of `/dev/null` would
/// read what was written there).
pub fn write_atomic_with(path: &Path, fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> Result<()> {
    if std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir()) {
        let f = std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .with_context(|| format!("cannot open {}", path.display()))?;
        let mut w = std::io::BufWriter::with_capacity(1 << 16, f);
        return fill(&mut w).and_then(|_| w.flush()).with_context(|| format!("cannot write {}", path.display()));
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "out".into());
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let result = (|| {
        let f = std::fs::File::create(&tmp).with_context(|| format!("cannot create {}", tmp.display()))?;
        let mut w = std::io::BufWriter::with_capacity(1 << 16, f);
        fill(&mut w).and_then(|_| w.flush()).with_context(|| format!("cannot write {}", tmp.display()))?;
        let f =
            w.into_inner().map_err(|e| e.into_error()).with_context(|| format!("cannot write {}", tmp.display()))?;
        f.sync_all().ok();
        std::fs::rename(&tmp, path).with_context(|| format!("cannot write {}", path.display()))
    })();
    if result.is_err() {
        std::fs::remove_file(&tmp).ok();
    }
    result
}

/// A folder of subprogram files named `O1234.nc` (also `O1234`, `o1234.nc`,
/// `O1234.NC`, `1234.nc`).
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
}
