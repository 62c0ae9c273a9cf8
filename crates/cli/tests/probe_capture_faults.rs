//! How an overnight capture survives what goes wrong, on a pseudo-terminal
//! playing the indicator: readings sent while kezuri is stopped, a line cut
//! by a kill, damaged and over-long lines, two resumes on one file, a
//! capture that fails before its first point, a restart at the wrong point,
//! and power loss (SIGKILL, and the data file cut at every byte of its last
//! record, then resumed and levelled).

#![cfg(unix)]

#[allow(dead_code)]
#[path = "../src/cmd/probe/capture.rs"]
mod capture;
mod pty;

use std::path::Path;
use std::thread;
use std::time::Duration;

use pty::*;

/// A Mitutoyo record of point `no` (`01A+0012.345`), as the indicator sends it.
fn record(no: usize) -> String {
    let um = reading_um(no);
    format!("01A+{:04}.{:03}\r", um / 1000, um % 1000)
}

/// Session 1 through the binary, still running with points 1..=4 stored
/// (its messages kept: a closed stderr would end it).
fn first_four(p: &mut Pty, data: &Path) -> (std::process::Child, Log) {
    let (child, mut log) = spawn_capture(&capture_words(&p.path, data, false));
    log.wait_for("waiting for readings");
    for no in 1..=4 {
        p.send(&plunge(no));
    }
    wait_points(data, 4);
    (child, log)
}

/// Four points captured, then the cable cut: the capture stops with exit 1.
/// Returns the port it read.
fn four_then_cut(data: &Path) -> String {
    let mut p = pty();
    let (mut child, _log) = first_four(&mut p, data);
    p.cut();
    assert_eq!(wait_child(&mut child).code(), Some(1));
    p.path.clone()
}

/// A resumed capture through the binary: waits until it listens.
fn resume(p: &Pty, data: &Path) -> (std::process::Child, Log) {
    let (child, mut log) = spawn_capture(&capture_words(&p.path, data, true));
    log.wait_for("waiting for readings");
    (child, log)
}

/// Issue 16, case 1: two readings sent while kezuri was down are not taken
/// as the next points (the port is flushed on open).
#[test]
fn readings_sent_while_stopped_are_not_points() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("ume.csv");
    let mut p1 = pty();
    let (mut child, _log1) = first_four(&mut p1, &data);
    child.kill().unwrap();
    child.wait().unwrap();
    // The measuring program runs on: two plunges while kezuri is down.
    p1.send(&plunge(5));
    p1.send(&plunge(6));
    let (mut child, mut log) = resume(&p1, &data);
    for no in 4..=NX * NY {
        p1.send(&plunge(no));
    }
    assert!(wait_child(&mut child).success(), "{:#?}", log.drain());
    check_final(&data, &p1.path);
    log.wait_for("restart the measuring program at point 4");
    log.wait_for("point 4 measured again");
    // Flushed on open, not even read.
    assert!(!log.drain().iter().any(|m| m.contains("discarded")), "{:#?}", log.seen);
}

/// Case 2: half a record read before a kill and its rest after the resume
/// (sent while kezuri is down, or arriving as it opens the port) never
/// make a reading.
#[test]
fn a_record_cut_by_a_kill_is_not_completed_by_its_tail() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("ume.csv");
    let mut p1 = pty();
    let (mut child, _log1) = first_four(&mut p1, &data);
    let five = record(5);
    let (head, tail) = five.split_at(7); // `01A+001` | `2.345\r`
    p1.send(head);
    thread::sleep(Duration::from_millis(100));
    child.kill().unwrap();
    child.wait().unwrap();
    p1.send(tail);
    // And the same tail again, a byte at a time, as the resumed capture
    // opens the port.
    let (mut child, mut log) = spawn_capture(&capture_words(&p1.path, &data, true));
    for b in tail.chars() {
        p1.send(&b.to_string());
        thread::sleep(Duration::from_millis(20));
    }
    log.wait_for("waiting for readings");
    for no in 4..=NX * NY {
        p1.send(&record(no));
    }
    assert!(wait_child(&mut child).success(), "{:#?}", log.drain());
    check_final(&data, &p1.path);
}

/// Cases 3 and 4: Mitutoyo records with lost characters and the tail of an
/// over-long line are reported and never stored.
#[test]
fn damaged_and_overlong_lines_are_not_points() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("ume.csv");
    let mut p = pty();
    let (mut child, mut log) = spawn_capture(&capture_words(&p.path, &data, false));
    log.wait_for("waiting for readings");
    p.send("01A+0001345\r"); // `01A+0001.345` with its point lost
    p.send("01A+0001\r"); // the rest lost
    p.send("01A+00012.345\r"); // one digit too many
                               // Over-long garbage ending in a number: cut into pieces of whatever
                               // length, its tail must never be a reading.
    for k in [257, 300, 514, 771] {
        p.send(&format!("{}5.5\r", "x".repeat(k)));
    }
    for no in 1..=NX * NY {
        p.send(&record(no));
    }
    assert!(wait_child(&mut child).success(), "{:#?}", log.drain());
    check_final(&data, &p.path);
    for raw in ["01A+0001345", "01A+0001\"", "01A+00012.345", "xxxxxxxx"] {
        log.wait_for(raw);
    }
}

