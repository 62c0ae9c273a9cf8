//! Drop-cutter: the lowest tip z at which a cutter held at `(x, y)` rests
//! on a surface without cutting into it (the CL point's z).
//!
//! Every surface is triangles; the contact with one triangle is the highest
//! of three exact contacts (see `contact.rs`): the profile on a vertex, a
//! tilted plane on the profile (facet), and the profile along an edge,
//! solved in closed form for flat, ball, oval and V-bit and by a bracketed
//! root finder for the bull's torus. A point where no triangle comes within
//! the cutter's radius has no answer: `None`, never a made-up z.
//!
//! Three [`Surface`]s: a [`MeshSurface`] (a mesh with its [`XyIndex`]; each
//! query visits only the triangles whose box meets the cutter's disk and
//! tests each shared vertex and edge once), a [`Heightfield`](kezuri_geom::Heightfield) (the fast path:
//! the grid is its own index), and a plain slice of triangles (brute force,
//! the reference the tests compare the others with). Each query first tests
//! the vertices, then skips every triangle that cannot beat the best z so
//! far (its top minus the profile's height at its nearest possible point).
//!
//! # Example
//! ```
//! use kezuri_cam::dropcut::{drop_cutter, MeshSurface};
//! use kezuri_cam::Cutter;
//! use kezuri_geom::{Mesh, Triangle, Vec3};
//! // A plane rising 0.5 mm per mm along X.
//! let p = |x: f64, y: f64| Vec3::new(x, y, 0.5 * x);
//! let mesh = Mesh::from_triangles([
//!     Triangle::new(p(-10., -10.), p(10., -10.), p(10., 10.)),
//!     Triangle::new(p(-10., -10.), p(10., 10.), p(-10., 10.)),
//! ]);
//! let surface = MeshSurface::new(mesh);
//! let ball: Cutter = "ball:6".parse().unwrap();
//! // The ball touches the plane off-centre: R·(√(1 + 0.5²) − 1) above it.
//! let z = drop_cutter(&ball, &surface, 0.0, 0.0).unwrap();
//! assert!((z - 3.0 * (1.25f64.sqrt() - 1.0)).abs() < 1e-12);
//! assert_eq!(drop_cutter(&ball, &surface, 50.0, 0.0), None);
//! ```

mod along;
pub use along::drop_cutter_along_rows;
mod contact;
mod heightfield;
mod rows;

use std::str::FromStr;
use std::sync::Mutex;

use kezuri_geom::{Heightfield, Mesh, Triangle, XyIndex};
use rayon::prelude::*;

use crate::cutter::{each_shape, Cutter, Profile};
use crate::error::{Error, ErrorKind};
use contact::Probe;

/// Something a cutter can be dropped on.
pub trait Surface: Sync {
    /// Working memory of one thread's queries.
    type Scratch: Send;

    /// Fresh working memory for [`Surface::drop_cutter_with`].
    fn scratch(&self) -> Self::Scratch;

    /// The tip z of `cutter` dropped at `(x, y)`; `None` where no part of the
    /// surface lies within the cutter's radius (or `x`, `y` are not finite).
    fn drop_cutter_with(&self, cutter: &Cutter, x: f64, y: f64, scratch: &mut Self::Scratch) -> Option<f64>;

    /// [`Surface::drop_cutter_with`] for one query, with working memory the
    /// surface finds itself (a fresh one unless the surface keeps a pool).
    fn drop_cutter_once(&self, cutter: &Cutter, x: f64, y: f64) -> Option<f64> {
        self.drop_cutter_with(cutter, x, y, &mut self.scratch())
    }
}

/// The tip z of `cutter` dropped at `(x, y)` on `surface`; `None` where no
/// part of the surface lies within the cutter's radius.
pub fn drop_cutter<S: Surface + ?Sized>(cutter: &Cutter, surface: &S, x: f64, y: f64) -> Option<f64> {
    surface.drop_cutter_once(cutter, x, y)
}

