//! `kezuri probe capture`: read a dial indicator over a serial port, one
//! reading per plunge of the measuring program, into a `No,Z` data file
//! (seed 000: a Mitutoyo Digimatic indicator behind a MUX-10 multiplexer,
//! read by a PC over RS-232C at each plunge).
//!
//! # Data file
//!
//! ```text
//! # kezuri probe capture
//! # grid nx=85 ny=105 pitch=1 origin=0,0 pattern=zigzag
//! # tip_z = bottom + sign * (reading - zero): bottom=-20 sign=-1 zero=0
//! # port /dev/ttyUSB0 9600 baud, started 2026-11-23T19:45:00Z
//! No,Z
//! 1,-12.345
//! ```
//!
//! `No` counts from 1 in capture order, `Z` is the stylus tip Z in mm
//! (shortest round-trip float, rounded to the decimals of the reading,
//! `--bottom` and `--zero`, so `-20 - 12.345` is written `-32.345`). Every
//! point is appended in one write and fsync'd as it arrives, so a crash loses
//! at most the line being written; `--resume` drops such a truncated last line
//! and measures that point again.
//!
//! # Reading lines (sources)
//!
//! Lines end with CR, LF or CR LF; blank lines are skipped.
//! - Mitutoyo multiplexer / USB output (MUX-10 "Mux-10 format" as described
//!   in the GageMux operating manual, p. 7: `0CASRRRRRRRR<CR>`; Mitutoyo
//!   QM-Height manual No. 99MAF600B §6.3 "USB data output": D1 code `0`,
//!   D2 channel, D3 measurement item `A`, D4 sign, D5–D12 data with a
//!   floating decimal point, D13 CR), e.g. `01A+00012.345`, `01A-001.2340`,
//!   `01A+0000.123`. The two digits before `A` are taken as the channel.
//! - Digimatic raw frame written as its 13 hexadecimal nibbles d1…d13
//!   (Mitutoyo manuals No. 99MBA043A and 99MAF600B §6.2 "Digimatic data
//!   output"): `FFFF`, sign nibble (0 `+`, 8 `-`), six BCD digits, the
//!   decimal point position (0–5), the unit (0 mm, 1 inch; inch readings are
//!   converted to mm), e.g. `FFFF8012345 30` → −12.345 mm.
//! - A plain number, optionally signed and followed by `mm`: `-12.345`,
//!   `+19.16`, `19.16 mm` (what most USB cables and terminal-style interfaces
//!   send).
//!
//! A line in none of these forms is reported (with its raw text) and never
//! becomes a point, as are readings outside `--range` and readings from
//! another `--channel`. A long silence is reported and the capture keeps
//! waiting; a read error or end of file (cable pulled, converter unplugged)
//! ends the capture with the number of points stored and the command that
//! resumes it.

// By path, so that the test that compiles this file by path
// (tests/probe_capture.rs) finds them too.
#[path = "capture/clock.rs"]
mod clock;
#[path = "capture/port.rs"]
mod port;
#[path = "capture/reading.rs"]
mod reading;

use std::fmt::Write as _;
use std::fs::{File, OpenOptions};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime};

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use kezuri_cam::probe::data::grid_header;
use kezuri_cam::probe::{Grid, Order};

use clock::{human, local_time, utc_iso};
use port::{Got, Port};
pub use reading::{parse_reading, TipZ};

