//! Toolpath to text: NC dialects and the CSV motion dump.

mod blocks;
mod csv;
mod frames;
mod gcode;
mod kept;
mod post;

pub use csv::csv;
pub use gcode::{made_text, program, Dialect, MadeText, UnknownDialect, WriteError, WriteOptions};
pub use post::{Arcs, CoolantChoice, Home, Retract, Setup, UnknownPost, PRESETS};

/// A number as hand-made program text writes it: `digits` decimals,
/// trailing zeros dropped, a decimal point always (`2.`, `-0.05`, never
/// `-0.`).
pub fn number(v: f64, digits: usize) -> String {
    let s = format!("{v:.digits$}");
    let s = if s.contains('.') { s.trim_end_matches('0').to_string() } else { s + "." };
    if s == "-0." {
        "0.".into()
    } else {
        s
    }
}