/// Brute force: every triangle's vertices, edges and facet.
impl Surface for [Triangle] {
    type Scratch = ();

    fn scratch(&self) {}

    fn drop_cutter_with(&self, cutter: &Cutter, x: f64, y: f64, _: &mut ()) -> Option<f64> {
        if !(x.is_finite() && y.is_finite()) {
            return None;
        }
        each_shape!(cutter, shape => brute_force(self, Probe::new(shape, x, y)))
    }
}

/// [`Surface::drop_cutter_with`] on every triangle.
fn brute_force<P: Profile>(triangles: &[Triangle], mut probe: Probe<P>) -> Option<f64> {
    {
        for t in triangles {
            for k in 0..3 {
                probe.vertex(t.v[k]);
            }
            probe.facet(t);
            for k in 0..3 {
                probe.edge(t.v[k], t.v[(k + 1) % 3]);
            }
        }
        probe.result()
    }
}

/// A mesh with its XY index, ready for drop-cutter queries.
#[derive(Debug)]
pub struct MeshSurface {
    mesh: Mesh,
    index: XyIndex,
    /// Highest z of each triangle.
    top: Vec<f64>,
    /// Working memory of finished single queries, for the next ones: a
    /// scratch holds a stamp per vertex and edge, too big to make afresh
    /// for every point.
    pool: Mutex<Vec<MeshScratch>>,
}

impl MeshSurface {
    /// Indexes `mesh` (cells sized from its median triangle).
    pub fn new(mesh: Mesh) -> MeshSurface {
        let index = XyIndex::new(&mesh);
        MeshSurface::with_index(mesh, index)
    }

    /// `mesh` with an index built for it.
    pub fn with_index(mesh: Mesh, index: XyIndex) -> MeshSurface {
        let top = mesh.iter().map(|t| t.max_z()).collect();
        MeshSurface { mesh, index, top, pool: Mutex::new(Vec::new()) }
    }

    /// The mesh.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The index.
    pub fn index(&self) -> &XyIndex {
        &self.index
    }
}

/// Working memory of [`MeshSurface`] queries: the candidate triangles and a
/// "seen in query n" stamp per vertex and per edge.
#[derive(Debug)]
pub struct MeshScratch {
    candidates: Vec<u32>,
    /// The triangles near a row ([`MeshSurface::drop_cutter_along`]): the
    /// low and high ends of each one's box along the row.
    near_row: Vec<(f64, f64, u32)>,
    /// Those by slot along the row, and where each slot's begin.
    sorted_row: Vec<(f64, f64, u32)>,
    slot_starts: Vec<u32>,
    vertex_seen: Vec<u32>,
    edge_seen: Vec<u32>,
    query: u32,
}

impl MeshScratch {
    fn next_query(&mut self) -> u32 {
        self.query = self.query.wrapping_add(1);
        if self.query == 0 {
            self.vertex_seen.fill(0);
            self.edge_seen.fill(0);
            self.query = 1;
        }
        self.query
    }
}

impl Surface for MeshSurface {
    type Scratch = MeshScratch;

    fn scratch(&self) -> MeshScratch {
        MeshScratch {
            candidates: Vec::new(),
            near_row: Vec::new(),
            sorted_row: Vec::new(),
            slot_starts: Vec::new(),
            vertex_seen: vec![0; self.mesh.vertices().len()],
            edge_seen: vec![0; self.mesh.edges().len()],
            query: 0,
        }
    }

    fn drop_cutter_once(&self, cutter: &Cutter, x: f64, y: f64) -> Option<f64> {
        let pooled = self.pool.lock().ok().and_then(|mut p| p.pop());
        let mut scratch = pooled.unwrap_or_else(|| self.scratch());
        let z = self.drop_cutter_with(cutter, x, y, &mut scratch);
        if let Ok(mut pool) = self.pool.lock() {
            pool.push(scratch);
        }
        z
    }

