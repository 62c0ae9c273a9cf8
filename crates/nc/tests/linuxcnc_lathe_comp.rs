//! LinuxCNC's cutter compensation with a lathe tool's orientation, and the
//! checks LinuxCNC makes as it reads: the entry move, the end of the file.
//!
//! From the LinuxCNC G-code reference (`/usr/share/doc/linuxcnc`, "G41.1,
//! G42.1 Dynamic Cutter Compensation", "Lathe Tool Orientation",
//! Figure 2.13 "Lathe Tool Orientations"; "G40, G41, G42" for the entry
//! move), and `docs/cutter-compensation.md` for LinuxCNC's corners:
//! - `G42.1 D… L…` compensates as `G42` with the cutter diameter D and the
//!   lathe tool orientation L (0–9; an L outside 0–9, or with the XZ plane
//!   not active, is an error).
//! - The figure draws the ZX plane with +Z to the right and +X *down* (a
//!   front tool post lathe) and marks, for each orientation, the point the
//!   tool is set to (its imaginary tip) with a cross: for orientation 2
//!   (the turning tool, drawn bottom right) the cross is at the nose's
//!   upper left, toward −X and −Z from the nose centre: tip = centre +
//!   (−R, −R) in (X, Z). Orientation 6 (bottom middle): the cross above
//!   the nose, tip = centre + (−R, 0). 9 is the nose centre.
//! - The nose centre runs as a mill's cutter centre does under LinuxCNC's
//!   rules: the entry move ends off its end by R, square to it; a concave
//!   corner moves the move before to the offset lines' intersection; a
//!   convex corner gets an arc of radius R round the programmed corner;
//!   an arc the tool is inside is offset to its radius less R; G40 leaves
//!   no vector. The machine moves the imaginary tip: centre + tip vector.
//! - The entry move (the first after G41/G42) must be longer than the
//!   tool radius: "Length of cutter compensation entry move is not greater
//!   than the tool radius", given where that move is read.
//!
//! G42 puts the tool right of the direction of travel seen from +Y (+Z to
//! the right, +X up): travelling −Z, the tool is on the +X side. X is a
//! radius throughout (G8).

use std::collections::BTreeMap;

use kezuri_nc::interp::{comp::Rules, Nose, Settings};

mod common;

use common::nose::{assert_ends, S2};

/// LinuxCNC's settings (its dialect and rules, no lathe conventions: a
/// LinuxCNC lathe turns by its own G7/G8/G18), tool 1 with `nose`.
fn linuxcnc(nose: Option<Nose>) -> Settings {
    Settings {
        noses: nose.map(|n| BTreeMap::from([(1, n)])).unwrap_or_default(),
        tool_radii: BTreeMap::from([(1, 0.8)]),
        comp_rules: Rules::LinuxCnc,
        ..common::linuxcnc::settings()
    }
}

/// An OD with a 45° chamfer and a fillet, X a radius: entry down Z to
/// Z2 on X4, the chamfer X4 Z2 → X6 Z0, the OD X6 to Z−5, a fillet R2
/// (G2, centre X8 Z−5) up to X8 Z−7, the shoulder face to X12, cancel.
fn program(comp: &str) -> String {
    format!(
        "G18 G8 G21 G90 G40
T1 M6
G0 X4 Z5
{comp}
G1 Z2 F100
X6 Z0
Z-5
G2 X8 Z-7 I2 K0
G1 X12
G40 G0 X14
M2
"
    )
}

