//! The stock: a box, an upright cylinder or the top surface of a solid,
//! as the Z-map's starting heights.
//!
//! A Z-map holds one height per cell: it has no undercuts, so a stock is
//! what is seen of it from above. Where a cylinder or a solid does not
//! reach, the cells start at its bottom: there is no stock above it.

use std::ops::Range;

use kezuri_geom::{limits, Move, MoveKind, Toolpath};

use super::compare::target_heights;
use super::{bad_tolerance, empty_toolpath, out_of_memory, SimOptions, Tool};
use crate::error::{Error, ErrorKind};
use crate::Cutter;

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
    /// (feeds, arcs, probes) grown by the cutter radius, the top at the
    /// highest point of the moves that cut sideways ([`cutting_top`]).
    /// Rapids are left out: a return to a far home position must not grow
    /// the grid, and a rapid approach to just above the work must not
    /// count as cutting. Without cutting moves, all moves.
    pub fn around(path: &Toolpath, cutter: &Cutter) -> Result<Stock, Error> {
        Stock::around_tool(path, &Tool::Cutter(*cutter))
    }

    /// [`Stock::around`] for any [`Tool`]: the cutting moves' box grown by
    /// the tool's radius.
    pub fn around_tool(path: &Toolpath, tool: &Tool) -> Result<Stock, Error> {
        Stock::around_reach(path, tool.radius())
    }

    /// [`Stock::around`] grown by `radius` (the widest of a program's tools).
    pub fn around_reach(path: &Toolpath, radius: f64) -> Result<Stock, Error> {
        Stock::around_cutting(path, radius, &|_| true)
    }

    /// [`Stock::around_reach`] with the top taken from the moves
    /// `tells_top(k)` keeps (by index): a drill's sideways feed is no cut
    /// at the top of the material, but a mistake to find.
    pub fn around_cutting(path: &Toolpath, radius: f64, tells_top: &dyn Fn(usize) -> bool) -> Result<Stock, Error> {
        let mut extent = Extent::default();
        path.moves.iter().for_each(|m| extent.add(m));
        extent.stock(radius, cutting_top(path, tells_top))
    }

    fn check(&self) -> Result<(), Error> {
        let v = [self.x0, self.y0, self.x1, self.y1, self.top];
        if !v.iter().all(|v| v.is_finite()) {
            return Err(bad_stock(format!("{:?} is not finite", v)));
        }
        if !(self.x1 > self.x0 && self.y1 > self.y0) {
            return Err(bad_stock(format!(
                "empty box: X {} to {}, Y {} to {} (need X0 < X1 and Y0 < Y1)",
                self.x0, self.x1, self.y0, self.y1
            )));
        }
        Ok(())
    }
}

/// The top of the material a program cuts, as far as its moves tell: the
/// highest Z of its feed moves that move sideways (G01 with X or Y
/// changing, every G02/G03). A plunge, a retract at feed and a probing move
/// are left out: a program that feeds down from its clearance height does
/// not cut there. Only the moves `tells_top(k)` keeps (by index) count.
/// `None` for a program with no such move (a drilling program: its feeds
/// are all vertical).
pub fn cutting_top(path: &Toolpath, tells_top: &dyn Fn(usize) -> bool) -> Option<f64> {
    let tops = path.moves.iter().enumerate().filter(|&(k, _)| tells_top(k)).filter_map(|(_, m)| sideways_top(m));
    tops.reduce(f64::max).filter(|z| z.is_finite())
}

/// The highest Z of a feed move that moves sideways ([`cutting_top`]):
/// `None` for any other move.
pub fn sideways_top(m: &Move) -> Option<f64> {
    let sideways = match m.kind {
        MoveKind::Arc(_) => true,
        MoveKind::Feed => m.start.x != m.end.x || m.start.y != m.end.y,
        _ => false,
    };
    let mut top = f64::NEG_INFINITY;
    m.extreme_points(&mut |p| top = top.max(p[2]));
    sideways.then_some(top)
}

