//! Outputs written all together or not at all.
//!
//! Every output file of a command is first written whole to a temporary
//! file beside it; only when all are complete are they renamed over their
//! targets. A failure before the renames leaves every old file as it was;
//! a failure between them says which files were replaced already.
//!
//! Standard output (`-`, or no path) and a device or a pipe (`/dev/null`,
//! a named pipe) cannot be replaced by a rename: their bytes are held (in
//! memory up to [`HELD_IN_MEMORY`], then in an unnamed temporary file) and
//! written at [`Outputs::commit`], before the renames.
//!
//! A link is written through: the file it points to is replaced and the
//! link stays a link. A file the user may not write is refused, as the
//! shell would (a rename would replace a read-only file). The temporary
//! files are removed when the command fails, and on Ctrl-C, SIGTERM and
//! SIGHUP (see [`live`]).

use std::fs::OpenOptions;
use std::io::{Seek, Write};
use std::os::unix::ffi::OsStrExt;
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

use super::live;

/// Bytes for standard output, a device or a pipe held in memory at most;
/// more go to an unnamed temporary file (a program of any length is never
/// held whole).
pub const HELD_IN_MEMORY: usize = 8 << 20;

/// A set of outputs written all together: [`add`](Outputs::add) each, then
/// [`commit`](Outputs::commit). Dropped without a commit, it leaves every
/// target as it was.
#[derive(Default)]
pub struct Outputs {
    staged: Vec<Staged>,
}

enum Staged {
    /// A file written to `tmp`, renamed over `target` (`shown` as the user
    /// named it, `target` past any link) at the commit.
    File { shown: PathBuf, target: PathBuf, tmp: PathBuf },
    /// Standard output (`None`) or a device or pipe, written at the commit.
    Stream { to: Option<PathBuf>, bytes: tempfile::SpooledTempFile },
}

impl Outputs {
    /// An empty set.
    pub fn new() -> Outputs {
        Outputs::default()
    }

    /// Adds `data` for `path` (`None` or `-`: standard output).
    pub fn add(&mut self, path: Option<&Path>, data: &[u8]) -> Result<()> {
        self.add_with(path, |w| w.write_all(data))
    }

    /// Adds the bytes that `fill` makes for `path`. A file's bytes go
    /// straight to its temporary file (a large STL is never held whole).
    pub fn add_with(
        &mut self,
        path: Option<&Path>,
        fill: impl FnOnce(&mut (dyn Write + Send)) -> std::io::Result<()>,
    ) -> Result<()> {
        let path = match path {
            Some(p) if p != Path::new("-") => p,
            _ => return self.stream(None, fill),
        };
        let target = through_links(path)?;
        let old = match std::fs::metadata(&target) {
            Ok(m) if m.is_dir() => bail!("cannot write {}: it is a folder", path.display()),
            Ok(m) if !m.is_file() => return self.stream(Some(path.to_path_buf()), fill),
            Ok(m) => {
                writable(path, &target)?;
                Some(m.permissions())
            }
            Err(_) => None,
        };
        let tmp = temporary_name(&target);
        live::add(&tmp);
        // From here on the temporary file is listed: a failure, a drop or a
        // signal removes it.
        self.staged.push(Staged::File { shown: path.to_path_buf(), target, tmp: tmp.clone() });
        let cannot = |e: std::io::Error| cannot_write(path, e);
        let mut options = OpenOptions::new();
        options.write(true).create_new(true).mode(0o666);
        let f = options.open(&tmp).map_err(cannot)?;
        if let Some(p) = old {
            f.set_permissions(p).map_err(cannot)?;
        }
        let mut w = std::io::BufWriter::with_capacity(1 << 16, f);
        fill(&mut w).and_then(|_| w.flush()).map_err(cannot)?;
        let f = w.into_inner().map_err(|e| e.into_error()).map_err(cannot)?;
        // A full disk may show only here (space the file system promised
        // and could not give); a file system that cannot sync is no error.
        match f.sync_all() {
            Err(e) if is_full(&e) => return Err(cannot(e)),
            _ => {}
        }
        Ok(())
    }

    fn stream(
        &mut self,
        to: Option<PathBuf>,
        fill: impl FnOnce(&mut (dyn Write + Send)) -> std::io::Result<()>,
    ) -> Result<()> {
        let mut bytes = tempfile::SpooledTempFile::new(HELD_IN_MEMORY);
        let mut w = std::io::BufWriter::with_capacity(1 << 16, &mut bytes);
        fill(&mut w).and_then(|_| w.flush()).context("cannot make the output")?;
        drop(w);
        self.staged.push(Staged::Stream { to, bytes });
        Ok(())
    }

    /// Adds the outputs `other` holds to these, to be written with them.
    pub fn append(&mut self, mut other: Outputs) {
        self.staged.append(&mut other.staged);
    }

