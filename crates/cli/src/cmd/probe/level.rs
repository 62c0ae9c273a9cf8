//! `kezuri probe level`: reference-plane correction, with a before-and-after table of the readings.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use kezuri_cam::probe::data;
use kezuri_cam::probe::level::{level, Method, Reference};
use kezuri_cam::probe::ProbeGrid;
use serde_json::json;

use super::DataArgs;
use crate::files::{read_text, write_output};

/// Options of `kezuri probe level`.
#[derive(Args, Debug)]
#[command(after_help = "\
The reference region holds the points that should lie in one horizontal plane (the model's flat
part): corners, border, rows:A,B or cols:A,B (numbered from 1; row 1 is the first measured) or
mask:FILE (one line per row, row 1 first, a 0 or 1 per point). Candidates: plane (the
least-squares plane turned horizontal), and lines (least-squares lines along two
reference rows or columns, the straight line between them subtracted row by row: takes out a
twist too; with the border, both the row pair and the column pair). Every candidate keeps the
reference's mean height. The table gives count, max, min, mean and standard deviation of the
reference points for the raw data and every candidate; --method auto keeps the smallest
standard deviation.

The levelled data are written in the format read (a capture file gains a `# levelled` line).

Examples:
  kezuri relief samples/plum-sketch.png --width 40 --depth 3 --tool ball:3 \\
      --stepover 1 --surface-stl plum.stl -o plum.nc
  kezuri probe simulate plum.stl --count 41,31 --pitch 1 --stylus ball:10 \\
      --tilt 0.002,-0.001 --noise 0.002 -o plum.txt
  kezuri probe level plum.txt --reference border -o plum-level.txt
  kezuri probe level plum.txt --reference cols:1,41 --method auto --json \\
      -o plum-cols.txt
  grep -v '#' plum.txt > bare.txt   # a bare No,Z file: give its grid
  kezuri probe level bare.txt --count 41,31 --pitch 1 --reference corners")]
pub struct LevelArgs {
    #[command(flatten)]
    pub data: DataArgs,
    /// The reference region: corners, border, rows:A,B, cols:A,B or mask:FILE.
    #[arg(long, value_name = "REGION", default_value = "border")]
    pub reference: String,
    /// The correction to keep.
    #[arg(long, value_enum, default_value = "auto")]
    pub method: LevelMethod,
    /// The levelled data [default: standard output; the table then goes to standard error].
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
    /// Print one JSON object (method, reference_points, std_before_mm, std_after_mm, the
    /// table) instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// `--method`.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum LevelMethod {
    /// Least-squares plane.
    Plane,
    /// Least-squares lines along two reference rows or columns.
    Lines,
    /// The smallest standard deviation.
    Auto,
}

/// Runs `kezuri probe level`.
pub fn run(args: &LevelArgs) -> Result<()> {
    let data = args.data.read()?;
    let g = data.grid.grid;
    let reference = match args.reference.strip_prefix("mask:") {
        Some(file) => Reference::mask(&read_text(Path::new(file))?, g.nx, g.ny).with_context(|| file.to_string())?,
        None => args.reference.parse::<Reference>().map_err(anyhow::Error::msg)?,
    };
    let method = match args.method {
        LevelMethod::Plane => Method::Plane,
        LevelMethod::Lines => Method::Lines,
        LevelMethod::Auto => Method::Auto,
    };
    let levelled = level(&data.grid, &reference, method)
        .with_context(|| format!("{}: --reference {}", args.data.data.display(), args.reference))?;
    let kept = levelled.kept();
    let format = levelled.written_as(&data.format, &args.reference);
    let out = ProbeGrid { grid: g, z: kept.z.clone() };
    write_output(args.output.as_deref(), data::write(&out, &format).as_bytes())?;
    // The table goes to standard output unless the data went there.
    let to_stdout = args.output.as_deref().is_some_and(|o| o != Path::new("-"));
    if args.json {
        let rows: Vec<_> = std::iter::once(("raw".to_string(), levelled.raw))
            .chain(levelled.candidates.iter().map(|c| (c.name.clone(), c.stats)))
            .map(|(name, s)| {
                json!({"data": name, "count": s.count, "max": s.max, "min": s.min, "mean": s.mean, "std": s.std})
            })
            .collect();
        let value = json!({
            "method": kept.name,
            "reference": args.reference,
            "reference_points": levelled.raw.count,
            "std_before_mm": levelled.raw.std,
            "std_after_mm": kept.stats.std,
            "format": data.format.name(),
            "table": rows,
        });
        if to_stdout {
            write_output(None, (value.to_string() + "\n").as_bytes())?;
        } else {
            eprintln!("{value}");
        }
    } else if to_stdout {
        write_output(None, levelled.table().as_bytes())?;
    } else if !crate::say::quiet() {
        eprint!("{}", levelled.table());
    }
    Ok(())
}
