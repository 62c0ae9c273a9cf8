//! One indicator reading from a line the instrument sent, and how it
//! becomes the tip Z. The formats and where they are defined:
//!
//! - **Mitutoyo multiplexer / USB record**, `01A+0012.345` then CR. Mitutoyo
//!   QM-Height manual No. 99MAF600B, §6.2.2 "USB data output
//!   specifications" (9600 bps, 8 data bits, no parity, 1 stop bit): D1 code
//!   `0`, D2 channel, D3 measurement item `A`, D4 sign `+` or `-`, D5–D12 the
//!   data with a floating decimal point, D13 CR; its examples `01A+0000.123`
//!   (mm, 0.001), `01A+00.12345` and `01A+000.1234` (inch). The GageMux
//!   operating manual (ASD document 10040PF), p. 7, "Mitutoyo Mux-10
//!   format": `0CASRRRRRRRR<CR>`, first character `0`, C the channel, `A`,
//!   S the sign, RRRRRRRR the reading, e.g. `01A-001.2340`. So the data field
//!   is exactly eight characters, seven digits and one decimal point; kezuri
//!   also wants a digit on each side of the point (every example has one).
//!   A record with characters lost (`01A+0001345`, `01A+0001`) or added is
//!   refused, never read as another value. The two characters before `A` are
//!   read as the channel number (for `--channel`).
//! - **Digimatic frame** written as its 13 hexadecimal nibbles d1…d13
//!   (99MAF600B §6.2.1 and Mitutoyo manual No. 99MBA043A, "Digimatic data
//!   output"): `FFFF`, the sign (0 `+`, 8 `-`), six BCD digits, the decimal
//!   point position (0–5), the unit (0 mm, 1 inch; inch readings are
//!   converted to mm), e.g. `FFFF8012345 30` → −12.345 mm.
//! - **A plain number**, optionally signed and followed by `mm`: `-12.345`,
//!   `+19.16`, `19.16 mm` (what most USB cables and terminal-style interfaces
//!   send). It has no fixed form to check, so only the port's settling on
//!   open and the check of the last point on `--resume` guard it against a
//!   line cut in two.

/// Which line formats a capture accepts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Any of the formats below.
    Auto,
    /// Mitutoyo multiplexer/USB records (`01A+0012.345`) and raw Digimatic
    /// nibbles.
    Digimatic,
    /// Plain numbers (`-12.345`, `19.16 mm`).
    Number,
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
            Format::Digimatic => "not a Mitutoyo record (01A+0012.345) or Digimatic frame".into(),
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

/// Mitutoyo multiplexer / USB record `01A+0012.345` (D1–D2 channel, D3 `A`,
/// D4 sign, D5–D12 the value: eight characters, seven digits and one
/// decimal point with a digit on each side). `None` when the line does not
/// look like one at all, `Some(Err)` when it does but is damaged: a record
/// with characters lost or added is never read as another value.
fn parse_mitutoyo(t: &str) -> Option<Result<Reading, String>> {
    let b = t.as_bytes();
    if b.len() < 3 || !b[0].is_ascii_digit() || !b[1].is_ascii_digit() || b[2] != b'A' {
        return None;
    }
    let negative = match b.get(3) {
        Some(b'+') => false,
        Some(b'-') => true,
        _ => return Some(Err("Mitutoyo record without a sign after the channel".into())),
    };
    let channel = u32::from(b[0] - b'0') * 10 + u32::from(b[1] - b'0');
    let data = &b[4..];
    if data.len() != 8 {
        return Some(Err(format!(
            "Mitutoyo record with {} characters after the sign where the protocol sends 8 \
             (characters lost or added)",
            data.len()
        )));
    }
    let point = data.iter().position(|&c| c == b'.');
    let well_formed = data.iter().filter(|&&c| c == b'.').count() == 1
        && data.iter().all(|&c| c.is_ascii_digit() || c == b'.')
        && point.is_some_and(|p| (1..=6).contains(&p));
    match (well_formed, decimal(&t[4..])) {
        (true, Some((v, decimals))) => {
            Some(Ok(Reading { mm: if negative { -v } else { v }, decimals, channel: Some(channel) }))
        }
        _ => Some(Err("Mitutoyo record with a damaged value (7 digits and one decimal point expected)".into())),
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
#[derive(Debug, Clone, Copy, PartialEq)]
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tip_z_rounds_to_the_inputs_decimals() {
        let t = TipZ { bottom: -20.0, sign: -1, zero: 0.0 };
        let r = parse_reading("01A+0012.345", Format::Auto).unwrap();
        assert_eq!(t.tip_z(&r).to_string(), "-32.345");
        let t = TipZ { bottom: -70.5, sign: 1, zero: 0.01 };
        let r = parse_reading("19.16", Format::Auto).unwrap();
        assert_eq!(t.tip_z(&r).to_string(), "-51.35");
    }
}
