//! Material-removal simulation: a Z-map of 3-axis cutting.
//!
//! The stock is a grid of cells ([`ZMap`]), one height per cell centre,
//! starting at the stock top. Every move of a [`Toolpath`] lowers each cell
//! to the lower envelope of the cutter swept along it — rapids too, since a
//! rapid moves the same cutter: a rapid that lowers a cell by more than
//! [`SimOptions::rapid_tolerance`] is reported ([`RapidHit`]), which is the
//! safety check a simulation is for. What the cutter occupies at a rapid's
//! start is not the rapid's doing (it stood there already), so lifting out
//! of a cut, or out of the stock where a program starts, is no crash.
//!
//! # Exactness
//! - **Straight moves exactly.** At each cell centre the envelope of one
//!   straight move is the minimum of a convex function of one variable (the
//!   convex profile composed with the convex distance, plus the linear tip
//!   height), found in closed form for ball, oval and flat cutters and by a
//!   bracketed bisection for bull-nose and V-bits; see the `sweep` module
//!   (`sim/sweep.rs`). The result is the true envelope at the cell centre,
//!   to rounding — not a sampling along the move.
//! - **Arcs within a chord tolerance.** An arc (any plane, helical too) is
//!   split into straight chords whose sagitta is at most
//!   [`SimOptions::chord_tolerance`], the chord ends on the arc; the
//!   simulated surface is then that of the chords, at most the tolerance
//!   from the true arc's in XY.
//! - **Cells, not the continuum.** A Z-map knows the surface at the cell
//!   centres only: a feature narrower than a cell can fall between centres.
//! - **3 axes.** A B C are ignored (moves that turn them are counted in
//!   [`SimReport::rotary_moves`]); the cutter axis is Z.
//!
//! # Measured tools
//! [`simulate_tool`] also cuts with a [`MeasuredTool`], the profile a worn
//! (or eccentric: the profile is the swept envelope) tool was measured to
//! have ([`kezuri_geom::ToolProfile`]). Its lower surface is piecewise
//! linear in the radius but not convex; the envelope is still exact at the
//! cell centres, the least over its linear pieces (`sim/measured.rs`).
//! Above the last sample the tool is taken as a cylinder of its widest
//! measured radius; below the first there is none, so a worn tip cuts less
//! deep.
//!
//! # Speed
//! The grid is cut into bands of rows, processed in parallel (rayon); each
//! band runs, in program order, only the segments whose footprint (segment
//! grown by the cutter radius) meets it, and within a row only the cells of
//! the footprint's exact X interval. The closed-form kernel is branch-free
//! and vectorises (AVX2 where the CPU has it, same results bit for bit).
//! Since the envelope is a minimum, bands are independent and the result
//! does not depend on the number of threads.
//!
//! # Example
//! ```
//! use kezuri_cam::sim::{simulate, SimOptions, Stock, ZMap};
//! use kezuri_cam::Cutter;
//! use kezuri_geom::{Axes, Move, MoveKind, Toolpath};
//! let at = |x, y, z| Axes { x, y, z, ..Axes::ZERO };
//! let path = Toolpath::from(vec![Move {
//!     kind: MoveKind::Feed,
//!     start: at(2.0, 5.0, -1.0),
//!     end: at(8.0, 5.0, -1.0),
//!     ..Move::default()
//! }]);
//! let ball: Cutter = "ball:4".parse().unwrap();
//! let stock = Stock { x0: 0.0, y0: 0.0, x1: 10.0, y1: 10.0, top: 0.0 };
//! let options = SimOptions::new(0.5);
//! let mut zmap = ZMap::new(&stock, &options).unwrap();
//! let report = simulate(&path, &ball, &mut zmap, &options).unwrap();
//! assert_eq!(report.moves, 1);
//! // The cell centred on (5.25, 5.25): 0.25 mm off the line's axis.
//! let (i, j) = (10, 10);
//! let want = -1.0 + 2.0 - (4.0f64 - 0.0625).sqrt();
//! // Heights are kept to the nanometre.
//! assert!((zmap.height(i, j) - want).abs() <= 0.5e-6);
//! ```

pub mod compare;
pub mod measured;
mod segments;
pub mod stock;
mod stream;
pub mod sweep;
pub mod tiles;
pub mod tools;

