//! `G71`, `G72` and `G73` with tool nose radius compensation in force.
//!
//! FANUC Series 0i-TF Plus Operator's Manual (B-64604EN), lathe system,
//! "Multiple repetitive cycle", "Tool nose radius compensation": with
//! G41/G42 in force the cycle is made on the *compensated* finishing shape
//! (the shape offset by the nose radius on the side G41/G42 names, the
//! machine moving the imaginary tip: the nose centre plus the tip vector),
//! the roughing running to that shape moved by the allowances (Δu/2 in X,
//! Δw in Z); the return to the start point is made with the offset
//! cancelled.
//!
//! Conventions as `lathe_cycle_nose.rs`: X read as a diameter in the
//! programs, every point below in (X radius, Z); right of travel (dZ, dX)
//! is (dX, −dZ) in (Z, X); nose R 0.8, tip 3: tip = centre + (−0.8, −0.8)
//! in (X, Z). Allowances U0.4 W0.1: the shape moves by w = (+0.2, +0.1).
//! Every expected number is worked out in the comments before the run was
//! looked at.

use kezuri_geom::{Move, MoveKind, Toolpath};
use kezuri_nc::interp::{nose_centre_path, GCodeSystem, Lathe, Nose, Settings, TipNumbers, XMode};

mod common;

use common::nose::*;

const R: f64 = 0.8;

fn settings() -> Settings {
    let mut s = lathe(1, Nose { radius: R, tip: 3 });
    s.lathe = Some(Lathe { x: XMode::Diameter, system: GCodeSystem::A });
    s
}

/// The moves the cycle block on 1-based line `line` makes.
fn cycle(path: &Toolpath, line: u32) -> Vec<Move> {
    path.moves.iter().filter(|m| m.line == line).copied().collect()
}

/// The feed cuts at a constant X (G71's cuts by depth): (X, end Z).
fn cuts_along_z(moves: &[Move]) -> Vec<(f64, f64)> {
    let flat = |m: &&Move| m.kind == MoveKind::Feed && (m.start.x - m.end.x).abs() < 1e-12 && m.end.z < m.start.z;
    moves.iter().filter(flat).map(|m| (m.end.x, m.end.z)).collect()
}

/// The end Z of the cut at level X `x`.
fn cut_at(cuts: &[(f64, f64)], x: f64) -> f64 {
    cuts.iter().find(|c| (c.0 - x).abs() < 1e-9).unwrap_or_else(|| panic!("no cut at X{x}: {cuts:?}")).1
}

/// A point of the finished part's surface (X, Z) and its outward normal.
type Sample = ((f64, f64), (f64, f64));

/// A stretch of the finished part's surface: points (X, Z) with the unit
/// normal (X, Z) pointing out of the material, sampled every 0.02 mm.
fn line_samples(a: (f64, f64), b: (f64, f64), n: (f64, f64)) -> Vec<Sample> {
    let k = ((b.0 - a.0).hypot(b.1 - a.1) / 0.02).ceil() as usize;
    (0..=k)
        .map(|i| {
            let t = i as f64 / k as f64;
            ((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)), n)
        })
        .collect()
}

/// Points of a convex arc round `c` (X, Z) of radius `r`, at angles `from`
/// to `to` degrees from +X toward +Z, the normal outward.
fn arc_samples(c: (f64, f64), r: f64, from: f64, to: f64) -> Vec<Sample> {
    let k = ((to - from).to_radians().abs() * r / 0.02).ceil() as usize;
    (0..=k)
        .map(|i| {
            let n = dir(from + (to - from) * i as f64 / k as f64);
            ((c.0 + r * n.0, c.1 + r * n.1), n)
        })
        .collect()
}

/// The stock the cycle's cutting moves leave on the part at each sample,
/// less the allowance there (the part moved by w, measured along the
/// normal: n·w, the arcs' curvature changing it by under |w|²/(2·6) =
/// 0.0042 mm): (least, most) over the samples.
fn left_over_allowance(moves: &[Move], samples: &[Sample], w: (f64, f64)) -> (f64, f64) {
    let path = Toolpath { moves: moves.to_vec(), ..Default::default() };
    let centre = nose_centre_path(&path, &settings().noses, TipNumbers::Fanuc);
    let points = centres(&centre, 0.01);
    let mut range = (f64::INFINITY, f64::NEG_INFINITY);
    for &(p, n) in samples {
        let left = cut_surface(&points, R, p, n) - (n.0 * w.0 + n.1 * w.1);
        range = (range.0.min(left), range.1.max(left));
    }
    range
}

