//! A grid larger than the memory allowed, cut in tiles.
//!
//! A tile is a run of whole rows of the grid. Each tile is a pass over all
//! the segments; a segment whose swept box (its XY box grown by the tool's
//! radius) misses the tile's rows is skipped before any cell is looked at.
//! A tile's cell centres are the whole grid's (rows are counted over the
//! whole grid), each cell's height is the least of the same envelopes in
//! the same order, rounded once to the nanometre, and the tool that
//! lowered it last is the same: the tiles give the untiled grid cell for
//! cell, and the volumes (whole nanometres summed) and rapid hits the same
//! figures.

use std::ops::Range;

use kezuri_geom::Toolpath;

use super::segments::first_tool;
use super::stock::{Grid, Start, ZMap};
use super::tools::Tooling;
use super::{Cuts, Cutting, SimOptions, SimReport};
use crate::error::{Error, ErrorKind};

/// Rows a tile of `grid` holds so that its cells, at `bytes_per_cell`,
/// take at most `budget` bytes; the whole grid when it fits. An error when
/// not even one row fits.
pub fn tile_rows(grid: &Grid, bytes_per_cell: u64, budget: u64) -> Result<usize, Error> {
    let row = (grid.nx as u64).saturating_mul(bytes_per_cell.max(1));
    if row > budget {
        return Err(Error::new(
            ErrorKind::TooManyCells,
            format!(
                "one row of the grid ({} cells, {:.1} MB) is more than the memory allowed ({:.1} MB): use a \
                 coarser resolution or allow more memory",
                grid.nx,
                row as f64 / 1e6,
                budget as f64 / 1e6
            ),
        ));
    }
    Ok(((budget / row) as usize).clamp(1, grid.ny.max(1)))
}

/// The row ranges of the tiles of `rows` rows each over `grid`, bottom up.
pub fn tiles(grid: &Grid, rows: usize) -> impl Iterator<Item = Range<usize>> + '_ {
    let rows = rows.max(1);
    (0..grid.ny.div_ceil(rows)).map(move |t| t * rows..((t + 1) * rows).min(grid.ny))
}

/// What is done with each tile cut: `(tile, cut_by, top)`.
pub type TileDone<'a, E> = dyn FnMut(&ZMap, &[u8], f64) -> Result<(), E> + 'a;

/// [`super::simulate_tools`] over the grid of `start`, `rows` rows at a
/// time ([`tile_rows`]): each tile is made, cut and handed to
/// `each(tile, cut_by, top)` (the tool that lowered each of its cells
/// last, as [`SimReport::cut_by`]; its highest cell before cutting), then
/// dropped. The report's `cut_by` is empty;
/// everything else is what the untiled simulation reports.
/// `progress(done, total)` counts over all the tiles.
pub fn simulate_tiles<E: From<Error>>(
    path: &Toolpath,
    tooling: Tooling<'_>,
    start: &Start<'_>,
    options: &SimOptions,
    rows: usize,
    progress: &(dyn Fn(u64, u64) + Sync),
    each: &mut TileDone<'_, E>,
) -> Result<SimReport, E> {
    let mut pass = |cutting: &mut Cutting<'_>| cutting.add_last(path).map_err(E::from);
    cut_tiles(tooling, first_tool(path), start, options, rows, progress, &mut pass, each)
}

/// [`simulate_tiles`] of a path that `pass` hands to each tile's cutting
/// ([`Cutting::add`] piece by piece: a program run once a tile), `first`
/// the first tool it loads.
#[allow(clippy::too_many_arguments)]
pub fn cut_tiles<E: From<Error>>(
    tooling: Tooling<'_>,
    first: u32,
    start: &Start<'_>,
    options: &SimOptions,
    rows: usize,
    progress: &(dyn Fn(u64, u64) + Sync),
    pass: &mut dyn FnMut(&mut Cutting<'_>) -> Result<(), E>,
    each: &mut TileDone<'_, E>,
) -> Result<SimReport, E> {
    let grid = start.grid(options)?;
    let count = grid.ny.div_ceil(rows.max(1)) as u64;
    let mut all: Option<Cuts> = None;
    for (t, range) in tiles(&grid, rows).enumerate() {
        let mut tile = start.rows(options, range)?;
        let top = tile.range().1;
        // Each tile a 1000th part of the whole.
        let step = |done: u64, total: u64| {
            let part = (done * 1000).checked_div(total).unwrap_or(1000);
            progress(t as u64 * 1000 + part, count * 1000)
        };
        let mut cutting = Cutting::new(tooling, &mut tile, options, Some(first), Some(*start))?;
        cutting.progress = &step;
        pass(&mut cutting)?;
        let (cuts, cut_by) = cutting.finish()?;
        match &mut all {
            Some(all) => all.add(cuts),
            None => all = Some(cuts),
        }
        each(&tile, &cut_by, top)?;
    }
    let all = all.ok_or_else(|| Error::new(ErrorKind::TooManyCells, "the grid has no rows"))?;
    Ok(all.report(grid.res))
}
