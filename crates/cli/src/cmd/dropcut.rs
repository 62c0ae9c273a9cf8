//! `kezuri dropcut`: cutter-location z over a grid of points on an STL.

use std::fmt::Write as _;
use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::Args;
use kezuri_cam::dropcut::{drop_cutter_grid_in_order, Grid, MeshSurface};
use kezuri_cam::Cutter;

use crate::files::Outputs;

/// Options of `kezuri dropcut`.
#[derive(Args, Debug)]
#[command(after_help = "\
For every grid point (x, y) the cutter is lowered onto the mesh until it touches: the output is
the tip's z (the lowest point of the cutter: cutter-location or CL points, as OpenCAMLib's), exact for every shape
(vertex, facet and edge contacts). Points run x = X0 + i·STEP for i = 0..round((X1−X0)/STEP),
y likewise; one line `x y z` a point, no header, y outer, x inner, numbers in full precision
(shortest round-trip). The points are written as they are computed, on all cores, so memory
does not grow with the grid. Binary and ASCII STL are read (a binary one a piece at a time,
never held whole); degenerate triangles are skipped.

Points with no triangle within the cutter's radius (off the mesh) get no line, and a warning
on stderr says how many; --fill Z writes Z for them instead. A grid entirely off the mesh is
an error.

Examples:
  kezuri relief samples/plum-sketch.png --width 40 --depth 3 --tool ball:3 \\
      --stepover 1 --surface-stl plum.stl -o plum.nc
  kezuri dropcut plum.stl --tool ball:6 --grid 0,0,40,30,2 -o plum.cl
  kezuri dropcut plum.stl --units inch --tool ball:6 --grid 0,0,1016,762,50 \\
      -o plum-inch.cl   # the model drawn in inches: 25.4 times larger
  kezuri dropcut plum.stl --tool bull:10,1 --grid -5,-5,45,35,1 --fill 5 \\
      > plum-bull.cl
  cat plum.stl | kezuri dropcut - --tool oval:16,24 --grid 0,0,40,30,1

Exit code 1 for an unreadable or empty STL, a coordinate that is no number or beyond the format (file:line:column), a bad tool or grid.")]
pub struct DropcutArgs {
    /// The STL mesh (binary or ASCII); `-` reads stdin.
    #[arg(value_name = "MESH")]
    pub mesh: PathBuf,
    /// The unit the mesh is drawn in (STL files carry none): `inch` multiplies it by 25.4.
    /// [default: mm, with a note where the model is under 13 mm in every direction]
    #[arg(long, value_enum, value_name = "mm|inch")]
    pub units: Option<crate::surface::Units>,
    /// Cutter: flat:D, ball:D, bull:D,R, oval:D,RL or v:D,ANGLE (mm, degrees).
    #[arg(long, value_name = "SPEC", long_help = tool_help!("The cutter."))]
    pub tool: String,
    /// The grid of cutter positions: X0,Y0,X1,Y1,STEP (mm).
    #[arg(long, value_name = "X0,Y0,X1,Y1,STEP", allow_hyphen_values = true)]
    pub grid: String,
    /// Write this z for points with no triangle under the cutter (default:
    /// leave them out).
    #[arg(long, value_name = "Z", allow_negative_numbers = true, value_parser = crate::numbers::coordinate)]
    pub fill: Option<f64>,
    /// The cutter locations, `x y z` a line; `-` or none for stdout.
    #[arg(short, long, value_name = "CL")]
    pub output: Option<PathBuf>,
}

