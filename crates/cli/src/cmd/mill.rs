//! `kezuri mill`: a raster finishing program over an STL or a height grid.

use anyhow::{bail, Context, Result};
use clap::Args;
use kezuri_cam::dropcut::{drop_cutter_along_rows, drop_cutter_rows, rows_at_once};
use kezuri_cam::mill::reach::{self, unreached, unreached_by_rows, Area};
use kezuri_cam::mill::{gouge_note, raster_into, RasterOptions, Region, Rows, GOUGE_TOL};
use kezuri_cam::{scallop, Cutter};
use kezuri_geom::{PathSink, WholePath};

use crate::files::Outputs;
use crate::machine::MachineArg;
use crate::program::{stream_made_program, write_program, Origin, WriteArgs};
use crate::raster::{RowDirection, RowPattern};
use crate::surface::{read_surface, Surface};

/// Options of `kezuri mill`.
#[derive(Args, Debug)]
#[command(after_help = "\
The cutter is placed on the surface with drop-cutter (lowered at each point until it touches:
exact contact for every shape), so the program never cuts into the surface by more than
--gouge-tol: rows are sampled every --sample-step, halved where the path bends more than
--gouge-tol/2, and merged where it is straight within --gouge-tol/2. Rows run over the surface's XY box (or --region), the cutter's centre inside
it, so nothing outside the surface is cut; within a radius of the edges the cutter cannot
reach down everywhere, and material is left there. Where no part of the surface is under
the cutter the row is cut in pieces, with a retract between. The program carries its
allowance in a header comment, (KEZURI GOUGE-TOL 0.010), which `kezuri sim` and `kezuri view`
read back as theirs.

Where the surface has valleys narrower than the cutter (or corners sharper than it), no
stepover reaches them: a warning says how much is left (normal to the surface), where, and
over what share of it, as relief does; the edges within a radius, above, are not judged.

--cusp H sets the pick feed (the step from one row to the next) by the cusp it leaves: each
next row goes as far as the theoretical cusp between the rows, from the slope across them, stays within H (the pick feed in the inclined
plane from `kezuri scallop`, converted to the stepover in plan); --stepover is then the widest
it may be.

The program is written for the control --post names (fanuc, haas, linuxcnc, grbl, mach3; the
machine file's [post] changes any part, its tool table gives the tool's H register): the safe
start, the tool change with its retract and G43 H on the first Z move, spindle, coolant, end.

Examples:
  kezuri relief samples/plum-sketch.png --width 40 --depth 3 --tool ball:3 \\
      --stepover 1 --surface-stl plum.stl -o plum.nc
  kezuri mill plum.stl --tool ball:6 --stepover 1 -o plum-ball.nc
  kezuri dropcut plum.stl --tool ball:0.5 --grid 0,0,40,30,0.25 -o plum.xyz
  kezuri mill plum.xyz --tool oval:16,24 --stepover 1.5 --cusp 0.01 \\
      --direction both -o plum-oval.nc
  kezuri mill plum.xyz --tool ball:3 --stepover 0.3 --pattern oneway \\
      --post grbl -o plum.gcode
  kezuri mill plum.xyz --tool ball:3.175 --stepover 0.5 --tool-number 2 \\
      --post haas --machine samples/tools/mill.toml -o plum-haas.nc")]
