//! Tool nose radius compensation on a lathe (G40/G41/G42 with the nose
//! radius and imaginary tip direction of the tool in use), end to end.
//!
//! Conventions (FANUC Series 0i-TF Plus Operator's Manual (B-64604EN),
//! lathe system, "Tool nose radius compensation"; Haas Lathe Operator's
//! Manual, "Tool Nose Compensation" and "Imaginary Tool Tip and
//! Direction"):
//! - the ZX plane (G18) is seen from +Y: +Z to the right, +X up; G41 puts
//!   the nose left of the direction of travel, G42 right. An OD tool
//!   turning toward the chuck (−Z) above the work is on the right: G42; a
//!   boring bar below the bore wall on the left: G41.
//! - the program is written to the imaginary tool tip; the nose centre is
//!   off it by the tip vector: tip 3 (OD) centre = tip + (R, R) in (X, Z),
//!   tip 2 (boring) centre = tip + (−R, R), tip 8 centre = tip + (R, 0).
//! - with G41/G42 the nose centre runs on the programmed contour offset by
//!   R (type C corners: the offset lines' intersections; tangent joints
//!   the offset point), and the machine puts the imaginary tip at centre −
//!   (tip → centre).
//!
//! Every expected point is worked out in the comment above it before the
//! run was looked at. X is a radius throughout (the tool's distance from
//! the spindle axis).

use std::collections::BTreeMap;

use kezuri_geom::{MoveKind, Toolpath};
use kezuri_nc::interp::{nose_centre_path, GCodeSystem, Lathe, Nose, Outcome, Settings, TipNumbers, XMode};
use kezuri_nc::Dialect;

mod common;

/// √2.
const S2: f64 = std::f64::consts::SQRT_2;

/// A lathe with X read as a radius, the plain Fanuc dialect (a lathe's
/// codes, system A: `G98` feed per minute, `T0101` tool 1 with offset 1),
/// `nose` as tool `tool`'s.
fn lathe(tool: u32, nose: Nose) -> Settings {
    Settings {
        lathe: Some(Lathe { x: XMode::Radius, system: GCodeSystem::A }),
        noses: BTreeMap::from([(tool, nose)]),
        ..Settings::default()
    }
}

fn run(text: &str, settings: &Settings) -> Outcome {
    common::run("t.nc", text, settings).completed()
}

/// The (X, Z) end of each move.
fn ends(path: &Toolpath) -> Vec<(f64, f64)> {
    path.moves.iter().map(|m| (m.end.x, m.end.z)).collect()
}

fn assert_ends(what: &str, path: &Toolpath, want: &[(f64, f64)]) {
    let got = ends(path);
    assert_eq!(got.len(), want.len(), "{what}: {got:?}");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert!((g.0 - w.0).abs() < 1e-6 && (g.1 - w.1).abs() < 1e-6, "{what}, move {k}: (X, Z) {g:?}, want {w:?}");
    }
}

/// An OD profile toward the chuck, X a radius: start-up down onto the end
/// face (−Z), the face up to X4 (+X), a 45° chamfer to X6 Z−2, the OD X6
/// to Z−10, a concave fillet R3 to the shoulder X9 Z−13 (G02, centre X9
/// Z−10), the shoulder face up to X12, a convex round R2 (G03, centre X12
/// Z−15) onto the OD X14, the OD to Z−20, cancel up to X18.
fn od(comp: &str, cancel: &str, tool: u32) -> String {
    format!(
        "G18 G21 G40 G98
T{tool:02}{tool:02}
G00 X20. Z10.
G00 X0. Z3.
{comp} G01 Z0. F100.
X4.
X6. Z-2.
Z-10.
G02 X9. Z-13. I3. K0.
G01 X12.
G03 X14. Z-15. I0. K-2.
G01 Z-20.
{cancel} G00 X18.
M30
"
    )
}

