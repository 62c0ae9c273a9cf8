//! `kezuri view`: the job in 3D as one self-contained, offline HTML page —
//! the toolpath, the tool, the simulated part and its deviation — and the
//! `--view` output of `sim`, `mill`, `relief` and `probe mill`.
//!
//! # The page
//!
//! `page.html` (the body), `viewer.css` and `viewer.js` (hand-written
//! WebGL2, no library) are compiled in. The data follows them as three
//! inert script elements: `kz-meta`, JSON with `<`, `>` and `&` escaped;
//! `kz-data` and `kz-text`, base64 of gzip (the browser's
//! `DecompressionStream` unpacks them). The page's Content-Security-Policy
//! forbids every network request and lets only `viewer.js` run (by its
//! SHA-256), and the viewer puts program text and names on the page as text
//! only: an NC comment holding `</script>` is shown, never run.
//!
//! # kz-data
//!
//! Little-endian arrays, each from a multiple of four bytes: per move (N)
//! `kind: u8` (0 rapid, 1 feed, 2 arc, 3 plunge, 4 probe, 5 dwell),
//! `tool: u16` (index into meta.tools; number 0 there is the tool of a
//! program that loads none), `frame: u16` (index into
//! meta.frames, the work zeros), `line_delta: i32`, `feed: f32` (mm/min),
//! `seconds: f32`, `vertex_count: u32`; per vertex (V) `dx, dy, dz: i32`
//! (quanta of meta.quantum_mm from the previous vertex, the first from
//! meta.origin_mm) and `break: u8` (1: no segment from the vertex before);
//! with a simulation, `height: i32[nx·ny]` (delta coded, quanta above
//! sim.z0_mm), `block: u32[3·B]` (flat squares `i, j, size` of the vertex
//! grid) and with a target `deviation: i32[nx·ny]` (0.1 µm; i32::MIN where
//! the target does not reach).

mod blob;
mod pack;
pub(crate) mod part;

use std::io::Write as _;
use std::path::PathBuf;

use anyhow::{bail, Result};
use base64::Engine as _;
use clap::Args;
use kezuri_cam::shorten::{shorten, ShortenOptions};
use kezuri_cam::sim::Tool;
use kezuri_cam::Cutter;
use kezuri_geom::{move_times, Toolpath};
use kezuri_machine::Machine;
use serde_json::{json, Value};
use sha2::Digest as _;

use crate::program::{read_and_run_centre, Ran, RunOptions};
use crate::sim::picture::{DeviationScale, GOUGE_MM};
use crate::sim::{DeviationArgs, SimSetup, Simulated};
use blob::Blob;
use pack::ToolLook;
use part::Part;

/// How the page is made.
#[derive(Args, Debug, Clone)]
pub struct PageOptions {
    /// Largest sagitta of the chords arcs are drawn as, mm.
    #[arg(long, value_name = "MM", default_value_t = 0.01, value_parser = crate::numbers::length)]
    pub arc_tol: f64,
    /// Merge moves within this distance first (as `convert --shorten`): for a page that would
    /// pass --max-page-mb. Said on the page.
    #[arg(long, value_name = "MM", value_parser = crate::numbers::length)]
    pub shorten: Option<f64>,
    /// Leave the program text out of the page (the view and the readouts stay).
    #[arg(long)]
    pub no_text: bool,
    /// Largest page to write, MB: a bigger one is refused, naming --shorten and --no-text.
    #[arg(long, value_name = "MB", default_value_t = 32.0)]
    pub max_page_mb: f64,
    /// Most vertices of the simulated part's mesh (a finer grid is shown coarser, each vertex the
    /// lowest cell under it).
    #[arg(long, value_name = "N", default_value_t = 1_000_000)]
    pub mesh_vertices: usize,
}

