//! A smooth surface through the readings: the stylus's tip surface.
//!
//! # The scheme
//! A reading is an exact point of the surface the stylus's tip traces as
//! it rolls over the model (its centre surface, lowered by the radius).
//! [`Smooth`] interpolates the readings with **bicubic Hermite patches**,
//! one per grid cell, each given by the height `f` and the slopes `f_x`,
//! `f_y` at its four corners (twist `f_xy = 0`). The slopes at a node are
//! shared by the four cells around it, so the surface is C¹: values and
//! both slopes match across every patch border.
//!
//! The slopes are **monotone (shape-preserving)** in each direction, in the
//! manner of Fritsch and Carlson: along a row (a column for `f_y`), with
//! `a` and `b` the rises to the node from the previous one and from it to
//! the next,
//! - `0` where `a` and `b` differ in sign or one is zero (a top, a bottom or
//!   a flat: the surface does not swing past the readings there);
//! - otherwise the central difference `(a + b)/2`, held to at most
//!   `3·min(|a|, |b|)` (Fritsch and Carlson's region, so each row and column
//!   is monotone between monotone readings);
//! - at the first and last node, the one-sided second-order difference
//!   `(3a − b)/2` (of the first two rises), `0` against the sign of the
//!   first rise and held to `3|a|`.
//!
//! Central differences make the scheme exact on planes (a tilted flat is
//! copied as it was read) and second-order accurate elsewhere; they are
//! only held back near tops and bottoms.
//!
//! # No overshoot
//! A bicubic patch is a Bézier patch whose 16 control points are the four
//! corner heights, `f ± f_x·p/3` and `f ± f_y·p/3` beside each corner (`p`
//! the pitch) and `f ± f_x·p/3 ± f_y·p/3` inside (the signs pointing into
//! the cell). The surface lies within its control points' range (Bernstein
//! polynomials are positive and sum to one). The held slopes keep the
//! points beside each corner between the heights of that edge's ends; the
//! inner ones are kept between the lowest and highest corner of the cell by
//! scaling a node's two slopes down together where needed (which keeps
//! every other condition, all of them bounds on the slopes' size). Hence
//! **every patch lies between the lowest and highest of its four
//! readings**, and along every row and column of the grid the surface is
//! the one-dimensional monotone curve above.
//!
//! # Following
//! Between readings the surface the stylus traced is not known, and no
//! interpolant can place a bend that falls inside a cell. Two measured
//! cases on the demo's plum mould (10 mm ball, 1 mm pitch, exact
//! readings), the surface against the exact tip surface along the rows:
//! - **next to a bottom reading** the slope is 0 (it must be, for the
//!   cell beyond to stay above that reading and the surface to be C¹),
//!   while the traced surface already rises there: the patch starts flat
//!   and falls up to `4/27·|slope|·p` below it (40 µm, slope 0.27). The
//!   straight line between the readings is above a valley;
//! - **on a ridge** bent tighter than about twice the stylus (a sharp rim
//!   the ball rolls round), the straight line passes `p²/(8ρ)` below it
//!   (29 µm) and the surface, which puts the bend where the neighbouring
//!   readings suggest, up to 12 µm.
//!
//! So a cutter of the stylus's own shape follows [`Smooth::over_chord`],
//! the higher of the two: 13 µm at most below the traced surface on the
//! mould where the straight lines alone go 29 µm below, exact on planes,
//! and the surface itself on spheres and other ridges (which lie over
//! their chords). [`sharpest_bend`] finds where the readings bend so
//! sharply that this is more than a tolerance.

use super::{Grid, ProbeGrid};
use crate::error::{Error, ErrorKind};

/// The bicubic surface through the readings (module docs).
#[derive(Clone, Debug)]
pub struct Smooth {
    grid: Grid,
    z: Vec<f64>,
    /// `f_x · pitch` by node.
    p: Vec<f64>,
    /// `f_y · pitch` by node.
    q: Vec<f64>,
}

/// The height and its derivatives at a point, per mm.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Local {
    /// Height.
    pub z: f64,
    /// ∂z/∂x, ∂z/∂y.
    pub slope: [f64; 2],
    /// ∂²z/∂x², ∂²z/∂x∂y, ∂²z/∂y².
    pub second: [f64; 3],
}

