//! What a lathe's nose cuts, with tool nose radius compensation and
//! without: the nose swept along the run's nose centre path
//! (`nose_centre_path`), measured along the contour's normal at chosen
//! points. Without G41/G42 a program written to the imaginary tip is cut
//! off the contour by the nose's geometry (derived in each test's comment
//! from the tip vectors of FANUC Series 0i-TF Plus Operator's Manual
//! (B-64604EN), lathe system, "Imaginary tool nose direction"); with them
//! the contour exactly. X is a radius (the tool's distance from the
//! spindle axis).

use std::collections::BTreeMap;

use kezuri_nc::interp::{nose_centre_path, Nose, Settings, TipNumbers};
use kezuri_nc::Dialect;

mod common;

use common::nose::*;

#[test]
fn lathe_nose_uncompensated_error_on_a_taper_and_an_arc_is_its_geometry() {
    // The OD profile run without G41/G42, tip 3, R 0.8: the imaginary tip
    // follows the contour, the nose centre runs (R, R) = (0.8, 0.8) off
    // it. Where the contour's normal toward the tool is n, the nose
    // touches with its point centre − R·n, so a straight line is cut
    // (0.8, 0.8)·n − R beyond itself:
    // - the OD (n = +X) and the faces (n = +Z): 0.8 − 0.8 = 0;
    // - the 45° chamfer (n = (1, 1)/√2): 0.8·√2 − 0.8 = R·(√2 − 1) =
    //   0.331371 normal to it, material left standing; R·(√2 − 1)·√2 =
    //   2·R·(1 − 1/√2) = 0.468629 in X (a radius; twice that on the
    //   diameter).
    // An arc of radius ρ round O is cut by the nose centres on the arc of
    // radius ρ round O + w, w = (0.8, 0.8): the convex round's surface is
    // the circle of radius ρ − R round O + w; along the ray from O in
    // direction n it lies at s = n·w + √((n·w)² − |w|² + (ρ − R)²), the
    // error s − ρ (at 45° n·w = R·√2, |w|² = 2R², so s − ρ = R·(√2 − 1)
    // again: the nose touches with the same point). The concave fillet
    // (material outside, tool toward O: n = −m for the ray direction m
    // from O) is bounded by the circle of radius ρ + R round O + w, at
    // P + t·n with t = ρ + n·w − √((n·w)² − |w|² + (ρ + R)²).
    let r = 0.8;
    let settings = lathe(1, Nose { radius: r, tip: 3 });
    let out = run(&od("G40", "G40", 1), &settings);
    assert!(out.programmed.is_none(), "nothing compensated");
    let centre = nose_centre_path(&out.toolpath, &settings.noses, TipNumbers::Fanuc);
    let c = centres(&centre, 0.0005);
    let w = (r, r);
    let tol = 2e-6;
    // The ODs and faces, away from their ends.
    for (p, n) in
        [((6.0, -6.0), (1.0, 0.0)), ((14.0, -17.5), (1.0, 0.0)), ((2.0, 0.0), (0.0, 1.0)), ((10.5, -13.0), (0.0, 1.0))]
    {
        let e = cut_surface(&c, r, p, n);
        assert!(e.abs() < tol, "{p:?}: {e}");
    }
    // The chamfer at a quarter, half and three quarters of its length.
    for t in [0.25, 0.5, 0.75] {
        let p = (4.0 + 2.0 * t, -2.0 * t);
        let e = cut_surface(&c, r, p, dir(45.0));
        assert!((e - r * (S2 - 1.0)).abs() < tol, "chamfer at {p:?}: {e}, want {}", r * (S2 - 1.0));
    }
    let in_x = cut_surface(&c, r, (5.0, -1.0), (1.0, 0.0));
    assert!((in_x - 2.0 * r * (1.0 - 1.0 / S2)).abs() < tol, "in X: {in_x}");
    // The convex round R2 round X12 Z−15, between +Z (0°... 90° from +X)
    // and +X: at 30°, 45° and 60° from +X.
    let (o, rho) = ((12.0, -15.0), 2.0);
    for deg in [30.0, 45.0, 60.0] {
        let n = dir(deg);
        let nw = n.0 * w.0 + n.1 * w.1;
        let s = nw + (nw * nw - 2.0 * r * r + (rho - r) * (rho - r)).sqrt();
        let want = s - rho;
        let p = (o.0 + rho * n.0, o.1 + rho * n.1);
        let e = cut_surface(&c, r, p, n);
        assert!((e - want).abs() < tol, "round at {deg}°: {e}, want {want}");
        if deg == 45.0 {
            assert!((want - r * (S2 - 1.0)).abs() < 1e-12);
        }
    }
    // The concave fillet R3 round X9 Z−10, from −X to −Z: the ray from O
    // at 225°, 210° and 240° from +X (the tool side n = −m).
    let (o, rho) = ((9.0, -10.0), 3.0);
    for deg in [210.0, 225.0, 240.0] {
        let m = dir(deg);
        let n = (-m.0, -m.1);
        let nw = n.0 * w.0 + n.1 * w.1;
        let want = rho + nw - (nw * nw - 2.0 * r * r + (rho + r) * (rho + r)).sqrt();
        let p = (o.0 + rho * m.0, o.1 + rho * m.1);
        let e = cut_surface(&c, r, p, n);
        assert!((e - want).abs() < tol, "fillet at {deg}°: {e}, want {want}");
        if deg == 225.0 {
            assert!((want - r * (S2 - 1.0)).abs() < 1e-12);
        }
    }
}

