//! The nouns every other kezuri crate shares.
//!
//! `geom` sits at the bottom of the workspace: it knows nothing of NC syntax,
//! cutters, files or the terminal. Today it holds the machine-neutral
//! [`Toolpath`]: the one motion model that the NC interpreter produces, the CAM
//! pipelines will produce, and every writer and transform reads.
//!
//! # Units and frames
//! One internal unit per quantity: millimetres for linear axes, degrees for
//! rotary axes A, B, C (as on the control), mm/min for feed, rpm for spindle
//! speed, seconds for dwell. Positions are the tool tip: the lowest point of
//! the cutter, with work and tool length offsets already applied, so with all
//! offsets zero they equal the program's own coordinates.
//!
//! # Example
//! ```
//! use kezuri_geom::{Axes, Move, MoveKind, Toolpath};
//! let mut path = Toolpath::default();
//! let start = Axes::ZERO;
//! let end = Axes { x: 10.0, ..Axes::ZERO };
//! path.push(Move { kind: MoveKind::Feed, start, end, feed: 600.0, ..Move::default() });
//! assert_eq!(path.feed_length(), 10.0);
//! ```

#![warn(missing_docs)]

mod alloc;
mod time;
mod toolpath;

pub use alloc::LargePages;
pub use time::{cycle_time, Dynamics};
pub use toolpath::{Arc, Axes, AxisSet, Coolant, Frame, LengthOffset, Move, MoveKind, Plane, Spindle, Toolpath};
