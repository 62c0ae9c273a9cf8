//! Cutter radius compensation, hand-derived cases. Every expected point
//! below was worked out on paper from the rule it names (offset lines,
//! offset circles, their intersections); none is copied from a run.

use kezuri_geom::{Arc, Axes, Move, MoveKind, Plane};
use kezuri_nc::interp::comp::{compensate, Approach, Comp, Rules, Side};
use kezuri_nc::ErrorKind;

const FANUC_A: Rules = Rules::Fanuc { startup: Approach::A };
const FANUC_B: Rules = Rules::Fanuc { startup: Approach::B };
const LCNC: Rules = Rules::LinuxCnc;
const S2: f64 = std::f64::consts::SQRT_2;
const H: f64 = std::f64::consts::FRAC_1_SQRT_2;

fn at(x: f64, y: f64) -> Axes {
    Axes { x, y, ..Axes::ZERO }
}
fn line(a: (f64, f64), b: (f64, f64)) -> Move {
    Move { kind: MoveKind::Feed, start: at(a.0, a.1), end: at(b.0, b.1), feed: 500.0, ..Move::default() }
}
fn arc(a: (f64, f64), b: (f64, f64), c: (f64, f64), ccw: bool) -> Move {
    let kind = MoveKind::Arc(Arc { center: [c.0, c.1, 0.0], plane: Plane::Xy, ccw, turns: 0 });
    Move { kind, ..line(a, b) }
}
/// Numbers the moves' lines 10, 20, 30 … so that outputs can be traced.
fn numbered(mut moves: Vec<Move>) -> Vec<Move> {
    for (k, m) in moves.iter_mut().enumerate() {
        m.line = 10 * (k as u32 + 1);
    }
    moves
}
fn comp(side: Side, radius: f64) -> Option<Comp> {
    Some(Comp { side, radius, plane: Plane::Xy })
}
/// Tags: the first `on` moves compensated, the rest not.
fn tags(n: usize, on: usize, c: Option<Comp>) -> Vec<Option<Comp>> {
    (0..n).map(|k| if k < on { c } else { None }).collect()
}

/// What an output move is, for comparison: its end, its source line, and
/// for an arc its centre and direction.
#[derive(Debug)]
enum Want {
    L(f64, f64, u32),
    A(f64, f64, u32, (f64, f64), bool),
}
use Want::{A, L};

fn check(out: &[Move], want: &[Want]) {
    assert_eq!(out.len(), want.len(), "moves: {out:#?}");
    for (k, (m, w)) in out.iter().zip(want).enumerate() {
        if k > 0 {
            assert_eq!(m.start, out[k - 1].end, "move {k} starts where {} ends", k - 1);
        }
        let (x, y, line) = match *w {
            L(x, y, line) => {
                assert!(matches!(m.kind, MoveKind::Feed | MoveKind::Rapid), "move {k} is straight: {m:?}");
                (x, y, line)
            }
            A(x, y, line, c, ccw) => {
                let MoveKind::Arc(a) = m.kind else { panic!("move {k} is an arc: {m:?}") };
                assert!((a.center[0] - c.0).abs() < 1e-9 && (a.center[1] - c.1).abs() < 1e-9, "move {k} centre {a:?}");
                assert_eq!(a.ccw, ccw, "move {k} direction");
                let (r0, r1) = (a.radius(m.start), a.radius(m.end));
                assert!((r0 - r1).abs() < 1e-9, "move {k} is a circular arc: {r0} {r1}");
                (x, y, line)
            }
        };
        assert!((m.end.x - x).abs() < 1e-9 && (m.end.y - y).abs() < 1e-9, "move {k} ends at ({x}, {y}): {m:?}");
        assert_eq!(m.line, line, "move {k} comes from line {line}");
    }
}

fn err(moves: &[Move], tags: &[Option<Comp>], rules: Rules) -> (usize, String) {
    let e = compensate(moves, tags, rules).expect_err("refused");
    assert_eq!(e.kind, ErrorKind::Compensation, "{e}");
    (e.move_index().expect("at a move"), e.message)
}

