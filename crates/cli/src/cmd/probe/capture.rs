//! `kezuri probe capture`: read a dial indicator over a serial port, one
//! reading per plunge of the measuring program (the machine's M07 at the
//! bottom of each plunge triggers it), into a `No,Z` data file. The user's
//! page is docs/capture.md.
//!
//! The rules are `kezuri_cam::probe::capture`'s: the data file and what is
//! written when (`DataFile`), the reading formats (`parse_reading`) and the
//! session (`Session`: what each byte, silence and reading means, and the
//! check of the last stored point on `--resume`). Here are the serial port
//! (its input flushed on open, and what arrives until the line has been
//! quiet for `SETTLE` discarded: a reading sent while kezuri was stopped,
//! or the tail of one under way), the clock, the data file on disk
//! (`store`: created with its first point, locked while a capture writes
//! it, every point fsync'd before the next is taken) and the terminal. A
//! read error or end of file (cable pulled, converter unplugged) ends the
//! capture with the number of points stored and the command that resumes
//! it.

// By path, so that the test that compiles this file by path
// (tests/probe_capture.rs) finds them too.
#[path = "capture/clock.rs"]
mod clock;
#[path = "capture/port.rs"]
mod port;
#[path = "capture/store.rs"]
mod store;

use std::fmt::Write as _;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::{Duration, Instant, SystemTime};

use anyhow::Result;
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use kezuri_cam::probe::capture::{self, human, restart, utc_iso, Action, Capture, Session, Settings, TipZ};
use kezuri_cam::probe::{Grid, Order};

use clock::local_time;
use port::{Got, Port};
use store::Store;

/// How long the line must be quiet after the port is opened before a
/// reading is taken: what arrives before is discarded, as a line already
/// under way when the port opened is only its tail.
const SETTLE: Duration = Duration::from_millis(300);