/// The OD profile's nose centre points with G42 and R = 0.8 (they do not
/// depend on the tip: the offset is the nose's). Right of travel in (Z, X)
/// is (dX, −dZ): +X on the OD (−Z), +Z on the faces (+X), (+X, +Z)/√2 on
/// the chamfer (direction (−Z, +X)/√2).
/// - start-up (−Z) then face (+X): an inside corner (the path turns right,
///   toward the nose); the offset lines X = 0.8 and Z = 0.8 meet at
///   (X0.8, Z0.8).
/// - face then chamfer at X4 Z0: outside, obtuse; the chamfer's line is
///   Z + X = 4, offset Z + X = 4 + 0.8·√2; with Z = 0.8: X = 4 + 0.8·(√2 − 1).
/// - chamfer then OD at X6 Z−2: outside, obtuse; X = 6.8 on Z + X = 4 +
///   0.8·√2: Z = −2.8 + 0.8·√2.
/// - OD then fillet: tangent; the OD's offset end X6.8 Z−10. The fillet is
///   concave (the nose inside it): centre path radius 3 − 0.8 round X9
///   Z−10, ending tangent to the shoulder face at X9 Z−12.2.
/// - shoulder face to X12 at Z−12.2; the round is convex: radius 2 + 0.8
///   round X12 Z−15, ending at X14.8 Z−15.
/// - the OD at X14.8 meets the cancel move's offset (up, +X: Z = −20 +
///   0.8) at X14.8 Z−19.2 (inside corner); the cancel move then ends on
///   the programmed point X18 Z−20.
const OD_CENTRE: [(f64, f64); 9] = [
    (0.8, 0.8),
    (4.0 + 0.8 * (S2 - 1.0), 0.8),
    (6.8, -2.8 + 0.8 * S2),
    (6.8, -10.0),
    (9.0, -12.2),
    (12.0, -12.2),
    (14.8, -15.0),
    (14.8, -19.2),
    (18.0, -20.0),
];

/// The first two moves, before compensation: the imaginary tip on the
/// programmed points.
const OD_APPROACH: [(f64, f64); 2] = [(20.0, 10.0), (0.0, 3.0)];

/// `centre` points moved by the tip vector `v` (X, Z), the last (the
/// cancel move's end, a programmed point) left.
fn tips(centre: &[(f64, f64)], v: (f64, f64)) -> Vec<(f64, f64)> {
    let n = centre.len();
    centre.iter().enumerate().map(|(k, &(x, z))| if k + 1 < n { (x + v.0, z + v.1) } else { (x, z) }).collect()
}

