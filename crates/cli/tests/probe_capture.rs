//! `kezuri probe capture` against a simulated indicator on a pseudo-terminal:
//! garbage lines, an out-of-range value, a silence, a cut-off mid-run (the
//! instrument's end closed, or kezuri killed), a crash mid-write, and a
//! resume with a new instrument session. The final file must hold exactly
//! the grid's points, in order, equal to what the instrument sent minus the
//! rejected lines. (The line parser's table of formats is
//! crates/cam/tests/probe_capture.rs.)
//!
//! The module is compiled into this test by path, so its functions are
//! driven directly (messages collected, no progress bar); the binary is
//! driven too, and killed mid-run.

#![cfg(unix)]

#[allow(dead_code)]
#[path = "../src/cmd/probe/capture.rs"]
mod capture;
mod pty;

use std::io::Write;
use std::path::PathBuf;
use std::process::Stdio;
use std::thread;
use std::time::{Duration, Instant};

use pty::*;

/// Through the module's functions: cut by closing the instrument's end.
#[test]
fn disconnect_and_resume_lose_and_duplicate_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("ume.csv");

    // Session 1: points 1..=4, then the cable is pulled in the middle of a line.
    let mut p1 = pty();
    let port1 = p1.path.clone();
    let (tx, mut log) = Log::new();
    let a = args(&capture_words(&p1.path, &data, false));
    let job = thread::spawn(move || capture::run_with(&a, false, &mut |m| tx.send(m.to_string()).unwrap()));
    log.wait_for("waiting for readings");
    for no in 1..=4 {
        p1.send(&plunge(no));
    }
    wait_points(&data, 4);
    p1.send("01A+000");
    p1.cut();
    let err = join(job).expect_err("a disconnect is an error");
    let msg = format!("{err:#}");
    assert!(msg.contains("4 of 15 points are stored"), "{msg}");
    assert!(msg.contains("restart the measuring program at point 4 (measured again"), "{msg}");
    assert!(msg.contains("--resume"), "{msg}");
    let seen = log.drain().join("\n");
    eprintln!("session 1 messages:\n{seen}\nerror: {msg}");
    assert!(seen.contains("line ignored") && seen.contains("01A+001?.345"), "{seen}");
    assert!(seen.contains("outside --range 0,50") && seen.contains("01A+0075.000"), "{seen}");
    assert_eq!(points(&data).len(), 4);

    // A crash while writing point 5: a truncated last line.
    std::fs::OpenOptions::new().append(true).open(&data).unwrap().write_all(b"5,-3").unwrap();

    // Without --resume the file is never overwritten.
    let a = args(&capture_words("/dev/null/none", &data, false));
    let e = format!("{:#}", capture::run_with(&a, false, &mut |_| {}).unwrap_err());
    assert!(e.contains("exists") && e.contains("--resume"), "{e}");
    // With other options --resume refuses.
    let mut w = capture_words("/dev/null/none", &data, true);
    w[3] = "6,3".into();
    let a = args(&w);
    let e = format!("{:#}", capture::run_with(&a, false, &mut |_| {}).unwrap_err());
    assert!(e.contains("other options") && e.contains("nx=6"), "{e}");

    // Session 2: a new instrument session from point 4 (checked), with a silence.
    let mut p2 = pty();
    let (tx, mut log) = Log::new();
    let a = args(&capture_words(&p2.path, &data, true));
    let job = thread::spawn(move || capture::run_with(&a, false, &mut |m| tx.send(m.to_string()).unwrap()));
    log.wait_for("dropped an incomplete last line \"5,-3\"");
    log.wait_for("restart the measuring program at point 4");
    log.wait_for("waiting for readings");
    for no in 4..=NX * NY {
        if no == 9 {
            log.wait_for("no reading for");
        }
        p2.send(&plunge(no));
    }
    // Readings after the last point are not stored.
    p2.send("01A+0001.000\r");
    join(job).expect("capture completes");
    let eta = log.wait_for("predicted end");
    assert!(eta.starts_with("started 20") && eta.contains("; predicted end 20"), "{eta}");
    log.wait_for("capture complete: 15 points");
    eprintln!("session 2 messages:\n{}", log.drain().join("\n"));
    check_final(&data, &port1);

    // Resuming a complete file does nothing (and does not open the port).
    let a = args(&capture_words("/dev/null/none", &data, true));
    capture::run_with(&a, false, &mut |_| {}).expect("complete");
    check_final(&data, &port1);
}

