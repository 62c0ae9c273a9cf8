//! A Fanuc lathe's side drilling, tapping and boring (G87, G88, G89): the
//! face cycles G83, G84, G85 turned to go along X, toward the spindle axis,
//! with Z and C placing the hole; and the face and side drilling cycles
//! without a peck depth.
//!
//! Every expected number is worked out by hand in the comments from the
//! definitions of FANUC Series 0i-TF Plus Operator's Manual (B-64604EN),
//! lathe system, "Canned cycle for drilling", before the output was looked
//! at: the format `G87 Z(W)_ C(H)_ X(U)_ R_ Q_ P_ F_ K_ M_;` (G88, G89 the
//! same without Q), Z and C the hole's position, X (U) its bottom, R the
//! distance from the initial level to point R with its sign in G code system
//! A (parameter 5102#6 RAB at its default, 0) and given as a radius
//! (5102#7 RDI at its default, 0), Q the depth of each peck in least
//! increments, P the dwell at the bottom in milliseconds. As kezuri's G83
//! does, each peck returns to point R at rapid and goes down at rapid to d
//! (parameter 5115, 0.1 mm) short of the last depth. In system A G98 and
//! G99 are the feed modes and the tool returns to the initial level after
//! each hole; in system B G98 returns to the initial level and G99 to point
//! R. Positions are the tool's: X a radius (X60. is 30 from the axis).

use kezuri_geom::{MoveKind, Spindle, Toolpath};
use kezuri_nc::interp::GCodeSystem;

mod common;

use common::lathe::{error, fanuc, haas, lathe, path};

/// A rapid, a feed or a dwell, with its end's X (radius), Z and C.
#[derive(Clone, Copy, Debug, PartialEq)]
enum K {
    R,
    F,
    D,
}

/// The moves from index `from` on are these, in kind and end (X radius, Z, C).
fn expect(t: &Toolpath, from: usize, want: &[(K, f64, f64, f64)]) {
    let got: Vec<_> = t.moves[from.min(t.moves.len())..]
        .iter()
        .take(want.len())
        .map(|m| {
            let kind = match m.kind {
                MoveKind::Rapid => K::R,
                MoveKind::Dwell(_) => K::D,
                _ => K::F,
            };
            (kind, m.end.x, m.end.z, m.end.c)
        })
        .collect();
    let ok = got.len() == want.len()
        && got.iter().zip(want).all(|(g, w)| {
            g.0 == w.0 && (g.1 - w.1).abs() < 1e-6 && (g.2 - w.2).abs() < 1e-6 && (g.3 - w.3).abs() < 1e-6
        });
    assert!(ok, "moves from {from}:\n got  {got:?}\n want {want:?}");
}

// G87, system A, G98 (feed per minute). The tool stands at X60. Z-10.: the
// initial level is radius 30, the hole's place Z-10 C0, where it is already.
// puts point R at 30 - 2 = 28; X20. is the bottom at radius 10; Q4000
// is 4.000 mm a peck, no P: no dwell. Pecks: feed 28 → 24; rapid to 28, rapid to 24.1, feed
// to 20; to 28, 20.1, feed 16; to 28, 16.1, feed 12; to 28, 12.1, feed to
// the bottom 10; then rapid to the initial level 30. F100. is 100 mm/min.
#[test]
fn g87_pecks_along_x_from_the_initial_level() {
    let text = "S1000 M03\nG98 G00 X60. Z-10. C0.\nG87 Z-10. C0. X20. R-2. Q4000 F100.\nG80\nM30\n";
    let t = path(text, &fanuc());
    let z = -10.0;
    expect(
        &t,
        1,
        &[
            (K::R, 28.0, z, 0.0),
            (K::F, 24.0, z, 0.0),
            (K::R, 28.0, z, 0.0),
            (K::R, 24.1, z, 0.0),
            (K::F, 20.0, z, 0.0),
            (K::R, 28.0, z, 0.0),
            (K::R, 20.1, z, 0.0),
            (K::F, 16.0, z, 0.0),
            (K::R, 28.0, z, 0.0),
            (K::R, 16.1, z, 0.0),
            (K::F, 12.0, z, 0.0),
            (K::R, 28.0, z, 0.0),
            (K::R, 12.1, z, 0.0),
            (K::F, 10.0, z, 0.0),
            (K::R, 30.0, z, 0.0),
        ],
    );
    assert_eq!(t.moves.len(), 16);
    assert!((t.moves[2].feed - 100.0).abs() < 1e-9, "feed {}", t.moves[2].feed);
}