#[test]
fn lathe_nose_tip_3_od_with_g42_keeps_the_tip_on_the_diameters_and_faces() {
    // Tip 3, R 0.8: tip = centre + (−0.8, −0.8). On the ODs (X6, X14) the
    // tip runs on the programmed X, on the faces on the programmed Z: the
    // nose touches those with the points the tool was set on. On the
    // chamfer the tip is off the line: X4 + 0.8·(√2 − 1) − 0.8 = 3.531371
    // at Z0, and X6 at Z −2.8 + 0.8·√2 − 0.8 = −2.468629.
    let settings = lathe(1, Nose { radius: 0.8, tip: 3 });
    let out = run(&od("G42", "G40", 1), &settings);
    let mut want = OD_APPROACH.to_vec();
    want.extend(tips(&OD_CENTRE, (-0.8, -0.8)));
    assert_ends("tip path", &out.toolpath, &want);
    assert_eq!(want[3], (4.0 + 0.8 * (S2 - 1.0) - 0.8, 0.0));
    // One continuous path: the start-up from the programmed X0 Z3, the
    // cancel move from the last tip point.
    for w in out.toolpath.moves.windows(2) {
        assert_eq!(w[1].start, w[0].end);
    }
    assert_eq!((out.toolpath.moves[2].start.x, out.toolpath.moves[2].start.z), (0.0, 3.0));
    // The nose centre path is the toolpath less the tip vector: the
    // centre points, and the approach 0.8 up and 0.8 toward +Z.
    let centre = nose_centre_path(&out.toolpath, &settings.noses, TipNumbers::Fanuc);
    let mut want = vec![(20.8, 10.8), (0.8, 3.8)];
    want.extend_from_slice(&OD_CENTRE[..8]);
    want.push((18.8, -19.2));
    assert_ends("centre path", &centre, &want);
    // The arcs keep their radii round centres moved with them: the fillet
    // 2.2 round X9 Z−10 (the tip's round X8.2 Z−10.8), the round 2.8.
    let arcs: Vec<_> = centre.moves.iter().filter_map(arc_of).collect();
    assert_eq!(arcs.len(), 2);
    for ((c, r), (wc, wr)) in arcs.iter().zip([((9.0, -10.0), 2.2), ((12.0, -15.0), 2.8)]) {
        assert!((c.0 - wc.0).abs() < 1e-9 && (c.1 - wc.1).abs() < 1e-9 && (r - wr).abs() < 1e-9, "{c:?} {r}");
    }
    // The programmed contour is kept, with G42 and G40 for a writer.
    let programmed = out.programmed.expect("compensated");
    assert_eq!(programmed.moves[4].end.x, 6.0);
    let kept: Vec<_> = programmed.kept.iter().map(|k| k.text.as_str()).collect();
    assert_eq!(kept, ["G42", "G40"]);
}

#[test]
fn lathe_nose_tip_8_od_with_g42_is_the_centre_less_r_in_x() {
    // Tip 8, R 0.8: tip = centre + (−0.8, 0). The same centre path; the
    // tip on the programmed ODs, but 0.8 off the faces in +Z (its Z is the
    // nose centre's): the end face at Z0.8, the shoulder at Z−12.2.
    let settings = lathe(4, Nose { radius: 0.8, tip: 8 });
    let out = run(&od("G42", "G40", 4), &settings);
    let mut want = OD_APPROACH.to_vec();
    want.extend(tips(&OD_CENTRE, (-0.8, 0.0)));
    assert_ends("tip path", &out.toolpath, &want);
    assert_eq!(want[5], (6.0, -10.0));
    assert_eq!(want[7], (11.2, -12.2));
}

/// A bore, X a radius, toward the chuck with a boring bar (G41, the nose
/// below the wall): start-up onto the front face (−Z) at X14, the face
/// down to X10 (−X), a 45° chamfer to X8 Z−2, the bore X8 to Z−10, a
/// concave fillet R3 (G03, centre X5 Z−10) down to the step X5 Z−13, the
/// step down to X4, a convex round R2 (G02, centre X4 Z−15) into the bore
/// X2, the bore to Z−20, cancel down to X0.5.
fn bore(comp: &str) -> String {
    format!(
        "G18 G21 G40 G98
T0202
G00 X14. Z3.
{comp} G01 Z0. F100.
X10.
X8. Z-2.
Z-10.
G03 X5. Z-13. I-3. K0.
G01 X4.
G02 X2. Z-15. I0. K-2.
G01 Z-20.
G40 G00 X0.5
M30
"
    )
}

