//! Tool nose radius compensation around a multiple repetitive cycle: `G42`
//! before `G70 P Q`, `G40` after, as a real turning program has them.
//!
//! FANUC Series 0i-TF Plus Operator's Manual (B-64604EN), lathe system,
//! "Multiple repetitive cycle", "Tool nose radius compensation": G41/G42 is
//! given before the cycle and G40 outside the shape's blocks; the cycle's
//! finishing shape is compensated, and the cycle's offset ends with the
//! shape: the vector at the shape's end point is the one perpendicular to
//! its last block, and the return to the cycle's start point is made with
//! the offset cancelled (the tool back on the programmed start point);
//! compensation stays in force, and the next move starts it up again.
//!
//! Conventions as `lathe_nose.rs`: X a radius, (Z, X) seen from +Y, G42 the
//! nose right of travel (right of (dZ, dX) is (dX, −dZ) in (Z, X)), tip 3:
//! tip = centre + (−R, −R). Every expected point is worked out in the
//! comments before the run was looked at.

use kezuri_geom::MoveKind;
use kezuri_nc::interp::{nose_centre_path, Nose, TipNumbers};

mod common;

use common::nose::*;

/// An OD finishing shape N10–N20 from the start point A (X16, Z2): down the
/// front (−X) to the axis, onto the end face (−Z), the face up to X6, a 45°
/// chamfer to X8 Z−2, the OD X8 to Z−12, the shoulder up to X14, the OD X14
/// to Z−20. G71 roughs it without compensation; G70 finishes it with G42.
const PROGRAM: &str = "G18 G21 G40 G98
T0101
G00 X16. Z2.
G71 U1. R0.5
G71 P10 Q20 U0.4 W0.1 F100.
N10 G00 X0.
G01 Z0. F80.
X6.
X8. Z-2.
Z-12.
X14.
N20 Z-20.
G00 X30. Z10.
G42 G00 X16. Z2.
G70 P10 Q20
G40 G00 X30. Z10.
M30
";

/// The programmed contour the finishing pass cuts, (X, Z) corners.
const CONTOUR: [(f64, f64); 7] =
    [(0.0, 2.0), (0.0, 0.0), (6.0, 0.0), (8.0, -2.0), (8.0, -12.0), (14.0, -12.0), (14.0, -20.0)];

/// The nose centre points of G70 with G42, R 0.8, in order:
/// - start-up X30 Z10 → A (X16 Z2), direction (dZ, dX) = (−8, −14), then
///   N10 (−X): cross (−8)(−1) − (−14)(0) = 8 > 0, a left turn with the nose
///   on the right: outside; type A ends on the vector perpendicular to N10
///   at its start, right of −X is −Z: (X16, Z1.2).
/// - N10 (−X, offset Z = 1.2) → Z0 (−Z at X0, offset X = 0.8): right turn,
///   inside: the offsets meet at (X0.8, Z1.2).
/// - Z0 (−Z) → face (+X at Z0, offset Z = 0.8): right turn, inside:
///   (X0.8, Z0.8).
/// - face → chamfer (direction (−1, 1)/√2, offset X + Z = 6 + 0.8·√2):
///   left turn, outside obtuse, the offset lines' intersection: Z = 0.8,
///   X = 6 + 0.8·(√2 − 1).
/// - chamfer → OD X8 (offset X = 8.8): outside obtuse: Z = 6 + 0.8·√2 −
///   8.8 = −2.8 + 0.8·√2.
/// - OD → shoulder (+X at Z−12, offset Z = −11.2): right turn, inside:
///   (X8.8, Z−11.2).
/// - shoulder → OD X14 (offset X = 14.8): left turn, outside obtuse (90°):
///   (X14.8, Z−11.2).
/// - the OD's end, the shape's last point X14 Z−20: the vector
///   perpendicular to the OD, +X by R: (X14.8, Z−20). (Taking the
///   intersection with the return instead, the return's offset line
///   through (Z −20, X 14) + 0.8·(2, −22)/|(22, 2)| along (22, 2) meets
///   X = 14.8 at Z ≈ −2.36, behind the OD's start Z−11.2: the OD would run
///   backwards, alarm PS0041.)
const CENTRE: [(f64, f64); 8] = [
    (16.0, 1.2),
    (0.8, 1.2),
    (0.8, 0.8),
    (6.0 + 0.8 * (S2 - 1.0), 0.8),
    (8.8, -2.8 + 0.8 * S2),
    (8.8, -11.2),
    (14.8, -11.2),
    (14.8, -20.0),
];

/// Distance from `p` to the segment `a`–`b`, (X, Z).
fn to_segment(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dz) = (b.0 - a.0, b.1 - a.1);
    let t = (((p.0 - a.0) * dx + (p.1 - a.1) * dz) / (dx * dx + dz * dz)).clamp(0.0, 1.0);
    (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dz)
}

