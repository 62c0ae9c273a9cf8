//! `kezuri view`: the job in 3D as one self-contained, offline HTML page —
//! the toolpath, the tool, the simulated part and its deviation; the page
//! itself is [`kezuri_picture::view`]'s.

use std::path::PathBuf;

use anyhow::{bail, Result};
use clap::Args;
use kezuri_cam::Cutter;
use kezuri_picture::view::{Page, PathPage};
use kezuri_picture::{Job, PageOptions};

use crate::program::{read_and_run, read_and_run_into, RunOptions};
use crate::simulation::{simulate, DeviationArgs, SimSetup};

/// How the page is made: `view`'s options of [`PageOptions`].
#[derive(Args, Debug, Clone)]
pub struct PageArgs {
    /// How far the chords arcs are drawn as may stray from the arc (their sagitta), mm.
    #[arg(long, value_name = "MM", default_value_t = PageOptions::default().arc_tol, value_parser = crate::numbers::length)]
    pub arc_tol: f64,
    /// Merge moves within this distance first (as `convert --shorten`). Said on the page.
    #[arg(long, value_name = "MM", value_parser = crate::numbers::length)]
    pub shorten: Option<f64>,
    /// Leave the program text out of the page (the view and the readouts stay).
    #[arg(long)]
    pub no_text: bool,
    /// Largest page to write, MB: a program that would make a bigger one is drawn simplified to
    /// fit (said on the page and in the summary).
    #[arg(long, value_name = "MB", default_value_t = PageOptions::default().max_page_mb)]
    pub max_page_mb: f64,
    /// Most vertices of the simulated part's mesh (a finer grid is shown coarser, each vertex the
    /// lowest cell under it).
    #[arg(long, value_name = "N", default_value_t = PageOptions::default().mesh_vertices)]
    pub mesh_vertices: usize,
}

impl PageArgs {
    /// The page's options.
    fn options(&self) -> PageOptions {
        PageOptions {
            arc_tol: self.arc_tol,
            shorten: self.shorten,
            no_text: self.no_text,
            max_page_mb: self.max_page_mb,
            mesh_vertices: self.mesh_vertices,
        }
    }
}