use std::fmt;
use std::sync::atomic::{AtomicU64, Ordering};

use kezuri_geom::{limits, Toolpath};
use rayon::prelude::*;

use crate::error::{Error, ErrorKind};
use crate::Cutter;
pub use measured::MeasuredTool;
use segments::{first_tool, Segment};
use stock::round_nm;
pub use stock::{
    from_nm, sideways_top, to_nm, Cylinder, Extent, Grid, Start, Stock, ZMap, CELL_BYTES, HIGHEST, LOWEST,
};
pub use stream::{Cuts, Cutting};
use sweep::{cell_range, Band, Prep, Reach, Shape};
pub use tiles::{cut_tiles, simulate_tiles, tile_rows};
pub use tools::{cutting_tools, ToolCut, Tooling, UNCUT};
use tools::{Ledger, Window};

/// What cuts: a nominal cutter or a measured tool.
#[derive(Clone, Debug, PartialEq)]
pub enum Tool {
    /// A cutter by its nominal geometry (a `SPEC` such as `ball:6`).
    Cutter(Cutter),
    /// A tool as measured.
    Measured(MeasuredTool),
}

impl Tool {
    /// The radius the tool reaches, mm.
    pub fn radius(&self) -> f64 {
        match self {
            Tool::Cutter(c) => c.radius(),
            Tool::Measured(m) => m.radius(),
        }
    }

    /// A drill (`drill:D,ANGLE`): it cuts along its axis only.
    pub fn is_drill(&self) -> bool {
        matches!(self, Tool::Cutter(c) if c.is_drill())
    }

    fn shape(&self) -> Shape<'_> {
        match self {
            Tool::Cutter(c) => Shape::of(c),
            Tool::Measured(m) => Shape::Measured(m),
        }
    }
}

impl From<Cutter> for Tool {
    fn from(c: Cutter) -> Tool {
        Tool::Cutter(c)
    }
}

impl From<MeasuredTool> for Tool {
    fn from(m: MeasuredTool) -> Tool {
        Tool::Measured(m)
    }
}

impl fmt::Display for Tool {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Tool::Cutter(c) => write!(f, "{c}"),
            Tool::Measured(m) => write!(f, "{m}"),
        }
    }
}

/// How to simulate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimOptions {
    /// Cell size in mm (> 0).
    pub resolution: f64,
    /// Largest sagitta of the chords an arc is split into (mm, > 0).
    pub chord_tolerance: f64,
    /// A rapid that lowers some cell by more than this (mm) is a rapid
    /// into the stock.
    pub rapid_tolerance: f64,
    /// Most bytes a grid may take held at once ([`CELL_BYTES`] a cell:
    /// its height and the tool that lowered it last). [`ZMap::new`] refuses
    /// a larger grid; [`simulate_tiles`] cuts it in tiles of this size.
    pub max_memory: u64,
}

impl SimOptions {
    /// Defaults at `resolution`: 1 µm chords, 1 µm rapid tolerance, at most
    /// [`DEFAULT_MEMORY`] for the grid.
    pub fn new(resolution: f64) -> SimOptions {
        SimOptions { resolution, chord_tolerance: 1e-3, rapid_tolerance: 1e-3, max_memory: DEFAULT_MEMORY }
    }
}

/// The memory a grid may take by default: 2 GiB (some 429 million cells).
pub const DEFAULT_MEMORY: u64 = 2 << 30;

/// A rapid that cut into the stock.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RapidHit {
    /// Index of the move in the toolpath.
    pub index: usize,
    /// Its source line (0 when generated).
    pub line: u32,
    /// The most it lowered any cell (mm).
    pub depth: f64,
}

