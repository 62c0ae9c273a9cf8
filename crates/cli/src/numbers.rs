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

/// An amount of memory, bytes: a number with K, M, G or T (powers of 1024:
/// `512M`, `2G`, `1.5G`; a trailing `B` or `iB` allowed), or a number of
/// bytes; at least 1 MiB.
pub fn memory(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let t = t.strip_suffix("iB").or_else(|| t.strip_suffix('B')).unwrap_or(t);
    let (digits, shift) = match t.char_indices().last() {
        Some((k, c)) if c.is_ascii_alphabetic() => {
            let shift = match c.to_ascii_uppercase() {
                'K' => 10,
                'M' => 20,
                'G' => 30,
                'T' => 40,
                _ => return Err(format!("'{s}' is not a size: a number with K, M, G or T (such as 2G or 512M)")),
            };
            (&t[..k], shift)
        }
        _ => (t, 0),
    };
    let v = digits.trim().parse::<f64>().map_err(|_| format!("'{s}' is not a size: a number with K, M, G or T"))?;
    let bytes = v * (1u64 << shift) as f64;
    if !(bytes >= (1u64 << 20) as f64 && bytes <= (1u64 << 50) as f64) {
        return Err(format!("'{s}' must be from 1M to 1024T"));
    }
    Ok(bytes as u64)
}

#[cfg(test)]
mod tests {
    use super::memory;

    #[test]
    fn sizes_are_powers_of_1024() {
        assert_eq!(memory("2G"), Ok(2 << 30));
        assert_eq!(memory("512M"), Ok(512 << 20));
        assert_eq!(memory("1.5GiB"), Ok(3 << 29));
        assert_eq!(memory("4096k"), Ok(4 << 20));
        assert_eq!(memory("1048576"), Ok(1 << 20));
        for bad in ["", "2X", "G", "-1G", "100K", "nanG", "infG"] {
            assert!(memory(bad).is_err(), "{bad}");
        }
    }
}