#[test]
fn lathe_nose_tip_8_uncompensated_cuts_into_a_chamfer() {
    // Tip 8 is set on the bottom of the nose with Z at its centre: centre
    // = tip + (R, 0). On the 45° chamfer the nose reaches (R, 0)·n − R =
    // R/√2 − R = −R·(1 − 1/√2) = −0.234315: into the part.
    let r = 0.8;
    let settings = lathe(4, Nose { radius: r, tip: 8 });
    let out = run(&od("G40", "G40", 4), &settings);
    let c = centres(&nose_centre_path(&out.toolpath, &settings.noses, TipNumbers::Fanuc), 0.0005);
    let e = cut_surface(&c, r, (5.0, -1.0), dir(45.0));
    assert!((e + r * (1.0 - 1.0 / S2)).abs() < 2e-6, "{e}");
}

#[test]
fn lathe_nose_compensated_cut_is_the_contour() {
    // With G42 (OD, tips 3 and 8) and G41 (bore, tip 2) the nose centre
    // runs R off the contour: the swept nose touches every point of it and
    // cuts nowhere beyond, on the lines and the arcs alike.
    let od_points: Vec<((f64, f64), (f64, f64))> = vec![
        ((2.0, 0.0), (0.0, 1.0)),
        ((5.0, -1.0), dir(45.0)),
        ((6.0, -6.0), (1.0, 0.0)),
        ((9.0 - 3.0 * S2 / 2.0, -10.0 - 3.0 * S2 / 2.0), dir(45.0)),
        ((10.5, -13.0), (0.0, 1.0)),
        ((12.0 + 2.0 * dir(30.0).0, -15.0 + 2.0 * dir(30.0).1), dir(30.0)),
        ((14.0, -17.5), (1.0, 0.0)),
    ];
    for (tool, tip) in [(1, 3), (4, 8)] {
        let settings = lathe(tool, Nose { radius: 0.8, tip });
        let out = run(&od("G42", "G40", tool), &settings);
        let c = centres(&nose_centre_path(&out.toolpath, &settings.noses, TipNumbers::Fanuc), 0.0005);
        for &(p, n) in &od_points {
            let e = cut_surface(&c, 0.8, p, n);
            assert!(e.abs() < 2e-6, "tip {tip} at {p:?}: {e}");
        }
    }
    // The bore: the tool side is −X on the bores, +Z on the faces, (−X,
    // +Z)/√2 on the chamfer, toward the fillet's centre, away from the
    // round's.
    let settings = lathe(2, Nose { radius: 0.4, tip: 2 });
    let out = run(&bore("G41"), &settings);
    let c = centres(&nose_centre_path(&out.toolpath, &settings.noses, TipNumbers::Fanuc), 0.0005);
    // The fillet spans +X to −Z from its centre X5 Z−10, the round +Z to
    // −X from X4 Z−15: their middles.
    let (m, k) = (dir(-45.0), dir(135.0));
    for (p, n) in [
        ((12.0, 0.0), (0.0, 1.0)),
        ((9.0, -1.0), (-1.0 / S2, 1.0 / S2)),
        ((8.0, -6.0), (-1.0, 0.0)),
        ((5.0 + 3.0 * m.0, -10.0 + 3.0 * m.1), (-m.0, -m.1)),
        ((4.5, -13.0), (0.0, 1.0)),
        ((4.0 + 2.0 * k.0, -15.0 + 2.0 * k.1), k),
        ((2.0, -17.5), (-1.0, 0.0)),
    ] {
        let e = cut_surface(&c, 0.4, p, n);
        assert!(e.abs() < 2e-6, "bore at {p:?}: {e}");
    }
}

