//! The lathe's multiple repetitive cycles of a finishing shape: G71 type I
//! and II, G72, G73, G70 (two-block Fanuc forms) and Haas's one-block G71.
//! Every expected pass is worked out by hand below from the definitions of
//! FANUC Series 0i-TF Plus Operator's Manual (B-64604EN), lathe system,
//! "Multiple repetitive cycle", before the output was looked at:
//!
//! - G71: from the start point A the stock down to the finishing shape
//!   moved by the allowance (Δu/2 in X, Δw in Z) is cut in depths of Δd
//!   (radius), each cut approached in X as block ns moves (G00 at rapid,
//!   G01 at the feed), run along Z to the moved shape, left at 45° by e
//!   (rapid), and the tool goes back to A's Z at rapid; after the last
//!   depth, one cut along the moved shape, and back to A at rapid.
//! - Type II (block ns names Z too): each cut follows the shape up to the
//!   previous depth and leaves straight out by e; a pocket is entered down
//!   its wall from the previous depth (the order and the moves between
//!   pockets: kezuri's reading, see `interp/lathe/roughing.rs`).
//! - G72: the same with X and Z exchanged, Δd given as `W` in its first
//!   block.
//! - G73: d passes of the shape, the first moved by (Δi + Δu/2, Δk + Δw),
//!   the last by (Δu/2, Δw), evenly between; each from A moved the same.
//! - G70: blocks ns…nf as they stand (their own F), then back to A at rapid.
//!
//! Positions are the tool's: X a radius (the program's X a diameter).

use kezuri_geom::{Move, MoveKind};
use kezuri_nc::interp::{Control, CoordSettings, GCodeSystem, Lathe, Outcome, Settings};
use kezuri_nc::Dialect;

mod common;

fn fanuc() -> Settings {
    Settings { dialect: Dialect::FanucLathe, ..Settings::default() }
}

fn haas() -> Settings {
    Settings {
        dialect: Dialect::HaasLathe,
        coords: CoordSettings { control: Control::Haas, ..CoordSettings::default() },
        ..Settings::default()
    }
}

/// The spindle at 1000 rpm (feed per revolution, G99, is the lathe's power-on
/// state) on the program's first line, so that its lines stay as numbered.
fn spindle(text: &str) -> String {
    format!("S1000 M03 {text}")
}

fn run(text: &str, settings: &Settings) -> Outcome {
    common::run("t.nc", &spindle(text), settings).completed()
}

/// `R` for a rapid, `F` for a feed, `A` for an arc; X (radius) and Z.
fn moves(o: &Outcome) -> Vec<(char, f64, f64)> {
    o.toolpath.moves.iter().map(|m: &Move| (kind(m), m.end.x, m.end.z)).collect()
}

fn kind(m: &Move) -> char {
    match m.kind {
        MoveKind::Rapid => 'R',
        MoveKind::Feed => 'F',
        MoveKind::Arc(_) => 'A',
        _ => '?',
    }
}

fn same(got: &[(char, f64, f64)], want: &[(char, f64, f64)]) {
    assert_eq!(got.len(), want.len(), "got {got:?}");
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            g.0 == w.0 && (g.1 - w.1).abs() < 1e-9 && (g.2 - w.2).abs() < 1e-9,
            "move {k}: got {g:?}, want {w:?}\n{got:?}"
        );
    }
}

/// An outside diameter: Ø20 for 22 mm, a taper to Ø40, Ø40 to Z-45, out to
/// Ø62. The start point A is X60 (radius 30) Z2.
const OUTSIDE: &str = "G00 X60. Z2.
G71 U2. R0.5
G71 P10 Q20 U0.4 W0.1 F0.25
N10 G00 X20.
G01 Z-20.
X40. Z-30.
Z-45.
N20 X62.
G70 P10 Q20
M30
";