/// An OD shape from the start point A (X30 → radius 15, Z1): N10 to X8
/// (radius 4), a 45° chamfer to radius 7 at Z−2, the OD to Z−8, a convex
/// R6 round (G03 in the ZX plane seen from +Y: from angle 0 to 90° round
/// (Z−14, X7) in (Z, X)) up to radius 13 at Z−14, the OD to Z−20.
const OD: &str = "N10 G00 X8.
N11 G01 X14. Z-2.
N12 Z-8.
N13 G03 X26. Z-14. R6.
N14 G01 Z-20.
";

fn g71(comp: &str) -> String {
    format!(
        "G18 G21 G40 G98\nT0101\nG00 X40. Z10.\n{comp} G00 X30. Z1.\nG71 U1. R0.5\nG71 P10 Q14 U0.4 W0.1 F100.\n{OD}G40 G00 X40. Z10.\nM30\n"
    )
}

/// The OD's surface where the finishing allowance is the cycle's to leave:
/// away from the outside corners by 0.3 mm, on the chamfer past where the
/// start-up's corner lets the nose reach (see below), and out of the inside
/// corner of the OD radius 7 and the round, where the nose leaves its own
/// round: its centre stops where X7.8 meets the circle of radius 6.8 round
/// (X7, Z−14), Z = −14 + √(6.8² − 0.8²) ≈ −7.247, touching the OD there
/// and the round at atan(6.753/0.8) ≈ 83.2° from +X; the stretches end
/// short of that (Z−7.0, 80°).
fn od_surface() -> Vec<Sample> {
    let n45 = (0.5f64.sqrt(), 0.5f64.sqrt());
    let mut s = line_samples((5.6, -0.6), (6.8, -1.8), n45);
    s.extend(line_samples((7.0, -2.3), (7.0, -7.0), (1.0, 0.0)));
    s.extend(arc_samples((7.0, -14.0), 6.0, 3.0, 80.0));
    s.extend(line_samples((13.0, -14.3), (13.0, -19.7), (1.0, 0.0)));
    s
}

/// G71 type I, G42: the compensated shape (tip path) is, element by
/// element:
/// - the chamfer: nose centre on Z + X = 5 + 0.8·√2 (the line Z + X = 5
///   moved 0.8 along its normal (1, 1)/√2), the tip 0.8 lower in both:
///   Z + X = 3.4 + 0.8·√2; moved by w: Z + X = 3.7 + 0.8·√2 ≈ 4.83137.
/// - the OD radius 7: centre X7.8, tip X7.0, moved X7.2.
/// - the round: centre path an arc of radius 6.8 round (X7, Z−14); the tip
///   path the same round (X6.2, Z−14.8); moved, round (X6.4, Z−14.7).
/// - the OD radius 13: tip X13.0, moved X13.2.
///
/// The cuts by depth are at X = 15 − k·1 (Δd = U1.0, a radius), each
/// ending where it meets the moved shape: on the chamfer (X below 7.2, and
/// above where the chamfer begins, X ≈ 5.37 + 0.2: X7 and X6) at
/// Z = 4.83137 − X; on the round (X from 7.2 to 13.2: X8 … X13) at
/// Z = −14.7 + √(6.8² − (X − 6.4)²). The uncompensated cycle ends them on
/// Z + X = 5.3 and on the round of radius 6 round (X7.2, Z−13.9).
///
/// The shape's offset starts up on its first block N10 (−X from A), which
/// turns right into the chamfer, an inside corner for the nose on the
/// right: the centre stops where N10's offset line Z = 1 − 0.8 = 0.2
/// meets the chamfer's, X = 4.8 + 0.8·√2 ≈ 5.931; the nose touches the
/// chamfer 0.8 along (−1, −1)/√2 from there, at X ≈ 5.366, and on: the
/// finished stock is checked from X5.6.
#[test]
fn lathe_g71_with_g42_roughs_the_compensated_shape() {
    let out = run(&g71("G42"), &settings());
    let moves = cycle(&out.toolpath, 6);
    let cuts = cuts_along_z(&moves);
    let chamfer = 3.7 + 0.8 * S2;
    for x in [7.0, 6.0] {
        let z = cut_at(&cuts, x);
        assert!((z - (chamfer - x)).abs() < 1e-9, "the cut at X{x} ends at Z{z}, want Z{}", chamfer - x);
    }
    for x in [8.0, 9.0, 10.0, 11.0, 12.0, 13.0] {
        let want = -14.7 + (6.8f64 * 6.8 - (x - 6.4) * (x - 6.4)).sqrt();
        let z = cut_at(&cuts, x);
        assert!((z - want).abs() < 1e-9, "the cut at X{x} ends at Z{z}, want Z{want}");
    }
    // Back to the programmed start point A, with the offset cancelled.
    let last = moves.last().expect("the cycle's moves");
    assert_eq!((last.end.x, last.end.z, last.kind), (15.0, 1.0, MoveKind::Rapid));
    // The stock left on the finished OD is the allowance: the cut along
    // the shape (the compensated shape moved by w) leaves it even; nothing
    // cuts into it.
    let (least, most) = left_over_allowance(&moves, &od_surface(), (0.2, 0.1));
    assert!(least > -0.005, "the roughing cuts {least} mm into the allowance");
    assert!(most < 0.005, "the roughing leaves {most} mm more than the allowance");
    // Compensation stays in force after the cycle: the G40 move after it
    // cancels it on the programmed point X40 (radius 20) Z10.
    assert!(out.toolpath.moves.last().is_some_and(|m| (m.end.x, m.end.z) == (20.0, 10.0)));
}

