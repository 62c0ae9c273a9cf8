//! `kezuri relief`: a grayscale sketch carved as a relief.

use std::path::PathBuf;
use std::sync::OnceLock;

use anyhow::{bail, Context, Result};
use clap::Args;
use indicatif::ProgressBar;
use kezuri_cam::mill::{gouge_note, GOUGE_TOL};
use kezuri_cam::relief::{
    carve, check_smoothing, parse_levels, surface, Carved, Event, Job, Mapping, Placement, Roughing, Stage,
};
use kezuri_cam::Cutter;

use crate::files::Outputs;
use crate::gray::{dimensions, read_gray};
use crate::machine::MachineArg;
use crate::program::{write_program, Origin, WriteArgs};
use crate::raster::{RowDirection, RowPattern};
use crate::surface::stage_surface_stl;

/// Options of `kezuri relief`.
#[derive(Args, Debug)]
#[command(after_help = "\
The picture (PNG, JPEG, BMP, TIFF or PGM, 8 or 16 bit; colour is read as luma) becomes heights
below the stock top z = 0: white at the top and black --depth below (--invert: the other way),
with --gamma on the gray value; or --levels gives ranges of gray explicit heights above the
floor, a height per region (the highest level is the stock top). --smooth
rounds the steps (a Gaussian of that many pixels); --mask IMAGE cuts only where the mask is
light. The picture's top row is the largest Y; --width (or --pixel) sets the size, --origin
puts a corner (corner or lower-left, lower-right, upper-left, upper-right) or the centre
(centre) at X0 Y0, or the lower-left corner at X,Y.

The cutter is placed on the height grid with drop-cutter, so the carving never cuts into the
relief: rows are sampled every --sample-step and refined until the path stays within --gouge-tol
(0.01 mm) below and --leave-tol above the exact cutter locations (steep steps included).
The program carries its allowance in a header comment, (KEZURI GOUGE-TOL 0.010), which
`kezuri sim` and `kezuri view` read back as theirs. --rough SPEC first
clears the stock in levels --step-down apart, leaving --allowance for the finishing cutter.
--surface-stl writes the relief surface for `kezuri sim --compare`. With --rough the roughing
cutter is T1 and the finishing one T2: give both shapes in a machine file's tool table to
simulate each with its own cutter (`kezuri sim --machine`).