/// What [`Stock::around_cutting`] needs of a path, gathered move by move
/// (a path taken in pieces): the box of the cutting moves (feeds, arcs,
/// probes), and of all moves where none cuts.
#[derive(Clone, Copy, Debug, Default)]
pub struct Extent {
    all: Option<([f64; 3], [f64; 3])>,
    cutting: Option<([f64; 3], [f64; 3])>,
}

impl Extent {
    /// The next move of the path.
    pub fn add(&mut self, m: &Move) {
        let grow = |b: &mut Option<([f64; 3], [f64; 3])>| {
            let (lo, hi) = b.get_or_insert(([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]));
            m.extreme_points(&mut |p| {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            });
        };
        grow(&mut self.all);
        if !m.is_rapid() && !matches!(m.kind, MoveKind::Dwell(_)) {
            grow(&mut self.cutting);
        }
    }

    /// The stock box: the cutting moves' XY box grown by `radius`, its top
    /// at `top` (the highest sideways feed: [`cutting_top`]), else at the
    /// box's top.
    pub fn stock(&self, radius: f64, top: Option<f64>) -> Result<Stock, Error> {
        let (lo, hi) = self.cutting.or(self.all).ok_or_else(empty_toolpath)?;
        if !lo.iter().chain(&hi).all(|v| v.is_finite()) {
            return Err(bad_stock("the program's bounds are not finite"));
        }
        let r = radius;
        let top = top.unwrap_or(hi[2]);
        Ok(Stock { x0: lo[0] - r, y0: lo[1] - r, x1: hi[0] + r, y1: hi[1] + r, top })
    }
}

/// The layout of a grid: its origin, cell size and cells, without heights.
/// Cell `(i, j)` is centred at `(x0 + (i + ½)·res, y0 + (j + ½)·res)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// X of the grid's left edge.
    pub x0: f64,
    /// Y of the grid's bottom edge.
    pub y0: f64,
    /// Cell size.
    pub res: f64,
    /// Cells along X.
    pub nx: usize,
    /// Cells along Y (rows).
    pub ny: usize,
}

impl Grid {
    /// The grid over the box at `options.resolution`. It covers the box,
    /// the last cell reaching past its edge when the size is not a whole
    /// number of cells. Any size: [`ZMap::new`] holds it whole only within
    /// [`SimOptions::max_memory`]; [`super::simulate_tiles`] cuts it in tiles.
    pub fn new(stock: &Stock, options: &SimOptions) -> Result<Grid, Error> {
        let res = options.resolution;
        if let Err(m) = limits::length(res, "the resolution") {
            return Err(Error::new(ErrorKind::Resolution, m));
        }
        if limits::length(options.chord_tolerance, "").is_err() {
            return Err(bad_tolerance(options.chord_tolerance));
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
        // Past 2⁵³ cells a count is no longer exact; nothing that large is cut.
        if fx * fy > 9e15 {
            return Err(too_many_cells(fx, fy, options));
        }
        Ok(Grid { x0: stock.x0, y0: stock.y0, res, nx: fx as usize, ny: fy as usize })
    }

    /// Number of cells.
    pub fn cells(&self) -> u64 {
        self.nx as u64 * self.ny as u64
    }

    /// Bytes the whole grid takes held at once ([`CELL_BYTES`] a cell).
    pub fn bytes(&self) -> u64 {
        self.cells().saturating_mul(CELL_BYTES)
    }
}

/// Bytes a cell of the grid takes: its height (4, whole nanometres) and
/// the tool that lowered it last (1).
pub const CELL_BYTES: u64 = 5;

/// A grid of `fx × fy` cells is more than the memory allowed.
fn too_many_cells(fx: f64, fy: f64, options: &SimOptions) -> Error {
    Error::new(
        ErrorKind::TooManyCells,
        format!(
            "a grid of {fx} × {fy} = {:.0} cells ({:.1} GB at {CELL_BYTES} bytes a cell) is more than the memory \
             allowed ({:.1} GB); cut it in tiles, use a coarser resolution or a smaller stock",
            fx * fy,
            fx * fy * CELL_BYTES as f64 / 1e9,
            options.max_memory as f64 / 1e9
        ),
    )
}

/// What the stock is, to make a grid or a tile of its rows from.
#[derive(Clone, Copy, Debug)]
pub enum Start<'a> {
    /// A box.
    Box(Stock),
    /// An upright cylinder.
    Cylinder(Cylinder),
    /// The top surface of a solid (its triangles).
    Solid(&'a [[[f64; 3]; 3]]),
}

impl Start<'_> {
    /// The grid the stock takes at `options.resolution`.
    pub fn grid(&self, options: &SimOptions) -> Result<Grid, Error> {
        match self {
            Start::Box(s) => Grid::new(s, options),
            Start::Cylinder(c) => Grid::new(&c.square()?, options),
            Start::Solid(t) => Grid::new(&solid_box(t)?.0, options),
        }
    }

