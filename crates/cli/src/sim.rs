//! `kezuri sim`: material-removal simulation of a program (Z-map), its
//! pictures and STL, rapids into the stock, and the comparison with the
//! intended surface.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use clap::{ArgGroup, Args};
use image::codecs::png::PngEncoder;
use image::{ExtendedColorType, ImageEncoder};
use kezuri_cam::sim::compare::{compare, target_heights, Comparison};
use kezuri_cam::sim::{simulate_tool, MeasuredTool, SimOptions, SimReport, Stock, Tool, ZMap};
use kezuri_cam::Cutter;
use kezuri_geom::{write_binary_stl_to, Triangle, Vec3};
use serde_json::json;

use crate::files::{write_output, write_output_with};
use crate::program::{read_and_run_centre, RunOptions};

/// Options of `kezuri sim`.
#[derive(Args, Debug)]
#[command(group(ArgGroup::new("cutter").required(true).args(["tool", "tool_profile"])))]
#[command(after_help = "\
Every move lowers each cell of the stock grid to the lower envelope of the cutter swept along
it: straight moves exactly (at the cell centres), arcs as chords within --chord-tol. Rapids
cut too: a rapid that removes material is reported as a rapid into the stock (a crash), with
its line. Without --stock the stock is the XY box of the cutting moves grown by the cutter
radius, its top at their highest point; give --stock for a real check of the rapids.

--tool-profile PROFILE.csv cuts with a measured tool instead of --tool SPEC: the CSV of
`kezuri tool` (`z_mm,radius_mm`: z up from the nominal tip, the radius of the swept envelope,
straight between samples). The tool is what a Z-map sees of it from below: at each radius the
lowest height it reaches there, so a worn tip cuts less deep and a worn waist leaves a ridge.
Below the first sample there is no tool; above the last it is taken as a cylinder of the
widest measured radius. Exact at the cell centres, as for the nominal shapes.

--compare TARGET reads the intended surface: an STL (binary or ASCII; the highest surface over
each cell centre) or a height grid (`x y z` or `x,y,z` lines on a regular grid). Deviation is
simulated − target: below the target is a gouge, above is material left.

Examples:
  kezuri sim part.nc --tool ball:6 --res 0.05 -o part.png
  kezuri sim part.nc --tool ball:6 --res 0.1 --stock 0,0,100,100,0 --json
  kezuri sim part.nc --tool oval:16,24 --res 0.05 --compare part.stl --deviation-png dev.png --stl cut.stl
  kezuri sim part.nc --tool-profile worn.csv --res 0.01 --compare part.stl --json

Exit code 1 for a program with errors, a bad tool, resolution or stock, a grid too large
(the cell count is given), an unreadable target; with --fail-on-rapid also for a rapid into
the stock.")]
pub struct SimArgs {
    #[command(flatten)]
    pub run: RunOptions,
    /// Cutter: flat:D, ball:D, bull:D,R, oval:D,RL or v:D,ANGLE (mm, degrees). This or
    /// --tool-profile.
    #[arg(long, value_name = "SPEC")]
    pub tool: Option<String>,
    /// A measured tool instead of --tool: its profile CSV (`z_mm,radius_mm`, from `kezuri tool`).
    #[arg(long, value_name = "PROFILE.csv")]
    pub tool_profile: Option<PathBuf>,
    /// Cell size of the simulation grid, mm.
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    pub res: f64,
    /// Stock box and top, mm [default: the cutting moves' XY box grown by the cutter radius, top at
    /// their highest Z].
    #[arg(long, value_name = "X0,Y0,X1,Y1,ZTOP", allow_hyphen_values = true)]
    pub stock: Option<String>,
    /// Intended surface: an STL, or a height grid of `x y z` lines.
    #[arg(long, value_name = "TARGET")]
    pub compare: Option<PathBuf>,
    /// Shaded picture of the simulated surface (PNG; `-` for stdout).
    #[arg(short, long, value_name = "HEIGHT.png")]
    pub output: Option<PathBuf>,
    /// The simulated surface as a binary STL (two triangles per four cell centres).
    #[arg(long, value_name = "OUT.stl")]
    pub stl: Option<PathBuf>,
    /// Picture of the deviation from the target (with --compare) [default: HEIGHT-deviation.png
    /// beside -o].
    #[arg(long, value_name = "DEV.png")]
    pub deviation_png: Option<PathBuf>,
    /// Deviation shown in full colour, mm [default: the largest deviation].
    #[arg(long, value_name = "MM")]
    pub deviation_scale: Option<f64>,
    /// Largest sagitta of the chords arcs are cut as, mm.
    #[arg(long, value_name = "MM", default_value_t = 0.001)]
    pub chord_tol: f64,
    /// Most cells the grid may have (8 bytes each).
    #[arg(long, value_name = "N", default_value_t = 250_000_000)]
    pub max_cells: usize,
    /// Bins of the deviation histogram.
    #[arg(long, value_name = "N", default_value_t = 10)]
    pub bins: usize,
    /// Exit with code 1 when a rapid cuts into the stock.
    #[arg(long)]
    pub fail_on_rapid: bool,
    /// Print one JSON object: cells, moves, min_z_mm, rapids_into_stock, …, and with
    /// --compare max_gouge_mm, max_left_mm, mean_abs_dev_mm and the histogram.
    #[arg(long)]
    pub json: bool,
}

