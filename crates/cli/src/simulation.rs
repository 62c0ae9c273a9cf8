//! A simulation as `sim` and `view --sim` run it: what it is cut with and
//! compared to (the options both take), the stock and the cutters read, the
//! cutting with a progress bar, and the comparison with the target.

mod once;
pub mod stock;
pub mod survey;
pub mod tiled;
pub mod tools;

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use clap::{ArgGroup, Args};
use kezuri_cam::mill::{read_gouge_note, GOUGE_TOL};
use kezuri_cam::sim::compare::Comparison;
use kezuri_cam::sim::compare::{compare, gouged_cells, gouges_by_tool, target_heights, ToolGouge};
use kezuri_cam::sim::{Cutting, Grid, SimOptions, SimReport, Tooling, ZMap, CELL_BYTES, DEFAULT_MEMORY, UNCUT};
use kezuri_geom::{PathSink, Toolpath};
use kezuri_picture::sim::DeviationScale;
use kezuri_picture::Simulation;

use crate::program::{Ran, RunOptions};
use crate::progress::LateBar;
use kezuri_machine::Machine;
pub use once::{simulate_once, Once};
use stock::StockSpec;
pub use survey::Survey;

/// How the deviation from the target is coloured: the options `sim` and
/// `view` share.
#[derive(Args, Debug)]
pub struct DeviationArgs {
    /// Deviation shown in full colour, mm; beyond it amber (material left) or dark purple (a
    /// gouge), the largest in the legend [default: the 99th percentile of |deviation|].
    #[arg(long, value_name = "MM", value_parser = crate::numbers::length)]
    pub deviation_scale: Option<f64>,
    /// Deeper than this below the target is a gouge (magenta), mm [default: the allowance the
    /// program's header gives, `(KEZURI GOUGE-TOL 0.010)` as mill and relief write it, else
    /// 0.01 as mill's --gouge-tol].
    #[arg(long, value_name = "MM", value_parser = crate::numbers::length)]
    pub gouge_tol: Option<f64>,
}

/// The gouge allowance a comparison applies, and where it came from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Allowance {
    /// Deeper than this below the target is a gouge, mm.
    pub mm: f64,
    /// `given` (--gouge-tol), `program` (its header comment) or `default`.
    pub from: &'static str,
}

impl Allowance {
    /// How the summaries say where it came from.
    pub fn source(&self) -> &'static str {
        match self.from {
            "given" => "--gouge-tol",
            "program" => "the program's header",
            _ => "the default",
        }
    }
}

impl DeviationArgs {
    /// The gouge allowance: --gouge-tol where given, else the one the
    /// program's `text` carries in a comment (`KEZURI GOUGE-TOL 0.010`, as
    /// kezuri writes it), else the default. A mapped program's pages are let
    /// go of as its comments are read through.
    pub fn allowance(&self, text: &kezuri_nc::source::Text) -> Allowance {
        if let Some(mm) = self.gouge_tol {
            return Allowance { mm, from: "given" };
        }
        let forget = |r| text.forget(r);
        match kezuri_nc::comments_forgetting(text, &forget).find_map(|(_, c)| read_gouge_note(c)) {
            Some(mm) => Allowance { mm, from: "program" },
            None => Allowance { mm: GOUGE_TOL, from: "default" },
        }
    }

    /// The scale of `sim`'s deviation, where it has a target, its gouges
    /// deeper than `allowance`.
    pub fn scale(&self, sim: &Simulated, allowance: &Allowance) -> Option<DeviationScale> {
        let (_, heights) = sim.comparison.as_ref()?;
        Some(DeviationScale::new(&sim.zmap, heights, self.deviation_scale, allowance.mm))
    }
}

