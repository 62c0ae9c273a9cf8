//! A study of engagements (`kezuri engage`): one tooth's chip at each
//! inclination, step and cut, every flute's `E_d` together, the torque
//! estimate `T = kc·E_d`, and the results as a table, as CSV and as JSON.

use std::fmt::Write as _;

use serde_json::{json, Value};

use super::{sweep, Chip, Cut, Engagement, Section, Step, Sweep};
use crate::{scallop, Cutter, Error};

/// What every case of a study shares, as given, and its cases.
#[derive(Clone, Debug)]
pub struct Study {
    /// The cutter.
    pub cutter: Cutter,
    /// Number of flutes (≥ 1).
    pub flutes: u32,
    /// Helix angle of the flutes, degrees.
    pub helix_deg: f64,
    /// Depth of cut square to the plane, mm.
    pub depth: f64,
    /// Feed per tooth, mm.
    pub feed_per_tooth: f64,
    /// Cutting force per chip area, N/mm², for the torque estimate
    /// `T = kc·E_d`.
    pub kc: f64,
    /// Rotation angles over one revolution.
    pub rotation_steps: usize,
    /// The cases, in the order added.
    pub cases: Vec<Case>,
}

/// One inclination, step and cut, computed.
#[derive(Clone, Debug)]
pub struct Case {
    /// Inclination of the plane, degrees.
    pub angle_deg: f64,
    /// Pick feed along the slope, mm.
    pub pick_feed: f64,
    /// Where the previous pass lies.
    pub step: Step,
    /// Down- or up-cut.
    pub cut: Cut,
    /// One tooth's sections over a revolution.
    pub sweep: Sweep,
    /// The chip's volume, mm³.
    pub volume: f64,
    /// `E_d` of all the flutes together at each angle of the sweep, mm³:
    /// every tooth cuts the same chip, `2π/flutes` behind the one before.
    pub tool_ed: Vec<f64>,
}

/// The name of a step, as the report gives it: `up` or `down`.
pub fn step_name(s: Step) -> &'static str {
    match s {
        Step::Up => "up",
        Step::Down => "down",
    }
}

/// The name of a cut, as the report gives it: `down` or `up`.
pub fn cut_name(c: Cut) -> &'static str {
    match c {
        Cut::Down => "down",
        Cut::Up => "up",
    }
}

impl Study {
    /// Computes the case of the inclination `angle_deg` (degrees) with
    /// `pick_feed` (mm), `step` and `cut`, and adds it. An engagement no
    /// chip can be computed from is an error saying which case.
    pub fn add(&mut self, angle_deg: f64, pick_feed: f64, step: Step, cut: Cut) -> Result<(), Error> {
        let e = Engagement {
            cutter: self.cutter,
            flutes: self.flutes,
            helix: self.helix_deg.to_radians(),
            angle: angle_deg.to_radians(),
            depth: self.depth,
            pick_feed,
            feed_per_tooth: self.feed_per_tooth,
            step,
            cut,
        };
        let chip = Chip::new(&e).map_err(|err| {
            Error::new(
                err.kind,
                format!("at {angle_deg}° with a pick feed of {pick_feed} mm, step {}: {err}", step_name(step)),
            )
        })?;
        let sweep = sweep(&chip, self.rotation_steps);
        let tool_ed = tool_ed(&chip, &sweep, self.flutes);
        self.cases.push(Case { angle_deg, pick_feed, step, cut, volume: chip.volume(), sweep, tool_ed });
        Ok(())
    }