/// By hand, R = 0.8, orientation 2 (tip = centre + (−0.8, −0.8)):
/// - entry (X4 Z5) → (X4 Z2), travelling −Z: the centre's offset line is
///   X = 4.8. The chamfer X4 Z2 → X6 Z0 runs toward −Z and +X, turning
///   toward the tool: a concave corner. Its line is X + Z = 6; the tool
///   side (right of travel) is +X +Z, so its offset line is X + Z = 6 +
///   0.8·√2. The entry ends at the intersection: X4.8, Z = 1.2 + 0.8·√2 =
///   2.331371; the tip at X4.0 Z1.531371.
/// - the chamfer ends off X6 Z0 by 0.8 along (X, Z) = (1, 1)/√2: centre
///   X6.565685 Z0.565685, tip X5.765685 Z−0.234315.
/// - the OD (−Z) turns away from the tool after the chamfer (a convex
///   corner): an arc round X6 Z0 to the OD's offset start, centre X6.8 Z0,
///   tip X6.0 Z−0.8; then the OD to centre X6.8 Z−5, tip X6.0 Z−5.8.
/// - the fillet's centre X8 Z−5 is on the tool's side: the nose centre
///   runs round it at 2 − 0.8 = 1.2, ending at X8 Z−6.2 (tangent to the OD
///   before and the face after: no corner moves); tip X7.2 Z−7.0, its arc
///   round X7.2 Z−5.8.
/// - the face (+X) has the tool on its +Z side: centre X12 Z−6.2, tip
///   X11.2 Z−7.0; G40 G0 X14 from there to the programmed X14 Z−7.
///
/// rs274 (`G42.1 D1.6 L2`) prints 4.0000/1.5314, 5.7657/−0.2343, 6.0000/
/// −0.8000, 6.0000/−5.8000, 7.2000/−7.0000, 11.2000/−7.0000, 14/−7.
const ORIENTATION_2: [(f64, f64); 8] = [
    (4.0, 5.0),
    (4.0, 1.2 + 0.8 * S2 - 0.8),
    (6.0 + 0.8 / S2 - 0.8, 0.8 / S2 - 0.8),
    (6.0, -0.8),
    (6.0, -5.8),
    (7.2, -7.0),
    (11.2, -7.0),
    (14.0, -7.0),
];

fn want() -> Vec<(f64, f64)> {
    ORIENTATION_2.to_vec()
}

#[test]
fn g42_1_with_orientation_2_moves_the_imaginary_tip() {
    let path = common::linuxcnc::path_with(&program("G42.1 D1.6 L2"), &linuxcnc(None));
    assert_ends("G42.1 D1.6 L2", &path, &want());
    // The fillet keeps its radius round its centre moved with the tip: 1.2
    // round X7.2 Z−5.8.
    let fillet = &path.moves[5];
    let kezuri_geom::MoveKind::Arc(arc) = fillet.kind else { panic!("the fillet is an arc: {fillet:?}") };
    assert!((arc.center[0] - 7.2).abs() < 1e-9 && (arc.center[2] + 5.8).abs() < 1e-9, "{arc:?}");
    assert!((arc.radius(fillet.start) - 1.2).abs() < 1e-9 && (arc.radius(fillet.end) - 1.2).abs() < 1e-9);
    // The convex corner's arc: radius 0.8 round the programmed corner
    // shifted by the tip, X5.2 Z−0.8.
    let corner = &path.moves[3];
    let kezuri_geom::MoveKind::Arc(arc) = corner.kind else { panic!("the corner is an arc: {corner:?}") };
    assert!((arc.center[0] - 5.2).abs() < 1e-9 && (arc.center[2] + 0.8).abs() < 1e-9, "{arc:?}");
}

#[test]
fn g42_with_a_tool_of_orientation_2_is_the_same_path() {
    // The tool table's Q2 is kept as Fanuc's tip 3 (the same corner):
    // G42 compensates tool 1's nose, radius 0.8, as G42.1 D1.6 L2 does.
    let settings = linuxcnc(Some(Nose { radius: 0.8, tip: 3 }));
    let path = common::linuxcnc::path_with(&program("G42"), &settings);
    assert_ends("G42, tool 1 tip 3", &path, &want());
}

#[test]
fn orientation_6_and_9_shift_as_the_figure_says() {
    // Orientation 6: tip = centre − 0.8 in X only, so each compensated
    // point is 0.8 further in Z (+0.8) than orientation 2's. Orientation 9
    // (and 0): the nose centre itself, 0.8 further in X and Z.
    let path = common::linuxcnc::path_with(&program("G42.1 D1.6 L6"), &linuxcnc(None));
    let mut six = want();
    for p in &mut six[1..7] {
        p.1 += 0.8;
    }
    assert_ends("L6", &path, &six);
    for l in ["L9", "L0", ""] {
        let path = common::linuxcnc::path_with(&program(&format!("G42.1 D1.6 {l}")), &linuxcnc(None));
        let mut centre = want();
        for p in &mut centre[1..7] {
            (p.0, p.1) = (p.0 + 0.8, p.1 + 0.8);
        }
        assert_ends(&format!("G42.1 D1.6 {l}"), &path, &centre);
    }
}