/// Reads one dial-indicator value per plunge from a serial port into a `No,Z` data file.
#[derive(Args, Debug, Clone)]
#[command(after_help = "\
How a reading becomes the tip Z (recorded in the file's header):
  tip_z = bottom + sign * (reading - zero)
  bottom: machine Z of the stylus tip at the bottom of the plunge with the indicator
          showing `zero`; sign: +1 when the reading grows as the stylus is pushed in
          (Mitutoyo indicators), -1 otherwise. The defaults (0, +1, 0) store the raw reading.

Accepted lines: Mitutoyo multiplexer/USB records `01A+0012.345` (channel, A, sign, then
exactly 8 characters: 7 digits and a decimal point), Digimatic raw nibbles `FFFF0012345 30`
(13 hex digits), plain numbers `-12.345`, `19.16 mm`. Damaged records, over-long lines,
values outside --range and long silences are reported on stderr and never stored.

Interruptions: what the instrument sent while kezuri was stopped is discarded when the port
opens. Every point is on disk before the next is taken; the data file exists from the first
point on, and two captures cannot write one file. After a stop, --resume names the point to
restart the measuring program at: the last stored point, measured again and compared with the
stored Z (--recheck-tol) before new points are taken; on a mismatch nothing new is stored.
A last record cut off by a power loss is dropped and taken again.

Examples (the indicator on a serial port; not run without one):
  kezuri probe capture --port /dev/ttyUSB0 --count 85,105 -o ume.csv
  kezuri probe capture --port /dev/ttyUSB0 --baud 9600 --count 85,105 \\
      --pitch 1 --bottom -70 --sign 1 --zero 0 --range 0,50 -o ume.csv
  kezuri probe capture --port /dev/ttyUSB0 --count 85,105 --bottom -70 \\
      -o ume.csv --resume")]
pub struct CaptureArgs {
    /// Serial port of the indicator interface (e.g. /dev/ttyUSB0, COM3).
    #[arg(long, value_name = "DEV")]
    pub port: String,
    /// Baud rate (8 data bits, no parity, 1 stop bit).
    #[arg(long, value_name = "B", default_value_t = 9600)]
    pub baud: u32,
    /// Grid points along X (per row) and along Y (rows); the capture stops after NX·NY points.
    #[arg(long, value_name = "NX,NY", value_parser = parse_count)]
    pub count: (usize, usize),
    /// Data file to write (or, with --resume, to continue). A file, not standard output: every
    /// point is on disk before the next is taken, and --resume continues the file.
    #[arg(short = 'o', long = "output", value_name = "DATA")]
    pub output: PathBuf,
    /// Continue an interrupted capture: check that DATA's header matches these options and
    /// append after its last complete point (a missing DATA starts a new capture).
    #[arg(long)]
    pub resume: bool,
    /// Grid pitch in mm (recorded in the header).
    #[arg(long, value_name = "P", default_value_t = 1.0, value_parser = parse_pitch)]
    pub pitch: f64,
    /// Grid origin in mm (recorded in the header).
    #[arg(long, value_name = "X,Y", default_value = "0,0", value_parser = parse_pair, allow_hyphen_values = true)]
    pub origin: (f64, f64),
    /// Order of the points (recorded in the header): zigzag reverses every other row.
    #[arg(long, value_enum, default_value_t = Pattern::Zigzag)]
    pub pattern: Pattern,
    /// Which reading lines to accept.
    #[arg(long, value_enum, default_value_t = Format::Auto)]
    pub format: Format,
    /// Accept only readings from this multiplexer channel, 0 to 99 (Mitutoyo lines carry
    /// it in two digits).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(0..=99))]
    pub channel: Option<u32>,
    /// Tip Z (mm) at the bottom of the plunge when the indicator reads `--zero`.
    #[arg(long, value_name = "Z", default_value_t = 0.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub bottom: f64,
    /// +1 when the reading grows as the stylus is pushed in (tip higher), -1 otherwise.
    #[arg(long, value_name = "1|-1", default_value_t = 1, value_parser = parse_sign, allow_hyphen_values = true)]
    pub sign: i32,
    /// Indicator reading (mm) with the tip at --bottom.
    #[arg(long, value_name = "R", default_value_t = 0.0, value_parser = parse_finite, allow_hyphen_values = true)]
    pub zero: f64,
    /// Plausible raw readings in mm (e.g. 0,50 for a 50 mm indicator); others are rejected.
    #[arg(long, value_name = "MIN,MAX", value_parser = parse_range, allow_hyphen_values = true)]
    pub range: Option<(f64, f64)>,
    /// On --resume the last stored point is measured again first (restart the measuring program
    /// there): its Z must agree with the stored one within this many mm (the indicator's
    /// accuracy), or the capture stops and stores nothing new.
    #[arg(long, value_name = "MM", default_value_t = 0.01, value_parser = parse_tolerance)]
    pub recheck_tol: f64,
    /// Report a silence longer than S seconds (again every S seconds) while waiting.
    #[arg(long, value_name = "S", default_value_t = 60.0, value_parser = parse_timeout)]
    pub timeout: f64,
}

/// The order of the grid points.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pattern {
    /// Rows alternate direction.
    Zigzag,
    /// Every row runs the same way.
    Oneway,
}

impl From<Pattern> for Order {
    fn from(p: Pattern) -> Order {
        match p {
            Pattern::Zigzag => Order::ZigZag,
            Pattern::Oneway => Order::OneWay,
        }
    }
}

/// Which line formats the capture accepts.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Any of the formats below.
    Auto,
    /// Mitutoyo multiplexer/USB records (`01A+0012.345`) and raw Digimatic nibbles.
    Digimatic,
    /// Plain numbers (`-12.345`, `19.16 mm`).
    Number,
}

impl From<Format> for capture::Format {
    fn from(f: Format) -> capture::Format {
        match f {
            Format::Auto => capture::Format::Auto,
            Format::Digimatic => capture::Format::Digimatic,
            Format::Number => capture::Format::Number,
        }
    }
}

impl Format {
    fn name(self) -> &'static str {
        match self {
            Format::Auto => "auto",
            Format::Digimatic => "digimatic",
            Format::Number => "number",
        }
    }
}

fn parse_count(s: &str) -> Result<(usize, usize), String> {
    let (a, b) = s.split_once(',').ok_or("expected NX,NY (e.g. 85,105)")?;
    let n = |t: &str| t.trim().parse::<usize>().ok().filter(|&v| v > 0).ok_or(format!("`{t}` is not a count ≥ 1"));
    let (nx, ny) = (n(a)?, n(b)?);
    nx.checked_mul(ny).filter(|&t| t <= 100_000_000).ok_or("too many points (at most 100 million)")?;
    Ok((nx, ny))
}