The program is written for the control --post names (fanuc, haas, linuxcnc, grbl, mach3; the
machine file's [post] changes any part): its safe start, and at each tool change the retract,
T M06 and the tool length offset (G43 H, the tool table's h, on the first Z move), spindle and
coolant, and its end.

Examples:
  kezuri relief samples/plum-sketch.png --width 120 --depth 5 --tool ball:3 \\
      --stepover 0.3 -o plum.nc
  kezuri relief samples/plum-sketch.png --pixel 0.1 --tool ball:6 \\
      --levels 0-63:0,64-191:2.5,192-255:5 --stepover 0.4 --rough flat:6 \\
      --step-down 2 --allowance 0.3 --surface-stl levels.stl -o levels.nc
  kezuri relief samples/plum-sketch.png --width 80 --depth 8 --invert \\
      --gamma 0.8 --smooth 1.5 --tool ball:2 --stepover 0.4 --direction both \\
      --post linuxcnc -o plum.ngc
  kezuri relief samples/plum-sketch.png --width 40 --depth 3 --tool ball:3 \\
      --rough flat:6 --stepover 1 --post haas \\
      --machine samples/tools/mill.toml -o plum-haas.nc")]
pub struct ReliefArgs {
    /// The sketch: PNG, JPEG, BMP, TIFF or PGM.
    #[arg(value_name = "IMAGE")]
    pub image: PathBuf,
    /// Width of the carving, mm (the height follows the picture's aspect).
    #[arg(
        long,
        value_name = "MM",
        required_unless_present = "pixel",
        conflicts_with = "pixel",
        allow_negative_numbers = true,
        value_parser = crate::numbers::length,
    )]
    pub width: Option<f64>,
    /// Size of one pixel, mm.
    #[arg(long, value_name = "MM", allow_negative_numbers = true, value_parser = crate::numbers::length)]
    pub pixel: Option<f64>,
    /// Depth of black (white with --invert) below the stock top, mm.
    #[arg(
        long,
        value_name = "MM",
        required_unless_present = "levels",
        conflicts_with = "levels",
        allow_negative_numbers = true
    )]
    pub depth: Option<f64>,
    /// Dark high, light low.
    #[arg(long)]
    pub invert: bool,
    /// Exponent on the gray value before it becomes a depth.
    #[arg(long, value_name = "G", default_value_t = 1.0, allow_negative_numbers = true)]
    pub gamma: f64,
    /// Heights per range of gray: FROM-TO:HEIGHT,… over 0–255, e.g. 0-63:0,64-191:2.5,192-255:5.
    #[arg(long, value_name = "RANGES")]
    pub levels: Option<String>,
    /// Cut only where this picture (same size) is light.
    #[arg(long, value_name = "IMAGE")]
    pub mask: Option<PathBuf>,
    /// Gaussian smoothing of the heights, pixels.
    #[arg(long, value_name = "PX", default_value_t = 0.0, allow_negative_numbers = true)]
    pub smooth: f64,
    /// Where the picture goes: a corner at X0 Y0 (corner is lower-left; lower-right, upper-left,
    /// upper-right), its centre there (centre), or its lower-left corner at X,Y.
    #[arg(long, value_name = "CORNER|centre|X,Y", default_value = "corner", allow_hyphen_values = true)]
    pub origin: String,
    /// Finishing cutter: flat:D, ball:D, bull:D,R, oval:D,RL or v:D,ANGLE.
    #[arg(long, value_name = "SPEC", long_help = tool_help!("The finishing cutter."))]
    pub tool: String,
    /// Distance between finishing rows, mm.
    #[arg(long, value_name = "MM", value_parser = crate::numbers::length)]
    pub stepover: f64,
    /// Row direction.
    #[arg(long, value_enum, default_value = "x")]
    pub direction: RowDirection,
    /// Row linking.
    #[arg(long, value_enum, default_value = "zigzag")]
    pub pattern: RowPattern,
    /// Sampling step along a row, mm [default: the pixel size, or the
    /// program's increment where the pixel is finer].
    #[arg(long = "sample-step", alias = "step", value_name = "MM", value_parser = crate::numbers::length)]
    pub step: Option<f64>,
    /// How much material the path may leave above the exact cutter locations, mm.
    #[arg(long, alias = "tolerance", value_name = "MM", default_value_t = 0.01, value_parser = crate::numbers::length)]
    pub leave_tol: f64,
    /// How far the path may cut below the exact cutter locations, mm (at most --leave-tol): the
    /// program carries it in its header, which `kezuri sim` and `kezuri view` read back.
    #[arg(long, value_name = "MM", default_value_t = GOUGE_TOL, value_parser = crate::numbers::length)]
    pub gouge_tol: f64,
    /// Roughing cutter (a tool as --tool): clear the stock in levels first.
    #[arg(long, value_name = "SPEC")]
    pub rough: Option<String>,
    /// Depth of each roughing level, mm.
    #[arg(long, value_name = "MM", default_value_t = 2.0, value_parser = crate::numbers::length)]
    pub step_down: f64,
    /// Material the roughing leaves on the relief, mm.
    #[arg(long, value_name = "MM", default_value_t = 0.3, value_parser = crate::numbers::length_or_zero)]
    pub allowance: f64,
    /// Distance between roughing rows, mm [default: 40 % of the roughing cutter's diameter].
    #[arg(long, value_name = "MM", value_parser = crate::numbers::length)]
    pub rough_stepover: Option<f64>,
    /// Height for rapids, above the stock top.
    #[arg(long, value_name = "Z", default_value_t = 5.0, value_parser = crate::numbers::coordinate)]
    pub safe_z: f64,
    /// Cutting feed, mm/min.
    #[arg(long, value_name = "MM/MIN", default_value_t = 1500.0, value_parser = crate::numbers::positive)]
    pub feed: f64,
    /// Plunge feed, mm/min.
    #[arg(long, value_name = "MM/MIN", default_value_t = 300.0, value_parser = crate::numbers::positive)]
    pub plunge_feed: f64,
    /// Spindle speed, rpm.
    #[arg(long, value_name = "RPM", default_value_t = 10000.0, value_parser = crate::numbers::positive)]
    pub speed: f64,
    /// Also write the relief as designed (the surface the finished carving should have) as a
    /// binary STL: the target of `kezuri sim --compare` and `kezuri wear apply --surface`.
    #[arg(long, value_name = "FILE.stl")]
    pub surface_stl: Option<PathBuf>,
    #[command(flatten)]
    pub machine: MachineArg,
    #[command(flatten)]
    pub write: WriteArgs,
}

