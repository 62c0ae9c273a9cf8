//! Times of measurement: RFC 3339 text in, whole seconds of UTC out, kept
//! as `YYYY-MM-DDTHH:MM:SSZ` (text of that one form sorts by time).

use anyhow::{bail, Context, Result};

/// Days from 1970-01-01 to the date (proleptic Gregorian; H. Hinnant's
/// `days_from_civil`).
fn days_from_civil(y: i64, m: i64, d: i64) -> i64 {
    let y = if m <= 2 { y - 1 } else { y };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let doy = (153 * (m + if m > 2 { -3 } else { 9 }) + 2) / 5 + d - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

/// The date `days` after 1970-01-01.
fn civil_from_days(days: i64) -> (i64, i64, i64) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    (yoe + era * 400 + i64::from(m <= 2), m, d)
}

fn days_in_month(y: i64, m: i64) -> i64 {
    match m {
        2 if (y % 4 == 0 && y % 100 != 0) || y % 400 == 0 => 29,
        2 => 28,
        4 | 6 | 9 | 11 => 30,
        _ => 31,
    }
}

/// Seconds since 1970-01-01T00:00:00Z of an RFC 3339 time such as
/// `2026-05-01T08:30:00Z`, `2026-05-01 17:30:00+09:00` or
/// `2026-05-01T08:30:00.25Z` (fractions round to the nearest second); a
/// bare date `2026-05-01` is its midnight UTC.
pub fn parse_rfc3339(text: &str) -> Result<i64> {
    let t = text.trim();
    parse(t).with_context(|| {
        format!("--at {t:?} is not an RFC 3339 time (such as 2026-05-01T08:30:00Z or 2026-05-01T17:30:00+09:00)")
    })
}

fn parse(t: &str) -> Result<i64> {
    let b = t.as_bytes();
    let num = |r: std::ops::Range<usize>| -> Result<i64> {
        match t.get(r.clone()) {
            Some(s) if !s.is_empty() && s.bytes().all(|c| c.is_ascii_digit()) => Ok(s.parse()?),
            _ => bail!("expected digits at character {}", r.start + 1),
        }
    };
    if b.len() < 10 || b[4] != b'-' || b[7] != b'-' {
        bail!("expected a date YYYY-MM-DD");
    }
    let (y, mo, d) = (num(0..4)?, num(5..7)?, num(8..10)?);
    if !(1..=12).contains(&mo) || d < 1 || d > days_in_month(y, mo) {
        bail!("no such date");
    }
    let days = days_from_civil(y, mo, d);
    if b.len() == 10 {
        return Ok(days * 86_400);
    }
    if !matches!(b[10], b'T' | b't' | b' ') || b.len() < 19 || b[13] != b':' || b[16] != b':' {
        bail!("expected THH:MM:SS after the date");
    }
    let (h, mi, s) = (num(11..13)?, num(14..16)?, num(17..19)?);
    if h > 23 || mi > 59 || s > 60 {
        bail!("no such time of day");
    }
    let mut i = 19;
    let mut frac = 0.0;
    if b.get(i) == Some(&b'.') {
        let start = i + 1;
        i = start;
        while b.get(i).is_some_and(u8::is_ascii_digit) {
            i += 1;
        }
        frac = format!("0.{}", num(start..i)?).parse::<f64>()?;
    }
    let offset = match &t[i..] {
        "Z" | "z" => 0,
        zone if zone.len() == 6 && matches!(zone.as_bytes()[0], b'+' | b'-') && zone.as_bytes()[3] == b':' => {
            let (oh, om) = (num(i + 1..i + 3)?, num(i + 4..i + 6)?);
            if oh > 23 || om > 59 {
                bail!("no such offset");
            }
            (oh * 60 + om) * 60 * if zone.starts_with('-') { -1 } else { 1 }
        }
        "" => bail!("the time has no zone (Z or ±HH:MM)"),
        _ => bail!("expected Z or ±HH:MM after the time"),
    };
    Ok(days * 86_400 + h * 3600 + mi * 60 + s.min(59) + i64::from(frac >= 0.5) - offset)
}

/// `YYYY-MM-DDTHH:MM:SSZ` for seconds since 1970-01-01T00:00:00Z.
pub fn format_utc(seconds: i64) -> String {
    let (days, s) = (seconds.div_euclid(86_400), seconds.rem_euclid(86_400));
    let (y, m, d) = civil_from_days(days);
    format!("{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z", s / 3600, s / 60 % 60, s % 60)
}

/// Now, in whole seconds since 1970-01-01T00:00:00Z.
pub fn now() -> i64 {
    match std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH) {
        Ok(d) => d.as_secs() as i64,
        Err(e) => -(e.duration().as_secs() as i64),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_parse_to_utc_and_print_back() {
        let at = |s| format_utc(parse_rfc3339(s).unwrap());
        assert_eq!(parse_rfc3339("1970-01-01T00:00:00Z").unwrap(), 0);
        assert_eq!(at("2026-05-01T08:30:00Z"), "2026-05-01T08:30:00Z");
        assert_eq!(at("2026-05-01T17:30:00+09:00"), "2026-05-01T08:30:00Z");
        assert_eq!(at("2026-04-30 23:30:00-09:00"), "2026-05-01T08:30:00Z");
        assert_eq!(at("2024-02-29t23:59:59.6z"), "2024-03-01T00:00:00Z");
        assert_eq!(at("2026-05-01"), "2026-05-01T00:00:00Z");
        assert_eq!(at("1969-12-31T23:59:59Z"), "1969-12-31T23:59:59Z");
        assert_eq!(parse_rfc3339("2000-03-01T00:00:00Z").unwrap(), 951_868_800);
        for bad in ["", "2026-02-30", "2026-13-01", "2026-05-01T25:00:00Z", "2026-05-01T08:30:00", "yesterday"] {
            let e = parse_rfc3339(bad).unwrap_err();
            assert!(format!("{e:#}").contains("RFC 3339"), "{bad}: {e:#}");
        }
    }
}