/// Start-up along +X, a collinear move, a left turn (inside for G41) and a
/// cancel move along +X.
fn inside_path() -> Vec<Move> {
    numbered(vec![
        line((0.0, 0.0), (10.0, 0.0)),
        line((10.0, 0.0), (20.0, 0.0)),
        line((20.0, 0.0), (20.0, 10.0)),
        line((20.0, 10.0), (30.0, 10.0)),
    ])
}

#[test]
fn inside_corner_fanuc_a_and_b() {
    // G41 r=1. Start-up into a collinear move: the offset lines are one,
    // y=1, so the start-up ends at (10,1). Inside corner at (20,0): y=1
    // meets x=19 at (19,1). Cancel turns right (outside, 90° = obtuse):
    // type A keeps the perpendicular of the last move, (20,10)+(-1,0);
    // type B takes the intersection of x=19 with the cancel's offset line
    // y=11: (19,11).
    let moves = inside_path();
    let t = tags(4, 3, comp(Side::Left, 1.0));
    check(
        &compensate(&moves, &t, FANUC_A).unwrap(),
        &[L(10.0, 1.0, 10), L(19.0, 1.0, 20), L(19.0, 10.0, 30), L(30.0, 10.0, 40)],
    );
    check(
        &compensate(&moves, &t, FANUC_B).unwrap(),
        &[L(10.0, 1.0, 10), L(19.0, 1.0, 20), L(19.0, 11.0, 30), L(30.0, 10.0, 40)],
    );
}

#[test]
fn inside_corner_linuxcnc() {
    // Entry (0,0)->(10,0) ends perpendicular at (10,1); the collinear move
    // (beta 0) needs nothing; the concave corner moves the end of the
    // second move to (19,1); G40 leaves from the last offset point (19,10).
    let moves = inside_path();
    let out = compensate(&moves, &tags(4, 3, comp(Side::Left, 1.0)), LCNC).unwrap();
    check(&out, &[L(10.0, 1.0, 10), L(19.0, 1.0, 20), L(19.0, 10.0, 30), L(30.0, 10.0, 40)]);
}

#[test]
fn outside_obtuse_corner_and_negative_radius() {
    // G42 r=1 on the same path: the left turn at (20,0) is outside at 90°
    // (obtuse): y=-1 meets x=21 at (21,-1). The right turn at (20,10) into
    // the cancel move is inside: x=21 meets the cancel's offset y=9.
    // G41 with a register of -1 is G42 with 1.
    let moves = inside_path();
    let want = [L(10.0, -1.0, 10), L(21.0, -1.0, 20), L(21.0, 9.0, 30), L(30.0, 10.0, 40)];
    for rules in [FANUC_A, FANUC_B] {
        check(&compensate(&moves, &tags(4, 3, comp(Side::Right, 1.0)), rules).unwrap(), &want);
        check(&compensate(&moves, &tags(4, 3, comp(Side::Left, -1.0)), rules).unwrap(), &want);
    }
    // LinuxCNC: the convex corner gets an arc of r around (20,0) from
    // (20,-1) to (21,0), counter-clockwise for G42, made for move 3.
    let want = [
        L(10.0, -1.0, 10),
        L(20.0, -1.0, 20),
        A(21.0, 0.0, 30, (20.0, 0.0), true),
        L(21.0, 10.0, 30),
        L(30.0, 10.0, 40),
    ];
    check(&compensate(&moves, &tags(4, 3, comp(Side::Left, -1.0)), LCNC).unwrap(), &want);
}