fn parse_finite(s: &str) -> Result<f64, String> {
    s.trim().parse::<f64>().ok().filter(|v| v.is_finite()).ok_or(format!("`{s}` is not a finite number"))
}

/// A pitch is a length (this file stands alone in its tests: the
/// shared parsers of `numbers.rs` are not here).
fn parse_pitch(s: &str) -> Result<f64, String> {
    parse_finite(s).and_then(|v| kezuri_geom::limits::length(v, "it"))
}

fn parse_timeout(s: &str) -> Result<f64, String> {
    parse_finite(s).and_then(|v| {
        if v > 0.0 && v <= 86_400.0 {
            Ok(v)
        } else {
            Err(format!("the timeout must be more than 0 s and at most 86400 s (a day), got {v}"))
        }
    })
}

fn parse_tolerance(s: &str) -> Result<f64, String> {
    parse_finite(s).and_then(|v| if v >= 0.0 { Ok(v) } else { Err("the tolerance must be ≥ 0 mm".into()) })
}

fn parse_pair(s: &str) -> Result<(f64, f64), String> {
    let (a, b) = s.split_once(',').ok_or("expected two numbers: A,B")?;
    Ok((parse_finite(a)?, parse_finite(b)?))
}

fn parse_range(s: &str) -> Result<(f64, f64), String> {
    let (lo, hi) = parse_pair(s)?;
    if lo < hi {
        Ok((lo, hi))
    } else {
        Err(format!("MIN must be below MAX, got {lo},{hi}"))
    }
}

fn parse_sign(s: &str) -> Result<i32, String> {
    match s.trim() {
        "1" | "+1" => Ok(1),
        "-1" => Ok(-1),
        _ => Err(format!("the sign is 1 or -1, not `{s}`")),
    }
}

impl CaptureArgs {
    fn total(&self) -> usize {
        self.count.0 * self.count.1
    }

    /// What the data file records of this capture.
    fn capture(&self) -> Capture {
        Capture {
            grid: Grid {
                nx: self.count.0,
                ny: self.count.1,
                pitch: self.pitch,
                origin: [self.origin.0, self.origin.1],
                order: self.pattern.into(),
            },
            tip: TipZ { bottom: self.bottom, sign: self.sign, zero: self.zero },
        }
    }

    /// The whole header of a new file.
    fn header(&self, started: SystemTime) -> String {
        self.capture().header(&self.port, self.baud, &utc_iso(started))
    }

    /// The command that continues this capture.
    fn resume_command(&self) -> String {
        let mut c = format!(
            "kezuri probe capture --port {} --baud {} --count {},{} --pitch {} --origin {},{} --pattern {} --format {}",
            quote(&self.port),
            self.baud,
            self.count.0,
            self.count.1,
            self.pitch,
            self.origin.0,
            self.origin.1,
            Order::from(self.pattern).name(),
            self.format.name()
        );
        if let Some(ch) = self.channel {
            let _ = write!(c, " --channel {ch}");
        }
        let _ = write!(c, " --bottom {} --sign {} --zero {}", self.bottom, self.sign, self.zero);
        if let Some((lo, hi)) = self.range {
            let _ = write!(c, " --range {lo},{hi}");
        }
        let _ = write!(
            c,
            " --recheck-tol {} --timeout {} -o {} --resume",
            self.recheck_tol,
            self.timeout,
            quote(&self.output.display().to_string())
        );
        c
    }

    /// The error when the instrument goes away with point `next` to take.
    fn gone(&self, why: &str, next: usize) -> anyhow::Error {
        anyhow::anyhow!(
            "the instrument went away ({why} on {}): {} of {} points are stored in {}.\n\
             To continue, {} and run:\n  {}",
            self.port,
            next - 1,
            self.total(),
            self.output.display(),
            restart(next),
            self.resume_command()
        )
    }

    /// How the session takes readings.
    fn settings(&self) -> Settings {
        Settings {
            capture: self.capture(),
            name: self.output.display().to_string(),
            format: self.format.into(),
            channel: self.channel,
            range: self.range,
            recheck_tol: self.recheck_tol,
            timeout: Duration::from_secs_f64(self.timeout),
        }
    }
}

/// Quotes a word for a POSIX shell when it needs it.
fn quote(s: &str) -> String {
    if !s.is_empty() && s.bytes().all(|b| b.is_ascii_alphanumeric() || b"/._-:,+=@".contains(&b)) {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', r"'\''"))
    }
}

