//! `kezuri probe mill`: the copy-milling program from ball-stylus readings.

mod parts;

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use kezuri_cam::probe::copy::{self, Copied, Floor, Job};
use kezuri_cam::{Cutter, ErrorKind};
use kezuri_geom::cycle_time;
use kezuri_machine::Machine;
use kezuri_nc::write::{self, program, WriteOptions};

use super::DataArgs;
use crate::files::Outputs;
use crate::program::post_options;
use parts::{check_left_over, part_name, remove_left_over};

/// Options of `kezuri probe mill`.
#[derive(Args, Debug)]
#[command(after_help = "\
The data are the positions of the stylus's tip (its lowest point) where it rested on the model:
exact points of the surface the tip traces. By default (--between smooth) a smooth surface is
drawn through every reading (bicubic, with slopes that never swing past the readings: each cell
stays between its lowest and highest reading), and the model is that surface lowered by the
stylus's shape (for a ball, offset inward by its radius). With the stylus's own ball as cutter
the program passes through every reading (rounded to the nearest last digit) and between them
follows the higher of that surface and the straight line from reading to reading, every quarter
of the pitch; with --sample-step the pitch it goes straight from reading to reading, as the
original copy system's programs did, which cuts up to p²/(8ρ) into a rim or crest of radius ρ
(25 µm at 1 mm round a sharp edge). Where the readings bend down so sharply that the copy may
cut more than --gouge-tol below the model between them, a warning says so. Any other cutter is
placed on the model, sampled every --res, with drop-cutter (lowered at each point until it
touches). Where the surface through the readings bends tighter than the stylus (a sharp edge,
noise, a pitch too coarse) a warning says: no ball rolling on a model gives such readings.

--between bound keeps the former behaviour: the highest surface the readings allow (the lowest
of the stylus shapes over each point), which never cuts below any stylus position but leaves the
cusps (the ridges left between readings: 25 µm along the rows, 50 µm mid-cell, at 1 mm pitch
with a 10 mm ball); heights are rounded up. See docs/probe-copy.md.

Rows run along X in zig-zag, over the data's XY box. Cuts that run along the flat top of the
data (--floor-z: auto finds a flat margin at the top, held by 5% of the points or more) are
crossed at rapid --clearance above it. --incremental writes the moves after the first
positioning in G91; --split-bytes N writes parts OUT-1, OUT-2, … of at most N bytes each, each
a whole program that starts from the safe height. A summary on standard error gives the program's
size, moves and cycle time.

Examples:
  kezuri relief samples/plum-sketch.png --width 40 --depth 3 --tool ball:3 \\
      --stepover 1 --surface-stl plum.stl -o plum.nc
  kezuri probe simulate plum.stl --count 41,31 --pitch 1 --stylus ball:10 \\
      --tilt 0.002,-0.001 --noise 0.002 -o plum.txt
  kezuri probe mill plum.txt --stylus ball:10 --tool ball:10 -o plum-copy.nc
  kezuri probe mill plum.txt --stylus ball:10 --tool ball:6 --stepover 0.5 \\
      --split-bytes 20000 -o plum-part.nc")]
