//! The charts of an engagement study (`kezuri engage`), as one SVG.

use kezuri_cam::engage::report::{cut_name, step_name, window, Case, Study};
use kezuri_cam::engage::{Cut, Section, Step};

use crate::chart::{line_chart, stack, Line};

/// The charts of `study`, its cutter named `tool`: the area per rotation
/// angle of each step and cut (a line per inclination), `E_d` per rotation
/// angle where there is one inclination, and the largest area and `E_d`
/// per inclination where there are several.
pub fn charts(study: &Study, tool: &str) -> String {
    let (cases, kc) = (&study.cases, study.kc);
    let mut combos: Vec<(Step, Cut)> = Vec::new();
    for c in cases {
        if !combos.contains(&(c.step, c.cut)) {
            combos.push((c.step, c.cut));
        }
    }
    let several = cases.iter().any(|c| c.angle_deg != cases[0].angle_deg);
    let combo_name = |s: Step, c: Cut| format!("{tool}, step-{}, {}-cut", step_name(s), cut_name(c));
    let per_theta = |s: Step, c: Cut, value: &dyn Fn(&Section) -> f64| -> Vec<Line> {
        let these: Vec<&Case> = cases.iter().filter(|x| x.step == s && x.cut == c).collect();
        per_rotation_angle(&these, value)
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

/// A line per case of its `value` per rotation angle, on an axis within one
/// turn, 0 to 360°: the window where the chips are ([`window`]) where it
/// lies within it, else the whole turn (each case's points in [0°, 360°),
/// the turn closed at 360°).
fn per_rotation_angle(these: &[&Case], value: &dyn Fn(&Section) -> f64) -> Vec<Line> {
    let (centre, lo, hi) = window(these);
    let within = lo >= 0.0 && hi <= 360.0;
    these
        .iter()
        .map(|x| {
            let label = format!("α {}°, Pf {:.3} mm", x.angle_deg, x.pick_feed);
            let mut points: Vec<(f64, f64)> = if within {
                x.around_peak(centre)
                    .into_iter()
                    .filter(|(t, _)| (lo..=hi).contains(t))
                    .map(|(t, v)| (t, value(v)))
                    .collect()
            } else {
                x.around_peak(centre).into_iter().map(|(t, v)| (t.rem_euclid(360.0), value(v))).collect()
            };
            if !within {
                points.sort_by(|a, b| a.0.total_cmp(&b.0));
                if let Some(&(t, v)) = points.first().filter(|p| p.0 < 1e-9) {
                    points.push((t + 360.0, v));
                }
            }
            Line { label, points }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn study(angles: &[f64]) -> Study {
        let mut s = Study {
            cutter: "ball:10".parse().unwrap(),
            flutes: 2,
            helix_deg: 30.0,
            depth: 0.5,
            feed_per_tooth: 0.1,
            kc: 3500.0,
            rotation_steps: 72,
            cases: Vec::new(),
        };
        for &a in angles {
            s.add(a, 0.5, Step::Down, Cut::Down).unwrap();
        }
        s
    }

    #[test]
    fn one_inclination_draws_area_and_ed_several_draw_the_largest_per_inclination() {
        let one = charts(&study(&[30.0]), "ball:10");
        assert!(one.contains("Chip area per rotation angle (ball:10, step-down, down-cut)"));
        assert!(one.contains("E_d = A·L_G per rotation angle (ball:10, step-down, down-cut)"));
        assert!(!one.contains("per inclination"));
        let two = charts(&study(&[30.0, 60.0]), "ball:10");
        assert!(two.contains("Largest chip area per inclination, ball:10"));
        assert!(two.contains("Largest E_d per inclination, ball:10; torque ≈ 3500 N/mm² × E_d"));
        assert!(!two.contains("E_d = A·L_G per rotation angle"));
    }

    #[test]
    fn the_rotation_angle_stays_within_one_turn() {
        // The demo's oval end mill stepping down: its chips peak from 165°
        // to 50° past a turn, drawn before over 60° … 460°.
        let mut s = Study {
            cutter: "oval:16,24".parse().unwrap(),
            flutes: 2,
            helix_deg: 30.0,
            depth: 0.8,
            feed_per_tooth: 0.16,
            kc: 3500.0,
            rotation_steps: 360,
            cases: Vec::new(),
        };
        for (a, pf) in [(0.0, 0.462), (15.0, 0.484), (30.0, 0.558), (45.0, 0.718), (60.0, 1.053), (75.0, 1.739)] {
            s.add(a, pf, Step::Down, Cut::Down).unwrap();
        }
        let these: Vec<&Case> = s.cases.iter().collect();
        let lines = per_rotation_angle(&these, &|v| v.area);
        let (lo, hi) =
            lines.iter().flat_map(|l| &l.points).fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
        assert!(lo >= 0.0 && hi <= 360.0, "rotation angles from {lo}° to {hi}°");
        // Every case's largest chip is still on its line.
        for (line, case) in lines.iter().zip(&s.cases) {
            let most = line.points.iter().map(|p| p.1).fold(0.0, f64::max);
            assert!((most - case.sweep.area_max).abs() < 1e-12, "{}: {most} of {}", line.label, case.sweep.area_max);
        }
        // One inclination's window within the turn is kept as it was.
        let one = study(&[30.0]);
        let these: Vec<&Case> = one.cases.iter().collect();
        let (_, lo, hi) = window(&these);
        let line = &per_rotation_angle(&these, &|v| v.area)[0];
        assert!(line.points.iter().all(|p| (lo..=hi).contains(&p.0)));
    }
}