#[test]
fn outside_acute_corner() {
    // G41 r=1: (-10,0)->(0,0)->(10,0) then toward (0,-10), a right turn of
    // 135° (outside, 45° on the work side). t1=(1,0), t2=(-1,-1)/√2,
    // n2=(1,-1)/√2. Fanuc: the first offset line extended by r ends at
    // (10,1)+(1,0)=(11,1); the second starts r before its perpendicular
    // point (10+1/√2,-1/√2)-t2 = (10+√2,0); the last move ends on its
    // perpendicular (0,-10)+n2.
    let moves =
        numbered(vec![line((-10.0, 0.0), (0.0, 0.0)), line((0.0, 0.0), (10.0, 0.0)), line((10.0, 0.0), (0.0, -10.0))]);
    let t = tags(3, 3, comp(Side::Left, 1.0));
    let end = L(H, -10.0 - H, 30);
    check(&compensate(&moves, &t, FANUC_A).unwrap(), &[L(0.0, 1.0, 10), L(11.0, 1.0, 20), L(10.0 + S2, 0.0, 20), end]);
    // LinuxCNC: an arc of r around (10,0), clockwise for G41, from (10,1)
    // to (10+1/√2,-1/√2).
    let out = compensate(&moves, &t, LCNC).unwrap();
    check(&out, &[L(0.0, 1.0, 10), L(10.0, 1.0, 20), A(10.0 + H, -H, 30, (10.0, 0.0), false), L(H, -10.0 - H, 30)]);
}

#[test]
fn line_to_arc_inside() {
    // G41 r=1: line along +X to (10,0), then G03 around (4,8) (R=10) to
    // (14,8); its start tangent (0.8,0.6) turns left: inside. Offset line
    // y=1 meets the offset circle (R-r=9): (x-4)²+49=81, x=4+4√2 (the
    // root nearest the corner). The arc ends on its perpendicular
    // (14,8)+(-1,0); the cancel along +Y is tangent, so nothing is added.
    let moves = numbered(vec![
        line((-10.0, 0.0), (0.0, 0.0)),
        line((0.0, 0.0), (10.0, 0.0)),
        arc((10.0, 0.0), (14.0, 8.0), (4.0, 8.0), true),
        line((14.0, 8.0), (14.0, 20.0)),
    ]);
    let want = [L(0.0, 1.0, 10), L(4.0 + 4.0 * S2, 1.0, 20), A(13.0, 8.0, 30, (4.0, 8.0), true), L(14.0, 20.0, 40)];
    for rules in [FANUC_A, FANUC_B, LCNC] {
        check(&compensate(&moves, &tags(4, 3, comp(Side::Left, 1.0)), rules).unwrap(), &want);
    }
}

#[test]
fn arc_to_line_outside() {
    // G41 r=1: tangent start-up into G02 around (0,-10) to (10,-10) (tool
    // outside, offset radius 11), then a line toward (0,-20): from the
    // arc's end tangent (0,-1) a right turn of 45° (outside, obtuse).
    // Fanuc, tangent extension: the arc ends on its perpendicular (11,-10);
    // the tangent's offset line x=11 meets the line's offset (through
    // (10+1/√2,-10-1/√2) along (-1,-1)) at y=-9-√2.
    let moves = numbered(vec![
        line((-10.0, 0.0), (0.0, 0.0)),
        arc((0.0, 0.0), (10.0, -10.0), (0.0, -10.0), false),
        line((10.0, -10.0), (0.0, -20.0)),
    ]);
    let t = tags(3, 3, comp(Side::Left, 1.0));
    let out = compensate(&moves, &t, FANUC_A).unwrap();
    check(
        &out,
        &[L(0.0, 1.0, 10), A(11.0, -10.0, 20, (0.0, -10.0), false), L(11.0, -9.0 - S2, 20), L(H, -20.0 - H, 30)],
    );
    // LinuxCNC: an arc around (10,-10) from (11,-10) to (10+1/√2,-10-1/√2).
    let out = compensate(&moves, &t, LCNC).unwrap();
    let want = [
        L(0.0, 1.0, 10),
        A(11.0, -10.0, 20, (0.0, -10.0), false),
        A(10.0 + H, -10.0 - H, 30, (10.0, -10.0), false),
        L(H, -20.0 - H, 30),
    ];
    check(&out, &want);
}

