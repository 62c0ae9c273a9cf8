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
//! assert!((zmap.height(i, j) - want).abs() < 1e-12);
//! ```

pub mod compare;
pub mod measured;
pub mod sweep;

use std::fmt;

use kezuri_geom::{MoveKind, Toolpath};
use rayon::prelude::*;

use crate::Cutter;
pub use measured::MeasuredTool;
use sweep::{cell_range, Band, Prep, Reach, Shape};

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

/// The stock box: `x0..x1` × `y0..y1` in XY (mm), its top at `top`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stock {
    /// Lowest X.
    pub x0: f64,
    /// Lowest Y.
    pub y0: f64,
    /// Highest X.
    pub x1: f64,
    /// Highest Y.
    pub y1: f64,
    /// Height of the top face.
    pub top: f64,
}

impl Stock {
    /// The stock a program implies: the XY bounds of its cutting moves
    /// (feeds, arcs, probes) grown by the cutter radius, the top at their
    /// highest point. Rapids are left out: a return to a far home position
    /// must not grow the grid, and a rapid approach to just above the
    /// work must not count as cutting. Without cutting moves, all moves.
    pub fn around(path: &Toolpath, cutter: &Cutter) -> Result<Stock, SimError> {
        Stock::around_tool(path, &Tool::Cutter(*cutter))
    }

    /// [`Stock::around`] for any [`Tool`]: the cutting moves' box grown by
    /// the tool's radius.
    pub fn around_tool(path: &Toolpath, tool: &Tool) -> Result<Stock, SimError> {
        let cutting: Vec<_> =
            path.moves.iter().filter(|m| !m.is_rapid() && !matches!(m.kind, MoveKind::Dwell(_))).copied().collect();
        let bounds = if cutting.is_empty() { path.bounds() } else { Toolpath::from(cutting).bounds() };
        let (lo, hi) = bounds.ok_or(SimError::EmptyToolpath)?;
        if !lo.iter().chain(&hi).all(|v| v.is_finite()) {
            return Err(SimError::BadStock("the program's bounds are not finite".into()));
        }
        let r = tool.radius();
        Ok(Stock { x0: lo[0] - r, y0: lo[1] - r, x1: hi[0] + r, y1: hi[1] + r, top: hi[2] })
    }

    fn check(&self) -> Result<(), SimError> {
        let v = [self.x0, self.y0, self.x1, self.y1, self.top];
        if !v.iter().all(|v| v.is_finite()) {
            return Err(SimError::BadStock(format!("{:?} is not finite", v)));
        }
        if !(self.x1 > self.x0 && self.y1 > self.y0) {
            return Err(SimError::BadStock(format!(
                "empty box: X {} to {}, Y {} to {} (need X0 < X1 and Y0 < Y1)",
                self.x0, self.x1, self.y0, self.y1
            )));
        }
        Ok(())
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
    /// Most cells a grid may have (memory: 8 bytes a cell).
    pub max_cells: usize,
}

impl SimOptions {
    /// Defaults at `resolution`: 1 µm chords, 1 µm rapid tolerance, at most
    /// 250 million cells (2 GB).
    pub fn new(resolution: f64) -> SimOptions {
        SimOptions { resolution, chord_tolerance: 1e-3, rapid_tolerance: 1e-3, max_cells: 250_000_000 }
    }
}

/// A height per cell: cell `(i, j)` is centred at
/// `(x0 + (i + ½)·res, y0 + (j + ½)·res)`; rows of constant `j` are
/// contiguous in `z`.
#[derive(Clone, Debug, PartialEq)]
pub struct ZMap {
    /// X of the grid's left edge.
    pub x0: f64,
    /// Y of the grid's bottom edge.
    pub y0: f64,
    /// Cell size.
    pub res: f64,
    /// Cells along X.
    pub nx: usize,
    /// Cells along Y.
    pub ny: usize,
    /// Heights, `z[j·nx + i]`.
    pub z: Vec<f64>,
}

impl ZMap {
    /// The stock as a grid at `options.resolution`, every cell at the top.
    /// The grid covers the box, the last cell reaching past its edge when
    /// the size is not a whole number of cells.
    pub fn new(stock: &Stock, options: &SimOptions) -> Result<ZMap, SimError> {
        let res = options.resolution;
        if !(res.is_finite() && res > 0.0) {
            return Err(SimError::BadResolution(res));
        }
        if !(options.chord_tolerance.is_finite() && options.chord_tolerance > 0.0) {
            return Err(SimError::BadTolerance(options.chord_tolerance));
        }
        stock.check()?;
        let count = |len: f64| {
            let n = len / res;
            // 100 / 0.05 is 2000.0000000000002: a whole number of cells.
            if (n - n.round()).abs() <= 1e-9 * n.max(1.0) {
                n.round().max(1.0)
            } else {
                n.ceil()
            }
        };
        let (fx, fy) = (count(stock.x1 - stock.x0), count(stock.y1 - stock.y0));
        let cells = fx * fy;
        if cells > options.max_cells as f64 {
            return Err(SimError::TooManyCells { nx: fx, ny: fy, limit: options.max_cells });
        }
        let (nx, ny) = (fx as usize, fy as usize);
        let mut z = Vec::new();
        if z.try_reserve_exact(nx * ny).is_err() {
            return Err(SimError::OutOfMemory { cells: nx * ny });
        }
        z.resize(nx * ny, stock.top);
        Ok(ZMap { x0: stock.x0, y0: stock.y0, res, nx, ny, z })
    }

