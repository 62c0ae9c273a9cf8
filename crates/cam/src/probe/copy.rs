//! The copy-milling job (`kezuri probe mill`): from a ball stylus's
//! readings to the surface between them ([`Between`]), the cutter placed on
//! it in zig-zag rows along X over the data's XY box, and the cuts along
//! the flat top of the data crossed at rapid.
//!
//! With [`Between::Smooth`] and the stylus's own shape as cutter, the
//! cutter follows the smooth surface through the readings itself (or the
//! straight line from reading to reading where that is higher, every
//! `step`; with `step` the pitch, straight from reading to reading, as the
//! original copy system's programs did). Any other cutter, and every
//! cutter with [`Between::Bound`], is placed with drop-cutter on a fine
//! sampling of the surface ([`super::stylus`]).

use std::fmt;

use kezuri_geom::{Heightfield, MoveKind, Toolpath};

use super::smooth::{sharpest_bend, Bend, Smooth, Tight};
use super::stylus::{detect_flat, model, rapid_margins, reconstruct, Margins, OverFlat};
use super::ProbeGrid;
use crate::dropcut::{drop_cutter, drop_cutter_rows, rows_at_once};
use crate::error::{Error, ErrorKind};
use crate::mill::{raster_with, ClRowsFn, Direction, Pattern, Progress, RasterOptions, Region};
use crate::Cutter;

/// How far from the flat top a reading may be and still be on it, mm.
const FLAT_TOLERANCE: f64 = 0.01;

/// The share of the readings on a flat margin at the top for
/// [`Floor::Auto`] to find it.
const FLAT_SHARE: f64 = 0.05;

/// What lies between the readings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Between {
    /// A smooth surface through the readings; the model under it.
    Smooth,
    /// The highest surface the readings allow; heights rounded up.
    Bound,
}

/// The flat top of the data, whose cuts are crossed at rapid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Floor {
    /// Found where one is: a flat margin at the top held by 5 % of the
    /// readings or more.
    Auto,
    /// None: every cut is cut.
    Off,
    /// At this height.
    At(f64),
}

/// A copy to mill. Lengths mm, feeds mm/min.
#[derive(Clone, Copy, Debug)]
pub struct Job<'a> {
    /// The readings: where the stylus's tip rested on the model.
    pub data: &'a ProbeGrid,
    /// The stylus that took them.
    pub stylus: Cutter,
    /// The cutter.
    pub cutter: Cutter,
    /// Distance between rows; `None`: the pitch.
    pub stepover: Option<f64>,
    /// Sampling step along a row; `None`: a quarter of the pitch where the
    /// stylus's own shape follows the smooth surface, else the pitch.
    pub step: Option<f64>,
    /// How far the path may stray from the exact cutter locations (a gouge
    /// into the model of up to this much is allowed).
    pub gouge_tol: f64,
    /// What lies between the readings.
    pub between: Between,
    /// Node spacing of the sampled surface; `None`: an eighth of the pitch.
    pub resolution: Option<f64>,
    /// The program's output increment: with [`Between::Bound`] positions
    /// lie on it and heights are rounded up to it (never below the bound).
    pub quantum: f64,
    /// Height for rapids; `None`: 5 mm above the highest reading.
    pub safe_z: Option<f64>,
    /// The flat top crossed at rapid.
    pub floor: Floor,
    /// Height of those rapids over the flat top.
    pub clearance: f64,
    /// Cutting feed.
    pub feed: f64,
    /// Plunge feed.
    pub plunge_feed: f64,
    /// Spindle speed, rpm.
    pub speed: f64,
    /// Tool number.
    pub tool: u32,
}

/// The surface the cutter was placed on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Surface {
    /// The highest surface the readings allow, sampled on `nodes` at `step`.
    Bound {
        /// Nodes along X and Y.
        nodes: [usize; 2],
        /// Their spacing, mm.
        step: f64,
    },
    /// The model under the smooth surface, sampled on `nodes` at `step`.
    Model {
        /// Nodes along X and Y.
        nodes: [usize; 2],
        /// Their spacing, mm.
        step: f64,
    },
    /// The smooth surface through the readings, followed by the stylus's
    /// own shape.
    Followed,
}