/// The finishing pass of a real program that leaves the nose to the
/// control (a Fusion 360 Fanuc lathe post: `G42` on the first profile
/// move, `G40` on the retract); MaestroFusion360/easy_gcode_plot,
/// tests/fixtures/turning/compensation_control_on.nc (MIT), its lines 64–94.
const FUSION_FINISH: &str = "G21
N4 T0202
G99 G18
G54
M8
G97 S227 M3
G0 X128.27 Z25.4
G50 S5000
G96 S91 M3
G0 Z-1.267
X14.616
G1 X13.883 F0.127
G42 X14. Z-3.24
X16. Z-4.24
Z-8.44
X18.
X20. Z-9.44
Z-28.393
X30. Z-36.94
X30.046 Z-40.963
X36. Z-43.94
Z-65.94
X41.
Z-85.94
X56. Z-93.44
X98.
X100. Z-94.44
Z-111.06
G40 X102.874 Z-112.697
X103.316
G0 X128.27
Z25.4
M30
";

#[test]
fn lathe_nose_a_cam_finishing_pass_with_g42_cuts_its_contour() {
    // Tool 2 with a 0.4 nose, tip 3 (an OD finishing tool). Every
    // programmed move between the G42 and the G40 block is cut exactly:
    // the swept nose touches its middle (tool side: right of travel,
    // (X, Z) = (−dZ, dX)) and cuts nothing beyond it.
    let settings = Settings {
        dialect: Dialect::FanucLathe,
        noses: BTreeMap::from([(2, Nose { radius: 0.4, tip: 3 })]),
        ..Settings::default()
    };
    let out = run(FUSION_FINISH, &settings);
    let programmed = out.programmed.as_ref().expect("compensated");
    let line = |word: &str| FUSION_FINISH.lines().position(|l| l.starts_with(word)).expect("in the program") as u32 + 1;
    let (on, off) = (line("G42"), line("G40"));
    let c = centres(&nose_centre_path(&out.toolpath, &settings.noses, TipNumbers::Fanuc), 0.0005);
    let mut checked = 0;
    for m in programmed.moves.iter().filter(|m| m.line > on && m.line < off) {
        let (dx, dz) = (m.end.x - m.start.x, m.end.z - m.start.z);
        let len = dx.hypot(dz);
        let p = ((m.start.x + m.end.x) / 2.0, (m.start.z + m.end.z) / 2.0);
        let e = cut_surface(&c, 0.4, p, (-dz / len, dx / len));
        assert!(e.abs() < 2e-6, "line {}: {e}", m.line);
        checked += 1;
    }
    assert_eq!(checked, 15);
}

#[test]
fn lathe_nose_the_cam_pass_without_g42_is_off_by_each_line_s_geometry() {
    // The same pass with G42 and G40 taken out: the imaginary tip (tip 3,
    // R 0.4) follows the contour, the nose centre is (0.4, 0.4) off it,
    // and each line (1 mm or longer: its neighbours' noses do not reach
    // its middle) is cut (0.4, 0.4)·n − 0.4 beyond itself: 0 on the
    // diameters and faces, 0.4·(√2 − 1) = 0.165685 on the five 45° lines
    // (the chamfers X14 to X16, X18 to X20, X98 to X100, and X30.046 to
    // X36, X41 to X56), 0.4·(sin a + cos a − 1) on a taper at a to the
    // axis.
    let r = 0.4;
    let text = FUSION_FINISH.replace("G42 ", "").replace("G40 ", "");
    let settings = Settings {
        dialect: Dialect::FanucLathe,
        noses: BTreeMap::from([(2, Nose { radius: r, tip: 3 })]),
        ..Settings::default()
    };
    let out = run(&text, &settings);
    let c = centres(&nose_centre_path(&out.toolpath, &settings.noses, TipNumbers::Fanuc), 0.0005);
    let line = |word: &str| FUSION_FINISH.lines().position(|l| l.starts_with(word)).expect("in the program") as u32 + 1;
    let (on, off) = (line("G42"), line("G40"));
    let mut chamfers = 0;
    for m in out.toolpath.moves.iter().filter(|m| m.line > on && m.line < off) {
        let (dx, dz) = (m.end.x - m.start.x, m.end.z - m.start.z);
        let len = dx.hypot(dz);
        if len < 1.0 {
            continue;
        }
        let n = (-dz / len, dx / len);
        let want = r * (n.0 + n.1) - r;
        let p = ((m.start.x + m.end.x) / 2.0, (m.start.z + m.end.z) / 2.0);
        let e = cut_surface(&c, r, p, n);
        assert!((e - want).abs() < 2e-6, "line {}: {e}, want {want}", m.line);
        if (dx.abs() - dz.abs()).abs() < 1e-9 {
            assert!((e - r * (S2 - 1.0)).abs() < 2e-6);
            chamfers += 1;
        }
    }
    assert_eq!(chamfers, 5);
}