    /// Rows `rows` of the stock's grid (all of them: `0..grid.ny`), every
    /// cell at the stock's height there.
    pub fn rows(&self, options: &SimOptions, rows: Range<usize>) -> Result<ZMap, Error> {
        let grid = self.grid(options)?;
        let rows = rows.start.min(grid.ny)..rows.end.min(grid.ny);
        match self {
            Start::Box(s) => ZMap::filled(&grid, rows, s.top),
            Start::Cylinder(c) => {
                let bottom = c.top - c.height;
                let mut zmap = ZMap::filled(&grid, rows, c.top)?;
                let low = to_nm(bottom).ok_or_else(|| beyond_range(bottom))?;
                let r = c.diameter / 2.0;
                for j in 0..zmap.ny {
                    for i in 0..zmap.nx {
                        let [x, y] = zmap.centre(i, j);
                        if (x - c.x).hypot(y - c.y) > r {
                            zmap.nm[j * zmap.nx + i] = low;
                        }
                    }
                }
                Ok(zmap)
            }
            Start::Solid(t) => {
                let (square, bottom) = solid_box(t)?;
                let mut zmap = ZMap::filled(&grid, rows, square.top)?;
                let heights = target_heights(&zmap, t.iter().copied());
                if zmap.first_row == 0 && zmap.ny == grid.ny && heights.iter().all(|&h| h == f64::NEG_INFINITY) {
                    return Err(bad_stock("the solid covers no cell centre: use a finer resolution"));
                }
                for (z, h) in zmap.nm.iter_mut().zip(heights) {
                    let h = if h == f64::NEG_INFINITY { bottom } else { h };
                    *z = to_nm(h).ok_or_else(|| beyond_range(h))?;
                }
                Ok(zmap)
            }
        }
    }

    /// The whole grid, refused past [`SimOptions::max_memory`].
    fn whole(&self, options: &SimOptions) -> Result<ZMap, Error> {
        let grid = self.grid(options)?;
        if grid.bytes() > options.max_memory {
            return Err(too_many_cells(grid.nx as f64, grid.ny as f64, options));
        }
        self.rows(options, 0..grid.ny)
    }
}

