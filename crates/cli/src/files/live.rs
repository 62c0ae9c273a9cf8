//! The temporary files alive now, removed on Ctrl-C, SIGTERM and SIGHUP.
//!
//! The first file listed starts a thread that waits for those signals
//! (signal-hook: the handler itself only wakes the thread); on one it
//! removes every listed file and ends the process as the signal would
//! have. A command that never writes a file keeps the default handling.

use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, Once};

use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};

static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn live() -> MutexGuard<'static, Vec<PathBuf>> {
    LIVE.lock().unwrap_or_else(|e| e.into_inner())
}

/// Lists `tmp` (before it is created).
pub fn add(tmp: &Path) {
    static WATCH: Once = Once::new();
    WATCH.call_once(watch);
    live().push(tmp.to_path_buf());
}

/// Takes `tmp` off the list (it is gone, or renamed).
pub fn remove(tmp: &Path) {
    live().retain(|p| p != tmp);
}

/// Renames `tmp` to `target` and takes it off the list, a signal waiting
/// until both are done.
pub fn rename(tmp: &Path, target: &Path) -> std::io::Result<()> {
    let mut list = live();
    let r = std::fs::rename(tmp, target);
    list.retain(|p| p != tmp);
    r
}

/// Starts the thread that cleans up on a signal. Without it (the handler
/// cannot be installed) the files are still removed on every other exit.
fn watch() {
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else { return };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            let list = live();
            for p in list.iter() {
                std::fs::remove_file(p).ok();
            }
            // Ends the process as the signal would have (the list stays
            // locked: no rename starts meanwhile).
            signal_hook::low_level::emulate_default_handler(signal).ok();
            std::process::exit(128 + signal);
        }
    });
}