#[test]
fn g71_type_one_cuts_by_depth_then_along_the_shape() {
    // The shape moved by Δu/2 = 0.2, Δw = 0.1 (radius, Z):
    // (10.2, 2.1) (10.2, -19.9) (20.2, -29.9) (20.2, -44.9) (31.2, -44.9).
    // Depths from A's radius 30, by Δd = 2: radius 28, 26, …, 12 (9 cuts;
    // radius 10 would pass the shape's deepest point, 10.2). Radius 28 to
    // 22 (depths 2–8) meet the shape at its last block, Z-44.9; radius 20
    // meets the taper at Z = -19.9 - (20 - 10.2) = -29.7, 18 at -27.7,
    // 16 at -25.7, 14 at -23.7, 12 at -21.7. Each: in at rapid (N10 is
    // G00), along Z at the feed, out 0.5 and 0.5 at 45° (rapid), back to Z2.
    let o = run(OUTSIDE, &fanuc());
    let mut want = vec![('R', 30.0, 2.0)];
    let ends = [-44.9, -44.9, -44.9, -44.9, -29.7, -27.7, -25.7, -23.7, -21.7];
    for (k, &z) in ends.iter().enumerate() {
        let x = 28.0 - 2.0 * k as f64;
        want.extend([('R', x, 2.0), ('F', x, z), ('R', x + 0.5, z + 0.5), ('R', x + 0.5, 2.0)]);
    }
    // Along the moved shape: in to its start at rapid, along it, back to A.
    want.extend([
        ('R', 10.2, 2.1),
        ('F', 10.2, -19.9),
        ('F', 20.2, -29.9),
        ('F', 20.2, -44.9),
        ('F', 31.2, -44.9),
        ('R', 30.0, 2.0),
    ]);
    // G70: the shape itself (the program goes on after N20: its blocks run
    // only under G70), then back to A.
    want.extend([
        ('R', 10.0, 2.0),
        ('F', 10.0, -20.0),
        ('F', 20.0, -30.0),
        ('F', 20.0, -45.0),
        ('F', 31.0, -45.0),
        ('R', 30.0, 2.0),
    ]);
    same(&moves(&o), &want);
}

#[test]
fn g70_runs_the_shape_at_its_own_feed_and_g71_at_the_cycle_feed() {
    // F0.1 in the shape is ignored by G71 (its F0.25 cuts) and used by G70.
    let text = OUTSIDE.replace("G01 Z-20.", "G01 Z-20. F0.1");
    let o = run(&text, &fanuc());
    let feeds: Vec<f64> = o.toolpath.moves.iter().filter(|m| m.kind == MoveKind::Feed).map(|m| m.feed).collect();
    // 9 cuts + 4 along the shape under G71, then 4 under G70.
    assert_eq!(feeds.len(), 17);
    assert!(feeds[..13].iter().all(|&f| (f - feeds[0]).abs() < 1e-9));
    assert!(feeds[13..].iter().all(|&f| (f / feeds[0] - 0.1 / 0.25).abs() < 1e-9), "{feeds:?}");
}