impl Default for PageOptions {
    /// The options' defaults, as `--help` gives them.
    fn default() -> PageOptions {
        crate::program::options_from(&[]).expect("PageOptions' defaults parse")
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
|deviation|): red below the target, blue above, gouges deeper than --gouge-tol (1 µm) in
magenta; the worst gouge and the first rapid into the stock are marked and listed.

A program of a million moves makes a page of some 8 MB; above --max-page-mb (32) the page is
refused: --shorten TOL merges moves first and says so on the page, --no-text leaves the program
text out.

Examples (on the bundled samples):
  kezuri view samples/nameplate-cam.nc -o plate-path.html
  kezuri view samples/nameplate-cam.nc --sim --tool ball:6 --res 0.2 \\
      -o plate.html
  kezuri sim samples/nameplate-cam.nc --tool ball:6 --res 0.2 --view plate.html

Exit code 1 for a program with errors or a page over --max-page-mb.")]
pub struct ViewArgs {
    #[command(flatten)]
    pub run: RunOptions,
    /// Cut the program out of the stock (needs --res) and draw the part.
    #[arg(long, requires = "res")]
    pub sim: bool,
    /// Cell size of the simulation grid, mm (with --sim).
    #[arg(long, value_name = "MM", value_parser = crate::numbers::length, requires = "sim")]
    pub res: Option<f64>,
    #[command(flatten)]
    pub setup: SimSetup,
    #[command(flatten)]
    pub deviation: DeviationArgs,
    #[command(flatten)]
    pub page: PageOptions,
    /// The page [default: standard output].
    #[arg(short, long, value_name = "PAGE.html")]
    pub output: Option<PathBuf>,
}

/// Runs `kezuri view`.
pub fn run(args: &ViewArgs) -> Result<()> {
    let (mut ran, parse_diagnostics) = read_and_run_centre(&args.run)?;
    ran.shown(&parse_diagnostics, &args.run.file, "no page written")?;
    let mut out = std::mem::take(&mut ran.outputs);
    let file = args.run.file.display().to_string();
    if !args.sim && (args.setup.compare.is_some() || args.setup.stock.is_some()) {
        bail!("--compare and --stock are for the simulated part: give --sim --res MM too");
    }
    let sim = match args.res {
        Some(res) => Some(crate::sim::simulate(&ran.outcome.toolpath, &ran.machine, &args.setup, res, 10, &file)?),
        None => None,
    };
    let any: Option<Cutter> = args.setup.tool.as_deref().map(str::parse).transpose()?;
    let scale = sim.as_ref().and_then(|s| args.deviation.scale(s));
    let sim_and_scale = sim.as_ref().map(|s| (s, scale.as_ref()));
    let page = page_with(&Job::of(&ran, &file), sim_and_scale, &[], any, &args.page)?;
    out.add(args.output.as_deref(), &page)?;
    out.commit()?;
    let moves = ran.outcome.toolpath.moves.len();
    crate::say::note!(
        "{file}: {moves} moves{}; page {:.1} MB{}",
        if sim.is_some() { " and the simulated part" } else { "" },
        page.len() as f64 / 1e6,
        args.output.as_ref().map(|p| format!(" in {}", p.display())).unwrap_or_default()
    );
    Ok(())
}

/// What a page shows: a program's moves, its text, its units and the
/// machine it runs on (for the cycle time and the tool table).
struct Job<'a> {
    title: &'a str,
    path: &'a Toolpath,
    text: Option<&'a str>,
    inch: bool,
    machine: &'a Machine,
}

impl<'a> Job<'a> {
    fn of(ran: &'a Ran, title: &'a str) -> Job<'a> {
        Job {
            title,
            path: &ran.outcome.toolpath,
            text: Some(ran.sources.get(0).text.as_str()),
            inch: ran.outcome.inch,
            machine: &ran.machine,
        }
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
    page_with(&Job::of(ran, file), sim, cutters, None, options)
}

/// The page of a toolpath with no program text (a CSV or RML-1 output).
pub fn path_page(
    path: &Toolpath,
    title: &str,
    machine: &Machine,
    cutters: &[(u32, Cutter)],
    options: &PageOptions,
) -> Result<Vec<u8>> {
    page_with(&Job { title, path, text: None, inch: false, machine }, None, cutters, None, options)
}

