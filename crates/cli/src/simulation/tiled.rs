//! A grid over the memory allowed (`--max-memory`), cut in tiles of rows.
//!
//! Every figure of the report — the surface's range, the volumes, the
//! rapids, and with `--compare` the gouges, the material left, the mean
//! deviation and the gouged cells — comes from every cell, tile by tile.
//! What needs the grid whole — the pictures, the STL, the page and the
//! histogram's counts — is drawn from a sample of the cells: every `f`-th
//! cell each way (`f` odd, so a sampled cell's centre is the centre of the
//! coarse cell it stands for), at most [`SAMPLE_CELLS`] of them.

use anyhow::{bail, Result};
use kezuri_cam::sim::compare::{gouged_cells, gouges_by_tool, histogram, target_heights, Comparison, Tally, ToolGouge};
use kezuri_cam::sim::{
    cut_tiles, tile_rows, Cutting, Grid, SimOptions, SimReport, Start, Tooling, ZMap, CELL_BYTES, UNCUT,
};

/// Most tiles, each a pass over the moves, a grid is cut in.
pub const MAX_TILES: usize = 10_000;

/// Most cells of the sample that the pictures, the STL and the page show.
pub const SAMPLE_CELLS: u64 = 16_000_000;

/// What the whole grid gave where it was cut in tiles.
#[derive(Clone, Debug)]
pub struct Tiles {
    /// Tiles cut, each a pass over the moves.
    pub count: usize,
    /// Rows a tile.
    pub rows: usize,
    /// The sample takes every `sample`-th cell each way.
    pub sample: usize,
}

/// A simulation cut in tiles: the sample, the report, the comparison (its
/// histogram from the sample) and the figures of every cell.
pub struct TiledRun {
    /// The sample of the cut grid.
    pub zmap: ZMap,
    /// The report; `cut_by` of the sample.
    pub report: SimReport,
    /// With a target: the comparison and the target's heights over the sample.
    pub comparison: Option<(Comparison, Vec<f64>)>,
    /// The stock's highest cell before cutting.
    pub top: f64,
    /// Lowest and highest cell after cutting.
    pub range: (f64, f64),
    /// Cells deeper than the allowance below the target.
    pub gouged: usize,
    /// Each tool's worst gouge (by slot).
    pub gouges: Vec<Option<ToolGouge>>,
    /// The slot of the tool that lowered the worst gouge's cell last.
    pub gouge_slot: Option<u8>,
    pub tiles: Tiles,
}

/// The sample of `grid` at every `f`-th cell each way (`f` odd): its
/// cells centred on the sampled cells' centres.
fn sample_grid(grid: &Grid, f: usize) -> Grid {
    let h = (f - 1) / 2;
    // A side shorter than half a sample: one cell, the last.
    let n = |cells: usize| cells.saturating_sub(h).div_ceil(f).max(1);
    Grid { x0: grid.x0, y0: grid.y0, res: grid.res * f as f64, nx: n(grid.nx), ny: n(grid.ny) }
}

/// What a tile is cut with: the tools, the first tool the program loads,
/// and a pass over the moves into a tile's cutting.
pub struct Cut<'a, 'b> {
    pub tooling: Tooling<'a>,
    pub first: u32,
    pub pass: &'b mut dyn FnMut(&mut Cutting<'_>) -> Result<()>,
}

