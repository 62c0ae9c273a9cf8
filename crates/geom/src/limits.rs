//! The range of every length a user may give: from 1 nm to 1 km.
//!
//! A cutter, a step, a tolerance, a pitch or a resolution outside it means
//! nothing on a machine, and sizes reckoned from it (points, cells, knots)
//! overflow or never end; a coordinate beyond it loses the micrometre in
//! the digits of a double. One check, used by every crate and command, so
//! each refusal reads the same.

/// The shortest length a user may give, mm (1 nm).
pub const SHORTEST_MM: f64 = 1e-6;
/// The longest length, and the largest coordinate, a user may give, mm (1 km).
pub const LONGEST_MM: f64 = 1e6;

/// `v` if it is a length from [`SHORTEST_MM`] to [`LONGEST_MM`]; else why
/// not, naming `what`.
pub fn length(v: f64, what: &str) -> Result<f64, String> {
    if (SHORTEST_MM..=LONGEST_MM).contains(&v) {
        Ok(v)
    } else {
        Err(format!("{what} must be a length from {SHORTEST_MM} to {LONGEST_MM} mm, got {}", shown(v)))
    }
}

/// `v` if it is zero or a [`length`].
pub fn length_or_zero(v: f64, what: &str) -> Result<f64, String> {
    if v == 0.0 {
        Ok(v)
    } else {
        length(v, what).map_err(|e| e.replace("must be a length", "must be zero or a length"))
    }
}

/// `v` if it is a coordinate within ±[`LONGEST_MM`].
pub fn coordinate(v: f64, what: &str) -> Result<f64, String> {
    if v.abs() <= LONGEST_MM {
        Ok(v)
    } else {
        Err(format!("{what} must be a coordinate from -{LONGEST_MM} to {LONGEST_MM} mm, got {}", shown(v)))
    }
}

/// `v` as a person reads it: in full, or with an exponent where the digits
/// would run on (1e-300, not three hundred zeros).
fn shown(v: f64) -> String {
    if v != 0.0 && !(1e-4..1e9).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nan_infinity_and_the_tiny_are_refused() {
        for v in [f64::NAN, f64::INFINITY, -1.0, 0.0, 1e-300, 1e7] {
            assert!(length(v, "--pitch").unwrap_err().starts_with("--pitch must be a length from"), "{v}");
        }
        assert!(length(1e-300, "x").unwrap_err().ends_with("got 1e-300"));
        assert_eq!(length(0.5, "x"), Ok(0.5));
        assert_eq!(length_or_zero(0.0, "x"), Ok(0.0));
        assert!(length_or_zero(f64::NAN, "x").unwrap_err().contains("zero or a length"));
        assert!(coordinate(f64::NEG_INFINITY, "x").is_err() && coordinate(f64::NAN, "x").is_err());
        assert_eq!(coordinate(-5.0, "x"), Ok(-5.0));
    }
}
