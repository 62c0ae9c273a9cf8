//! `,C` and `,R` where an arc meets a line or another arc on a Fanuc lathe:
//! FANUC Series 0i-TF Plus Operator's Manual (B-64604EN), lathe system,
//! "Chamfering and corner R" (arbitrary angle chamfering and corner
//! rounding between lines and arcs). A corner R is the arc of that radius
//! tangent to both moves; a chamfer joins the points at the length `,C`
//! from the corner along each move (along an arc, that arc length).
//!
//! X is a radius here (the machine reads X as a radius), G18: (Z, X) seen
//! from +Y, G03 counter-clockwise. Every expected point is derived in the
//! comments before the run was looked at.

use kezuri_geom::{Move, MoveKind, Toolpath};
use kezuri_nc::interp::{Control, CoordSettings, GCodeSystem, IntegerInput, Lathe, Settings, XMode};
use kezuri_nc::Dialect;

mod common;

fn lathe() -> Settings {
    Settings {
        dialect: Dialect::FanucLathe,
        integer_input: IntegerInput::Increments,
        coords: CoordSettings { control: Control::Fanuc, ..CoordSettings::default() },
        lathe: Some(Lathe { x: XMode::Radius, system: GCodeSystem::B }),
        ..Settings::default()
    }
}

fn path(body: &str) -> Toolpath {
    common::run("t.nc", &format!("G18 G21 G90 G94\n{body}M30\n"), &lathe()).path()
}

fn error(body: &str) -> (String, String) {
    let text = format!("G18 G21 G90 G94\n{body}M30\n");
    let ran = common::run("t.nc", &text, &lathe());
    let d = ran.error().unwrap_or_else(|| panic!("no error:\n{text}")).clone();
    (d.message.clone(), text[d.span.start as usize..d.span.end as usize].to_string())
}

/// (X, Z) end, and for an arc its (X, Z) centre and whether it turns
/// counter-clockwise.
type End = ((f64, f64), Option<((f64, f64), bool)>);

fn end(m: &Move) -> End {
    let arc = match m.kind {
        MoveKind::Arc(a) => Some(((a.center[0], a.center[2]), a.ccw)),
        _ => None,
    };
    ((m.end.x, m.end.z), arc)
}

fn assert_path(p: &Toolpath, want: &[End]) {
    let got: Vec<End> = p.moves.iter().map(end).collect();
    assert_eq!(got.len(), want.len(), "{got:?}");
    let near = |a: (f64, f64), b: (f64, f64)| (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9;
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        let arc = match (g.1, w.1) {
            (Some((c, ccw)), Some((wc, wccw))) => near(c, wc) && ccw == wccw,
            (None, None) => true,
            _ => false,
        };
        assert!(near(g.0, w.0) && arc, "move {k}: {g:?}, want {w:?}");
    }
    for w in p.moves.windows(2) {
        assert_eq!(w[1].start, w[0].end, "one continuous path");
    }
}

/// Every arc of `p` keeps its radius: start and end equally far from its centre.
fn assert_round(p: &Toolpath) {
    for m in &p.moves {
        if let MoveKind::Arc(a) = m.kind {
            let r0 = (m.start.x - a.center[0]).hypot(m.start.z - a.center[2]);
            let r1 = (m.end.x - a.center[0]).hypot(m.end.z - a.center[2]);
            assert!((r0 - r1).abs() < 1e-9, "{m:?}");
        }
    }
}

// The quarter circle Q: G03 from X10 Z−10 to X20 Z−20 round X10 Z−20
// (K−10), radius 10, from the angle 0 (in (Z, X): +Z) to 90° (+X); at its
// start it runs +X, at its end −Z.

#[test]
fn lathe_corner_r_between_a_line_and_an_arc() {
    // Z−10 (−Z along X10) then Q: the path turns from −Z to +X, a right
    // turn. The corner arc's centre is 2 right of both: on X = 12 (the
    // line moved +X) and on the circle of radius 10 + 2 round Q's centre
    // (Q turns left, so its right is outward): (Z + 20)² + 2² = 12², Z =
    // −20 + √140 (the meeting nearer the corner). It touches the line at
    // X10 below its centre and Q where Q's radius through its centre
    // meets Q: Q's centre + 10·(√140, 2)/12 in (Z, X). It turns clockwise.
    let p = path("G00 X10. Z1.\nG01 Z0. F100.\nZ-10. ,R2.\nG03 X20. Z-20. K-10.\n");
    let zc = -20.0 + 140f64.sqrt();
    let b = (10.0 + 10.0 * 2.0 / 12.0, -20.0 + 10.0 * 140f64.sqrt() / 12.0);
    assert_path(
        &p,
        &[
            ((10.0, 1.0), None),
            ((10.0, 0.0), None),
            ((10.0, zc), None),
            (b, Some(((12.0, zc), false))),
            ((20.0, -20.0), Some(((10.0, -20.0), true))),
        ],
    );
    assert_round(&p);
}

#[test]
fn lathe_chamfer_between_a_line_and_an_arc_is_its_length_along_each() {
    // ,C1: 1 back along the line from the corner (Z−9), 1 along Q from
    // its start: the angle 1/10 rad on it, X 10 + 10·sin 0.1, Z −20 +
    // 10·cos 0.1.
    let p = path("G00 X10. Z1.\nG01 Z0. F100.\nZ-10. ,C1.\nG03 X20. Z-20. K-10.\n");
    let b = (10.0 + 10.0 * 0.1f64.sin(), -20.0 + 10.0 * 0.1f64.cos());
    assert_path(
        &p,
        &[
            ((10.0, 1.0), None),
            ((10.0, 0.0), None),
            ((10.0, -9.0), None),
            (b, None),
            ((20.0, -20.0), Some(((10.0, -20.0), true))),
        ],
    );
    assert_round(&p);
}

