//! Toolpath to text: NC dialects and the CSV motion dump.

mod blocks;
mod csv;
mod gcode;

pub use csv::csv;
pub use gcode::{program, Dialect, UnknownDialect, WriteError, WriteOptions};