/// Cuts the moves of `cut` over the grid of `start` in tiles within
/// `options.max_memory` (a target's heights taking 8 bytes a cell more),
/// each tile a pass over the moves, compared with `target`'s triangles
/// where given, deeper than `allowance` a gouge.
pub fn run(
    cut: Cut<'_, '_>,
    start: &Start<'_>,
    options: &SimOptions,
    target: Option<&[[[f64; 3]; 3]]>,
    allowance: f64,
    bins: usize,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<TiledRun> {
    let grid = start.grid(options)?;
    let extra = if target.is_some() { 8 } else { 0 };
    // The sample: at most an eighth of the memory, the tiles the rest less
    // the bands being cut (their heights in mm and before each tool).
    let per_sample = CELL_BYTES + extra;
    let most = SAMPLE_CELLS.min(options.max_memory / 8 / per_sample).max(1) as f64;
    let mut f = (grid.cells() as f64 / most).sqrt().ceil().max(1.0) as usize;
    f += 1 - f % 2;
    let coarse = sample_grid(&grid, f);
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    // At most a quarter of the memory: many cores and a small budget share.
    let bands = (threads as u64 * 32 * grid.nx as u64 * 12).min(options.max_memory / 4);
    let budget = options.max_memory.saturating_sub(coarse.bytes() + coarse.cells() * extra + bands);
    let row = grid.nx as u64 * (CELL_BYTES + extra);
    if row > budget {
        let size = |bytes: f64| match bytes {
            b if b >= 1e9 => format!("{:.1} GB", b / 1e9),
            b if b >= 1e6 => format!("{:.1} MB", b / 1e6),
            b => format!("{:.1} kB", b / 1e3),
        };
        bail!(
            "a grid of {} × {} = {} cells does not fit in --max-memory ({}) even in tiles: a tile is whole rows of \
             {} cells ({} each) and the cutting holds {} more rows of heights ({}); use a coarser resolution, a \
             smaller stock or more memory",
            grid.nx,
            grid.ny,
            grid.cells(),
            size(options.max_memory as f64),
            grid.nx,
            size(row as f64),
            threads * 32,
            size(bands as f64)
        );
    }
    let rows = tile_rows(&grid, CELL_BYTES + extra, budget)?;
    let passes = grid.ny.div_ceil(rows);
    if passes > MAX_TILES {
        bail!(
            "a grid of {} × {} = {} cells would take {passes} tiles of {rows} rows within --max-memory, each a \
             pass over the moves (at most {MAX_TILES}): use a coarser resolution, a smaller stock or more memory",
            grid.nx,
            grid.ny,
            grid.cells()
        );
    }
    let mut zmap = ZMap::filled(&coarse, 0..coarse.ny, 0.0)?;
    let mut cut_by = vec![UNCUT; zmap.cells()];
    let (mut top, mut range) = (f64::NEG_INFINITY, (f64::INFINITY, f64::NEG_INFINITY));
    let (mut tally, mut gouged, mut gouges, mut gouge_slot) = (Tally::default(), 0, Vec::new(), None);
    let mut count = 0;
    let h = (f - 1) / 2;
    let Cut { tooling, first, pass } = cut;
    let report =
        cut_tiles::<anyhow::Error>(tooling, first, start, options, rows, progress, pass, &mut |tile, by, high| {
            count += 1;
            top = top.max(high);
            let (lo, hi) = tile.range();
            range = (range.0.min(lo), range.1.max(hi));
            for jc in 0..coarse.ny {
                let j = (jc * f + h).min(grid.ny - 1);
                if j < tile.first_row || j >= tile.first_row + tile.ny {
                    continue;
                }
                let row = (j - tile.first_row) * tile.nx;
                for ic in 0..coarse.nx {
                    zmap.nm[jc * coarse.nx + ic] = tile.nm[row + (ic * f + h).min(grid.nx - 1)];
                    cut_by[jc * coarse.nx + ic] = by[row + (ic * f + h).min(grid.nx - 1)];
                }
            }
            let Some(triangles) = target else { return Ok(()) };
            let heights = target_heights(tile, triangles.iter().copied());
            let before = tally.comparison().gouge_cell;
            tally.add(tile, &heights);
            let worst = tally.comparison().gouge_cell;
            if let Some(cell) = worst.filter(|_| worst != before) {
                let slot = by[cell - tile.first_row * tile.nx];
                gouge_slot = (slot != UNCUT).then_some(slot);
            }
            gouged += gouged_cells(tile, &heights, allowance);
            let these = gouges_by_tool(tile, &heights, by, 256);
            gouges.resize(these.len(), None);
            for (g, t) in gouges.iter_mut().zip(these) {
                if let Some(t) = t.filter(|t| g.is_none_or(|g: ToolGouge| t.depth > g.depth)) {
                    *g = Some(t);
                }
            }
            Ok(())
        })?;
    gouges.truncate(report.tools.len());
    let comparison = match target {
        Some(triangles) => {
            let mut c = tally.comparison();
            if c.compared == 0 {
                bail!("the target covers none of the {} cells", grid.cells());
            }
            let heights = target_heights(&zmap, triangles.iter().copied());
            histogram(&mut c, &zmap, &heights, bins);
            // The worst gouge's cell in the sample: the one it falls in.
            c.gouge_cell = c.gouge_cell.map(|k| {
                let (i, j) = (k % grid.nx, k / grid.nx);
                (j / f).min(coarse.ny - 1) * coarse.nx + (i / f).min(coarse.nx - 1)
            });
            Some((c, heights))
        }
        None => None,
    };
    let report = SimReport { cut_by, ..report };
    let tiles = Tiles { count, rows, sample: f };
    Ok(TiledRun { zmap, report, comparison, top, range, gouged, gouges, gouge_slot, tiles })
}
