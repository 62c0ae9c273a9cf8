//! A capture session: the bytes the instrument sends, made lines, the
//! lines made readings, and the readings made points, one per plunge.
//! The caller reads the port and the clock, stores the points and tells
//! the operator; the [`Session`] decides what each byte, silence and
//! reading means and what is to be done.
//!
//! Lines end with CR, LF or CR LF; blank lines are skipped. A line that is
//! not a whole, well-formed reading ([`parse_reading`]), a reading outside
//! the plausible range or from another multiplexer channel is reported
//! with its raw text and never becomes a point.
//!
//! Readings carry no point number, so a resumed session takes the last
//! stored point again first (the operator restarts the measuring program
//! there) and compares its Z with the stored one: a mismatch stops the
//! capture with nothing new stored. A line over [`MAX_LINE`] bytes is
//! ignored to its end, and so is the first line where the port never went
//! quiet as it opened (its start may have been lost). A long silence is
//! reported, again every `timeout`, and the capture keeps waiting.

use std::time::{Duration, SystemTime, UNIX_EPOCH};

use super::reading::{parse_reading, Format, Reading};
use super::Capture;
use crate::probe::data::num;

/// The longest line taken as a reading, bytes.
pub const MAX_LINE: usize = 256;

/// How readings are taken.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    /// The grid and how a reading becomes the tip Z.
    pub capture: Capture,
    /// The data file's name, for messages.
    pub name: String,
    /// Which line formats are readings.
    pub format: Format,
    /// Only readings of this multiplexer channel, where one is given.
    pub channel: Option<u32>,
    /// Plausible raw readings, mm; others are rejected.
    pub range: Option<(f64, f64)>,
    /// How far the last stored point measured again may be from its stored
    /// Z, mm.
    pub recheck_tol: f64,
    /// A silence longer than this is reported (again every `timeout`).
    pub timeout: Duration,
}

/// What the caller is to do, in order.
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    /// Tell the operator.
    Say(String),
    /// Store point `no` at tip Z `z`, on disk before anything more is done.
    Store {
        /// The point, from 1.
        no: usize,
        /// Its tip Z, mm.
        z: f64,
    },
    /// The first ten points of this session took `per` each, and `left`
    /// points are to come: the time to tell when the capture will end.
    Pace {
        /// Time per point.
        per: Duration,
        /// Points still to take.
        left: usize,
    },
    /// The last stored point measured again is not where it was: stop,
    /// nothing new stored. What went wrong, for the operator.
    Mismatch(String),
    /// Every point of the grid is stored: the capture is complete.
    Done,
}

/// A capture under way (see the module docs). Times are what the caller's
/// clock says since the readings began.
#[derive(Debug, Clone)]
pub struct Session {
    settings: Settings,
    /// The first point not stored, from 1.
    next: usize,
    /// On a resume, the last stored point and its Z, until it is measured
    /// again.
    check: Option<(usize, f64)>,
    /// The line so far.
    line: Vec<u8>,
    /// Ignoring bytes to the end of the line.
    skipping: bool,
    /// When bytes last came.
    last_data: Duration,
    /// Silences reported since.
    silences: u32,
    /// When the first ten points of this session were taken.
    taken: Vec<Duration>,
    /// Lines rejected in this session.
    rejected: usize,
}

impl Session {
    /// A session storing from point `stored + 1` on; `last`, the Z of
    /// point `stored`, is checked first where it is.
    pub fn new(settings: Settings, stored: usize, last: Option<f64>) -> Session {
        Session {
            settings,
            next: stored + 1,
            check: last.map(|z| (stored, z)),
            line: Vec::new(),
            skipping: false,
            last_data: Duration::ZERO,
            silences: 0,
            taken: Vec::new(),
            rejected: 0,
        }
    }

    /// The first point not stored, from 1.
    pub fn next(&self) -> usize {
        self.next
    }

    /// The point the next reading is for: on a resume, first the last
    /// stored point, measured again.
    pub fn point(&self) -> usize {
        self.check.map_or(self.next, |(no, _)| no)
    }

    /// What arrived as the port opened, until the line went `quiet` (or
    /// the wait gave up): `discarded` bytes, `sample` the first of them.
    /// Where it never went quiet the first line may be partial and is
    /// dropped. Returns what to tell the operator.
    pub fn settled(&mut self, quiet: bool, discarded: usize, sample: &[u8]) -> Vec<String> {
        let mut said = Vec::new();
        if discarded > 0 {
            said.push(format!(
                "discarded {discarded} byte(s) that were arriving as the port opened (sent while kezuri was \
                 stopped, or a line already begun): {:?}",
                String::from_utf8_lossy(sample)
            ));
        }
        self.skipping = !quiet;
        if self.skipping {
            said.push(
                "the instrument sends without a pause: its first line is dropped (set it to send one reading per \
                 trigger)"
                    .into(),
            );
        }
        said
    }