#[test]
fn lathe_nose_tip_2_bore_with_g41() {
    // R 0.4. Left of travel in (Z, X) is (−dX, dZ): −X on the bore (−Z),
    // +Z on the faces (−X), (+Z, −X)/√2 on the chamfer (direction
    // (−Z, −X)/√2).
    // - start-up (−Z at X14) then face (−X): inside (the path turns left,
    //   toward the nose): X = 13.6 and Z = 0.4 meet at (X13.6, Z0.4).
    // - face then chamfer at X10 Z0: outside, obtuse; the chamfer's line
    //   X − Z = 10 offset by 0.4 toward (+Z, −X): X − Z = 10 − 0.4·√2;
    //   with Z = 0.4: X = 10.4 − 0.4·√2.
    // - chamfer then bore X8 at Z−2: outside, obtuse; X = 7.6 on that
    //   line: Z = −2.4 + 0.4·√2.
    // - bore then fillet: tangent at X7.6 Z−10; the fillet is concave
    //   (radius 3 − 0.4 round X5 Z−10), ending tangent to the step at X5
    //   Z−12.6; the step to X4 Z−12.6; the round is convex (2 + 0.4 round
    //   X4 Z−15), ending at X1.6 Z−15; the bore at X1.6 meets the cancel
    //   move's offset (down, −X: Z = −20 + 0.4) at X1.6 Z−19.6 (inside).
    let centre = [
        (13.6, 0.4),
        (10.4 - 0.4 * S2, 0.4),
        (7.6, -2.4 + 0.4 * S2),
        (7.6, -10.0),
        (5.0, -12.6),
        (4.0, -12.6),
        (1.6, -15.0),
        (1.6, -19.6),
        (0.5, -20.0),
    ];
    // Tip 2: tip = centre + (0.4, −0.4): on the bores (X8, X2) and the
    // faces (Z0, Z−13) the tip is on the programmed line.
    let settings = lathe(2, Nose { radius: 0.4, tip: 2 });
    let out = run(&bore("G41"), &settings);
    let mut want = vec![(14.0, 3.0)];
    want.extend(tips(&centre, (0.4, -0.4)));
    assert_ends("tip path", &out.toolpath, &want);
    assert_eq!(want[1], (14.0, 0.0));
    assert_eq!(want[4], (8.0, -10.4));
    assert_eq!(want[6], (4.4, -13.0));
}

#[test]
fn lathe_nose_sides_swapped_cut_the_other_side() {
    // G41 on the OD profile puts the nose below the OD (inside the work):
    // the same moves offset the other way. The start-up (−Z) then face (+X)
    // is then an outside corner (type A: the start-up ends on the face's
    // perpendicular vector, Z −0.8 at X0), and the OD's offset is X6 − 0.8:
    // the tip, (−0.8, −0.8) from the centre, is at X4.4 at the end of the
    // first OD.
    let settings = lathe(1, Nose { radius: 0.8, tip: 3 });
    let out = run(&od("G41", "G40", 1), &settings);
    let (x, z) = ends(&out.toolpath)[2];
    assert!((x - (0.0 - 0.8)).abs() < 1e-9 && (z - (-0.8 - 0.8)).abs() < 1e-9, "{x} {z}");
    let od_end = ends(&out.toolpath).iter().position(|&(_, z)| (z - (-10.0 - 0.8)).abs() < 1e-9);
    let k = od_end.expect("the first OD's end");
    assert!((out.toolpath.moves[k].end.x - 4.4).abs() < 1e-9);
}

/// The centre (X, Z) and radius of an arc move.
fn arc_of(m: &kezuri_geom::Move) -> Option<((f64, f64), f64)> {
    let MoveKind::Arc(a) = m.kind else { return None };
    Some(((a.center[0], a.center[2]), (m.end.x - a.center[0]).hypot(m.end.z - a.center[2])))
}

