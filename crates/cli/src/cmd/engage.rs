//! `kezuri engage`: the chip one tooth cuts on an inclined plane — its area
//! on the rake face, that area's distance from the axis and the torque it
//! suggests, at every rotation angle (`kezuri_cam::engage`).

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use kezuri_cam::engage::{self, Chip, Cut, Engagement, Step, Sweep};
use kezuri_cam::{scallop, Cutter};
use kezuri_picture::chart::{line_chart, stack, Line};
use kezuri_picture::png_from_svg;
use serde_json::{json, Value};

use crate::files::Outputs;

/// Options of `kezuri engage`.
#[derive(Args, Debug)]
#[command(after_help = "\
The tool runs along X on a plane inclined at --angle about X, tangent to its tip; the stock
surface stands --depth above that plane (square to it) and the previous pass lies --pick-feed
away along the slope: higher for --step down, lower for --step up. One tooth's chip is what
this pass removes in one feed per tooth; its rake face (the straight radial line from the axis
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
      --depth 0.8 --feed-per-tooth 0.16 --step both --cut both --png engage.png
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
    /// Pick feed along the slope, mm: one for every angle, one per angle
    /// (0.462,0.484,…), or `auto` for the largest that keeps the cusp
    /// within --cusp.
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
    /// Where the previous pass lies: the next pass is lower on the slope
    /// (down) or higher (up); both computes each.
    #[arg(long, value_enum, default_value = "down")]
    pub step: StepChoice,
    /// Down-cut (climb) or up-cut (conventional), spindle turning M03; both computes each.
    #[arg(long, value_enum, default_value = "down")]
    pub cut: CutChoice,
    /// Cutting force per chip area, N/mm², for the torque estimate T = kc·E_d.
    #[arg(long, value_name = "N/MM2", default_value_t = 3500.0, value_parser = crate::numbers::positive)]
    pub kc: f64,
    /// Rotation angles over one revolution.
    #[arg(long, value_name = "N", default_value_t = 360, value_parser = clap::value_parser!(u32).range(8..=100_000))]
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

/// `--step`.
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

/// One inclination, step and cut, computed.
struct Case {
    angle_deg: f64,
    pick_feed: f64,
    step: Step,
    cut: Cut,
    sweep: Sweep,
    volume: f64,
    /// E_d of all the flutes together at each angle of the sweep, mm³:
    /// every tooth cuts the same chip, `2π/flutes` behind the one before.
    tool_ed: Vec<f64>,
}

impl Case {
    fn tool_ed_max(&self) -> f64 {
        self.tool_ed.iter().copied().fold(0.0, f64::max)
    }
}

/// E_d of all `flutes` teeth at each angle of `sweep` (one revolution in
/// equal steps): where the flutes' pitch is a whole number of steps the
/// other teeth's sections are the sweep's own, else they are computed.
fn tool_ed(chip: &Chip, sweep: &Sweep, flutes: u32) -> Vec<f64> {
    let n = sweep.sections.len();
    let f = flutes as usize;
    if n.is_multiple_of(f) {
        let shift = n / f;
        return (0..n).map(|j| (0..f).map(|k| sweep.sections[(j + n - k * shift) % n].ed).sum()).collect();
    }
    let pitch = std::f64::consts::TAU / f64::from(flutes);
    sweep
        .theta
        .iter()
        .zip(&sweep.sections)
        .map(|(&t, first)| first.ed + (1..flutes).map(|k| chip.section(t - pitch * f64::from(k)).ed).sum::<f64>())
        .collect()
}

fn step_name(s: Step) -> &'static str {
    match s {
        Step::Up => "up",
        Step::Down => "down",
    }
}

