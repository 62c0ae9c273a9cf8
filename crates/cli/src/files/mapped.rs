//! A large program's text mapped into memory instead of read: the kernel
//! reads its pages as they are needed, and this process lets go of them
//! again every 20 ms, so that reading a file of any size holds only the
//! pages read in the last moment (they stay in the page cache and come back
//! at the cost of a minor fault).

use std::fs::File;
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

use anyhow::{bail, Context, Result};
use kezuri_nc::source::TextStore;
use memmap2::{Mmap, UncheckedAdvice};

/// Files at least this long are mapped rather than read.
const MAP_FROM_BYTES: u64 = 8 << 20;

/// How often the pages read are let go of.
const FORGET_EVERY: Duration = Duration::from_millis(20);

/// A file's text, mapped: UTF-8 (a byte-order mark skipped).
pub struct MappedText {
    map: Arc<Mmap>,
    /// Where the text begins (3 after a byte-order mark).
    start: usize,
    stop: Arc<AtomicBool>,
    forgetter: Option<JoinHandle<()>>,
}

/// `path` mapped, where it is a plain file of [`MAP_FROM_BYTES`] or more
/// holding UTF-8 text; `None` where it is to be read as before (smaller,
/// not a plain file, or bytes that are not UTF-8, which reading replaces).
pub fn map_text(path: &Path) -> Result<Option<MappedText>> {
    if path == Path::new("-") {
        return Ok(None);
    }
    let file = File::open(path).with_context(|| format!("cannot read {}", path.display()))?;
    map_file(&file, path)
}

/// Standard input's text, more than [`MAP_FROM_BYTES`] of it spooled to a
/// temporary file (gone when closed) and mapped as a file is: `Err` with
/// the bytes read where there is less (or where they are not UTF-8).
pub fn spool_stdin() -> Result<std::result::Result<MappedText, Vec<u8>>> {
    let cannot = || "cannot read standard input";
    let mut head = Vec::new();
    let mut stdin = std::io::stdin().lock();
    stdin.by_ref().take(MAP_FROM_BYTES).read_to_end(&mut head).context(cannot())?;
    if (head.len() as u64) < MAP_FROM_BYTES {
        return Ok(Err(head));
    }
    let mut spool = tempfile::tempfile().context("cannot make a temporary file for standard input")?;
    spool.write_all(&head).context("cannot spool standard input")?;
    drop(head);
    std::io::copy(&mut stdin, &mut spool).context(cannot())?;
    match map_file(&spool, Path::new("-"))? {
        Some(mapped) => Ok(Ok(mapped)),
        None => {
            let mut bytes = Vec::new();
            spool.seek(SeekFrom::Start(0)).and_then(|_| spool.read_to_end(&mut bytes)).context(cannot())?;
            Ok(Err(bytes))
        }
    }
}

/// The open `file` (named `path`) mapped, as [`map_text`] maps it.
fn map_file(file: &File, path: &Path) -> Result<Option<MappedText>> {
    let meta = file.metadata().with_context(|| format!("cannot read {}", path.display()))?;
    if meta.is_file() && meta.len() > u64::from(u32::MAX) {
        // Positions in a program are kept in 32 bits.
        bail!("{}: {} bytes: kezuri reads programs of up to 4 GiB", path.display(), meta.len());
    }
    if !meta.is_file() || meta.len() < MAP_FROM_BYTES {
        return Ok(None);
    }
    // SAFETY: the map is read only. A program must not be rewritten on disk
    // while kezuri reads it (its text would change under the run, as it
    // would under a control drip-feeding it).
    let map = Arc::new(unsafe { Mmap::map(file) }.with_context(|| format!("cannot read {}", path.display()))?);
    let start = if map.starts_with(b"\xEF\xBB\xBF") { 3 } else { 0 };
    let stop = Arc::new(AtomicBool::new(false));
    let forgetter = {
        let (map, stop) = (Arc::clone(&map), Arc::clone(&stop));
        std::thread::spawn(move || {
            while !stop.load(Ordering::Relaxed) {
                std::thread::park_timeout(FORGET_EVERY);
                forget(&map, 0..map.len());
            }
        })
    };
    let text = MappedText { map, start, stop, forgetter: Some(forgetter) };
    // Checked a piece at a time, each let go of once checked. (A piece
    // ends at a line: no character is split.)
    let mut from = start;
    while from < text.map.len() {
        let to = match memchr::memchr(b'\n', &text.map[(from + (4 << 20)).min(text.map.len())..]) {
            Some(i) => (from + (4 << 20)).min(text.map.len()) + i + 1,
            None => text.map.len(),
        };
        if std::str::from_utf8(&text.map[from..to]).is_err() {
            return Ok(None);
        }
        forget(&text.map, from / 4096 * 4096..to / 4096 * 4096);
        from = to;
    }
    Ok(Some(text))
}

/// Lets go of the pages of `range` (they are read again when touched).
fn forget(map: &Mmap, range: std::ops::Range<usize>) {
    if range.is_empty() {
        return;
    }
    // SAFETY: DONTNEED on a read-only file mapping drops this process's
    // copies of the pages; the next touch reads the file's bytes again.
    let _ = unsafe { map.unchecked_advise_range(UncheckedAdvice::DontNeed, range.start, range.len()) };
}

impl TextStore for MappedText {
    fn text(&self) -> &str {
        // SAFETY: checked to be UTF-8 when mapped; the file is read only.
        unsafe { std::str::from_utf8_unchecked(&self.map[self.start..]) }
    }

    fn forget(&self, range: std::ops::Range<usize>) {
        let page = 4096;
        let from = (self.start + range.start).div_ceil(page) * page;
        let to = ((self.start + range.end) / page * page).max(from);
        forget(&self.map, from..to);
    }
}

impl Drop for MappedText {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.forgetter.take() {
            t.thread().unpark();
            let _ = t.join();
        }
    }
}