/// `file:line:col: error: …` of the error that stops `text` under
/// LinuxCNC's rules.
fn error(text: &str) -> String {
    let (outcome, sources) = common::linuxcnc::run_with(text, &linuxcnc(None)).unwrap_or_else(|e| panic!("{e}"));
    let d = outcome.diagnostics.iter().find(|d| d.is_error()).unwrap_or_else(|| panic!("{text}: no error"));
    assert!(!outcome.completed);
    d.headline(&sources)
}

#[test]
fn a_bad_orientation_is_refused_where_it_is_written() {
    for (l, said) in
        [("L2.5", "Non integer value for integer"), ("L-1", "Negative l word used"), ("L10", "orientation is 0 to 9")]
    {
        let e = error(&program(&format!("G42.1 D1.6 {l}")));
        assert!(e.starts_with("t.ngc:4:12:") && e.contains(said), "{l}: {e}");
    }
    // L in the XY plane.
    let e = error(&program("G17 G42.1 D1.6 L2"));
    assert!(e.starts_with("t.ngc:4:16:") && e.contains("plane is not G18"), "{e}");
}

#[test]
fn an_entry_move_not_longer_than_the_radius_stops_where_it_is_made() {
    // The entry Z4.5 travels 0.5, not more than the radius 0.8: LinuxCNC
    // stops at it, before the arc after it (off its circle) is read.
    let text = "G18 G8 G21 G90\nG0 X4 Z5\nG42.1 D1.6 L2\nG1 Z4.5 F100\nG2 X9 Z0 R1\nM2\n";
    let e = error(text);
    assert!(
        e.starts_with("t.ngc:4:")
            && e.contains("Length of cutter compensation entry move is not greater than the tool radius"),
        "{e}"
    );
    // An entry of 1 mm runs on (and the arc is refused, for its own reason).
    let e = error(&text.replace("Z4.5", "Z4"));
    assert!(e.starts_with("t.ngc:5:"), "{e}");
}

#[test]
fn a_program_must_end_with_m2_m30_or_its_closing_percent() {
    // LinuxCNC reads to the end of the file and refuses a program that
    // runs off it: "File ended with no percent sign or program end".
    let e = error("G0 X1\nG1 X2 F10\n");
    assert!(e.starts_with("t.ngc:2:") && e.contains("File ended with no percent sign or program end"), "{e}");
    common::linuxcnc::path("G0 X1\nG1 X2 F10\nM2\n");
    common::linuxcnc::path("G0 X1\nG1 X2 F10\nM30\n");
    common::linuxcnc::path("%\nG0 X1\nG1 X2 F10\n%\n");
    // A subroutine ends at its endsub, not at the end of its file.
    common::linuxcnc::path("o<a> sub\nG1 X2 F10\no<a> endsub\no<a> call\nM2\n");
}

#[test]
fn a_move_that_goes_nowhere_after_the_entry_leaves_the_corner_to_the_next_move() {
    // R = 0.15 (D0.3), orientation 2 (tip = centre − (0.15, 0.15)). The
    // entry X15 Z−37.59 → X15 Z3.041 travels +Z: the tool right of it is
    // on the −X side, its offset line X14.85. The rapid to the same point
    // moves nothing in the plane and makes no corner. The next move, −X
    // to X0.452, has the tool on its −Z side (offset line Z2.891) and
    // turns toward the tool: a concave corner, so the entry ends at
    // X14.85 Z2.891, tip X14.7 Z2.741. −X then −Z turns toward the tool
    // again: the corner X0.602 Z2.891 (the −Z move's offset line X0.602),
    // tip X0.452 Z2.741; Z−5 ends at centre X0.602 Z−5, tip X0.452 Z−5.15;
    // G40 goes to X20 Z−5. rs274 prints the same (14.7/2.741 twice,
    // 0.452/2.741, 0.452/−5.15, 20/−5).
    let text = "G18 G8 G21\nG0 X15 Z-37.59\nG42.1 D0.3 L2\nG0 X15 Z3.041\nG0 X15 Z3.041\nG0 X0.452 Z3.041\n\
                G1 Z-5 F100\nG40 G0 X20\nM2\n";
    let path = common::linuxcnc::path_with(text, &linuxcnc(None));
    let want = [(15.0, -37.59), (14.7, 2.741), (14.7, 2.741), (0.452, 2.741), (0.452, -5.15), (20.0, -5.0)];
    assert_ends("a rapid in place after the entry", &path, &want);
}

