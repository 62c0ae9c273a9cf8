//! `kezuri`: the command line. Only this crate touches files, the terminal,
//! the clock and the environment; the libraries take values and return values.
//!
//! The commands are this library so that the fuzz targets (`fuzz/`) and the
//! tests can reach them: `src/main.rs` is only the process around [`Cli`].

/// A tool option's help: `$lead`, then what each tool spec means (the
/// help of every command that takes one says it where it first names one).
macro_rules! tool_help {
    ($lead:literal) => {
        concat!(
            $lead,
            "\nTools: flat:D (flat end mill, diameter D), ball:D (ball end mill), bull:D,R (bull-nose, \
             corner radius R), oval:D,RL (oval end mill: a half-ellipsoid tip RL long), v:D,ANGLE (V-bit, \
             included angle), drill:D,ANGLE (twist drill, point angle: 118 for most; sim flags it fed \
             sideways in material); mm and degrees."
        )
    };
}

mod cmd;
mod corrected;
mod files;
mod gray;
mod machine;
mod numbers;
mod page;
mod program;
mod progress;
mod raster;
mod say;
mod simulation;
mod surface;
mod table;
mod tool_profile;
mod tool_store;

use std::path::PathBuf;

use clap::{Parser, Subcommand};

use cmd::tool::ToolCommand;
use cmd::{
    check, convert, demo, dropcut, engage, mill, probe, relief, run, scallop, sim, texture, thermal, tool, view, wear,
};
use program::{RunOptions, WriteArgs};

/// kezuri (削り): read, run, check and write NC programs — Fanuc Custom Macro B,
/// LinuxCNC and GRBL — for NC routers and machining centres.
#[derive(Parser, Debug)]
#[command(name = "kezuri", version, about, long_about = None)]
#[command(after_help = "Examples:
  kezuri demo
  kezuri check samples/o1011-digitize.nc
  kezuri run samples/o7023-texture.nc --clock-seed 7 --to fanuc -o expanded.nc")]
pub struct Cli {
    /// Say nothing on standard error but errors and warnings: no summaries
    /// of what was written, no progress bars.
    #[arg(long, short, global = true, display_order = 1000)]
    quiet: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run every pipeline on the bundled samples and show what it made.
    #[command(
        after_help = "Examples:\n  kezuri demo --only thermal,copy -o demo\n  kezuri demo --only relief --quiet"
    )]
    Demo {
        /// Folder for the outputs.
        #[arg(short = 'o', long = "output", alias = "out", value_name = "DIR", default_value = "kezuri-demo")]
        out: PathBuf,
        /// Only these pipelines (comma-separated) [default: all].
        #[arg(long, value_enum, value_delimiter = ',', value_name = "PIPELINE")]
        only: Vec<demo::Pipeline>,
        /// Keep all 36 microscope pictures of each tool the tool-wear demo measures (67 MB; by
        /// default two of each are kept).
        #[arg(long)]
        frames: bool,
    },
    /// Parse and run a program (macros and subprograms too) and report blocks,
    /// motions, lengths, cycle time, bounds, canned-cycle holes and warnings.
    #[command(after_help = "Examples:
  kezuri check samples/o1011-digitize.nc
  kezuri check samples/nameplate-cam.nc --json --machine samples/tools/mill.toml
  kezuri check samples/o2007-thermal.nc --machine samples/mill-turn.toml
  kezuri check samples/o3001-turning.nc --machine samples/lathe.toml
  printf 'G21 G90 F300\\nG0 Z5\\nG1 X10.5 Y0\\nG3 X20.5 Y10 I10\\nM30\\n' > router.nc
  kezuri check router.nc --no-decimal units   # Y10 is 10 mm, not 0.010 mm
  kezuri check --jobs 2 samples/nameplate-cam.nc samples/o2007-thermal.nc\n\n\
