//! One module per command (`kezuri NAME`, and its subcommands in `NAME/`): each parses its
//! arguments, reads and writes files, draws progress and prints, over the library crates and
//! the plumbing the commands share (the modules beside `cmd`). No command imports another's
//! module (`tests/tidy.rs` holds it).

pub mod check;
pub mod convert;
pub mod demo;
pub mod dropcut;
pub mod engage;
pub mod mill;
pub mod probe;
pub mod relief;
pub mod run;
pub mod scallop;
pub mod sim;
pub mod texture;
pub mod thermal;
pub mod tool;
pub mod view;
pub mod wear;
