//! Toolpath to text: NC dialects and the CSV motion dump.
//!
//! The modules stand in layers, each using only those above it:
//! `dialect` and `options` (the words and the choices), `blocks` (the
//! writer and what the control knows), then what it writes: `arcs`,
//! `frames`, `kept` blocks and the presets' start, tool changes and end
//! (`post`); `gcode` writes a program from them, whole or piece by piece
//! as a run hands its path on (`ProgramWriter`), and `parts` a program in
//! parts of at most so many bytes. `csv` writes the motion dump, whole or
//! piece by piece (`CsvWriter`).

mod arcs;
mod blocks;
mod csv;
mod dialect;
mod frames;
mod gcode;
mod kept;
mod options;
mod parts;
mod post;

pub use csv::{csv, may_move_uvw, CsvWriter};
pub use dialect::{Codes, Dialect};
pub use gcode::{dwell_block, made_text, program, MadeText, ProgramWriter};
pub use options::{Arcs, CoolantChoice, Home, Retract, Setup, WriteOptions};
pub use parts::parts;
pub use post::PRESETS;

/// `post` for a measuring program kezuri writes as text (`probe plan`,
/// `thermal plan`): its dwells in seconds (Fanuc `G04 X0.5`, others
/// `G4 P0.5`) unless the post gives them in milliseconds, and its blocks
/// without `N` numbers (the program's own blocks have none).
pub fn text_options(post: &WriteOptions) -> WriteOptions {
    WriteOptions { dwell_ms: Some(post.dwell_ms.unwrap_or(false)), line_numbers: None, ..post.clone() }
}
