//! A dial-indicator capture (`kezuri probe capture`): the lines an
//! indicator sends read as readings ([`parse_reading`]), a reading made the
//! tip Z ([`TipZ`]), the session that makes the bytes from the instrument
//! points and decides what to do at each ([`Session`]), and the rules of
//! the `No,Z` data file the points go to ([`DataFile`]). The serial port,
//! the clock and the file itself are the caller's: this module works on
//! strings, bytes, time values and [`Write`] values.
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
//! `No` counts from 1 in capture order, `Z` is the stylus tip Z in mm. The
//! header is written with the first point (a capture that stops before one
//! leaves no file), and every point is one record written at once. A capture
//! resumed on a file must have the same first three header lines; a last
//! record cut off by a crash or a power loss (no end of line) is dropped.

mod reading;
mod session;

use std::io::{self, Write};

pub use reading::{parse_reading, Format, Reading, TipZ};
pub use session::{human, restart, utc_iso, Action, Session, Settings, MAX_LINE};

use super::data::grid_header;
use super::Grid;
use crate::error::{Error, ErrorKind};

/// What a capture's data file records of it: the grid and how a reading
/// becomes the tip Z, which a resumed capture must share.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Capture {
    /// The grid the points are measured on.
    pub grid: Grid,
    /// How a reading becomes the tip Z.
    pub tip: TipZ,
}

impl Capture {
    /// The header lines that must match on a resume (grid and tip Z).
    pub fn fixed_header(&self) -> [String; 3] {
        [
            "# kezuri probe capture".to_string(),
            grid_header(&self.grid),
            format!(
                "# tip_z = bottom + sign * (reading - zero): bottom={} sign={} zero={}",
                self.tip.bottom, self.tip.sign, self.tip.zero
            ),
        ]
    }

    /// The whole header of a new file: the fixed lines, the port the
    /// readings come from at `baud` and when the capture `started`, and the
    /// `No,Z` line.
    pub fn header(&self, port: &str, baud: u32, started: &str) -> String {
        format!("{}\n# port {port} {baud} baud, started {started}\nNo,Z\n", self.fixed_header().join("\n"))
    }

    /// Checks the complete lines of a data file `name` against this
    /// capture: the number of points stored and the Z of the last.
    fn check(&self, text: &str, name: &str) -> Result<(usize, Option<f64>), Error> {
        let fail = |message: String| Err(Error::new(ErrorKind::Capture, message));
        let lines: Vec<&str> = text.lines().collect();
        for (i, w) in self.fixed_header().iter().enumerate() {
            match lines.get(i) {
                Some(l) if l.trim_end() == w => {}
                Some(l) => {
                    return fail(format!(
                        "{name}:{}: the file was captured with other options:\n  file:    {}\n  options: {w}\n\
                         (give the options it was started with, or capture to another file)",
                        i + 1,
                        l.trim_end()
                    ))
                }
                None => return fail(format!("{name} has no complete capture header; remove it and start again")),
            }
        }
        let Some(table) = lines.iter().position(|l| l.trim_end() == "No,Z") else {
            return fail(format!("{name} has no complete capture header (no `No,Z` line); remove it and start again"));
        };
        if let Some((i, l)) = lines[3..table].iter().enumerate().find(|(_, l)| !l.starts_with('#')) {
            return fail(format!("{name}:{}: unexpected line in the header: {l:?}", i + 4));
        }
        let (mut stored, mut last) = (0usize, None);
        for (i, l) in lines.iter().enumerate().skip(table + 1) {
            let bad = || format!("{name}:{}: not point {} as `No,Z`: {l:?}", i + 1, stored + 1);
            let Some((no, z)) = l.trim_end().split_once(',') else { return fail(bad()) };
            let z = z.parse::<f64>().ok().filter(|z| z.is_finite());
            if no.parse::<usize>().ok() != Some(stored + 1) || z.is_none() {
                return fail(bad());
            }
            stored += 1;
            last = z;
        }
        if stored > self.grid.len() {
            return fail(format!("{name} holds {stored} points, more than the {} of the grid", self.grid.len()));
        }
        Ok((stored, last))
    }
}

