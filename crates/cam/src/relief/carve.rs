//! The carving of a relief (`kezuri relief`): roughing in levels where a
//! roughing cutter is given, then raster finishing with drop-cutter on the
//! relief, the mask keeping both to the light of the mask picture, and the
//! check of what the finishing cutter cannot reach.

use kezuri_geom::{Heightfield, Toolpath};

use super::{inside, Gray, Placement};
use crate::dropcut::{drop_cutter, drop_cutter_rows, rows_at_once};
use crate::error::Error;
use crate::mill::reach::{self, unreached, Area, Unreached};
use crate::mill::{raster_with, ClRowsFn, Direction, Pattern, RasterOptions, Region};
use crate::rough::{levels, Levels};
use crate::Cutter;

/// Roughing before the finish: the stock cleared in levels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Roughing {
    /// The roughing cutter (tool 1; the finishing cutter is then tool 2).
    pub cutter: Cutter,
    /// Distance between roughing rows, mm; `None`: 40 % of the cutter's
    /// diameter.
    pub stepover: Option<f64>,
    /// Depth of each level, mm.
    pub step_down: f64,
    /// Material left on the relief for the finish, mm.
    pub allowance: f64,
}

/// A relief to carve. Lengths mm, feeds mm/min.
#[derive(Clone, Copy, Debug)]
pub struct Job<'a> {
    /// The relief (see [`surface`](super::surface)), below the stock top
    /// `z = 0`.
    pub field: &'a Heightfield,
    /// Cut only where this picture (the relief's size) is light.
    pub mask: Option<&'a Gray>,
    /// Where the picture lies.
    pub placement: Placement,
    /// The finishing cutter.
    pub cutter: Cutter,
    /// Which way the finishing rows run.
    pub direction: Direction,
    /// How the rows are linked.
    pub pattern: Pattern,
    /// Distance between finishing rows.
    pub stepover: f64,
    /// Sampling step along a row; `None`: the pixel size, or `quantum`
    /// where the pixel is finer (sampling finer than the program's
    /// increment writes nothing finer).
    pub step: Option<f64>,
    /// How much material the path may leave above the exact cutter
    /// locations.
    pub leave_tol: f64,
    /// How far the path may dip below the exact cutter locations: the
    /// chord between samples is refined until it stays this close.
    pub gouge_tol: f64,
    /// The program's output increment (0: none).
    pub quantum: f64,
    /// Height for rapids, above the stock top.
    pub safe_z: f64,
    /// Cutting feed.
    pub feed: f64,
    /// Plunge feed.
    pub plunge_feed: f64,
    /// Spindle speed, rpm.
    pub speed: f64,
    /// Roughing first, where given.
    pub rough: Option<Roughing>,
}

impl Job<'_> {
    /// How far the finishing path may dip below the exact cutter
    /// locations: the gouge allowance, within the leave tolerance.
    pub fn gouge(&self) -> f64 {
        self.gouge_tol.min(self.leave_tol)
    }
}

/// A stage of the carving.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Roughing in levels.
    Rough,
    /// Raster finishing.
    Finish,
}

impl Stage {
    /// `rough` or `finish`.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Rough => "rough",
            Stage::Finish => "finish",
        }
    }
}

/// What [`carve`] tells as it goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Event {
    /// `done` of the stage's `total` rows are done.
    Rows {
        /// The stage.
        stage: Stage,
        /// Rows done so far.
        done: usize,
        /// Rows in all.
        total: usize,
    },
    /// The stage is over.
    Done(Stage),
}

/// The carving and what its finishing cutter cannot reach.
#[derive(Clone, Debug)]
pub struct Carved {
    /// Roughing (tool 1) then finishing (tool 2; tool 1 without roughing).
    pub path: Toolpath,
    /// Where the finishing cutter leaves more than `threshold` on the
    /// relief: valleys narrower than the cutter.
    pub unreached: Option<Unreached>,
    /// Material left that counts as unreached, mm.
    pub threshold: f64,
}

/// Carves `job`, telling `on` how far it is.
pub fn carve(job: &Job, on: &(dyn Fn(Event) + Sync)) -> Result<Carved, Error> {
    let (field, cutter, placement, masked) = (job.field, job.cutter, job.placement, job.mask);
    let [x0, y0, x1, y1] = field.xy_box();
    let region = Region { x0, y0, x1, y1 };
    let finish = RasterOptions {
        direction: job.direction,
        pattern: job.pattern,
        stepover: job.stepover,
        // Sampling finer than the program's increment writes nothing finer.
        step: job.step.unwrap_or(placement.pixel.max(job.quantum)),
        tolerance: job.leave_tol,
        gouge: job.gouge(),
        quantum: job.quantum,
        safe_z: job.safe_z,
        feed: job.feed,
        plunge_feed: job.plunge_feed,
        speed: job.speed,
        tool: if job.rough.is_some() { 2 } else { 1 },
    };
    let cl_of = |c: Cutter| {
        move |x: f64, y: f64| if inside(masked, placement, x, y) { drop_cutter(&c, field, x, y) } else { None }
    };
    // The same, whole rows at once (drop_cutter_rows: a ball row by row).
    let rows_of = |c: Cutter| {
        move |along_y: bool, asked: &[(f64, &[f64])]| {
            let mut found = drop_cutter_rows(&c, field, along_y, asked);
            for (&(v, us), zs) in asked.iter().zip(&mut found) {
                for (&u, z) in us.iter().zip(zs) {
                    let (x, y) = if along_y { (v, u) } else { (u, v) };
                    if !inside(masked, placement, x, y) {
                        *z = None;
                    }
                }
            }
            found
        }
    };
    let rows = |stage: Stage| move |done: usize, total: usize| on(Event::Rows { stage, done, total });
    let mut path = Toolpath::default();
    if let Some(r) = job.rough {
        let options = RasterOptions { stepover: r.stepover.unwrap_or(0.8 * r.cutter.radius()), tool: 1, ..finish };
        let l = Levels { top: 0.0, step_down: r.step_down, allowance: r.allowance };
        path = levels(&cl_of(r.cutter), region, &options, l, &rows(Stage::Rough))?;
        on(Event::Done(Stage::Rough));
    }
    let finish_rows = rows_of(cutter);
    let rows_at = rows_at_once(&cutter).then_some(&finish_rows as &ClRowsFn);
    let finishing = raster_with(&cl_of(cutter), rows_at, region, &finish, None, &rows(Stage::Finish))?;
    on(Event::Done(Stage::Finish));
    path.moves.extend(finishing.moves);
    // What the finishing cutter cannot reach, at any stepover.
    // Cutter locations a fifth of the radius apart: the sketch 200 mm wide
    // with ball:12 carves in 0.03 s and the check adds 0.035 s (0.06 s at a
    // tenth of the radius); the scallop that grid leaves on the flat,
    // step²/8R, is forgiven on top of the threshold.
    let step = placement.pixel.max(cutter.radius() / 5.0);
    let threshold = reach::threshold(job.leave_tol, step, cutter.radius());
    let area = Area { bounds: field.xy_box(), inset: 0.0, step };
    let unreached = unreached(area, &cutter, threshold, |x, y| field.z_at(x, y), cl_of(cutter));
    Ok(Carved { path, unreached, threshold })
}