impl Local {
    /// The principal curvatures (1/mm) of the surface here, lowest first:
    /// negative where it bends down (a ridge, convex seen from above).
    pub fn curvatures(&self) -> [f64; 2] {
        let [gx, gy] = self.slope;
        let [hxx, hxy, hyy] = self.second;
        let w2 = 1.0 + gx * gx + gy * gy;
        // The shape operator (I + g gᵀ)⁻¹ H / √(1 + |g|²).
        let inv = [[1.0 + gy * gy, -gx * gy], [-gx * gy, 1.0 + gx * gx]];
        let s = 1.0 / (w2 * w2.sqrt());
        let m = [
            [s * (inv[0][0] * hxx + inv[0][1] * hxy), s * (inv[0][0] * hxy + inv[0][1] * hyy)],
            [s * (inv[1][0] * hxx + inv[1][1] * hxy), s * (inv[1][0] * hxy + inv[1][1] * hyy)],
        ];
        let (half, det) = (0.5 * (m[0][0] + m[1][1]), m[0][0] * m[1][1] - m[0][1] * m[1][0]);
        let root = (half * half - det).max(0.0).sqrt();
        [half - root, half + root]
    }
}

/// Cells where the surface bends tighter than the stylus.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tight {
    /// How many cells.
    pub cells: usize,
    /// The tightest radius of curvature found, mm.
    pub radius: f64,
    /// Where, (x, y).
    pub at: [f64; 2],
}

/// Where the readings bend down (a ridge, seen from above) most sharply:
/// how far a straight line between two readings there may pass below the
/// surface the stylus traced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bend {
    /// Readings where that depth is over the limit asked.
    pub points: usize,
    /// The largest depth, mm: `−Δ²z / 8` of the three readings about it.
    pub depth: f64,
    /// Where, (x, y).
    pub at: [f64; 2],
}

/// The readings where the row or column bends down so that a straight
/// line between two readings passes more than `limit` below an arc
/// through them of the same bend: `−(z₋ − 2z + z₊) / 8`, which is
/// `p²/(8ρ)` on an arc of radius `ρ` (nearly level) at pitch `p`: about
/// the depth a copy may cut below the model there (module docs,
/// *Following*). `None` where no reading bends that sharply.
pub fn sharpest_bend(data: &ProbeGrid, limit: f64) -> Option<Bend> {
    let g = data.grid;
    let mut found: Option<Bend> = None;
    for j in 0..g.ny {
        for i in 0..g.nx {
            let along = |a: Option<(usize, usize)>, b: Option<(usize, usize)>| match (a, b) {
                (Some(a), Some(b)) => (2.0 * data.z(i, j) - data.z(a.0, a.1) - data.z(b.0, b.1)) / 8.0,
                _ => 0.0,
            };
            let depth = along(i.checked_sub(1).map(|a| (a, j)), (i + 1 < g.nx).then_some((i + 1, j)))
                .max(along(j.checked_sub(1).map(|b| (i, b)), (j + 1 < g.ny).then_some((i, j + 1))));
            if depth > limit {
                let b = found.get_or_insert(Bend { points: 0, depth, at: [g.x(i), g.y(j)] });
                b.points += 1;
                if depth > b.depth {
                    (b.depth, b.at) = (depth, [g.x(i), g.y(j)]);
                }
            }
        }
    }
    found
}

/// The held slope at each of `v`'s points, in rise per point (module docs).
pub fn slopes(v: &[f64]) -> Vec<f64> {
    let n = v.len();
    let rise: Vec<f64> = v.windows(2).map(|w| w[1] - w[0]).collect();
    let held = |c: f64, a: f64, b: f64| {
        if a * b <= 0.0 || c * a <= 0.0 {
            0.0
        } else {
            c.signum() * c.abs().min(3.0 * a.abs().min(b.abs()))
        }
    };
    (0..n)
        .map(|k| match (k, rise.len()) {
            (_, 0) => 0.0,
            (_, 1) => rise[0],
            (0, _) => held(0.5 * (3.0 * rise[0] - rise[1]), rise[0], rise[0]),
            (k, r) if k == r => held(0.5 * (3.0 * rise[r - 1] - rise[r - 2]), rise[r - 1], rise[r - 1]),
            (k, _) => held(0.5 * (rise[k - 1] + rise[k]), rise[k - 1], rise[k]),
        })
        .collect()
}