/// What a simulation is cut with and compared to: the options `sim` and
/// `view --sim` share.
#[derive(Args, Debug, Default)]
#[command(group(ArgGroup::new("cutter").args(["tool", "profile"])))]
pub struct SimSetup {
    /// Cutter of a program with one tool: flat:D, ball:D, bull:D,R, oval:D,RL, v:D,ANGLE or
    /// drill:D,ANGLE (mm, degrees) [default: the machine file's tool table].
    #[arg(
        long,
        value_name = "SPEC",
        long_help = tool_help!("Cutter of a program with one tool [default: the machine file's tool table].")
    )]
    pub tool: Option<String>,
    /// A measured tool instead of --tool: its profile CSV (`z_mm,radius_mm`, from `kezuri tool
    /// profile`).
    #[arg(long, alias = "tool-profile", value_name = "PROFILE.csv")]
    pub profile: Option<PathBuf>,
    /// Cut every move with --tool (or --profile), whatever tools the program changes to.
    #[arg(long)]
    pub same_tool_for_all: bool,
    /// Stock: a box X0,Y0,X1,Y1,ZTOP, a cylinder cyl:D,H[,X,Y,ZTOP] or a solid's top FILE.stl, mm
    /// [default: the cutting moves' XY box grown by the widest cutter's radius, its top the
    /// target's top (--compare), else the highest feed move that moves in X or Y].
    #[arg(long, value_name = "X0,Y0,X1,Y1,ZTOP|cyl:D,H|FILE.stl", allow_hyphen_values = true)]
    pub stock: Option<String>,
    /// The part as designed, to compare the cut with: an STL (such as relief's --surface-stl), or a
    /// height grid of `x y z` lines.
    #[arg(long, value_name = "TARGET")]
    pub compare: Option<PathBuf>,
    /// The unit the --compare and --stock files are drawn in (STL files carry none).
    /// [default: mm, with a note where the model is under 13 mm in every direction]
    #[arg(long, value_enum, value_name = "mm|inch")]
    pub units: Option<crate::surface::Units>,
    /// How far the chords arcs are cut as may stray from the arc (their sagitta), mm.
    #[arg(long, value_name = "MM", default_value_t = 0.001, value_parser = crate::numbers::length)]
    pub chord_tol: f64,
    /// Memory for the grid (5 bytes a cell: its height to the nanometre and the tool that cut it
    /// last; 13 with --compare): K, M, G or T, powers of 1024. A larger grid is cut in tiles of
    /// rows, each a pass over the moves (`sim` runs the program again for each): the same cells
    /// [default: 2G].
    #[arg(long, value_name = "SIZE", value_parser = crate::numbers::memory, conflicts_with = "max_cells")]
    pub max_memory: Option<u64>,
    /// The same as --max-memory, as a number of cells (kept for older scripts: 5 bytes a cell).
    #[arg(long, value_name = "N")]
    pub max_cells: Option<u64>,
}

impl SimSetup {
    /// The memory the grid may take, bytes.
    pub fn memory(&self) -> u64 {
        match (self.max_memory, self.max_cells) {
            (Some(bytes), _) => bytes,
            (None, Some(cells)) => cells.saturating_mul(CELL_BYTES),
            (None, None) => DEFAULT_MEMORY,
        }
    }
}

/// A simulation done: the cutters, the stock, the cut grid, the report and
/// the comparison with the target.
pub struct Simulated {
    pub tools: tools::ToolSet,
    pub stock: StockSpec,
    /// The stock's highest point before cutting.
    pub top: f64,
    /// Where the top came from: `given` (--stock), `target` (the top of
    /// --compare's surface) or `cutting-moves` (the highest sideways feed).
    pub top_from: &'static str,
    pub zmap: ZMap,
    pub report: SimReport,
    /// With --compare: the comparison and the target's height over each cell.
    pub comparison: Option<(Comparison, Vec<f64>)>,
    /// Seconds the cutting took.
    pub seconds: f64,
    /// The figures of every cell (where the grid was cut in tiles, `zmap`
    /// and the comparison's heights are a sample of it).
    pub figures: Figures,
    /// Seconds each tool's moves take (by [`tools::ToolSet::table`]), each
    /// run of them from a stop.
    pub times: Vec<f64>,
}

/// What the report says of every cell of the grid, whole or in tiles.
pub struct Figures {
    /// The grid cut.
    pub grid: Grid,
    /// Lowest and highest cell after cutting.
    pub range: (f64, f64),
    /// With a target: cells deeper than the allowance below it.
    pub gouged: usize,
    /// With a target: each tool's worst gouge (by [`SimReport::tools`]).
    pub gouges: Vec<Option<ToolGouge>>,
    /// With a target: the number of the tool that lowered the worst gouge's cell last.
    pub gouge_tool: Option<u32>,
    /// Where the grid was cut in tiles: how.
    pub tiles: Option<tiled::Tiles>,
}

impl Simulated {
    /// The simulation as the view page shows it, its deviation on `scale`.
    pub fn on_page<'a>(&'a self, scale: Option<&'a DeviationScale>) -> Simulation<'a> {
        Simulation {
            tools: &self.tools.table,
            names: &self.tools.names,
            zmap: &self.zmap,
            report: &self.report,
            comparison: self.comparison.as_ref().map(|(c, heights)| (c, heights.as_slice())),
            scale,
        }
    }
}

/// The cell size `sim` and `view --sim` take without `--res`, as their
/// helps say it.
pub const DEFAULT_RES_HELP: &str = "a tenth of the smallest cutter's radius, at most 0.1 mm; \
coarser where the stock would need more than 16 million cells";

