//! G72 type I with a shape that goes deeper as it moves in (a recessed
//! face): FANUC Series 0i-TF Plus Operator's Manual (B-64604EN), lathe
//! system, "Multiple repetitive cycle", G72. The shape of type I must be a
//! monotonous change in X and Z: the alarms PS0064 and PS0329 are for a
//! shape that is "not a monotonous increase or decrease" of a plane axis.
//! Z 0 then −2 while X goes in is a monotonous decrease, and runs. The cuts
//! of Δd are made from the start point A toward A' (the shape's start), so
//! they reach A' only; the cut along the shape (moved by the allowance)
//! takes the recess. Expected moves are worked out below before the output
//! was looked at; X is a radius (the program's X a diameter).

use kezuri_nc::interp::Settings;
use kezuri_nc::Dialect;

mod common;

fn fanuc() -> Settings {
    Settings { dialect: Dialect::FanucLathe, ..Settings::default() }
}

/// The face of corpus/lathe/MaestroFusion360__easy_gcode_plot/face_groove.nc:
/// A at X102 (radius 51) Z3; the shape A' X102 Z0, in to X82 along Z0, down
/// to Z−2, in to X42.
const FACE: &str = "S1000 M03 G00 X102. Z3.
G72 W2. R0.3
G72 P30 Q40 W0.15 F0.22
N30 G0 Z0.
G1 X82.
Z-2.
N40 X42.
M30
";

#[test]
fn lathe_g72_type_one_shape_going_deeper_runs_cuts_to_a_prime_then_follows_the_shape() {
    // In the facing frame (a = 51 − radius along the cut, d = 3 − Z into
    // the stock) the shape is (0, 3) (10, 3) (10, 5) (30, 5): d rises
    // only, monotonous. W0.15 leaves 0.15 on the faces: the shape the
    // cuts stop at is 0.15 shallower, (0, 2.85) … (30, 4.85).
    // Cuts of Δd = 2 from A toward A' (d 2.85): one, at d 2 (Z1), in at
    // rapid (N30 is G00) to X51 Z1, along to the shape's end a 30 (radius
    // 21: the shape lies deeper all the way), out at 45° by R0.3 to radius
    // 21.3 Z1.3, back to radius 51 at rapid.
    // Then the cut along the shape moved by 0.15: in to Z0.15 at rapid,
    // radius 41, down to Z−1.85, in to radius 21, out along Z to A's Z3
    // (at rapid), back to radius 51.
    let o = common::run("t.nc", FACE, &fanuc()).completed();
    let got: Vec<_> =
        o.toolpath.moves.iter().map(|m| (m.kind == kezuri_geom::MoveKind::Rapid, m.end.x, m.end.z)).collect();
    let want = [
        (true, 51.0, 3.0),
        (true, 51.0, 1.0),
        (false, 21.0, 1.0),
        (true, 21.3, 1.3),
        (true, 51.0, 1.3),
        (true, 51.0, 0.15),
        (false, 41.0, 0.15),
        (false, 41.0, -1.85),
        (false, 21.0, -1.85),
        (true, 21.0, 3.0),
        (true, 51.0, 3.0),
    ];
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (k, (g, w)) in got.iter().zip(&want).enumerate() {
        assert!(g.0 == w.0 && (g.1 - w.1).abs() < 1e-9 && (g.2 - w.2).abs() < 1e-9, "move {k}: {g:?}, want {w:?}");
    }
}

#[test]
fn lathe_g72_type_one_shape_going_deeper_then_back_up_is_the_controls_alarm() {
    // Z0, down to Z−2, then back up to Z−1: not a monotonous change in Z.
    let text = FACE.replace("N40 X42.", "X62.\nZ-1.\nN40 X42.");
    let ran = common::run("t.nc", &text, &fanuc());
    let d = ran.error().expect("the control's alarm").clone();
    assert!(d.message.contains("PS0329") && d.message.contains("type II"), "{}", d.message);
    assert_eq!(&text[d.span.start as usize..d.span.end as usize], "Z-1.");
}
