//! Pictures of a job, as bytes: line charts and toolpath drawings as SVG
//! text, framed raster figures (a simulated surface, its deviation, a
//! probed grid, a tool's silhouette) and any SVG as PNG with the bundled
//! font, and the offline 3D view page as HTML.
//!
//! The crate takes values (toolpaths, Z-maps, a simulation's report) and
//! returns bytes; writing them to files is the caller's.

#![warn(missing_docs)]

pub mod chart;
pub mod engage;
mod error;
pub mod figure;
pub mod plot;
pub mod probe;
pub mod sim;
pub mod view;

pub use error::{Error, ErrorKind};
pub use plot::png_from_svg;
pub use view::{page, Job, PageOptions, Simulation};
