//! The nouns every other kezuri crate shares.
//!
//! `geom` sits at the bottom of the workspace: it knows nothing of NC syntax,
//! cutters, files or the terminal. Today it holds the machine-neutral
//! [`Toolpath`]: the one motion model that the NC interpreter produces, the CAM
//! pipelines produce, and every writer and transform reads.
//!
//! The surfaces CAM places cutters on live here too: [`Mesh`] (an indexed
//! triangle mesh, read from binary or ASCII STL by [`Mesh::from_stl`], whose
//! [`Error`] says what is wrong with a bad file), [`XyIndex`] (XY
//! grids of its triangles, the finest sized from the median triangle, each
//! triangle in the grid its box fits: at most four entries a triangle)
//! and [`Heightfield`] (z over a regular grid, a triangulated surface).
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
mod ends;
mod error;
mod heightfield;
mod index;
pub mod limits;
mod mesh;
mod random;
mod stl;
mod time;
mod tool_profile;
mod toolpath;

pub use alloc::LargePages;
pub use ends::{set_ends, set_ends_after, ArcCentre};
pub use error::{Error, ErrorKind};
pub use heightfield::{Heightfield, Slopes, BLOCK};
pub use index::XyIndex;
pub use mesh::{Mesh, Triangle, Vec3};
pub use random::SplitMix64;
pub use stl::{
    parse_stl, read_binary_stl_mesh, read_stl, write_ascii_stl, write_binary_stl, write_binary_stl_to, StlFile,
};
pub use time::{cycle_time, move_times, CycleClock, Dynamics};
pub use tool_profile::{Support, ToolProfile};
pub use toolpath::{
    Arc, Axes, AxisRanges, AxisSet, Coolant, CycleBlock, Frame, Kept, KnownBounds, LengthOffset, Move, MoveKind,
    PathSink, Plane, Spindle, ToolState, Toolpath, WholePath,
};