/// A solid's box seen from above (its top the highest point) and its
/// lowest point; only triangles with finite corners count.
fn solid_box(triangles: &[[[f64; 3]; 3]]) -> Result<(Stock, f64), Error> {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in triangles.iter().filter(|t| t.iter().flatten().all(|v| v.is_finite())).flat_map(|t| t.iter()) {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    if !(hi[0] > lo[0] && hi[1] > lo[1]) {
        return Err(bad_stock("the solid has no area seen from above"));
    }
    Ok((Stock { x0: lo[0], y0: lo[1], x1: hi[0], y1: hi[1], top: hi[2] }, lo[2]))
}

/// Heights are kept in whole nanometres: `z` mm to the nearest one, `None`
/// when not finite or beyond what a cell holds ([`LOWEST`] to [`HIGHEST`]).
pub fn to_nm(z: f64) -> Option<i32> {
    let n = nearest(z * 1e6);
    (n >= i32::MIN as f64 && n <= i32::MAX as f64).then_some(n as i32)
}

/// `x` to the nearest whole number, a half to the even one, for |x| up to
/// 2⁵¹ (what a cell holds and well beyond): adding and taking away 1.5·2⁵²
/// leaves no fraction bits. Branch-free and without a library call, so a
/// row of cells rounds in vector registers; larger `x` stays past the range.
#[inline(always)]
fn nearest(x: f64) -> f64 {
    const SHIFT: f64 = 6_755_399_441_055_744.0;
    (x + SHIFT) - SHIFT
}

/// The height in mm of a cell holding `n` nanometres: the nearest double
/// to `n / 10⁶` (so [`to_nm`] gives `n` back).
#[inline(always)]
pub fn from_nm(n: i32) -> f64 {
    n as f64 / 1e6
}

/// `z` mm in whole nanometres, to the nearest; past what a cell holds,
/// the nearest end of its range (never wrapped). Rounding is monotone, so
/// the lowest of heights rounds to the lowest of their roundings: cutting
/// in mm and rounding once gives what rounding after every move would.
#[inline(always)]
pub(crate) fn round_nm(z: f64) -> i32 {
    let x = z * 1e6;
    // Past ±2⁵¹ the shift would not round: those are far out of range anyway.
    if x.abs() < 2_251_799_813_685_248.0 {
        nearest(x) as i32
    } else {
        x as i32
    }
}

/// The lowest height a cell holds, mm (−2147.483648).
pub const LOWEST: f64 = i32::MIN as f64 / 1e6;
/// The highest height a cell holds, mm (2147.483647).
pub const HIGHEST: f64 = i32::MAX as f64 / 1e6;

/// A stock height `z` a cell cannot hold.
fn beyond_range(z: f64) -> Error {
    bad_stock(format!(
        "a height of {z} mm is beyond what the grid holds: heights are kept to the nanometre, from {LOWEST} to \
         {HIGHEST} mm"
    ))
}

/// A height per cell, in whole nanometres: cell `(i, j)` is centred at
/// `(x0 + (i + ½)·res, y0 + (first_row + j + ½)·res)`; rows of constant
/// `j` are contiguous in `nm`. A whole grid has `first_row` 0; a tile of a
/// larger grid ([`super::simulate_tiles`]) holds its rows from `first_row`.
#[derive(Clone, Debug, PartialEq)]
pub struct ZMap {
    /// X of the grid's left edge.
    pub x0: f64,
    /// Y of the whole grid's bottom edge.
    pub y0: f64,
    /// Cell size.
    pub res: f64,
    /// Cells along X.
    pub nx: usize,
    /// Rows held.
    pub ny: usize,
    /// The grid row of the first row held.
    pub first_row: usize,
    /// Heights in nanometres, `nm[j·nx + i]` ([`from_nm`] gives mm).
    pub nm: Vec<i32>,
}

impl ZMap {
    /// The stock as a grid at `options.resolution`, every cell at the top.
    /// The grid covers the box, the last cell reaching past its edge when
    /// the size is not a whole number of cells. Refused when it takes more
    /// than [`SimOptions::max_memory`] ([`CELL_BYTES`] a cell).
    pub fn new(stock: &Stock, options: &SimOptions) -> Result<ZMap, Error> {
        Start::Box(*stock).whole(options)
    }

    /// Rows `rows` of `grid`, every cell at `top`.
    pub fn filled(grid: &Grid, rows: Range<usize>, top: f64) -> Result<ZMap, Error> {
        let level = to_nm(top).ok_or_else(|| beyond_range(top))?;
        let count = grid.nx * rows.len();
        let mut nm = Vec::new();
        if nm.try_reserve_exact(count).is_err() {
            return Err(out_of_memory(count));
        }
        nm.resize(count, level);
        Ok(ZMap { x0: grid.x0, y0: grid.y0, res: grid.res, nx: grid.nx, ny: rows.len(), first_row: rows.start, nm })
    }

    /// The layout of the rows held.
    pub fn grid(&self) -> Grid {
        Grid { x0: self.x0, y0: self.y0, res: self.res, nx: self.nx, ny: self.ny }
    }

    /// Number of cells.
    pub fn cells(&self) -> usize {
        self.nx * self.ny
    }

    /// Centre of cell `(i, j)` (`j` counted from the first row held).
    pub fn centre(&self, i: usize, j: usize) -> [f64; 2] {
        [self.x0 + (i as f64 + 0.5) * self.res, self.y0 + ((self.first_row + j) as f64 + 0.5) * self.res]
    }

    /// Height of cell `(i, j)`, mm.
    pub fn height(&self, i: usize, j: usize) -> f64 {
        from_nm(self.nm[j * self.nx + i])
    }

    /// Height of cell `k` (`j·nx + i`), mm.
    pub fn height_at(&self, k: usize) -> f64 {
        from_nm(self.nm[k])
    }

    /// Every cell's height, mm, in the order of [`ZMap::nm`].
    pub fn heights(&self) -> impl ExactSizeIterator<Item = f64> + '_ {
        self.nm.iter().map(|&n| from_nm(n))
    }

    /// Lowest and highest cell, mm (infinite for no cells).
    pub fn range(&self) -> (f64, f64) {
        match (self.nm.iter().min(), self.nm.iter().max()) {
            (Some(&lo), Some(&hi)) => (from_nm(lo), from_nm(hi)),
            _ => (f64::INFINITY, f64::NEG_INFINITY),
        }
    }
}