    /// Number of cells.
    pub fn cells(&self) -> usize {
        self.nx * self.ny
    }

    /// Centre of cell `(i, j)`.
    pub fn centre(&self, i: usize, j: usize) -> [f64; 2] {
        [self.x0 + (i as f64 + 0.5) * self.res, self.y0 + (j as f64 + 0.5) * self.res]
    }

    /// Height of cell `(i, j)`.
    pub fn height(&self, i: usize, j: usize) -> f64 {
        self.z[j * self.nx + i]
    }

    /// Lowest and highest cell.
    pub fn range(&self) -> (f64, f64) {
        self.z.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &z| (lo.min(z), hi.max(z)))
    }
}

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
    /// Moves not simulated: returns to the reference point and moves in
    /// machine coordinates (G28, G30, G53: their ends are the machine's
    /// setup, not the model's), and moves that start where the tool's
    /// position is not known ([`Toolpath::unknown_start`]) — before the
    /// program has named X, Y and Z, and after such a return until it
    /// names them again.
    pub unplaced_moves: usize,
}

/// Why a simulation cannot run.
#[derive(Clone, Debug, PartialEq)]
pub enum SimError {
    /// The cell size is not a positive number.
    BadResolution(f64),
    /// The chord tolerance is not a positive number.
    BadTolerance(f64),
    /// The stock box is empty or not finite.
    BadStock(String),
    /// The toolpath has no motion.
    EmptyToolpath,
    /// The grid would have more cells than allowed.
    TooManyCells {
        /// Cells along X.
        nx: f64,
        /// Cells along Y.
        ny: f64,
        /// The limit.
        limit: usize,
    },
    /// The grid's memory could not be had.
    OutOfMemory {
        /// Cells asked for.
        cells: usize,
    },
    /// A move has a coordinate that is not finite.
    NonFinite {
        /// Index of the move.
        index: usize,
        /// Its source line.
        line: u32,
    },
    /// Arcs split into more chords than can be indexed.
    TooManySegments(usize),
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimError::BadResolution(r) => write!(f, "the resolution must be a positive number of mm, got {r}"),
            SimError::BadTolerance(t) => write!(f, "the chord tolerance must be a positive number of mm, got {t}"),
            SimError::BadStock(why) => write!(f, "bad stock: {why}"),
            SimError::EmptyToolpath => write!(f, "the program makes no motion: nothing to simulate"),
            SimError::TooManyCells { nx, ny, limit } => write!(
                f,
                "a grid of {nx} × {ny} = {:.0} cells ({:.1} GB) is more than the limit of {limit} cells; \
                 use a coarser resolution or a smaller stock",
                nx * ny,
                nx * ny * 8.0 / 1e9
            ),
            SimError::OutOfMemory { cells } => {
                write!(f, "not enough memory for a grid of {cells} cells ({:.1} GB)", *cells as f64 * 8.0 / 1e9)
            }
            SimError::NonFinite { index, line } => {
                write!(f, "move {index} (line {line}) has a coordinate that is not a finite number")
            }
            SimError::TooManySegments(n) => {
                write!(f, "arcs split into {n} chords, too many: raise the chord tolerance")
            }
        }
    }
}

