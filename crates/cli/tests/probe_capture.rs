//! `kezuri probe capture` against a simulated indicator on a pseudo-terminal:
//! garbage lines, an out-of-range value, a silence, a cut-off mid-run (the
//! instrument's end closed, or kezuri killed), a crash mid-write, and a
//! resume with a new instrument session. The final file must hold exactly
//! the grid's points, in order, equal to what the instrument sent minus the
//! rejected lines. Also the line parser on a table of formats.
//!
//! The module is compiled into this test by path, so its functions are
//! driven directly (messages collected, no progress bar); the binary is
//! driven too, and killed mid-run.

#![cfg(unix)]

#[allow(dead_code)]
#[path = "../src/probe/capture.rs"]
mod capture;

use std::fs::File;
use std::io::{BufRead, BufReader, Write};
use std::os::unix::io::FromRawFd;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::mpsc::{channel, Receiver, Sender};
use std::thread;
use std::time::{Duration, Instant};

use capture::{parse_reading, CaptureArgs, Format};
use clap::Parser;

#[derive(Parser)]
struct Cmd {
    #[command(flatten)]
    a: CaptureArgs,
}

fn args(words: &[&str]) -> CaptureArgs {
    Cmd::try_parse_from(std::iter::once("capture").chain(words.iter().copied())).expect("arguments").a
}

/// A pseudo-terminal: the test is the instrument on `master`; kezuri opens `path`.
struct Pty {
    master: Option<File>,
    _slave: File,
    path: String,
}

fn pty() -> Pty {
    let (mut m, mut s) = (0, 0);
    // SAFETY: openpty writes two descriptors; no name buffer, default settings.
    let r = unsafe { libc::openpty(&mut m, &mut s, std::ptr::null_mut(), std::ptr::null_mut(), std::ptr::null_mut()) };
    assert_eq!(r, 0, "openpty: {}", std::io::Error::last_os_error());
    // Not inherited by the kezuri processes other tests spawn: a copy of the
    // master there would keep the line up after the test closes it.
    // SAFETY: fcntl on the descriptors we just opened.
    unsafe {
        assert_eq!(libc::fcntl(m, libc::F_SETFD, libc::FD_CLOEXEC), 0);
        assert_eq!(libc::fcntl(s, libc::F_SETFD, libc::FD_CLOEXEC), 0);
    }
    // Raw from the start, so bytes written before kezuri opens the port are
    // not cooked (CR to LF, echo) by the line discipline.
    // SAFETY: termios calls on the slave we just opened.
    unsafe {
        let mut t: libc::termios = std::mem::zeroed();
        assert_eq!(libc::tcgetattr(s, &mut t), 0);
        libc::cfmakeraw(&mut t);
        assert_eq!(libc::tcsetattr(s, libc::TCSANOW, &t), 0);
    }
    let path = std::fs::read_link(format!("/proc/self/fd/{s}")).expect("slave path").display().to_string();
    // SAFETY: we own both descriptors.
    let (master, slave) = unsafe { (File::from_raw_fd(m), File::from_raw_fd(s)) };
    Pty { master: Some(master), _slave: slave, path }
}

impl Pty {
    fn send(&mut self, text: &str) {
        let m = self.master.as_mut().expect("master open");
        m.write_all(text.as_bytes()).unwrap();
        m.flush().unwrap();
        thread::sleep(Duration::from_millis(15));
    }
    /// The instrument's end goes away (cable pulled).
    fn cut(&mut self) {
        self.master.take();
    }
}

/// Messages from a capture, collected as they come.
struct Log {
    rx: Receiver<String>,
    seen: Vec<String>,
}