impl fmt::Display for Surface {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Surface::Bound { nodes: [nx, ny], step } => {
                write!(f, "the highest the readings allow, {nx} × {ny} nodes at {step:.4} mm")
            }
            Surface::Model { nodes: [nx, ny], step } => {
                write!(f, "smooth through the readings, the model {nx} × {ny} nodes at {step:.4} mm")
            }
            Surface::Followed => f.write_str("smooth through the readings, followed by the stylus's own shape"),
        }
    }
}

/// The copy and what the command reports of it.
#[derive(Clone, Debug)]
pub struct Copied {
    /// The toolpath.
    pub path: Toolpath,
    /// The distance between rows it was made with.
    pub stepover: f64,
    /// Its height for rapids.
    pub safe_z: f64,
    /// The surface the cutter was placed on.
    pub surface: Surface,
    /// The flat top crossed at rapid, and how much of the cuts that was.
    pub flat: Option<(f64, Margins)>,
    /// What the operator is warned of: where the surface through the
    /// readings bends tighter than a ball stylus (no ball rolling on a
    /// model reads like that), and where the readings bend down so sharply
    /// that the copy may cut more than `gouge_tol` below the model between
    /// them.
    pub warnings: Vec<String>,
}

/// The warnings of a copy with `stylus` whose surface bends `tight`er than
/// it and whose readings `bend` down more than `gouge_tol` at `pitch`.
fn warnings(stylus: &Cutter, tight: Option<Tight>, bend: Option<Bend>, gouge_tol: f64, pitch: f64) -> Vec<String> {
    let tight = tight.map(|t| {
        format!(
            "the surface through the readings bends tighter than the stylus (radius {} mm) in {} cell(s), tightest \
             radius {:.3} mm at X{:.3} Y{:.3}: no ball rolling on a model reads like that (a sharp edge, noise or a \
             pitch too coarse); the model there is what the stylus could reach",
            stylus.radius(),
            t.cells,
            t.radius,
            t.at[0],
            t.at[1]
        )
    });
    let bend = bend.map(|b| {
        format!(
            "the readings bend down sharply at {} point(s) (a rim or a crest): between readings there the copy may \
             cut about {:.3} mm below the model (the most at X{:.3} Y{:.3}), more than --gouge-tol {gouge_tol}; a \
             finer pitch there, or --between bound (the highest surface the readings allow: it leaves {:.3} mm \
             between readings on a flat)",
            b.points,
            b.depth,
            b.at[0],
            b.at[1],
            stylus.height(0.5 * pitch)
        )
    });
    tight.into_iter().chain(bend).collect()
}

/// `v` if it is a length (the data's pitch sets the defaults).
fn length(what: &str, v: f64) -> Result<f64, Error> {
    kezuri_geom::limits::length(v, what).map_err(|m| Error::new(ErrorKind::Option, m))
}

