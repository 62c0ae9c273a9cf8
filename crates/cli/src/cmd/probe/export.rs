//! `kezuri probe export`: DXF cross sections, STL surface, shaded PNG, CSV.

use std::path::PathBuf;

use anyhow::{bail, Result};
use clap::{Args, ValueEnum};
use kezuri_cam::probe::data::{self, Format};
use kezuri_cam::probe::export::{dxf, mirror, shade_size, triangles, Mirror};
use kezuri_geom::write_binary_stl;

use super::DataArgs;
use crate::files::Outputs;

/// Options of `kezuri probe export`.
#[derive(Args, Debug)]
#[command(after_help = "\
--dxf writes AutoCAD R12 ASCII: one 3D POLYLINE per row on layer ROWS (cross
sections), with --columns one per column on layer COLS too. --stl is the surface through the
points (two triangles per cell, not a closed solid). --mirror x reflects the data in the last
column (the largest X, the symmetry line, kept once), --mirror y in the last row: a model
measured on one half is completed before anything is written.

Examples:
  kezuri relief samples/plum-sketch.png --width 40 --depth 3 --tool ball:3 \\
      --stepover 1 --surface-stl plum.stl -o plum.nc
  kezuri probe simulate plum.stl --count 41,31 --pitch 1 --stylus ball:10 \\
      --tilt 0.002,-0.001 --noise 0.002 -o plum.txt
  kezuri probe export plum.txt --dxf plum.dxf --columns --png plum.png
  kezuri probe export plum.txt --mirror x --stl whole.stl --csv whole.csv")]
pub struct ExportArgs {
    #[command(flatten)]
    pub data: DataArgs,
    /// DXF (R12 ASCII) cross sections, one polyline per row.
    #[arg(long, value_name = "F.dxf")]
    pub dxf: Option<PathBuf>,
    /// Also a polyline per column in the DXF.
    #[arg(long)]
    pub columns: bool,
    /// Binary STL of the measured surface (through the points).
    #[arg(long, value_name = "F.stl")]
    pub stl: Option<PathBuf>,
    /// Shaded picture (PNG).
    #[arg(long, value_name = "F.png")]
    pub png: Option<PathBuf>,
    /// Pixels per pitch in the PNG.
    #[arg(long, value_name = "N", default_value_t = 4)]
    pub png_scale: usize,
    /// `x,y,z` CSV.
    #[arg(long, value_name = "F.csv")]
    pub csv: Option<PathBuf>,
    /// Complete a half-measured model by its mirror image.
    #[arg(long, value_enum)]
    pub mirror: Option<MirrorAxis>,
}

/// `--mirror`.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum MirrorAxis {
    /// In the last column.
    X,
    /// In the last row.
    Y,
}

/// The most pixels a --png may have (150 MB of RGB).
const MAX_PIXELS: usize = 50_000_000;

/// Runs `kezuri probe export`.
pub fn run(args: &ExportArgs) -> Result<()> {
    if args.dxf.is_none() && args.stl.is_none() && args.png.is_none() && args.csv.is_none() {
        bail!("nothing to export: give --dxf, --stl, --png or --csv");
    }
    if !(1..=64).contains(&args.png_scale) {
        bail!("--png-scale must be 1 to 64, got {}", args.png_scale);
    }
    let mut grid = args.data.read()?.grid;
    if let Some(axis) = args.mirror {
        grid = mirror(&grid, if matches!(axis, MirrorAxis::X) { Mirror::X } else { Mirror::Y });
    }
    // Everything is made before anything is written.
    let mut outputs: Vec<(&PathBuf, Vec<u8>)> = Vec::new();
    if let Some(p) = &args.dxf {
        outputs.push((p, dxf(&grid, args.columns).into_bytes()));
    }
    if let Some(p) = &args.stl {
        outputs.push((p, write_binary_stl(&triangles(&grid))));
    }
    if let Some(p) = &args.png {
        let pixels = shade_size(&grid, args.png_scale).and_then(|(w, h)| Some((w, h, w.checked_mul(h)?)));
        match pixels {
            Some((_, _, n)) if n <= MAX_PIXELS => {}
            Some((w, h, _)) => bail!(
                "--png: {w} × {h} pixels is more than {MAX_PIXELS}: give a smaller --png-scale (now {})",
                args.png_scale
            ),
            None => bail!("--png: the picture is too large: give a smaller --png-scale"),
        }
        let data = &args.data.data;
        let name = data.file_name().map_or_else(|| data.display().to_string(), |n| n.to_string_lossy().into_owned());
        outputs.push((p, kezuri_picture::probe::probed(&grid, args.png_scale, &name)?));
    }
    if let Some(p) = &args.csv {
        outputs.push((p, data::write(&grid, &Format::Csv).into_bytes()));
    }
    let mut out = Outputs::new();
    for (path, bytes) in outputs {
        out.add(Some(path), &bytes)?;
    }
    out.commit()
}