Values the program read from the machine file rather than set itself (a work offset #5221, a tool \
offset #2001, the machine position #5021, an input #1000, the clock #3001) are listed as notes: a \
program expanded from them holds this machine's values.\n\n\
The bounds are the tool tip's, in program coordinates, over the positions the program gives: returns \
to a reference point (G28, G30) and G53 moves are machine positions, counted apart (machine_moves) \
and never in the bounds (docs/coordinates.md).\n\n\
On a lathe (a machine file's kind = \"lathe\" or \"mill-turn\", or --dialect fanuc-lathe|haas-lathe) X is \
the tool's radius, whatever the program's diameter mode; the report gives the spindle speeds over the \
cutting moves (spindle_rpm: under constant surface speed, the range the spindle turns through) and each \
thread cut, with its lead (docs/lathe.md).\n\n\
A program `kezuri run` refuses to write (with no option of how to write it: a block the post has no \
words for, G41/G42 for GRBL) is an error here too, said as run says it. Where a word without a decimal \
point may be behind an error, the error says how it was read and the option that reads it otherwise: \
without --no-decimal units, router.nc above stops at its arc with `…; Y10 was read as 0.010 mm \
(Fanuc increments); with --no-decimal units it is 10 mm`.\n\n\
Several programs (a shop's library) are checked on --jobs threads, each as it would be alone, the \
reports in the order the files are given; with --json one line a file, with `error` null or why it \
failed (an unreadable file is a failure in its place, not the end of the batch). docs/batch.md shows \
it under GNU parallel or Slurm for more than one computer.\n\n\
Exit code 1 when the program has errors (each shown with file:line:column), or any of several does.")]
    Check {
        #[command(flatten)]
        run: RunOptions,
        /// Print one JSON object: blocks, motions, holes, feed_length_mm,
        /// rapid_length_mm, time_s, bounds, machine_moves, spindle_rpm
        /// ([min, max] or null), threads (lead, start, end, line), errors,
        /// warnings, machine_values. With several files, one such line a
        /// file, in the order given, with `error` (null, or why it failed).
        #[arg(long)]
        json: bool,
        /// More programs, checked as the first is: each report in the
        /// order the files are given (exit code 1 if any fails).
        #[arg(value_name = "FILE")]
        more: Vec<PathBuf>,
        /// Programs checked at once [default: one a core].
        #[arg(long, value_name = "N")]
        jobs: Option<usize>,
    },
    /// Execute macros and subprograms and write the expanded motion program.
    #[command(after_help = "Examples:
  kezuri run samples/o7023-texture.nc --clock-seed 7 -o expanded.nc
  kezuri run samples/nameplate-cam.nc --to csv -o moves.csv
  kezuri run samples/nameplate-cam.nc --to linuxcnc --svg plate.svg -o plate.ngc
  printf 'G0 X0 Y0 Z5.\\nG83 X10. Y10. Z-12. R2. Q3. F200\\n' > drill.nc
  printf 'X20.\\nG80\\nM30\\n' >> drill.nc
  kezuri run drill.nc --keep-cycles -o drill-cycles.nc   # G83 stays a cycle
  printf 'G0 X-10. Y-10. Z5.\\nG1 Z-1. F300\\nG41 D1 X0 Y0\\n' > contour.nc
  printf 'X40.\\nY30.\\nX0\\nY0\\nG40 X-10. Y-10.\\nG0 Z5.\\nM30\\n' >> contour.nc
  kezuri run contour.nc --machine samples/tools/mill.toml --apply-comp \\
      --to grbl -o contour.gcode   # the tool centre, for GRBL\n\n\
What the machine must do itself is written where the program had it: M codes kezuri does not \
follow (M00, M19, clamps), G10, G92, G52, smoothing codes (G05.1, G187), output signals, taps \
(G84/G74, always as cycles), G41/G42 D. A move the program made as an increment from a \
position it never named (after G28, G53, a tool change) stays an increment.\n\n\
Where nothing names the control (no --post or --to, no [post] preset in the machine file, no .ngc or \
.gcode output), a LinuxCNC or GRBL program is written for its own control, a Fanuc or Haas one for \
Fanuc. What the post cannot write is said at its line, file:line:column.")]
    Run {
        #[command(flatten)]
        run: RunOptions,
        #[command(flatten)]
        write: WriteArgs,
    },
    /// Cusp (the ridge left between neighbouring passes) on an inclined plane, or the pick feed
    /// (the step from one pass to the next) for a target cusp.
    Scallop(scallop::ScallopArgs),
    /// Chip area, E_d (the area times its distance from the axis: what the torque follows) and a
    /// torque estimate per rotation angle on an inclined plane.
    Engage(engage::EngageArgs),
    /// Cutter-location z over a grid of points on an STL mesh: drop-cutter, the cutter lowered at
    /// each point until it touches.
    Dropcut(dropcut::DropcutArgs),
    /// Raster finishing program over an STL or a height grid: rows a stepover apart, or as far
    /// apart as a largest cusp (the ridge left between rows) allows.
    Mill(Box<mill::MillArgs>),
    /// Material-removal simulation of a program on a Z-map (the stock as a grid of heights seen
    /// from above): picture, STL, rapids into the stock, comparison with the intended surface.
    Sim(Box<sim::SimArgs>),
    /// See the job in 3D: one offline HTML page with the toolpath, the tool, the program text
    /// and a playback slider; with --sim the simulated part, with --compare its deviation.
    View(Box<view::ViewArgs>),
    /// Digitize a model on a grid and copy-mill it: plan, capture, level, export, mill.
    #[command(subcommand)]
    Probe(probe::ProbeCommand),
    /// Carve a grayscale sketch as a relief: heights from gray, the cutter lowered onto them until
    /// it touches (drop-cutter), roughing.
    Relief(Box<relief::ReliefArgs>),
    /// Convert between G-code dialects and Roland RML-1: units, scaling, shortening.
    Convert(Box<convert::ConvertArgs>),
    /// Random "hand-carved" texture on the cutting moves of a program: baked in, or as a Fanuc
    /// macro that draws each depth from the control's clock.
    Texture(Box<texture::TextureArgs>),
    /// Thermal drift from on-machine measurements: the measuring program, the
    /// tool's edge in the sensors' profiles, the error model, the corrected program.
    #[command(
        subcommand,
        after_help = "The pipeline, on the demo's simulated sensor profiles (in demo/thermal/):
  kezuri demo --only thermal -o demo
  kezuri thermal plan --machine samples/mill-turn.toml -o O2007.nc
  kezuri thermal measure demo/thermal/index.csv -o meas.csv
  kezuri thermal fit meas.csv --machine samples/mill-turn.toml -o model.json
  kezuri thermal apply samples/o2007-thermal.nc --model model.json \\
      --machine samples/mill-turn.toml --allow-extrapolation -o o2007-warm.nc"
    )]
    Thermal(thermal::ThermalCommand),
    /// A tool's measured cutting profile from backlit images, the database of its wear, and tool
    /// tables read from LinuxCNC, FreeCAD and Fusion 360 files.
    #[command(subcommand)]
    Tool(ToolCommand),
    /// The program corrected for the measured tool's wear and runout.
    #[command(
        subcommand,
        after_help = "The pipeline, on pictures of a worn 0.5 mm ball end mill:
  kezuri tool profile samples/tool-T7/worn/*.png --pixel-um 2 --tip-row 260 \\
      -o t7.csv
  kezuri relief samples/plum-sketch.png --width 20 --depth 1 --smooth 2 \\
      --tool ball:0.5 --stepover 0.5 --post grbl --surface-stl plum.stl \\
      -o plum.gcode
  kezuri wear apply plum.gcode --profile t7.csv --nominal ball:0.5 \\
      --surface plum.stl -o plum-t7.gcode"
    )]
    Wear(wear::WearCommand),
}

/// Runs one command.
fn dispatch(command: &Command) -> anyhow::Result<()> {
    match command {
        Command::Demo { out, only, frames } => demo::run(out, only, *frames),
        Command::Check { run, json, more, jobs } if more.is_empty() && jobs.is_none() => check::run(run, *json),
        Command::Check { run, json, more, jobs } => {
            let files: Vec<PathBuf> = std::iter::once(run.file.clone()).chain(more.iter().cloned()).collect();
            let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
            check::run_many(run, &files, jobs.unwrap_or(cores), *json)
        }
        Command::Run { run, write } => run::run(run, write),
        Command::Scallop(args) => scallop::run(args),
        Command::Engage(args) => engage::run(args),
        Command::Dropcut(args) => dropcut::run(args),
        Command::Mill(args) => mill::run(args),
        Command::Sim(args) => sim::run(args),
        Command::View(args) => view::run(args),
        Command::Probe(command) => probe::run(command),
        Command::Relief(args) => relief::run(args),
        Command::Convert(args) => convert::run(args),
        Command::Texture(args) => texture::run(args),
        Command::Thermal(command) => thermal::run(command),
        Command::Tool(command) => tool::run(command),
        Command::Wear(command) => wear::run(command),
    }
}

impl Cli {
    /// Runs the command given.
    pub fn run(&self) -> anyhow::Result<()> {
        say::set_quiet(self.quiet);
        dispatch(&self.command)
    }
}

/// Refuses a command line that names one file as an output and an input
/// (by device and inode), before the command reads or writes anything:
/// the error is a [`Usage`] (exit code 2).
pub fn refuse_same_files(matches: &clap::ArgMatches) -> anyhow::Result<()> {
    use clap::CommandFactory;
    Ok(files::refuse_same_files(&Cli::command(), matches)?)
}

pub use files::Usage;

/// Runs `kezuri ARGS…` in this process, as the demo does: the words are
/// parsed exactly as on the command line.
fn run_words(words: &[&str]) -> anyhow::Result<()> {
    use clap::{CommandFactory, FromArgMatches};
    let matches = Cli::command().try_get_matches_from(std::iter::once("kezuri").chain(words.iter().copied()))?;
    refuse_same_files(&matches)?;
    let cli = Cli::from_arg_matches(&matches)?;
    dispatch(&cli.command)
}

/// The readers of what users give kezuri (pictures, CSV tables), for the
/// fuzz targets in `fuzz/`: not an API.
#[doc(hidden)]
pub mod inputs {
    pub use crate::gray::read_gray;
    pub use crate::table::read_columns;
}