pub struct MillArgs {
    /// The surface to finish, as designed: an STL (binary or ASCII), or a height grid of `x y z`
    /// lines; `-` reads stdin.
    #[arg(value_name = "SURFACE")]
    pub surface: std::path::PathBuf,
    /// The unit the surface is drawn in (STL files carry none): `inch` multiplies it by 25.4.
    /// [default: mm, with a note where the model is under 13 mm in every direction]
    #[arg(long, value_enum, value_name = "mm|inch")]
    pub units: Option<crate::surface::Units>,
    /// Cutter: flat:D, ball:D, bull:D,R, oval:D,RL or v:D,ANGLE (mm, degrees).
    #[arg(long, value_name = "SPEC", long_help = tool_help!("The cutter."))]
    pub tool: String,
    /// Distance between rows in plan, mm (the widest, with --cusp).
    #[arg(long, value_name = "MM", allow_negative_numbers = true, value_parser = crate::numbers::length)]
    pub stepover: f64,
    /// The largest cusp (the ridge left between two rows) to keep to, mm: each row as far from
    /// the last as that allows, up to --stepover.
    #[arg(long, value_name = "MM", allow_negative_numbers = true, value_parser = crate::numbers::length)]
    pub cusp: Option<f64>,
    /// Row direction.
    #[arg(long, value_enum, default_value = "x")]
    pub direction: RowDirection,
    /// Row linking: zigzag rows are linked along the surface; oneway rows
    /// retract, return and plunge.
    #[arg(long, value_enum, default_value = "zigzag")]
    pub pattern: RowPattern,
    /// Sampling step along a row, mm [default: a quarter of the cutter radius].
    #[arg(long = "sample-step", alias = "step", value_name = "MM", value_parser = crate::numbers::length)]
    pub step: Option<f64>,
    /// How far the path may stray from the exact cutter locations, mm: a gouge into the surface
    /// of up to this much is allowed (the program carries it in its header, which `kezuri sim`
    /// reads back).
    #[arg(long, alias = "tolerance", value_name = "MM", default_value_t = GOUGE_TOL, value_parser = crate::numbers::length)]
    pub gouge_tol: f64,
    /// Area the cutter's centre covers in plan [default: the surface's XY box;
    /// a larger one finishes the edges, with the cutter resting on the
    /// surface's edge beyond them, lower than the surface].
    #[arg(long, value_name = "X0,Y0,X1,Y1", allow_hyphen_values = true)]
    pub region: Option<String>,
    /// Height for rapids [default: 5 mm above the surface's top].
    #[arg(long, value_name = "Z", allow_negative_numbers = true, value_parser = crate::numbers::coordinate)]
    pub safe_z: Option<f64>,
    /// Cutting feed, mm/min.
    #[arg(long, value_name = "MM/MIN", default_value_t = 1000.0, value_parser = crate::numbers::positive)]
    pub feed: f64,
    /// Plunge feed, mm/min.
    #[arg(long, value_name = "MM/MIN", default_value_t = 300.0, value_parser = crate::numbers::positive)]
    pub plunge_feed: f64,
    /// Spindle speed, rpm.
    #[arg(long, value_name = "RPM", default_value_t = 10000.0, value_parser = crate::numbers::positive)]
    pub speed: f64,
    /// Tool number for the tool change.
    #[arg(long, value_name = "T", default_value_t = 1)]
    pub tool_number: u32,
    #[command(flatten)]
    pub machine: MachineArg,
    #[command(flatten)]
    pub write: WriteArgs,
}

/// Runs `kezuri mill`.
pub fn run(args: &MillArgs) -> Result<()> {
    let cutter: Cutter = crate::raster::row_cutter(&args.tool)?;
    let machine = args.machine.load()?;
    let surface = read_surface(&args.surface, args.units)?;
    let [x0, y0, x1, y1] = match &args.region {
        Some(text) => parse_region(text)?,
        None => surface.xy_box(),
    };
    let options = RasterOptions {
        direction: args.direction.into(),
        pattern: args.pattern.into(),
        stepover: args.stepover,
        step: args.step.unwrap_or(cutter.radius() / 4.0),
        tolerance: args.gouge_tol,
        gouge: args.gouge_tol,
        quantum: args.write.quantum(&machine)?,
        safe_z: args.safe_z.unwrap_or(surface.top() + 5.0),
        feed: args.feed,
        plunge_feed: args.plunge_feed,
        speed: args.speed,
        tool: args.tool_number,
    };
    let top = surface.top();
    if options.safe_z <= top {
        bail!(
            "--safe-z {} is not above the surface's top, z = {top}: rapids between rows would run into the part",
            options.safe_z
        );
    }
    let digits = args.write.digits.unwrap_or(if args.write.inch { 4 } else { 3 });
    let rounding = 0.5 * 10f64.powi(-i32::from(digits)) * if args.write.inch { 25.4 } else { 1.0 };
    if rounding > args.gouge_tol {
        eprintln!(
            "warning: {digits} decimals round positions by up to {rounding} mm, more than --gouge-tol {} mm",
            args.gouge_tol
        );
    }
    let pick_feeds = args.cusp.map(|h| pick_feed_table(&cutter, h));
    let pick_feed = pick_feeds.as_ref().map(|table| {
        move |angle: f64| {
            // The smaller of the two tabulated angles around `angle`.
            let k = angle.to_degrees() * 10.0;
            let (lo, hi) = ((k.floor() as usize).min(table.len() - 1), (k.ceil() as usize).min(table.len() - 1));
            match (table[lo], table[hi]) {
                (Some(a), Some(b)) => Some(a.min(b)),
                _ => None,
            }
        }
    });
    let cl = |x: f64, y: f64| surface.drop_cutter(&cutter, x, y);
    let bar = std::sync::OnceLock::new();
    let on_row = |done: usize, total: usize| {
        // Long jobs only: some hundreds of rows.
        if let Some(bar) = bar.get_or_init(|| crate::progress::bar("mill", "rows", total as u64, 200)) {
            bar.set_position(done as u64);
        }
    };
    let row_queries = |along_y: bool, asked: &[(f64, &[f64])]| match &surface {
        Surface::Grid(field) => drop_cutter_rows(&cutter, field, along_y, asked),
        Surface::Mesh(mesh) => drop_cutter_along_rows(&cutter, mesh, along_y, asked),
    };
    // A ball on a height grid is placed on whole rows at once, far faster
    // than point by point; a mesh answers a row's points together, the
    // triangles near the row found once. The same answers.
    let rows = match &surface {
        Surface::Grid(_) if rows_at_once(&cutter) => Rows::Whole(&row_queries),
        Surface::Grid(_) => Rows::PointByPoint,
        Surface::Mesh(_) => Rows::Along(&row_queries),
    };
    let region = Region { x0, y0, x1, y1 };
    let pick_feed = pick_feed.as_ref().map(|f| f as &kezuri_cam::mill::PickFeedFn);
    let make = |sink: &mut dyn PathSink| {
        raster_into(&cl, rows, region, &options, pick_feed, &on_row, sink)
            .with_context(|| args.surface.display().to_string())
    };
    let title = format!("{} raster {} stepover {}", cutter, args.surface.display(), args.stepover);
    let notes = [gouge_note(args.gouge_tol)];
    let cutters = [(args.tool_number, cutter)];
    let mut out = Outputs::new();
    // A program or CSV alone is written row by row as the rows are made; a
    // drawing, a page or RML-1 needs the whole path.
    let summary = if args.write.streams() {
        let summary =
            stream_made_program(&mut out, &args.surface, &title, &notes, &args.write, &machine, &cutters, make)?;
        finish_bar(&bar);
        warn_unreached(&cutter, &surface, [x0, y0, x1, y1], args, &cl);
        summary
    } else {
        let mut whole = WholePath::default();
        make(&mut whole)?;
        finish_bar(&bar);
        warn_unreached(&cutter, &surface, [x0, y0, x1, y1], args, &cl);
        let path = whole.path;
        write_program(&mut out, &path, &path, &title, &notes, &args.write, &machine, Origin::Made, &cutters)?;
        crate::say::program_summary(&path, &machine)
    };
    out.commit()?;
    crate::say::note!("wrote {}: {summary}", crate::say::shown(args.write.output()));
    Ok(())
}