#[test]
fn g71_type_two_cuts_a_pocket() {
    // A from X42 (radius 21) Z2. The shape (radius, Z): (15, 0) (15, -10)
    // into a pocket (10, -15) (10, -20) out (15, -25) (15, -35) (21, -35);
    // no allowance. In the cycle's frame, a = 2 - Z along the cut and
    // d = 21 - radius into the stock: (2, 6) (12, 6) (17, 11) (22, 11)
    // (27, 6) (37, 6) (37, 0), the stock from a = 0 at depth 6 before it.
    // Depths 2, 4, 6, 8, 10 (12 is past the bottom, 11).
    // d 2: in at the feed (N30 is G01) to (0, 2); along to the end wall
    //   a 37; up it to the start's depth 0 (the shape ends there); out 0.5.
    // d 4: over the shape at d -0.5 back to a 0; in; along to a 37; up to
    //   the last depth 2; out to 1.5.
    // d 6: the shape lies at 6 from a 0 to 12 and 27 to 37: from a 0 down
    //   to 6, along the shape to a 12, along d 6 over the pocket to 27, on
    //   along the shape to 37 and up to 4; out to 3.5.
    // d 8: the pocket's wall crosses 6 at a 12, 8 at a 14 (on 12→17,
    //   6→11); its far wall 8 at a 25, 6 at a 27. Over the shape (it rises
    //   to 0 at a 37: at -0.5) to a 12, down to 6 at rapid, down the wall
    //   to (14, 8), along to 25, up the wall to (27, 6), out to 5.5.
    // d 10: walls at a 16 and 23 (10), from 8 at 14 and 25. Across at 5.5
    //   (the shape between a 14 and 27 comes up to 6), down to (14, 8),
    //   the wall to (16, 10), along to 23, up to (25, 8), out to 7.5.
    // Along the shape: across at 5.5 to a 0, in to its start (2, 6) at the
    //   feed, along it to (37, 0), back to A at rapid.
    // In machine terms: radius = 21 - d, Z = 2 - a.
    let text = "G00 X42. Z2.
G71 U2. R0.5
G71 P30 Q40 U0 W0 F0.2
N30 G01 X30. Z0
Z-10.
X20. Z-15.
Z-20.
X30. Z-25.
Z-35.
N40 X42.
M30
";
    let o = run(text, &fanuc());
    let want = [
        ('R', 21.0, 2.0),
        // d 2
        ('F', 19.0, 2.0),
        ('F', 19.0, -35.0),
        ('F', 21.0, -35.0),
        ('R', 21.5, -35.0),
        // d 4
        ('R', 21.5, 2.0),
        ('F', 17.0, 2.0),
        ('F', 17.0, -35.0),
        ('F', 19.0, -35.0),
        ('R', 19.5, -35.0),
        // d 6
        ('R', 21.5, -35.0),
        ('R', 21.5, 2.0),
        ('F', 15.0, 2.0),
        ('F', 15.0, 0.0),
        ('F', 15.0, -10.0),
        ('F', 15.0, -25.0),
        ('F', 15.0, -35.0),
        ('F', 17.0, -35.0),
        ('R', 17.5, -35.0),
        // d 8
        ('R', 21.5, -35.0),
        ('R', 21.5, -10.0),
        ('R', 15.0, -10.0),
        ('F', 13.0, -12.0),
        ('F', 13.0, -23.0),
        ('F', 15.0, -25.0),
        ('R', 15.5, -25.0),
        // d 10
        ('R', 15.5, -12.0),
        ('R', 13.0, -12.0),
        ('F', 11.0, -14.0),
        ('F', 11.0, -21.0),
        ('F', 13.0, -23.0),
        ('R', 13.5, -23.0),
        // along the shape
        ('R', 15.5, -23.0),
        ('R', 15.5, 2.0),
        ('F', 15.0, 0.0),
        ('F', 15.0, -10.0),
        ('F', 10.0, -15.0),
        ('F', 10.0, -20.0),
        ('F', 15.0, -25.0),
        ('F', 15.0, -35.0),
        ('F', 21.0, -35.0),
        ('R', 21.0, 2.0),
    ];
    same(&moves(&o), &want);
}

#[test]
fn g72_faces_by_depth_in_z() {
    // A at X82 (radius 41) Z2. The shape: (41, -6) (30, -6) (20, -3)
    // (10, -3) (10, 2). Facing frame: d = 2 - Z into the stock, a = 41 -
    // radius along the cut: (0, 8) (11, 8) (21, 5) (31, 5) (31, 0).
    // Depths of Δd = 2 (W2.): 2, 4, 6 (8 is the bottom). Depths 2 and 4
    // meet the shape at its last block, radius 10; depth 6 (Z-4) meets the
    // taper (30, -6)→(20, -3) at radius 30 - 10·(2/3) = 23.333….
    // Each: in along Z at rapid (N50 is G00), along X at the feed, out at
    // 45° by 0.5, back to radius 41. Then along the shape, back to A.
    let text = "G00 X82. Z2.
G72 W2. R0.5
G72 P50 Q60 U0 W0 F0.2
N50 G00 Z-6.
G01 X60.
X40. Z-3.
X20.
N60 Z2.
M30
";
    let o = run(text, &fanuc());
    let x6 = 30.0 - 20.0 / 3.0;
    let want = [
        ('R', 41.0, 2.0),
        ('R', 41.0, 0.0),
        ('F', 10.0, 0.0),
        ('R', 10.5, 0.5),
        ('R', 41.0, 0.5),
        ('R', 41.0, -2.0),
        ('F', 10.0, -2.0),
        ('R', 10.5, -1.5),
        ('R', 41.0, -1.5),
        ('R', 41.0, -4.0),
        ('F', x6, -4.0),
        ('R', x6 + 0.5, -3.5),
        ('R', 41.0, -3.5),
        ('R', 41.0, -6.0),
        ('F', 30.0, -6.0),
        ('F', 20.0, -3.0),
        ('F', 10.0, -3.0),
        ('F', 10.0, 2.0),
        ('R', 41.0, 2.0),
    ];
    same(&moves(&o), &want);
}

