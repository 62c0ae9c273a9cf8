//! Digitizing a model on an NC machine and copy-milling it (the copy-milling
//! paper): grid data, levelling, export geometry and the surfaces a ball
//! stylus's readings imply.
//!
//! # The grid and capture order
//! A probed model is `nx × ny` points at `pitch` mm from `origin`. The
//! stylus visits them in rows along X, stepping +Y between rows, the first
//! row toward +X; with [`Order::ZigZag`] every other row runs toward −X
//! (the paper's measuring program), with [`Order::OneWay`] every row runs
//! toward +X. Point `No` k (from 1) of a capture is the k-th point visited;
//! [`Grid::node`] says which node it is. Heights are stored by node, row by
//! row (`z[j·nx + i]`, as [`Heightfield`] stores them).
//!
//! # Modules
//! - [`capture`]: a dial indicator's lines as readings and the rules of
//!   the `No,Z` data file a capture writes.
//! - [`copy`]: the copy-milling job, from the readings to the toolpath.
//! - [`data`]: readers and writers of the data files (the capture file
//!   with its `#` header, the paper's bare `No,Z` files, `x,y,z` CSV and
//!   LinuxCNC probe logs), with errors that name the line.
//! - [`level`]: reference-plane correction — a least-squares plane, the
//!   paper's least-squares lines along two edges corrected row by row, or
//!   whichever leaves the smallest standard deviation — and the paper's
//!   table.
//! - [`export`]: DXF cross sections, a surface mesh, a shaded picture,
//!   mirroring a half-measured model.
//! - [`simulate`]: the readings a ball stylus would give on a model, to
//!   try the pipeline on.
//! - [`smooth`]: a smooth (C¹, shape-preserving bicubic) surface through
//!   the readings, each cell between its readings, with the places where it
//!   bends tighter than the stylus.
//! - [`stylus`]: the model under that surface (the default of `probe
//!   mill`) or the highest surface consistent with the readings (`--between
//!   bound`), on which any cutter is placed with drop-cutter, and the flat
//!   margins a program can cross at rapid.

pub mod capture;
pub mod copy;
pub mod data;
pub mod export;
pub mod level;
pub mod simulate;
pub mod smooth;
pub mod stylus;

use kezuri_geom::Heightfield;

/// The order points are visited in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Order {
    /// Every other row runs backwards (toward −X).
    #[default]
    ZigZag,
    /// Every row runs toward +X.
    OneWay,
}

impl Order {
    /// `zigzag` or `oneway`.
    pub fn name(self) -> &'static str {
        match self {
            Order::ZigZag => "zigzag",
            Order::OneWay => "oneway",
        }
    }
}

impl std::str::FromStr for Order {
    type Err = String;

    fn from_str(s: &str) -> Result<Order, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "zigzag" | "zig-zag" => Ok(Order::ZigZag),
            "oneway" | "one-way" => Ok(Order::OneWay),
            other => Err(format!("pattern '{other}': expected zigzag or oneway")),
        }
    }
}

/// A measuring grid: where the points are and in which order they were
/// measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// Points along X (in a row).
    pub nx: usize,
    /// Points along Y (rows).
    pub ny: usize,
    /// Distance between neighbouring points, mm (the same along X and Y).
    pub pitch: f64,
    /// The first point (node `(0, 0)`), mm.
    pub origin: [f64; 2],
    /// The order of the capture.
    pub order: Order,
}

impl Grid {
    /// Points in all.
    pub fn len(&self) -> usize {
        self.nx * self.ny
    }

    /// `true` for a grid of no points.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// X of column `i`.
    pub fn x(&self, i: usize) -> f64 {
        self.origin[0] + i as f64 * self.pitch
    }

    /// Y of row `j`.
    pub fn y(&self, j: usize) -> f64 {
        self.origin[1] + j as f64 * self.pitch
    }

    /// The node `(i, j)` of the `k`-th point measured (k from 0).
    pub fn node(&self, k: usize) -> (usize, usize) {
        let (j, along) = (k / self.nx, k % self.nx);
        let backwards = self.order == Order::ZigZag && j % 2 == 1;
        (if backwards { self.nx - 1 - along } else { along }, j)
    }

    /// The capture index (from 0) of node `(i, j)`.
    pub fn index(&self, i: usize, j: usize) -> usize {
        let backwards = self.order == Order::ZigZag && j % 2 == 1;
        j * self.nx + if backwards { self.nx - 1 - i } else { i }
    }
}

/// Heights measured on a [`Grid`].
#[derive(Clone, Debug, PartialEq)]
pub struct ProbeGrid {
    /// The grid.
    pub grid: Grid,
    /// Heights by node, row by row: `z[j·nx + i]`.
    pub z: Vec<f64>,
}

impl ProbeGrid {
    /// Height at node `(i, j)`.
    pub fn z(&self, i: usize, j: usize) -> f64 {
        self.z[j * self.grid.nx + i]
    }

    /// The heights in capture order.
    pub fn in_capture_order(&self) -> Vec<f64> {
        (0..self.grid.len())
            .map(|k| {
                let (i, j) = self.grid.node(k);
                self.z(i, j)
            })
            .collect()
    }

    /// The grid as a [`Heightfield`] (needs 2 × 2 points or more).
    pub fn heightfield(&self) -> Result<Heightfield, kezuri_geom::Error> {
        let g = &self.grid;
        Heightfield::new(g.origin[0], g.origin[1], g.pitch, g.nx, g.ny, self.z.clone())
    }

    /// Lowest and highest height.
    pub fn range(&self) -> (f64, f64) {
        self.z.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &z| (lo.min(z), hi.max(z)))
    }
}