impl std::error::Error for SimError {}

/// A straight piece of a move.
#[derive(Clone, Copy, Debug)]
struct Segment {
    prep: Prep,
    /// Index of the move it belongs to.
    index: u32,
    rapid: bool,
    /// The slab `from ≤ s ≤ to` of along-track distances whose cells this
    /// segment evaluates (see [`continuations`]).
    from: f64,
    to: f64,
    a: [f64; 3],
    b: [f64; 3],
}

/// Narrows each cutting segment's slab where the path runs straight on.
///
/// Where a cell lies behind a segment's start (`s < 0`) and the tip does
/// not descend (`Δz ≥ 0`), the envelope's minimum over the segment is at
/// its start: the derivative `−g + height'(ρ)·σ/ρ` is ≤ 0 for every
/// `σ ≤ s ≤ 0`. Likewise ahead of its end when it does not climb. For the
/// closed-form shapes the bound is sharper: the minimum is at the start
/// when `s ≤ q·k`, so when `s ≤ min(0, k·R)`. So where the previous segment
/// ends exactly at this one's start and runs in the same XY direction, the
/// cells behind `min(0, k·R)` (−R when descending, for the general shapes;
/// for a measured tool the bound from its flattest slope,
/// [`MeasuredTool::monotone_beyond`]) are cut at least as deep by the
/// previous segment through that shared point, and the same holds ahead of
/// the end. Following such cells from
/// segment to segment always ends at one that evaluates them (the same
/// direction means "behind this one's start" is never "ahead of the
/// previous one's end"), so the result is unchanged while a raster move
/// of 0.1 mm with a 6 mm ball evaluates a slab of about 0.7 mm instead of
/// its whole 6.1 mm footprint. Rapids are never narrowed, so each rapid is
/// judged on everything it cuts.
fn continuations(segs: &mut [Segment], shape: &Shape<'_>) {
    let r = shape.radius();
    let eps = 1e-9 * (1.0 + r);
    let joined = |p: &Segment, q: &Segment| {
        !p.rapid
            && !q.rapid
            && p.b == q.a
            && p.prep.len > 0.0
            && q.prep.len > 0.0
            && (p.prep.ux - q.prep.ux).abs() <= 1e-12
            && (p.prep.uy - q.prep.uy).abs() <= 1e-12
    };
    for k in 0..segs.len() {
        let p = segs[k].prep;
        let (back, ahead) = match shape {
            Shape::Closed { .. } => ((p.k * r).min(0.0), (p.k * r).max(0.0)),
            Shape::General(_) => (if p.dz < 0.0 { -r } else { 0.0 }, if p.dz > 0.0 { r } else { 0.0 }),
            Shape::Measured(m) => {
                let d = if p.dz == 0.0 { 0.0 } else { m.monotone_beyond(p.dz.abs() * p.inv_len) };
                (if p.dz < 0.0 { -d } else { 0.0 }, if p.dz > 0.0 { d } else { 0.0 })
            }
        };
        if k > 0 && joined(&segs[k - 1], &segs[k]) {
            segs[k].from = back - eps;
        }
        if k + 1 < segs.len() && joined(&segs[k], &segs[k + 1]) {
            segs[k].to = p.len + ahead + eps;
        }
    }
}

/// The chords of an arc: `n` with sagitta ≤ `tol` (at least 1, at most 10⁷).
fn chords(radius: f64, sweep: f64, tol: f64) -> usize {
    if radius <= tol {
        return ((sweep / std::f64::consts::PI).ceil() as usize).max(1);
    }
    let step = 2.0 * (1.0 - tol / radius).acos();
    ((sweep / step).ceil().max(1.0) as usize).min(10_000_000)
}