/// The nose centres along the cutting moves (feeds and arcs) of `path`,
/// every `step` mm and at each end.
fn centres(path: &Toolpath, step: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for m in &path.moves {
        let (a, b) = ((m.start.x, m.start.z), (m.end.x, m.end.z));
        match m.kind {
            MoveKind::Feed => {
                let n = ((b.0 - a.0).hypot(b.1 - a.1) / step).ceil().max(1.0) as usize;
                out.extend((0..=n).map(|k| {
                    let t = k as f64 / n as f64;
                    (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))
                }));
            }
            MoveKind::Arc(arc) => {
                let c = (arc.center[0], arc.center[2]);
                let r = (a.0 - c.0).hypot(a.1 - c.1);
                // Angles in (Z, X), counter-clockwise from +Z seen from +Y.
                let (t0, t1) = ((a.0 - c.0).atan2(a.1 - c.1), (b.0 - c.0).atan2(b.1 - c.1));
                let mut sweep = t1 - t0;
                if arc.ccw && sweep <= 0.0 {
                    sweep += std::f64::consts::TAU;
                }
                if !arc.ccw && sweep >= 0.0 {
                    sweep -= std::f64::consts::TAU;
                }
                let n = (r * sweep.abs() / step).ceil().max(1.0) as usize;
                out.extend((0..=n).map(|k| {
                    let t = t0 + sweep * k as f64 / n as f64;
                    (c.0 + r * t.sin(), c.1 + r * t.cos())
                }));
            }
            _ => {}
        }
    }
    out
}

/// Where the part's surface is along the line through the contour point
/// `p` (X, Z) in the unit direction `n` toward the tool: the signed
/// distance from `p` to the first point the swept nose (radius `r` round
/// `centres`) removed, coming from the material. Positive: material left
/// standing beyond the contour; negative: cut into it.
fn cut_surface(centres: &[(f64, f64)], r: f64, p: (f64, f64), n: (f64, f64)) -> f64 {
    let mut first = f64::INFINITY;
    for &c in centres {
        let d = (c.0 - p.0, c.1 - p.1);
        let along = d.0 * n.0 + d.1 * n.1;
        let across2 = d.0 * d.0 + d.1 * d.1 - along * along;
        if across2 < r * r {
            first = first.min(along - (r * r - across2).sqrt());
        }
    }
    first
}

/// Unit vector at `deg` degrees from +X toward +Z, as (X, Z).
fn dir(deg: f64) -> (f64, f64) {
    let a = deg.to_radians();
    (a.cos(), a.sin())
}

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

#[test]
fn lathe_nose_tip_outside_0_to_9_is_refused_at_g42() {
    let settings = lathe(1, Nose { radius: 0.8, tip: 12 });
    let ran = common::run("t.nc", &od("G42", "G40", 1), &settings);
    let e = ran.error().expect("refused");
    let text = e.render(&ran.sources);
    assert!(e.message.contains("0 to 9") && e.message.contains("tool 1"), "{text}");
    // Located at the G42 word of line 5.
    assert!(text.contains("t.nc:5:"), "{text}");
}

#[test]
fn lathe_nose_missing_is_warned_of_or_refused_where_the_centre_path_is_needed() {
    // Tool 1 has a nose, the program uses tool 7.
    let mut settings = lathe(1, Nose { radius: 0.8, tip: 3 });
    let ran = common::run("t.nc", &od("G42", "G40", 7), &settings);
    let out = ran.completed();
    let w = out.diagnostics.iter().find(|d| d.message.contains("tool 7 has no nose")).expect("warned");
    assert!(!w.is_error());
    // Radius 0: the tip on the programmed points.
    assert_eq!(ends(&out.toolpath)[3], (4.0, 0.0));
    settings.radii_required = true;
    let ran = common::run("t.nc", &od("G42", "G40", 7), &settings);
    let e = ran.error().expect("refused");
    assert!(e.message.contains("tool 7 has no nose") && e.message.contains("cannot be made"), "{}", e.message);
}

#[test]
fn lathe_nose_interference_is_the_nose_s_alarm() {
    // A concave fillet of radius 0.5 with a nose of 0.8: the nose cannot
    // get in (Fanuc alarm PS0041), said of the nose.
    let text = "G18 G21 G40 G98
T0101
G00 X10. Z3.
G42 G01 Z0. F100.
G01 X6.
G01 Z-10.
G02 X6.5 Z-10.5 I0.5 K0.
G01 X12.
G40 G00 X18.
M30
";
    let settings = lathe(1, Nose { radius: 0.8, tip: 3 });
    let ran = common::run("t.nc", text, &settings);
    let e = ran.error().expect("alarm");
    assert!(
        e.message.starts_with("tool nose radius compensation:") && e.message.contains("nose radius"),
        "{}",
        e.message
    );
    assert!(e.message.contains("PS0041"), "{}", e.message);
}