    /// The table of the cases: the study's settings, then per case its
    /// largest area, `E_d` and torque, engaged range, chip volume and the
    /// largest torque of every flute together.
    pub fn table(&self) -> String {
        let kc = self.kc;
        let mut out = format!(
            "tool {}, {} flutes, helix {}°; depth {} mm, feed per tooth {} mm; torque T = {} N/mm² × E_d\n",
            self.cutter, self.flutes, self.helix_deg, self.depth, self.feed_per_tooth, kc
        );
        out += "angle  step  cut   pick feed  A max      E_d max    T max     engaged θ          chip volume  T tool max\n";
        out += "deg               mm         mm²        mm³        N·mm      deg                mm³          N·mm\n";
        out += "                             (one tooth's, but the last: every flute together)\n";
        let mut sliver = false;
        for c in &self.cases {
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
                kc * c.sweep.ed_max,
                c.volume,
                kc * c.tool_ed_max()
            );
        }
        if sliver {
            out += "* the lowest part of the tip, narrower than the feed per tooth, is never covered by the\n  \
                    tooth before: a sliver of it is cut at every angle (the charts show the real chip)\n";
        }
        out
    }

    /// The cases as JSON: one case as an object (its settings, and per
    /// rotation angle its area, `L_G`, `E_d` and torque, ...), several as
    /// `{"cases": [...]}`.
    pub fn to_json(&self) -> Value {
        let mut objects: Vec<Value> = self.cases.iter().map(|c| self.case_json(c)).collect();
        if objects.len() == 1 {
            objects.remove(0)
        } else {
            json!({ "cases": objects })
        }
    }

    /// The JSON object of one case.
    fn case_json(&self, c: &Case) -> Value {
        let (s, kc) = (&c.sweep, self.kc);
        json!({
            "tool": self.cutter.to_string(),
            "inclination_deg": c.angle_deg,
            "step": step_name(c.step),
            "cut": cut_name(c.cut),
            "flutes": self.flutes,
            "helix_deg": self.helix_deg,
            "depth_mm": self.depth,
            "feed_per_tooth_mm": self.feed_per_tooth,
            "kc_n_mm2": kc,
            "pick_feed_mm": c.pick_feed,
            "angles_deg": degrees(&s.theta),
            "area_mm2": s.sections.iter().map(|x| x.area).collect::<Vec<_>>(),
            "lg_mm": s.sections.iter().map(|x| x.lg).collect::<Vec<_>>(),
            "ed_mm3": s.sections.iter().map(|x| x.ed).collect::<Vec<_>>(),
            "torque_n_mm": s.sections.iter().map(|x| kc * x.ed).collect::<Vec<_>>(),
            "area_max_mm2": s.area_max,
            "ed_max_mm3": s.ed_max,
            "torque_max_n_mm": kc * s.ed_max,
            "tool_torque_n_mm": c.tool_ed.iter().map(|e| kc * e).collect::<Vec<_>>(),
            "tool_torque_max_n_mm": kc * c.tool_ed_max(),
            "engaged_deg": s.engaged.map(|(a, b)| degrees(&[a, b])),
            "chip_volume_mm3": c.volume,
        })
    }

    /// Every rotation angle of every case as CSV, a header line first.
    pub fn csv(&self) -> String {
        let mut out = String::from("angle_deg,step,cut,pick_feed_mm,theta_deg,area_mm2,lg_mm,ed_mm3,torque_n_mm\n");
        for c in &self.cases {
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
                    self.kc * x.ed
                );
            }
        }
        out
    }
}

impl Case {
    /// The largest `E_d` of every flute together, mm³.
    pub fn tool_ed_max(&self) -> f64 {
        self.tool_ed.iter().copied().fold(0.0, f64::max)
    }

    /// The rotation angle of the largest area, degrees.
    pub fn peak_deg(&self) -> f64 {
        let s = &self.sweep;
        let k = (0..s.sections.len()).max_by(|&a, &b| s.sections[a].area.total_cmp(&s.sections[b].area));
        k.map_or(0.0, |k| s.theta[k].to_degrees())
    }

    /// The rotation angles (degrees) and sections, in order, over the turn
    /// about the largest area, that area's angle taken within half a turn
    /// of `centre`: each case drawn as one curve, the cases side by side.
    pub fn around_peak(&self, centre: f64) -> Vec<(f64, &Section)> {
        let p = self.peak_deg();
        let p = centre + (p - centre + 180.0).rem_euclid(360.0) - 180.0;
        let mut points: Vec<(f64, &Section)> = self
            .sweep
            .theta
            .iter()
            .zip(&self.sweep.sections)
            .map(|(t, v)| (p + (t.to_degrees() - p + 180.0).rem_euclid(360.0) - 180.0, v))
            .collect();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        points
    }
}

