//! Toolpath to text: NC dialects and the CSV motion dump.

mod blocks;
mod csv;
mod frames;
mod gcode;
mod kept;
mod post;

pub use blocks::Codes;
pub use csv::csv;
pub use gcode::{dwell_block, made_text, program, Dialect, MadeText, UnknownDialect, WriteError, WriteOptions};
pub use post::{Arcs, CoolantChoice, Home, Retract, Setup, UnknownPost, PRESETS};

/// `post` for a measuring program kezuri writes as text (`probe plan`,
/// `thermal plan`): its dwells in seconds (Fanuc `G04 X0.5`, others
/// `G4 P0.5`) unless the post gives them in milliseconds, and its blocks
/// without `N` numbers (the program's own blocks have none).
pub fn text_options(post: &WriteOptions) -> WriteOptions {
    WriteOptions { dwell_ms: Some(post.dwell_ms.unwrap_or(false)), line_numbers: None, ..post.clone() }
}

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