/// Without compensation the same cycle roughs the programmed shape with
/// the tip: on the chamfer the nose leaves the uncompensated nose's error
/// over the allowance. The nose centre runs 0.8 in X and Z above the tip
/// path Z + X = 5.3, on Z + X = 6.9; its edge on Z + X = 6.9 − 0.8·√2: the
/// stock left is (6.9 − 0.8·√2 − 5)/√2 = 0.543 mm against the allowance's
/// 0.3/√2 = 0.212 mm, 0.331 over. On the ODs the tip runs on the line, no
/// error.
#[test]
fn lathe_g71_without_compensation_leaves_the_nose_error_on_the_chamfer() {
    let out = run(&g71(""), &settings());
    let moves = cycle(&out.toolpath, 6);
    let cuts = cuts_along_z(&moves);
    for x in [7.0, 6.0] {
        assert!((cut_at(&cuts, x) - (5.3 - x)).abs() < 1e-9);
    }
    let n45 = (0.5f64.sqrt(), 0.5f64.sqrt());
    let (_, most) = left_over_allowance(&moves, &line_samples((5.6, -0.6), (6.8, -1.8), n45), (0.2, 0.1));
    let want = (6.9 - 0.8 * S2 - 5.0) / S2 - 0.3 / S2;
    assert!((most - want).abs() < 0.002, "{most}, want {want}");
}