// G87 in system B, G91 and G99: R-3. is 3 below the initial level 25
// (X50.), point R at 22; in G91 the bottom X-16. (a diameter: 8 in radius) is
// from point R: 22 - 8 = 14. Q3000, 3 mm a peck: feed 22 → 19; to 22, 19.1,
// feed 16; to 22, 16.1, feed to 14; G99 returns to point R, 22. The next
// block Z-10. C90. (incremental) places the second hole at Z-5 - 10 = -15,
// C90, reached at rapid at the R level; the tool is at point R already, so
// the pecks begin at once, the same, and end at 22. F0.1 a turn at S1000
// (feed per revolution at power-on) is 100 mm/min.
#[test]
fn g87_in_system_b_returns_to_point_r_with_g99_and_drills_the_next_hole() {
    let text = "S1000 M03\nG00 X50. Z-5. C0.\nG91 G99 G87 X-16. R-3. Q3000 F0.1\nZ-10. C90.\nG80\nM30\n";
    let t = path(text, &lathe(GCodeSystem::B));
    let pecks = |z: f64, c: f64| {
        vec![
            (K::F, 19.0, z, c),
            (K::R, 22.0, z, c),
            (K::R, 19.1, z, c),
            (K::F, 16.0, z, c),
            (K::R, 22.0, z, c),
            (K::R, 16.1, z, c),
            (K::F, 14.0, z, c),
            (K::R, 22.0, z, c),
        ]
    };
    let mut want = vec![(K::R, 22.0, -5.0, 0.0)];
    want.extend(pecks(-5.0, 0.0));
    want.push((K::R, 22.0, -15.0, 90.0));
    want.extend(pecks(-15.0, 90.0));
    expect(&t, 1, &want);
    assert_eq!(t.moves.len(), 19);
    assert!((t.moves[2].feed - 100.0).abs() < 1e-9, "feed {}", t.moves[2].feed);
}

// G87 with Q and P: the pecks as above, then the dwell P at the bottom
// before the rapid out. From X50. (radius 25), R-1. (point R 24), X30.
// (bottom 15), Q5000 (5 mm): feed 24 → 19; to 24, 19.1, feed to 15; the
// dwell P300 (0.3 s); rapid to 25.
#[test]
fn g87_dwells_at_the_bottom_after_its_last_peck() {
    let text = "S1000 M03\nG98 G00 X50. Z-4.\nG87 Z-4. X30. R-1. Q5000 P300 F60.\nG80\nM30\n";
    let t = path(text, &fanuc());
    expect(
        &t,
        1,
        &[
            (K::R, 24.0, -4.0, 0.0),
            (K::F, 19.0, -4.0, 0.0),
            (K::R, 24.0, -4.0, 0.0),
            (K::R, 19.1, -4.0, 0.0),
            (K::F, 15.0, -4.0, 0.0),
            (K::D, 15.0, -4.0, 0.0),
            (K::R, 25.0, -4.0, 0.0),
        ],
    );
    assert_eq!(t.moves.len(), 8);
    assert_eq!(t.moves[6].kind, MoveKind::Dwell(0.3));
}

// G87 and the face G83 without Q: "Drilling cycle" (no depth of cut
// given): one feed to the bottom, the dwell P there, rapid out. G87 from
// X40. (radius 20), R-1. (point R 19), X10. (bottom 5), P200 (0.2 s); G83
// from Z5., R-2. (point R at Z3), Z-8., no dwell.
#[test]
fn drilling_without_q_is_one_feed_to_the_bottom() {
    let text = "S1000 M03\nG98 G00 X40. Z-6.\nG87 Z-6. X10. R-1. P200 F50.\nG80\nM30\n";
    let t = path(text, &fanuc());
    expect(&t, 1, &[(K::R, 19.0, -6.0, 0.0), (K::F, 5.0, -6.0, 0.0), (K::D, 5.0, -6.0, 0.0), (K::R, 20.0, -6.0, 0.0)]);
    assert_eq!(t.moves.len(), 5);
    assert_eq!(t.moves[3].kind, MoveKind::Dwell(0.2));
    let text = "S1000 M03\nG98 G00 X0. Z5.\nG83 X0. Z-8. R-2. F50.\nG80\nM30\n";
    let t = path(text, &fanuc());
    expect(&t, 1, &[(K::R, 0.0, 3.0, 0.0), (K::F, 0.0, -8.0, 0.0), (K::R, 0.0, 5.0, 0.0)]);
    assert_eq!(t.moves.len(), 4);
}