/// Hermite basis at `t` (`d` times differentiated): the two value
/// functions, then the two slope functions.
fn basis(t: f64, d: usize) -> [f64; 4] {
    let (t2, t3) = (t * t, t * t * t);
    match d {
        0 => [1.0 - 3.0 * t2 + 2.0 * t3, 3.0 * t2 - 2.0 * t3, t - 2.0 * t2 + t3, t3 - t2],
        1 => [6.0 * (t2 - t), 6.0 * (t - t2), 1.0 - 4.0 * t + 3.0 * t2, 3.0 * t2 - 2.0 * t],
        _ => [12.0 * t - 6.0, 6.0 - 12.0 * t, 6.0 * t - 4.0, 6.0 * t - 2.0],
    }
}

impl Smooth {
    /// The surface through `data` (2 × 2 points or more, finite heights).
    pub fn new(data: &ProbeGrid) -> Result<Smooth, Error> {
        let g = data.grid;
        if g.nx < 2 || g.ny < 2 || data.z.len() != g.len() {
            return Err(Error::new(
                ErrorKind::Surface,
                format!("a surface needs 2 × 2 points or more, got {} × {}", g.nx, g.ny),
            ));
        }
        if let Some(k) = data.z.iter().position(|z| !z.is_finite()) {
            return Err(Error::new(
                ErrorKind::Surface,
                format!("reading at node ({}, {}) is not a number", k % g.nx, k / g.nx),
            ));
        }
        let mut p = vec![0.0; g.len()];
        let mut q = vec![0.0; g.len()];
        for j in 0..g.ny {
            let row = &data.z[j * g.nx..(j + 1) * g.nx];
            p[j * g.nx..(j + 1) * g.nx].copy_from_slice(&slopes(row));
        }
        for i in 0..g.nx {
            let col: Vec<f64> = (0..g.ny).map(|j| data.z(i, j)).collect();
            for (j, s) in slopes(&col).into_iter().enumerate() {
                q[j * g.nx + i] = s;
            }
        }
        let mut s = Smooth { grid: g, z: data.z.clone(), p, q };
        s.keep_inner_points();
        Ok(s)
    }

    /// Scales each node's slopes so that the inner control points of the
    /// four cells around it stay within each cell's range (module docs).
    fn keep_inner_points(&mut self) {
        let g = self.grid;
        for j in 0..g.ny {
            for i in 0..g.nx {
                let k = j * g.nx + i;
                let (f, p, q) = (self.z[k], self.p[k], self.q[k]);
                let mut scale: f64 = 1.0;
                for (di, dj) in [(1isize, 1isize), (-1, 1), (1, -1), (-1, -1)] {
                    let (a, b) = (i as isize + di, j as isize + dj);
                    if a < 0 || b < 0 || a as usize >= g.nx || b as usize >= g.ny {
                        continue;
                    }
                    let (a, b) = (a as usize, b as usize);
                    let corners = [f, self.z[j * g.nx + a], self.z[b * g.nx + i], self.z[b * g.nx + a]];
                    let lo = corners.iter().fold(f64::INFINITY, |m, &v| m.min(v));
                    let hi = corners.iter().fold(f64::NEG_INFINITY, |m, &v| m.max(v));
                    let e = (di as f64 * p + dj as f64 * q) / 3.0;
                    if e > hi - f {
                        scale = scale.min((hi - f) / e);
                    } else if e < lo - f {
                        scale = scale.min((lo - f) / e);
                    }
                }
                self.p[k] *= scale;
                self.q[k] *= scale;
            }
        }
    }

