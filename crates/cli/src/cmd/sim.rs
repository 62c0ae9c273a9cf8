//! `kezuri sim`: material-removal simulation of a program (Z-map) with the
//! tool each move is made by, its pictures and STL, rapids into the stock,
//! what each tool removed, and the comparison with the intended surface.

mod report;

use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use clap::Args;
use kezuri_geom::write_binary_stl_to;
use kezuri_picture::sim as picture;

use crate::files::write_output;
use crate::program::{read_and_run, read_and_run_into, Ran, RunOptions};
use crate::simulation::{
    simulate_moves, simulate_once, tools, Allowance, DeviationArgs, Moves, Once, SimSetup, Simulated, Survey,
};
use kezuri_geom::PathSink;
use report::Done;

/// Options of `kezuri sim`.
#[derive(Args, Debug)]
#[command(after_help = "\
Every move lowers each cell of the stock grid to the lower envelope of the cutter swept along
it: straight moves exactly (at the cell centres), arcs as chords within --chord-tol. Rapids
cut too: a rapid that removes material is reported as a rapid into the stock (a crash), with
its line.

Tools: each move is cut with the tool in the spindle (T… M06). With --machine M.toml the
shapes come from its tool table ([tools.T1] shape = \"flat:6\"). --tool SPEC is the cutter of
a program with one tool (or none): a program that changes tools needs the table, and --tool
alone is refused for it, naming the tools it needs (T1 = ?, T2 = ?); --same-tool-for-all cuts
every move with --tool anyway. --tool for a tool the table gives another shape is refused.
Moves before the first tool change (the approach) are cut with the first tool the program
loads, so a rapid into the stock there is still found. The report gives each tool's moves,
time (on the machine file's rapids, feeds and acceleration; each tool's moves from a stop),
volume removed (over the cells: Σ (before − after) × cell area) and, with --compare, its
worst gouge; the worst gouge names the tool that cut that cell last.

Stock (--stock): X0,Y0,X1,Y1,ZTOP a box; cyl:D,H an upright cylinder of diameter D and height
H, its axis on X0 Y0 and its top at Z0 (cyl:D,H,X,Y,ZTOP to place it); FILE.stl the top
surface of a solid, no stock outside its outline. A Z-map holds one height per cell, so it has
no undercuts: a stock is what is seen of it from above, and where a cylinder or solid does not
reach the cells start at its bottom. Without --stock the stock is the XY box of the cutting
moves grown by the widest cutter's radius, its top the target's top with --compare, else the
highest feed move that moves in X or Y (a plunge from the clearance height is not cutting
there); the report says which (--json: stock_top_mm, stock_top_from). Give --stock for a real
check of the rapids.

Drills: --tool drill:D,ANGLE (or the table's shape) cuts as the cone v:D,ANGLE, but a drill cuts
along its axis only: a feed move that takes it sideways (in X or Y) through material is
reported with its line and a warning (--json: drill_side_moves).

--profile PROFILE.csv cuts with a measured tool instead of --tool SPEC: the CSV of
`kezuri tool` (`z_mm,radius_mm`: z up from the nominal tip, the radius of the swept envelope,
straight between samples). The tool is what a Z-map sees of it from below: at each radius the
lowest height it reaches there, so a worn tip cuts less deep and a worn waist leaves a ridge.
Below the first sample there is no tool; above the last it is taken as a cylinder of the
widest measured radius. Exact at the cell centres, as for the nominal shapes. It stands for
the tool the program loads even where the table gives that tool's nominal shape.

--compare TARGET reads the intended surface: an STL (binary or ASCII; the highest surface over
each cell centre) or a height grid (`x y z` or `x,y,z` lines on a regular grid). Deviation is
simulated − target: below the target is a gouge, above is material left. A gouge within the
allowance is no gouge: --gouge-tol, else the allowance a program kezuri wrote carries in its
header, `(KEZURI GOUGE-TOL 0.010)`, else 0.01 mm, mill's own; the report says which applied
(max_gouge_mm stays the deepest point, whatever the allowance).

A progress bar shows on a terminal when the cutting runs over a second.

Examples (on the bundled samples):
  kezuri sim samples/nameplate-cam.nc --tool ball:6 --res 0.2 -o plate.png
  kezuri sim samples/nameplate-cam.nc --tool ball:6 --res 0.2 \\
      --stock -110,-60,110,5,0.5 --json
  kezuri sim samples/nameplate-cam.nc --tool ball:6 --res 0.2 \\
      --stock cyl:230,10,0,-30,0.5
  kezuri relief samples/plum-sketch.png --width 40 --depth 3 --tool ball:3 \\
      --rough flat:6 --stepover 1 --surface-stl plum.stl -o plum.nc
  printf '[tools.T1]\\nshape = \"flat:6\"\\n' > tools.toml
  printf '[tools.T2]\\nshape = \"ball:3\"\\n' >> tools.toml
  kezuri sim plum.nc --machine tools.toml --res 0.1 --stock 0,0,40,30,0 \\
      --compare plum.stl -o plum.png
  kezuri sim plum.nc --tool ball:3 --same-tool-for-all --res 0.1 \\
      --compare plum.stl --json

Exit code 1 for a program with errors, a bad tool, resolution or stock, a tool without a
shape, a grid too large (the cell count is given), an unreadable target; with --fail-on-rapid
also for a rapid into the stock.")]
pub struct SimArgs {
    #[command(flatten)]
    pub run: RunOptions,
    #[command(flatten)]
    pub setup: SimSetup,
    /// Cell size of the simulation grid, mm [default: a tenth of the smallest cutter's radius, at
    /// most 0.1 mm; coarser where the stock would need more than 16 million cells].
    #[arg(long, value_name = "MM", allow_negative_numbers = true, value_parser = crate::numbers::length)]
    pub res: Option<f64>,
    /// Shaded picture of the simulated surface (PNG; `-` for stdout).
    #[arg(short, long, value_name = "HEIGHT.png")]
    pub output: Option<PathBuf>,
    /// Also write the part as simulated (the stock after cutting: its top surface, two triangles
    /// per four cell centres) as a binary STL.
    #[arg(long, value_name = "OUT.stl")]
    pub stl: Option<PathBuf>,
    /// Picture of the deviation from the target (with --compare) [default: HEIGHT-deviation.png
    /// beside -o].
    #[arg(long, value_name = "DEV.png")]
    pub deviation_png: Option<PathBuf>,
    #[command(flatten)]
    pub deviation: DeviationArgs,
    /// The job in 3D as one offline HTML page: the toolpath and the simulated part (coloured by
    /// deviation with --compare), as `kezuri view --sim` writes it.
    #[arg(long, value_name = "PAGE.html")]
    pub view: Option<PathBuf>,
    /// Bins of the deviation histogram (1 to 10000).
    #[arg(long, value_name = "N", default_value_t = 10, value_parser = clap::value_parser!(u16).range(1..=10_000))]
    pub bins: u16,
    /// Exit with code 1 when a rapid cuts into the stock.
    #[arg(long)]
    pub fail_on_rapid: bool,
    /// Print one JSON object: cells, moves, min_z_mm, stock_top_mm, stock_top_from (given, target
    /// or cutting-moves), rapids_into_stock, drill_side_moves, volume_mm3, tools (number, shape,
    /// moves, time_s, volume_mm3), …, and with --compare max_gouge_mm (and max_gouge_tool, each
    /// tool's max_gouge_mm), gouge_tol_mm, gouge_tol_from (given, program or default),
    /// gouge_cells, max_left_mm, mean_abs_dev_mm and the histogram.
    #[arg(long)]
    pub json: bool,
}

/// The name of the file at `path`, without its folder.
fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned())
}