/// Mills the copy of `job`, telling `on` how many rows are done of how
/// many. Errors about the readings (the surface they cannot make) are of
/// kind [`ErrorKind::Surface`].
pub fn copy(job: &Job, on: &Progress) -> Result<Copied, Error> {
    let (data, stylus, cutter) = (job.data, job.stylus, job.cutter);
    let g = data.grid;
    let pitch = g.pitch;
    let stepover = length("--stepover", job.stepover.unwrap_or(pitch))?;
    // The stylus's own ball follows the surface between the readings at a
    // quarter of the pitch: straight lines from reading to reading (--step
    // the pitch) cut p²/(8ρ) into a ridge of radius ρ (docs/probe-copy.md).
    let follows = job.between == Between::Smooth && cutter == stylus;
    let step = length("--step", job.step.unwrap_or(if follows { pitch / 4.0 } else { pitch }))?;
    let resolution = length("--res", job.resolution.unwrap_or(pitch / 8.0))?;
    let top = data.range().1;
    let smooth = match job.between {
        Between::Smooth => Some(Smooth::new(data)?),
        Between::Bound => None,
    };
    // The stylus's own shape follows the smooth surface itself (or the
    // straight line between readings where that is higher); any other
    // cutter (and every cutter with --between bound) is placed on a fine
    // sampling of the surface with drop-cutter.
    let follow = smooth.as_ref().filter(|_| follows);
    let field = match (&smooth, follow) {
        (_, Some(_)) => None,
        (Some(s), None) => Some(model(s, &stylus, resolution)),
        (None, _) => Some(reconstruct(data, &stylus, resolution)),
    }
    .transpose()?;
    let tight = match (&smooth, stylus) {
        (Some(s), Cutter::Ball(_)) => s.tighter_than(stylus.radius()),
        _ => None,
    };
    let bend = smooth.as_ref().and_then(|_| sharpest_bend(data, job.gouge_tol));
    let options = RasterOptions {
        direction: Direction::X,
        pattern: Pattern::ZigZag,
        stepover,
        step,
        tolerance: job.gouge_tol,
        gouge: job.gouge_tol,
        // Bound: positions on the output grid and heights rounded up to it
        // (never below the bound); smooth: exact positions, the writer
        // rounds to the nearest.
        quantum: match job.between {
            Between::Bound => job.quantum,
            Between::Smooth => 0.0,
        },
        safe_z: job.safe_z.unwrap_or(top + 5.0),
        feed: job.feed,
        plunge_feed: job.plunge_feed,
        speed: job.speed,
        tool: job.tool,
    };
    if options.safe_z <= top {
        return Err(Error::new(
            ErrorKind::Option,
            format!(
                "--safe-z {} is not above the data's top, z = {top}: rapids would run into the part",
                options.safe_z
            ),
        ));
    }
    let flat = match job.floor {
        Floor::Off => None,
        Floor::Auto => detect_flat(data, FLAT_TOLERANCE, FLAT_SHARE),
        Floor::At(z) => Some(z),
    };
    // Over the flat margin, which becomes rapids, a bound of the cutter's
    // location serves: no drop-cutter there.
    let over_flat = flat.map(|z| OverFlat::new(data, &stylus, z, FLAT_TOLERANCE));
    let flat_at = |x: f64, y: f64| over_flat.as_ref().and_then(|f| f.height(x, y));
    // With --step the pitch, straight from reading to reading along the rows.
    let straight = (step - pitch).abs() <= 1e-9 * pitch;
    let on_tip = |s: &Smooth, x: f64, y: f64| if straight { s.chord(x, y) } else { s.over_chord(x, y) };
    let cl = |x: f64, y: f64| {
        flat_at(x, y).or_else(|| match (follow, &field) {
            (Some(s), _) => Some(on_tip(s, x, y)),
            (None, Some(f)) => drop_cutter(&cutter, f, x, y),
            (None, None) => None,
        })
    };
    let rows = |f: &Heightfield, along_y: bool, asked: &[(f64, &[f64])]| {
        let mut found = drop_cutter_rows(&cutter, f, along_y, asked);
        for (&(v, us), zs) in asked.iter().zip(&mut found) {
            for (&u, z) in us.iter().zip(zs) {
                let (x, y) = if along_y { (v, u) } else { (u, v) };
                *z = flat_at(x, y).or(*z);
            }
        }
        found
    };
    let on_field =
        field.as_ref().filter(|_| rows_at_once(&cutter)).map(|f| move |a: bool, q: &[(f64, &[f64])]| rows(f, a, q));
    let rows_at = on_field.as_ref().map(|r| r as &ClRowsFn);
    let region = Region { x0: g.origin[0], y0: g.origin[1], x1: g.x(g.nx - 1), y1: g.y(g.ny - 1) };
    let path = raster_with(&cl, rows_at, region, &options, None, on)?;
    let (path, flat) = match flat {
        Some(z) => {
            let min_length = 2.0 * pitch.max(step);
            let (path, margins) =
                rapid_margins(&path, z, job.gouge_tol.max(1e-3), job.clearance, min_length, job.plunge_feed);
            (path, Some((z, margins)))
        }
        None => (path, None),
    };
    if path.moves.iter().any(|m| m.kind == MoveKind::Rapid && m.end.z > options.safe_z + 1e-9) {
        return Err(Error::new(
            ErrorKind::Option,
            format!("--clearance {} lifts rapids above --safe-z {}", job.clearance, options.safe_z),
        ));
    }
    let surface = match (&field, job.between) {
        (Some(f), Between::Bound) => Surface::Bound { nodes: [f.nx(), f.ny()], step: f.step() },
        (Some(f), Between::Smooth) => Surface::Model { nodes: [f.nx(), f.ny()], step: f.step() },
        (None, _) => Surface::Followed,
    };
    let warnings = warnings(&stylus, tight, bend, job.gouge_tol, pitch);
    Ok(Copied { path, stepover, safe_z: options.safe_z, surface, flat, warnings })
}