#[test]
fn arc_to_arc_tangent() {
    // G41 r=1: G03 around (0,5) (tool inside, radius 4) to (0,10), then
    // G02 around (0,15) (tool outside, radius 6): an S bend, tangent at
    // (0,10). Both offset circles pass through (0,9); the last arc ends on
    // its perpendicular (0,21).
    let moves = numbered(vec![
        line((-10.0, 0.0), (0.0, 0.0)),
        arc((0.0, 0.0), (0.0, 10.0), (0.0, 5.0), true),
        arc((0.0, 10.0), (0.0, 20.0), (0.0, 15.0), false),
    ]);
    let want = [L(0.0, 1.0, 10), A(0.0, 9.0, 20, (0.0, 5.0), true), A(0.0, 21.0, 30, (0.0, 15.0), false)];
    for rules in [FANUC_A, FANUC_B, LCNC] {
        check(&compensate(&moves, &tags(3, 3, comp(Side::Left, 1.0)), rules).unwrap(), &want);
    }
}

fn two_arcs() -> Vec<Move> {
    // G03 around (0,5) from (0,0) to (5,5) (end tangent (0,1)), then G03
    // around (1,2) (R=5) from (5,5) to (1,7) (start tangent (-0.6,0.8)):
    // a left turn of 36.87°.
    numbered(vec![
        line((-10.0, 0.0), (0.0, 0.0)),
        arc((0.0, 0.0), (5.0, 5.0), (0.0, 5.0), true),
        arc((5.0, 5.0), (1.0, 7.0), (1.0, 2.0), true),
    ])
}

#[test]
fn arc_to_arc_inside() {
    // G41 r=1: inside both arcs, offset circles (0,5) r4 and (1,2) r4.
    // Centres √10 apart: the chord's midpoint (0.5,3.5), half chord
    // √(16-2.5); across the centre line, direction (3,1)/√10, so the point
    // nearest (5,5) is (0.5+3√1.35, 3.5+√1.35). The last arc ends at
    // (1,7)+(0,-1).
    let q = 1.35f64.sqrt();
    let want = [L(0.0, 1.0, 10), A(0.5 + 3.0 * q, 3.5 + q, 20, (0.0, 5.0), true), A(1.0, 6.0, 30, (1.0, 2.0), true)];
    for rules in [FANUC_A, LCNC] {
        check(&compensate(&two_arcs(), &tags(3, 3, comp(Side::Left, 1.0)), rules).unwrap(), &want);
    }
}

#[test]
fn arc_to_arc_outside() {
    // G42 r=1: outside both arcs. The first ends on its perpendicular
    // (5,5)+(1,0) = (6,5); the second starts at (5,5)+(0.8,0.6).
    // Fanuc: the tangent offset lines x=6 and (5.8,5.6)+t(-0.6,0.8) meet
    // at t=-1/3: (6,16/3); straight moves to it and on to (5.8,5.6).
    let t = tags(3, 3, comp(Side::Right, 1.0));
    let out = compensate(&two_arcs(), &t, FANUC_A).unwrap();
    let want = [
        L(0.0, -1.0, 10),
        A(6.0, 5.0, 20, (0.0, 5.0), true),
        L(6.0, 16.0 / 3.0, 20),
        L(5.8, 5.6, 20),
        A(1.0, 8.0, 30, (1.0, 2.0), true),
    ];
    check(&out, &want);
    // LinuxCNC: an arc of r around (5,5), counter-clockwise for G42.
    let out = compensate(&two_arcs(), &t, LCNC).unwrap();
    let want = [
        L(0.0, -1.0, 10),
        A(6.0, 5.0, 20, (0.0, 5.0), true),
        A(5.8, 5.6, 30, (5.0, 5.0), true),
        A(1.0, 8.0, 30, (1.0, 2.0), true),
    ];
    check(&out, &want);
}

#[test]
fn start_up_types_a_and_b() {
    // G41 r=1, start-up (0,0)->(10,0), then a right turn (outside).
    // Obtuse (next along -Y): A ends on the next move's perpendicular
    // (10,0)+(1,0); B at the intersection of y=1 and x=11.
    let obtuse = numbered(vec![line((0.0, 0.0), (10.0, 0.0)), line((10.0, 0.0), (10.0, -10.0))]);
    let t = tags(2, 2, comp(Side::Left, 1.0));
    check(&compensate(&obtuse, &t, FANUC_A).unwrap(), &[L(11.0, 0.0, 10), L(11.0, -10.0, 20)]);
    check(&compensate(&obtuse, &t, FANUC_B).unwrap(), &[L(11.0, 1.0, 10), L(11.0, -10.0, 20)]);
    // Acute (next toward (0,-10), n2=(1,-1)/√2): A ends at
    // (10+1/√2,-1/√2); B runs to (11,1), then to (10+√2,0).
    let acute = numbered(vec![line((0.0, 0.0), (10.0, 0.0)), line((10.0, 0.0), (0.0, -10.0))]);
    check(&compensate(&acute, &t, FANUC_A).unwrap(), &[L(10.0 + H, -H, 10), L(H, -10.0 - H, 20)]);
    check(&compensate(&acute, &t, FANUC_B).unwrap(), &[L(11.0, 1.0, 10), L(10.0 + S2, 0.0, 10), L(H, -10.0 - H, 20)]);
}