    fn drop_cutter_with(&self, cutter: &Cutter, x: f64, y: f64, scratch: &mut MeshScratch) -> Option<f64> {
        if !(x.is_finite() && y.is_finite()) {
            return None;
        }
        each_shape!(cutter, shape => self.drop(Probe::new(shape, x, y), scratch))
    }
}

impl MeshSurface {
    /// [`Surface::drop_cutter_with`] with the cutter's shape known.
    fn drop<P: Profile>(&self, probe: Probe<P>, scratch: &mut MeshScratch) -> Option<f64> {
        scratch.candidates.clear();
        let candidates = &mut scratch.candidates;
        self.index.for_each_in_disk(probe.centre(), probe.radius(), |t| candidates.push(t));
        self.contacts(probe, scratch)
    }

    /// The highest contact of `probe` with the triangles of
    /// `scratch.candidates` (each tried once, vertices and edges once).
    fn contacts<P: Profile>(&self, mut probe: Probe<P>, scratch: &mut MeshScratch) -> Option<f64> {
        let query = scratch.next_query();
        let MeshScratch { candidates, vertex_seen, edge_seen, .. } = scratch;
        let (vertices, triangles, edges) = (self.mesh.vertices(), self.mesh.triangles(), self.mesh.edges());
        for &t in candidates.iter() {
            for &v in &triangles[t as usize] {
                if vertex_seen[v as usize] != query {
                    vertex_seen[v as usize] = query;
                    probe.vertex(vertices[v as usize]);
                }
            }
        }
        for &t in candidates.iter() {
            if !probe.may_win(&self.index.triangle_box(t), self.top[t as usize]) {
                continue;
            }
            probe.facet(&self.mesh.triangle(t as usize));
            for &e in &self.mesh.triangle_edges()[t as usize] {
                if edge_seen[e as usize] != query {
                    edge_seen[e as usize] = query;
                    let [a, b] = edges[e as usize];
                    probe.edge(vertices[a as usize], vertices[b as usize]);
                }
            }
        }
        probe.result()
    }
}

/// A regular grid of cutter positions: `x = x0 + i·step` for
/// `i = 0..nx`, `y = y0 + j·step` for `j = 0..ny`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// X of the first column.
    pub x0: f64,
    /// Y of the first row.
    pub y0: f64,
    /// Spacing, mm.
    pub step: f64,
    /// Columns.
    pub nx: usize,
    /// Rows.
    pub ny: usize,
}

impl Grid {
    /// Most points a grid may have.
    pub const MAX_POINTS: usize = 100_000_000;

    /// The grid from `(x0, y0)` to `(x1, y1)` at `step`: `round((x1 − x0) /
    /// step) + 1` columns, likewise rows.
    pub fn new(x0: f64, y0: f64, x1: f64, y1: f64, step: f64) -> Result<Grid, Error> {
        if ![x0, y0, x1, y1, step].iter().all(|v| v.is_finite()) {
            return Err(Error::new(ErrorKind::Grid, "grid numbers must be finite"));
        }
        if step <= 0.0 {
            return Err(Error::new(ErrorKind::Grid, format!("the grid step must be positive, got {step}")));
        }
        if x1 < x0 || y1 < y0 {
            return Err(Error::new(
                ErrorKind::Grid,
                format!("the grid must run from low to high: X1 ≥ X0 and Y1 ≥ Y0, got {x0},{y0} to {x1},{y1}"),
            ));
        }
        let (cols, rows) = (((x1 - x0) / step).round() + 1.0, ((y1 - y0) / step).round() + 1.0);
        if cols * rows > Grid::MAX_POINTS as f64 {
            return Err(Error::new(
                ErrorKind::Grid,
                format!(
                    "the grid has {cols} x {rows} points, more than {} million; use a larger step",
                    Grid::MAX_POINTS / 1_000_000
                ),
            ));
        }
        Ok(Grid { x0, y0, step, nx: cols as usize, ny: rows as usize })
    }

