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

use std::fmt::Write as _;
use std::fs::{File, OpenOptions};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use kezuri_cam::probe::data::grid_header;
use kezuri_cam::probe::{Grid, Order};

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
    parse_finite(s).and_then(|v| if v > 0.0 { Ok(v) } else { Err("the timeout must be > 0 s".into()) })
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

/// One indicator reading, in mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reading {
    /// The value in mm.
    pub mm: f64,
    /// Decimals the instrument gave (the result is rounded to them).
    pub decimals: u32,
    /// Multiplexer channel, for lines that carry one.
    pub channel: Option<u32>,
}

/// Parses one line (without its terminator) in `format`; `Err` says why it
/// is not a reading.
pub fn parse_reading(line: &str, format: Format) -> Result<Reading, String> {
    let t = line.trim_matches(|c: char| c.is_ascii_whitespace());
    if t.is_empty() {
        return Err("empty line".into());
    }
    let digimatic = || parse_mitutoyo(t).or_else(|| parse_nibbles(t));
    let number = || parse_number(t);
    let found = match format {
        Format::Digimatic => digimatic(),
        Format::Number => number(),
        Format::Auto => digimatic().or_else(number),
    };
    match found {
        Some(Ok(r)) => Ok(r),
        Some(Err(e)) => Err(e),
        None => Err(match format {
            Format::Auto => "not a Mitutoyo line, Digimatic frame or number".into(),
            Format::Digimatic => "not a Mitutoyo line (01A+00012.345) or Digimatic frame".into(),
            Format::Number => "not a number".into(),
        }),
    }
}

/// `[+-]digits[.digits]` with at least one digit: (value, decimals).
fn decimal(s: &str) -> Option<(f64, u32)> {
    let body = s.strip_prefix(['+', '-']).unwrap_or(s);
    let (int, frac) = body.split_once('.').unwrap_or((body, ""));
    let digits = |p: &str| p.bytes().all(|b| b.is_ascii_digit());
    if int.len() + frac.len() == 0 || !digits(int) || !digits(frac) || frac.len() > 12 {
        return None;
    }
    let v: f64 = s.parse().ok()?;
    v.is_finite().then_some((v, frac.len() as u32))
}

/// Mitutoyo multiplexer / USB line: `01A+00012.345`. `None` when the line
/// does not look like one at all, `Some(Err)` when it does but is damaged.
fn parse_mitutoyo(t: &str) -> Option<Result<Reading, String>> {
    let b = t.as_bytes();
    if b.len() < 4 || !b[0].is_ascii_digit() || !b[1].is_ascii_digit() || b[2] != b'A' {
        return None;
    }
    if b[3] != b'+' && b[3] != b'-' {
        return Some(Err("Mitutoyo line without a sign after the channel".into()));
    }
    let channel = u32::from(b[0] - b'0') * 10 + u32::from(b[1] - b'0');
    let data = &t[4..];
    if data.len() > 13 {
        return Some(Err("Mitutoyo line with too many digits".into()));
    }
    match decimal(data) {
        Some((v, decimals)) if !data.starts_with(['+', '-']) => {
            Some(Ok(Reading { mm: if b[3] == b'-' { -v } else { v }, decimals, channel: Some(channel) }))
        }
        _ => Some(Err("Mitutoyo line with a damaged value".into())),
    }
}

/// Digimatic frame as 13 hex nibbles `FFFF s dddddd p u` (spaces allowed).
fn parse_nibbles(t: &str) -> Option<Result<Reading, String>> {
    let n: Vec<u8> = t.bytes().filter(|b| *b != b' ').collect();
    if n.len() != 13 || !n[..4].iter().all(|b| b.eq_ignore_ascii_case(&b'F')) {
        return None;
    }
    let sign = match n[4] {
        b'0' => 1.0,
        b'8' => -1.0,
        _ => return Some(Err("Digimatic frame with a bad sign nibble".into())),
    };
    if !n[5..12].iter().all(u8::is_ascii_digit) || n[11] > b'5' {
        return Some(Err("Digimatic frame with a bad digit or decimal point".into()));
    }
    let digits: u64 = std::str::from_utf8(&n[5..11]).ok()?.parse().ok()?;
    let point = u32::from(n[11] - b'0');
    let value = sign * digits as f64 / 10f64.powi(point as i32);
    match n[12] {
        b'0' => Some(Ok(Reading { mm: value, decimals: point, channel: None })),
        b'1' => Some(Ok(Reading { mm: value * 25.4, decimals: point + 1, channel: None })),
        _ => Some(Err("Digimatic frame with an unknown unit nibble".into())),
    }
}