/// Reads one dial-indicator value per plunge from a serial port into a `No,Z` data file.
#[derive(Args, Debug, Clone)]
#[command(after_help = "\
How a reading becomes the tip Z (recorded in the file's header):
  tip_z = bottom + sign * (reading - zero)
  bottom: machine Z of the stylus tip at the bottom of the plunge with the indicator
          showing `zero`; sign: +1 when the reading grows as the stylus is pushed in
          (Mitutoyo indicators), -1 otherwise. The defaults (0, +1, 0) store the raw reading.

Accepted lines: Mitutoyo multiplexer/USB `01A+00012.345` (channel, item A, sign, value),
Digimatic raw nibbles `FFFF0012345 30` (13 hex digits), plain numbers `-12.345`, `19.16 mm`.
Garbled lines, values outside --range and long silences are reported on stderr and never
stored. Every point is fsync'd as it arrives; after a disconnect, --resume continues after
the last stored point (restart the measuring program at the point it names).

Examples:
  kezuri probe capture --port /dev/ttyUSB0 --count 85,105 -o ume.csv
  kezuri probe capture --port /dev/ttyUSB0 --baud 9600 --count 85,105 --pitch 1 \\
      --bottom -70 --sign 1 --zero 0 --range 0,50 -o ume.csv
  kezuri probe capture --port /dev/ttyUSB0 --count 85,105 --bottom -70 -o ume.csv --resume")]
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
    /// Data file to write (or, with --resume, to continue).
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
    /// Accept only readings from this multiplexer channel (Mitutoyo lines carry one).
    #[arg(long, value_name = "N")]
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
    /// Mitutoyo multiplexer/USB lines (`01A+00012.345`) and raw Digimatic nibbles.
    Digimatic,
    /// Plain numbers (`-12.345`, `19.16 mm`).
    Number,
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

fn parse_pitch(s: &str) -> Result<f64, String> {
    parse_finite(s).and_then(|v| if v > 0.0 { Ok(v) } else { Err("the pitch must be > 0".into()) })
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

    fn tip(&self) -> TipZ {
        TipZ { bottom: self.bottom, sign: self.sign, zero: self.zero }
    }

    /// The header lines that must match on `--resume` (grid and tip Z).
    fn header_fixed(&self) -> [String; 3] {
        [
            "# kezuri probe capture".to_string(),
            grid_header(&Grid {
                nx: self.count.0,
                ny: self.count.1,
                pitch: self.pitch,
                origin: [self.origin.0, self.origin.1],
                order: self.pattern.into(),
            }),
            format!(
                "# tip_z = bottom + sign * (reading - zero): bottom={} sign={} zero={}",
                self.bottom, self.sign, self.zero
            ),
        ]
    }

    /// The whole header of a new file.
    fn header(&self, started: SystemTime) -> String {
        let mut h = self.header_fixed().join("\n");
        let _ = write!(h, "\n# port {} {} baud, started {}\nNo,Z\n", self.port, self.baud, utc_iso(started));
        h
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
        let _ = write!(c, " --timeout {} -o {} --resume", self.timeout, quote(&self.output.display().to_string()));
        c
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

/// Opens DATA for appending: a new file with its header, or (`--resume`)
/// the existing one after checking its header and dropping a truncated last
/// line. Returns the file and the number of points already stored.
fn open_data(args: &CaptureArgs, say: &mut dyn FnMut(&str)) -> Result<(File, usize)> {
    let path = &args.output;
    if path.as_os_str() == "-" {
        bail!("probe capture writes a file (-o DATA), not standard output");
    }
    if !args.resume || !path.exists() {
        let mut f = OpenOptions::new().append(true).create_new(true).open(path).map_err(|e| {
            if e.kind() == std::io::ErrorKind::AlreadyExists {
                anyhow::anyhow!(
                    "{} exists: add --resume to continue that capture, or choose another file",
                    path.display()
                )
            } else {
                anyhow::Error::new(e).context(format!("cannot create {}", path.display()))
            }
        })?;
        f.write_all(args.header(SystemTime::now()).as_bytes())
            .and_then(|_| f.sync_all())
            .with_context(|| format!("cannot write {}", path.display()))?;
        sync_dir(path);
        return Ok((f, 0));
    }
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    let complete = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |p| p + 1);
    let text = String::from_utf8_lossy(&bytes[..complete]);
    let name = path.display();
    let lines: Vec<&str> = text.lines().collect();
    let want = args.header_fixed();
    for (i, w) in want.iter().enumerate() {
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
    let mut stored = 0usize;
    for (i, l) in lines.iter().enumerate().skip(table + 1) {
        let bad = || anyhow::anyhow!("{name}:{}: not point {} as `No,Z`: {l:?}", i + 1, stored + 1);
        let (no, z) = l.trim_end().split_once(',').ok_or_else(bad)?;
        if no.parse::<usize>().ok() != Some(stored + 1) || !z.parse::<f64>().is_ok_and(f64::is_finite) {
            return Err(bad());
        }
        stored += 1;
    }
    if stored > args.total() {
        bail!("{name} holds {stored} points, more than the {} of the grid", args.total());
    }
    if complete < bytes.len() {
        let tail = String::from_utf8_lossy(&bytes[complete..]).into_owned();
        say(&format!(
            "{name}: dropped an incomplete last line {tail:?} (the capture stopped while writing it); \
             point {} will be measured again",
            stored + 1
        ));
    }
    let f = OpenOptions::new().write(true).open(path).with_context(|| format!("cannot open {name}"))?;
    f.set_len(complete as u64).and_then(|_| f.sync_all()).with_context(|| format!("cannot truncate {name}"))?;
    drop(f);
    let f = OpenOptions::new().append(true).open(path).with_context(|| format!("cannot open {name}"))?;
    Ok((f, stored))
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

/// Runs `kezuri probe capture`, messages on stderr.
pub fn run(args: &CaptureArgs) -> Result<()> {
    let bar = std::io::stderr().is_terminal();
    run_with(args, bar, &mut |m| eprintln!("{m}"))
}

/// The capture, with every message passed to `log` (one message a call)
/// and a progress bar on stderr when `bar`.
pub fn run_with(args: &CaptureArgs, bar: bool, log: &mut dyn FnMut(&str)) -> Result<()> {
    let total = args.total();
    let name = args.output.display().to_string();
    let (mut file, stored) = open_data(args, log)?;
    if stored == total {
        log(&format!("{name} already holds all {total} points; nothing to capture"));
        return Ok(());
    }
    let mut port = Port::open(&args.port, args.baud)?;
    let started = SystemTime::now();
    let mut out = Out { log, bar: None };
    if stored > 0 {
        out.say(&format!("{name}: {stored} of {total} points stored; continuing with point {}", stored + 1));
    }
    out.say(&format!(
        "capture: {total} points ({}×{}) to {name}; waiting for readings on {} at {} baud (point {} is next)",
        args.count.0,
        args.count.1,
        args.port,
        args.baud,
        stored + 1
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

    let tip = args.tip();
    let timeout = Duration::from_secs_f64(args.timeout);
    let mut next = stored + 1;
    let mut line: Vec<u8> = Vec::new();
    let mut buf = [0u8; 512];
    let mut last_data = Instant::now();
    let mut silences = 0u32;
    let mut session: Vec<Instant> = Vec::new();
    let mut rejected = 0usize;
    const MAX_LINE: usize = 256;

    let result = 'capture: loop {
        match port.read(&mut buf, Duration::from_millis(200)) {
            Got::Data(n) => {
                last_data = Instant::now();
                silences = 0;
                for &b in &buf[..n] {
                    if b != b'\r' && b != b'\n' {
                        line.push(b);
                        if line.len() > MAX_LINE {
                            let raw = String::from_utf8_lossy(&line).into_owned();
                            out.say(&format!(
                                "line ignored (over {MAX_LINE} bytes without an end of line; wrong --baud?): {raw:?}"
                            ));
                            rejected += 1;
                            line.clear();
                        }
                        continue;
                    }
                    let raw = String::from_utf8_lossy(&line).into_owned();
                    line.clear();
                    if raw.trim().is_empty() {
                        continue;
                    }
                    let reading = match parse_reading(&raw, args.format) {
                        Ok(r) => r,
                        Err(why) => {
                            rejected += 1;
                            let hint = if session.is_empty() { " (check --baud and --format)" } else { "" };
                            out.say(&format!("point {next}: line ignored ({why}){hint}: {raw:?}"));
                            continue;
                        }
                    };
                    if let (Some(want), Some(ch)) = (args.channel, reading.channel) {
                        if want != ch {
                            out.say(&format!(
                                "point {next}: reading from channel {ch} ignored (--channel {want}): {raw:?}"
                            ));
                            continue;
                        }
                    }
                    if let Some((lo, hi)) = args.range {
                        if !(lo..=hi).contains(&reading.mm) {
                            rejected += 1;
                            out.say(&format!(
                                "point {next}: reading {} mm ignored (outside --range {lo},{hi}): {raw:?}",
                                reading.mm
                            ));
                            continue;
                        }
                    }
                    let z = tip.tip_z(&reading);
                    let record = format!("{next},{z}\n");
                    if let Err(e) = file.write_all(record.as_bytes()).and_then(|_| file.sync_data()) {
                        break 'capture Err(anyhow::Error::new(e).context(format!(
                            "cannot write point {next} to {name}; {} of {total} points are stored — \
                             free the disk, then resume with:\n  {}",
                            next - 1,
                            args.resume_command()
                        )));
                    }
                    session.push(Instant::now());
                    if let Some(b) = &out.bar {
                        b.set_position(next as u64);
                    }
                    if session.len() == 10 && next < total {
                        let per = (session[9] - session[0]) / 9;
                        let left = (total - next) as u32;
                        let end = SystemTime::now() + per * left;
                        out.say(&format!(
                            "started {}; {:.2} s per point over the first 10; predicted end {} ({} for {left} points)",
                            local_time(started),
                            per.as_secs_f64(),
                            local_time(end),
                            human(per * left)
                        ));
                    }
                    next += 1;
                    if next > total {
                        break 'capture Ok(());
                    }
                }
            }
            Got::Quiet => {
                if last_data.elapsed() >= timeout * (silences + 1) {
                    silences += 1;
                    if !line.is_empty() {
                        let raw = String::from_utf8_lossy(&line).into_owned();
                        out.say(&format!("point {next}: incomplete line ignored after a silence: {raw:?}"));
                        rejected += 1;
                        line.clear();
                    }
                    let lost = if rejected > 0 {
                        format!(
                            "; {rejected} line(s) were rejected in this session — if the measuring program \
                             has finished, a plunge's reading was lost and the points after it are shifted"
                        )
                    } else {
                        String::new()
                    };
                    out.say(&format!(
                        "no reading for {} (point {next} of {total} is next); still waiting — check the \
                         machine and the cable{lost}",
                        human(last_data.elapsed())
                    ));
                }
            }
            Got::Gone(why) => {
                if !line.is_empty() {
                    let raw = String::from_utf8_lossy(&line).into_owned();
                    out.say(&format!("point {next}: incomplete line dropped at the disconnect: {raw:?}"));
                }
                break 'capture Err(anyhow::anyhow!(
                    "the instrument went away ({why} on {}): {} of {total} points are stored in {name}.\n\
                     To continue, restart the measuring program at point {next} and run:\n  {}",
                    args.port,
                    next - 1,
                    args.resume_command()
                ));
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
