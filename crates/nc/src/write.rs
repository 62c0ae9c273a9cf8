//! Toolpath to text: NC dialects and the CSV motion dump.

mod csv;

pub use csv::csv;