/// Splits the toolpath into straight segments (program order).
/// The straight segments to simulate, the report so far, and the rapids
/// whose start is not known (see [`SimReport::unplaced_moves`]).
#[allow(clippy::type_complexity)]
fn segments(path: &Toolpath, shape: &Shape<'_>, tol: f64) -> Result<(Vec<Segment>, SimReport, Vec<usize>), SimError> {
    let mut out = Vec::with_capacity(path.moves.len());
    let mut report = SimReport::default();
    // Axes (X Y Z bits) whose position is known: none at the start of an
    // NC program, where the start is only the interpreter's assumption.
    let mut known = if path.unknown_start { 0u8 } else { 0b111 };
    let mut unplaced_rapids = Vec::new();
    for (index, m) in path.moves.iter().enumerate() {
        if matches!(m.kind, MoveKind::Dwell(_)) {
            continue;
        }
        if !m.start.to_array().iter().chain(&m.end.to_array()).all(|v| v.is_finite()) {
            return Err(SimError::NonFinite { index, line: m.line });
        }
        report.moves += 1;
        // A return to the reference point (G28, G30) and a move in machine
        // coordinates (G53) go where the machine's setup puts them, which
        // the model only guesses: not simulated, and the axes they move
        // are unknown until the program names them again.
        let to_machine = matches!(m.kind, MoveKind::Home | MoveKind::Machine);
        let placed = known & 0b111 == 0b111 && !to_machine;
        known = if to_machine { known & !m.named.0 } else { known | m.named.0 };
        if !placed {
            report.unplaced_moves += 1;
            if m.is_rapid() && !to_machine {
                unplaced_rapids.push(index);
            }
            continue;
        }
        if (m.start.a, m.start.b, m.start.c) != (m.end.a, m.end.b, m.end.c) {
            report.rotary_moves += 1;
        }
        let index32 = u32::try_from(index).map_err(|_| SimError::TooManySegments(index))?;
        let rapid = m.is_rapid();
        let r = shape.radius();
        let mut push = |a: [f64; 3], b: [f64; 3]| {
            let prep = Prep::new(a, b, shape);
            out.push(Segment { prep, index: index32, rapid, from: -r, to: prep.len + r, a, b })
        };
        match m.kind {
            MoveKind::Arc(arc) => {
                let n = chords(arc.radius(m.start), arc.sweep(m.start, m.end), tol);
                let mut a = m.start.xyz();
                for k in 1..=n {
                    let b = if k == n { m.end.xyz() } else { arc.point_at(m.start, m.end, k as f64 / n as f64).xyz() };
                    push(a, b);
                    a = b;
                }
            }
            _ => push(m.start.xyz(), m.end.xyz()),
        }
        if out.len() > u32::MAX as usize {
            return Err(SimError::TooManySegments(out.len()));
        }
    }
    if report.moves == 0 {
        return Err(SimError::EmptyToolpath);
    }
    report.segments = out.len();
    continuations(&mut out, shape);
    Ok((out, report, unplaced_rapids))
}

/// Runs the toolpath over `zmap`, lowering it; reports rapids that cut.
pub fn simulate(
    path: &Toolpath,
    cutter: &Cutter,
    zmap: &mut ZMap,
    options: &SimOptions,
) -> Result<SimReport, SimError> {
    simulate_tool(path, &Tool::Cutter(*cutter), zmap, options)
}

