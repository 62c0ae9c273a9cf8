//! `kezuri engage`: the chip one tooth cuts on an inclined plane — its area
//! on the rake face, that area's distance from the axis and the torque it
//! suggests, at every rotation angle (`kezuri_cam::engage`).

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use kezuri_cam::engage::report::{uncut_stock, Study};
use kezuri_cam::engage::{Cut, Step};
use kezuri_cam::{scallop, Cutter};
use kezuri_picture::png_from_svg;

use crate::files::Outputs;

/// Options of `kezuri engage`.
#[derive(Args, Debug)]
#[command(after_help = "\
The tool runs along X on a plane inclined at --angle about X, tangent to its tip; the stock
surface stands --depth above that plane (square to it) and the previous pass lies --pick-feed
away along the slope: higher for --next-pass down, lower for --next-pass up. One tooth's
chip is what this pass removes in one feed per tooth; its rake face (the straight radial line from the axis
to the helical edge at each height) turns through it. For each rotation angle θ (0 where the
edge at the top of the cutter's tip points to +Y, increasing as the spindle turns, M03):
  A    the area where the rake face cuts the chip, mm²
  L_G  the distance from the axis to that area's centroid, mm
  E_d  A·L_G, mm³: the torque the tooth needs, up to the material's constant
  T    --kc × E_d, N·mm: a torque estimate, not a measurement
See docs/engage.md for the model and its checks.

Examples:
  kezuri engage --tool oval:16,24 --angle 45 --pick-feed 0.8 --depth 0.8 \\
      --feed-per-tooth 0.16
  kezuri engage --tool oval:16,24 --angle 0:75:15 --pick-feed auto --cusp 0.01 \\
      --depth 0.8 --feed-per-tooth 0.16 --next-pass both --cut both \\
      --png engage.png
  kezuri engage --tool ball:10 --angle 30 --pick-feed 0.5 --depth 0.5 \\
      --feed-per-tooth 0.1 --json

Exit code 1 for a bad tool, an angle outside [0, 90), a pick feed wider than the cutter, a depth
the cutter cannot reach, a helix outside [0, 90) or a file that cannot be written.")]
pub struct EngageArgs {
    /// Cutter: flat:D, ball:D, bull:D,R, oval:D,RL or v:D,ANGLE (mm, degrees).
    #[arg(long, value_name = "SPEC", long_help = tool_help!("The cutter."))]
    pub tool: String,
    /// Inclination of the plane in degrees, [0, 90): one angle, a list
    /// (15,30,45) or a range FIRST:LAST:STEP (0:75:15).
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    pub angle: String,
    /// Pick feed (the step from the previous pass to this one) along the slope, mm: one for every
    /// angle, one per angle (0.462,0.484,…), or `auto` for the largest that keeps the cusp (the
    /// ridge left between two passes) within --cusp.
    #[arg(long, value_name = "MM|auto", allow_negative_numbers = true)]
    pub pick_feed: String,
    /// The cusp `--pick-feed auto` keeps to, mm.
    #[arg(long, value_name = "MM", default_value_t = 0.010, value_parser = crate::numbers::length)]
    pub cusp: f64,
    /// Depth of cut square to the plane, mm (the stock above the finished surface).
    #[arg(long, value_name = "MM", allow_negative_numbers = true, value_parser = crate::numbers::length)]
    pub depth: f64,
    /// Feed per tooth, mm.
    #[arg(long, value_name = "MM", allow_negative_numbers = true, value_parser = crate::numbers::length)]
    pub feed_per_tooth: f64,
    /// Number of flutes.
    #[arg(long, value_name = "N", default_value_t = 2)]
    pub flutes: u32,
    /// Helix angle of the flutes, degrees (right hand), [0, 90).
    #[arg(long, value_name = "DEG", default_value_t = 30.0, allow_negative_numbers = true)]
    pub helix: f64,
    /// Which way the passes go on the slope: each next pass lower (down: step-down, the previous
    /// pass above it) or higher (up: step-up, the previous pass below); both computes each.
    #[arg(long = "next-pass", alias = "step", value_enum, value_name = "down|up|both", default_value = "down")]
    pub step: StepChoice,
    /// Down-cut (climb) or up-cut (conventional), spindle turning M03; both computes each.
    #[arg(long, value_enum, default_value = "down")]
    pub cut: CutChoice,
    /// Cutting force per chip area, N/mm², for the torque estimate T = kc·E_d.
    #[arg(long, value_name = "N/MM2", default_value_t = 3500.0, value_parser = crate::numbers::positive)]
    pub kc: f64,
    /// Rotation angles computed over one revolution of the cutter.
    #[arg(long = "rotation-steps", alias = "steps", value_name = "N", default_value_t = 360, value_parser = clap::value_parser!(u32).range(8..=100_000))]
    pub steps: u32,
    /// Write every angle of every case as CSV.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Draw the charts (area per rotation angle; largest area and E_d per inclination) as SVG.
    #[arg(long, value_name = "FILE")]
    pub svg: Option<PathBuf>,
    /// Draw the same charts as PNG.
    #[arg(long, value_name = "FILE")]
    pub png: Option<PathBuf>,
    /// Print JSON: one case as an object (angles_deg, area_mm2, lg_mm, ed_mm3, torque_n_mm,
    /// area_max_mm2, ed_max_mm3, torque_max_n_mm, engaged_deg, chip_volume_mm3, pick_feed_mm, and
    /// tool_torque_n_mm, tool_torque_max_n_mm: every flute together), several as {"cases": [...]}.
    #[arg(long)]
    pub json: bool,
}

/// `--next-pass`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum StepChoice {
    /// The next pass lower on the slope (the previous pass higher).
    Down,
    /// The next pass higher on the slope.
    Up,
    /// Each of the two.
    Both,
}