fn parse_stock(text: &str) -> Result<Stock> {
    let v: Vec<f64> = text
        .split(',')
        .map(|s| s.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect::<Option<_>>()
        .with_context(|| format!("--stock '{text}': expected five numbers X0,Y0,X1,Y1,ZTOP"))?;
    if v.len() != 5 {
        bail!("--stock '{text}': expected five numbers X0,Y0,X1,Y1,ZTOP, got {}", v.len());
    }
    if !(v[2] > v[0] && v[3] > v[1]) {
        bail!("--stock '{text}': need X0 < X1 and Y0 < Y1");
    }
    Ok(Stock { x0: v[0], y0: v[1], x1: v[2], y1: v[3], top: v[4] })
}

/// The tool to cut with: --tool's cutter or --tool-profile's measured tool.
fn read_tool(args: &SimArgs) -> Result<Tool> {
    match (&args.tool, &args.tool_profile) {
        (Some(spec), None) => Ok(Tool::Cutter(spec.parse::<Cutter>()?)),
        (None, Some(path)) => Ok(Tool::Measured(MeasuredTool::new(&crate::tool::read_profile(path)?))),
        _ => bail!("give exactly one of --tool SPEC and --tool-profile PROFILE.csv"),
    }
}

/// How the reports name the tool: the cutter's SPEC, or `profile:FILE`.
fn tool_name(args: &SimArgs, tool: &Tool) -> String {
    match (tool, &args.tool_profile) {
        (Tool::Measured(_), Some(path)) => format!("profile:{}", path.display()),
        _ => tool.to_string(),
    }
}

/// Runs `kezuri sim`.
pub fn run(args: &SimArgs) -> Result<()> {
    let tool = read_tool(args)?;
    if args.json && args.output.as_deref() == Some(Path::new("-")) {
        bail!("--json and -o - both want standard output");
    }
    let mut options = SimOptions::new(args.res);
    options.chord_tolerance = args.chord_tol;
    options.max_cells = args.max_cells;
    if !(options.resolution.is_finite() && options.resolution > 0.0) {
        bail!("--res must be a positive number of mm, got {}", args.res);
    }
    let stock = args.stock.as_deref().map(parse_stock).transpose()?;

    let (ran, parse_diagnostics) = read_and_run_centre(&args.run)?;
    ran.print_diagnostics(&parse_diagnostics);
    let file = args.run.file.display().to_string();
    if ran.errors() > 0 {
        bail!("{file}: {} error(s); nothing simulated", ran.errors());
    }
    let path = &ran.outcome.toolpath;
    let stock = match stock {
        Some(s) => s,
        None => Stock::around_tool(path, &tool).with_context(|| file.clone())?,
    };
    let mut zmap = ZMap::new(&stock, &options)?;
    let t0 = Instant::now();
    let report = simulate_tool(path, &tool, &mut zmap, &options).with_context(|| file.clone())?;
    let seconds = t0.elapsed().as_secs_f64();

    let comparison = match &args.compare {
        Some(target) => {
            let triangles = crate::surface::read_surface(target)?.triangles();
            let heights = target_heights(&zmap, triangles);
            let c = compare(&zmap, &heights, args.bins);
            if c.compared == 0 {
                bail!("{}: the target covers none of the {} cells", target.display(), zmap.cells());
            }
            Some((c, heights))
        }
        None => None,
    };

    if let Some(out) = &args.output {
        write_output(Some(out), &height_png(&zmap)?)?;
    }
    if let Some(out) = &args.stl {
        write_surface_stl(out, &zmap)?;
    }
    let mut deviation_note = None;
    if let Some((c, heights)) = &comparison {
        let out = args.deviation_png.clone().or_else(|| {
            args.output.as_ref().filter(|o| o.as_path() != Path::new("-")).map(|o| {
                let stem = o.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
                o.with_file_name(format!("{stem}-deviation.png"))
            })
        });
        if let Some(out) = out {
            let scale = match args.deviation_scale {
                Some(s) if s.is_finite() && s > 0.0 => s,
                Some(s) => bail!("--deviation-scale must be a positive number of mm, got {s}"),
                None => c.max_gouge.max(c.max_left).max(1e-9),
            };
            write_output(Some(&out), &deviation_png(&zmap, heights, scale)?)?;
            deviation_note = Some(format!(
                "{}: red = below the target (gouge), blue = above (material left), white = on it; \
                 full colour at ±{scale:.4} mm; grey = no target",
                out.display()
            ));
        }
    }

    let (lo, hi) = zmap.range();
    if !report.rapid_hits.is_empty() {
        let first = report.rapid_hits[0];
        eprintln!(
            "warning: {file}: {} rapid move(s) cut into the stock; the first at line {} ({:.3} mm deep), deepest {:.3} mm",
            report.rapid_hits.len(),
            first.line,
            first.depth,
            report.rapid_hits.iter().map(|h| h.depth).fold(0.0, f64::max)
        );
    }
    let to_stderr = args.output.as_deref() == Some(Path::new("-"));
    if args.json {
        let value = json_report(args, &file, &tool, &stock, &zmap, &report, comparison.as_ref().map(|c| &c.0), seconds);
        write_output(None, (value.to_string() + "\n").as_bytes())?;
    } else {
        let text = text_report(&file, &tool, &stock, &zmap, &report, seconds, (lo, hi), comparison.as_ref(), args);
        let text = text + &deviation_note.map(|n| format!("  {n}\n")).unwrap_or_default();
        if to_stderr {
            eprint!("{text}");
        } else {
            write_output(None, text.as_bytes())?;
        }
    }
    if args.fail_on_rapid && !report.rapid_hits.is_empty() {
        bail!("{file}: {} rapid move(s) into the stock", report.rapid_hits.len());
    }
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn json_report(
    args: &SimArgs,
    file: &str,
    tool: &Tool,
    stock: &Stock,
    zmap: &ZMap,
    report: &SimReport,
    comparison: Option<&Comparison>,
    seconds: f64,
) -> serde_json::Value {
    let (lo, hi) = zmap.range();
    let mut v = json!({
        "file": file,
        "tool": tool_name(args, tool),
        "res_mm": zmap.res,
        "nx": zmap.nx,
        "ny": zmap.ny,
        "cells": zmap.cells(),
        "stock": {"x0": stock.x0, "y0": stock.y0, "x1": stock.x1, "y1": stock.y1, "top": stock.top},
        "moves": report.moves,
        "segments": report.segments,
        "rotary_moves": report.rotary_moves,
        "unplaced_moves": report.unplaced_moves,
        "chord_tol_mm": args.chord_tol,
        "min_z_mm": lo,
        "max_z_mm": hi,
        "rapids_into_stock": report.rapid_hits.len(),
        "first_rapid_into_stock_line": report.rapid_hits.first().map(|h| h.line),
        "rapid_hits": report.rapid_hits.iter().take(100)
            .map(|h| json!({"line": h.line, "move": h.index, "depth_mm": h.depth})).collect::<Vec<_>>(),
        "seconds": seconds,
    });
    if let (Tool::Measured(m), Some(o)) = (tool, v.as_object_mut()) {
        o.insert(
            "tool_profile".into(),
            json!({
                "samples": m.samples(),
                "diameter_mm": 2.0 * m.radius(),
                "tip_mm": m.tip(),
                "lower_surface_corners": m.corners().len(),
            }),
        );
    }
    if let Some(c) = comparison {
        let extra = json!({
            "max_gouge_mm": c.max_gouge,
            "max_left_mm": c.max_left,
            "mean_abs_dev_mm": c.mean_abs_dev,
            "max_gouge_at": c.gouge_at,
            "max_left_at": c.left_at,
            "compared_cells": c.compared,
            "cells_without_target": c.missing,
            "deviation_range_mm": [c.range.0, c.range.1],
            "histogram": {"edges_mm": c.histogram.edges, "counts": c.histogram.counts},
        });
        if let (Some(o), Some(e)) = (v.as_object_mut(), extra.as_object()) {
            o.extend(e.clone());
        }
    }
    v
}

#[allow(clippy::too_many_arguments)]
fn text_report(
    file: &str,
    tool: &Tool,
    stock: &Stock,
    zmap: &ZMap,
    report: &SimReport,
    seconds: f64,
    (lo, hi): (f64, f64),
    comparison: Option<&(Comparison, Vec<f64>)>,
    args: &SimArgs,
) -> String {
    let mut t = String::new();
    let name = match tool {
        Tool::Cutter(c) => c.to_string(),
        Tool::Measured(m) => format!(
            "{} (measured: Ø{:.4}, tip at {:.4}, {} samples)",
            tool_name(args, tool),
            2.0 * m.radius(),
            m.tip(),
            m.samples()
        ),
    };
    let _ = writeln!(
        t,
        "{file}: {name} over X {} … {}, Y {} … {}, top {} at {} mm: {} × {} = {} cells",
        stock.x0,
        stock.x1,
        stock.y0,
        stock.y1,
        stock.top,
        zmap.res,
        zmap.nx,
        zmap.ny,
        zmap.cells()
    );
    let _ = writeln!(t, "  moves      {} ({} straight segments), {:.2} s", report.moves, report.segments, seconds);
    let _ = writeln!(t, "  surface    {lo:.4} … {hi:.4} mm");
    if report.unplaced_moves > 0 {
        let _ = writeln!(
            t,
            "  unplaced   {} moves before the program names X, Y and Z (or after G28) are not simulated",
            report.unplaced_moves
        );
    }
    if report.rotary_moves > 0 {
        let _ = writeln!(t, "  rotary     {} moves turn A/B/C (simulated in X Y Z only)", report.rotary_moves);
    }
    match report.rapid_hits.first() {
        None => t.push_str("  rapids     none into the stock\n"),
        Some(h) => {
            let _ = writeln!(
                t,
                "  RAPIDS     {} into the stock; first at line {} ({:.4} mm deep)",
                report.rapid_hits.len(),
                h.line,
                h.depth
            );
        }
    }
    if let Some((c, _)) = comparison {
        let target = args.compare.as_ref().map(|p| p.display().to_string()).unwrap_or_default();
        let _ = writeln!(t, "compare with {target}: {} cells ({} outside the target)", c.compared, c.missing);
        let at = |p: Option<[f64; 2]>| p.map(|[x, y]| format!(" at ({x:.3}, {y:.3})")).unwrap_or_default();
        let _ = writeln!(t, "  max gouge  {:.4} mm{}", c.max_gouge, at(c.gouge_at));
        let _ = writeln!(t, "  max left   {:.4} mm{}", c.max_left, at(c.left_at));
        let _ = writeln!(t, "  mean |dev| {:.4} mm", c.mean_abs_dev);
        t.push_str("  deviation (simulated − target), mm:\n");
        let most = c.histogram.counts.iter().copied().max().unwrap_or(1).max(1);
        for (k, &n) in c.histogram.counts.iter().enumerate() {
            let bar = "#".repeat(((n as f64 / most as f64) * 40.0).round() as usize);
            let (a, b) = (c.histogram.edges[k], c.histogram.edges[k + 1]);
            let _ = writeln!(t, "    {a:>9.4} … {b:>9.4} {n:>10} {bar}");
        }
    }
    t
}

/// The target's triangles: STL by content, else a height grid.
/// Largest picture side; bigger grids are sampled every k-th cell.
const MAX_SIDE: usize = 4096;

/// The cells a picture shows: every `k`-th along both axes.
fn picture_grid(zmap: &ZMap) -> (usize, usize, usize) {
    let k = zmap.nx.max(zmap.ny).div_ceil(MAX_SIDE).max(1);
    (k, zmap.nx.div_ceil(k), zmap.ny.div_ceil(k))
}

fn png(rgb: &[u8], w: usize, h: usize) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    PngEncoder::new(&mut out)
        .write_image(rgb, w as u32, h as u32, ExtendedColorType::Rgb8)
        .context("cannot encode the PNG")?;
    Ok(out)
}

/// The simulated surface, hill-shaded (light from the north-west, 45° up)
/// and tinted by height; +Y up.
fn height_png(zmap: &ZMap) -> Result<Vec<u8>> {
    let (k, w, h) = picture_grid(zmap);
    let (lo, hi) = zmap.range();
    let span = (hi - lo).max(1e-12);
    let z = |i: usize, j: usize| zmap.height(i.min(zmap.nx - 1), j.min(zmap.ny - 1));
    let d = k as f64 * zmap.res;
    let (az, alt) = (315f64.to_radians(), 45f64.to_radians());
    let light = [alt.cos() * az.sin(), alt.cos() * az.cos(), alt.sin()];
    let mut rgb = Vec::with_capacity(w * h * 3);
    for row in 0..h {
        let j = (h - 1 - row) * k;
        for col in 0..w {
            let i = col * k;
            let gx =
                (z(i + k, j) - z(i.saturating_sub(k), j)) / (d * if i >= k && i + k < zmap.nx { 2.0 } else { 1.0 });
            let gy =
                (z(i, j + k) - z(i, j.saturating_sub(k))) / (d * if j >= k && j + k < zmap.ny { 2.0 } else { 1.0 });
            // Relief exaggerated twice, so gentle cusps show.
            let (gx, gy) = (2.0 * gx, 2.0 * gy);
            let n = (1.0 + gx * gx + gy * gy).sqrt();
            let shade = ((-gx * light[0] - gy * light[1] + light[2]) / n).clamp(0.0, 1.0);
            let t = (z(i, j) - lo) / span;
            let base = [0.45 + 0.55 * t, 0.42 + 0.5 * t, 0.38 + 0.4 * t];
            for c in base {
                rgb.push((255.0 * c * (0.15 + 0.85 * shade)).round().clamp(0.0, 255.0) as u8);
            }
        }
    }
    png(&rgb, w, h)
}

/// The deviation simulated − target: red below, blue above, white on it,
/// full colour at ±`scale`; grey where there is no target.
fn deviation_png(zmap: &ZMap, target: &[f64], scale: f64) -> Result<Vec<u8>> {
    let (k, w, h) = picture_grid(zmap);
    let mut rgb = Vec::with_capacity(w * h * 3);
    for row in 0..h {
        let j = (h - 1 - row) * k;
        for col in 0..w {
            let c = j * zmap.nx + col * k;
            let px = if target[c] == f64::NEG_INFINITY {
                [128.0, 128.0, 128.0]
            } else {
                let t = ((zmap.z[c] - target[c]) / scale).clamp(-1.0, 1.0);
                let end = if t < 0.0 { [200.0, 20.0, 30.0] } else { [30.0, 70.0, 210.0] };
                let a = t.abs();
                [255.0 + (end[0] - 255.0) * a, 255.0 + (end[1] - 255.0) * a, 255.0 + (end[2] - 255.0) * a]
            };
            rgb.extend(px.map(|v: f64| v.round() as u8));
        }
    }
    png(&rgb, w, h)
}

/// Writes the simulated surface as a binary STL, a triangle at a time:
/// two per square of four neighbouring cell centres, facing up, split as a
/// height grid's cells are.
fn write_surface_stl(path: &Path, zmap: &ZMap) -> Result<()> {
    let (cx, cy) = (zmap.nx.saturating_sub(1), zmap.ny.saturating_sub(1));
    let p = |i: usize, j: usize| {
        let [x, y] = zmap.centre(i, j);
        Vec3::new(x, y, zmap.height(i, j))
    };
    let triangles = (0..2 * cx * cy).map(|k| {
        let (i, j) = ((k / 2) % cx, k / 2 / cx);
        let (a, c) = (p(i, j), p(i + 1, j + 1));
        if k % 2 == 0 {
            Triangle::new(a, p(i + 1, j), c)
        } else {
            Triangle::new(a, c, p(i, j + 1))
        }
    });
    write_output_with(Some(path), |w| write_binary_stl_to(w, triangles))
}
