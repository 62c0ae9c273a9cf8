//! The data file of a capture on disk. What is written when is
//! [`DataFile`]'s; here the file is created with its first point (a
//! capture that stops before one leaves no file), locked while a capture
//! writes it (a second capture on it refuses), and every point is written
//! in one append and fsync'd before the next is taken. On `--resume` a last
//! record cut off by a crash or a power loss (no end of line) is dropped.

use std::fs::{File, OpenOptions, TryLockError};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::time::SystemTime;

use anyhow::{bail, Context, Result};
use kezuri_cam::probe::capture::DataFile;

use super::CaptureArgs;

/// The data file, open for appending once it exists.
pub(super) struct Store {
    path: PathBuf,
    /// `None` until the first point of a new capture.
    file: Option<File>,
    /// What is written and stored.
    pub(super) data: DataFile,
}

impl Store {
    /// A new capture (no file until its first point) or, with `--resume`, the
    /// existing file, locked, its header checked against `args` and a cut-off
    /// last record dropped (reported through `say`).
    pub(super) fn open(args: &CaptureArgs, say: &mut dyn FnMut(&str)) -> Result<Store> {
        let path = &args.output;
        let name = path.display();
        if path.as_os_str() == "-" {
            bail!("probe capture writes a file (-o DATA), not standard output");
        }
        if !path.exists() {
            return Ok(Store { path: path.clone(), file: None, data: DataFile::new(args.header(SystemTime::now())) });
        }
        if !args.resume {
            bail!("{name} exists: add --resume to continue that capture, or choose another file");
        }
        let mut f =
            OpenOptions::new().read(true).append(true).open(path).with_context(|| format!("cannot open {name}"))?;
        lock(&f, path)?;
        let mut bytes = Vec::new();
        f.read_to_end(&mut bytes).with_context(|| format!("cannot read {name}"))?;
        let (data, cut_off) = DataFile::resume(&args.capture(), &bytes, &name.to_string())?;
        if let Some(cut) = cut_off {
            say(&cut.message);
            f.set_len(cut.keep as u64).and_then(|_| f.sync_all()).with_context(|| format!("cannot truncate {name}"))?;
        }
        Ok(Store { path: path.clone(), file: Some(f), data })
    }

    /// Appends point `no` and syncs it to disk; the first point of a new
    /// capture creates the file with its header.
    pub(super) fn append(&mut self, no: usize, z: f64) -> Result<()> {
        let name = self.path.display();
        match &mut self.file {
            Some(f) => self.data.append(f, no, z).and_then(|_| f.sync_data()),
            None => {
                let mut f = OpenOptions::new().append(true).create_new(true).open(&self.path).map_err(|e| {
                    if e.kind() == std::io::ErrorKind::AlreadyExists {
                        anyhow::anyhow!("{name} was created by another program during the capture")
                    } else {
                        anyhow::Error::new(e).context(format!("cannot create {name}"))
                    }
                })?;
                lock(&f, &self.path)?;
                self.data.append(&mut f, no, z).and_then(|_| f.sync_all())?;
                sync_dir(&self.path);
                self.file = Some(f);
                Ok(())
            }
        }
        .with_context(|| format!("cannot write {name}"))
    }
}

/// Takes the advisory lock on the data file, or says who holds it.
fn lock(f: &File, path: &Path) -> Result<()> {
    match f.try_lock() {
        Ok(()) => Ok(()),
        Err(TryLockError::WouldBlock) => bail!(
            "{} is in use by another capture (a `kezuri probe capture` still running on it): stop that \
             one first — two captures on one file would mix their points",
            path.display()
        ),
        Err(TryLockError::Error(e)) => Err(e).with_context(|| format!("cannot lock {}", path.display())),
    }
}

/// Makes a new file's name durable (best effort).
fn sync_dir(path: &Path) {
    #[cfg(unix)]
    if let Some(dir) = path.parent() {
        let dir = if dir.as_os_str().is_empty() { Path::new(".") } else { dir };
        if let Ok(d) = File::open(dir) {
            let _ = d.sync_all();
        }
    }
    #[cfg(not(unix))]
    let _ = path;
}