#[test]
fn g73_repeats_the_shape_nearer_each_time() {
    // A at X60 (radius 30) Z5. Δi 3 (radius), Δk 1, d = 3 passes;
    // Δu/2 = 0.2, Δw = 0.2. Pass 1 is moved by (3.2, 1.2), pass 2 by
    // (1.7, 0.7), pass 3 by (0.2, 0.2) (radius, Z). The shape: from A to
    // (10, 0) (N70, G01), (10, -10), (20, -10). Each pass: to A moved, at
    // rapid; the shape moved, at the feed; then the next; last, back to A.
    let text = "G00 X60. Z5.
G73 U3. W1. R3
G73 P70 Q80 U0.4 W0.2 F0.2
N70 G01 X20. Z0.
Z-10.
N80 X40.
M30
";
    let o = run(text, &fanuc());
    let mut want = vec![('R', 30.0, 5.0)];
    for (dx, dz) in [(3.2, 1.2), (1.7, 0.7), (0.2, 0.2)] {
        want.extend([
            ('R', 30.0 + dx, 5.0 + dz),
            ('F', 10.0 + dx, dz),
            ('F', 10.0 + dx, -10.0 + dz),
            ('F', 20.0 + dx, -10.0 + dz),
        ]);
    }
    want.push(('R', 30.0, 5.0));
    same(&moves(&o), &want);
}

#[test]
fn haas_g71_in_one_block_leaves_the_rough_allowance_then_follows_the_shape() {
    // OUTSIDE's shape in Haas's one block: D2. the depth of cut, U0.4 W0.1
    // the finishing allowance, I0.3 K0.2 the rough cuts' own (Haas Lathe
    // Operator's Manual, G71). The cuts stop at the shape moved by
    // (0.2 + 0.3, 0.1 + 0.2): radius 20 meets the taper, now
    // (10.5, -19.7)→(20.5, -29.7), at Z -19.7 - 9.5 = -29.2; the deepest
    // point is radius 10.5, so 9 cuts again (radius 28 … 12). No R word: the
    // escape is kezuri's 1 mm. The cut along the shape then leaves (0.2,
    // 0.1): it starts at (10.2, 2.1).
    let text = "G00 X60. Z2.
G71 P10 Q20 D2. U0.4 W0.1 I0.3 K0.2 F0.25
N10 G00 X20.
G01 Z-20.
X40. Z-30.
Z-45.
N20 X62.
M30
";
    let o = run(text, &haas());
    let m = moves(&o);
    assert_eq!(m.len(), 1 + 9 * 4 + 6, "{m:?}");
    // The fifth cut (radius 20): in, along, out by 1 at 45°, back.
    same(&m[17..21], &[('R', 20.0, 2.0), ('F', 20.0, -29.2), ('R', 21.0, -28.2), ('R', 21.0, 2.0)]);
    same(
        &m[37..],
        &[
            ('R', 10.2, 2.1),
            ('F', 10.2, -19.9),
            ('F', 20.2, -29.9),
            ('F', 20.2, -44.9),
            ('F', 31.2, -44.9),
            ('R', 30.0, 2.0),
        ],
    );
}

fn stop(text: &str, settings: &Settings) -> (String, String) {
    let ran = common::run("t.nc", &spindle(text), settings);
    (ran.headline(), ran.message())
}

#[test]
fn a_type_one_shape_that_goes_deeper_is_the_controls_alarm() {
    // Ø30 then down to Ø24 again: not a monotonous change in X.
    let text = "G00 X60. Z2.
G71 U2. R0.5
G71 P10 Q20 U0.4 W0.1 F0.25
N10 G00 X20.
G01 Z-10.
X30. Z-15.
X24. Z-20.
N20 X62.
M30
";
    let (head, message) = stop(text, &fanuc());
    assert!(head.starts_with("t.nc:7:1: error"), "{head}");
    assert!(message.contains("PS0064") && message.contains("type II"), "{message}");
}

#[test]
fn the_shapes_first_block_must_be_g00_or_g01() {
    let text = "G00 X60. Z2.
G71 U2. R0.5
G71 P10 Q20 U0.4 W0.1 F0.25
N10 X20.
G01 Z-20.
N20 X62.
M30
";
    let (head, message) = stop(text, &fanuc());
    assert!(head.starts_with("t.nc:4:1: error"), "{head}");
    assert!(message.contains("G00 or G01") && message.contains("PS0065"), "{message}");
}

