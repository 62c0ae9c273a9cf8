//! `kezuri thermal …`: seed 003's thermal-drift measurements.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Args, Subcommand};
use kezuri_post::edge::find_edge;
use serde_json::json;

use crate::files::read_text;
use crate::table::read_columns;

/// The thermal commands.
#[derive(Subcommand, Debug)]
pub enum ThermalCommand {
    /// The reference tool's edge in a line-sensor profile: the profile split into its two
    /// sides, a robust least-squares line through each, their intersection and angle.
    Edge(EdgeArgs),
}

/// `kezuri thermal edge PROFILE.csv`.
#[derive(Args, Debug)]
#[command(after_help = "The profile is a CSV with the header x_mm,z_mm, one point per row in order across the
corner of the square reference tool (../shared/CLI.md). Points more than three robust
standard deviations off their side's line are left out.

Examples:
  kezuri thermal edge sensor1-cold.csv
  kezuri thermal edge sensor1-warm.csv --json
  kezuri thermal edge odd.csv --split 0.25     # the second side starts at x = 0.25 mm")]
pub struct EdgeArgs {
    /// The profile CSV (`x_mm,z_mm`; `-` for standard input).
    pub profile: PathBuf,
    /// Where the second side starts, x in mm [default: where the two lines fit best].
    #[arg(long, value_name = "X", allow_negative_numbers = true)]
    pub split: Option<f64>,
    /// Print one JSON object: edge, angle_deg, rms_residual_mm, inliers, outliers, sides.
    #[arg(long)]
    pub json: bool,
}

/// Runs a thermal command.
pub fn run(command: &ThermalCommand) -> Result<()> {
    match command {
        ThermalCommand::Edge(a) => edge(a),
    }
}

fn edge(a: &EdgeArgs) -> Result<()> {
    let name = a.profile.display().to_string();
    let rows = read_columns(&name, &read_text(&a.profile)?, &["x_mm", "z_mm"])?;
    let points: Vec<[f64; 2]> = rows.iter().map(|r| [r[0], r[1]]).collect();
    let e = find_edge(&points, a.split).with_context(|| name.clone())?;
    if a.json {
        let side = |k: usize| {
            json!({
                "point": e.sides[k].point,
                "direction": e.sides[k].direction,
                "angle_deg": e.sides[k].direction[1].atan2(e.sides[k].direction[0]).to_degrees(),
                "inliers": e.inliers[k],
            })
        };
        let v = json!({
            "file": name,
            "points": points.len(),
            "edge": e.edge,
            "angle_deg": e.angle_deg,
            "rms_residual_mm": e.rms_residual_mm,
            "inliers": e.inliers[0] + e.inliers[1],
            "outliers": e.outliers,
            "split_index": e.split,
            "sides": [side(0), side(1)],
        });
        println!("{v}");
    } else {
        println!("{name}: {} points", points.len());
        println!("  edge       x {:.6} mm, z {:.6} mm", e.edge[0], e.edge[1]);
        println!("  angle      {:.4}° between the sides", e.angle_deg);
        for (k, s) in e.sides.iter().enumerate() {
            println!(
                "  side {}     {} points, direction {:.4}°",
                k + 1,
                e.inliers[k],
                s.direction[1].atan2(s.direction[0]).to_degrees()
            );
        }
        println!("  residual   {:.4} µm rms; {} outliers left out", e.rms_residual_mm * 1e3, e.outliers);
    }
    Ok(())
}