/// Case 5: a second capture on a data file another one is writing refuses,
/// and the file ends up as one capture wrote it.
#[test]
fn two_resumes_on_one_file_refuse() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("ume.csv");
    let port = four_then_cut(&data);
    let mut p2 = pty();
    let (mut first, _log) = resume(&p2, &data);
    let p3 = pty();
    let (mut second, mut log) = spawn_capture(&capture_words(&p3.path, &data, true));
    assert_eq!(wait_child(&mut second).code(), Some(1));
    log.wait_for("in use by another capture");
    for no in 4..=NX * NY {
        p2.send(&plunge(no));
    }
    assert!(wait_child(&mut first).success());
    check_final(&data, &port);
}

/// Case 6: a capture that fails (or is killed) before its first point
/// leaves no data file.
#[test]
fn no_points_no_data_file() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("ume.csv");
    let a = args(&capture_words("/dev/null/none", &data, false));
    let e = format!("{:#}", capture::run_with(&a, false, &mut |_| {}).unwrap_err());
    assert!(e.contains("cannot open serial port"), "{e}");
    assert!(!data.exists(), "left {data:?} after the port failed");
    let mut p = pty();
    let (mut child, mut log) = spawn_capture(&capture_words(&p.path, &data, false));
    log.wait_for("waiting for readings");
    p.send("garbage\r");
    p.cut();
    assert_eq!(wait_child(&mut child).code(), Some(1));
    assert!(!data.exists(), "left {data:?} after the instrument went away");
    let p = pty();
    let (mut child, mut log) = spawn_capture(&capture_words(&p.path, &data, false));
    log.wait_for("waiting for readings");
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(!data.exists(), "left {data:?} after a kill");
}

/// A resume whose first reading is not the last stored point (the program
/// restarted elsewhere) stops and stores nothing; `--range` applies to that
/// reading too.
#[test]
fn a_restart_at_the_wrong_point_stores_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("ume.csv");
    four_then_cut(&data);
    let before = std::fs::read(&data).unwrap();
    let mut p2 = pty();
    let (mut child, mut log) = resume(&p2, &data);
    p2.send("01A+0075.000\r"); // outside --range 0,50: not the check
    p2.send(&plunge(5));
    assert_eq!(wait_child(&mut child).code(), Some(1));
    log.wait_for("outside --range");
    let msg = log.wait_for("measured again");
    assert!(msg.contains("point 4"), "{msg}");
    log.wait_for("nothing new was stored");
    assert_eq!(std::fs::read(&data).unwrap(), before);
}

/// Power loss: the complete data file cut at every byte of its last record
/// is refused by `probe level` (never levelled with a cut value) and, resumed,
/// drops the cut record, checks point 14 and ends as the complete file.
#[test]
fn a_data_file_cut_in_its_last_record_is_resumed_and_never_levelled() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("ume.csv");
    let mut p = pty();
    let (mut child, mut log) = spawn_capture(&capture_words(&p.path, &data, false));
    log.wait_for("waiting for readings");
    for no in 1..=NX * NY {
        p.send(&plunge(no));
    }
    assert!(wait_child(&mut child).success());
    let full = std::fs::read(&data).unwrap();
    let level = |file: &Path| {
        let out = kezuri().args(["probe", "level"]).arg(file).args(["-o", "-"]).output().unwrap();
        (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned())
    };
    assert_eq!(level(&data).0, Some(0));
    let last = full[..full.len() - 1].iter().rposition(|&b| b == b'\n').unwrap() + 1;
    let cut_file = |cut: usize| {
        let name = dir.path().join(format!("cut{cut}.csv"));
        std::fs::write(&name, &full[..cut]).unwrap();
        name
    };
    for cut in last..full.len() {
        let (code, err) = level(&cut_file(cut));
        assert_eq!(code, Some(1), "cut at byte {cut}: levelled\n{err}");
    }
    for cut in last..full.len() {
        let name = cut_file(cut);
        let mut p = pty();
        let a = args(&capture_words(&p.path, &name, true));
        let (tx, mut log) = Log::new();
        let job = thread::spawn(move || capture::run_with(&a, false, &mut |m| tx.send(m.to_string()).unwrap()));
        log.wait_for("waiting for readings");
        if cut > last {
            log.wait_for("dropped an incomplete last line");
        }
        p.send(&plunge(14));
        p.send(&plunge(15));
        join(job).unwrap_or_else(|e| panic!("cut at byte {cut}: {e:#}"));
        assert_eq!(std::fs::read(&name).unwrap(), full, "cut at byte {cut}");
    }
}
