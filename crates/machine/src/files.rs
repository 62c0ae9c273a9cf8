//! The files a machine file or a tool library names, read by the caller:
//! this crate opens no path.

use std::collections::BTreeMap;
use std::io;
use std::path::{Path, PathBuf};

use crate::error::{with_sources, Error, ErrorKind, Result};

/// Where the files named by a file come from: a tool table beside the
/// machine file (`[tools] import`), the bits of a FreeCAD library. The
/// command line reads them from the disk.
pub trait Files {
    /// Whether `path` is a file (not a folder, not missing).
    fn is_file(&self, path: &Path) -> bool;
    /// The bytes of the file at `path`.
    fn read(&self, path: &Path) -> io::Result<Vec<u8>>;
}

/// Files held in memory, by path (an empty map: no file at all).
impl Files for BTreeMap<PathBuf, Vec<u8>> {
    fn is_file(&self, path: &Path) -> bool {
        self.contains_key(path)
    }

    fn read(&self, path: &Path) -> io::Result<Vec<u8>> {
        self.get(path).cloned().ok_or_else(|| io::Error::from(io::ErrorKind::NotFound))
    }
}

/// The bytes of `path`, or an error saying it cannot be read.
pub(crate) fn read_bytes(files: &dyn Files, path: &Path) -> Result<Vec<u8>> {
    files
        .read(path)
        .map_err(|e| Error::new(ErrorKind::Unreadable, format!("cannot read {}: {}", path.display(), with_sources(&e))))
}

/// The text of `path`; bytes that are not UTF-8 become U+FFFD.
pub(crate) fn read_text(files: &dyn Files, path: &Path) -> Result<String> {
    Ok(String::from_utf8_lossy(&read_bytes(files, path)?).into_owned())
}