/// Options of `kezuri view`.
#[derive(Args, Debug)]
#[command(after_help = "\
The page is one HTML file that opens from disk in Chromium, Chrome, Edge or Firefox (WebGL2):
nothing is fetched, nothing is sent. Drag to turn the view, right-drag (or shift-drag) to pan,
the wheel to zoom; Fit, Top, Front, Side and Iso set the view. The slider and the step buttons
play the program move by move: the path so far, the tool at its position, the block's line
highlighted in the program text beside the view, the position in the program's units, the feed
and the elapsed cycle time (on the machine file's rapids, feeds and acceleration). Click a
segment to jump to its line; click a line to jump to its first move.

Colours: rapids red, feeds blue, arcs green, plunges yellow, probing violet; or each tool its
own colour (the legend switches). Arcs are drawn as chords within --arc-tol. Moves of rotary
axes are drawn by their X Y Z only, which the page says.

With --sim the program is cut out of the stock as `kezuri sim` cuts it (the same --tool,
--machine, --stock and --res) and the part is drawn; with --compare the part is coloured by its
deviation from the target on a fixed scale (--deviation-scale, else the 99th percentile of
|deviation|): red below the target, blue above, gouges deeper than --gouge-tol in magenta
(default: the allowance a program kezuri wrote carries in its header, `(KEZURI GOUGE-TOL
0.010)`, else 0.01 mm, said in the summary); the worst gouge and the first rapid into the stock
are marked and listed.

A program of a million moves makes a page of some 8 MB. Where the page would pass --max-page-mb
(32), the path is drawn simplified, to the finest tolerance (0.001 to 5 mm) that fits, chosen
before the page is built: runs of moves of one colour, tool and work zero drawn through the
fewest of their own points that keep every point of the path within the tolerance, arcs as
chords; rapids, tool changes and breaks stay where they are. The page and the summary say it
(\"simplified to 0.05 mm to fit 32 MB: 9,000,000 moves drawn as 1,212,000\"). Program text that
would take more than half the page is left out, said the same way.

Examples (on the bundled samples):
  kezuri view samples/nameplate-cam.nc -o plate-path.html
  kezuri view samples/nameplate-cam.nc --sim --tool ball:6 --res 0.2 \\
      -o plate.html
  kezuri sim samples/nameplate-cam.nc --tool ball:6 --res 0.2 --view plate.html

Exit code 1 for a program with errors, or a path that even simplified to 5 mm would not fit
--max-page-mb (refused before the page is built).")]
pub struct ViewArgs {
    #[command(flatten)]
    pub run: RunOptions,
    /// Cut the program out of the stock and draw the part.
    #[arg(long)]
    pub sim: bool,
    /// Cell size of the simulation grid, mm (with --sim) [default: a tenth of the smallest
    /// cutter's radius, at most 0.1 mm; coarser where the stock would need more than 16 million
    /// cells].
    #[arg(long, value_name = "MM", value_parser = crate::numbers::length, requires = "sim")]
    pub res: Option<f64>,
    #[command(flatten)]
    pub setup: SimSetup,
    #[command(flatten)]
    pub deviation: DeviationArgs,
    #[command(flatten)]
    pub page: PageArgs,
    /// The page [default: standard output].
    #[arg(short, long, value_name = "PAGE.html")]
    pub output: Option<PathBuf>,
}

/// Runs `kezuri view`: the path drawn as the run hands it on, never held
/// whole; with --sim or --shorten, which need the whole path, from the
/// whole run.
pub fn run(args: &ViewArgs) -> Result<()> {
    if args.sim || args.page.shorten.is_some() {
        return whole(args);
    }
    let options = args.page.options();
    let (mut ran, parse_diagnostics, builder) =
        read_and_run_into(&args.run, false, |machine, _, _| PathPage::new(&machine.dynamics, &options, Vec::new()))?;
    ran.shown(&parse_diagnostics, &args.run.file, "no page written")?;
    let mut out = std::mem::take(&mut ran.outputs);
    if args.setup.compare.is_some() || args.setup.stock.is_some() {
        bail!("--compare and --stock are for the simulated part: give --sim too");
    }
    let file = args.run.file.display().to_string();
    let any: Option<Cutter> = args.setup.tool.as_deref().map(str::parse).transpose()?;
    let job = Job { any, ..crate::page::job(&ran, &file, &[]) };
    let moves = builder.moves();
    // The text read again in pieces (a mapped file lets each go once read).
    let text = &ran.sources.get(0).text;
    let mut pieces = |take: &mut dyn FnMut(&[u8]) -> bool| {
        let bytes = text.as_bytes();
        for start in (0..bytes.len()).step_by(TEXT_PIECE) {
            let end = (start + TEXT_PIECE).min(bytes.len());
            let more = take(&bytes[start..end]);
            text.forget(start..end);
            if !more {
                break;
            }
        }
    };
    let page = builder.finish(&job, None, Some(&mut pieces))?;
    out.add(args.output.as_deref(), &page.html)?;
    out.commit()?;
    said(args, &file, moves, "", &page);
    Ok(())
}

/// The program text is packed this many bytes at a time.
const TEXT_PIECE: usize = 1 << 20;

/// `kezuri view` from the whole run: with --sim (the part simulated from
/// the whole path) or --shorten.
fn whole(args: &ViewArgs) -> Result<()> {
    let (mut ran, parse_diagnostics) = read_and_run(&args.run)?;
    ran.shown(&parse_diagnostics, &args.run.file, "no page written")?;
    let mut out = std::mem::take(&mut ran.outputs);
    let file = args.run.file.display().to_string();
    if !args.sim && (args.setup.compare.is_some() || args.setup.stock.is_some()) {
        bail!("--compare and --stock are for the simulated part: give --sim too");
    }
    let allowance = args.deviation.allowance(&ran.sources.get(0).text);
    let sim = if args.sim {
        Some(simulate(&ran.outcome.toolpath, &ran.machine, &args.setup, args.res, 10, allowance.mm, &file)?)
    } else {
        None
    };
    let any: Option<Cutter> = args.setup.tool.as_deref().map(str::parse).transpose()?;
    let scale = sim.as_ref().and_then(|s| args.deviation.scale(s, &allowance));
    let shown = sim.as_ref().map(|s| s.on_page(scale.as_ref()));
    let job = Job { any, ..crate::page::job(&ran, &file, &[]) };
    let page = kezuri_picture::view::fitted_page(&job, shown.as_ref(), &args.page.options())?;
    out.add(args.output.as_deref(), &page.html)?;
    out.commit()?;
    let gouges = match &scale {
        Some(_) => format!(" (gouges past {} mm, {})", allowance.mm, allowance.source()),
        None => String::new(),
    };
    let part = if sim.is_some() { " and the simulated part" } else { "" };
    said(args, &file, ran.outcome.toolpath.moves.len() as u64, &format!("{part}{gouges}"), &page);
    Ok(())
}

/// Says what the page shows: `moves` moves, and `what` else.
fn said(args: &ViewArgs, file: &str, moves: u64, what: &str, page: &Page) {
    let fitted: String = page.fitted.iter().map(|f| format!("; {f}")).collect();
    crate::say::note!(
        "{file}: {moves} moves{what}; page {:.1} MB{}{fitted}",
        page.html.len() as f64 / 1e6,
        args.output.as_ref().map(|p| format!(" in {}", p.display())).unwrap_or_default()
    );
}