/// The title of `sim`'s pictures: the program's name and the tools (a
/// measured tool by its file's name).
fn picture_title(file: &Path, tools: &tools::ToolSet) -> String {
    let summary = tools.summary();
    let summary = match summary.strip_prefix("profile:") {
        Some(p) => format!("measured tool {}", file_name(Path::new(p))),
        None => summary,
    };
    format!("{}: {summary}", file_name(file))
}

/// The simulation of `sim`'s program (`file`): with `--view` of the whole
/// path, which the page draws; else with the program run once to survey it
/// (its tools, extent and times), then again for each pass of the cutting,
/// never holding its path.
fn whole_or_surveyed(args: &SimArgs, file: &str) -> Result<(Ran, Allowance, Simulated)> {
    let (ran, parse_diagnostics, survey) = match &args.view {
        Some(_) => {
            let (ran, parse_diagnostics) = read_and_run(&args.run)?;
            let mut survey = Survey::new(&ran.machine.dynamics);
            survey.take(&ran.outcome.toolpath, None);
            (ran, parse_diagnostics, survey)
        }
        None => read_and_run_into(&args.run, false, |machine, _, _| Survey::new(&machine.dynamics))?,
    };
    ran.shown(&parse_diagnostics, &args.run.file, "nothing simulated")?;
    let allowance = args.deviation.allowance(&ran.sources.get(0).text);
    let moves = match &args.view {
        Some(_) => Moves::Whole(&ran.outcome.toolpath),
        None => Moves::Program { options: &args.run, ran: &ran },
    };
    let (setup, bins) = (&args.setup, args.bins.into());
    let sim = simulate_moves(&moves, survey, &ran.machine, setup, args.res, bins, allowance.mm, file)?;
    Ok((ran, allowance, sim))
}

