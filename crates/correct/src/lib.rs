//! Corrections from measurements taken on the machine: thermal drift and tool wear, the
//! corrected command of every move of a program (the thermal and wear report's method).
//!
//! - [`edge`]: the corner of the square reference tool in a 2D line-sensor
//!   profile — the profile split into its two sides, a robust least-squares
//!   line through each, their intersection (`kezuri thermal edge`).
//! - [`kinematics`]: the machine's tool and work chains, forward and inverse.
//! - [`thermal`]: the drift measured at stations fitted as error polynomials
//!   per axis and B angle, the model file, and every move of a program
//!   corrected ([`thermal::correct_moves`]).
//! - [`microscope`], [`stitch`], [`tool_image`]: backlit pictures of a turning
//!   tool to its measured profile and runout; [`synthetic`] such pictures of a
//!   known tool.
//! - [`wear`]: the cutting point moved for the measured tool's wear and runout,
//!   for every move of a program ([`wear::correct_moves`]).
//!
//! The crate works on numbers and [`kezuri_geom`]'s toolpaths; reading files
//! and writing programs is the CLI's. Every failure is an [`Error`], its
//! [`ErrorKind`] saying which.

#![warn(missing_docs)]

pub mod edge;
mod error;
pub mod kinematics;
pub mod microscope;
pub mod stitch;
pub mod synthetic;
pub mod thermal;
pub mod tool_image;
pub mod wear;

pub use error::{Error, ErrorKind};
