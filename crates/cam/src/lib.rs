//! Making toolpaths: the cutters, placing a cutter on a surface
//! (drop-cutter), what two neighbouring passes leave behind (scallop theory),
//! and what a program really cuts (material-removal simulation).
//!
//! `cam` knows nothing of NC syntax: it reads surfaces and
//! [`kezuri_geom::Toolpath`]s and makes toolpaths. Programs position a
//! cutter by its tip, the lowest point of the cutter, for every shape.
//!
//! # The cutter abstraction
//! Every cutter is a surface of revolution about its axis: a convex,
//! non-decreasing profile `height(r)` above the tip for `0 ≤ r ≤ R`, then a
//! cylindrical shank of radius `R`. Drop-cutter and the scallop envelope
//! need nothing else from a shape ([`cutter::Profile`]); what else a new shape
//! takes (a `Cutter` variant, its SPEC, its cusp) ARCHITECTURE.md lists.
//!
//! # Example
//! ```
//! use kezuri_cam::Cutter;
//! let oval: Cutter = "oval:16,24".parse().unwrap();
//! assert_eq!(oval.radius(), 8.0);
//! // The egg-shaped tip: 24 mm high where it meets the 16 mm shank.
//! assert!((oval.height(8.0) - 24.0).abs() < 1e-12);
//! ```

#![warn(missing_docs)]

pub mod cutter;
pub mod dropcut;
pub mod engage;
mod error;
pub mod mill;
pub mod probe;
pub mod relief;
pub mod rough;
pub mod scallop;
pub mod shorten;
pub mod sim;
pub mod texture;

pub use cutter::Cutter;
pub use dropcut::{
    drop_cutter, drop_cutter_grid, drop_cutter_grid_in_order, drop_cutter_rows, rows_at_once, Grid, MeshSurface,
    Surface,
};
pub use error::{Error, ErrorKind};