    /// `bytes` from the instrument at `now`: what to do. Nothing after
    /// [`Action::Mismatch`] or [`Action::Done`]; after an
    /// [`Action::Store`] that fails, the caller stops.
    pub fn bytes(&mut self, bytes: &[u8], now: Duration) -> Vec<Action> {
        self.last_data = now;
        self.silences = 0;
        let mut todo = Vec::new();
        for &b in bytes {
            if b != b'\r' && b != b'\n' {
                if self.skipping {
                    continue;
                }
                self.line.push(b);
                if self.line.len() > MAX_LINE {
                    let raw = String::from_utf8_lossy(&self.line).into_owned();
                    todo.push(Action::Say(format!(
                        "line ignored to its end (over {MAX_LINE} bytes without an end of line; wrong --baud?): \
                         {raw:?}"
                    )));
                    self.rejected += 1;
                    self.line.clear();
                    self.skipping = true;
                }
                continue;
            }
            self.skipping = false;
            let raw = String::from_utf8_lossy(&self.line).into_owned();
            self.line.clear();
            if raw.trim().is_empty() {
                continue;
            }
            let stop = self.line_of(&raw, now, &mut todo);
            if stop {
                break;
            }
        }
        todo
    }

    /// One whole line: what to do; `true` when the capture stops.
    fn line_of(&mut self, raw: &str, now: Duration, todo: &mut Vec<Action>) -> bool {
        let point = self.point();
        let reading = match self.accept(raw) {
            Ok(r) => r,
            Err((why, counts)) => {
                self.rejected += usize::from(counts);
                let hint = if counts && self.taken.is_empty() { " (check --baud and --format)" } else { "" };
                todo.push(Action::Say(format!("point {point}: {why}{hint}: {raw:?}")));
                return false;
            }
        };
        let (next, tol) = (self.next, self.settings.recheck_tol);
        let z = self.settings.capture.tip.tip_z(&reading);
        if let Some((no, was)) = self.check.take() {
            if (z - was).abs() > tol + 1e-9 {
                todo.push(Action::Mismatch(format!(
                    "point {no} measured again reads Z {z}, but {} holds Z {was} for it ({} mm apart, more than \
                     --recheck-tol {tol}): the measuring program did not restart at point {no}, or the part or the \
                     indicator moved; nothing new was stored.",
                    self.settings.name,
                    num((z - was).abs(), 6),
                )));
                return true;
            }
            todo.push(Action::Say(format!(
                "point {no} measured again: Z {z}, stored {was} (within --recheck-tol {tol}); point {next} is next"
            )));
            return false;
        }
        todo.push(Action::Store { no: next, z });
        let total = self.settings.capture.grid.len();
        if self.taken.len() < 10 {
            self.taken.push(now);
            if self.taken.len() == 10 && next < total {
                let per = (self.taken[9] - self.taken[0]) / 9;
                todo.push(Action::Pace { per, left: total - next });
            }
        }
        self.next += 1;
        if self.next > total {
            todo.push(Action::Done);
            return true;
        }
        false
    }

    /// The reading of one line, or why it is ignored (and whether that
    /// counts as a rejected line: another channel's reading does not).
    /// With `Format::Auto`, the first Mitutoyo record or Digimatic frame
    /// locks the format to those: a stray number between records (noise,
    /// a `7`) is then no reading and shifts no point.
    fn accept(&mut self, raw: &str) -> Result<Reading, (String, bool)> {
        let reading =
            parse_reading(raw, self.settings.format).map_err(|why| (format!("line ignored ({why})"), true))?;
        if self.settings.format == Format::Auto && parse_reading(raw, Format::Digimatic).is_ok() {
            self.settings.format = Format::Digimatic;
        }
        let s = &self.settings;
        if let (Some(want), Some(ch)) = (s.channel, reading.channel) {
            if want != ch {
                return Err((format!("reading from channel {ch} ignored (--channel {want})"), false));
            }
        }
        if let Some((lo, hi)) = s.range {
            if !(lo..=hi).contains(&reading.mm) {
                return Err((format!("reading {} mm ignored (outside --range {lo},{hi})", reading.mm), true));
            }
        }
        Ok(reading)
    }

    /// Nothing came by `now`: what to tell the operator (a silence of
    /// `timeout` is reported, and again every `timeout`; an incomplete
    /// line before it is ignored).
    pub fn quiet(&mut self, now: Duration) -> Vec<String> {
        let mut said = Vec::new();
        let silent = now.saturating_sub(self.last_data);
        if silent < self.settings.timeout * (self.silences + 1) {
            return said;
        }
        let point = self.point();
        self.silences += 1;
        self.skipping = false;
        if !self.line.is_empty() {
            let raw = String::from_utf8_lossy(&self.line).into_owned();
            said.push(format!("point {point}: incomplete line ignored after a silence: {raw:?}"));
            self.rejected += 1;
            self.line.clear();
        }
        let lost = if self.rejected > 0 {
            format!(
                "; {} line(s) were rejected in this session — if the measuring program has finished, a plunge's \
                 reading was lost and the points after it are shifted",
                self.rejected
            )
        } else {
            String::new()
        };
        said.push(format!(
            "no reading for {} (point {point} of {} is next); still waiting — check the machine and the cable{lost}",
            human(silent),
            self.settings.capture.grid.len()
        ));
        said
    }