/// [`simulate`] with any [`Tool`]: a nominal cutter or a measured one.
pub fn simulate_tool(
    path: &Toolpath,
    tool: &Tool,
    zmap: &mut ZMap,
    options: &SimOptions,
) -> Result<SimReport, SimError> {
    if !(options.chord_tolerance.is_finite() && options.chord_tolerance > 0.0) {
        return Err(SimError::BadTolerance(options.chord_tolerance));
    }
    let shape = tool.shape();
    let r = shape.radius();
    let (segs, mut report, unplaced_rapids) = segments(path, &shape, options.chord_tolerance)?;
    let (nx, ny, res, x0, y0) = (zmap.nx, zmap.ny, zmap.res, zmap.x0, zmap.y0);
    if nx == 0 || ny == 0 {
        return Ok(report);
    }
    let top = zmap.range().1;
    // A margin of a millionth of a cell keeps cells on the footprint's edge.
    let margin = 1e-6 * res;

    // Bands of rows; each segment is listed (in order) in every band its
    // footprint meets.
    let threads = rayon::current_num_threads().max(1);
    let band_rows = ny.div_ceil(8 * threads).clamp(1, 32);
    let bands = ny.div_ceil(band_rows);
    let mut reaches = Vec::with_capacity(segs.len());
    let mut counts = vec![0u32; bands + 1];
    for s in &segs {
        let p = &s.prep;
        let (bx, by) = (p.ax + p.ux * p.len, p.ay + p.uy * p.len);
        let xs = cell_range(p.ax.min(bx) - r - margin, p.ax.max(bx) + r + margin, x0, res, nx);
        // A segment at or above every cell cannot cut.
        let rows = if p.z_min() >= top || xs.is_empty() {
            0..0
        } else {
            cell_range(p.ay.min(by) - r - margin, p.ay.max(by) + r + margin, y0, res, ny)
        };
        if !rows.is_empty() {
            for b in rows.start / band_rows..=(rows.end - 1) / band_rows {
                counts[b + 1] += 1;
            }
        }
        reaches.push(Reach { j0: rows.start, j1: rows.end, from: s.from, to: s.to });
    }
    for b in 0..bands {
        counts[b + 1] += counts[b];
    }
    let mut fill: Vec<u32> = counts[..bands].to_vec();
    let mut listed = vec![0u32; counts[bands] as usize];
    for (k, reach) in reaches.iter().enumerate() {
        if reach.j0 < reach.j1 {
            for b in reach.j0 / band_rows..=(reach.j1 - 1) / band_rows {
                listed[fill[b] as usize] = k as u32;
                fill[b] += 1;
            }
        }
    }
    let xs: Vec<f64> = (0..nx).map(|i| x0 + (i as f64 + 0.5) * res).collect();

    let hits: Vec<Vec<(u32, f64)>> = zmap
        .z
        .par_chunks_mut(band_rows * nx)
        .enumerate()
        .map(|(b, cells)| {
            let mut band = Band { cells, first: b * band_rows, nx, xs: &xs, x0, y0, res };
            let mut hits: Vec<(u32, f64)> = Vec::new();
            for &k in &listed[counts[b] as usize..counts[b + 1] as usize] {
                let s = &segs[k as usize];
                let reach = &reaches[k as usize];
                let deepest = match shape {
                    Shape::Closed { r, r2, hs } if s.rapid => {
                        sweep::closed_rows::<true>(&s.prep, r, r2, hs, reach, &mut band)
                    }
                    Shape::Closed { r, r2, hs } => sweep::closed_rows::<false>(&s.prep, r, r2, hs, reach, &mut band),
                    Shape::General(c) => sweep::general_rows(&c, &s.prep, reach, &mut band),
                    Shape::Measured(m) => measured::measured_rows(m, &s.prep, reach, &mut band, s.rapid),
                };
                if s.rapid && deepest > options.rapid_tolerance {
                    hits.push((s.index, deepest));
                }
            }
            hits
        })
        .collect();

    // Merge the bands' hits: one per move, the deepest.
    let mut all: Vec<(u32, f64)> = hits.into_iter().flatten().collect();
    // A rapid from an unknown position is not simulated, but if it ends
    // inside the stock it went through it.
    for index in unplaced_rapids {
        let e = path.moves[index].end;
        let (i, j) = (((e.x - x0) / res).floor(), ((e.y - y0) / res).floor());
        if i >= 0.0 && j >= 0.0 && (i as usize) < nx && (j as usize) < ny && e.z < top - options.rapid_tolerance {
            all.push((index as u32, top - e.z));
        }
    }
    all.sort_by(|a, b| a.0.cmp(&b.0).then(b.1.total_cmp(&a.1)));
    all.dedup_by_key(|h| h.0);
    report.rapid_hits = all
        .into_iter()
        .map(|(index, depth)| RapidHit { index: index as usize, line: path.moves[index as usize].line, depth })
        .collect();
    Ok(report)
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
