//! `kezuri dropcut`: cutter-location z over a grid of points on an STL.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};

use anyhow::{bail, Context, Result};
use clap::Args;
use kezuri_cam::dropcut::{drop_cutter_grid, Grid, MeshSurface};
use kezuri_cam::Cutter;

use crate::files::write_output;

/// Options of `kezuri dropcut`.
#[derive(Args, Debug)]
#[command(after_help = "\
For every grid point (x, y) the cutter is lowered onto the mesh until it touches: the output is
the tip's z (the lowest point of the cutter: cutter-location or CL points, as OpenCAMLib's), exact for every shape
(vertex, facet and edge contacts). Points run x = X0 + i·STEP for i = 0..round((X1−X0)/STEP),
y likewise; one line `x y z` a point, no header, y outer, x inner, numbers in full precision
(shortest round-trip). Binary and ASCII STL are read; degenerate triangles are skipped.

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
    // Each point's height (16 bytes) and its line of text (about 40).
    crate::budget::memory("--grid", grid.len() as f64, "points", 56.0)?;
    let mesh = crate::surface::read_mesh(&args.mesh, args.units)?;
    let surface = MeshSurface::new(mesh);

    // Long runs only: a quarter of a million points take a second or so.
    let bar = crate::progress::bar("dropcut", "rows", grid.ny as u64, if grid.len() < 200_000 { u64::MAX } else { 0 });
    let rows_done = AtomicU64::new(0);
    let on_row = || {
        let done = rows_done.fetch_add(1, Ordering::Relaxed) + 1;
        if let Some(bar) = &bar {
            bar.set_position(done);
        }
    };
    let z = drop_cutter_grid(&cutter, &surface, &grid, &on_row);
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }

    let missing = z.iter().filter(|z| z.is_none()).count();
    if missing == z.len() {
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
    let mut out = String::with_capacity(z.len() * 32);
    for (k, z) in z.iter().enumerate() {
        if let Some(z) = z.or(args.fill) {
            // `+ 0.0` turns a -0 into 0.
            let (x, y) = (grid.x(k % grid.nx) + 0.0, grid.y(k / grid.nx) + 0.0);
            writeln!(out, "{x} {y} {}", z + 0.0).expect("writing to a String");
        }
    }
    write_output(args.output.as_deref(), out.as_bytes())?;
    if missing > 0 {
        let what = if args.fill.is_some() { "written with --fill" } else { "left out (use --fill Z to write them)" };
        eprintln!(
            "warning: {missing} of {} grid points have no triangle within the cutter's radius: {what}",
            grid.len()
        );
    }
    Ok(())
}