#[test]
fn p_or_q_naming_no_block_is_located_at_the_word() {
    let text = "G00 X60. Z2.
G71 U2. R0.5
G71 P10 Q99 U0.4 W0.1 F0.25
N10 G00 X20.
N20 X62.
M30
";
    let (head, message) = stop(text, &fanuc());
    assert!(head.starts_with("t.nc:3:9: error"), "{head}");
    assert!(message.contains("N99") && message.contains("PS0063"), "{message}");
    let (head, _) = stop(&text.replace("P10 Q99", "P11 Q20"), &fanuc());
    assert!(head.starts_with("t.nc:3:5: error"), "{head}");
}

#[test]
fn a_depth_of_cut_of_zero_is_refused() {
    let (head, message) = stop(&OUTSIDE.replace("G71 U2. R0.5", "G71 U0 R0.5"), &fanuc());
    assert!(head.starts_with("t.nc:2:5: error"), "{head}");
    assert!(message.contains("PS0062"), "{message}");
    // No first block at all: no depth of cut is known.
    let (head, message) = stop(&OUTSIDE.replace("G71 U2. R0.5\n", ""), &fanuc());
    assert!(head.starts_with("t.nc:2:1: error"), "{head}");
    assert!(message.contains("no depth of cut"), "{message}");
    // Haas: D0.
    let text = "G00 X60. Z2.\nG71 P10 Q20 D0 U0.4 W0.1 F0.25\nN10 G00 X20.\nN20 X62.\nM30\n";
    let (head, _) = stop(text, &haas());
    assert!(head.starts_with("t.nc:2:13: error"), "{head}");
}

#[test]
fn the_shape_may_use_u_and_w_and_system_c_numbers_the_cycles_from_g72() {
    // The same shape with increments: from N10's (radius 10, Z2), W-22. is
    // Z-20, U20. W-10. is Ø40 Z-30, W-15. Z-45, U22. Ø62: the same moves.
    let incremental = OUTSIDE
        .replace("G01 Z-20.", "G01 W-22.")
        .replace("X40. Z-30.", "U20. W-10.")
        .replace("Z-45.\nN20 X62.", "W-15.\nN20 U22.");
    let want = moves(&run(OUTSIDE, &fanuc()));
    same(&moves(&run(&incremental, &fanuc())), &want);
    // G code system C (B-64604EN, "G code list"): G72 is finishing, G73
    // stock removal in turning; X and Z are absolute (G90 at power-on).
    let system_c = Settings { lathe: Some(Lathe { system: GCodeSystem::C, ..Lathe::default() }), ..fanuc() };
    let text = OUTSIDE.replace("G71", "G73").replace("G70", "G72");
    same(&moves(&run(&text, &system_c)), &want);
}