/// An upright cylinder of stock: its axis vertical through `(x, y)`, its
/// top face at `top`, `height` deep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cylinder {
    /// X of the axis.
    pub x: f64,
    /// Y of the axis.
    pub y: f64,
    /// Diameter (> 0).
    pub diameter: f64,
    /// Height (> 0): the bottom is at `top − height`.
    pub height: f64,
    /// Height of the top face.
    pub top: f64,
}

impl Cylinder {
    /// The square around the circle, checked.
    fn square(&self) -> Result<Stock, Error> {
        let c = self;
        let v = [c.x, c.y, c.diameter, c.height, c.top];
        if !v.iter().all(|v| v.is_finite()) || c.diameter <= 0.0 || c.height <= 0.0 {
            return Err(bad_stock(format!(
                "cylinder Ø{} × {} at ({}, {}), top {}: need a positive diameter and height",
                c.diameter, c.height, c.x, c.y, c.top
            )));
        }
        let r = c.diameter / 2.0;
        Ok(Stock { x0: c.x - r, y0: c.y - r, x1: c.x + r, y1: c.y + r, top: c.top })
    }
}

impl ZMap {
    /// An upright cylinder as a grid over its square: cells whose centre
    /// lies within the circle at the top, the others at its bottom.
    pub fn cylinder(c: &Cylinder, options: &SimOptions) -> Result<ZMap, Error> {
        Start::Cylinder(*c).whole(options)
    }

    /// The top surface of a solid (its triangles) as a grid over its XY
    /// box: at each cell centre the highest triangle over it; where none,
    /// the solid's lowest point (its bottom: no stock there).
    pub fn top_of(triangles: &[[[f64; 3]; 3]], options: &SimOptions) -> Result<ZMap, Error> {
        Start::Solid(triangles).whole(options)
    }
}

/// The stock box or solid is empty or not finite: `why`.
fn bad_stock(why: impl std::fmt::Display) -> Error {
    Error::new(ErrorKind::Stock, format!("bad stock: {why}"))
}
