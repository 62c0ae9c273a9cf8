//! `kezuri check --jobs N FILE...`: a shop's library of programs checked
//! at once, each as `check` checks one, the reports in the order the files
//! were given.

use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::sync::mpsc::{channel, sync_channel};
use std::sync::Mutex;
use std::time::Duration;

use anyhow::{bail, Result};
use serde_json::json;

use super::{check, Checked, Said};
use crate::files::write_output;
use crate::program::RunOptions;
use crate::progress::LateBar;
use crate::say;

/// Reports that may wait, per worker, for an earlier file still being
/// checked: memory stays bounded however many files there are.
const AHEAD_PER_JOB: usize = 4;

/// Checks `files` (the first is `o.file`'s place) on `jobs` threads; exits
/// with an error naming how many failed when any did.
pub fn run(o: &RunOptions, files: &[PathBuf], jobs: usize, as_json: bool) -> Result<()> {
    if jobs == 0 {
        bail!("--jobs must be at least 1");
    }
    if o.dprnt.is_some() && files.len() > 1 {
        bail!("--dprnt names one file for one program's printed lines: leave it out to check several programs");
    }
    if files.len() > 1 && files.iter().any(|f| f.as_os_str() == "-") {
        bail!("standard input (-) can be checked alone only");
    }
    let bar = LateBar::new("check", "files", Duration::from_secs(2));
    // More threads than files would only wait.
    let jobs = jobs.min(files.len());
    let window = jobs * AHEAD_PER_JOB;
    let (task_tx, task_rx) = sync_channel::<usize>(jobs);
    let task_rx = Mutex::new(task_rx);
    let (done_tx, done_rx) = channel::<(usize, Checked)>();
    let mut failed = 0;
    std::thread::scope(|scope| -> Result<()> {
        for _ in 0..jobs {
            let done_tx = done_tx.clone();
            let task_rx = &task_rx;
            scope.spawn(move || loop {
                let next = task_rx.lock().map(|rx| rx.recv());
                let Ok(Ok(k)) = next else { return };
                let one = RunOptions { file: files[k].clone(), ..o.clone() };
                if done_tx.send((k, checked(&one, as_json))).is_err() {
                    return;
                }
            });
        }
        drop(done_tx);
        let (mut sent, mut shown) = (0, 0);
        let mut waiting: BTreeMap<usize, Checked> = BTreeMap::new();
        let mut task_tx = Some(task_tx);
        while shown < files.len() {
            while sent < files.len() && sent < shown + window {
                if let Some(tx) = &task_tx {
                    tx.send(sent)?;
                }
                sent += 1;
            }
            if sent == files.len() {
                // No more work: idle workers stop.
                task_tx = None;
            }
            let Ok((k, c)) = done_rx.recv() else { bail!("the checking threads stopped early") };
            waiting.insert(k, c);
            while let Some(c) = waiting.remove(&shown) {
                failed += usize::from(c.failure.is_some());
                let say = || -> Result<()> {
                    eprint!("{}", c.notes);
                    if let (Some(f), false) = (&c.failure, as_json) {
                        eprintln!("error: {f}");
                    }
                    write_output(None, c.said().as_bytes())
                };
                match &bar {
                    Some(bar) => bar.suspend(say)?,
                    None => say()?,
                }
                shown += 1;
                if let Some(bar) = &bar {
                    bar.update(shown as u64, files.len() as u64);
                }
            }
        }
        Ok(())
    })?;
    if let Some(bar) = &bar {
        bar.finish();
    }
    if failed > 0 {
        bail!("{} of {} failed", say::count(failed as u64, "program"), files.len());
    }
    Ok(())
}

/// One file checked, whatever happens: a file that cannot be read (or a
/// fault in kezuri) is a failure reported in its place, not the end of the
/// batch. With `--json` the object gains `error`: null, or why it failed.
fn checked(o: &RunOptions, as_json: bool) -> Checked {
    let file = o.file.display().to_string();
    let result = catch_unwind(AssertUnwindSafe(|| check(o, as_json)))
        .unwrap_or_else(|_| Err(anyhow::anyhow!("{file}: kezuri failed on this program (an internal fault)")));
    let mut c = result.unwrap_or_else(|e| {
        let failure = format!("{e:#}");
        let report =
            if as_json { Said::Json(json!({"file": file, "completed": false})) } else { Said::Text(String::new()) };
        Checked { report, notes: String::new(), failure: Some(failure) }
    });
    if let Said::Json(serde_json::Value::Object(map)) = &mut c.report {
        map.insert("error".into(), c.failure.clone().map_or(serde_json::Value::Null, serde_json::Value::String));
    }
    c
}
