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
        let (centre, lo, hi) = window(&these);
        these
            .iter()
            .map(|x| Line {
                label: format!("α {}°, Pf {:.3} mm", x.angle_deg, x.pick_feed),
                points: x
                    .around_peak(centre)
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
}