/// Messages go through `log`, above the progress bar when there is one.
struct Out<'a> {
    log: &'a mut dyn FnMut(&str),
    bar: Option<ProgressBar>,
}

impl Out<'_> {
    fn say(&mut self, msg: &str) {
        match &self.bar {
            Some(bar) => bar.suspend(|| (self.log)(msg)),
            None => (self.log)(msg),
        }
    }
}

/// Runs `kezuri probe capture`, messages on stderr, a progress bar on a
/// terminal unless `quiet`.
pub fn run(args: &CaptureArgs, quiet: bool) -> Result<()> {
    let bar = std::io::stderr().is_terminal() && !quiet;
    run_with(args, bar, &mut |m| eprintln!("{m}"))
}

/// The capture, with every message passed to `log` (one message a call)
/// and a progress bar on stderr when `bar`.
pub fn run_with(args: &CaptureArgs, bar: bool, log: &mut dyn FnMut(&str)) -> Result<()> {
    let total = args.total();
    let name = args.output.display().to_string();
    let mut store = Store::open(args, log)?;
    let stored = store.data.stored;
    if stored == total {
        log(&format!("{name} already holds all {total} points; nothing to capture"));
        return Ok(());
    }
    let mut port = Port::open(&args.port, args.baud)?;
    let started = SystemTime::now();
    let mut out = Out { log, bar: None };
    let mut session = Session::new(args.settings(), stored, store.data.last);
    if stored > 0 {
        out.say(&format!("{name}: {stored} of {total} points stored; {}", restart(stored + 1)));
    }
    let timeout = Duration::from_secs_f64(args.timeout);
    let settled =
        port.settle(SETTLE, timeout.max(Duration::from_secs(1))).map_err(|why| args.gone(&why, stored + 1))?;
    for said in session.settled(settled.quiet, settled.discarded, &settled.sample) {
        out.say(&said);
    }
    out.say(&format!(
        "capture: {total} points ({}×{}) to {name}; waiting for readings on {} at {} baud (point {} is next)",
        args.count.0,
        args.count.1,
        args.port,
        args.baud,
        session.point()
    ));
    if bar && total - stored > 1 {
        let b = ProgressBar::new(total as u64);
        b.set_style(
            ProgressStyle::with_template("capture {bar:40} {pos}/{len} points, {eta} left")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        b.set_position(stored as u64);
        out.bar = Some(b);
    }

    let mut buf = [0u8; 512];
    let t0 = Instant::now();
    let result = 'capture: loop {
        match port.read(&mut buf, Duration::from_millis(200)) {
            Got::Data(n) => {
                for action in session.bytes(&buf[..n], t0.elapsed()) {
                    match action {
                        Action::Say(said) => out.say(&said),
                        Action::Store { no, z } => {
                            if let Err(e) = store.append(no, z) {
                                break 'capture Err(e.context(format!(
                                    "{} of {total} points are stored — free the disk; to continue, {} and run:\n  {}",
                                    no - 1,
                                    restart(no),
                                    args.resume_command()
                                )));
                            }
                            if let Some(b) = &out.bar {
                                b.set_position(no as u64);
                            }
                        }
                        Action::Pace { per, left } => {
                            let end = SystemTime::now() + per * left as u32;
                            out.say(&format!(
                                "started {}; {:.2} s per point over the first 10; predicted end {} ({} for {left} \
                                 points)",
                                local_time(started),
                                per.as_secs_f64(),
                                local_time(end),
                                human(per * left as u32)
                            ));
                        }
                        Action::Mismatch(what) => {
                            break 'capture Err(anyhow::anyhow!(
                                "{what}\nTo continue, {} and run:\n  {}",
                                restart(session.next()),
                                args.resume_command()
                            ))
                        }
                        Action::Done => break 'capture Ok(()),
                    }
                }
            }
            Got::Quiet => {
                for said in session.quiet(t0.elapsed()) {
                    out.say(&said);
                }
            }
            Got::Gone(why) => {
                if let Some(said) = session.gone() {
                    out.say(&said);
                }
                break 'capture Err(args.gone(&why, session.next()));
            }
        }
    };
    if let Some(b) = out.bar.take() {
        b.finish_and_clear();
    }
    result?;
    (out.log)(&format!("capture complete: {total} points in {name}"));
    Ok(())
}
