//! The progress bar of a long program: on a terminal, a run that lasts over
//! two seconds shows "running … of … left" on standard error and clears it
//! before the report; short work, `--quiet` and a pipe show nothing.

#![cfg(unix)]

mod common;
#[path = "pty/terminal.rs"]
mod terminal;

use std::io::Read;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A small file that runs long: a WHILE loop of `passes` passes (three
/// statements each).
fn looping(passes: u64) -> String {
    format!("%\nO0001\n#1=0\nWHILE[#1LT{passes}]DO1\n#1=#1+1\nEND1\nG0 X1.\nM30\n%\n")
}

/// `kezuri check FILE WORDS` with standard output and standard error on a
/// pseudo-terminal: all it wrote there, and how long it ran.
fn on_terminal(file: &str, words: &[&str]) -> (String, Duration) {
    let terminal::Pty { master, _slave: slave, .. } = terminal::pty();
    let mut master = master.expect("the terminal's end");
    let t0 = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_kezuri"))
        .args(["check", file, "--step-limit", "100000000"])
        .args(words)
        .stdin(Stdio::null())
        .stdout(slave.try_clone().unwrap())
        .stderr(slave)
        .spawn()
        .expect("kezuri runs");
    // The slave's last copy is the child's: reading the master ends (EIO)
    // once the child has exited.
    let reader = std::thread::spawn(move || {
        let mut out = Vec::new();
        let mut buf = [0u8; 4096];
        while let Ok(n) = master.read(&mut buf) {
            if n == 0 {
                break;
            }
            out.extend_from_slice(&buf[..n]);
        }
        out
    });
    let status = child.wait().unwrap();
    let took = t0.elapsed();
    let out = String::from_utf8_lossy(&reader.join().unwrap()).into_owned();
    assert!(status.success(), "{out}");
    (out, took)
}

#[test]
fn a_long_run_shows_its_bar_on_a_terminal_and_clears_it_before_the_report() {
    let dir = tempfile::tempdir().unwrap();
    // How fast this build runs the loop, through a pipe (no bar there).
    let probe = common::path(dir.path(), "probe.nc");
    std::fs::write(&probe, looping(100_000)).unwrap();
    let t0 = Instant::now();
    let piped = common::kezuri(&["check", &probe]);
    let rate = 100_000.0 / t0.elapsed().as_secs_f64();
    common::ok(&piped);
    assert!(!String::from_utf8_lossy(&piped.stderr).contains("left"), "no bar through a pipe");
    // A loop that takes about four seconds.
    let passes = ((4.0 * rate) as u64).max(100_000);
    let long = common::path(dir.path(), "long.nc");
    std::fs::write(&long, looping(passes)).unwrap();
    let report = common::ok(&common::kezuri(&["check", &long, "--step-limit", "100000000"]));
    let (out, took) = on_terminal(&long, &[]);
    if took > Duration::from_millis(2600) {
        assert!(out.contains("running") && out.contains(" of ") && out.contains("left"), "{took:?}: {out:?}");
    }
    // The bar was cleared, then the report printed whole on a clean line.
    let after = out.rsplit_once("\x1b[2K").map_or(out.as_str(), |(_, rest)| rest);
    assert!(after.ends_with(&report), "{out:?}");
    assert!(!after.contains("left") && !after.contains('\x1b'), "{after:?}");
    // --quiet: nothing of a bar, whatever the time.
    let (quiet, _) = on_terminal(&long, &["--quiet"]);
    assert!(!quiet.contains("left") && !quiet.contains('\x1b'), "{quiet:?}");
    assert!(quiet.ends_with(&report), "{quiet:?}");
}

#[test]
fn short_work_shows_no_bar_on_a_terminal() {
    let dir = tempfile::tempdir().unwrap();
    let short = common::path(dir.path(), "short.nc");
    std::fs::write(&short, looping(10)).unwrap();
    let (out, took) = on_terminal(&short, &[]);
    assert!(took < Duration::from_secs(2), "{took:?}");
    assert!(!out.contains("left") && !out.contains('\x1b'), "{out:?}");
}