#[test]
fn g71_follows_an_arc_of_the_shape() {
    // A at X50 (radius 25) Z2. The shape: (10, 2) → (10, -10), then G02 R10
    // to (20, -20): in the ZX plane (Z across, X up, seen from +Y) G02 turns
    // clockwise, so the centre is (radius 20, Z-10) — a fillet into the
    // shoulder — then out to Ø52. In the cut's frame (d = 25 - radius,
    // a = 2 - Z): (0, 15) → (12, 15), the arc about (12, 5) to (22, 5), then
    // (22, -1). Depths 2 … 14 (15 is the bottom). Depths 2 and 4 meet the
    // shoulder at a 22 (Z-20); a depth d from 6 to 14 meets the arc where
    // (a - 12)² + (d - 5)² = 100: a = 12 + √(100 - (d - 5)²).
    let text = "G00 X50. Z2.
G71 U2. R0.5
G71 P10 Q20 U0 W0 F0.2
N10 G00 X20.
G01 Z-10.
G02 X40. Z-20. R10.
N20 G01 X52.
M30
";
    let o = run(text, &fanuc());
    // The cuts: feeds along Z from Z2 (the cut along the shape's first
    // block, at radius 10, is not one of them).
    let cuts: Vec<(f64, f64)> = o
        .toolpath
        .moves
        .iter()
        .filter(|m| m.kind == MoveKind::Feed && m.start.x == m.end.x && m.start.z == 2.0 && m.end.x > 10.5)
        .map(|m| (m.end.x, m.end.z))
        .collect();
    let want: Vec<(f64, f64)> = (1..=7)
        .map(|k| {
            let d = 2.0 * k as f64;
            let a = if d <= 5.0 { 22.0 } else { 12.0 + (100.0 - (d - 5.0) * (d - 5.0)).sqrt() };
            (25.0 - d, 2.0 - a)
        })
        .collect();
    assert_eq!(cuts.len(), want.len(), "{cuts:?}");
    for (g, w) in cuts.iter().zip(&want) {
        assert!((g.0 - w.0).abs() < 1e-9 && (g.1 - w.1).abs() < 1e-9, "{cuts:?} vs {want:?}");
    }
    // The cut along the shape turns the arc as the program does.
    let arc = o.toolpath.moves.iter().find(|m| matches!(m.kind, MoveKind::Arc(_))).expect("the arc");
    let MoveKind::Arc(a) = arc.kind else { unreachable!() };
    assert!(!a.ccw);
    assert!((a.center[0] - 20.0).abs() < 1e-9 && (a.center[2] + 10.0).abs() < 1e-9, "{a:?}");
    assert!((arc.end.x - 20.0).abs() < 1e-9 && (arc.end.z + 20.0).abs() < 1e-9);
}

#[test]
fn haas_g73_and_g70_in_one_block_are_fanucs_two() {
    // Haas's G73: I and K the first pass's distance from the last (radius,
    // Z), D the passes (Haas Lathe Operator's Manual, G73): the Fanuc case's
    // U3. W1. R3 written so, the same moves; then G70 P Q.
    let fanuc_text = "G00 X60. Z5.
G73 U3. W1. R3
G73 P70 Q80 U0.4 W0.2 F0.2
N70 G01 X20. Z0.
Z-10.
N80 X40.
G70 P70 Q80
M30
";
    let haas_text =
        fanuc_text.replace("G73 U3. W1. R3\nG73 P70 Q80 U0.4 W0.2 F0.2", "G73 P70 Q80 I3. K1. D3 U0.4 W0.2 F0.2");
    let want = moves(&run(fanuc_text, &fanuc()));
    // 1 + 3 passes of 4 + back to A; G70: the shape's 3 moves and back.
    assert_eq!(want.len(), 1 + 12 + 1 + 4, "{want:?}");
    same(&want[14..], &[('F', 10.0, 0.0), ('F', 10.0, -10.0), ('F', 20.0, -10.0), ('R', 30.0, 5.0)]);
    same(&moves(&run(&haas_text, &haas())), &want);
}

#[test]
fn haas_r1_is_type_two() {
    // The pocket of `g71_type_two_cuts_a_pocket` in Haas's one block with
    // R1: its cuts (the feeds) are type II's, the escape (Haas's setting,
    // kezuri's 1 mm) aside. Without R1 a first block naming X alone makes
    // it type I, and the pocket is refused; one naming X and Z (Fanuc's
    // type II, which real Haas programs rely on) is type II again.
    let body = "N30 G01 X30. Z0
Z-10.
X20. Z-15.
Z-20.
X30. Z-25.
Z-35.
N40 X42.
M30
";
    let fanuc_text = format!("G00 X42. Z2.\nG71 U2. R1.\nG71 P30 Q40 U0 W0 F0.2\n{body}");
    let haas_text = format!("G00 X42. Z2.\nG71 P30 Q40 D2. U0 W0 I0 K0 R1 F0.2\n{body}");
    let feeds = |o: &Outcome| moves(o).into_iter().filter(|m| m.0 == 'F').collect::<Vec<_>>();
    same(&feeds(&run(&haas_text, &haas())), &feeds(&run(&fanuc_text, &fanuc())));
    let fanuc_reading = haas_text.replace(" R1", "");
    same(&feeds(&run(&fanuc_reading, &haas())), &feeds(&run(&fanuc_text, &fanuc())));
    let (head, message) = stop(&fanuc_reading.replace("N30 G01 X30. Z0\n", "N30 G01 X30.\n"), &haas());
    // Refused where the shape stops being monotonous: it goes deeper to
    // Ø20 (line 5), which alone a type I shape may do, and turns back up
    // to Ø30 on line 7.
    assert!(head.starts_with("t.nc:7:1: error"), "{head}");
    assert!(message.contains("type II"), "{message}");
}