    /// X of column `i`.
    #[inline]
    pub fn x(&self, i: usize) -> f64 {
        self.x0 + i as f64 * self.step
    }

    /// Y of row `j`.
    #[inline]
    pub fn y(&self, j: usize) -> f64 {
        self.y0 + j as f64 * self.step
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.nx * self.ny
    }

    /// Whether the grid has no point (never, for a grid from [`Grid::new`]).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl FromStr for Grid {
    type Err = Error;

    /// `X0,Y0,X1,Y1,STEP`.
    fn from_str(s: &str) -> Result<Grid, Error> {
        let v: Vec<f64> = s
            .split(',')
            .map(|w| w.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| Error::new(ErrorKind::Grid, format!("'{s}' is not X0,Y0,X1,Y1,STEP (five numbers)")))?;
        match v[..] {
            [x0, y0, x1, y1, step] => Grid::new(x0, y0, x1, y1, step),
            _ => Err(Error::new(
                ErrorKind::Grid,
                format!("'{s}' is not X0,Y0,X1,Y1,STEP (five numbers, got {})", v.len()),
            )),
        }
    }
}

/// Drops `cutter` at every point of `grid`, in parallel; the result is
/// row by row (`y` outer, `x` inner). `on_row` is called after each row,
/// for progress.
pub fn drop_cutter_grid<S: Surface + ?Sized>(
    cutter: &Cutter,
    surface: &S,
    grid: &Grid,
    on_row: &(dyn Fn() + Sync),
) -> Vec<Option<f64>> {
    let mut out = Vec::with_capacity(grid.len());
    let mut rows_told = 0;
    let each = |zs: Vec<Option<f64>>| -> Result<(), std::convert::Infallible> {
        out.extend(zs);
        for _ in rows_told..out.len() / grid.nx.max(1) {
            on_row();
        }
        rows_told = out.len() / grid.nx.max(1);
        Ok(())
    };
    match drop_cutter_grid_in_order(cutter, surface, grid, |_, zs| zs.to_vec(), each) {
        Ok(()) => out,
        Err(never) => match never {},
    }
}

/// Points dropped at once by [`drop_cutter_grid_in_order`]: what is held
/// of its output.
const BATCH_POINTS: usize = 1 << 16;

/// Points one thread takes at a time.
const PIECE_POINTS: usize = 512;

/// [`drop_cutter_grid`] handed on as it goes, in bounded memory: the
/// points are dropped a batch of 65,536 at a time, both cores sharing
/// each batch in pieces of 512; `make(k, zs)` turns a piece (`zs` the z of
/// points `k..k + zs.len()`, row by row) into what is kept of it, on the
/// thread that dropped it; `each` gets the pieces in order, on the
/// caller's thread, and may stop the run with an error (a full disk).
pub fn drop_cutter_grid_in_order<S: Surface + ?Sized, T: Send, E>(
    cutter: &Cutter,
    surface: &S,
    grid: &Grid,
    make: impl Fn(usize, &[Option<f64>]) -> T + Sync,
    mut each: impl FnMut(T) -> Result<(), E>,
) -> Result<(), E> {
    // Working memory for each thread, kept from batch to batch (a stamp per
    // vertex and edge of the mesh: too big to make afresh).
    let pool = Mutex::new(Vec::new());
    let nx = grid.nx.max(1);
    for first in (0..grid.len()).step_by(BATCH_POINTS) {
        let last = (first + BATCH_POINTS).min(grid.len());
        let starts: Vec<usize> = (first..last).step_by(PIECE_POINTS).collect();
        let pieces: Vec<T> = starts
            .par_iter()
            .map_init(
                || Pooled::take(&pool, surface),
                |scratch, &k0| {
                    let zs: Vec<Option<f64>> = (k0..(k0 + PIECE_POINTS).min(last))
                        .map(|k| surface.drop_cutter_with(cutter, grid.x(k % nx), grid.y(k / nx), scratch.get()))
                        .collect();
                    make(k0, &zs)
                },
            )
            .collect();
        for piece in pieces {
            each(piece)?;
        }
    }
    Ok(())
}