/// What a simulation did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SimReport {
    /// Moves that move the tool (every move but dwells).
    pub moves: usize,
    /// Straight segments simulated (arcs split into chords).
    pub segments: usize,
    /// Moves that also turn a rotary axis (simulated in X Y Z only).
    pub rotary_moves: usize,
    /// Rapids (G00, G28, G53) that lowered the stock, in program order.
    pub rapid_hits: Vec<RapidHit>,
    /// Feeds of a drill (`drill:D,ANGLE`) that move in X or Y and lowered
    /// the stock by more than [`SimOptions::rapid_tolerance`]: a drill fed
    /// sideways in material, in program order (the most a cell was lowered
    /// as `depth`).
    pub drill_side_moves: Vec<RapidHit>,
    /// Moves not simulated: returns to the reference point and moves in
    /// machine coordinates (G28, G30, G53: their ends are the machine's
    /// setup, not the model's), and moves that start where the tool's
    /// position is not known ([`Toolpath::unknown_start`]) — before the
    /// program has named X, Y and Z, and after such a return until it
    /// names them again.
    pub unplaced_moves: usize,
    /// Each tool, in the order it first moves: its moves and the material
    /// it removed. The volumes add up to all the material removed.
    pub tools: Vec<ToolCut>,
    /// Per cell (as [`ZMap::nm`]), the index in [`SimReport::tools`] of the
    /// tool whose move lowered it last; [`UNCUT`] where none did.
    pub cut_by: Vec<u8>,
}

/// The chord tolerance `t` is not a length.
fn bad_tolerance(t: f64) -> Error {
    Error::new(ErrorKind::ChordTolerance, limits::length(t, "the chord tolerance").err().unwrap_or_default())
}

/// The memory of a grid of `cells` cells could not be had.
fn out_of_memory(cells: usize) -> Error {
    Error::new(
        ErrorKind::OutOfMemory,
        format!("not enough memory for a grid of {cells} cells ({:.1} GB)", cells as f64 * CELL_BYTES as f64 / 1e9),
    )
}

/// The toolpath has no motion.
fn empty_toolpath() -> Error {
    Error::new(ErrorKind::EmptyToolpath, "the program makes no motion: nothing to simulate")
}

/// Runs the toolpath over `zmap`, lowering it; reports rapids that cut.
pub fn simulate(path: &Toolpath, cutter: &Cutter, zmap: &mut ZMap, options: &SimOptions) -> Result<SimReport, Error> {
    simulate_tool(path, &Tool::Cutter(*cutter), zmap, options)
}

/// [`simulate`] with any [`Tool`]: a nominal cutter or a measured one, for
/// every move whatever tools the program loads.
pub fn simulate_tool(path: &Toolpath, tool: &Tool, zmap: &mut ZMap, options: &SimOptions) -> Result<SimReport, Error> {
    simulate_tools(path, Tooling::One(tool), zmap, options, &|_, _| {})
}

/// Segments cut between two reports of progress.
const PROGRESS_STEP: usize = 1024;

