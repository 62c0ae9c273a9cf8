//! Direct drawing dimension programming on a Fanuc lathe: FANUC Series
//! 0i-TF Plus Operator's Manual (B-64604EN), lathe system, "Direct drawing
//! dimension programming". A straight line given by its angle A (degrees
//! from +Z, counter-clockwise with +X up) and one end coordinate; C and R
//! between such lines the chamfer (its leg from the corner along each
//! move) and the corner R (an arc of that radius tangent to both). In G
//! code system A the addresses are written without the comma.
//!
//! Expected points are worked out in the comments from those definitions
//! (X a radius: the program's diameters halved) before the runs were
//! looked at.

use kezuri_geom::{Move, MoveKind, Toolpath};
use kezuri_nc::interp::{GCodeSystem, Settings};

mod common;

use common::lathe::lathe;

fn path(text: &str, settings: &Settings) -> Toolpath {
    common::run("t.nc", text, settings).path()
}

fn error(text: &str, settings: &Settings) -> (String, String) {
    let ran = common::run("t.nc", text, settings);
    let d = ran.error().unwrap_or_else(|| panic!("no error:\n{text}")).clone();
    (d.message.clone(), text[d.span.start as usize..d.span.end as usize].to_string())
}

/// A move's end (X, Z) and, for an arc, its centre.
type End = ((f64, f64), Option<(f64, f64)>);

/// The end (X, Z) of `m` and, for an arc, its centre.
fn end(m: &Move) -> End {
    let centre = match m.kind {
        MoveKind::Arc(a) => Some((a.center[0], a.center[2])),
        _ => None,
    };
    ((m.end.x, m.end.z), centre)
}

fn assert_path(got: &[Move], want: &[End]) {
    let got: Vec<_> = got.iter().map(end).collect();
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        let near = |a: (f64, f64), b: (f64, f64)| (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9;
        let centre = match (g.1, w.1) {
            (Some(a), Some(b)) => near(a, b),
            (None, None) => true,
            _ => false,
        };
        assert!(near(g.0, w.0) && centre, "move {k}: {g:?}, want {w:?}");
    }
}

#[test]
fn lathe_drawing_angle_and_corners_in_system_a_as_the_bore_program_writes_them() {
    // The bore of corpus/lathe/MaestroFusion360__easy_gcode_plot/cycle71_ID.nc
    // (radii: X89.8 → 44.9, X87.8 → 43.9, X84.45 → 42.225, X75.5 → 37.75).
    let text =
        "G18 G21 G98\nG00 X89.8 Z1.\nG01 Z0. F100.\nX87.8 R1.\nX84.45 A20. R1.8\nZ-30.05\nX75.5 C1.\nZ-40.\nM30\n";
    let p = path(text, &lathe(GCodeSystem::A));
    let (s20, c20) = 20f64.to_radians().sin_cos();
    // The A20 line from X43.9 Z0 to X42.225: ΔX = −1.675, ΔZ = ΔX·cos20/sin20
    // (moving −X along a line at 20° from +Z is moving −Z too): Z −4.602025.
    let z3 = -1.675 * c20 / s20;
    // Its direction u2 = −(sin20, cos20) in (X, Z); the face before it runs
    // −X, u1 = (−1, 0). The corner R1 at X43.9 Z0 turns by 70° (cos = u1·u2
    // = sin20): it starts and ends R·tan35° from the corner along each move,
    // its centre R from its start square to the face, toward −Z.
    let l1 = (35f64).to_radians().tan();
    let r1_start = (43.9 + l1, 0.0);
    let r1_end = (43.9 - l1 * s20, -l1 * c20);
    let r1_centre = (43.9 + l1, -1.0);
    // The corner R1.8 between the A20 line and Z−30.05 (u3 = (0, −1)) turns
    // by 20°: legs 1.8·tan10°; the arc tangent to the bore X42.225 has its
    // centre 1.8 beyond it, at X44.025, level with its end.
    let l2 = 1.8 * 10f64.to_radians().tan();
    let r2_start = (42.225 + l2 * s20, z3 + l2 * c20);
    let r2_end = (42.225, z3 - l2);
    let r2_centre = (42.225 + 1.8, z3 - l2);
    // C1 between the step down to X37.75 (−X) and Z−40 (−Z): 1 mm back
    // from the corner X37.75 Z−30.05 along each.
    let want = [
        ((44.9, 1.0), None),
        ((44.9, 0.0), None),
        (r1_start, None),
        (r1_end, Some(r1_centre)),
        (r2_start, None),
        (r2_end, Some(r2_centre)),
        ((42.225, -30.05), None),
        ((38.75, -30.05), None),
        ((37.75, -31.05), None),
        ((37.75, -40.0), None),
    ];
    assert_path(&p.moves, &want);
    assert!((z3 + 4.602025).abs() < 1e-6);
    // Each arc is tangent where it meets a line: its radius from the centre.
    for (k, r) in [(3, 1.0), (5, 1.8)] {
        let m = &p.moves[k];
        let MoveKind::Arc(a) = m.kind else { panic!("move {k} is an arc") };
        for q in [m.start, m.end] {
            assert!(((q.x - a.center[0]).hypot(q.z - a.center[2]) - r).abs() < 1e-9);
        }
    }
}