#[test]
fn lathe_nose_linuxcnc_numbers_the_tip_with_x_mirrored_and_agrees_with_rs274() {
    // The OD profile in LinuxCNC's words, its OD tool being orientation 2
    // (its figure is drawn with X down, a front tool post): the imaginary
    // tip (−R, −R) from the centre, Fanuc's 3. LinuxCNC's own corners: the
    // entry ends perpendicular and is moved to the inside corner's
    // intersection (X0.8 Z0.8, tip X0 Z0); convex corners get an arc of
    // the nose centre round the programmed corner (from the face's offset
    // end X4 Z0.8 to the chamfer's offset start X4 + 0.8/√2 Z0.8/√2, then
    // from its end X6 + 0.8/√2 Z−2 + 0.8/√2 round X6 Z−2 to X6.8 Z−2);
    // G40 leaves no vector: the last OD ends at its offset end X14.8 Z−20.
    // Tips are those less (0.8, 0.8). rs274 (tool table `T1 P1 D0.062992126
    // Q2`, its 1.6 mm diameter in inches) prints the same to 4 decimals:
    // 0/−0, 3.2/0, arc to 3.7657/−0.2343, 5.7657/−2.2343, arc to 6/−2.8,
    // 6/−10.8, arc to 8.2/−13, 11.2/−13, arc to 14/−15.8, 14/−20.8, 18/−20.
    let text = "G18 G21 G40 G90
T1 M6
G0 X20 Z10
G0 X0 Z3
G42 G1 Z0 F100
X4
X6 Z-2
Z-10
G2 X9 Z-13 I3 K0
G1 X12
G3 X14 Z-15 I0 K-2
G1 Z-20
G40 G0 X18
M2
";
    let h = 0.8 / S2;
    let want = [
        (20.0, 10.0),
        (0.0, 3.0),
        (0.0, 0.0),
        (3.2, 0.0),
        (4.0 + h - 0.8, h - 0.8),
        (6.0 + h - 0.8, -2.0 + h - 0.8),
        (6.0, -2.8),
        (6.0, -10.8),
        (8.2, -13.0),
        (11.2, -13.0),
        (14.0, -15.8),
        (14.0, -20.8),
        (18.0, -20.0),
    ];
    let settings = Settings {
        lathe: Some(Lathe { x: XMode::Radius, system: GCodeSystem::A }),
        noses: BTreeMap::from([(1, Nose { radius: 0.8, tip: 2 })]),
        comp_rules: kezuri_nc::interp::comp::Rules::LinuxCnc,
        ..common::linuxcnc::settings()
    };
    let path = common::linuxcnc::path_with(text, &settings);
    assert_ends("LinuxCNC tip path", &path, &want);
    let rs274 = [(3.7657, -0.2343), (5.7657, -2.2343)];
    for (k, (x, z)) in [(4, rs274[0]), (5, rs274[1])] {
        assert!((want[k].0 - x).abs() < 1e-4 && (want[k].1 - z).abs() < 1e-4);
    }
}