/// A scratch taken from a pool, given back when dropped.
struct Pooled<'a, S: Surface + ?Sized> {
    pool: &'a Mutex<Vec<S::Scratch>>,
    scratch: Option<S::Scratch>,
}

impl<'a, S: Surface + ?Sized> Pooled<'a, S> {
    fn take(pool: &'a Mutex<Vec<S::Scratch>>, surface: &S) -> Pooled<'a, S> {
        let pooled = pool.lock().ok().and_then(|mut p| p.pop());
        Pooled { pool, scratch: Some(pooled.unwrap_or_else(|| surface.scratch())) }
    }

    fn get(&mut self) -> &mut S::Scratch {
        self.scratch.as_mut().expect("a scratch until dropped")
    }
}

impl<S: Surface + ?Sized> Drop for Pooled<'_, S> {
    fn drop(&mut self) {
        if let (Some(scratch), Ok(mut pool)) = (self.scratch.take(), self.pool.lock()) {
            pool.push(scratch);
        }
    }
}

/// Whether [`drop_cutter_rows`] places `cutter` whole rows at once (a ball
/// end mill) rather than point by point.
pub fn rows_at_once(cutter: &Cutter) -> bool {
    matches!(cutter, Cutter::Ball(_))
}

/// The tip z of `cutter` on a height grid at every `u` of every row `(v,
/// us)`: rows along X at `y = v`, or along Y at `x = v` when `along_y`;
/// each row's `us` ascending. The same as a query of its own at every point
/// ([`Surface::drop_cutter_with`]), to rounding. A ball end mill is placed
/// on whole rows at once, piece by piece of the surface (`rows.rs`: about
/// one contact per point instead of the thousands of cells under the
/// cutter); other shapes point by point, rows in parallel.
pub fn drop_cutter_rows(
    cutter: &Cutter,
    field: &Heightfield,
    along_y: bool,
    rows: &[(f64, &[f64])],
) -> Vec<Vec<Option<f64>>> {
    if let Cutter::Ball(ball) = cutter {
        return rows::ball_rows(field, ball, along_y, rows);
    }
    debug_assert!(!rows_at_once(cutter));
    rows.par_iter()
        .map_init(
            || field.scratch(),
            |scratch, &(v, us)| {
                let at = |u: f64| if along_y { (v, u) } else { (u, v) };
                us.iter().map(|&u| field.drop_cutter_with(cutter, at(u).0, at(u).1, scratch)).collect()
            },
        )
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_parse_and_count_like_the_cli_says() {
        let g: Grid = "0,0,10,5,0.5".parse().unwrap();
        assert_eq!((g.nx, g.ny, g.x(20), g.y(10)), (21, 11, 10.0, 5.0));
        // round((X1 − X0)/STEP): 10/3 → 3 intervals, the last x is 9.
        let g: Grid = "0,0,10,0,3".parse().unwrap();
        assert_eq!((g.nx, g.ny, g.x(3)), (4, 1, 9.0));
        for (bad, why) in [
            ("0,0,1,1", "five numbers"),
            ("0,0,1,1,0", "positive"),
            ("0,0,1,1,-1", "positive"),
            ("1,0,0,1,0.1", "low to high"),
            ("0,0,1,nan,0.1", "finite"),
            ("0,0,1e6,1e6,0.01", "more than"),
            ("a,0,1,1,1", "five numbers"),
        ] {
            let e = bad.parse::<Grid>().unwrap_err().to_string();
            assert!(e.contains(why), "{bad}: {e}");
        }
    }
}