#[test]
fn lathe_drawing_comma_angle_with_z_in_system_b() {
    // System B, ",A": from X20 (radius 10) Z0, Z−10 at 150° from +Z: the
    // line's X step is ΔZ·tan150° = −10·(−1/√3) = +5.773503: X radius
    // 15.773503 (diameter 31.547005). Then X40 ,A90 would be along X only:
    // read as the line X to 20 (radius) at 90°, Z unchanged.
    let text = "G18 G21 G90 G94\nG00 X20. Z0.\nG01 Z-10. ,A150. F100.\nX40. ,A90.\nM30\n";
    let p = path(text, &lathe(GCodeSystem::B));
    let x = 10.0 + 10.0 / 3f64.sqrt();
    assert_path(&p.moves, &[((10.0, 0.0), None), ((x, -10.0), None), ((20.0, -10.0), None)]);
}

#[test]
fn lathe_drawing_angle_alone_ends_where_its_line_meets_the_next() {
    // From X20 (radius 10) Z0 at A135 (direction (cos135, sin135) in
    // (Z, X): −Z and +X at 45°), then X60 (radius 30) Z−30 at A180 (along
    // Z): the second line is X = 30, met where 10 + t·sin45 = 30, t =
    // 20·√2: Z = −20. The first block's R2 rounds that corner: the turn
    // from 135° to 180° is 45°, legs 2·tan22.5° = 0.828427 along each;
    // the arc is tangent to X30 from below, its centre at X28, level with
    // its end Z −20.828427, turning counter-clockwise (left in (Z, X)).
    let text = "G18 G21 G98\nG00 X20. Z0.\nG01 A135. R2. F100.\nX60. Z-30. A180.\nM30\n";
    let p = path(text, &lathe(GCodeSystem::A));
    let leg = 2.0 * 22.5f64.to_radians().tan();
    let h = leg / 2f64.sqrt();
    let want = [
        ((10.0, 0.0), None),
        ((30.0 - h, -20.0 + h), None),
        ((30.0, -20.0 - leg), Some((28.0, -20.0 - leg))),
        ((30.0, -30.0), None),
    ];
    assert_path(&p.moves, &want);
    let MoveKind::Arc(a) = p.moves[2].kind else { panic!("the corner R is an arc") };
    assert!(a.ccw);
    // System B writes the same with ,A and ,R.
    let text_b = "G18 G21 G90 G94\nG00 X20. Z0.\nG01 ,A135. ,R2. F100.\nX60. Z-30. ,A180.\nM30\n";
    assert_path(&path(text_b, &lathe(GCodeSystem::B)).moves, &want);
}

#[test]
fn lathe_drawing_forms_kezuri_cannot_or_the_control_will_not_run_are_located_errors() {
    let a = lathe(GCodeSystem::A);
    // Both ends and an angle: the end point twice.
    let (m, at) = error("G98 G00 X20. Z0.\nG01 X30. Z-5. A45. F100.\nM30\n", &a);
    assert!(m.contains("given twice"), "{m}");
    assert_eq!(at, "A45.");
    // The angle alone, the next block without its angle: no line to meet.
    let (m, at) = error("G98 G00 X20. Z0.\nG01 A160. F100.\nX40. Z-20.\nM30\n", &a);
    assert!(m.contains("must give X, Z and its angle"), "{m}");
    assert_eq!(at, "A160.");
    // Two parallel lines never meet.
    let (m, _) = error("G98 G00 X20. Z0.\nG01 A135. F100.\nX60. Z-30. A-45.\nM30\n", &a);
    assert!(m.contains("parallel"), "{m}");
    // A line along Z (A180) cannot reach another X: the control's alarm.
    let (m, at) = error("G98 G00 X20. Z0.\nG01 X30. A180. F100.\nM30\n", &a);
    assert!(m.contains("never reaches"), "{m}");
    assert_eq!(at, "A180.");
    // A corner R that does not fit between the lines: longer than the
    // face before it (X87.8 from X89.8 is 1 mm; R3 at 70° needs 3·tan35° =
    // 2.1 mm of it).
    let (m, _) = error("G98 G00 X89.8 Z0.\nG01 X87.8 R3. F100.\nX84.45 A20.\nZ-30.\nM30\n", &a);
    assert!(m.contains("longer than a move beside it"), "{m}");
}