    /// Writes the streams, then renames every file over its target.
    pub fn commit(mut self) -> Result<()> {
        for s in &mut self.staged {
            if let Staged::Stream { to, bytes } = s {
                bytes.rewind().context("cannot read the output back")?;
                write_stream(to.as_deref(), bytes)?;
            }
        }
        let mut replaced: Vec<String> = Vec::new();
        for s in std::mem::take(&mut self.staged) {
            let Staged::File { shown, target, tmp } = s else { continue };
            if let Err(e) = live::rename(&tmp, &target) {
                std::fs::remove_file(&tmp).ok();
                let done = match replaced.len() {
                    0 => String::new(),
                    _ => format!(" ({} written already; the others are as they were)", replaced.join(", ")),
                };
                // The files still staged are removed by the drop.
                return Err(e).with_context(|| format!("cannot write {}{done}", shown.display()));
            }
            replaced.push(shown.display().to_string());
        }
        Ok(())
    }
}

impl Drop for Outputs {
    fn drop(&mut self) {
        for s in &self.staged {
            if let Staged::File { tmp, .. } = s {
                std::fs::remove_file(tmp).ok();
                live::remove(tmp);
            }
        }
    }
}

/// Whether `e` says the disk (or the user's quota, or the file size
/// limit) is full.
fn is_full(e: &std::io::Error) -> bool {
    matches!(e.raw_os_error(), Some(libc::ENOSPC) | Some(libc::EDQUOT) | Some(libc::EFBIG))
}

/// `cannot write PATH: …`, a full disk said as such.
pub fn cannot_write(path: &Path, e: std::io::Error) -> anyhow::Error {
    let full = match e.raw_os_error() {
        Some(libc::ENOSPC) => "the disk is full",
        Some(libc::EDQUOT) => "the disk quota is used up",
        Some(libc::EFBIG) => "the file is past the size this system allows (ulimit -f)",
        _ => return anyhow::Error::new(e).context(format!("cannot write {}", path.display())),
    };
    anyhow::anyhow!("cannot write {}: {full} ({e})", path.display())
}

/// Writes `bytes` to standard output (`None`) or into a device or pipe; a
/// reader of standard output that stops early is no error.
fn write_stream(to: Option<&Path>, bytes: &mut impl std::io::Read) -> Result<()> {
    match to {
        None => {
            let mut out = std::io::stdout().lock();
            match std::io::copy(bytes, &mut out).and_then(|_| out.flush()) {
                Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
                r => r.map(|_| ()).context("cannot write to standard output"),
            }
        }
        Some(p) => OpenOptions::new()
            .write(true)
            .open(p)
            .and_then(|mut f| std::io::copy(bytes, &mut f))
            .map(|_| ())
            .map_err(|e| cannot_write(p, e)),
    }
}

/// The file `path` names past every link (itself when it is no link, or a
/// link to a file not there yet).
fn through_links(path: &Path) -> Result<PathBuf> {
    let mut p = path.to_path_buf();
    for _ in 0..40 {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let to = std::fs::read_link(&p).with_context(|| format!("cannot read the link {}", path.display()))?;
                p = match p.parent() {
                    Some(dir) => dir.join(to),
                    None => to,
                };
            }
            _ => return Ok(p),
        }
    }
    bail!("cannot write {}: too many links", path.display())
}

/// Refuses a file the user may not write (`access(2)`, as the shell's `>`).
fn writable(shown: &Path, target: &Path) -> Result<()> {
    let Ok(c) = std::ffi::CString::new(target.as_os_str().as_bytes()) else {
        bail!("cannot write {}: the name holds a NUL byte", shown.display())
    };
    // SAFETY: `c` is a NUL-terminated path that lives through the call.
    if unsafe { libc::access(c.as_ptr(), libc::W_OK) } != 0 {
        let e = std::io::Error::last_os_error();
        bail!("cannot write {}: the file is read-only for this user ({e})", shown.display());
    }
    Ok(())
}

/// A temporary name beside `target`, unique in this process.
fn temporary_name(target: &Path) -> PathBuf {
    static COUNT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let n = COUNT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = target.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "out".into());
    dir.join(format!(".{name}.{}-{n}.tmp", std::process::id()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stream_larger_than_memory_holds_comes_out_whole_at_the_commit() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("device");
        std::fs::write(&path, b"").unwrap();
        // Bytes that are not all alike, past what is held in memory.
        let data: Vec<u8> = (0..HELD_IN_MEMORY + 123_457).map(|i| (i % 251) as u8).collect();
        let mut out = Outputs::new();
        out.stream(Some(path.clone()), |w| w.write_all(&data)).unwrap();
        // Nothing is written before the commit.
        assert_eq!(std::fs::metadata(&path).unwrap().len(), 0);
        out.commit().unwrap();
        assert!(std::fs::read(&path).unwrap() == data);
    }
}