/// Most cells the default cell size gives (16 million: 144 MB).
const DEFAULT_CELLS: f64 = 16e6;

/// The cell size without `--res`: a tenth of the smallest cutter's radius,
/// at most 0.1 mm, coarsened to whole hundredths until the stock holds at
/// most [`DEFAULT_CELLS`] cells (or what `--max-memory` holds).
fn default_res(stock: &StockSpec, radii: impl Iterator<Item = f64>, setup: &SimSetup) -> f64 {
    let smallest = radii.filter(|r| *r > 0.0).fold(f64::INFINITY, f64::min);
    let fine = (smallest / 10.0).min(0.1);
    // The stock's area, from a grid of 1 mm cells.
    let mut coarse = SimOptions::new(1.0);
    coarse.max_memory = setup.memory();
    let area = stock.grid(&coarse, setup.units).map_or(0.0, |z| z.cells() as f64);
    let most = DEFAULT_CELLS.min((setup.memory() / CELL_BYTES) as f64);
    if area / (fine * fine) > most {
        ((area / most).sqrt() * 100.0).ceil() / 100.0
    } else {
        fine
    }
}

/// Where a simulation's moves come from: a path held whole, or a program
/// run again for each pass over its moves (the grid, or each tile of it),
/// its path handed on in pieces to the cutting on the other core.
pub enum Moves<'a> {
    Whole(&'a Toolpath),
    /// The program `ran` (run first with `options`, to survey it).
    Program {
        options: &'a RunOptions,
        ran: &'a Ran,
    },
}

impl Moves<'_> {
    /// One pass over the moves, cut by `cutting`.
    fn pass(&self, cutting: &mut Cutting<'_>) -> Result<()> {
        match self {
            Moves::Whole(path) => Ok(cutting.add_last(path)?),
            Moves::Program { options, ran } => crate::program::run_again_into(options, ran, cutting).map(|_| ()),
        }
    }
}

/// Cuts `path` (of `file`, run on `machine`): [`simulate_moves`] of the
/// whole path.
pub fn simulate(
    path: &Toolpath,
    machine: &Machine,
    setup: &SimSetup,
    res: Option<f64>,
    bins: usize,
    allowance: f64,
    file: &str,
) -> Result<Simulated> {
    let mut survey = Survey::new(&machine.dynamics);
    survey.take(path, None);
    simulate_moves(&Moves::Whole(path), survey, machine, setup, res, bins, allowance, file)
}