/// Runs `kezuri sim`.
pub fn run(args: &SimArgs) -> Result<()> {
    if args.json && args.output.as_deref() == Some(Path::new("-")) {
        bail!("--json and -o - both want standard output");
    }
    let file = args.run.file.display().to_string();
    let (setup, bins) = (&args.setup, args.bins.into());
    // With --tool and --stock the program runs once, into the cutting.
    let once = match &args.view {
        Some(_) => None,
        None => simulate_once(&args.run, setup, args.res, bins, &args.deviation, &file)?,
    };
    let (mut ran, allowance, sim) = match once {
        Some(Once { ran, allowance, sim }) => (ran, allowance, sim),
        None => whole_or_surveyed(args, &file)?,
    };
    // Every output file (the DPRNT file too) is written together, or none.
    let mut out = std::mem::take(&mut ran.outputs);
    let Simulated { tools, stock, top, top_from, zmap, report, comparison, seconds, figures, times } = &sim;

    let title = picture_title(&args.run.file, tools);
    if let Some(png) = &args.output {
        out.add(Some(png), &picture::height_png(zmap, &title)?)?;
    }
    if let Some(stl) = &args.stl {
        out.add_with(Some(stl), |w| write_binary_stl_to(w, picture::surface_triangles(zmap)))?;
    }
    let mut deviation_note = None;
    let scale = args.deviation.scale(&sim, &allowance);
    if let (Some((_, heights)), Some(scale)) = (&comparison, &scale) {
        let deviation = args.deviation_png.clone().or_else(|| {
            args.output.as_ref().filter(|o| o.as_path() != Path::new("-")).map(|o| {
                let stem = o.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
                o.with_file_name(format!("{stem}-deviation.png"))
            })
        });
        if let Some(png) = deviation {
            let target = args.setup.compare.as_deref().map(file_name).unwrap_or_default();
            let subtitle = format!("deviation from {target} (simulated − target), {:.3} mm cells, +Y up", zmap.res);
            out.add(Some(&png), &picture::deviation_png(zmap, heights, scale, &title, &subtitle)?)?;
            let [deepest, most] = scale.extremes;
            let mut beyond = String::new();
            if most > scale.mm {
                beyond += &format!("; amber = more left than the scale (up to {most:.4} mm)");
            }
            if deepest > scale.mm && scale.mm > scale.gouge {
                beyond += &format!("; dark purple = a gouge deeper than the scale (down to {deepest:.4} mm)");
            }
            deviation_note = Some(format!(
                "{}: red = below the target, blue = above (material left), white = on it; \
                 full colour at ±{:.4} mm ({}); magenta = a gouge over {} µm deep ({}){beyond}; grey = no target",
                png.display(),
                scale.mm,
                scale.basis,
                scale.gouge * 1000.0,
                allowance.source()
            ));
        }
    }
    if let Some(page) = &args.view {
        let options = kezuri_picture::PageOptions::default();
        out.add(Some(page), &crate::page::page(&ran, &file, Some((&sim, scale.as_ref())), &[], &options)?)?;
    }
    out.commit()?;

    if !report.rapid_hits.is_empty() {
        let first = report.rapid_hits[0];
        eprintln!(
            "warning: {file}: {} cut into the stock; the first at line {} ({:.3} mm deep), deepest {:.3} mm",
            crate::say::count(report.rapid_hits.len() as u64, "rapid move"),
            first.line,
            first.depth,
            report.rapid_hits.iter().map(|h| h.depth).fold(0.0, f64::max)
        );
    }
    if let Some(first) = report.drill_side_moves.first() {
        eprintln!(
            "warning: {file}: {} a drill sideways in the material; the first at line {} ({:.3} mm deep): a drill \
             cuts along its axis only",
            match report.drill_side_moves.len() {
                1 => "1 feed move takes".to_string(),
                n => format!("{n} feed moves take"),
            },
            first.line,
            first.depth
        );
    }
    let done = Done {
        args,
        file: &file,
        tools,
        stock,
        top: *top,
        top_from,
        allowance,
        figures,
        report,
        times: times.clone(),
        comparison: comparison.as_ref().map(|c| &c.0),
        seconds: *seconds,
    };
    if args.json {
        write_output(None, (done.json().to_string() + "\n").as_bytes())?;
    } else {
        let text = done.text() + &deviation_note.map(|n| format!("  {n}\n")).unwrap_or_default();
        if args.output.as_deref() == Some(Path::new("-")) {
            eprint!("{text}");
        } else {
            write_output(None, text.as_bytes())?;
        }
    }
    if args.fail_on_rapid && !report.rapid_hits.is_empty() {
        bail!("{file}: {} into the stock", crate::say::count(report.rapid_hits.len() as u64, "rapid move"));
    }
    Ok(())
}
