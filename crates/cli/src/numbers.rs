//! The numbers of the command line, checked as clap reads them: each is
//! finite, and a length or coordinate lies in the range of
//! `kezuri_geom::limits` (1 nm to 1 km), so no NaN, infinity or 1e-300
//! reaches the work.

use kezuri_geom::limits;

fn number(s: &str) -> Result<f64, String> {
    s.trim().parse::<f64>().map_err(|_| format!("'{s}' is not a number"))
}

/// A length, mm: from 1e-6 to 1e6.
pub fn length(s: &str) -> Result<f64, String> {
    limits::length(number(s)?, "it")
}

/// Zero or a [`length`].
pub fn length_or_zero(s: &str) -> Result<f64, String> {
    limits::length_or_zero(number(s)?, "it")
}

/// A coordinate, mm: from -1e6 to 1e6.
pub fn coordinate(s: &str) -> Result<f64, String> {
    limits::coordinate(number(s)?, "it")
}

/// A finite number more than 0 and at most 1e6 (a feed in mm/min, a speed
/// in rpm, a factor).
pub fn positive(s: &str) -> Result<f64, String> {
    let v = number(s)?;
    if v > 0.0 && v <= limits::LONGEST_MM {
        Ok(v)
    } else {
        Err(format!("it must be a number more than 0 and at most {}, got {v}", limits::LONGEST_MM))
    }
}

/// A [`length`] either way (a signed step), mm.
pub fn signed_length(s: &str) -> Result<f64, String> {
    let v = number(s)?;
    limits::length(v.abs(), "its size").map(|_| v)
}