/// Cuts the `moves` (of `file`, run on `machine`; `survey` made of them)
/// out of the stock at `res` mm cells (none: [`DEFAULT_RES_HELP`]), with a
/// progress bar on a terminal, and compares it with the target (a
/// histogram of `bins` bins; deeper than `allowance` below it a gouge). A
/// grid over `--max-memory` is cut in tiles ([`tiled`]), each a pass over
/// the moves. A program that moves U V W is refused
/// ([`Survey::refuse_uvw`]).
#[allow(clippy::too_many_arguments)]
pub fn simulate_moves(
    moves: &Moves<'_>,
    survey: Survey,
    machine: &Machine,
    setup: &SimSetup,
    res: Option<f64>,
    bins: usize,
    allowance: f64,
    file: &str,
) -> Result<Simulated> {
    survey.refuse_uvw(file)?;
    let stock = setup.stock.as_deref().map(stock::parse).transpose()?;
    let tools = tools::tool_set(setup, &machine.tools, machine.tools_from, &survey.numbers())
        .with_context(|| file.to_string())?;
    // The target first: without --stock its top is the top of the material.
    let target = match &setup.compare {
        Some(target) => {
            let surface = crate::surface::read_surface(target, setup.units)?;
            Some((target, surface.top(), surface.triangles()))
        }
        None => None,
    };
    let (stock, top_from) = match stock {
        Some(s) => (s, "given"),
        None => {
            // A drill's sideways feed is the mistake to find, not the top.
            let drills: Vec<u32> = tools.table.iter().filter(|(_, t)| t.is_drill()).map(|(n, _)| *n).collect();
            let top = survey.top(&|n| !drills.contains(&n));
            let mut implied = survey.extent.stock(tools.reach(), top).with_context(|| file.to_string())?;
            let from = match &target {
                Some((_, top, _)) => {
                    implied.top = *top;
                    "target"
                }
                None => "cutting-moves",
            };
            (StockSpec::Box(implied), from)
        }
    };
    let res = res.unwrap_or_else(|| {
        let res = default_res(&stock, tools.table.iter().map(|(_, t)| t.radius()), setup);
        crate::say::note!("{file}: cells of {res} mm (no --res: {DEFAULT_RES_HELP})");
        res
    });
    let mut options = SimOptions::new(res);
    options.chord_tolerance = setup.chord_tol;
    options.max_memory = setup.memory();
    let solid = stock.solid(setup.units)?;
    let start = stock.start(solid.as_deref());
    let grid = start.grid(&options)?;
    let first = survey.first();
    let numbers: Vec<u32> = tools.table.iter().map(|(n, _)| *n).collect();
    let times = survey.times(&numbers);
    let t0 = Instant::now();
    // A program run again shows its own bar, by the bytes it has read.
    let bar = match moves {
        Moves::Whole(_) => LateBar::new("cutting", "pieces", Duration::from_secs(1)),
        Moves::Program { .. } => None,
    };
    let progress = |done: u64, total: u64| {
        if let Some(bar) = &bar {
            bar.update(done, total)
        }
    };
    let tooling = Tooling::Table(&tools.table);
    // A target's heights take 8 bytes a cell more.
    let extra = if target.is_some() { 8 } else { 0 };
    if grid.bytes().saturating_add(grid.cells().saturating_mul(extra)) > options.max_memory {
        let triangles = target.as_ref().map(|t| t.2.as_slice());
        let mut pass = |cutting: &mut Cutting<'_>| moves.pass(cutting);
        let cut = tiled::Cut { tooling, first, pass: &mut pass };
        let run = tiled::run(cut, &start, &options, triangles, allowance, bins, &progress);
        if let Some(bar) = &bar {
            bar.finish();
        }
        let run = run.with_context(|| file.to_string())?;
        let seconds = t0.elapsed().as_secs_f64();
        let gouge_tool = run.gouge_slot.map(|s| run.report.tools[s as usize].number);
        let figures = Figures {
            grid,
            range: run.range,
            gouged: run.gouged,
            gouges: run.gouges,
            gouge_tool,
            tiles: Some(run.tiles),
        };
        let (zmap, report, comparison, top) = (run.zmap, run.report, run.comparison, run.top);
        return Ok(Simulated { tools, stock, top, top_from, zmap, report, comparison, seconds, figures, times });
    }
    let mut zmap = start.rows(&options, 0..grid.ny)?;
    let top = zmap.range().1;
    let cut = (|| -> Result<SimReport> {
        let mut cutting = Cutting::new(tooling, &mut zmap, &options, Some(first), Some(start))?;
        cutting.progress = &progress;
        moves.pass(&mut cutting)?;
        let (cuts, cut_by) = cutting.finish()?;
        Ok(SimReport { cut_by, ..cuts.report(res) })
    })();
    if let Some(bar) = &bar {
        bar.finish();
    }
    let report = cut.with_context(|| file.to_string())?;
    let seconds = t0.elapsed().as_secs_f64();
    let target = target.map(|(target, _, triangles)| (target.as_path(), triangles));
    let (comparison, figures) = compared(&zmap, &report, target, bins, allowance, grid)?;
    Ok(Simulated { tools, stock, top, top_from, zmap, report, comparison, seconds, figures, times })
}

/// A comparison with the target, and the target's height over each cell.
type Compared = (Comparison, Vec<f64>);

/// The comparison of the cut `zmap` (with its `report`) with the target
/// (its file and triangles) where there is one, in `bins` bins, deeper
/// than `allowance` a gouge; and the figures of the whole `grid`.
fn compared(
    zmap: &ZMap,
    report: &SimReport,
    target: Option<(&std::path::Path, Vec<[[f64; 3]; 3]>)>,
    bins: usize,
    allowance: f64,
    grid: Grid,
) -> Result<(Option<Compared>, Figures)> {
    let comparison = match target {
        Some((target, triangles)) => {
            let heights = target_heights(zmap, triangles);
            let c = compare(zmap, &heights, bins);
            if c.compared == 0 {
                bail!("{}: the target covers none of the {} cells", target.display(), zmap.cells());
            }
            Some((c, heights))
        }
        None => None,
    };
    let (gouged, gouges, gouge_tool) = match &comparison {
        Some((c, heights)) => {
            let slot = c.gouge_cell.and_then(|k| report.cut_by.get(k)).filter(|&&b| b != UNCUT);
            (
                gouged_cells(zmap, heights, allowance),
                gouges_by_tool(zmap, heights, &report.cut_by, report.tools.len()),
                slot.map(|&b| report.tools[b as usize].number),
            )
        }
        None => (0, Vec::new(), None),
    };
    Ok((comparison, Figures { grid, range: zmap.range(), gouged, gouges, gouge_tool, tiles: None }))
}