// ------------------------------------------------------------ G70 under compensation
//
// LinuxCNC 2.9's G70 under G41/G42 (`src/emc/rs274ngc/interp_g7x.cc`,
// `interp_convert.cc`, `interp_queue.cc`; read to learn the rule, which is
// re-derived here, not copied):
// 1. `convert_g7x` first makes the cycle's rapid to its X Z (S) with
//    `convert_straight`, compensated as any move is (here the entry move,
//    `convert_straight_comp1`: the nose centre off S by r, square to it).
// 2. It then reads the profile subroutine block by block without moving,
//    setting `settings->current_x`/`current_z` to each block's end. Under
//    compensation those are the tool centre's position (the point the next
//    move is compensated from), while `program_x`/`program_z` (the
//    programmed point) stay at S: the centre is left at P, the profile's
//    last point, uncompensated.
// 3. `g7x::do_g70` makes each pass as a rapid to the pass's start (the
//    profile's first piece's start: S, unless `monotonic()` moved its Z
//    to the piece's end), a rapid to the first point of the profile moved
//    by the pass's distance, then the profile.
// 4. The first pass's rapid to S has no travel in the plane
//    (`convert_straight_comp2`, "no XY motion"): it is a traverse to the
//    current point, P. The next move is compensated as a corner from
//    there: `theta` is the direction from the programmed point S to P
//    (normally the radius from the path to the centre), `beta` the turn
//    from the direction square to it; beta within 0.05 rad of 0: nothing
//    moves (a straight corner); beta > 0.05 (convex): the moves queued
//    before (the cycle's rapid, the rapid to P) end at P
//    (`move_endpoint_and_flush`) and a rapid goes to S + r square to the
//    next move; beta < −0.05 (concave) after a straight move: they end at
//    P moved by r / tan((beta + π) / 2) along theta turned toward the
//    tool's side by a quarter (−90° for G42).
// 5. When the queue is printed (`dequeue_canons`) each point is moved by
//    the orientation (`latheorigin_x`/`_z`): orientation 2, −r in X and Z.
// The cycle's other passes start from where the pass before ended, as any
// move does. G71 and G72 refuse compensation, so only G70 shows it.
//
// Each program: X a radius (G8), mm, `G42.1 D1 L2`: r = 0.5, the tip
// (X, Z) = centre − (0.5, 0.5); the entry from X10 Z−20 up +Z to the
// cycle's start, so the tool, right of +Z, is on its −X side. rs274
// 2.9's figures are given beside each.

/// A G70 from X10 Z`z`, under `G42.1 D1 L2`, of the profile `profile`
/// (its blocks, one a line), then `after`, G40 and a rapid to X12.
fn g70(profile: &str, z: &str, after: &str) -> String {
    format!(
        "G18 G8 G21 G90 F100\no100 sub\n{profile}o100 endsub\nG0 X10 Z-20\nG42.1 D1 L2\n\
         G70 Q100 X10 Z{z}\n{after}G40 G0 X12\nM2\n"
    )
}

/// The (X, Z) of the programmed point `(z, x)` + `r` along the angle `a`,
/// as the tip of orientation 2 (− 0.5 in X and Z).
fn tip_off(z: f64, x: f64, r: f64, a: f64) -> (f64, f64) {
    (x + r * a.sin() - 0.5, z + r * a.cos() - 0.5)
}

