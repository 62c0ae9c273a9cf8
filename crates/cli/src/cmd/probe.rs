//! `kezuri probe`: digitize a model on a grid and copy-mill it:
//! the measuring program, the capture, levelling, export and the milling
//! program.

pub(crate) mod capture;
mod export;
mod level;
mod mill;
mod plan;
mod simulate;

use std::path::PathBuf;
use std::str::FromStr;

use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand};
use kezuri_cam::probe::data::{self, Data, Hint};
use kezuri_cam::probe::Order;

use crate::files::read_text;

/// The `kezuri probe` subcommands.
#[derive(Subcommand, Debug)]
pub enum ProbeCommand {
    /// The measuring program for a grid of plunges (subprogram, expanded or G31 style).
    Plan(Box<plan::PlanArgs>),
    /// Read the indicator over a serial port, one reading per plunge, into a data file.
    Capture(Box<capture::CaptureArgs>),
    /// Reference-plane correction (least-squares plane or reference lines), with a table
    /// of count, max, min, mean and standard deviation.
    Level(Box<level::LevelArgs>),
    /// DXF cross sections, STL surface, shaded PNG or x,y,z CSV of the data; --mirror
    /// completes a half-measured model.
    Export(Box<export::ExportArgs>),
    /// Copy-milling program: the surface the ball-stylus readings imply, with any cutter on it.
    Mill(Box<mill::MillArgs>),
    /// The readings a ball stylus would give on a model (STL or height grid), with tilt and
    /// noise: a capture file to try the pipeline on.
    Simulate(Box<simulate::SimulateArgs>),
}

/// Runs one `kezuri probe` subcommand.
pub fn run(command: &ProbeCommand) -> Result<()> {
    match command {
        ProbeCommand::Plan(args) => plan::run(args),
        ProbeCommand::Capture(args) => capture::run(args, crate::say::quiet()),
        ProbeCommand::Level(args) => level::run(args),
        ProbeCommand::Export(args) => export::run(args),
        ProbeCommand::Mill(args) => mill::run(args),
        ProbeCommand::Simulate(args) => simulate::run(args),
    }
}

/// The data file and what the command line says of its grid.
#[derive(Args, Debug)]
pub struct DataArgs {
    /// The data: a capture file (`#` header with the grid, then `No,Z`), a bare `No,Z` file
    /// (with --count and --pitch), `x,y,z` CSV or a LinuxCNC probe log (`x y z` lines);
    /// `-` reads stdin.
    #[arg(value_name = "DATA")]
    pub data: PathBuf,
    /// Points along X and Y (for bare No,Z files).
    #[arg(long, value_name = "NX,NY")]
    pub count: Option<String>,
    /// Grid pitch, mm (for bare No,Z files).
    #[arg(long, value_name = "MM", value_parser = crate::numbers::length)]
    pub pitch: Option<f64>,
    /// Capture order of a bare No,Z file [default: zigzag].
    #[arg(long, value_name = "zigzag|oneway")]
    pub pattern: Option<String>,
    /// The first point's X,Y, mm (for bare No,Z files) [default: 0,0].
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    pub origin: Option<String>,
}

impl DataArgs {
    /// Reads the data.
    pub fn read(&self) -> Result<Data> {
        let count = self.count.as_deref().map(|t| pair::<usize>("--count", t)).transpose()?;
        let origin = self.origin.as_deref().map(|t| pair::<f64>("--origin", t)).transpose()?;
        let order = self.pattern.as_deref().map(str::parse::<Order>).transpose().map_err(anyhow::Error::msg)?;
        let hint = Hint { count, pitch: self.pitch, origin, order };
        let text = read_text(&self.data)?;
        let name = self.data.display().to_string();
        let data = data::read(&text, &hint).with_context(|| name.clone())?;
        if data.grid.grid.nx < 2 || data.grid.grid.ny < 2 {
            bail!("{name}: the grid needs at least 2 × 2 points");
        }
        Ok(data)
    }
}

/// `A,B` of a flag (`--count 85,105`, `--origin -10,5`): two finite numbers.
fn pair<T: FromStr + Copy>(flag: &str, text: &str) -> Result<[T; 2]> {
    let number = |s: &str| s.trim().parse::<f64>().is_ok_and(f64::is_finite).then(|| s.trim().parse::<T>().ok())?;
    let v: Vec<T> = text
        .split(',')
        .map(number)
        .collect::<Option<_>>()
        .filter(|v: &Vec<T>| v.len() == 2)
        .with_context(|| format!("{flag} '{text}': expected two numbers, A,B"))?;
    Ok([v[0], v[1]])
}