// G88 side tapping: from the initial level X40. (radius 20), R-1. (point R
// 19) to the bottom X24. (radius 12) with the spindle forward, the dwell
// P500 (0.5 s), back out to point R with the spindle reversed, then the
// spindle forward again and rapid to the initial level 20. F625. is the
// pitch 1.25 mm at 500 rpm.
#[test]
fn g88_taps_along_x_and_reverses_out_to_point_r() {
    let text = "S500 M03\nG98 G00 X40. Z-8.\nG88 Z-8. C0. X24. R-1. P500 F625.\nG80\nM30\n";
    let t = path(text, &fanuc());
    expect(
        &t,
        1,
        &[
            (K::R, 19.0, -8.0, 0.0),
            (K::F, 12.0, -8.0, 0.0),
            (K::D, 12.0, -8.0, 0.0),
            (K::F, 19.0, -8.0, 0.0),
            (K::R, 20.0, -8.0, 0.0),
        ],
    );
    assert_eq!(t.moves.len(), 6);
    assert_eq!(t.moves[2].spindle, Spindle::Cw);
    assert_eq!(t.moves[3].kind, MoveKind::Dwell(0.5));
    assert_eq!(t.moves[4].spindle, Spindle::Ccw);
    assert!((t.moves[4].feed - 625.0).abs() < 1e-9, "feed {}", t.moves[4].feed);
}

// G89 side boring: the hole at C45., reached at rapid at the initial level
// X50. (radius 25); R-2. (point R 23), to the bottom X30. (radius 15) at
// F80., the dwell P1000 (1 s), feed back out to point R, rapid to 25.
#[test]
fn g89_bores_along_x_with_the_dwell_and_feeds_out() {
    let text = "S800 M03\nG98 G00 X50. Z-12. C0.\nG89 Z-12. C45. X30. R-2. P1000 F80.\nG80\nM30\n";
    let t = path(text, &fanuc());
    expect(
        &t,
        1,
        &[
            (K::R, 25.0, -12.0, 45.0),
            (K::R, 23.0, -12.0, 45.0),
            (K::F, 15.0, -12.0, 45.0),
            (K::D, 15.0, -12.0, 45.0),
            (K::F, 23.0, -12.0, 45.0),
            (K::R, 25.0, -12.0, 45.0),
        ],
    );
    assert_eq!(t.moves.len(), 7);
    assert_eq!(t.moves[4].kind, MoveKind::Dwell(1.0));
    assert!((t.moves[5].feed - 80.0).abs() < 1e-9, "feed {}", t.moves[5].feed);
}

// Bad words, each an error at the word: a peck depth of 0, a bottom
// farther from the axis than point R (the side cycles drill in toward the
// axis), a repeat count that is not a whole number. A Haas lathe's G87 is
// a boring cycle along Z, not Fanuc's side drilling: not read.
#[test]
fn bad_side_drilling_words_are_located_errors() {
    let start = "S1000 M03\nG98 G00 X60. Z-10.\n";
    let (message, at) = error(&format!("{start}G87 Z-10. X20. R-2. Q0 F100.\nM30\n"), &fanuc());
    assert_eq!(at, "Q0");
    assert!(message.contains("G87 needs a peck depth Q greater than 0"), "{message}");
    let (message, at) = error(&format!("{start}G87 Z-10. X70. R-2. Q1000 F100.\nM30\n"), &fanuc());
    assert_eq!(at, "X70.");
    assert!(message.contains("farther from the spindle axis than its R level"), "{message}");
    let (message, at) = error(&format!("{start}G89 Z-10. X20. R-2. K1.5 F100.\nM30\n"), &fanuc());
    assert_eq!(at, "K1.5");
    assert!(message.contains("a repeat count is a whole number"), "{message}");
    let (message, at) = error(&format!("{start}G87 Z-10. X20. R-2. Q1000 F100.\nM30\n"), &haas());
    assert_eq!(at, "G87");
    assert!(message.contains("G87"), "{message}");
}