/// [`page`], where `any` is the shape of every tool nothing else names.
fn page_with(
    job: &Job,
    sim: Option<(&Simulated, Option<&DeviationScale>)>,
    cutters: &[(u32, Cutter)],
    any: Option<Cutter>,
    options: &PageOptions,
) -> Result<Vec<u8>> {
    let file = job.title;
    let mut notes = Vec::new();
    let original = job.path;
    let shortened;
    let path = match options.shorten {
        Some(tolerance) => {
            shortened = shorten(original, &ShortenOptions { tolerance, arcs: false });
            notes.push(format!(
                "shortened within {tolerance} mm: {} moves drawn as {}",
                original.moves.len(),
                shortened.moves.len()
            ));
            &shortened
        }
        None => original,
    };
    let (seconds, _) = move_times(path, &job.machine.dynamics);
    let looks = tool_looks(job.machine, path, sim.map(|s| s.0), cutters, any);
    let mut blob = Blob::default();
    let packed = pack::pack(path, &seconds, looks, options.arc_tol, &mut blob)?;
    let mut bounds = packed.bounds;
    let mut marks = Vec::new();
    let sim_meta = match sim {
        Some((s, scale)) => {
            let part = Part {
                zmap: &s.zmap,
                target: s.comparison.as_ref().map(|c| c.1.as_slice()),
                scale,
                max_vertices: options.mesh_vertices,
            };
            let (meta, (lo, hi)) = part.pack(&mut blob);
            if meta["cell_mm"].as_f64() != Some(s.zmap.res) {
                notes.push(format!(
                    "the part is shown at {:.3} mm cells (simulated at {} mm), each the lowest of its cells",
                    meta["cell_mm"].as_f64().unwrap_or(0.0),
                    s.zmap.res
                ));
            }
            bounds = Some(match bounds {
                Some((a, b)) => (std::array::from_fn(|k| a[k].min(lo[k])), std::array::from_fn(|k| b[k].max(hi[k]))),
                None => (lo, hi),
            });
            marks.extend(sim_marks(s, original, path, scale.map_or(GOUGE_MM, |d| d.gouge)));
            meta
        }
        None => Value::Null,
    };
    let text = job.text.filter(|_| !options.no_text);
    let mut meta = packed.meta();
    let extra = json!({
        "version": 1,
        "title": file,
        "units": if job.inch { "inch" } else { "mm" },
        "unit_mm": if job.inch { 25.4 } else { 1.0 },
        "bbox_mm": bounds.map(|(a, b)| [a, b]),
        "arc_tolerance_mm": options.arc_tol,
        "cycle_time_s": seconds.iter().sum::<f64>(),
        "notes": notes,
        "text": text.is_some(),
        "sim": sim_meta,
        "marks": marks,
    });
    if let (Value::Object(m), Value::Object(e)) = (&mut meta, extra) {
        m.extend(e);
    }
    let html = html(&meta, &blob.into_bytes(), text)?;
    let limit = options.max_page_mb * 1e6;
    if html.len() as f64 > limit {
        bail!(
            "{file}: the page would be {:.1} MB, over --max-page-mb {}: merge moves with --shorten 0.005 \
             (or a larger tolerance){}, or raise --max-page-mb",
            html.len() as f64 / 1e6,
            options.max_page_mb,
            if text.is_some() { ", leave the program text out with --no-text" } else { "" }
        );
    }
    Ok(html)
}

/// How each tool the program loads looks: the simulation's cutters, else
/// `cutters`, the machine file's shapes, or `any`.
fn tool_looks(
    machine: &Machine,
    path: &Toolpath,
    sim: Option<&Simulated>,
    cutters: &[(u32, Cutter)],
    any: Option<Cutter>,
) -> Vec<ToolLook> {
    let mut numbers: Vec<u32> = path.moves.iter().map(|m| m.tool).collect();
    numbers.sort_unstable();
    numbers.dedup();
    let changes = numbers.iter().any(|&n| n != 0);
    numbers
        .into_iter()
        .map(|number| {
            let simulated = sim.and_then(|s| {
                let k = s.tools.table.iter().position(|(n, _)| *n == number)?;
                Some((s.tools.names[k].clone(), profile(&s.tools.table[k].1)))
            });
            let named = || cutters.iter().find(|(n, _)| *n == number).map(|(_, c)| *c);
            let (shape, outline) = match simulated {
                Some((name, outline)) => (Some(name), Some(outline)),
                None => match named().or_else(|| machine.tools.get(&number).and_then(|e| e.shape)).or(any) {
                    Some(c) => (Some(c.to_string()), Some(profile(&Tool::Cutter(c)))),
                    None => (None, None),
                },
            };
            let label = match (number, &shape) {
                (0, _) if changes => "before the first tool change".to_string(),
                (0, Some(s)) => format!("the tool, {s} (no tool change)"),
                (0, None) => "the tool (no tool change; shape not given)".to_string(),
                (n, Some(s)) => format!("T{n} {s}"),
                (n, None) => format!("T{n} (shape not given)"),
            };
            ToolLook { number, label, shape, profile: outline }
        })
        .collect()
}