#[test]
fn lathe_corner_r_between_an_arc_and_a_line() {
    // Q then X30 (+X along Z−20): from −Z to +X, a right turn. Centre on
    // Z = −18 (the line moved 2 to its right, +Z) and on the circle of
    // radius 12 round Q's centre: (X − 10)² + 2² = 12², X = 10 + √140.
    // Q ends where its radius through that centre meets it: Q's centre +
    // 10·(2, √140)/12 in (Z, X); the line starts at X 10 + √140.
    let p = path("G00 X10. Z1.\nG01 Z-10. F100.\nG03 X20. Z-20. K-10. ,R2.\nG01 X30.\n");
    let xc = 10.0 + 140f64.sqrt();
    let a = (10.0 + 10.0 * 140f64.sqrt() / 12.0, -20.0 + 10.0 * 2.0 / 12.0);
    assert_path(
        &p,
        &[
            ((10.0, 1.0), None),
            ((10.0, -10.0), None),
            (a, Some(((10.0, -20.0), true))),
            ((xc, -20.0), Some(((xc, -18.0), false))),
            ((30.0, -20.0), None),
        ],
    );
    assert_round(&p);
}

#[test]
fn lathe_corner_r_between_two_arcs() {
    // Q, then G02 from X20 Z−20 round X20 Z−30 (K−10) to X10 Z−30: it
    // starts running −X (clockwise from the angle 0). From −Z to −X: a left
    // turn. Centre 2 left of both: on the circle of radius 10 − 2 = 8 round
    // c1 = (Z−20, X10) (left of a counter-clockwise arc is inward) and of
    // 10 + 2 = 12 round c2 = (Z−30, X20) (left of a clockwise arc is
    // outward). |c2 − c1| = √200; along it a = (8² − 12² + 200)/(2√200)
    // from c1, h = √(8² − a²) across; the meeting nearer the corner
    // (Z−20, X20). The arc touches each where its radius through the
    // centre meets it, and turns counter-clockwise.
    let p = path("G00 X10. Z1.\nG01 Z-10. F100.\nG03 X20. Z-20. K-10. ,R2.\nG02 X10. Z-30. K-10.\n");
    let (c1, c2) = ((-20.0, 10.0), (-30.0, 20.0)); // (Z, X)
    let d = 200f64.sqrt();
    let u = ((c2.0 - c1.0) / d, (c2.1 - c1.1) / d);
    let a = (64.0 - 144.0 + 200.0) / (2.0 * d);
    let h = (64.0 - a * a).sqrt();
    let m = (c1.0 + a * u.0, c1.1 + a * u.1);
    let options = [(m.0 - h * u.1, m.1 + h * u.0), (m.0 + h * u.1, m.1 - h * u.0)];
    let dist = |p: (f64, f64)| (p.0 + 20.0).hypot(p.1 - 20.0);
    let c = if dist(options[0]) < dist(options[1]) { options[0] } else { options[1] };
    let touch = |o: (f64, f64), r: f64| {
        let l = (c.0 - o.0).hypot(c.1 - o.1);
        (o.1 + r * (c.1 - o.1) / l, o.0 + r * (c.0 - o.0) / l) // (X, Z)
    };
    assert_path(
        &p,
        &[
            ((10.0, 1.0), None),
            ((10.0, -10.0), None),
            (touch(c1, 10.0), Some(((10.0, -20.0), true))),
            (touch(c2, 10.0), Some(((c.1, c.0), true))),
            ((10.0, -30.0), Some(((20.0, -30.0), false))),
        ],
    );
    assert_round(&p);
    // The corner arc is tangent to both: its centre 8 from c1, 12 from c2.
    assert!(((c.0 - c1.0).hypot(c.1 - c1.1) - 8.0).abs() < 1e-9);
    assert!(((c.0 - c2.0).hypot(c.1 - c2.1) - 12.0).abs() < 1e-9);
}

#[test]
fn lathe_chamfer_or_corner_next_to_an_arc_that_does_not_fit_is_the_controls_alarm() {
    // Q is 10·π/2 = 15.708 mm long: ,C16 does not fit on it.
    let (m, at) = error("G00 X10. Z1.\nG01 Z0. F100.\nZ-20. ,C16.\nG03 X20. Z-30. K-10.\n");
    assert!(m.contains("does not fit"), "{m}");
    assert_eq!(at, ",C16.");
    // R20 between Z0…Z−10 and Q: its centre on X30 and on the circle of
    // radius 30 round Q's centre, Z −20 + √500 = 2.36: beyond the line's
    // start, the arc needs 12.36 mm of a 10 mm line.
    let (m, at) = error("G00 X10. Z1.\nG01 Z0. F100.\nZ-10. ,R20.\nG03 X20. Z-20. K-10.\n");
    assert!(m.contains("does not fit"), "{m}");
    assert_eq!(at, ",R20.");
    // A line into an arc tangent to it: no corner. Z−10 then an arc that
    // starts running −Z (G03 round X0 Z−10: at X10 it runs −Z).
    let (m, _) = error("G00 X10. Z1.\nG01 Z0. F100.\nZ-10. ,R1.\nG03 X0. Z-20. I-10.\n");
    assert!(m.contains("no corner"), "{m}");
}