#[test]
fn lathe_nose_entry_arc_with_the_tip_off_the_centre_is_refused() {
    // LinuxCNC's rules allow an arc as the entry move; with the tip off
    // the nose centre its start is the tip and its end the compensated
    // tip, which no arc round one centre joins: refused at that block.
    let text = "G18 G21 G40 G90
T1 M6
G0 X10 Z3
G42 G2 X13 Z0 I3 K0 F100
G1 Z-10
G40 G0 X18
M2
";
    let settings = Settings {
        lathe: Some(Lathe { x: XMode::Radius, system: GCodeSystem::A }),
        noses: BTreeMap::from([(1, Nose { radius: 0.8, tip: 2 })]),
        comp_rules: kezuri_nc::interp::comp::Rules::LinuxCnc,
        ..common::linuxcnc::settings()
    };
    let (out, sources) = common::linuxcnc::run_with(text, &settings).expect("parses");
    let e = out.diagnostics.iter().find(|d| d.is_error()).expect("refused");
    let headline = e.headline(&sources);
    assert!(headline.starts_with("t.ngc:4:") && headline.contains("start-up move"), "{headline}");
    // With the tip on the centre (0) the same program runs.
    let settings = Settings { noses: BTreeMap::from([(1, Nose { radius: 0.8, tip: 0 })]), ..settings };
    common::linuxcnc::path_with(text, &settings);
}

/// The OD profile as a Fanuc lathe program: X a diameter (every X above
/// doubled; I and K stay radii), power-on G18, T0101 selecting tool 1 with
/// offset 1 at once, G98 feed per minute (system A).
const OD_DIAMETER: &str = "G21 G40 G98
T0101
G00 X40. Z10.
G00 X0. Z3.
G42 G01 Z0. F100.
X8.
X12. Z-2.
Z-10.
G02 X18. Z-13. I3. K0.
G01 X24.
G03 X28. Z-15. I0. K-2.
G01 Z-20.
G40 G00 X36.
M30
";

#[test]
fn lathe_nose_fanuc_lathe_program_in_diameters_gives_the_same_tip_path() {
    // X halved where it is read: the moves are those of the radius
    // program, the tip path the same hand-derived points (tip 3, R 0.8).
    for dialect in [Dialect::FanucLathe, Dialect::HaasLathe] {
        let settings =
            Settings { dialect, noses: BTreeMap::from([(1, Nose { radius: 0.8, tip: 3 })]), ..Settings::default() };
        let text =
            if dialect == Dialect::HaasLathe { OD_DIAMETER.replace("T0101", "T101") } else { OD_DIAMETER.to_string() };
        let out = run(&text, &settings);
        let mut want = OD_APPROACH.to_vec();
        want.extend(tips(&OD_CENTRE, (-0.8, -0.8)));
        assert_ends(&format!("{dialect:?} tip path"), &out.toolpath, &want);
        let centre = nose_centre_path(&out.toolpath, &settings.noses, TipNumbers::Fanuc);
        assert_ends(
            &format!("{dialect:?} centre"),
            &centre,
            &[&[(20.8, 10.8), (0.8, 3.8)][..], &OD_CENTRE[..8], &[(18.8, -19.2)]].concat(),
        );
    }
}

#[test]
fn lathe_nose_chamfer_and_corner_words_are_compensated_as_the_moves_they_make() {
    // The same OD profile with its chamfer and rounds given as chamfer and
    // corner R words (system A; the sign is the way the next move goes):
    // the face X12. C-2. ends 2 short of the corner X6 Z0 (radius) and
    // chamfers to X6 Z−2; Z-13. R3. rounds the OD into the shoulder face
    // (the concave R3 round X9 Z−10); X28. R-2. rounds the shoulder into
    // the OD X14 (the convex R2 round X12 Z−15).
    // Those are the moves of the written-out program: the same tip path.
    let text = "G21 G40 G98
T0101
G00 X40. Z10.
G00 X0. Z3.
G42 G01 Z0. F100.
X12. C-2.
Z-13. R3.
X28. R-2.
Z-20.
G40 G00 X36.
M30
";
    let settings = Settings {
        dialect: Dialect::FanucLathe,
        noses: BTreeMap::from([(1, Nose { radius: 0.8, tip: 3 })]),
        ..Settings::default()
    };
    let out = run(text, &settings);
    let mut want = OD_APPROACH.to_vec();
    want.extend(tips(&OD_CENTRE, (-0.8, -0.8)));
    assert_ends("tip path", &out.toolpath, &want);
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