/// The outline of a tool from its tip up, `(z, r)`: the cutting end
/// sampled over its radius, then the flutes as a cylinder three radii high.
fn profile(tool: &Tool) -> Vec<[f64; 2]> {
    let mut out: Vec<[f64; 2]> = match tool {
        Tool::Cutter(c) => {
            let r = c.radius();
            (0..=24).map(|k| r * f64::from(k) / 24.0).map(|x| [c.height(x), x]).collect()
        }
        Tool::Measured(m) => m.corners().iter().map(|&(r, z)| [z, r]).collect(),
    };
    out.retain(|p| p[0].is_finite() && p[1].is_finite());
    let (top, r) = out.last().map_or((0.0, tool.radius()), |p| (p[0], p[1]));
    out.push([top + 3.0 * tool.radius().max(r), tool.radius().max(r)]);
    out
}

/// The marks of a simulation: the first rapid into the stock and the
/// worst gouge, if deeper than `gouge`. Move numbers are of `drawn` (the moves of `run`, or fewer
/// where shortened: then the rapid is marked without one).
fn sim_marks(s: &Simulated, run: &Toolpath, drawn: &Toolpath, gouge: f64) -> Vec<Value> {
    let mut marks = Vec::new();
    if let Some(hit) = s.report.rapid_hits.first() {
        let m = &run.moves[hit.index];
        let index = (run.moves.len() == drawn.moves.len()).then_some(hit.index);
        marks.push(json!({
            "kind": "rapid",
            "label": format!("first rapid into the stock: line {}, {:.3} mm deep ({} in all)", hit.line, hit.depth, s.report.rapid_hits.len()),
            "at_mm": m.end.xyz(),
            "move": index,
            "line": hit.line,
        }));
    }
    if let Some((c, _)) = &s.comparison {
        if let (Some(cell), true) = (c.gouge_cell, c.max_gouge > gouge) {
            let [x, y] = s.zmap.centre(cell % s.zmap.nx, cell / s.zmap.nx);
            let by = s.report.cut_by.get(cell).copied().filter(|&b| b != kezuri_cam::sim::UNCUT);
            // Tool 0 is the one tool of a program that changes none.
            let number = by.map(|b| s.report.tools[b as usize].number).filter(|&n| n != 0);
            let tool = number.map(|n| format!(", cut last by T{n}")).unwrap_or_default();
            marks.push(json!({
                "kind": "gouge",
                "label": format!("worst gouge {:.1} µm below the target at X{x:.3} Y{y:.3}{tool}", c.max_gouge * 1000.0),
                "at_mm": [x, y, s.zmap.z[cell]],
                "move": null,
                "line": null,
            }));
        }
    }
    marks
}

const VIEWER_JS: &str = include_str!("view/viewer.js");
const VIEWER_CSS: &str = include_str!("view/viewer.css");
const BODY: &str = include_str!("view/page.html");

/// `data` gzipped and in base64.
fn packed(data: &[u8]) -> Result<String> {
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::new(3));
    gz.write_all(data)?;
    Ok(base64::engine::general_purpose::STANDARD.encode(gz.finish()?))
}

/// The page: the viewer and the data as inert script elements, a policy
/// that lets only the viewer run and nothing load.
fn html(meta: &Value, data: &[u8], text: Option<&str>) -> Result<Vec<u8>> {
    let hash = base64::engine::general_purpose::STANDARD.encode(sha2::Sha256::digest(VIEWER_JS.as_bytes()));
    // JSON holds < > & only inside strings, where \u escapes mean the same.
    let meta = meta.to_string().replace('<', "\\u003c").replace('>', "\\u003e").replace('&', "\\u0026");
    let mut page = String::with_capacity(data.len() / 2 + VIEWER_JS.len() + 4096);
    page.push_str("<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n");
    page.push_str(&format!(
        "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; script-src 'sha256-{hash}'; \
         style-src 'unsafe-inline'; img-src data: blob:\">\n"
    ));
    page.push_str("<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n");
    page.push_str("<title>kezuri view</title>\n<style>");
    page.push_str(VIEWER_CSS);
    page.push_str("</style>\n</head><body>\n");
    page.push_str(BODY);
    page.push_str("\n<script type=\"application/json\" id=\"kz-meta\">");
    page.push_str(&meta);
    page.push_str("</script>\n<script type=\"application/octet-stream\" id=\"kz-data\">");
    page.push_str(&packed(data)?);
    page.push_str("</script>\n");
    if let Some(text) = text {
        page.push_str("<script type=\"application/octet-stream\" id=\"kz-text\">");
        page.push_str(&packed(text.as_bytes())?);
        page.push_str("</script>\n");
    }
    page.push_str("<script>");
    page.push_str(VIEWER_JS);
    page.push_str("</script>\n</body></html>\n");
    Ok(page.into_bytes())
}