#[test]
fn cancel_types_a_and_b() {
    // G41 r=1 along +X to (10,0), then G40 toward (0,-10): outside acute.
    // A: the last move ends on its perpendicular (10,1), the cancel goes
    // from there. B: extended to (11,1), a vector to (10+√2,0), then the
    // cancel move.
    let moves =
        numbered(vec![line((-10.0, 0.0), (0.0, 0.0)), line((0.0, 0.0), (10.0, 0.0)), line((10.0, 0.0), (0.0, -10.0))]);
    let t = tags(3, 2, comp(Side::Left, 1.0));
    check(&compensate(&moves, &t, FANUC_A).unwrap(), &[L(0.0, 1.0, 10), L(10.0, 1.0, 20), L(0.0, -10.0, 30)]);
    let want = [L(0.0, 1.0, 10), L(11.0, 1.0, 20), L(10.0 + S2, 0.0, 20), L(0.0, -10.0, 30)];
    check(&compensate(&moves, &t, FANUC_B).unwrap(), &want);
}

fn at3(x: f64, y: f64, z: f64) -> Axes {
    Axes { x, y, z, ..Axes::ZERO }
}

#[test]
fn plunge_between_compensated_moves() {
    // G41 r=1: along +X to (10,0), a plunge to Z-5, then up +Y (inside).
    // The corner is found past the plunge: (9,1), and the plunge is made
    // there.
    let mut moves = vec![line((-10.0, 0.0), (0.0, 0.0)), line((0.0, 0.0), (10.0, 0.0))];
    moves.push(Move { start: at3(10.0, 0.0, 0.0), end: at3(10.0, 0.0, -5.0), ..line((0.0, 0.0), (0.0, 0.0)) });
    moves.push(Move { start: at3(10.0, 0.0, -5.0), end: at3(10.0, 10.0, -5.0), ..line((0.0, 0.0), (0.0, 0.0)) });
    let moves = numbered(moves);
    let t = tags(4, 4, comp(Side::Left, 1.0));
    for rules in [FANUC_A, LCNC] {
        let out = compensate(&moves, &t, rules).unwrap();
        check(&out, &[L(0.0, 1.0, 10), L(9.0, 1.0, 20), L(9.0, 1.0, 30), L(9.0, 10.0, 40)]);
        assert_eq!((out[2].start.z, out[2].end.z, out[3].end.z), (0.0, -5.0, -5.0));
    }
    // Three blocks without plane travel: past Fanuc's look-ahead, so the
    // move before them ends on its perpendicular (10,1) and the next
    // straight move goes from there to its own end (9,10). LinuxCNC has no
    // such limit.
    let mut long = moves[..3].to_vec();
    for k in 0..2 {
        let z = -5.0 - f64::from(k);
        long.push(Move { start: at3(10.0, 0.0, z), end: at3(10.0, 0.0, z - 1.0), ..moves[2] });
    }
    long.push(Move { start: at3(10.0, 0.0, -7.0), end: at3(10.0, 10.0, -7.0), ..moves[3] });
    let t = tags(6, 6, comp(Side::Left, 1.0));
    let out = compensate(&long, &t, FANUC_A).unwrap();
    check(
        &out,
        &[L(0.0, 1.0, 10), L(10.0, 1.0, 20), L(10.0, 1.0, 30), L(10.0, 1.0, 30), L(10.0, 1.0, 30), L(9.0, 10.0, 40)],
    );
    let out = compensate(&long, &t, LCNC).unwrap();
    check(
        &out,
        &[L(0.0, 1.0, 10), L(9.0, 1.0, 20), L(9.0, 1.0, 30), L(9.0, 1.0, 30), L(9.0, 1.0, 30), L(9.0, 10.0, 40)],
    );
}