fn cut_name(c: Cut) -> &'static str {
    match c {
        Cut::Down => "down",
        Cut::Up => "up",
    }
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
        // A cusp as tall as the stock: the passes leave a strip of it uncut.
        if let Ok(s) = scallop::cusp(&cutter, angle_deg.to_radians(), pick_feed) {
            if s.cusp >= args.depth {
                eprintln!(
                    "warning: at {angle_deg}° a pick feed of {pick_feed:.4} mm leaves a cusp of {:.4} mm, not less \
                     than the depth of {} mm: the passes leave stock between them uncut",
                    s.cusp, args.depth
                );
            }
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
    let mut cases = Vec::new();
    for &cut in cuts {
        for &step in steps {
            for (&angle_deg, &pick_feed) in angles.iter().zip(&feeds) {
                let e = Engagement {
                    cutter,
                    flutes: args.flutes,
                    helix: args.helix.to_radians(),
                    angle: angle_deg.to_radians(),
                    depth: args.depth,
                    pick_feed,
                    feed_per_tooth: args.feed_per_tooth,
                    step,
                    cut,
                };
                let chip = Chip::new(&e).with_context(|| {
                    format!("at {angle_deg}° with a pick feed of {pick_feed} mm, step {}", step_name(step))
                })?;
                let sweep = engage::sweep(&chip, args.steps as usize);
                let tool_ed = tool_ed(&chip, &sweep, args.flutes);
                cases.push(Case { angle_deg, pick_feed, step, cut, volume: chip.volume(), sweep, tool_ed });
            }
        }
    }

    let mut out = Outputs::new();
    if let Some(path) = &args.csv {
        out.add(Some(path), csv(&cases, args.kc).as_bytes())?;
    }
    if args.svg.is_some() || args.png.is_some() {
        let svg = charts(&cases, args.kc, &args.tool);
        if let Some(path) = &args.svg {
            out.add(Some(path), svg.as_bytes())?;
        }
        if let Some(path) = &args.png {
            out.add(Some(path), &png_from_svg(&svg)?)?;
        }
    }
    if args.json {
        let mut objects: Vec<Value> = cases.iter().map(|c| report(&cutter, args, c)).collect();
        let value = if objects.len() == 1 { objects.remove(0) } else { json!({ "cases": objects }) };
        out.add(None, (serde_json::to_string_pretty(&value)? + "\n").as_bytes())?;
    } else {
        out.add(None, text(&cutter, args, &cases).as_bytes())?;
    }
    out.commit()
}

/// Angles in degrees, rounded to 1e-9° (no `127.00000000000001`).
fn degrees(v: &[f64]) -> Vec<f64> {
    v.iter().map(|t| (t.to_degrees() * 1e9).round() / 1e9).collect()
}

fn report(cutter: &Cutter, args: &EngageArgs, c: &Case) -> Value {
    let s = &c.sweep;
    json!({
        "tool": cutter.to_string(),
        "inclination_deg": c.angle_deg,
        "step": step_name(c.step),
        "cut": cut_name(c.cut),
        "flutes": args.flutes,
        "helix_deg": args.helix,
        "depth_mm": args.depth,
        "feed_per_tooth_mm": args.feed_per_tooth,
        "kc_n_mm2": args.kc,
        "pick_feed_mm": c.pick_feed,
        "angles_deg": degrees(&s.theta),
        "area_mm2": s.sections.iter().map(|x| x.area).collect::<Vec<_>>(),
        "lg_mm": s.sections.iter().map(|x| x.lg).collect::<Vec<_>>(),
        "ed_mm3": s.sections.iter().map(|x| x.ed).collect::<Vec<_>>(),
        "torque_n_mm": s.sections.iter().map(|x| args.kc * x.ed).collect::<Vec<_>>(),
        "area_max_mm2": s.area_max,
        "ed_max_mm3": s.ed_max,
        "torque_max_n_mm": args.kc * s.ed_max,
        "tool_torque_n_mm": c.tool_ed.iter().map(|e| args.kc * e).collect::<Vec<_>>(),
        "tool_torque_max_n_mm": args.kc * c.tool_ed_max(),
        "engaged_deg": s.engaged.map(|(a, b)| degrees(&[a, b])),
        "chip_volume_mm3": c.volume,
    })
}

