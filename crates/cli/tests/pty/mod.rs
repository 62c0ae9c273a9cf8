//! The instrument on a pseudo-terminal, and what the capture tests share:
//! the simulated readings, the capture's options, waiting for messages and
//! points, running the binary.
#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::mpsc::{channel, Receiver, Sender};
use std::thread;
use std::time::{Duration, Instant};

use crate::capture::CaptureArgs;
use clap::Parser;

mod terminal;
#[allow(unused_imports)]
pub use terminal::{pty, Pty};

#[derive(Parser)]
pub struct Cmd {
    #[command(flatten)]
    a: CaptureArgs,
}

/// The capture's options from its command-line words.
pub fn args(words: &[String]) -> CaptureArgs {
    let words = words.iter().map(String::as_str);
    Cmd::try_parse_from(std::iter::once("capture").chain(words)).expect("arguments").a
}

/// Messages from a capture, collected as they come.
pub struct Log {
    pub rx: Receiver<String>,
    pub seen: Vec<String>,
}

impl Log {
    pub fn new() -> (Sender<String>, Log) {
        let (tx, rx) = channel();
        (tx, Log { rx, seen: Vec::new() })
    }
    pub fn wait_for(&mut self, what: &str) -> String {
        if let Some(m) = self.seen.iter().find(|m| m.contains(what)) {
            return m.clone();
        }
        let end = Instant::now() + Duration::from_secs(20);
        while let Some(left) = end.checked_duration_since(Instant::now()) {
            match self.rx.recv_timeout(left) {
                Ok(m) => {
                    self.seen.push(m.clone());
                    if m.contains(what) {
                        return m;
                    }
                }
                Err(_) => break,
            }
        }
        panic!("no message containing {what:?}; got {:#?}", self.seen)
    }
    pub fn drain(&mut self) -> &[String] {
        while let Ok(m) = self.rx.try_recv() {
            self.seen.push(m);
        }
        &self.seen
    }
}

/// Points stored in a data file (complete lines after `No,Z`).
pub fn points(path: &Path) -> Vec<(usize, f64)> {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let body = match text.rfind('\n') {
        Some(p) => &text[..=p],
        None => "",
    };
    body.lines()
        .skip_while(|l| *l != "No,Z")
        .skip(1)
        .map(|l| {
            let (n, z) = l.split_once(',').expect("No,Z");
            (n.parse().unwrap(), z.parse().unwrap())
        })
        .collect()
}

pub fn wait_points(path: &Path, n: usize) {
    let end = Instant::now() + Duration::from_secs(20);
    while points(path).len() < n {
        assert!(Instant::now() < end, "only {} of {n} points arrived", points(path).len());
        thread::sleep(Duration::from_millis(10));
    }
}

/// tip_z = bottom + sign·(reading − zero) in integer µm, as text → f64: the
/// oracle for what the file must hold (bottom −20, sign −1, zero 0.5).
pub fn expected_z(reading_um: i64) -> f64 {
    let um = -20_000 - (reading_um - 500);
    format!("{}{}.{:03}", if um < 0 { "-" } else { "" }, um.abs() / 1000, um.abs() % 1000).parse().unwrap()
}

/// The simulated indicator: reading of point `no` in µm (a 0–50 mm stroke).
pub fn reading_um(no: usize) -> i64 {
    12_345 + (no as i64 * 7_919) % 20_000
}

/// The lines the instrument sends for point `no`, in rotating forms of the
/// Mitutoyo family (once a record is seen, `--format auto` takes no plain
/// number), and now and then rejected lines before the good one.
pub fn plunge(no: usize) -> String {
    let um = reading_um(no);
    let mm = format!("{}.{:03}", um / 1000, um % 1000);
    let good = match no % 4 {
        0 => format!("01A+{:0>8}\r", mm),   // Mitutoyo multiplexer, CR
        1 => format!("01A+{:0>8}\r\n", mm), // Mitutoyo record, CR LF
        2 => format!("FFFF0{:06}30\r", um), // Digimatic nibbles
        _ => format!("01A+{:0>8}\n", mm),   // USB-ITN style, LF
    };
    let noise = match no % 3 {
        0 => "01A+001?.345\r", // garbled digit
        1 => "01A+0075.000\r", // out of --range 0,50
        _ => "\r\n\u{1}#@!\r", // blank and binary junk
    };
    format!("{noise}{good}")
}

pub const NX: usize = 5;
pub const NY: usize = 3;

pub fn capture_words(port: &str, data: &Path, resume: bool) -> Vec<String> {
    let mut w: Vec<String> = [
        "--port",
        port,
        "--count",
        "5,3",
        "--pitch",
        "0.5",
        "--origin",
        "-10,-7.5",
        "--bottom",
        "-20",
        "--sign",
        "-1",
        "--zero",
        "0.5",
        "--range",
        "0,50",
        "--timeout",
        "0.4",
        "-o",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    w.push(data.display().to_string());
    if resume {
        w.push("--resume".into());
    }
    w
}

pub fn check_final(data: &Path, port1: &str) {
    let text = std::fs::read_to_string(data).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "# kezuri probe capture");
    assert_eq!(lines[1], "# grid nx=5 ny=3 pitch=0.5 origin=-10,-7.5 pattern=zigzag");
    assert_eq!(lines[2], "# tip_z = bottom + sign * (reading - zero): bottom=-20 sign=-1 zero=0.5");
    assert!(lines[3].starts_with(&format!("# port {port1} 9600 baud, started 20")), "{}", lines[3]);
    assert!(lines[3].ends_with('Z'));
    assert_eq!(lines[4], "No,Z");
    assert!(text.ends_with('\n'));
    let got = points(data);
    assert_eq!(got.len(), NX * NY, "{text}");
    for (i, (no, z)) in got.iter().enumerate() {
        assert_eq!(*no, i + 1);
        assert_eq!(*z, expected_z(reading_um(i + 1)), "point {no}");
        // Shortest round trip, no binary noise.
        assert!(lines[5 + i].len() <= 12, "{}", lines[5 + i]);
    }
}

/// Joins a capture thread, failing instead of hanging.
pub fn join<T>(job: thread::JoinHandle<T>) -> T {
    let end = Instant::now() + Duration::from_secs(20);
    while !job.is_finished() {
        assert!(Instant::now() < end, "the capture did not end");
        thread::sleep(Duration::from_millis(10));
    }
    job.join().unwrap()
}

/// Waits for a kezuri process, killing it (and failing) after 20 s.
pub fn wait_child(child: &mut std::process::Child) -> std::process::ExitStatus {
    let end = Instant::now() + Duration::from_secs(20);
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status;
        }
        if Instant::now() > end {
            child.kill().ok();
            child.wait().ok();
            panic!("kezuri probe capture did not end");
        }
        thread::sleep(Duration::from_millis(10));
    }
}

pub fn kezuri() -> Command {
    Command::new(env!("CARGO_BIN_EXE_kezuri"))
}

/// Runs `kezuri probe capture WORDS`, its stderr lines into a channel.
pub fn spawn_capture(words: &[String]) -> (std::process::Child, Log) {
    let mut child = kezuri()
        .args(["probe", "capture"])
        .args(words)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn kezuri");
    let (tx, log) = Log::new();
    let err = child.stderr.take().unwrap();
    thread::spawn(move || {
        for line in BufReader::new(err).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    (child, log)
}