/// Through the binary: cut by killing kezuri mid-run, then resume.
#[test]
fn binary_killed_and_resumed() {
    let dir = tempfile::tempdir().unwrap();
    let data: PathBuf = dir.path().join("ume.csv");
    let mut p1 = pty();
    let port1 = p1.path.clone();
    let (mut child, mut log) = spawn_capture(&capture_words(&p1.path, &data, false));
    log.wait_for("waiting for readings");
    for no in 1..=6 {
        p1.send(&plunge(no));
    }
    wait_points(&data, 6);
    child.kill().unwrap();
    child.wait().unwrap();
    assert_eq!(points(&data).len(), 6);

    let mut p2 = pty();
    let (mut child, mut log) = spawn_capture(&capture_words(&p2.path, &data, true));
    log.wait_for("restart the measuring program at point 6");
    log.wait_for("waiting for readings");
    for no in 6..=10 {
        p2.send(&plunge(no));
    }
    wait_points(&data, 10);
    // This time the instrument goes away: exit code 1 and the resume command.
    p2.cut();
    let status = wait_child(&mut child);
    assert_eq!(status.code(), Some(1));
    log.wait_for("10 of 15 points are stored");
    log.wait_for("--resume");

    let mut p3 = pty();
    let (mut child, mut log) = spawn_capture(&capture_words(&p3.path, &data, true));
    log.wait_for("waiting for readings");
    for no in 10..=NX * NY {
        p3.send(&plunge(no));
    }
    assert!(wait_child(&mut child).success());
    log.wait_for("capture complete");
    check_final(&data, &port1);
}

/// Through the binary with its stderr on a terminal: the progress bar runs
/// from the first point to the last, between the messages.
#[test]
fn binary_draws_a_progress_bar_on_a_terminal() {
    use std::io::Read;
    use std::sync::{Arc, Mutex};
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("ume.csv");
    let mut instrument = pty();
    let terminal = pty();
    let mut child = kezuri()
        .args(["probe", "capture"])
        .args(capture_words(&instrument.path, &data, false))
        .stdout(Stdio::null())
        .stderr(Stdio::from(terminal._slave.try_clone().unwrap()))
        .spawn()
        .expect("spawn kezuri");
    // Everything the terminal shows, bar redraws (CR, escapes) and all.
    let shown = Arc::new(Mutex::new(String::new()));
    let mut screen = terminal.master.as_ref().unwrap().try_clone().unwrap();
    let sink = Arc::clone(&shown);
    thread::spawn(move || {
        let mut buf = [0u8; 4096];
        while let Ok(n) = screen.read(&mut buf) {
            if n == 0 {
                break;
            }
            sink.lock().unwrap().push_str(&String::from_utf8_lossy(&buf[..n]));
        }
    });
    let wait_shown = |what: &str| {
        let end = Instant::now() + Duration::from_secs(20);
        while !shown.lock().unwrap().contains(what) {
            assert!(Instant::now() < end, "{what:?} never shown: {:?}", shown.lock().unwrap());
            thread::sleep(Duration::from_millis(10));
        }
    };
    wait_shown("waiting for readings");
    wait_shown("0/15 points");
    for no in 1..=NX * NY {
        instrument.send(&plunge(no));
        // The bar redraws at most every 50 ms.
        thread::sleep(Duration::from_millis(60));
    }
    assert!(wait_child(&mut child).success());
    wait_shown("capture complete: 15 points");
    let text = shown.lock().unwrap().clone();
    // One redraw per point but for the rate limit and the bar cleared at the end.
    let drawn = (1..15).filter(|k| text.contains(&format!(" {k}/15 points"))).count();
    assert!(drawn >= 10, "the bar showed {drawn} of the points 1..14: {text:?}");
    assert!(text.contains("predicted end"), "{text:?}");
    assert_eq!(points(&data).len(), NX * NY);
}