/// The profile after the cycle's start (the same in each of the first
/// two programs): the piece along −Z at X2 to Z−10, the diagonal to X5
/// Z−15, up to X8. Its corners (each concave for G42) put the centre at
/// X2.5 (the −Z piece's offset line) and the diagonal's offset line
/// (normal (Z, X) = (3, 5)/√34 from X2 Z−10 → X5 Z−15) meeting X2.5 at
/// Z = −10 − 5/6 + 17/(3√34), and the +X piece's line Z−14.5 at
/// X = 4.7 + 3.4/√34. Tips: X2 Z−10.361508, X4.783095 Z−15, then X7.5
/// Z−15 (X8's centre X8 Z−14.5); G40 to X12 Z−15. rs274: 2/−10.3615,
/// 4.7831/−15, 7.5/−15, 12/−15.
fn profile_end() -> [(f64, f64); 4] {
    let s34 = 34f64.sqrt();
    [(2.0, -10.0 - 5.0 / 6.0 + 17.0 / (3.0 * s34) - 0.5), (4.7 + 3.4 / s34 - 0.5, -15.0), (7.5, -15.0), (12.0, -15.0)]
}

#[test]
fn g70s_second_start_rapid_goes_to_the_profiles_end_a_straight_corner() {
    // S = X10 Z0; profile X2 Z0, Z−10, X10 (P = X10 Z−10, on S's X, as
    // lathe_g70_71_demo's ends). The entry ends at centre X9.5 Z0, tip X9
    // Z−0.5. The rapid to S goes to P: tip X9.5 Z−10.5. theta from S to P
    // is −Z (π); the rapid to X2 Z0 runs −X (−π/2, +2π: 3π/2): beta = 3π/2
    // − π − π/2 = 0, straight: nothing moves, and the rapid goes from P to
    // its offset end, moved by the concave corner with −Z to X2.5 Z−0.5:
    // tip X2 Z−1. The −Z piece to Z−10, concave with +X: centre X2.5
    // Z−9.5, tip X2 Z−10; X10: tip X9.5 Z−10; G40 to X12 Z−10. rs274: 9/−0.5,
    // 9.5/−10.5, 2/−1, 2/−10, 9.5/−10, 12/−10.
    let text = g70("G1 X2 Z0\nZ-10\nX10\n", "0", "");
    let path = common::linuxcnc::path_with(&text, &linuxcnc(None));
    let want = [(10.0, -20.0), (9.0, -0.5), (9.5, -10.5), (2.0, -1.0), (2.0, -10.0), (9.5, -10.0), (12.0, -10.0)];
    assert_ends("straight", &path, &want);
}

#[test]
fn g70s_concave_corner_from_the_profiles_end_moves_the_cycles_rapid_there() {
    // S = X10 Z2; profile X2 Z0, Z−10, X5 Z−15, X8: P = X8 Z−15. theta =
    // atan2(8 − 10, −15 − 2) (from S to P), the rapid to X2 Z0 runs at
    // alpha = atan2(2 − 10, 0 − 2); alpha > theta, so beta = alpha − theta
    // − π/2 = −0.362: concave. The cycle's rapid and the rapid to P both
    // end at P + r / tan((beta + π) / 2) along theta − π/2: centre X8.090897
    // Z−15.010694, tip X7.590897 Z−15.510694 (rs274: 7.5909/−15.5107, twice).
    // The rapid to X2 Z0 (direction (Z, X) = (−2, −8)) then ends where its
    // offset line (normal (−8, 2)/√68) meets X2.5 (the −Z piece's): Z =
    // 0.125 − 4.25/√68, tip X2 Z−0.890388 (rs274: 2/−0.8904).
    let text = g70("G1 X2 Z0\nZ-10\nX5 Z-15\nX8\n", "2", "");
    let path = common::linuxcnc::path_with(&text, &linuxcnc(None));
    let theta = (8.0f64 - 10.0).atan2(-15.0 - 2.0);
    let alpha = (2.0f64 - 10.0).atan2(0.0 - 2.0);
    let beta = alpha - theta - std::f64::consts::FRAC_PI_2;
    assert!(beta < -0.05, "concave: {beta}");
    let mid =
        tip_off(-15.0, 8.0, 0.5 / ((beta + std::f64::consts::PI) / 2.0).tan(), theta - std::f64::consts::FRAC_PI_2);
    assert!((mid.0 - 7.590897).abs() < 1e-6 && (mid.1 + 15.510694).abs() < 1e-6, "{mid:?}");
    let mut want = vec![(10.0, -20.0), mid, mid, (2.0, 0.125 - 4.25 / 68f64.sqrt() - 0.5)];
    want.extend(profile_end());
    assert_ends("concave", &path, &want);
}