    /// The cells where the surface bends down (a ridge seen from above)
    /// tighter than `radius`, judged at 5 × 5 points of each cell: an
    /// offset inward by `radius` would fold over itself there.
    pub fn tighter_than(&self, radius: f64) -> Option<Tight> {
        let g = self.grid;
        let mut found: Option<Tight> = None;
        for c in 0..(g.nx - 1) * (g.ny - 1) {
            let (i, j) = (c % (g.nx - 1), c / (g.nx - 1));
            let mut worst = (0.0, [0.0; 2]);
            for s in 0..25 {
                let x = g.x(i) + (s % 5) as f64 * g.pitch / 4.0;
                let y = g.y(j) + (s / 5) as f64 * g.pitch / 4.0;
                let k = self.local(x, y).curvatures()[0];
                if k < worst.0 {
                    worst = (k, [x, y]);
                }
            }
            if worst.0 * radius < -1.0 {
                let t = found.get_or_insert(Tight { cells: 0, radius: f64::INFINITY, at: worst.1 });
                t.cells += 1;
                if -1.0 / worst.0 < t.radius {
                    (t.radius, t.at) = (-1.0 / worst.0, worst.1);
                }
            }
        }
        found
    }

    /// The grid.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// The node slopes `(∂z/∂x, ∂z/∂y)` at node `(i, j)`, per mm.
    pub fn node_slope(&self, i: usize, j: usize) -> [f64; 2] {
        let k = j * self.grid.nx + i;
        [self.p[k] / self.grid.pitch, self.q[k] / self.grid.pitch]
    }

    /// The height at `(x, y)` (clamped to the grid's box).
    pub fn z(&self, x: f64, y: f64) -> f64 {
        self.derivative(x, y, 0, 0)
    }

    /// The higher of the surface and the straight line along X between
    /// the heights of the surface at the nodes of its cell, at `(x, y)`:
    /// what the stylus's own ball follows (module docs, *Following*).
    pub fn over_chord(&self, x: f64, y: f64) -> f64 {
        self.chord(x, y).max(self.z(x, y))
    }

    /// The straight line along X between the heights of the surface at
    /// the nodes of `(x, y)`'s cell (on a row of readings, between the
    /// readings), at `(x, y)`.
    pub fn chord(&self, x: f64, y: f64) -> f64 {
        let g = &self.grid;
        let s = ((x - g.origin[0]) / g.pitch).clamp(0.0, (g.nx - 1) as f64);
        let i = (s.floor() as usize).min(g.nx - 2);
        let t = s - i as f64;
        (1.0 - t) * self.z(g.x(i), y) + t * self.z(g.x(i + 1), y)
    }

    /// Height, slopes and second derivatives at `(x, y)` (clamped to the
    /// grid's box; on a border between cells, those of the cell above it).
    pub fn local(&self, x: f64, y: f64) -> Local {
        let d = |a, b| self.derivative(x, y, a, b);
        Local { z: d(0, 0), slope: [d(1, 0), d(0, 1)], second: [d(2, 0), d(1, 1), d(0, 2)] }
    }

    /// `∂^(dx+dy) z / ∂x^dx ∂y^dy` at `(x, y)`, per mm.
    fn derivative(&self, x: f64, y: f64, dx: usize, dy: usize) -> f64 {
        let g = &self.grid;
        let cell = |v: f64, o: f64, n: usize| {
            let s = ((v - o) / g.pitch).clamp(0.0, (n - 1) as f64);
            let c = (s.floor() as usize).min(n - 2);
            (c, s - c as f64)
        };
        let (i, t) = cell(x, g.origin[0], g.nx);
        let (j, u) = cell(y, g.origin[1], g.ny);
        let (bt, bu) = (basis(t, dx), basis(u, dy));
        let mut sum = 0.0;
        for (b, nj) in [j, j + 1].into_iter().enumerate() {
            for (a, ni) in [i, i + 1].into_iter().enumerate() {
                let k = nj * g.nx + ni;
                sum += self.z[k] * bt[a] * bu[b] + self.p[k] * bt[2 + a] * bu[b] + self.q[k] * bt[a] * bu[2 + b];
            }
        }
        sum / g.pitch.powi((dx + dy) as i32)
    }
}