    /// The instrument went away: what to tell the operator of a line it
    /// left incomplete.
    pub fn gone(&self) -> Option<String> {
        (!self.line.is_empty()).then(|| {
            let raw = String::from_utf8_lossy(&self.line);
            format!("point {}: incomplete line dropped at the disconnect: {raw:?}", self.point())
        })
    }
}

/// Where the operator restarts the measuring program to take point `next`
/// on: at the last stored point, which is measured again.
pub fn restart(next: usize) -> String {
    match next - 1 {
        0 => "restart the measuring program at point 1".into(),
        last => format!(
            "restart the measuring program at point {last} (measured again to check the restart; point {next} \
             follows)"
        ),
    }
}

/// A duration for the operator: `2h05m`, `3m07s`, `12.5 s`.
pub fn human(d: Duration) -> String {
    let s = d.as_secs();
    if s >= 3600 {
        format!("{}h{:02}m", s / 3600, s / 60 % 60)
    } else if s >= 60 {
        format!("{}m{:02}s", s / 60, s % 60)
    } else {
        format!("{:.1} s", d.as_secs_f64())
    }
}

/// `2026-11-23T19:45:00Z`.
pub fn utc_iso(t: SystemTime) -> String {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::probe::capture::TipZ;
    use crate::probe::{Grid, Order};

    fn session(stored: usize, last: Option<f64>) -> Session {
        let capture = Capture {
            grid: Grid { nx: 2, ny: 2, pitch: 1.0, origin: [0.0, 0.0], order: Order::ZigZag },
            tip: TipZ { bottom: -20.0, sign: -1, zero: 0.0 },
        };
        let settings = Settings {
            capture,
            name: "ume.csv".into(),
            format: Format::Auto,
            channel: None,
            range: Some((0.0, 50.0)),
            recheck_tol: 0.01,
            timeout: Duration::from_secs(60),
        };
        Session::new(settings, stored, last)
    }

    #[test]
    fn dates() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(20_513), (2026, 3, 1));
        assert_eq!(utc_iso(UNIX_EPOCH + Duration::from_secs(1_795_463_100)), "2026-11-23T19:45:00Z");
    }

    #[test]
    fn a_resume_checks_the_last_point_then_stores_to_the_end() {
        let mut s = session(2, Some(-32.5));
        assert_eq!((s.point(), s.next()), (2, 3));
        let t = Duration::from_secs(1);
        // A line in pieces, a rejected one and another channel's between.
        assert_eq!(s.bytes(b"01A+00", t), []);
        let todo = s.bytes(b"12.500\r01A+0075.000\r\n01A+0012.345\r01A+0012.", t);
        assert!(matches!(&todo[0], Action::Say(m) if m.starts_with("point 2 measured again: Z -32.5")), "{todo:?}");
        assert!(matches!(&todo[1], Action::Say(m) if m.contains("outside --range 0,50")), "{todo:?}");
        assert_eq!(todo[2], Action::Store { no: 3, z: -32.345 });
        assert_eq!(s.gone().unwrap(), "point 4: incomplete line dropped at the disconnect: \"01A+0012.\"");
        assert_eq!(s.bytes(b"000\r01A+0001.000\r", t)[..], [Action::Store { no: 4, z: -32.0 }, Action::Done]);
    }

    #[test]
    fn auto_locks_to_mitutoyo_records_once_it_has_seen_one() {
        let mut s = session(0, None);
        let t = Duration::from_secs(1);
        // A noise line `7` between two records is no point: the second
        // record is point 2, not point 3.
        let todo = s.bytes(b"01A+0012.345\r7\r01A+0012.000\r", t);
        assert_eq!(todo[0], Action::Store { no: 1, z: -32.345 });
        assert!(matches!(&todo[1], Action::Say(m) if m.starts_with("point 2: line ignored")), "{todo:?}");
        assert_eq!(todo[2], Action::Store { no: 2, z: -32.0 });
        // Before any record, a plain number is a reading.
        let mut s = session(0, None);
        assert_eq!(s.bytes(b"19.16\r", t)[..], [Action::Store { no: 1, z: -39.16 }]);
    }

    #[test]
    fn a_wrong_restart_and_silences_and_overlong_lines() {
        let mut s = session(2, Some(-32.5));
        let todo = s.bytes(b"01A+0013.000\r01A+0013.000\r", Duration::ZERO);
        assert!(matches!(&todo[..], [Action::Mismatch(m)] if m.contains("ume.csv holds Z -32.5")), "{todo:?}");
        let mut s = session(0, None);
        assert_eq!(s.bytes(&[b'x'; 300], Duration::ZERO).len(), 1);
        assert_eq!(s.quiet(Duration::from_secs(59)), Vec::<String>::new());
        let said = s.quiet(Duration::from_secs(60));
        assert!(said[0].starts_with("no reading for 1m00s (point 1 of 4 is next)") && said[0].contains("1 line(s)"));
        assert_eq!(s.quiet(Duration::from_secs(100)), Vec::<String>::new());
        assert_eq!(s.quiet(Duration::from_secs(120)).len(), 1);
    }
}