#[test]
fn g18_plane() {
    // G18: the plane's axes are (Z, X), seen from +Y. G41 r=1 moving +Z
    // puts the tool on +X. Start-up Z-10 -> Z0 at X0, on to Z10, then +X
    // (a left turn: inside): the corner is Z9 X1. Y stays 3.
    let zx = |z: f64, x: f64| Axes { x, y: 3.0, z, ..Axes::ZERO };
    let mv = |a: (f64, f64), b: (f64, f64)| Move {
        kind: MoveKind::Feed,
        start: zx(a.0, a.1),
        end: zx(b.0, b.1),
        ..Move::default()
    };
    let moves = vec![mv((-10.0, 0.0), (0.0, 0.0)), mv((0.0, 0.0), (10.0, 0.0)), mv((10.0, 0.0), (10.0, 10.0))];
    let c = Some(Comp { side: Side::Left, radius: 1.0, plane: Plane::Zx });
    for rules in [FANUC_A, LCNC] {
        let out = compensate(&moves, &[c; 3], rules).unwrap();
        let ends: Vec<[f64; 3]> = out.iter().map(|m| m.end.xyz()).collect();
        assert_eq!(ends, vec![[1.0, 3.0, 0.0], [1.0, 3.0, 9.0], [10.0, 3.0, 9.0]]);
    }
    // LinuxCNC refuses G19.
    let c = Some(Comp { side: Side::Left, radius: 1.0, plane: Plane::Yz });
    assert_eq!(err(&moves, &[c; 3], LCNC), (0, "Cutter radius compensation allowed only in XY, XZ planes".into()));
}

#[test]
fn backwards_move_is_interference() {
    // G41 r=2: a 1 mm step between two inside corners. Offsets: y=2, x=8
    // and y=1-2=-1, so move 2 would run from (8,2) down to (8,-1) against
    // its programmed +Y.
    let moves = vec![
        line((-10.0, 0.0), (0.0, 0.0)),
        line((0.0, 0.0), (10.0, 0.0)),
        line((10.0, 0.0), (10.0, 1.0)),
        line((10.0, 1.0), (0.0, 1.0)),
    ];
    let t = tags(4, 4, comp(Side::Left, 2.0));
    assert_eq!(
        err(&moves, &t, FANUC_A),
        (2, "interference: the compensated move runs backwards (Fanuc alarm PS0041)".into())
    );
    assert_eq!(
        err(&moves, &t, LCNC),
        (2, "Straight feed in concave corner cannot be reached by the tool without gouging".into())
    );
    // With r=0.4 the step is long enough: (9.6,0.4) to (9.6,0.6).
    let out = compensate(&moves, &tags(4, 4, comp(Side::Left, 0.4)), FANUC_A).unwrap();
    assert!((out[2].end.x - 9.6).abs() < 1e-9 && (out[2].end.y - 0.6).abs() < 1e-9);
}

#[test]
fn inside_arc_smaller_than_cutter() {
    // G41 r=2 inside a G03 of radius 1 (move 2).
    let moves = vec![
        line((-10.0, 0.0), (0.0, 0.0)),
        line((0.0, 0.0), (10.0, 0.0)),
        arc((10.0, 0.0), (10.0, 2.0), (10.0, 1.0), true),
    ];
    let t = tags(3, 3, comp(Side::Left, 2.0));
    assert_eq!(err(&moves, &t, FANUC_B).0, 2);
    assert!(err(&moves, &t, FANUC_B).1.contains("PS0041"));
    assert_eq!(err(&moves, &t, LCNC), (2, "Tool radius not less than arc radius with comp".into()));
    // G42 puts the tool outside the same arc: no interference.
    assert!(compensate(&moves, &tags(3, 3, comp(Side::Right, 2.0)), LCNC).is_ok());
}