/// G72 type I, G41 (the nose on +Z of a face cut toward the axis), from A
/// (X40 → radius 20, Z2): N30 to Z−6, the face to radius 12, the step to
/// Z−3, a 45° chamfer to radius 9 at Z0, the face to radius 2.
///
/// Compensated (left of (dZ, dX) is (−dX, dZ)), tip = centre − (0.8, 0.8):
/// - the face at Z−6 (−X): centre Z−5.2, tip Z−6.0, moved Z−5.9;
/// - the step at radius 12 (+Z): centre X12.8, tip X12.0, moved X12.2;
/// - the chamfer Z + X = 9 (direction (1, −1)/√2 in (Z, X), left (1, 1)/√2):
///   centre Z + X = 9 + 0.8·√2, tip 1.6 less, moved 0.3 more:
///   Z + X = 7.7 + 0.8·√2 ≈ 8.83137; it meets X12.2 at Z ≈ −3.369;
/// - the face at Z0: tip Z0, moved Z0.1.
///
/// The cuts by depth (W1.0) are at Z = 2 − k, along −X from X20 to the
/// moved shape: Z0, −1, −2, −3 end on the chamfer at X = 8.83137 − Z; Z−4
/// and Z−5 on the step at X12.2 (Z−6 is past the moved face, Z−5.9). The
/// uncompensated cycle ends them on Z + X = 9.3.
#[test]
fn lathe_g72_with_g41_roughs_the_compensated_face() {
    let program = "G18 G21 G40 G98\nT0101\nG00 X50. Z10.\nG41 G00 X40. Z2.\nG72 W1. R0.5\nG72 P30 Q34 U0.4 W0.1 F100.\nN30 G00 Z-6.\nG01 X24.\nZ-3.\nX18. Z0.\nN34 X4.\nG40 G00 X50. Z10.\nM30\n";
    let out = run(program, &settings());
    let moves = cycle(&out.toolpath, 6);
    let flat = |m: &&Move| m.kind == MoveKind::Feed && (m.start.z - m.end.z).abs() < 1e-12 && m.end.x < m.start.x;
    let cuts: Vec<(f64, f64)> = moves.iter().filter(flat).map(|m| (m.end.z, m.end.x)).collect();
    let chamfer = 7.7 + 0.8 * S2;
    for (z, want) in [
        (0.0, chamfer),
        (-1.0, chamfer + 1.0),
        (-2.0, chamfer + 2.0),
        (-3.0, chamfer + 3.0),
        (-4.0, 12.2),
        (-5.0, 12.2),
    ] {
        let x = cut_at(&cuts, z);
        assert!((x - want).abs() < 1e-9, "the cut at Z{z} ends at X{x}, want X{want}");
    }
    assert!(cuts.iter().all(|c| c.0 > -5.9 - 1e-9), "no cut below the moved face: {cuts:?}");
    let last = moves.last().expect("the cycle's moves");
    assert_eq!((last.end.x, last.end.z), (20.0, 2.0));
    // The stock left: the face Z−6 from X13 to X19 (the start-up's
    // inside corner stops the nose centre at X19.2; the inside corner of
    // the face and the step, at X12 Z−6, at X12.8 Z−5.2, the nose touching
    // the face at X12.8 and the step at Z−5.2), the step from Z−5, the
    // chamfer, the face Z0 to X2.3.
    let n45 = (0.5f64.sqrt(), 0.5f64.sqrt());
    let mut s = line_samples((13.0, -6.0), (19.0, -6.0), (0.0, 1.0));
    s.extend(line_samples((12.0, -5.0), (12.0, -3.3), (1.0, 0.0)));
    s.extend(line_samples((11.7, -2.7), (9.3, -0.3), n45));
    s.extend(line_samples((8.7, 0.0), (2.3, 0.0), (0.0, 1.0)));
    let (least, most) = left_over_allowance(&moves, &s, (0.2, 0.1));
    assert!(least > -0.005 && most < 0.005, "the stock left is the allowance {least} … {most} mm over");
}

/// G73 with G42 on the OD shape: U3. W0.5 R3 (Δi 3 in radius, Δk 0.5,
/// three passes). Pass j of 3 is the compensated shape moved by
/// (Δu/2 + Δi·(3 − j)/2, Δw + Δk·(3 − j)/2): (3.2, 0.6), (1.7, 0.35),
/// (0.2, 0.1). The compensated chamfer meets the compensated OD (an
/// outside corner of 135°, the offset lines' intersection) with the
/// centre at X7.8 on Z + X = 5 + 0.8·√2, Z = −2.8 + 0.8·√2; the tip at
/// (X7.0, Z−3.6 + 0.8·√2 ≈ −2.46863). The round ends tangent to the OD
/// radius 13: centre (X13.8, Z−14), tip (X13.0, Z−14.8). The passes' ends
/// of the chamfer and of the round are these moved.
#[test]
fn lathe_g73_with_g42_repeats_the_compensated_shape() {
    let program = format!(
        "G18 G21 G40 G98\nT0101\nG00 X40. Z10.\nG42 G00 X30. Z1.\nG73 U3. W0.5 R3\nG73 P10 Q14 U0.4 W0.1 F100.\n{OD}G40 G00 X40. Z10.\nM30\n"
    );
    let out = run(&program, &settings());
    let moves = cycle(&out.toolpath, 6);
    let corner = (7.0, -3.6 + 0.8 * S2);
    let round = (13.0, -14.8);
    for (dx, dz) in [(3.2, 0.6), (1.7, 0.35), (0.2, 0.1)] {
        for p in [corner, round] {
            let want = (p.0 + dx, p.1 + dz);
            assert!(
                moves.iter().any(|m| (m.end.x - want.0).abs() < 1e-9 && (m.end.z - want.1).abs() < 1e-9),
                "no move of the pass moved by ({dx}, {dz}) ends at {want:?}"
            );
        }
    }
    let last = moves.last().expect("the cycle's moves");
    assert_eq!((last.end.x, last.end.z), (15.0, 1.0));
    // The last pass leaves the allowance.
    let (least, most) = left_over_allowance(&moves, &od_surface(), (0.2, 0.1));
    assert!(least > -0.005 && most < 0.005, "the stock left is the allowance {least} … {most} mm over");
}