fn text(cutter: &Cutter, args: &EngageArgs, cases: &[Case]) -> String {
    let mut out = format!(
        "tool {cutter}, {} flutes, helix {}°; depth {} mm, feed per tooth {} mm; torque T = {} N/mm² × E_d\n",
        args.flutes, args.helix, args.depth, args.feed_per_tooth, args.kc
    );
    out += "angle  step  cut   pick feed  A max      E_d max    T max     engaged θ          chip volume  T tool max\n";
    out += "deg               mm         mm²        mm³        N·mm      deg                mm³          N·mm\n";
    out += "                             (one tooth's, but the last: every flute together)\n";
    let mut sliver = false;
    for c in cases {
        let step = 360.0 / c.sweep.theta.len() as f64;
        let engaged = match c.sweep.engaged {
            // Every angle: the tip's sliver, narrower than the feed per
            // tooth, is cut all round (docs/engage.md).
            Some((a, b)) if (b - a).to_degrees() >= 360.0 - 1.5 * step => {
                sliver = true;
                "whole turn *".to_string()
            }
            Some((a, b)) => format!("{:7.1} … {:6.1}", a.to_degrees(), b.to_degrees()),
            None => "no chip".to_string(),
        };
        let _ = writeln!(
            out,
            "{:5.1}  {:<4}  {:<4}  {:9.4}  {:9.6}  {:9.5}  {:8.2}  {engaged:<17}  {:<11.6}  {:8.2}",
            c.angle_deg,
            step_name(c.step),
            cut_name(c.cut),
            c.pick_feed,
            c.sweep.area_max,
            c.sweep.ed_max,
            args.kc * c.sweep.ed_max,
            c.volume,
            args.kc * c.tool_ed_max()
        );
    }
    if sliver {
        out += "* the lowest part of the tip, narrower than the feed per tooth, is never covered by the\n  \
                tooth before: a sliver of it is cut at every angle (the charts show the real chip)\n";
    }
    out
}

/// The angle of a case's largest area, degrees.
fn peak(x: &Case) -> f64 {
    let s = &x.sweep;
    let k = (0..s.sections.len()).max_by(|&a, &b| s.sections[a].area.total_cmp(&s.sections[b].area));
    k.map_or(0.0, |k| s.theta[k].to_degrees())
}

/// A case's rotation angles (degrees) and sections, in order, over the turn
/// about its largest area, that area's angle taken within half a turn of
/// `centre`: each case drawn as one curve, the cases side by side.
fn around_peak(x: &Case, centre: f64) -> Vec<(f64, &engage::Section)> {
    let p = peak(x);
    let p = centre + (p - centre + 180.0).rem_euclid(360.0) - 180.0;
    let mut points: Vec<(f64, &engage::Section)> = x
        .sweep
        .theta
        .iter()
        .zip(&x.sweep.sections)
        .map(|(t, v)| (p + (t.to_degrees() - p + 180.0).rem_euclid(360.0) - 180.0, v))
        .collect();
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    points
}

/// Where to draw the cases' rotation angles, degrees: about the circular
/// mean of the angles of their largest areas (`centre`), from 5° before the
/// first angle where a case's area reaches 1 % of its largest to 5° after
/// the last (`lo`, `hi`).
fn window(cases: &[&Case]) -> (f64, f64, f64) {
    let (sin, cos) = cases.iter().fold((0.0, 0.0), |(s, c), x| {
        let p = peak(x).to_radians();
        (s + p.sin(), c + p.cos())
    });
    // In [0°, 360°), as the table and the JSON give the angles.
    let centre = sin.atan2(cos).to_degrees().rem_euclid(360.0);
    let (mut lo, mut hi) = (f64::MAX, f64::MIN);
    for x in cases {
        for (t, v) in around_peak(x, centre) {
            if v.area > 0.01 * x.sweep.area_max {
                (lo, hi) = (lo.min(t), hi.max(t));
            }
        }
    }
    if lo > hi {
        return (centre, centre - 180.0, centre + 180.0);
    }
    (centre, lo - 5.0, hi + 5.0)
}