#[test]
fn g70s_convex_corner_from_the_profiles_end_flushes_the_cycles_rapid_to_it() {
    // S = X10 Z2; profile X2 Z4 (up +Z first: LinuxCNC's monotonic() puts
    // the pass's start at X10 Z4), Z−10, X5 Z−15, X8: P = X8 Z−15. The
    // rapid to X10 Z4 now travels +Z: alpha = 0, theta as above (−3.0246):
    // beta = 0 − theta − π/2 = 1.454, convex. The cycle's rapid ends at P
    // (tip X7.5 Z−15.5), a rapid goes to S + r square to +Z (centre X9.5
    // Z2, tip X9 Z1.5), then the rapid to X10 Z4, whose end the concave
    // corner with −X (to X2 Z4) moves to X9.5 Z3.5: tip X9 Z3; the −X
    // rapid meets X2.5: tip X2 Z3. rs274: 7.5/−15.5, 9/1.5, 9/3, 2/3.
    let text = g70("G1 X2 Z4\nZ-10\nX5 Z-15\nX8\n", "2", "");
    let path = common::linuxcnc::path_with(&text, &linuxcnc(None));
    let mut want = vec![(10.0, -20.0), (7.5, -15.5), (9.0, 1.5), (9.0, 3.0), (2.0, 3.0)];
    want.extend(profile_end());
    assert_ends("convex", &path, &want);
}

#[test]
fn a_g70_that_cuts_nothing_still_leaves_the_centre_at_its_profiles_end() {
    // A profile of one piece (X4 Z0) is not cut (`path.size() <= 1`), but
    // reading it has left the centre at P = X4 Z0: the next move is
    // compensated from there. `G0 X12 Z−4` from S = X10 Z2: theta =
    // atan2(−6, −2), alpha = atan2(2, −6); beta = alpha − theta − π/2 =
    // 0.785 (convex): the cycle's rapid ends at P (tip X3.5 Z−0.5), a rapid
    // goes to S + r square to the move (normal (Z, X) = (1, 3)/√10 × 0.5),
    // then the move to its end + the same. rs274: 3.5/−0.5, 9.9743/1.6581,
    // 11.9743/−4.3419, G40 14/−4. A dwell between changes nothing.
    let n = (1.0 / 10f64.sqrt() * 0.5, 3.0 / 10f64.sqrt() * 0.5);
    let want = [
        (10.0, -20.0),
        (3.5, -0.5),
        (10.0 + n.1 - 0.5, 2.0 + n.0 - 0.5),
        (12.0 + n.1 - 0.5, -4.0 + n.0 - 0.5),
        (14.0, -4.0),
    ];
    for after in ["G0 X12 Z-4\n", "G4 P1\nG0 X12 Z-4\n"] {
        let text = g70("G1 X4 Z0\n", "2", after).replace("G40 G0 X12", "G40 G0 X14");
        let mut path = common::linuxcnc::path_with(&text, &linuxcnc(None));
        path.moves.retain(|m| !matches!(m.kind, kezuri_geom::MoveKind::Dwell(_)));
        assert_ends(after, &path, &want);
    }
    // An arc as that move: rs274 runs it, compensated from P by its arc
    // rule; kezuri does not model it and says so.
    let e = error(&g70("G1 X4 Z0\n", "2", "G2 X6 Z-2 R4\n"));
    assert!(e.starts_with("t.ngc:8:") && e.contains("kezuri does not model an arc"), "{e}");
}