#[test]
fn odd_shapes_stop_with_the_controls_alarm_never_a_panic() {
    let cases: [(&str, &str); 7] = [
        // A call in the shape: not allowed in it.
        ("N10 G00 X20.\nM98 P1000\nN20 X62.\n", "PS0066"),
        // Another cycle inside the shape.
        ("N10 G00 X20.\nG71 P10 Q20\nN20 X62.\n", "PS0066"),
        // A macro statement inside the shape.
        ("N10 G00 X20.\n#1=5\nN20 X62.\n", "PS0066"),
        // A shape of one block: it ends where it starts in Z.
        ("N10 G00 X20.\nN20 G00 X20.\n", "which way to cut"),
        // A first block that does not move towards the stock.
        ("N10 G00 X60.\nG01 Z-20.\nN20 X62.\n", "which way to cut"),
        // A shape that turns back in Z.
        ("N10 G00 X20.\nG01 Z-20.\nZ-10.\nN20 X62.\n", "PS0329"),
        // A dwell in the shape.
        ("N10 G00 X20.\nG04 U1.\nG01 Z-20.\nN20 X62.\n", "PS0066"),
    ];
    for (shape, alarm) in cases {
        let text = format!("G00 X60. Z2.\nG71 U2. R0.5\nG71 P10 Q20 U0.4 W0.1 F0.25\n{shape}M30\n");
        let (_, message) = stop(&text, &fanuc());
        assert!(message.contains(alarm), "{shape}: {message}");
    }
    // 100,000,001 cuts: refused before any is made, at the depth word.
    let text = OUTSIDE.replace("G71 U2. R0.5", "G71 U0.0000002 R0.5");
    let (head, message) = stop(&text, &fanuc());
    assert!(head.starts_with("t.nc:2:5: error") && message.contains("cuts"), "{head} {message}");
    // G73 with no passes.
    let (_, message) =
        stop("G00 X60. Z5.\nG73 U3. W1. R0\nG73 P70 Q80 F0.2\nN70 G01 X20. Z0.\nN80 X40.\nM30\n", &fanuc());
    assert!(message.contains("PS0062"), "{message}");
}

#[test]
fn under_constant_surface_speed_each_cut_turns_at_its_own_speed() {
    // G96 S100: 100 m/min at the tool, so at radius r (mm) the spindle turns
    // 100,000 / (2π r) rpm (clamped by G50 S3000, not reached here). The
    // first cut of OUTSIDE runs along Z at radius 28: 568.4 rpm, and at
    // F0.25 a turn the feed is 0.25 × that in mm/min; the fifth, at radius
    // 20, 795.8 rpm.
    let text = OUTSIDE.replace("G00 X60. Z2.", "G50 S3000\nG96 S100\nG00 X60. Z2.");
    let o = common::run("t.nc", &text, &fanuc()).completed();
    let cuts: Vec<&Move> = o.toolpath.moves.iter().filter(|m| m.kind == MoveKind::Feed && m.start.z == 2.0).collect();
    for (k, r) in [(0, 28.0), (4, 20.0)] {
        let rpm = 100_000.0 / (std::f64::consts::TAU * r);
        assert!((cuts[k].speed - rpm).abs() < 1e-6, "{k}: {} rpm", cuts[k].speed);
        assert!((cuts[k].feed - 0.25 * rpm).abs() < 1e-6, "{k}: {} mm/min", cuts[k].feed);
    }
}