/// `--cut`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum CutChoice {
    /// Down-cut (climb milling).
    Down,
    /// Up-cut (conventional milling).
    Up,
    /// Each of the two.
    Both,
}

/// The inclinations of `--angle`: `A`, `A,B,…` or `FIRST:LAST:STEP`.
fn angles(text: &str) -> Result<Vec<f64>> {
    let number = |s: &str| -> Result<f64> {
        let v: f64 = s.trim().parse().with_context(|| format!("--angle: '{s}' is not a number"))?;
        if !(v.is_finite() && (0.0..90.0).contains(&v)) {
            bail!("--angle must be from 0 up to (not including) 90 degrees, got {v}");
        }
        Ok(v)
    };
    let parts: Vec<&str> = text.split(':').collect();
    match parts.as_slice() {
        [first, last, step] => {
            let (a, b) = (number(first)?, number(last)?);
            let s: f64 = step.trim().parse().with_context(|| format!("--angle: '{step}' is not a number"))?;
            if !(s.is_finite() && s > 0.0) || b < a {
                bail!("--angle FIRST:LAST:STEP needs FIRST ≤ LAST and a STEP more than 0, got {text}");
            }
            let n = ((b - a) / s + 1e-9).floor();
            if n > 1000.0 {
                bail!("--angle {text} makes {} angles (at most 1001)", n + 1.0);
            }
            Ok((0..=n as usize).map(|k| a + k as f64 * s).collect())
        }
        [list] => list.split(',').map(number).collect(),
        _ => bail!("--angle takes an angle, a list A,B,… or a range FIRST:LAST:STEP, got {text}"),
    }
}

/// The pick feed of each inclination.
fn pick_feeds(args: &EngageArgs, cutter: &Cutter, angles: &[f64]) -> Result<Vec<f64>> {
    if args.pick_feed.trim().eq_ignore_ascii_case("auto") {
        return angles.iter().map(|a| Ok(scallop::pick_feed(cutter, a.to_radians(), args.cusp)?.pick_feed)).collect();
    }
    let given: Vec<f64> = args
        .pick_feed
        .split(',')
        .map(|s| crate::numbers::length(s).map_err(|e| anyhow::anyhow!("--pick-feed '{}': {e}", s.trim())))
        .collect::<Result<_>>()?;
    match given.len() {
        1 => Ok(vec![given[0]; angles.len()]),
        n if n == angles.len() => Ok(given),
        n => bail!("--pick-feed gives {n} pick feeds for {} angles: give one, one per angle, or auto", angles.len()),
    }
}

/// Runs `kezuri engage`.
pub fn run(args: &EngageArgs) -> Result<()> {
    let cutter: Cutter = args.tool.parse()?;
    if !(args.helix.is_finite() && (0.0..90.0).contains(&args.helix)) {
        bail!("--helix must be from 0 up to (not including) 90 degrees, got {}", args.helix);
    }
    if args.flutes == 0 {
        bail!("--flutes must be at least 1");
    }
    let angles = angles(&args.angle)?;
    let feeds = pick_feeds(args, &cutter, &angles)?;
    for (&angle_deg, &pick_feed) in angles.iter().zip(&feeds) {
        if let Some(warning) = uncut_stock(&cutter, angle_deg, pick_feed, args.depth) {
            eprintln!("warning: {warning}");
        }
    }
    let steps: &[Step] = match args.step {
        StepChoice::Down => &[Step::Down],
        StepChoice::Up => &[Step::Up],
        StepChoice::Both => &[Step::Up, Step::Down],
    };
    let cuts: &[Cut] = match args.cut {
        CutChoice::Down => &[Cut::Down],
        CutChoice::Up => &[Cut::Up],
        CutChoice::Both => &[Cut::Down, Cut::Up],
    };
    let mut study = Study {
        cutter,
        flutes: args.flutes,
        helix_deg: args.helix,
        depth: args.depth,
        feed_per_tooth: args.feed_per_tooth,
        kc: args.kc,
        rotation_steps: args.steps as usize,
        cases: Vec::new(),
    };
    for &cut in cuts {
        for &step in steps {
            for (&angle_deg, &pick_feed) in angles.iter().zip(&feeds) {
                study.add(angle_deg, pick_feed, step, cut)?;
            }
        }
    }

    let mut out = Outputs::new();
    if let Some(path) = &args.csv {
        out.add(Some(path), study.csv().as_bytes())?;
    }
    if args.svg.is_some() || args.png.is_some() {
        let svg = kezuri_picture::engage::charts(&study, &args.tool);
        if let Some(path) = &args.svg {
            out.add(Some(path), svg.as_bytes())?;
        }
        if let Some(path) = &args.png {
            out.add(Some(path), &png_from_svg(&svg)?)?;
        }
    }
    if args.json {
        out.add(None, (serde_json::to_string_pretty(&study.to_json())? + "\n").as_bytes())?;
    } else {
        out.add(None, study.table().as_bytes())?;
    }
    out.commit()
}