/// Clears the progress bar of the rows, where one was drawn.
fn finish_bar(bar: &std::sync::OnceLock<Option<indicatif::ProgressBar>>) {
    if let Some(Some(bar)) = bar.get() {
        bar.finish_and_clear();
    }
}

/// Warns of what `cutter` cannot reach of `surface` over `region` (`cl` its
/// cutter locations), at any stepover, as relief says it.
fn warn_unreached(
    cutter: &Cutter,
    surface: &Surface,
    [x0, y0, x1, y1]: [f64; 4],
    args: &MillArgs,
    cl: &(dyn Fn(f64, f64) -> Option<f64> + Sync),
) {
    let r = cutter.radius();
    let nodes = |step: f64| ((x1 - x0) / step + 1.0) * ((y1 - y0) / step + 1.0);
    let mut step = r / 5.0;
    if nodes(step) > REACH_NODES {
        step *= (nodes(step) / REACH_NODES).sqrt();
    }
    let threshold = reach::threshold(args.gouge_tol, step, r);
    let area = Area { bounds: [x0, y0, x1, y1], inset: r, step };
    let z_at = |x, y| surface.height_at(x, y);
    let found = match surface {
        // A mesh answers a row's points together, the triangles near the row found once.
        Surface::Mesh(mesh) => {
            unreached_by_rows(area, cutter, threshold, z_at, cl, |y, xs| mesh.drop_cutter_along(cutter, false, y, xs))
        }
        Surface::Grid(_) => unreached(area, cutter, threshold, z_at, cl),
    };
    if let Some(u) = found {
        eprintln!("warning: {}: {}", args.surface.display(), u.message(cutter, "the surface", threshold));
    }
}

/// Most points of the grid `mill` checks the cutter's reach on: a coarser
/// grid than a fifth of the cutter's radius for a large surface (some
/// seconds of drop-cutter).
const REACH_NODES: f64 = 1e6;

/// Pick feeds in the inclined plane for a cusp of `cusp` at every tenth of
/// a degree from 0 to 89.9°.
fn pick_feed_table(cutter: &Cutter, cusp: f64) -> Vec<Option<f64>> {
    (0..900)
        .map(|k| scallop::pick_feed(cutter, (k as f64 / 10.0).to_radians(), cusp).ok().map(|s| s.pick_feed))
        .collect()
}

fn parse_region(text: &str) -> Result<[f64; 4]> {
    let v: Vec<f64> = text
        .split(',')
        .map(|s| s.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect::<Option<_>>()
        .with_context(|| format!("--region '{text}': expected X0,Y0,X1,Y1"))?;
    if v.len() != 4 || v[2] < v[0] || v[3] < v[1] {
        bail!("--region '{text}': expected X0,Y0,X1,Y1 with X0 ≤ X1 and Y0 ≤ Y1");
    }
    Ok([v[0], v[1], v[2], v[3]])
}
