//! The view page of a run or of a written toolpath: what
//! [`kezuri_picture::page`] takes, from the run, its machine file and its
//! simulation.

use anyhow::Result;
use kezuri_cam::Cutter;
use kezuri_geom::Toolpath;
use kezuri_picture::sim::DeviationScale;
use kezuri_picture::{Job, PageOptions};

use crate::program::Ran;
use crate::simulation::Simulated;
use kezuri_machine::Machine;

/// Tool number and shape: `cutters` (as the command that made the program
/// knows them), then the machine file's tool table.
fn shapes(machine: &Machine, cutters: &[(u32, Cutter)]) -> Vec<(u32, Cutter)> {
    let table = machine.tools.iter().filter_map(|(&n, e)| Some((n, e.shape?)));
    cutters.iter().copied().chain(table).collect()
}

/// What the page of `ran` shows, titled `title`: its moves, text, units
/// and machine, the tools' shapes from `cutters` and the machine file.
pub fn job<'a>(ran: &'a Ran, title: &'a str, cutters: &[(u32, Cutter)]) -> Job<'a> {
    Job {
        title,
        path: &ran.outcome.toolpath,
        text: Some(ran.sources.get(0).text.as_str()),
        inch: ran.outcome.inch,
        dynamics: &ran.machine.dynamics,
        shapes: shapes(&ran.machine, cutters),
        any: None,
    }
}

/// The page of a run (and of its simulation with the deviation scale):
/// the tools' shapes from the simulation, the machine file or `cutters`
/// (tool number and shape, as the command that made the program knows
/// them).
pub fn page(
    ran: &Ran,
    file: &str,
    sim: Option<(&Simulated, Option<&DeviationScale>)>,
    cutters: &[(u32, Cutter)],
    options: &PageOptions,
) -> Result<Vec<u8>> {
    let sim = sim.map(|(s, scale)| s.on_page(scale));
    Ok(kezuri_picture::page(&job(ran, file, cutters), sim.as_ref(), options)?)
}

/// The page of a toolpath with no program text (a CSV or RML-1 output).
pub fn path_page(
    path: &Toolpath,
    title: &str,
    machine: &Machine,
    cutters: &[(u32, Cutter)],
    options: &PageOptions,
) -> Result<Vec<u8>> {
    let job = Job {
        title,
        path,
        text: None,
        inch: false,
        dynamics: &machine.dynamics,
        shapes: shapes(machine, cutters),
        any: None,
    };
    Ok(kezuri_picture::page(&job, None, options)?)
}