impl Log {
    fn new() -> (Sender<String>, Log) {
        let (tx, rx) = channel();
        (tx, Log { rx, seen: Vec::new() })
    }
    fn wait_for(&mut self, what: &str) -> String {
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
    fn drain(&mut self) -> &[String] {
        while let Ok(m) = self.rx.try_recv() {
            self.seen.push(m);
        }
        &self.seen
    }
}

/// Points stored in a data file (complete lines after `No,Z`).
fn points(path: &Path) -> Vec<(usize, f64)> {
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

fn wait_points(path: &Path, n: usize) {
    let end = Instant::now() + Duration::from_secs(20);
    while points(path).len() < n {
        assert!(Instant::now() < end, "only {} of {n} points arrived", points(path).len());
        thread::sleep(Duration::from_millis(10));
    }
}

/// tip_z = bottom + sign·(reading − zero) in integer µm, as text → f64: the
/// oracle for what the file must hold (bottom −20, sign −1, zero 0.5).
fn expected_z(reading_um: i64) -> f64 {
    let um = -20_000 - (reading_um - 500);
    format!("{}{}.{:03}", if um < 0 { "-" } else { "" }, um.abs() / 1000, um.abs() % 1000).parse().unwrap()
}

/// The simulated indicator: reading of point `no` in µm (a 0–50 mm stroke).
fn reading_um(no: usize) -> i64 {
    12_345 + (no as i64 * 7_919) % 20_000
}

/// The lines the instrument sends for point `no`, in rotating formats, and
/// now and then rejected lines before the good one.
fn plunge(no: usize) -> String {
    let um = reading_um(no);
    let mm = format!("{}.{:03}", um / 1000, um % 1000);
    let good = match no % 4 {
        0 => format!("01A+{:0>9}\r", mm),   // Mitutoyo multiplexer, CR
        1 => format!("{mm}\r\n"),           // plain number, CR LF
        2 => format!("FFFF0{:06}30\r", um), // Digimatic nibbles
        _ => format!("01A+{:0>8}\n", mm),   // USB-ITN style, LF
    };
    let noise = match no % 3 {
        0 => "01A+0001?.345\r", // garbled digit
        1 => "01A+00075.000\r", // out of --range 0,50
        _ => "\r\n\u{1}#@!\r",  // blank and binary junk
    };
    format!("{noise}{good}")
}

const NX: usize = 5;
const NY: usize = 3;

fn capture_words(port: &str, data: &Path, resume: bool) -> Vec<String> {
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

fn check_final(data: &Path, port1: &str) {
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

#[test]
fn parser_table() {
    use Format::*;
    // (line, format, value in mm, decimals, channel)
    let good: &[(&str, Format, f64, u32, Option<u32>)] = &[
        ("01A+00012.345", Auto, 12.345, 3, Some(1)),
        ("01A+00012.345\r", Digimatic, 12.345, 3, Some(1)),
        ("01A-001.2340", Auto, -1.234, 4, Some(1)), // GageMux manual's Mux-10 example
        ("01A+0000.123", Auto, 0.123, 3, Some(1)),  // Mitutoyo 99MAF600B, mm 0.001
        ("01A+000.1234", Digimatic, 0.1234, 4, Some(1)), // same, inch resolution digits
        ("07A-00000.00", Auto, -0.0, 2, Some(7)),
        ("10A+00019.16", Auto, 19.16, 2, Some(10)),
        ("FFFF8012345 30", Auto, -12.345, 3, None), // 99MBA043A example frame, mm
        ("FFFF0210765 40", Digimatic, 21.0765, 4, None), // LSM-6200 manual example
        ("FFFF0001234 41", Auto, 0.1234 * 25.4, 5, None), // inch → mm
        ("-12.345", Auto, -12.345, 3, None),
        ("+19.16", Number, 19.16, 2, None),
        ("19.16 mm", Auto, 19.16, 2, None),
        ("  - 3.5mm ", Auto, -3.5, 1, None),
        ("42", Auto, 42.0, 0, None),
        (".5", Number, 0.5, 1, None),
    ];
    for &(line, format, mm, decimals, channel) in good {
        let r = parse_reading(line, format).unwrap_or_else(|e| panic!("{line:?}: {e}"));
        assert!((r.mm - mm).abs() < 1e-12, "{line:?}: {} ≠ {mm}", r.mm);
        assert_eq!((r.decimals, r.channel), (decimals, channel), "{line:?}");
    }
    let bad: &[(&str, Format)] = &[
        ("", Auto),
        ("   ", Auto),
        ("01A+0001?.345", Auto),
        ("01A00012.345", Auto),
        ("01A+", Auto),
        ("01A+12.3.4", Auto),
        ("01A++0012.345", Auto),
        ("01A+00012.345", Number),
        ("-12.345", Digimatic),
        ("FFFF4012345 30", Auto), // bad sign nibble
        ("FFFF0012345 70", Auto), // decimal point past 5
        ("FFFF0012345 39", Auto), // unknown unit
        ("FFFF00A2345 30", Digimatic),
        ("FFFF0021076540", Auto), // 14 nibbles is not a frame
        ("nan", Auto),
        ("inf", Auto),
        ("1e5", Auto),
        ("12,345", Auto),
        ("1,19.16", Auto), // a No,Z record is not a reading
        ("12.3.4", Auto),
        ("--1", Auto),
        ("\u{1}#@!", Auto),
        ("ERR", Auto),
    ];
    for &(line, format) in bad {
        assert!(parse_reading(line, format).is_err(), "{line:?} ({format:?}) should be rejected");
    }
}

/// Through the module's functions: cut by closing the instrument's end.
#[test]
fn disconnect_and_resume_lose_and_duplicate_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("ume.csv");

    // Session 1: points 1..=4, then the cable is pulled in the middle of a line.
    let mut p1 = pty();
    let port1 = p1.path.clone();
    let (tx, mut log) = Log::new();
    let a = args(&capture_words(&p1.path, &data, false).iter().map(String::as_str).collect::<Vec<_>>());
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
    assert!(msg.contains("restart the measuring program at point 5"), "{msg}");
    assert!(msg.contains("--resume"), "{msg}");
    let seen = log.drain().join("\n");
    eprintln!("session 1 messages:\n{seen}\nerror: {msg}");
    assert!(seen.contains("line ignored") && seen.contains("01A+0001?.345"), "{seen}");
    assert!(seen.contains("outside --range 0,50") && seen.contains("01A+00075.000"), "{seen}");
    assert_eq!(points(&data).len(), 4);

    // A crash while writing point 5: a truncated last line.
    std::fs::OpenOptions::new().append(true).open(&data).unwrap().write_all(b"5,-3").unwrap();

    // Without --resume the file is never overwritten.
    let a = args(&capture_words("/dev/null/none", &data, false).iter().map(String::as_str).collect::<Vec<_>>());
    let e = format!("{:#}", capture::run_with(&a, false, &mut |_| {}).unwrap_err());
    assert!(e.contains("exists") && e.contains("--resume"), "{e}");
    // With other options --resume refuses.
    let mut w = capture_words("/dev/null/none", &data, true);
    w[3] = "6,3".into();
    let a = args(&w.iter().map(String::as_str).collect::<Vec<_>>());
    let e = format!("{:#}", capture::run_with(&a, false, &mut |_| {}).unwrap_err());
    assert!(e.contains("other options") && e.contains("nx=6"), "{e}");

    // Session 2: a new instrument session from point 5, with a silence.
    let mut p2 = pty();
    let (tx, mut log) = Log::new();
    let a = args(&capture_words(&p2.path, &data, true).iter().map(String::as_str).collect::<Vec<_>>());
    let job = thread::spawn(move || capture::run_with(&a, false, &mut |m| tx.send(m.to_string()).unwrap()));
    log.wait_for("dropped an incomplete last line \"5,-3\"");
    log.wait_for("continuing with point 5");
    log.wait_for("waiting for readings");
    for no in 5..=NX * NY {
        if no == 9 {
            log.wait_for("no reading for");
        }
        p2.send(&plunge(no));
    }
    // Readings after the last point are not stored.
    p2.send("01A+00001.000\r");
    join(job).expect("capture completes");
    let eta = log.wait_for("predicted end");
    assert!(eta.starts_with("started 20") && eta.contains("; predicted end 20"), "{eta}");
    log.wait_for("capture complete: 15 points");
    eprintln!("session 2 messages:\n{}", log.drain().join("\n"));
    check_final(&data, &port1);

    // Resuming a complete file does nothing (and does not open the port).
    let a = args(&capture_words("/dev/null/none", &data, true).iter().map(String::as_str).collect::<Vec<_>>());
    capture::run_with(&a, false, &mut |_| {}).expect("complete");
    check_final(&data, &port1);
}

/// Joins a capture thread, failing instead of hanging.
fn join<T>(job: thread::JoinHandle<T>) -> T {
    let end = Instant::now() + Duration::from_secs(20);
    while !job.is_finished() {
        assert!(Instant::now() < end, "the capture did not end");
        thread::sleep(Duration::from_millis(10));
    }
    job.join().unwrap()
}

/// Waits for a kezuri process, killing it (and failing) after 20 s.
fn wait_child(child: &mut std::process::Child) -> std::process::ExitStatus {
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

fn kezuri() -> Command {
    Command::new(env!("CARGO_BIN_EXE_kezuri"))
}

/// Runs `kezuri probe capture WORDS`, its stderr lines into a channel.
fn spawn_capture(words: &[String]) -> (std::process::Child, Log) {
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
    log.wait_for("continuing with point 7");
    log.wait_for("waiting for readings");
    for no in 7..=10 {
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
    for no in 11..=NX * NY {
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