/// Plain number, optionally followed by `mm`.
fn parse_number(t: &str) -> Option<Result<Reading, String>> {
    let s = t.strip_suffix("mm").or_else(|| t.strip_suffix("MM")).unwrap_or(t).trim_end();
    let s = match s.as_bytes().first() {
        Some(b'+' | b'-') => format!("{}{}", &s[..1], s[1..].trim_start()),
        _ => s.to_string(),
    };
    decimal(&s).map(|(mm, decimals)| Ok(Reading { mm, decimals, channel: None }))
}

/// How a reading becomes the tip Z: `bottom + sign * (reading - zero)`.
#[derive(Debug, Clone, Copy)]
pub struct TipZ {
    /// Tip Z at the plunge bottom with the indicator at `zero`.
    pub bottom: f64,
    /// +1 or -1.
    pub sign: i32,
    /// Reading with the tip at `bottom`.
    pub zero: f64,
}

impl TipZ {
    /// The tip Z of a reading, rounded to the decimals of the reading,
    /// `bottom` and `zero` (so no binary noise like `-32.344999999999999`).
    pub fn tip_z(&self, r: &Reading) -> f64 {
        let z = self.bottom + f64::from(self.sign) * (r.mm - self.zero);
        let k = r.decimals.max(decimals_of(self.bottom)).max(decimals_of(self.zero));
        let rounded = if k <= 9 && z.abs() < 1e6 {
            let p = 10f64.powi(k as i32);
            (z * p).round() / p
        } else {
            z
        };
        if rounded == 0.0 {
            0.0
        } else {
            rounded
        }
    }
}

/// Decimals of the shortest round-trip form of `v`.
fn decimals_of(v: f64) -> u32 {
    let s = format!("{v}");
    s.find('.').map_or(0, |p| (s.len() - p - 1) as u32)
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

/// `2026-11-23T19:45:00Z`.
fn utc_iso(t: SystemTime) -> String {
    let secs = t.duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs()) as i64;
    let (y, m, d) = civil_from_days(secs.div_euclid(86_400));
    let s = secs.rem_euclid(86_400);
    format!("{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z", s / 3600, s / 60 % 60, s % 60)
}

/// Proleptic Gregorian date of a day count from 1970-01-01 (H. Hinnant's algorithm).
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    (yoe + era * 400 + i64::from(m <= 2), m, d)
}

/// Local wall-clock time for messages (`2026-11-24 05:58:10 +0900`); UTC
/// where the local zone is unknown.
fn local_time(t: SystemTime) -> String {
    #[cfg(unix)]
    {
        let secs = t.duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs()) as libc::time_t;
        // SAFETY: localtime_r writes only the `tm` we hand it.
        let mut tm: libc::tm = unsafe { std::mem::zeroed() };
        if !unsafe { libc::localtime_r(&secs, &mut tm) }.is_null() {
            let off = tm.tm_gmtoff / 60;
            let sign = if off < 0 { '-' } else { '+' };
            return format!(
                "{:04}-{:02}-{:02} {:02}:{:02}:{:02} {sign}{:02}{:02}",
                tm.tm_year + 1900,
                tm.tm_mon + 1,
                tm.tm_mday,
                tm.tm_hour,
                tm.tm_min,
                tm.tm_sec,
                off.abs() / 60,
                off.abs() % 60
            );
        }
    }
    utc_iso(t)
}