/// The nearest the contour comes to `p`.
fn to_contour(p: (f64, f64)) -> f64 {
    CONTOUR.windows(2).map(|w| to_segment(p, w[0], w[1])).fold(f64::INFINITY, f64::min)
}

#[test]
fn lathe_g42_around_g70_compensates_the_shape_and_returns_uncompensated() {
    let settings = lathe(1, Nose { radius: 0.8, tip: 3 });
    let out = run(PROGRAM, &settings);
    let path = &out.toolpath;
    // G70's moves: from the start-up (the move that ends nearest Z1.2 after
    // the G00 X30 Z10) to the end. Find the G00 X30 Z10 before G42.
    let moves: Vec<_> = path.moves.iter().map(|m| (m.end.x, m.end.z)).collect();
    let park = moves.iter().position(|&(x, z)| x == 30.0 && z == 10.0).expect("the move to X30 Z10 before G42");
    let g70 = &path.moves[park + 1..];
    // Tip path: each centre point less (0.8, 0.8) (tip 3), then the return
    // to the programmed start point A (X16 Z2), then the G40 move to X30 Z10.
    let mut want: Vec<(f64, f64)> = CENTRE.iter().map(|&(x, z)| (x - 0.8, z - 0.8)).collect();
    want.push((16.0, 2.0));
    want.push((30.0, 10.0));
    let got: Vec<_> = g70.iter().map(|m| (m.end.x, m.end.z)).collect();
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (k, (g, w)) in got.iter().zip(&want).enumerate() {
        assert!((g.0 - w.0).abs() < 1e-9 && (g.1 - w.1).abs() < 1e-9, "move {k}: {g:?}, want {w:?}");
    }
    // The return is a rapid from the OD's compensated end to A.
    let back = &g70[CENTRE.len()];
    assert_eq!(back.kind, MoveKind::Rapid);
    assert_eq!((back.start.x, back.start.z), (14.0, -20.8));
    // The finishing pass touches the contour: no nose centre of its
    // cutting moves (every 0.05 mm) is nearer the contour than the nose
    // radius (no gouge), and each of the contour's elements comes within
    // the radius of one, to 1e-6 mm (no stock left). At the outside
    // corners the centre at the intersection is farther (type C corners).
    let centre = nose_centre_path(path, &settings.noses, TipNumbers::Fanuc);
    let cut =
        kezuri_geom::Toolpath { moves: centre.moves[park + 3..park + CENTRE.len() + 1].to_vec(), ..Default::default() };
    let points = centres(&cut, 0.05);
    assert!(points.len() > 100);
    for &p in &points {
        let d = to_contour(p);
        assert!(d > 0.8 - 1e-6, "nose centre {p:?} is {d} from the contour: a gouge");
    }
    for w in CONTOUR.windows(2) {
        let nearest = points.iter().map(|&p| to_segment(p, w[0], w[1])).fold(f64::INFINITY, f64::min);
        assert!((nearest - 0.8).abs() < 1e-6, "the contour {w:?} is {nearest} from the nose centres");
    }
    // G71 roughed without compensation: its cuts end on programmed
    // points (the first cut at X16 − 1 = 15 in radius).
    assert!(path.moves[..park].iter().any(|m| m.end.x == 15.0));
}

#[test]
fn lathe_g42_around_g70_in_the_bundled_sample_runs_without_an_alarm() {
    // The bundled turning job finishes with G42 … G70 … G40: it runs to
    // its end (X a diameter, tip 3, R 0.4 on T2).
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../samples/o3001-turning.nc"))
        .expect("the bundled sample");
    assert!(text.contains("G42") && text.contains("G40 X100."), "the sample compensates its G70");
    let mut settings = lathe(2, Nose { radius: 0.4, tip: 3 });
    settings.lathe = Some(kezuri_nc::interp::Lathe {
        x: kezuri_nc::interp::XMode::Diameter,
        system: kezuri_nc::interp::GCodeSystem::A,
    });
    settings.max_rpm = Some(3000.0);
    let out = run(&text, &settings);
    // The last finishing move, the OD X48 to Z−70: its nose centre +X by R
    // from the programmed end (radius 24): the tip (tip 3) at X24 Z−70.4,
    // then the return to the start point X52 (radius 26) Z2.
    let k = out.toolpath.moves.iter().position(|m| m.tool == 2 && (m.end.x - 26.0).abs() < 1e-9 && m.end.z == 2.0);
    let k = k.expect("the return to the start point from the shape's end");
    let back = &out.toolpath.moves[k];
    assert!((back.start.x - 24.0).abs() < 1e-9 && (back.start.z + 70.4).abs() < 1e-9, "{back:?}");
}