#[test]
fn g71_bores_with_a_negative_allowance() {
    // Boring: A at X20 (radius 10) Z2; N10 goes out to Ø50, so the cuts go
    // outwards from the axis. U-0.4 leaves 0.2 on the bore (towards the
    // axis), W0.1 towards +Z. The shape moved: (24.8, 2.1) (24.8, -19.9)
    // (14.8, -29.9) (8.8, -29.9). Depths from radius 10 outwards by 2:
    // radius 12 … 24 (7 cuts; 26 is past the deepest, 24.8). Radius 12 and
    // 14 meet the shape at its last block's Z-29.9; radius r from 16 on
    // meets the taper at Z = -29.9 + (r - 14.8): 16 → -28.7, 18 → -26.7,
    // 20 → -24.7, 22 → -22.7, 24 → -20.7. Out at 45° towards the axis and
    // +Z by 0.5, back to Z2; then along the moved shape, back to A.
    let text = "G00 X20. Z2.
G71 U2. R0.5
G71 P10 Q20 U-0.4 W0.1 F0.2
N10 G00 X50.
G01 Z-20.
X30. Z-30.
N20 X18.
M30
";
    let o = run(text, &fanuc());
    let mut want = vec![('R', 10.0, 2.0)];
    for (x, z) in
        [(12.0, -29.9), (14.0, -29.9), (16.0, -28.7), (18.0, -26.7), (20.0, -24.7), (22.0, -22.7), (24.0, -20.7)]
    {
        want.extend([('R', x, 2.0), ('F', x, z), ('R', x - 0.5, z + 0.5), ('R', x - 0.5, 2.0)]);
    }
    want.extend([('R', 24.8, 2.1), ('F', 24.8, -19.9), ('F', 14.8, -29.9), ('F', 8.8, -29.9), ('R', 10.0, 2.0)]);
    same(&moves(&o), &want);
}

#[test]
fn a_chamfer_in_the_shape_is_cut_and_may_not_end_it() {
    // `X40. C-2.`: from Ø20 up to Ø40 at Z-20 with a 2 mm chamfer towards
    // -Z at the corner (B-64604EN, "Chamfering and corner R"): the shape is
    // (10, 2) (10, -20) (18, -20) (20, -22) (20, -45) (31, -45). From
    // radius 30 by 2: radius 28 … 22 meet the last block (Z-45); radius 20
    // lies on the Ø40 face, below it only up to the chamfer's end, Z-22;
    // radius 18 … 12 meet the shoulder at Z-20.
    let text =
        OUTSIDE.replace("X40. Z-30.", "X40. C-2.").replace("G71 P10 Q20 U0.4 W0.1 F0.25", "G71 P10 Q20 U0 W0 F0.25");
    let o = run(&text, &fanuc());
    let m = moves(&o);
    let cuts: Vec<(char, f64, f64)> = m[..37].iter().copied().filter(|c| c.0 == 'F').collect();
    let ends = [-45.0, -45.0, -45.0, -45.0, -22.0, -20.0, -20.0, -20.0, -20.0];
    let want: Vec<_> = ends.iter().enumerate().map(|(k, &z)| ('F', 28.0 - 2.0 * k as f64, z)).collect();
    same(&cuts, &want);
    same(
        &m[37..43],
        &[
            ('R', 10.0, 2.0),
            ('F', 10.0, -20.0),
            ('F', 18.0, -20.0),
            ('F', 20.0, -22.0),
            ('F', 20.0, -45.0),
            ('F', 31.0, -45.0),
        ],
    );
    // The shape's last block with a chamfer: nothing follows it in the shape.
    let text = "G00 X60. Z2.\nG71 U2. R0.5\nG71 P10 Q20 U0 W0 F0.25\nN10 G00 X20.\nN20 G01 Z-20. C1.\nX62.\nM30\n";
    let (head, message) = stop(text, &fanuc());
    assert!(head.starts_with("t.nc:5:15: error"), "{head}");
    assert!(message.contains("PS0069"), "{message}");
}

#[test]
fn a_haas_depth_with_a_fraction_is_the_cycles_not_a_compensation_register() {
    // Haas G71's D is the depth of cut (radius), D0.5 as real programs give
    // it; it is no cutter compensation register (which must be whole). From
    // X42. (radius 21) the cuts along Z to the shape's Z-10. are every 0.5 mm
    // of radius: 20.5, 20.0, ... down to 10.5, above the shape's X20.
    // (radius 10) with nothing left (U0 W0): 21 cuts.
    let text = "G00 X42. Z2.\nG71 P30 Q40 D0.5 U0 W0 F0.2\nN30 G00 X20.\nG01 Z-10.\nN40 X42.\nM30\n";
    let cuts: Vec<f64> =
        moves(&run(text, &haas())).iter().filter(|m| m.0 == 'F' && m.2 == -10.0).map(|m| m.1).collect();
    let want: Vec<f64> = (0..21).map(|k| 20.5 - 0.5 * f64::from(k)).collect();
    assert_eq!(cuts, want);
}
