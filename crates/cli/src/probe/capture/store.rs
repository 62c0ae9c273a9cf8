//! The data file of a capture. It is created with its first point (a
//! capture that stops before one leaves no file), locked while a capture
//! writes it (a second capture on it refuses), and every point is written in
//! one append and fsync'd before the next is taken. On `--resume` a last
//! record cut off by a crash or a power loss (no end of line) is dropped.

use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::time::SystemTime;

use anyhow::{bail, Context, Result};

use super::CaptureArgs;

/// The data file, open for appending once it exists.
pub(super) struct Store {
    path: PathBuf,
    /// The header a new file starts with.
    header: String,
    /// `None` until the first point of a new capture.
    file: Option<File>,
    /// Points stored.
    pub(super) stored: usize,
    /// Z of the last stored point.
    pub(super) last: Option<f64>,
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
        let mut store =
            Store { path: path.clone(), header: args.header(SystemTime::now()), file: None, stored: 0, last: None };
        if !path.exists() {
            return Ok(store);
        }
        if !args.resume {
            bail!("{name} exists: add --resume to continue that capture, or choose another file");
        }
        let mut f =
            OpenOptions::new().read(true).append(true).open(path).with_context(|| format!("cannot open {name}"))?;
        lock(&f, path)?;
        let mut bytes = Vec::new();
        f.read_to_end(&mut bytes).with_context(|| format!("cannot read {name}"))?;
        let complete = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |p| p + 1);
        (store.stored, store.last) = check(args, &String::from_utf8_lossy(&bytes[..complete]), path)?;
        if complete < bytes.len() {
            let tail = String::from_utf8_lossy(&bytes[complete..]).into_owned();
            say(&format!(
                "{name}: dropped an incomplete last line {tail:?} (the capture stopped while writing it, \
                 a crash or a power loss); point {} was not stored",
                store.stored + 1
            ));
            f.set_len(complete as u64).and_then(|_| f.sync_all()).with_context(|| format!("cannot truncate {name}"))?;
        }
        store.file = Some(f);
        Ok(store)
    }

    /// Appends point `no` and syncs it to disk; the first point of a new
    /// capture creates the file with its header.
    pub(super) fn append(&mut self, no: usize, z: f64) -> Result<()> {
        let record = format!("{no},{z}\n");
        let name = self.path.display();
        match &mut self.file {
            Some(f) => f.write_all(record.as_bytes()).and_then(|_| f.sync_data()),
            None => {
                let mut f = OpenOptions::new().append(true).create_new(true).open(&self.path).map_err(|e| {
                    if e.kind() == std::io::ErrorKind::AlreadyExists {
                        anyhow::anyhow!("{name} was created by another program during the capture")
                    } else {
                        anyhow::Error::new(e).context(format!("cannot create {name}"))
                    }
                })?;
                lock(&f, &self.path)?;
                f.write_all(format!("{}{record}", self.header).as_bytes()).and_then(|_| f.sync_all())?;
                sync_dir(&self.path);
                self.file = Some(f);
                Ok(())
            }
        }
        .with_context(|| format!("cannot write {name}"))?;
        self.stored = no;
        self.last = Some(z);
        Ok(())
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

/// Checks the complete lines of a data file against `args`: the number of
/// points stored and the Z of the last.
fn check(args: &CaptureArgs, text: &str, path: &Path) -> Result<(usize, Option<f64>)> {
    let name = path.display();
    let lines: Vec<&str> = text.lines().collect();
    for (i, w) in args.header_fixed().iter().enumerate() {
        match lines.get(i) {
            Some(l) if l.trim_end() == w => {}
            Some(l) => bail!(
                "{name}:{}: the file was captured with other options:\n  file:    {}\n  options: {w}\n\
                 (give the options it was started with, or capture to another file)",
                i + 1,
                l.trim_end()
            ),
            None => bail!("{name} has no complete capture header; remove it and start again"),
        }
    }
    let Some(table) = lines.iter().position(|l| l.trim_end() == "No,Z") else {
        bail!("{name} has no complete capture header (no `No,Z` line); remove it and start again");
    };
    if let Some((i, l)) = lines[3..table].iter().enumerate().find(|(_, l)| !l.starts_with('#')) {
        bail!("{name}:{}: unexpected line in the header: {l:?}", i + 4);
    }
    let (mut stored, mut last) = (0usize, None);
    for (i, l) in lines.iter().enumerate().skip(table + 1) {
        let bad = || anyhow::anyhow!("{name}:{}: not point {} as `No,Z`: {l:?}", i + 1, stored + 1);
        let (no, z) = l.trim_end().split_once(',').ok_or_else(bad)?;
        let z = z.parse::<f64>().ok().filter(|z| z.is_finite());
        if no.parse::<usize>().ok() != Some(stored + 1) || z.is_none() {
            return Err(bad());
        }
        stored += 1;
        last = z;
    }
    if stored > args.total() {
        bail!("{name} holds {stored} points, more than the {} of the grid", args.total());
    }
    Ok((stored, last))
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