/// The data file as a capture writes it: what is written when, and what
/// is stored so far.
#[derive(Debug, Clone, PartialEq)]
pub struct DataFile {
    /// The header a new file starts with; `None` once the file has begun.
    header: Option<String>,
    /// Points stored.
    pub stored: usize,
    /// Z of the last stored point.
    pub last: Option<f64>,
}

/// A resumed data file's last record, cut off by a crash or a power loss:
/// the file is to be cut back to its complete records.
#[derive(Debug, Clone, PartialEq)]
pub struct CutOff {
    /// Bytes of the complete records (the length to cut the file to).
    pub keep: usize,
    /// What was dropped, for the operator.
    pub message: String,
}

impl DataFile {
    /// A new capture's file, which begins with `header` (see
    /// [`Capture::header`]) when its first point is written.
    pub fn new(header: String) -> DataFile {
        DataFile { header: Some(header), stored: 0, last: None }
    }

    /// An existing data file `name` holding `bytes`, continued by
    /// `capture`: its header checked against the capture's, its points
    /// counted, and a last record without an end of line dropped.
    pub fn resume(capture: &Capture, bytes: &[u8], name: &str) -> Result<(DataFile, Option<CutOff>), Error> {
        let complete = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |p| p + 1);
        let (stored, last) = capture.check(&String::from_utf8_lossy(&bytes[..complete]), name)?;
        let cut_off = (complete < bytes.len()).then(|| {
            let tail = String::from_utf8_lossy(&bytes[complete..]);
            CutOff {
                keep: complete,
                message: format!(
                    "{name}: dropped an incomplete last line {tail:?} (the capture stopped while writing it, \
                     a crash or a power loss); point {} was not stored",
                    stored + 1
                ),
            }
        });
        Ok((DataFile { header: None, stored, last }, cut_off))
    }

    /// Writes point `no` at tip Z `z` to `out` in one write (with the
    /// header before it when it is the file's first) and counts it stored.
    pub fn append(&mut self, out: &mut impl Write, no: usize, z: f64) -> io::Result<()> {
        let record = format!("{no},{z}\n");
        match &self.header {
            Some(header) => out.write_all(format!("{header}{record}").as_bytes())?,
            None => out.write_all(record.as_bytes())?,
        }
        self.header = None;
        self.stored = no;
        self.last = Some(z);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::probe::Order;

    fn capture() -> Capture {
        Capture {
            grid: Grid { nx: 2, ny: 2, pitch: 1.0, origin: [0.0, 0.0], order: Order::ZigZag },
            tip: TipZ { bottom: -20.0, sign: -1, zero: 0.0 },
        }
    }

    #[test]
    fn the_header_comes_with_the_first_point_and_a_resume_drops_a_cut_record() {
        let c = capture();
        let mut file = DataFile::new(c.header("/dev/ttyUSB0", 9600, "2026-11-23T19:45:00Z"));
        let mut bytes = Vec::new();
        file.append(&mut bytes, 1, -32.345).unwrap();
        file.append(&mut bytes, 2, -32.5).unwrap();
        let text = String::from_utf8(bytes.clone()).unwrap();
        assert!(text.starts_with("# kezuri probe capture\n# grid nx=2 ny=2 pitch=1 origin=0,0 pattern=zigzag\n"));
        assert!(
            text.ends_with("# port /dev/ttyUSB0 9600 baud, started 2026-11-23T19:45:00Z\nNo,Z\n1,-32.345\n2,-32.5\n")
        );
        bytes.extend_from_slice(b"3,-3");
        let (resumed, cut) = DataFile::resume(&c, &bytes, "ume.csv").unwrap();
        assert_eq!((resumed.stored, resumed.last), (2, Some(-32.5)));
        let cut = cut.unwrap();
        assert_eq!(cut.keep, text.len());
        assert!(cut.message.contains("\"3,-3\"") && cut.message.ends_with("point 3 was not stored"), "{cut:?}");
        let other = Capture { tip: TipZ { zero: 1.0, ..c.tip }, ..c };
        let e = DataFile::resume(&other, text.as_bytes(), "ume.csv").unwrap_err();
        assert_eq!(e.kind, ErrorKind::Capture);
        assert!(e.message.starts_with("ume.csv:3: the file was captured with other options"), "{e}");
    }
}
