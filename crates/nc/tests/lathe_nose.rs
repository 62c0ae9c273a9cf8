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

use kezuri_nc::interp::{nose_centre_path, GCodeSystem, Lathe, Nose, Settings, TipNumbers, XMode};
use kezuri_nc::Dialect;

mod common;

use common::nose::*;

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
fn lathe_nose_linuxcnc_compensates_the_tip_and_agrees_with_rs274() {
    // The OD profile in LinuxCNC's words, its OD tool being orientation 2
    // (its figure is drawn with X down, a front tool post): the imaginary
    // tip (−R, −R) from the centre, Fanuc's 3, the tip kezuri keeps (a
    // tool table's Q is turned into Fanuc's tip as it is read). LinuxCNC's own corners: the
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
        noses: BTreeMap::from([(1, Nose { radius: 0.8, tip: 3 })]),
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
        noses: BTreeMap::from([(1, Nose { radius: 0.8, tip: 3 })]),
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