/// Runs `kezuri relief`.
pub fn run(args: &ReliefArgs) -> Result<()> {
    let cutter: Cutter = crate::raster::row_cutter(&args.tool).context("--tool")?;
    let machine = args.machine.load()?;
    let rough: Option<Cutter> = args.rough.as_deref().map(crate::raster::row_cutter).transpose().context("--rough")?;
    let mapping = match (&args.levels, args.depth) {
        (Some(text), _) => Mapping::Levels(parse_levels(text)?),
        (None, Some(depth)) => Mapping::Depth { depth, invert: args.invert, gamma: args.gamma },
        (None, None) => bail!("give --depth or --levels"),
    };
    mapping.check()?;
    if !(args.safe_z.is_finite() && args.safe_z > 0.0) {
        bail!("--safe-z {} must be above the stock top, z = 0", args.safe_z);
    }
    let (w, h) = dimensions(&args.image)?;
    check_smoothing(args.smooth, w as usize, h as usize).context("--smooth")?;
    let picture = read_gray(&args.image)?;
    let mask = args.mask.as_deref().map(read_gray).transpose()?;
    let pixel = match (args.width, args.pixel) {
        (Some(width), _) => width / picture.width as f64,
        (None, Some(pixel)) => pixel,
        (None, None) => bail!("give --width or --pixel"),
    };
    if !(pixel.is_finite() && pixel > 0.0 && pixel <= 1000.0) {
        bail!("the pixel size must be a positive number of mm, got {pixel}");
    }
    let size = [picture.width as f64 * pixel, picture.height as f64 * pixel];
    let origin = origin_of(&args.origin, size)?;
    let placement = Placement { pixel, origin };
    let name = args.image.display().to_string();
    let field = surface(&picture, &mapping, args.smooth, mask.as_ref(), placement).context(name.clone())?;
    let job = Job {
        field: &field,
        mask: mask.as_ref(),
        placement,
        cutter,
        direction: args.direction.into(),
        pattern: args.pattern.into(),
        stepover: args.stepover,
        step: args.step,
        leave_tol: args.leave_tol,
        gouge_tol: args.gouge_tol,
        quantum: args.write.quantum(&machine)?,
        safe_z: args.safe_z,
        feed: args.feed,
        plunge_feed: args.plunge_feed,
        speed: args.speed,
        rough: rough.map(|cutter| Roughing {
            cutter,
            stepover: args.rough_stepover,
            step_down: args.step_down,
            allowance: args.allowance,
        }),
    };
    let t0 = std::time::Instant::now();
    let Carved { path, unreached, threshold } = with_bars(|on| carve(&job, on))?;
    if let Some(u) = unreached {
        eprintln!("warning: {name}: {}", u.message(&cutter, "the relief", threshold));
    }
    let what = format!(
        "{name}, {} × {} pixels of {pixel:.4} mm, {:.1} × {:.1} mm, computed in {:.2} s; ",
        picture.width,
        picture.height,
        size[0],
        size[1],
        t0.elapsed().as_secs_f64()
    );
    let title = format!("RELIEF {} {cutter} STEPOVER {}", args.image.display(), args.stepover);
    let mut out = Outputs::new();
    let cutters: Vec<(u32, Cutter)> = match rough {
        Some(r) => vec![(1, r), (2, cutter)],
        None => vec![(1, cutter)],
    };
    let notes = [gouge_note(job.gouge())];
    write_program(&mut out, &path, &path, &title, &notes, &args.write, &machine, Origin::Made, &cutters)?;
    if let Some(stl) = &args.surface_stl {
        stage_surface_stl(&mut out, stl, &field)?;
    }
    out.commit()?;
    crate::say::wrote_program(args.write.output(), &what, &path, &machine);
    Ok(())
}

/// The picture's lower-left corner for `--origin`: the named corner (or
/// the centre) of the `size` carving at X0 Y0, or the lower-left corner at
/// X,Y.
fn origin_of(text: &str, size: [f64; 2]) -> Result<[f64; 2]> {
    Ok(match text.trim() {
        "corner" | "lower-left" => [0.0, 0.0],
        "lower-right" => [-size[0], 0.0],
        "upper-left" => [0.0, -size[1]],
        "upper-right" => [-size[0], -size[1]],
        "centre" | "center" => [-0.5 * size[0], -0.5 * size[1]],
        xy => {
            let v: Vec<f64> =
                xy.split(',').filter_map(|t| t.trim().parse().ok()).filter(|v: &f64| v.is_finite()).collect();
            if v.len() != 2 || xy.split(',').count() != 2 {
                bail!(
                    "--origin '{xy}': expected corner (lower-left), lower-right, upper-left, upper-right, centre \
                     or X,Y"
                );
            }
            [v[0], v[1]]
        }
    })
}

/// The carving with a progress bar for each stage of a long job.
fn with_bars(work: impl FnOnce(&(dyn Fn(Event) + Sync)) -> Result<Carved, kezuri_cam::Error>) -> Result<Carved> {
    let (rough, finish) = (OnceLock::new(), OnceLock::new());
    let bar = |stage: Stage| -> &OnceLock<Option<ProgressBar>> {
        match stage {
            Stage::Rough => &rough,
            Stage::Finish => &finish,
        }
    };
    let clear = |stage: Stage| {
        if let Some(Some(bar)) = bar(stage).get() {
            if !bar.is_finished() {
                bar.finish_and_clear();
            }
        }
    };
    let on = |event: Event| match event {
        Event::Rows { stage, done, total } => {
            let bar = bar(stage).get_or_init(|| crate::progress::bar(stage.name(), "rows", total as u64, 200));
            if let Some(bar) = bar {
                bar.set_position(done as u64);
            }
        }
        Event::Done(stage) => clear(stage),
    };
    let carved = work(&on);
    clear(Stage::Rough);
    clear(Stage::Finish);
    Ok(carved?)
}