/// Runs `kezuri dropcut`.
pub fn run(args: &DropcutArgs) -> Result<()> {
    let cutter: Cutter = args.tool.parse()?;
    let grid: Grid = args.grid.parse().with_context(|| "--grid")?;
    let mesh = crate::surface::read_mesh(&args.mesh, args.units)?;
    let surface = MeshSurface::new(mesh);

    // Long runs only: a quarter of a million points take a second or so.
    let bar = crate::progress::bar("dropcut", "rows", grid.ny as u64, if grid.len() < 200_000 { u64::MAX } else { 0 });
    // The points are written as they are dropped: to the output file's
    // temporary file, or to standard output once a point has met the mesh
    // (until then a grid wholly off the mesh, an error, is still possible).
    let mut counts = Counts::default();
    let to_stdout = args.output.as_deref().is_none_or(|p| p == Path::new("-"));
    let mut out = Outputs::new();
    if to_stdout {
        let mut w = std::io::BufWriter::with_capacity(1 << 16, std::io::stdout().lock());
        counts = match write_points(&mut w, &cutter, &surface, &grid, args.fill, true, bar.as_ref())
            .and_then(|c| w.flush().map(|()| c))
        {
            // The reader has gone (`| head`): nothing more to do.
            Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => return Ok(()),
            r => r.context("cannot write to standard output")?,
        };
    } else {
        out.add_with(args.output.as_deref(), |w| {
            counts = write_points(w, &cutter, &surface, &grid, args.fill, false, bar.as_ref())?;
            Ok(())
        })?;
    }
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    if counts.missing == grid.len() {
        let (lo, hi) = surface.mesh().bounds().expect("a mesh from an STL has triangles");
        bail!(
            "no grid point has a triangle within the cutter's radius: the grid x {}..{}, y {}..{} lies off the mesh \
             (x {}..{}, y {}..{})",
            grid.x(0),
            grid.x(grid.nx - 1),
            grid.y(0),
            grid.y(grid.ny - 1),
            lo.x,
            hi.x,
            lo.y,
            hi.y
        );
    }
    out.commit()?;
    let missing = counts.missing;
    if missing > 0 {
        let what = if args.fill.is_some() { "written with --fill" } else { "left out (use --fill Z to write them)" };
        eprintln!(
            "warning: {missing} of {} grid points have no triangle within the cutter's radius: {what}",
            grid.len()
        );
    }
    Ok(())
}

/// Points written and left without a triangle under the cutter.
#[derive(Default)]
struct Counts {
    missing: usize,
}

/// Drops the cutter at every grid point and writes each point's line to
/// `w` in order, a batch at a time; with `hold`, nothing is written before
/// the first point that meets the mesh (the lines before it are kept).
fn write_points(
    w: &mut dyn Write,
    cutter: &Cutter,
    surface: &MeshSurface,
    grid: &Grid,
    fill: Option<f64>,
    hold: bool,
    bar: Option<&indicatif::ProgressBar>,
) -> std::io::Result<Counts> {
    let mut counts = Counts::default();
    let mut held: Option<Vec<u8>> = hold.then(Vec::new);
    let make = |k0: usize, zs: &[Option<f64>]| {
        let mut text = String::with_capacity(zs.len() * 40);
        let mut missing = 0;
        for (k, z) in (k0..).zip(zs) {
            missing += usize::from(z.is_none());
            if let Some(z) = z.or(fill) {
                // `+ 0.0` turns a -0 into 0.
                let (x, y) = (grid.x(k % grid.nx) + 0.0, grid.y(k / grid.nx) + 0.0);
                writeln!(text, "{x} {y} {}", z + 0.0).expect("writing to a String");
            }
        }
        (k0 + zs.len(), text, missing, missing < zs.len())
    };
    let each = |(end, text, missing, met): (usize, String, usize, bool)| -> std::io::Result<()> {
        counts.missing += missing;
        match &mut held {
            Some(bytes) if !met => bytes.extend_from_slice(text.as_bytes()),
            Some(bytes) => {
                w.write_all(bytes)?;
                held = None;
                w.write_all(text.as_bytes())?;
            }
            None => w.write_all(text.as_bytes())?,
        }
        if let Some(bar) = bar {
            bar.set_position((end / grid.nx) as u64);
        }
        Ok(())
    };
    drop_cutter_grid_in_order(cutter, surface, grid, make, each)?;
    Ok(counts)
}
