//! `sim` with the program run once: where `--tool` (or `--profile`) and
//! `--stock` say all the cutting needs before the run (the cutter, the
//! grid, the cell size) and the grid is held whole, the run hands its path
//! to the cutting on the other core as it makes it, with the survey beside
//! it; what the survey finds (the tools the program uses, U V W moved) is
//! judged after the run, as the survey run would judge it before.

use std::time::Instant;

use anyhow::{Context, Result};
use kezuri_cam::sim::{Cutting, SimOptions, SimReport, Tooling};

use super::DEFAULT_RES_HELP;
use super::{compared, default_res, stock, tools, Allowance, DeviationArgs, SimSetup, Simulated, Survey};
use crate::program::{read_and_run_into, Ran, RunOptions};

/// A simulation run once: the run, the gouge allowance and the
/// simulation.
pub struct Once {
    pub ran: Ran,
    pub allowance: Allowance,
    pub sim: Simulated,
}

/// Runs `kezuri sim`'s program (`o`, named `file`) once into the cutting,
/// at `res` mm cells (none: [`DEFAULT_RES_HELP`]), compared in `bins` bins;
/// `None` where the run alone cannot say all the cutting needs (no
/// `--tool` or `--profile`, no `--stock`, a grid cut in tiles) or a setting
/// is refused: then the program is surveyed first, and the refusal said
/// after its diagnostics, as before.
pub fn simulate_once(
    o: &RunOptions,
    setup: &SimSetup,
    res: Option<f64>,
    bins: usize,
    deviation: &DeviationArgs,
    file: &str,
) -> Result<Option<Once>> {
    let (Ok(Some((tool, _))), Some(Ok(stock))) = (tools::given(setup), setup.stock.as_deref().map(stock::parse)) else {
        return Ok(None);
    };
    let res_given = res;
    let res = res.unwrap_or_else(|| default_res(&stock, std::iter::once(tool.radius()), setup));
    let mut options = SimOptions::new(res);
    options.chord_tolerance = setup.chord_tol;
    options.max_memory = setup.memory();
    let Ok(solid) = stock.solid(setup.units) else { return Ok(None) };
    let start = stock.start(solid.as_deref());
    let Ok(grid) = start.grid(&options) else { return Ok(None) };
    // A target's heights take 8 bytes a cell more.
    let extra = if setup.compare.is_some() { 8 } else { 0 };
    if grid.bytes().saturating_add(grid.cells().saturating_mul(extra)) > options.max_memory {
        return Ok(None);
    }
    let Ok(mut zmap) = start.rows(&options, 0..grid.ny) else { return Ok(None) };
    let top = zmap.range().1;
    let t0 = Instant::now();
    let Ok(cutting) = Cutting::new(Tooling::One(&tool), &mut zmap, &options, None, Some(start)) else {
        return Ok(None);
    };
    let (ran, parse_diagnostics, (cutting, survey)) =
        read_and_run_into(o, false, |machine, _, _| (cutting, Survey::new(&machine.dynamics)))?;
    let cut = cutting.finish().map(|(cuts, cut_by)| SimReport { cut_by, ..cuts.report(res) });
    let seconds = t0.elapsed().as_secs_f64();
    // What the survey run would have said before the cutting, in its order.
    ran.shown(&parse_diagnostics, &o.file, "nothing simulated")?;
    survey.refuse_uvw(file)?;
    let numbers = survey.numbers();
    let tools = tools::tool_set(setup, &ran.machine.tools, ran.machine.tools_from, &numbers)
        .with_context(|| file.to_string())?;
    let target = match &setup.compare {
        Some(target) => Some((target.as_path(), crate::surface::read_surface(target, setup.units)?.triangles())),
        None => None,
    };
    if res_given.is_none() {
        crate::say::note!("{file}: cells of {res} mm (no --res: {DEFAULT_RES_HELP})");
    }
    let report = cut.with_context(|| file.to_string())?;
    let times = survey.times(&tools.table.iter().map(|(n, _)| *n).collect::<Vec<_>>());
    let allowance = deviation.allowance(&ran.sources.get(0).text);
    let (comparison, figures) = compared(&zmap, &report, target, bins, allowance.mm, grid)?;
    let sim = Simulated { tools, stock, top, top_from: "given", zmap, report, comparison, seconds, figures, times };
    Ok(Some(Once { ran, allowance, sim }))
}
