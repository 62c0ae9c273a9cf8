//! The stock: a box, an upright cylinder or the top surface of a solid,
//! as the Z-map's starting heights.
//!
//! A Z-map holds one height per cell: it has no undercuts, so a stock is
//! what is seen of it from above. Where a cylinder or a solid does not
//! reach, the cells start at its bottom: there is no stock above it.

use kezuri_geom::{limits, MoveKind, Toolpath};

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
        let cutting: Vec<_> =
            path.moves.iter().filter(|m| !m.is_rapid() && !matches!(m.kind, MoveKind::Dwell(_))).copied().collect();
        let bounds = if cutting.is_empty() { path.bounds() } else { Toolpath::from(cutting).bounds() };
        let (lo, hi) = bounds.ok_or_else(empty_toolpath)?;
        if !lo.iter().chain(&hi).all(|v| v.is_finite()) {
            return Err(bad_stock("the program's bounds are not finite"));
        }
        let r = radius;
        let top = cutting_top(path, tells_top).unwrap_or(hi[2]);
        Ok(Stock { x0: lo[0] - r, y0: lo[1] - r, x1: hi[0] + r, y1: hi[1] + r, top })
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
    let sideways = |m: &kezuri_geom::Move| match m.kind {
        MoveKind::Arc(_) => true,
        MoveKind::Feed => m.start.x != m.end.x || m.start.y != m.end.y,
        _ => false,
    };
    let moves: Vec<_> =
        path.moves.iter().enumerate().filter(|&(k, m)| sideways(m) && tells_top(k)).map(|(_, m)| *m).collect();
    let (_, hi) = Toolpath::from(moves).bounds()?;
    hi[2].is_finite().then_some(hi[2])
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
    pub fn new(stock: &Stock, options: &SimOptions) -> Result<ZMap, Error> {
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
        let cells = fx * fy;
        if cells > options.max_cells as f64 {
            return Err(Error::new(
                ErrorKind::TooManyCells,
                format!(
                    "a grid of {fx} × {fy} = {:.0} cells ({:.1} GB) is more than the limit of {} cells; \
                     use a coarser resolution or a smaller stock",
                    fx * fy,
                    fx * fy * 9.0 / 1e9,
                    options.max_cells
                ),
            ));
        }
        let (nx, ny) = (fx as usize, fy as usize);
        let mut z = Vec::new();
        if z.try_reserve_exact(nx * ny).is_err() {
            return Err(out_of_memory(nx * ny));
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

impl ZMap {
    /// An upright cylinder as a grid over its square: cells whose centre
    /// lies within the circle at the top, the others at its bottom.
    pub fn cylinder(c: &Cylinder, options: &SimOptions) -> Result<ZMap, Error> {
        let v = [c.x, c.y, c.diameter, c.height, c.top];
        if !v.iter().all(|v| v.is_finite()) || c.diameter <= 0.0 || c.height <= 0.0 {
            return Err(bad_stock(format!(
                "cylinder Ø{} × {} at ({}, {}), top {}: need a positive diameter and height",
                c.diameter, c.height, c.x, c.y, c.top
            )));
        }
        let r = c.diameter / 2.0;
        let square = Stock { x0: c.x - r, y0: c.y - r, x1: c.x + r, y1: c.y + r, top: c.top };
        let mut zmap = ZMap::new(&square, options)?;
        let bottom = c.top - c.height;
        for j in 0..zmap.ny {
            for i in 0..zmap.nx {
                let [x, y] = zmap.centre(i, j);
                if (x - c.x).hypot(y - c.y) > r {
                    zmap.z[j * zmap.nx + i] = bottom;
                }
            }
        }
        Ok(zmap)
    }

    /// The top surface of a solid (its triangles) as a grid over its XY
    /// box: at each cell centre the highest triangle over it; where none,
    /// the solid's lowest point (its bottom: no stock there).
    pub fn top_of(triangles: &[[[f64; 3]; 3]], options: &SimOptions) -> Result<ZMap, Error> {
        let finite: Vec<&[[f64; 3]; 3]> =
            triangles.iter().filter(|t| t.iter().flatten().all(|v| v.is_finite())).collect();
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for p in finite.iter().flat_map(|t| t.iter()) {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if finite.is_empty() || !(hi[0] > lo[0] && hi[1] > lo[1]) {
            return Err(bad_stock("the solid has no area seen from above"));
        }
        let square = Stock { x0: lo[0], y0: lo[1], x1: hi[0], y1: hi[1], top: hi[2] };
        let mut zmap = ZMap::new(&square, options)?;
        let heights = target_heights(&zmap, finite.into_iter().copied());
        if heights.iter().all(|&h| h == f64::NEG_INFINITY) {
            return Err(bad_stock("the solid covers no cell centre: use a finer resolution"));
        }
        for (z, h) in zmap.z.iter_mut().zip(heights) {
            *z = if h == f64::NEG_INFINITY { lo[2] } else { h };
        }
        Ok(zmap)
    }
}

/// The stock box or solid is empty or not finite: `why`.
fn bad_stock(why: impl std::fmt::Display) -> Error {
    Error::new(ErrorKind::Stock, format!("bad stock: {why}"))
}