fn human(d: Duration) -> String {
    let s = d.as_secs();
    if s >= 3600 {
        format!("{}h{:02}m", s / 3600, s / 60 % 60)
    } else if s >= 60 {
        format!("{}m{:02}s", s / 60, s % 60)
    } else {
        format!("{:.1} s", d.as_secs_f64())
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

/// What one wait on the port gave.
enum Got {
    Data(usize),
    Quiet,
    Gone(String),
}

/// The serial port, read with a bounded wait.
struct Port {
    #[cfg(unix)]
    port: serialport::TTYPort,
    #[cfg(not(unix))]
    port: Box<dyn serialport::SerialPort>,
}

impl Port {
    fn open(path: &str, baud: u32) -> Result<Port> {
        let builder = serialport::new(path, baud)
            .data_bits(serialport::DataBits::Eight)
            .parity(serialport::Parity::None)
            .stop_bits(serialport::StopBits::One)
            .flow_control(serialport::FlowControl::None)
            .timeout(Duration::from_millis(200));
        #[cfg(unix)]
        {
            let port = builder.open_native().with_context(|| format!("cannot open serial port {path}"))?;
            // Non-blocking reads: a hang-up must never leave us blocked in read().
            use std::os::unix::io::AsRawFd;
            let fd = port.as_raw_fd();
            // SAFETY: fcntl on a descriptor we own.
            unsafe {
                let flags = libc::fcntl(fd, libc::F_GETFL);
                if flags >= 0 {
                    libc::fcntl(fd, libc::F_SETFL, flags | libc::O_NONBLOCK);
                }
            }
            Ok(Port { port })
        }
        #[cfg(not(unix))]
        {
            let port = builder.open().with_context(|| format!("cannot open serial port {path}"))?;
            Ok(Port { port })
        }
    }

    #[cfg(unix)]
    fn read(&mut self, buf: &mut [u8], wait: Duration) -> Got {
        use std::os::unix::io::AsRawFd;
        let fd = self.port.as_raw_fd();
        let mut pfd = libc::pollfd { fd, events: libc::POLLIN, revents: 0 };
        let ms = wait.as_millis().clamp(1, 60_000) as libc::c_int;
        // SAFETY: one valid pollfd.
        let r = unsafe { libc::poll(&mut pfd, 1, ms) };
        if r < 0 {
            let e = std::io::Error::last_os_error();
            return if e.kind() == std::io::ErrorKind::Interrupted { Got::Quiet } else { Got::Gone(e.to_string()) };
        }
        if r == 0 {
            return Got::Quiet;
        }
        // Readable, hung up or in error: read() tells which (data still
        // buffered is read before a hang-up is reported).
        // SAFETY: reading into a buffer we own, at most its length.
        let n = unsafe { libc::read(fd, buf.as_mut_ptr().cast(), buf.len()) };
        match n {
            n if n > 0 => Got::Data(n as usize),
            0 => Got::Gone("end of file".into()),
            _ => {
                let e = std::io::Error::last_os_error();
                let hung = pfd.revents & (libc::POLLHUP | libc::POLLERR | libc::POLLNVAL) != 0;
                match e.kind() {
                    std::io::ErrorKind::Interrupted => Got::Quiet,
                    std::io::ErrorKind::WouldBlock if !hung => Got::Quiet,
                    std::io::ErrorKind::WouldBlock => Got::Gone("hang-up".into()),
                    _ => Got::Gone(e.to_string()),
                }
            }
        }
    }

    #[cfg(not(unix))]
    fn read(&mut self, buf: &mut [u8], wait: Duration) -> Got {
        let _ = self.port.set_timeout(wait);
        match std::io::Read::read(&mut self.port, buf) {
            Ok(0) => Got::Gone("end of file".into()),
            Ok(n) => Got::Data(n),
            Err(e) if e.kind() == std::io::ErrorKind::TimedOut => Got::Quiet,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => Got::Quiet,
            Err(e) => Got::Gone(e.to_string()),
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(20_513), (2026, 3, 1));
        assert_eq!(utc_iso(UNIX_EPOCH + Duration::from_secs(1_795_463_100)), "2026-11-23T19:45:00Z");
    }

    #[test]
    fn tip_z_rounds_to_the_inputs_decimals() {
        let t = TipZ { bottom: -20.0, sign: -1, zero: 0.0 };
        let r = parse_reading("01A+00012.345", Format::Auto).unwrap();
        assert_eq!(t.tip_z(&r).to_string(), "-32.345");
        let t = TipZ { bottom: -70.5, sign: 1, zero: 0.01 };
        let r = parse_reading("19.16", Format::Auto).unwrap();
        assert_eq!(t.tip_z(&r).to_string(), "-51.35");
    }
}
