//! What one command may spend. Every size a user can ask for (points, cells,
//! knots, rows, pixels) is weighed against this before the work starts, and
//! refused with its figure and the option that sets it.

use anyhow::{bail, Result};

/// The memory one command may take, bytes (2 GiB).
pub const MEMORY_BYTES: f64 = 2.0 * (1u64 << 30) as f64;

/// Refuses `count` things of `bytes_each` bytes beyond [`MEMORY_BYTES`],
/// naming the option that asks for them. `count` is a float so that an
/// estimate never overflows.
pub fn memory(option: &str, count: f64, noun: &str, bytes_each: f64) -> Result<()> {
    let bytes = count * bytes_each;
    if bytes <= MEMORY_BYTES {
        return Ok(());
    }
    bail!(
        "{option}: {} {noun} would take about {} of memory (at most {}, about {} {noun})",
        round(count),
        gigabytes(bytes),
        gigabytes(MEMORY_BYTES),
        round(MEMORY_BYTES / bytes_each)
    )
}

/// A count as a person reads it: whole below a million, else to two figures.
fn round(n: f64) -> String {
    if n < 1e6 {
        format!("{n:.0}")
    } else if n < 1e15 {
        format!("{:.1} million", n / 1e6)
    } else {
        format!("{n:.1e}")
    }
}

fn gigabytes(bytes: f64) -> String {
    if bytes < 1e15 {
        format!("{:.1} GB", bytes / 1e9)
    } else {
        format!("{:.1e} GB", bytes / 1e9)
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn refusals_say_the_figure_and_the_option() {
        assert!(super::memory("--grid", 1e6, "points", 56.0).is_ok());
        let e = super::memory("--grid", 1e8, "points", 56.0).unwrap_err().to_string();
        assert_eq!(e, "--grid: 100.0 million points would take about 5.6 GB of memory (at most 2.1 GB, about 38.3 million points)");
    }
}
