//! The machine model: what a machine file (`--machine M.toml`) says about
//! a machine — its rapids and acceleration, its tool table and the H and D
//! registers, work offsets and reference points, macro variables, input
//! signals, canned cycle and compensation settings, the kinematic chains —
//! and how programs are written for its control (the `[post]` section over
//! a preset, `--post`).
//!
//! - [`machine`]: the machine file and [`Machine`], [`ToolEntry`].
//! - [`post`]: the `[post]` section and the choice of the preset.
//! - [`tool_table`]: the tool files shops keep (LinuxCNC `tool.tbl`,
//!   FreeCAD bits and libraries, Fusion 360 libraries) read into a tool
//!   table, and the table as `kezuri tool table` shows it.
//!
//! Everything reads from text and bytes: the files a machine file names
//! come through [`Files`], which the caller gives; the crate opens no path.

#![warn(missing_docs)]

mod error;
pub mod files;
pub mod machine;
pub mod post;
pub mod tool_table;

pub use error::{Error, ErrorKind, Result};
pub use files::Files;
pub use machine::{Machine, ToolEntry};