/// A concave R0.5 fillet under a nose of R0.8: the compensated shape
/// cannot be made (the inside arc is not larger than the nose: Fanuc alarm
/// PS0041, interference), and the cycle stops at the fillet's block. The
/// same program without compensation runs.
#[test]
fn lathe_g71_stops_where_the_nose_cannot_follow_the_shape() {
    let shape = "N20 G00 X10.\nG01 Z-5.\nG02 X11. Z-5.5 R0.5\nG01 X24.\nN24 Z-10.\n";
    let program = |comp: &str| {
        format!("G18 G21 G40 G98\nT0101\nG00 X40. Z10.\n{comp} G00 X20. Z1.\nG71 U1. R0.5\nG71 P20 Q24 U0.4 W0.1 F100.\n{shape}G40 G00 X40. Z10.\nM30\n")
    };
    let text = program("G42");
    let ran = common::run("t.nc", &text, &settings());
    let e = ran.error().expect("an alarm");
    assert_eq!(&text[e.span.start as usize..e.span.end as usize], "G02 X11. Z-5.5 R0.5", "{}", e.message);
    assert!(e.message.contains("PS0041") && e.message.contains("nose radius"), "{}", e.message);
    run(&program(""), &settings());
}

/// G71 type II (N10 names X and Z), G42, a 45° V-sided pocket in the OD
/// radius 7: down from (X7, Z−4) to (X5, Z−6) (the line X − Z = 11), the
/// bottom to Z−9, up to (X7, Z−11) (X + Z = −4), the OD to Z−16.
///
/// Compensated: the down wall (direction (−1, −1)/√2 in (Z, X), right
/// (−1, 1)/√2) has its centre on X − Z = 11 + 0.8·√2, the tip the same
/// line (the tip vector (−0.8, −0.8) runs along it), moved by w
/// X − Z = 11.1 + 0.8·√2 ≈ 12.2314; the up wall (right (1, 1)/√2): centre
/// X + Z = −4 + 0.8·√2, tip 1.6 less, moved 0.3 more: X + Z = −5.3 +
/// 0.8·√2 ≈ −4.1686; the bottom: tip X5, moved X5.2; the ODs X7.2.
///
/// The cuts at X7 and X6 lie below the moved OD (7.2) and above the moved
/// bottom: each runs across the pocket from the down wall (Z = X − 12.2314)
/// to the up wall (Z = −4.1686 − X). The uncompensated cycle runs them
/// from X − Z = 11.3 to X + Z = −3.7.
#[test]
fn lathe_g71_type_ii_with_g42_cuts_the_compensated_pocket() {
    let program = "G18 G21 G40 G98\nT0101\nG00 X40. Z10.\nG42 G00 X30. Z1.\nG71 U1. R0.5\nG71 P10 Q15 U0.4 W0.1 F100.\nN10 G00 X14. Z1.\nG01 Z-4.\nX10. Z-6.\nZ-9.\nX14. Z-11.\nN15 Z-16.\nG40 G00 X40. Z10.\nM30\n";
    let out = run(program, &settings());
    let moves = cycle(&out.toolpath, 6);
    let (down, up) = (11.1 + 0.8 * S2, -5.3 + 0.8 * S2);
    for x in [7.0, 6.0] {
        let (from, to) = (x - down, up - x);
        let cut = moves.iter().find(|m| {
            m.kind == MoveKind::Feed
                && (m.start.x - x).abs() < 1e-12
                && (m.end.x - x).abs() < 1e-12
                && m.end.z < m.start.z
        });
        let cut = cut.unwrap_or_else(|| panic!("no cut at X{x}"));
        assert!(
            (cut.start.z - from).abs() < 1e-9 && (cut.end.z - to).abs() < 1e-9,
            "the cut at X{x} runs Z{} to Z{}, want Z{from} to Z{to}",
            cut.start.z,
            cut.end.z
        );
    }
    assert!(!moves.iter().any(|m| m.end.x < 5.2 - 1e-9), "nothing below the moved bottom");
    let last = moves.last().expect("the cycle's moves");
    assert_eq!((last.end.x, last.end.z), (15.0, 1.0));
}