#[test]
fn arcs_on_start_up_and_cancel() {
    // Fanuc refuses an arc as start-up or cancel move (PS0034).
    let moves = vec![arc((0.0, 0.0), (20.0, 0.0), (10.0, 0.0), true), line((20.0, 0.0), (20.0, 10.0))];
    let (k, m) = err(&moves, &tags(2, 2, comp(Side::Left, 1.0)), FANUC_A);
    assert!(k == 0 && m.contains("PS0034"), "{m}");
    let moves2 = vec![line((-10.0, 0.0), (0.0, 0.0)), arc((0.0, 0.0), (20.0, 0.0), (10.0, 0.0), true)];
    let (k, m) = err(&moves2, &tags(2, 1, comp(Side::Left, 1.0)), FANUC_A);
    assert!(k == 1 && m.contains("PS0034"), "{m}");
    let (k, m) = err(&moves2, &tags(2, 1, comp(Side::Left, 1.0)), LCNC);
    assert_eq!(
        (k, m.as_str()),
        (1, "The move just after exiting cutter compensation mode must be straight, not an arc")
    );
    // LinuxCNC takes an entry arc: G03 around (10,0) from (0,0) to (20,0),
    // G41 r=1 (inside). The end moves toward the centre to (19,0); the new
    // centre lies on the line from there to (10,0), as far from (0,0) as
    // from (19,0): (9.5,0).
    let out = compensate(&moves, &tags(2, 2, comp(Side::Left, 1.0)), LCNC).unwrap();
    check(&out, &[A(19.0, 0.0, 0, (9.5, 0.0), true), L(19.0, 10.0, 0)]);
}

#[test]
fn linuxcnc_entry_must_be_longer_than_radius() {
    let moves = vec![line((0.0, 0.0), (0.5, 0.0)), line((0.5, 0.0), (10.0, 0.0))];
    let t = tags(2, 2, comp(Side::Left, 1.0));
    assert_eq!(
        err(&moves, &t, LCNC),
        (0, "Length of cutter compensation entry move is not greater than the tool radius".into())
    );
    // A plunge as the first move after G41 has no length in the plane.
    let plunge = Move { start: at3(0.0, 0.0, 0.0), end: at3(0.0, 0.0, -1.0), ..moves[0] };
    assert_eq!(err(&[plunge, moves[1]], &t, LCNC).0, 0);
    // Fanuc starts up on the first plane move instead: the plunge is made
    // in place.
    let out = compensate(&[plunge, Move { start: at3(0.0, 0.0, -1.0), ..moves[1] }], &t, FANUC_A).unwrap();
    assert_eq!((out[0].end.x, out[0].end.y, out[0].end.z), (0.0, 0.0, -1.0));
    assert_eq!((out[1].end.x, out[1].end.y), (10.0, 1.0));
}

#[test]
fn refused_moves_while_on() {
    let probe = Move { kind: MoveKind::Probe, ..line((10.0, 0.0), (20.0, 0.0)) };
    let moves = vec![line((0.0, 0.0), (10.0, 0.0)), probe];
    let t = tags(2, 2, comp(Side::Left, 1.0));
    assert!(err(&moves, &t, FANUC_A).1.contains("PS0035"));
    assert_eq!(err(&moves, &t, LCNC), (1, "Cannot probe with cutter radius comp on".into()));
    // A change of offset without G40.
    let moves = vec![line((0.0, 0.0), (10.0, 0.0)), line((10.0, 0.0), (20.0, 0.0))];
    assert_eq!(err(&moves, &[comp(Side::Left, 1.0), comp(Side::Left, 2.0)], LCNC).0, 1);
    // Tags that do not match the moves.
    assert_eq!(err(&moves, &[None], FANUC_A).0, 1);
}

#[test]
fn radius_zero_and_uncompensated_moves_pass_unchanged() {
    let moves = inside_path();
    assert_eq!(compensate(&moves, &tags(4, 3, comp(Side::Left, 0.0)), FANUC_A).unwrap(), moves);
    assert_eq!(compensate(&moves, &[None; 4], LCNC).unwrap(), moves);
}