pub struct MillArgs {
    #[command(flatten)]
    pub data: DataArgs,
    /// The stylus that took the readings, as a tool (ball:10 for a 10 mm bead).
    #[arg(
        long,
        value_name = "SPEC",
        long_help = tool_help!("The stylus that took the readings, as a tool (ball:10 for a 10 mm bead).")
    )]
    pub stylus: String,
    /// The cutter: flat:D, ball:D, bull:D,R, oval:D,RL or v:D,ANGLE.
    #[arg(long, value_name = "SPEC")]
    pub tool: String,
    /// Distance between rows, mm [default: the pitch].
    #[arg(long, value_name = "MM", value_parser = crate::numbers::length)]
    pub stepover: Option<f64>,
    /// Sampling step along a row, mm [default: a quarter of the pitch with the stylus's own
    /// ball, else the pitch].
    #[arg(long = "sample-step", alias = "step", value_name = "MM", value_parser = crate::numbers::length)]
    pub step: Option<f64>,
    /// How far the path may stray from the exact cutter locations, mm: a gouge into the model
    /// of up to this much is allowed (the program carries it in its header for `kezuri sim`).
    #[arg(long, alias = "tolerance", value_name = "MM", default_value_t = kezuri_cam::mill::GOUGE_TOL, value_parser = crate::numbers::length)]
    pub gouge_tol: f64,
    /// Between the readings: smooth (a surface through them) or bound (the highest
    /// surface they allow, the former default).
    #[arg(long, value_enum, default_value = "smooth")]
    pub between: Between,
    /// Node spacing of the reconstructed surface, mm [default: pitch / 8].
    #[arg(long, alias = "resolution", value_name = "MM", value_parser = crate::numbers::length)]
    pub res: Option<f64>,
    /// Height for rapids [default: 5 mm above the highest cut].
    #[arg(long, value_name = "Z", allow_negative_numbers = true, value_parser = crate::numbers::coordinate)]
    pub safe_z: Option<f64>,
    /// The flat top to cross at rapid: auto, off or a height.
    #[arg(long, value_name = "auto|off|Z", default_value = "auto", allow_hyphen_values = true)]
    pub floor_z: String,
    /// Height of rapids over the flat top, mm.
    #[arg(long, value_name = "MM", default_value_t = 1.0, value_parser = crate::numbers::length)]
    pub clearance: f64,
    /// Cutting feed, mm/min.
    #[arg(long, value_name = "MM/MIN", default_value_t = 1800.0, value_parser = crate::numbers::positive)]
    pub feed: f64,
    /// Plunge feed, mm/min.
    #[arg(long, value_name = "MM/MIN", default_value_t = 500.0, value_parser = crate::numbers::positive)]
    pub plunge_feed: f64,
    /// Spindle speed, rpm.
    #[arg(long, value_name = "RPM", default_value_t = 15000.0, value_parser = crate::numbers::positive)]
    pub speed: f64,
    /// Tool number.
    #[arg(long, value_name = "T", default_value_t = 1)]
    pub tool_number: u32,
    /// Machine file (TOML): the cycle time, its [post] and tool table (the tool's H register).
    #[arg(long, value_name = "M.toml")]
    pub machine: Option<PathBuf>,
    /// G-code for this control: fanuc, haas, linuxcnc, grbl or mach3 [default: the
    /// machine file's [post] preset, else fanuc].
    #[arg(long, value_name = "NAME")]
    pub post: Option<String>,
    /// The older name of --post fanuc, linuxcnc or grbl.
    #[arg(long, alias = "to", value_enum, hide = true)]
    pub emit: Option<Emit>,
    /// The program [default: standard output; --split-bytes needs a file].
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
    /// Decimals written [default: the post's, 3].
    #[arg(long, value_parser = clap::value_parser!(u8).range(0..=6))]
    pub digits: Option<u8>,
    /// Fanuc program number (parts count on from it) [default: the post's, 1].
    #[arg(long, value_name = "N")]
    pub program_number: Option<u32>,
    /// Moves after the first positioning in incremental coordinates (G91).
    #[arg(long)]
    pub incremental: bool,
    /// Split into parts of at most this many bytes (controls with little memory):
    /// OUT-1.nc, OUT-2.nc, … Parts of OUT's name that this run would not write
    /// (of an earlier, longer job) are refused.
    #[arg(long, value_name = "N")]
    pub split_bytes: Option<usize>,
    /// With --split-bytes, remove the parts of OUT's name that this run does
    /// not write (once the new ones are written).
    #[arg(long, requires = "split_bytes")]
    pub overwrite_parts: bool,
    /// Also draw the toolpath to this SVG file.
    #[arg(long, value_name = "FILE.svg")]
    pub svg: Option<PathBuf>,
    /// Also show the copy program in 3D: one offline HTML page, as `kezuri view` makes of it
    /// (with --split-bytes, of the whole path without the program text).
    #[arg(long, value_name = "PAGE.html")]
    pub view: Option<PathBuf>,
}

/// `--between`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Between {
    /// A smooth surface through the readings; the model under it.
    Smooth,
    /// The highest surface the readings allow; heights rounded up.
    Bound,
}

impl From<Between> for copy::Between {
    fn from(b: Between) -> copy::Between {
        match b {
            Between::Smooth => copy::Between::Smooth,
            Between::Bound => copy::Between::Bound,
        }
    }
}

/// `--emit` (or `--to`), the older name of `--post` for three of the posts.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Emit {
    /// Fanuc (`%` framing, `O` number).
    Fanuc,
    /// LinuxCNC.
    Linuxcnc,
    /// GRBL.
    Grbl,
}

/// `--floor-z`: auto, off or a height.
fn floor(text: &str) -> Result<Floor> {
    Ok(match text.trim() {
        "off" | "none" => Floor::Off,
        "auto" => Floor::Auto,
        z => Floor::At(
            z.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .with_context(|| format!("--floor-z '{z}': expected auto, off or a height"))?,
        ),
    })
}

