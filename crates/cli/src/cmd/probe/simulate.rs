//! `kezuri probe simulate`: the readings a ball stylus would give on a
//! model, for trying the pipeline (level, export, mill, sim) before a
//! night on the machine, and for the demo and benchmarks.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::Args;
use kezuri_cam::probe::data::num;
use kezuri_cam::probe::simulate::{simulate, Simulated, Simulation};
use kezuri_cam::probe::Order;
use kezuri_cam::Cutter;

use super::pair;
use crate::files::write_output;
use crate::surface::read_surface;

/// Options of `kezuri probe simulate`.
#[derive(Args, Debug)]
#[command(after_help = "\
Each reading is where the stylus's tip (its lowest point) stops when it is lowered onto the model
at a grid point: drop-cutter of the stylus on the model, the same convention as a real capture.
--tilt adds a plane through the grid's centre (mm per mm along X and Y, the model set down out of
level); --noise adds uniform noise of ± that many mm, repeatable with --seed. The file is a capture
file (header with the grid, then No,Z in capture order) that every other probe command reads.

Examples:
  kezuri relief samples/plum-sketch.png --width 40 --depth 3 --tool ball:3 \\
      --stepover 1 --surface-stl plum.stl -o plum.nc
  kezuri probe simulate plum.stl --count 41,31 --pitch 1 --stylus ball:10 \\
      -o plum.txt
  kezuri probe simulate plum.stl --count 41,31 --pitch 0.5 --origin 10,7.5 \\
      --stylus ball:6 --tilt 0.002,-0.001 --noise 0.003 --seed 7 -o part.txt")]
pub struct SimulateArgs {
    /// The model: STL (binary or ASCII) or an `x y z` height grid.
    #[arg(value_name = "MODEL")]
    pub model: PathBuf,
    /// The unit the model is drawn in (STL files carry none): `inch` multiplies it by 25.4.
    /// [default: mm, with a note where the model is under 13 mm in every direction]
    #[arg(long, value_enum, value_name = "mm|inch")]
    pub units: Option<crate::surface::Units>,
    /// Points along X and Y.
    #[arg(long, value_name = "NX,NY")]
    pub count: String,
    /// Grid pitch, mm.
    #[arg(long, value_name = "MM", value_parser = crate::numbers::length)]
    pub pitch: f64,
    /// The first point's X,Y [default: the grid centred on the model].
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    pub origin: Option<String>,
    /// Capture order.
    #[arg(long, value_name = "zigzag|oneway", default_value = "zigzag")]
    pub pattern: String,
    /// The stylus, as a tool (ball:10 for a 10 mm bead).
    #[arg(
        long,
        value_name = "SPEC",
        long_help = tool_help!("The stylus, as a tool (ball:10 for a 10 mm bead).")
    )]
    pub stylus: String,
    /// Slope of the model's base along X and Y, mm per mm.
    #[arg(long, value_name = "AX,AY", allow_hyphen_values = true, default_value = "0,0")]
    pub tilt: String,
    /// Uniform noise added to each reading, ± mm.
    #[arg(long, value_name = "MM", default_value_t = 0.0, value_parser = crate::numbers::length_or_zero)]
    pub noise: f64,
    /// Seed of the noise.
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub seed: u64,
    /// The capture file [default: standard output].
    #[arg(short, long, value_name = "DATA")]
    pub output: Option<PathBuf>,
}

/// Runs `kezuri probe simulate`.
pub fn run(args: &SimulateArgs) -> Result<()> {
    let stylus: Cutter = args.stylus.parse().context("--stylus")?;
    let [nx, ny] = pair::<usize>("--count", &args.count)?;
    if nx < 2 || ny < 2 || nx.saturating_mul(ny) > 100_000_000 {
        bail!("--count {nx},{ny}: the grid needs 2 to 10,000 points a side and at most 100 million in all");
    }
    let tilt = pair::<f64>("--tilt", &args.tilt)?;
    if !tilt.iter().all(|t| t.abs() <= 1.0) {
        bail!("--tilt {}: a slope is at most 1 mm per mm (45°) either way", args.tilt);
    }
    let order: Order = args.pattern.parse().map_err(anyhow::Error::msg)?;
    let model = read_surface(&args.model, args.units)?;
    let origin = args.origin.as_deref().map(|t| pair::<f64>("--origin", t)).transpose()?;
    let name = args.model.display().to_string();
    let Simulated { grid, text } = simulate(&Simulation {
        model: &|x, y| model.drop_cutter(&stylus, x, y),
        model_box: model.xy_box(),
        name: &name,
        stylus,
        count: [nx, ny],
        pitch: args.pitch,
        origin,
        order,
        tilt,
        noise: args.noise,
        seed: args.seed,
    })?;
    let origin = grid.origin;
    write_output(args.output.as_deref(), text.as_bytes())?;
    crate::say::note!(
        "wrote {}: {nx} × {ny} readings of {stylus} at pitch {} mm from ({}, {})",
        crate::say::shown(args.output.as_deref()),
        num(args.pitch, 6),
        num(origin[0], 4),
        num(origin[1], 4)
    );
    Ok(())
}