/// [`simulate`] with the tool each move is made by ([`Tooling`]), the
/// volume each tool removed and the tool that last lowered each cell.
/// `progress(done, total)` is told, now and then from the worker threads,
/// how many of the `total` pieces of work are done.
pub fn simulate_tools(
    path: &Toolpath,
    tooling: Tooling<'_>,
    zmap: &mut ZMap,
    options: &SimOptions,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<SimReport, Error> {
    let res = zmap.res;
    let mut cutting = Cutting::new(tooling, zmap, options, Some(first_tool(path)), None)?;
    cutting.progress = progress;
    cutting.add_last(path)?;
    let (cuts, cut_by) = cutting.finish()?;
    Ok(SimReport { cut_by, ..cuts.report(res) })
}

/// What cutting a grid, or a tile of one, found.
#[derive(Clone, Debug, Default)]
struct Cut {
    /// Rapids that cut, one or more per move.
    hits: Vec<RapidHit>,
    /// A drill's sideways feeds that cut.
    sides: Vec<RapidHit>,
    /// What each tool (by slot) removed: whole nanometres of height summed
    /// over the cells, exact whatever the order.
    removed: Vec<i64>,
}

impl Cut {
    /// `other` added: a piece's or a tile's cut to those before it.
    fn add(&mut self, other: Cut) {
        self.hits.extend(other.hits);
        self.sides.extend(other.sides);
        self.removed.resize(self.removed.len().max(other.removed.len()), 0);
        for (a, b) in self.removed.iter_mut().zip(other.removed) {
            *a += b;
        }
    }

    /// Into `report`: the rapids and sideways drill feeds that cut, and
    /// each tool's volume on cells of `res` mm.
    fn into_report(self, report: &mut SimReport, res: f64) {
        for (cut, nm) in report.tools.iter_mut().zip(self.removed) {
            cut.volume = nm as f64 / 1e6 * (res * res);
        }
        report.rapid_hits = merged(self.hits);
        report.drill_side_moves = merged(self.sides);
    }
}

/// Runs `segs` (cut by the tools `shapes` by slot) over `zmap` (a whole
/// grid or a tile of one, its highest cell `top` before the first
/// segment), lowering it; `cut_by` (one per cell of `zmap`) takes the tool
/// that lowered each cell last.
fn cut(
    segs: &[Segment],
    shapes: &[Shape<'_>],
    zmap: &mut ZMap,
    cut_by: &mut [u8],
    options: &SimOptions,
    top: f64,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<Cut, Error> {
    let (nx, ny, res, x0, y0, row0) = (zmap.nx, zmap.ny, zmap.res, zmap.x0, zmap.y0, zmap.first_row);
    let mut cut = Cut { removed: vec![0; shapes.len()], ..Cut::default() };
    if nx == 0 || ny == 0 {
        return Ok(cut);
    }
    // A margin of a millionth of a cell keeps cells on the footprint's edge.
    let margin = 1e-6 * res;

    // Bands of rows; each segment is listed (in order) in every band its
    // footprint meets. Rows are counted over the whole grid (a tile's
    // cell centres are the whole grid's), bands from the first held.
    let threads = rayon::current_num_threads().max(1);
    let band_rows = ny.div_ceil(8 * threads).clamp(1, 32);
    let bands = ny.div_ceil(band_rows);
    let mut reaches = Vec::with_capacity(segs.len());
    let mut cols = Vec::with_capacity(segs.len());
    let mut counts = vec![0u32; bands + 1];
    for s in segs {
        let p = &s.prep;
        let r = shapes[s.slot as usize].radius();
        let (bx, by) = (p.ax + p.ux * p.len, p.ay + p.uy * p.len);
        let xs = cell_range(p.ax.min(bx) - r - margin, p.ax.max(bx) + r + margin, x0, res, nx);
        // A segment at or above every cell cannot cut.
        let rows = if p.z_min() >= top || xs.is_empty() {
            0..0
        } else {
            let rows = cell_range(p.ay.min(by) - r - margin, p.ay.max(by) + r + margin, y0, res, row0 + ny);
            rows.start.max(row0)..rows.end.max(row0)
        };
        if !rows.is_empty() {
            if p.z_min() < LOWEST {
                return Err(too_deep(s));
            }
            for b in (rows.start - row0) / band_rows..=(rows.end - 1 - row0) / band_rows {
                counts[b + 1] += 1;
            }
        }
        reaches.push(Reach { j0: rows.start, j1: rows.end, from: s.from, to: s.to });
        cols.push(xs);
    }
    for b in 0..bands {
        counts[b + 1] += counts[b];
    }
    let mut fill: Vec<u32> = counts[..bands].to_vec();
    let mut listed = vec![0u32; counts[bands] as usize];
    for (k, reach) in reaches.iter().enumerate() {
        if reach.j0 < reach.j1 {
            for b in (reach.j0 - row0) / band_rows..=(reach.j1 - 1 - row0) / band_rows {
                listed[fill[b] as usize] = k as u32;
                fill[b] += 1;
            }
        }
    }
    let xs: Vec<f64> = (0..nx).map(|i| x0 + (i as f64 + 0.5) * res).collect();
    let total = listed.len() as u64;
    let done = AtomicU64::new(0);
    progress(0, total);

    // Each band's rapid hits, drills fed sideways and what each tool removed from it.
    let bands: Vec<Cut> = zmap
        .nm
        .par_chunks_mut(band_rows * nx)
        .zip(cut_by.par_chunks_mut(band_rows * nx))
        .enumerate()
        .map(|(b, (heights, cut_by))| {
            let mut cut = Cut::default();
            let list = &listed[counts[b] as usize..counts[b + 1] as usize];
            if list.is_empty() {
                return cut;
            }
            // The band is cut in mm and rounded to the nanometre once.
            let mut cells: Vec<f64> = heights.iter().map(|&n| from_nm(n)).collect();
            let first = row0 + b * band_rows;
            let last = first + heights.len() / nx;
            let mut band = Band { cells: &mut cells, first, nx, xs: &xs, x0, y0, res };
            let mut ledger = Ledger::new(shapes.len());
            for run in list.chunk_by(|&p, &q| segs[p as usize].slot == segs[q as usize].slot) {
                let slot = segs[run[0] as usize].slot;
                let shape = shapes[slot as usize];
                let reached = run.iter().map(|&k| (reaches[k as usize].j0..reaches[k as usize].j1, &cols[k as usize]));
                let window = Window::around(reached, first..last, nx);
                ledger.open(band.cells, nx, &window);
                for (n, &k) in run.iter().enumerate() {
                    if n % PROGRESS_STEP == PROGRESS_STEP - 1 {
                        let step = PROGRESS_STEP as u64;
                        progress(done.fetch_add(step, Ordering::Relaxed) + step, total);
                    }
                    let s = &segs[k as usize];
                    let reach = &reaches[k as usize];
                    let deepest = match shape {
                        Shape::Closed { r, r2, hs } if s.rapid => {
                            sweep::closed_rows::<true>(&s.prep, r, r2, hs, reach, &mut band)
                        }
                        Shape::Closed { r, r2, hs } => {
                            sweep::closed_rows::<false>(&s.prep, r, r2, hs, reach, &mut band)
                        }
                        Shape::General(c) => sweep::general_rows(&c, &s.prep, reach, &mut band),
                        Shape::Measured(m) => measured::measured_rows(m, &s.prep, reach, &mut band, s.rapid),
                    };
                    let hit = RapidHit { index: s.index as usize, line: s.line, depth: deepest };
                    if s.rapid && deepest > options.rapid_tolerance {
                        cut.hits.push(hit);
                    }
                    if s.side && deepest > options.rapid_tolerance {
                        cut.sides.push(hit);
                    }
                }
                ledger.close(band.cells, cut_by, nx, &window, slot);
                let n = (run.len() % PROGRESS_STEP) as u64;
                progress(done.fetch_add(n, Ordering::Relaxed) + n, total);
            }
            for (n, &z) in heights.iter_mut().zip(&cells) {
                *n = round_nm(z);
            }
            cut.removed = ledger.removed;
            cut
        })
        .collect();
    for band in bands {
        cut.add(band);
    }
    Ok(cut)
}

/// A segment that goes lower than a cell's height can be kept.
fn too_deep(s: &Segment) -> Error {
    Error::new(
        ErrorKind::HeightRange,
        format!(
            "move {} (line {}) goes down to Z {} mm, below the lowest height the grid keeps ({LOWEST} mm: \
             heights are kept in whole nanometres)",
            s.index, s.line, s.low
        ),
    )
}

/// The bands' hits merged: one per move, the deepest, in program order.
fn merged(mut all: Vec<RapidHit>) -> Vec<RapidHit> {
    all.sort_by(|a, b| a.index.cmp(&b.index).then(b.depth.total_cmp(&a.depth)));
    all.dedup_by_key(|h| h.index);
    all
}

/// The envelope of `cutter` swept in a straight line from tip position `a`
/// to `b`, at `(x, y)`: the lowest height the cutter's lower surface
/// reaches there, or `None` where it does not reach. The same evaluation
/// the simulation runs per cell.
pub fn swept_height(cutter: &Cutter, a: [f64; 3], b: [f64; 3], x: f64, y: f64) -> Option<f64> {
    swept_height_tool(&Tool::Cutter(*cutter), a, b, x, y)
}

/// [`swept_height`] for any [`Tool`].
pub fn swept_height_tool(tool: &Tool, a: [f64; 3], b: [f64; 3], x: f64, y: f64) -> Option<f64> {
    let shape = tool.shape();
    let p = Prep::new(a, b, &shape);
    let z = match shape {
        Shape::Closed { r, r2, hs } => sweep::closed_at(&p, r, r2, hs, x, y - p.ay),
        Shape::General(c) => sweep::general_at(&c, &p, x, y - p.ay, f64::INFINITY).unwrap_or(f64::INFINITY),
        Shape::Measured(m) => measured::measured_at(m, &p, x, y - p.ay, f64::INFINITY).unwrap_or(f64::INFINITY),
    };
    z.is_finite().then_some(z)
}
