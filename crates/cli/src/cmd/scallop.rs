//! `kezuri scallop`: the cusp between neighbouring passes on an inclined
//! plane, or the pick feed that keeps it within a target.

use anyhow::{bail, Result};
use clap::{ArgGroup, Args};
use kezuri_cam::scallop::{self, Scallop};
use kezuri_cam::Cutter;
use serde_json::json;

/// Options of `kezuri scallop`.
#[derive(Args, Debug)]
#[command(group(ArgGroup::new("given").required(true).args(["pick_feed", "cusp"])))]
#[command(after_help = "\
The passes run along the contour (Z-level) of a plane inclined at --angle; the pick feed is
measured in the inclined plane (Pf): Pf·cos(angle) across in plan, Pf·sin(angle)
in Z. The cusp is the height of the ridge left between two neighbouring passes, square to
the plane. Step-up (next pass higher) and step-down (next pass lower) leave the same cusp:
both are reported. See docs/scallop.md.

Examples:
  kezuri scallop --tool oval:16,24 --angle 60 --cusp 0.010
  kezuri scallop --tool oval:16,24 --angle 15 --pick-feed 0.8
  kezuri scallop --tool ball:6 --angle 30 --pick-feed 0.5 --json
  kezuri scallop --tool bull:10,1 --angle 45 --cusp 0.005

Exit code 1 for a bad tool, an angle outside [0, 90), a negative pick feed or cusp, a pick
feed that leaves an uncut strip, or a cusp no pick feed can keep to.")]
pub struct ScallopArgs {
    /// Cutter: flat:D, ball:D, bull:D,R, oval:D,RL or v:D,ANGLE (mm, degrees).
    #[arg(long, value_name = "SPEC", long_help = tool_help!("The cutter."))]
    pub tool: String,
    /// Inclination of the plane in degrees, from 0 (level) up to 90 (not included).
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    pub angle: f64,
    /// Pick feed in the inclined plane, mm: report the cusp it leaves.
    #[arg(long, value_name = "MM", allow_negative_numbers = true, value_parser = crate::numbers::length)]
    pub pick_feed: Option<f64>,
    /// The cusp height to keep to, mm: report the largest pick feed that leaves no more.
    #[arg(long, alias = "target", value_name = "MM", allow_negative_numbers = true, value_parser = crate::numbers::length)]
    pub cusp: Option<f64>,
    /// Print one JSON object: tool, angle_deg, pick_feed_mm, cusp_mm,
    /// step_up_cusp_mm, step_down_cusp_mm, plan_stepover_mm, z_step_mm, …
    #[arg(long)]
    pub json: bool,
}

/// Runs `kezuri scallop`.
pub fn run(args: &ScallopArgs) -> Result<()> {
    let cutter: Cutter = args.tool.parse()?;
    let deg = args.angle;
    if !(deg.is_finite() && (0.0..90.0).contains(&deg)) {
        bail!("--angle must be from 0 up to (not including) 90 degrees, got {deg}");
    }
    let angle = deg.to_radians();
    let s = match (args.pick_feed, args.cusp) {
        (Some(pf), _) => scallop::cusp(&cutter, angle, pf)?,
        (None, Some(t)) => scallop::pick_feed(&cutter, angle, t)?,
        (None, None) => bail!("give --pick-feed or --cusp"),
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report(&cutter, deg, args.cusp, &s))?);
    } else {
        print!("{}", text(&cutter, deg, args.cusp, &s));
    }
    if s.width_limited {
        eprintln!(
            "note: every overlapping pick feed meets the target; {} mm is the widest, where the passes just touch",
            s.pick_feed
        );
    }
    Ok(())
}

fn report(cutter: &Cutter, deg: f64, target: Option<f64>, s: &Scallop) -> serde_json::Value {
    let mut v = json!({
        "tool": cutter.to_string(),
        "angle_deg": deg,
        "pick_feed_mm": s.pick_feed,
        "cusp_mm": s.cusp,
        "step_up_cusp_mm": s.step_up_cusp,
        "step_down_cusp_mm": s.step_down_cusp,
        "plan_stepover_mm": s.plan_stepover(),
        "z_step_mm": s.z_step(),
        "contact_radius_mm": s.contact_radius,
        "cusp_offset_mm": s.cusp_offset,
        "at_wall": s.at_wall,
        "width_limited": s.width_limited,
        "method": s.method.to_string(),
    });
    if let Some(t) = target {
        v["target_mm"] = json!(t);
    }
    v
}

fn text(cutter: &Cutter, deg: f64, target: Option<f64>, s: &Scallop) -> String {
    let mut out = format!("tool {cutter} on a plane inclined at {deg}°\n");
    out += &format!(
        "pick feed  {:.6} mm in the plane ({:.6} mm across in plan, {:.6} mm in Z){}\n",
        s.pick_feed,
        s.plan_stepover(),
        s.z_step(),
        if target.is_some() {
            if s.width_limited {
                ": the widest that overlaps"
            } else {
                ": the largest"
            }
        } else {
            ""
        }
    );
    out += &format!("cusp       {:.6} mm ({:.3} µm) square to the plane", s.cusp, s.cusp * 1e3);
    if let Some(t) = target {
        out += &format!(", target {t} mm");
    }
    out += "\n";
    out += &format!(
        "step-up    {:.6} mm, step-down {:.6} mm: the same, as the surface left is the lower envelope of all passes\n",
        s.step_up_cusp, s.step_down_cusp
    );
    out += &format!(
        "contact    r = {:.4} mm on the cutter; the cusp stands {:.4} mm up the plane from the lower pass's contact{}\n",
        s.contact_radius,
        s.cusp_offset,
        if s.at_wall { ", at a shank wall or corner" } else { "" }
    );
    out += &format!("method     {}\n", s.method);
    out
}