fn csv(cases: &[Case], kc: f64) -> String {
    let mut out = String::from("angle_deg,step,cut,pick_feed_mm,theta_deg,area_mm2,lg_mm,ed_mm3,torque_n_mm\n");
    for c in cases {
        for (theta, x) in c.sweep.theta.iter().zip(&c.sweep.sections) {
            let _ = writeln!(
                out,
                "{},{},{},{},{:.4},{:.9},{:.6},{:.9},{:.6}",
                c.angle_deg,
                step_name(c.step),
                cut_name(c.cut),
                c.pick_feed,
                theta.to_degrees(),
                x.area,
                x.lg,
                x.ed,
                kc * x.ed
            );
        }
    }
    out
}

/// The charts: the area per rotation angle of each step and cut (a line
/// per inclination), E_d per rotation angle where there is one inclination,
/// and the largest area and E_d per inclination where there are several.
fn charts(cases: &[Case], kc: f64, tool: &str) -> String {
    let mut combos: Vec<(Step, Cut)> = Vec::new();
    for c in cases {
        if !combos.contains(&(c.step, c.cut)) {
            combos.push((c.step, c.cut));
        }
    }
    let several = cases.iter().any(|c| c.angle_deg != cases[0].angle_deg);
    let combo_name = |s: Step, c: Cut| format!("{tool}, step-{}, {}-cut", step_name(s), cut_name(c));
    let per_theta = |s: Step, c: Cut, value: &dyn Fn(&engage::Section) -> f64| -> Vec<Line> {
        let these: Vec<&Case> = cases.iter().filter(|x| x.step == s && x.cut == c).collect();
        let (centre, lo, hi) = window(&these);
        these
            .iter()
            .map(|x| Line {
                label: format!("α {}°, Pf {:.3} mm", x.angle_deg, x.pick_feed),
                points: around_peak(x, centre)
                    .into_iter()
                    .filter(|(t, _)| (lo..=hi).contains(t))
                    .map(|(t, v)| (t, value(v)))
                    .collect(),
            })
            .collect()
    };
    let mut svgs = Vec::new();
    for &(s, c) in &combos {
        svgs.push(line_chart(
            &format!("Chip area per rotation angle ({})", combo_name(s, c)),
            "rotation angle θ, deg",
            "chip area A, mm²",
            &per_theta(s, c, &|v| v.area),
        ));
        if !several {
            svgs.push(line_chart(
                &format!("E_d = A·L_G per rotation angle ({}); torque ≈ {kc} N/mm² × E_d", combo_name(s, c)),
                "rotation angle θ, deg",
                "E_d, mm³",
                &per_theta(s, c, &|v| v.ed),
            ));
        }
    }
    if several {
        let per_angle = |value: &dyn Fn(&Case) -> f64| -> Vec<Line> {
            combos
                .iter()
                .map(|&(s, c)| Line {
                    label: combo_name(s, c),
                    points: cases
                        .iter()
                        .filter(|x| x.step == s && x.cut == c)
                        .map(|x| (x.angle_deg, value(x)))
                        .collect(),
                })
                .collect()
        };
        svgs.push(line_chart(
            &format!("Largest chip area per inclination, {tool}"),
            "inclination α, deg",
            "A max, mm²",
            &per_angle(&|x| x.sweep.area_max),
        ));
        svgs.push(line_chart(
            &format!("Largest E_d per inclination, {tool}; torque ≈ {kc} N/mm² × E_d"),
            "inclination α, deg",
            "E_d max, mm³",
            &per_angle(&|x| x.sweep.ed_max),
        ));
    }
    stack(&svgs)
}