/// Runs `kezuri probe mill`.
pub fn run(args: &MillArgs) -> Result<()> {
    let stylus: Cutter = args.stylus.parse().context("--stylus")?;
    let cutter: Cutter = crate::raster::row_cutter(&args.tool).context("--tool")?;
    let data = args.data.read()?;
    let name = args.data.data.display().to_string();
    let machine = match &args.machine {
        Some(p) => crate::machine::load(p)?,
        None => Machine::default(),
    };
    let emit = args.emit.map(|e| match e {
        Emit::Fanuc => "fanuc",
        Emit::Linuxcnc => "linuxcnc",
        Emit::Grbl => "grbl",
    });
    let mut post = post_options(args.post.as_deref(), emit, &machine, args.output.as_deref())?;
    post.digits = args.digits.unwrap_or(post.digits);
    let job = Job {
        data: &data.grid,
        stylus,
        cutter,
        stepover: args.stepover,
        step: args.step,
        gouge_tol: args.gouge_tol,
        between: args.between.into(),
        resolution: args.res,
        quantum: 10f64.powi(-i32::from(post.digits)),
        safe_z: args.safe_z,
        floor: floor(&args.floor_z)?,
        clearance: args.clearance,
        feed: args.feed,
        plunge_feed: args.plunge_feed,
        speed: args.speed,
        tool: args.tool_number,
    };
    let t0 = std::time::Instant::now();
    let Copied { path, stepover, safe_z, surface, flat, warnings } = copy::copy(&job, &|_, _| {}).map_err(|e| {
        if e.kind == ErrorKind::Surface {
            anyhow::Error::new(e).context(name.clone())
        } else {
            e.into()
        }
    })?;
    let seconds_cam = t0.elapsed().as_secs_f64();
    let title = format!("COPY {} {} STYLUS {} STEPOVER {}", args.data.data.display(), cutter, stylus, stepover);
    let options = WriteOptions {
        program_number: args.program_number.unwrap_or(post.program_number),
        loaded_tool: None,
        title: Some(title.clone()),
        notes: vec![kezuri_cam::mill::gouge_note(args.gouge_tol)],
        incremental: args.incremental,
        ..post
    };
    let parts: Vec<String> = match args.split_bytes {
        None => vec![program(&path, &options)?],
        Some(limit) => write::parts(&path, &options, limit, safe_z, args.plunge_feed)?,
    };
    let (time, _) = cycle_time(&path, &machine.dynamics);
    // Everything is made before anything is written, and written together.
    let file = args.output.as_deref().filter(|o| *o != Path::new("-"));
    let left_over = match (args.split_bytes, file) {
        (Some(_), Some(file)) => check_left_over(file, parts.len(), args.overwrite_parts)?,
        _ => Vec::new(),
    };
    let mut out = Outputs::new();
    match (parts.as_slice(), file) {
        ([one], _) => out.add(file, one.as_bytes())?,
        (_, Some(file)) => {
            for (k, text) in parts.iter().enumerate() {
                out.add(Some(&part_name(file, k + 1)), text.as_bytes())?;
            }
        }
        (_, None) => bail!("--split-bytes writes files: give -o FILE"),
    }
    if let Some(svg) = &args.svg {
        let name = crate::program::svg_title(args.output.as_deref(), &title, &[]);
        out.add(Some(svg), kezuri_picture::plot::svg(&path, &name).as_bytes())?;
    }
    if let Some(page) = &args.view {
        let (options, cutters) = (kezuri_picture::PageOptions::default(), [(args.tool_number, cutter)]);
        let html = match parts.as_slice() {
            [one] => {
                let name = file.unwrap_or(Path::new("copy.nc"));
                let ran = crate::program::run_written(&machine, name, one.clone())?;
                crate::page::page(&ran, &name.display().to_string(), None, &cutters, &options)?
            }
            _ => crate::page::path_page(&path, &title, &machine, &cutters, &options)?,
        };
        out.add(Some(page), &html)?;
    }
    out.commit()?;
    remove_left_over(&left_over)?;
    let bytes: usize = parts.iter().map(|p| p.len()).sum();
    let lines: usize = parts.iter().map(|p| p.lines().count()).sum();
    let flat_top = flat.map_or_else(String::new, |(z, margins)| {
        format!(
            "; flat top z = {z:.3}: {}, {:.1} mm of cuts crossed at rapid",
            crate::say::count(margins.runs as u64, "run"),
            margins.length
        )
    });
    let g = data.grid.grid;
    crate::say::note!(
        "wrote {}: {bytes} bytes, {lines} lines, {}; {} moves, feed {:.1} mm, rapid {:.1} mm, cycle time {}; \
         from {}, {} × {} points at pitch {} mm, surface {surface}{flat_top}; computed in {seconds_cam:.2} s",
        crate::say::shown(file),
        crate::say::count(parts.len() as u64, "part"),
        path.moves.len(),
        path.feed_length(),
        path.rapid_length(),
        crate::say::hms(time),
        args.data.data.display(),
        g.nx,
        g.ny,
        g.pitch,
    );
    for warning in warnings {
        eprintln!("warning: {warning}");
    }
    Ok(())
}