/// Where to draw the cases' rotation angles, degrees: about the circular
/// mean of the angles of their largest areas (`centre`), from 5° before the
/// first angle where a case's area reaches 1 % of its largest to 5° after
/// the last (`lo`, `hi`); `(centre, lo, hi)`.
pub fn window(cases: &[&Case]) -> (f64, f64, f64) {
    let (sin, cos) = cases.iter().fold((0.0, 0.0), |(s, c), x| {
        let p = x.peak_deg().to_radians();
        (s + p.sin(), c + p.cos())
    });
    // In [0°, 360°), as the table and the JSON give the angles.
    let centre = sin.atan2(cos).to_degrees().rem_euclid(360.0);
    let (mut lo, mut hi) = (f64::MAX, f64::MIN);
    for x in cases {
        for (t, v) in x.around_peak(centre) {
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

/// The warning where the passes at the inclination `angle_deg` (degrees)
/// `pick_feed` apart leave a cusp as tall as the stock `depth`: a strip of
/// it is left uncut between them.
pub fn uncut_stock(cutter: &Cutter, angle_deg: f64, pick_feed: f64, depth: f64) -> Option<String> {
    let s = scallop::cusp(cutter, angle_deg.to_radians(), pick_feed).ok()?;
    (s.cusp >= depth).then(|| {
        format!(
            "at {angle_deg}° a pick feed of {pick_feed:.4} mm leaves a cusp of {:.4} mm, not less than the depth of \
             {depth} mm: the passes leave stock between them uncut",
            s.cusp
        )
    })
}

/// Angles in degrees, rounded to 1e-9° (no `127.00000000000001`).
fn degrees(v: &[f64]) -> Vec<f64> {
    v.iter().map(|t| (t.to_degrees() * 1e9).round() / 1e9).collect()
}

/// `E_d` of all `flutes` teeth at each angle of `sweep` (one revolution in
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ErrorKind;

    fn study(flutes: u32, rotation_steps: usize) -> Study {
        Study {
            cutter: "ball:10".parse().unwrap(),
            flutes,
            helix_deg: 30.0,
            depth: 0.5,
            feed_per_tooth: 0.1,
            kc: 3500.0,
            rotation_steps,
            cases: Vec::new(),
        }
    }

    #[test]
    fn every_flute_together_is_the_tooth_repeated_a_pitch_behind() {
        // 3 flutes: 90 steps hold the pitch, 100 do not (computed).
        for steps in [90, 100] {
            let mut s = study(3, steps);
            s.add(30.0, 0.5, Step::Down, Cut::Down).unwrap();
            let c = &s.cases[0];
            assert_eq!(c.tool_ed.len(), steps);
            assert!(c.tool_ed_max() >= c.sweep.ed_max - 1e-12, "{steps}");
            let sum: f64 = c.tool_ed.iter().sum();
            let one: f64 = c.sweep.sections.iter().map(|x| x.ed).sum();
            assert!((sum - 3.0 * one).abs() < 0.02 * 3.0 * one, "{steps}: {sum} {one}");
        }
    }

    #[test]
    fn the_table_and_csv_name_each_case_and_a_bad_case_says_which() {
        let mut s = study(2, 72);
        s.add(30.0, 0.5, Step::Up, Cut::Up).unwrap();
        let table = s.table();
        assert!(table.starts_with("tool ball:10, 2 flutes, helix 30°; depth 0.5 mm"), "{table}");
        assert!(table.lines().nth(4).unwrap().starts_with(" 30.0  up    up       0.5000"), "{table}");
        let csv = s.csv();
        assert_eq!(csv.lines().count(), 73);
        assert!(csv.lines().nth(1).unwrap().starts_with("30,up,up,0.5,"), "{csv}");
        let c = &s.cases[0];
        let (centre, lo, hi) = window(&[c]);
        assert!(lo < centre && centre < hi && (0.0..360.0).contains(&centre), "{centre} {lo} {hi}");
        let v = s.to_json();
        assert_eq!(v["step"], "up");
        assert_eq!(v["angles_deg"].as_array().unwrap().len(), 72);
        let a = &v["angles_deg"];
        assert_eq!(a[1].as_f64().unwrap() - a[0].as_f64().unwrap(), 5.0, "{a}");
        let e = s.add(30.0, 20.0, Step::Down, Cut::Down).unwrap_err();
        assert_eq!(e.kind, ErrorKind::NoOverlap);
        assert!(e.to_string().starts_with("at 30° with a pick feed of 20 mm, step down: "), "{e}");
        s.add(60.0, 0.5, Step::Up, Cut::Up).unwrap();
        assert_eq!(s.to_json()["cases"].as_array().unwrap().len(), 2);
    }

    #[test]
    fn a_cusp_as_tall_as_the_stock_leaves_it_uncut() {
        let ball: Cutter = "ball:10".parse().unwrap();
        assert_eq!(uncut_stock(&ball, 30.0, 0.5, 0.5), None);
        let w = uncut_stock(&ball, 0.0, 6.0, 0.5).unwrap();
        assert!(w.starts_with("at 0° a pick feed of 6.0000 mm leaves a cusp of "), "{w}");
    }
}
