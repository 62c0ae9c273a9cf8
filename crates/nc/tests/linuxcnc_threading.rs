//! LinuxCNC's threading in the linuxcnc dialect: G33.1 rigid tapping and
//! the G76 threading cycle, its passes, tapers and degression, and how it
//! is written back. Each expectation comes from LinuxCNC's manual and was
//! confirmed with `rs274 -g` (LinuxCNC 2.9.0~pre1) on the same program,
//! then written here by hand: the tests pass without `rs274`.

mod common;

use common::linuxcnc::{error, moves, path};
use kezuri_geom::Toolpath;

// ---- G33.1 rigid tapping ----

#[test]
fn g33_1_taps_to_the_end_point_and_back_kept_as_its_block() {
    // rs274: RIGID_TAP(1, 1, -10) from (1, 1, 5), the feed synchronised at
    // K a turn, back to the start; `G91 G33.1 Z-4` from Z5 taps to Z1.
    let t = path("G21 G90\nG0 X1 Y1 Z5\nS500 M3\nG33.1 Z-10 K1.5\nG0 X2\nG91 G33.1 Z-4 K1\nG90\nG0 Z7\nM2\n");
    assert_eq!(
        moves(&t),
        [
            ('r', 1.0, 1.0, 5.0),
            ('f', 1.0, 1.0, -10.0),
            ('f', 1.0, 1.0, 5.0),
            ('r', 2.0, 1.0, 5.0),
            ('f', 2.0, 1.0, 1.0),
            ('f', 2.0, 1.0, 5.0),
            ('r', 2.0, 1.0, 7.0),
        ]
    );
    // The feed: 1.5 mm a turn at 500 rpm; the spindle reversed on the way out.
    assert_eq!((t.moves[1].feed, t.moves[1].spindle), (750.0, kezuri_geom::Spindle::Cw));
    assert_eq!((t.moves[2].feed, t.moves[2].spindle), (750.0, kezuri_geom::Spindle::Ccw));
    assert_eq!(t.moves[3].spindle, kezuri_geom::Spindle::Cw);
    // Kept for a written program, standing for its two moves.
    let kept: Vec<_> = t.kept.iter().filter(|k| k.moves > 0).map(|k| (k.before, k.moves, k.text.as_str())).collect();
    assert_eq!(kept, [(1, 2, "G21 G90 G33.1 Z-10. K1.5"), (4, 2, "G21 G90 G33.1 Z1. K1.")]);
}

#[test]
fn g33_1_errors_are_rs274s() {
    assert_eq!(
        error("G21 S500 M3\nG33.1 Z-10\nM2\n"),
        "t.ngc:2:1: error: K word missing with G33.1: give the pitch, the distance a turn"
    );
    assert!(error("G21\nG33.1 Z-10 K1\nM2\n").starts_with("t.ngc:2:1: error: Spindle not turning in G33.1"));
    // K is not modal: each block gives it.
    assert!(error("G21 S500 M3\nG33.1 Z-10 K1\nZ-3\nM2\n").starts_with("t.ngc:3:1: error: K word missing with G33.1"));
}

// ---- G76 threading ----

/// A G76's passes from move `from` on, four moves each, as rs274 prints
/// them: (x of the rapid out, z there, x of the cut, z at the end of the
/// feed); checks that each is rapid, rapid, feed, rapid, the rapid back at
/// the cut's z and the x out.
fn passes(t: &Toolpath, from: usize, count: usize) -> Vec<(f64, f64, f64, f64)> {
    let m = moves(t);
    (0..count)
        .map(|p| {
            let q = &m[from + 4 * p..from + 4 * p + 4];
            let kinds: String = q.iter().map(|m| m.0).collect();
            assert_eq!(kinds, "rrfr", "pass {p}: {q:?}");
            assert_eq!((q[1].3, q[2].1, q[3].1, q[3].3), (q[0].3, q[1].1, q[0].1, q[2].3), "pass {p}: {q:?}");
            (q[0].1, q[0].3, q[1].1, q[2].3)
        })
        .collect()
}

#[test]
fn g76_threads_pass_by_pass_as_rs274() {
    // rs274: from (10, 5), I-1 J0.3 K1 Q0 H2: passes at 0.3, 0.6, 0.9
    // (1.2 is past K), one at K, two spring passes at K; the feed
    // synchronised at P1.5 a turn; then a rapid to the end point (here
    // where the last pass ends), then G0 X20.
    let t = path("G21 G90 G18\nG0 X10 Z5\nS500 M3\nG76 P1.5 Z-20 I-1 J0.3 K1 Q0 H2\nG0 X20\nM2\n");
    let m = moves(&t);
    assert_eq!(m.len(), 1 + 6 * 4 + 2);
    assert_eq!(
        m[..5],
        [
            ('r', 10.0, 0.0, 5.0),
            ('r', 10.7, 0.0, 5.0),
            ('r', 8.7, 0.0, 5.0),
            ('f', 8.7, 0.0, -20.0),
            ('r', 10.7, 0.0, -20.0)
        ]
    );
    assert_eq!(
        passes(&t, 1, 6),
        [
            (10.7, 5.0, 8.7, -20.0),
            (10.4, 5.0, 8.4, -20.0),
            (10.1, 5.0, 8.1, -20.0),
            (10.0, 5.0, 8.0, -20.0),
            (10.0, 5.0, 8.0, -20.0),
            (10.0, 5.0, 8.0, -20.0),
        ]
    );
    assert_eq!(m[25..], [('r', 10.0, 0.0, -20.0), ('r', 20.0, 0.0, -20.0)]);
    assert_eq!(t.moves[3].feed, 750.0);

    // Under G17 too, in XZ; I2 cuts toward +X, Z above the start runs
    // toward +Z, R2 gives depths 0.4·√n, Q29.5 moves each pass's start
    // and end along Z by tan 29.5° of its depth; one spring pass (H1).
    let t = path("G21 G90 G17\nG0 X-10 Z2\nS500 M3\nG76 P2 Z10 I2 J0.4 K1.3 R2 Q29.5 H1\nM2\n");
    assert_eq!(t.moves.len(), 1 + 12 * 4 + 1);
    assert_eq!(
        passes(&t, 1, 12),
        [
            (-10.9, 2.2263, -7.6, 9.4908),
            (-10.7343, 2.32, -7.4343, 9.5845),
            (-10.6072, 2.392, -7.3072, 9.6565),
            (-10.5, 2.4526, -7.2, 9.7171),
            (-10.4056, 2.506, -7.1056, 9.7705),
            (-10.3202, 2.5543, -7.0202, 9.8188),
            (-10.2417, 2.5988, -6.9417, 9.8633),
            (-10.1686, 2.6401, -6.8686, 9.9046),
            (-10.1, 2.6789, -6.8, 9.9434),
            (-10.0351, 2.7157, -6.7351, 9.9801),
            (-10.0, 2.7355, -6.7, 10.0),
            (-10.0, 2.7355, -6.7, 10.0),
        ]
    );
    assert_eq!(moves(&t).last(), Some(&('r', -10.0, 0.0, 10.0)));
    assert_eq!(t.moves[3].feed, 1000.0);
}

#[test]
fn g76_end_point_increments_and_inches_as_rs274() {
    // J0.5 K1: 1.0 is not under K, so one pass at 0.5, then K. The rapid
    // after the passes goes to the block's end point: X3 given, Y3 given.
    let t = path("G21 G90\nG0 X10 Z5\nS500 M3\nG76 X3 P1 Z-2 I-1 J0.5 K1\nM2\n");
    assert_eq!(passes(&t, 1, 2), [(10.5, 5.0, 8.5, -2.0), (10.0, 5.0, 8.0, -2.0)]);
    assert_eq!(moves(&t)[9..], [('r', 3.0, 0.0, -2.0)]);
    let t = path("G21 G90\nG0 X10 Z5\nS500 M4\nG76 P1 Y3 Z-2 I-1 J0.5 K1\nM2\n");
    assert_eq!(moves(&t)[9..], [('r', 10.0, 3.0, -2.0)]);
    // G91: Z-2 from Z5 ends at Z3.
    let t = path("G21 G91\nG0 X10 Z5\nS500 M3\nG76 P1 Z-2 I-1 J0.5 K1\nM2\n");
    assert_eq!(passes(&t, 1, 2), [(10.5, 5.0, 8.5, 3.0), (10.0, 5.0, 8.0, 3.0)]);
    // Inches: rs274's 1.05, 0.85, -1 in.
    let t = path("G20 G90\nG0 X1 Z0.5\nS500 M3\nG76 P0.1 Z-1 I-0.1 J0.05 K0.1\nM2\n");
    assert_eq!(passes(&t, 1, 2), [(26.67, 12.7, 21.59, -25.4), (25.4, 12.7, 20.32, -25.4)]);
    assert_eq!(t.moves[3].feed, 1270.0);
    // Z at the start: rs274 shifts as toward -Z (Q30: tan 30° × 0.5).
    let t = path("G21 G90\nG0 X10 Z5\nS500 M3\nG76 P1 Z5 I-1 J0.5 K1 Q30\nM2\n");
    assert_eq!(passes(&t, 1, 1), [(10.5, 4.7113, 8.5, 5.2887)]);
}

#[test]
fn g76_tapered_ends_as_rs274() {
    // rs274 2.9's output for `G21 G90 G18 / G0 X10 Z5 / S500 M3 / G76 P1.5
    // Z-20 I-1 J0.4 K1 Q0 E2 L… / G0 X20 / M2`: passes at 0.4, 0.8, K.
    // L1: the rapid in becomes a feed in by I to K shallower than the pass
    // and a feed along the taper, 2 along Z, down to the pass (both at the
    // pitch 1.5·√(2² + 1²)/2 = 1.677051 a turn), then the feed at 1.5.
    let program =
        |l: u8| format!("G21 G90 G18\nG0 X10 Z5\nS500 M3\nG76 P1.5 Z-20 I-1 J0.4 K1 Q0 E2 L{l}\nG0 X20\nM2\n");
    let t = path(&program(1));
    #[rustfmt::skip]
    assert_eq!(moves(&t), [
        ('r', 10.0, 0.0, 5.0),
        ('r', 10.6, 0.0, 5.0), ('f', 9.6, 0.0, 5.0), ('f', 8.6, 0.0, 3.0), ('f', 8.6, 0.0, -20.0), ('r', 10.6, 0.0, -20.0),
        ('r', 10.2, 0.0, 5.0), ('f', 9.2, 0.0, 5.0), ('f', 8.2, 0.0, 3.0), ('f', 8.2, 0.0, -20.0), ('r', 10.2, 0.0, -20.0),
        ('r', 10.0, 0.0, 5.0), ('f', 9.0, 0.0, 5.0), ('f', 8.0, 0.0, 3.0), ('f', 8.0, 0.0, -20.0), ('r', 10.0, 0.0, -20.0),
        ('r', 10.0, 0.0, -20.0), ('r', 20.0, 0.0, -20.0),
    ]);
    let feeds: Vec<f64> = t.moves[2..5].iter().map(|m| (m.feed * 1e4).round() / 1e4).collect();
    assert_eq!(feeds, [838.5255, 838.5255, 750.0]);
    // L2: the feed stops 2 short and rises back out by K along the taper.
    let t = path(&program(2));
    #[rustfmt::skip]
    assert_eq!(moves(&t), [
        ('r', 10.0, 0.0, 5.0),
        ('r', 10.6, 0.0, 5.0), ('r', 8.6, 0.0, 5.0), ('f', 8.6, 0.0, -18.0), ('f', 9.6, 0.0, -20.0), ('r', 10.6, 0.0, -20.0),
        ('r', 10.2, 0.0, 5.0), ('r', 8.2, 0.0, 5.0), ('f', 8.2, 0.0, -18.0), ('f', 9.2, 0.0, -20.0), ('r', 10.2, 0.0, -20.0),
        ('r', 10.0, 0.0, 5.0), ('r', 8.0, 0.0, 5.0), ('f', 8.0, 0.0, -18.0), ('f', 9.0, 0.0, -20.0), ('r', 10.0, 0.0, -20.0),
        ('r', 10.0, 0.0, -20.0), ('r', 20.0, 0.0, -20.0),
    ]);
    let feeds: Vec<f64> = t.moves[3..5].iter().map(|m| (m.feed * 1e4).round() / 1e4).collect();
    assert_eq!(feeds, [750.0, 838.5255]);
    // L3: both.
    let t = path(&program(3));
    #[rustfmt::skip]
    assert_eq!(moves(&t), [
        ('r', 10.0, 0.0, 5.0),
        ('r', 10.6, 0.0, 5.0), ('f', 9.6, 0.0, 5.0), ('f', 8.6, 0.0, 3.0), ('f', 8.6, 0.0, -18.0), ('f', 9.6, 0.0, -20.0),
        ('r', 10.6, 0.0, -20.0),
        ('r', 10.2, 0.0, 5.0), ('f', 9.2, 0.0, 5.0), ('f', 8.2, 0.0, 3.0), ('f', 8.2, 0.0, -18.0), ('f', 9.2, 0.0, -20.0),
        ('r', 10.2, 0.0, -20.0),
        ('r', 10.0, 0.0, 5.0), ('f', 9.0, 0.0, 5.0), ('f', 8.0, 0.0, 3.0), ('f', 8.0, 0.0, -18.0), ('f', 9.0, 0.0, -20.0),
        ('r', 10.0, 0.0, -20.0),
        ('r', 10.0, 0.0, -20.0), ('r', 20.0, 0.0, -20.0),
    ]);
    // L0, E without L, E0: no taper, the passes of a plain G76.
    let plain = moves(&path(&program(0)));
    for block in ["E2", "E0 L3"] {
        let text = format!("G21 G90 G18\nG0 X10 Z5\nS500 M3\nG76 P1.5 Z-20 I-1 J0.4 K1 Q0 {block}\nG0 X20\nM2\n");
        assert_eq!(moves(&path(&text)), plain, "{block}");
    }
    assert_eq!(plain.len(), 1 + 3 * 4 + 2);

    // rs274 2.9's output for `G21 G90 G18 / G0 X-10 Z2 / S500 M3 / G76 P2
    // Z10 I2 J0.4 K1.3 R2 Q29.5 H1 E1.5 L3`: I2 cuts toward +X and Z runs
    // toward +Z, so the tapers do too; Q shifts each pass's ends, not the
    // tapers' length. The first pass and the last (a spring pass), pitch
    // 2·√(1.5² + 1.3²)/1.5 = 2.646591 on the tapers.
    let t = path("G21 G90 G18\nG0 X-10 Z2\nS500 M3\nG76 P2 Z10 I2 J0.4 K1.3 R2 Q29.5 H1 E1.5 L3\nM2\n");
    let m = moves(&t);
    assert_eq!(m.len(), 1 + 12 * 6 + 1);
    #[rustfmt::skip]
    assert_eq!(m[1..7], [
        ('r', -10.9, 0.0, 2.2263), ('f', -8.9, 0.0, 2.2263), ('f', -7.6, 0.0, 3.7263), ('f', -7.6, 0.0, 7.9908),
        ('f', -8.9, 0.0, 9.4908), ('r', -10.9, 0.0, 9.4908),
    ]);
    #[rustfmt::skip]
    assert_eq!(m[67..], [
        ('r', -10.0, 0.0, 2.7355), ('f', -8.0, 0.0, 2.7355), ('f', -6.7, 0.0, 4.2355), ('f', -6.7, 0.0, 8.5),
        ('f', -8.0, 0.0, 10.0), ('r', -10.0, 0.0, 10.0), ('r', -10.0, 0.0, 10.0),
    ]);
    assert_eq!((t.moves[2].feed * 1e4).round() / 1e4, 1323.2955);
    assert_eq!(t.moves[4].feed, 1000.0);
}

#[test]
fn g76_errors_are_rs274s() {
    for (block, expected) in [
        ("G76 P1 Z-2 I0 J0.5 K1", "t.ngc:4:12: error: In G76, I must not be 0"),
        ("G76 P1 Z-2 I-1 J0 K1", "t.ngc:4:16: error: In G76, J must be greater than 0"),
        ("G76 P1 Z-2 I-1 J2 K1", "t.ngc:4:19: error: In G76, K must be greater than J"),
        ("G76 P1 Z-2 I-1 K1", "t.ngc:4:1: error: I J or K words missing with G76"),
        ("G76 P1 Z-2 I-1 J0.5", "t.ngc:4:1: error: I J or K words missing with G76"),
        ("G76 P-1 Z-2 I-1 J0.5 K1", "t.ngc:4:1: error: P word missing with G76"),
        ("G76 P1 I-1 J0.5 K1", "t.ngc:4:1: error: All axes missing with G76"),
        ("G76 P1 Z-2 I-1 J0.5 K1 A3", "t.ngc:4:24: error: Cannot move rotary axes with G76"),
        // The mode stays; P I J K do not.
        ("G76 P1 Z-2 I-1 J0.5 K1\nZ-10", "t.ngc:5:1: error: P word missing with G76"),
        // L as rs274 reads it: "Negative l word used", "Non integer value
        // for integer" (L1.00001 is L1).
        ("G76 P1 Z-2 I-1 J0.5 K1 E1 L-1", "t.ngc:4:27: error: Negative L word used: G76 L is the tapered ends"),
        ("G76 P1 Z-2 I-1 J0.5 K1 E1 L1.5", "t.ngc:4:27: error: Non integer value for integer: G76 L is"),
        // Refused where rs274 runs it: L over 3 (rs274 reads its bits, L5
        // as L1), E < 0 (rs274: no taper), tapers longer than the thread
        // (rs274 feeds back along Z under synchronisation).
        (
            "G76 P1 Z-2 I-1 J0.5 K1 E1 L5",
            "t.ngc:4:27: error: G76 L is the tapered ends: 0 none, 1 entry, 2 exit, 3 both, not 5",
        ),
        ("G76 P1 Z-2 I-1 J0.5 K1 E-1 L1", "t.ngc:4:24: error: G76 needs a taper length E of 0 or more"),
        ("G76 P1 Z-2 I-1 J0.5 K1 E3.6 L3", "t.ngc:4:24: error: G76's tapers (E at each tapered end) are longer"),
        ("G76 P1 Z-2 I-1 J0.5 K1 E7.5 L2", "t.ngc:4:24: error: G76's tapers (E at each tapered end) are longer"),
        ("G76 P1 Z-2 I-1 J0.5 K1 Q30 E6.6 L1", "t.ngc:4:28: error: G76's tapers (E at each tapered end) are longer"),
    ] {
        let e = error(&format!("G21 G90\nG0 X10 Z5\nS500 M3\n{block}\nM2\n"));
        assert!(e.starts_with(expected), "{block}: {e}");
    }
    assert!(error("G21\nG0 X10 Z5\nG76 P1.5 Z-20 I-1 J0.3 K1\nM2\n")
        .starts_with("t.ngc:3:1: error: Spindle not turning in G76"));
    // A block without axis words in the mode moves nothing.
    let t = path("G21 G90\nG0 X10 Z5\nS500 M3\nG76 P1 Z-2 I-1 J0.5 K1\nM5\nG0 X20\nM2\n");
    assert_eq!(moves(&t).last(), Some(&('r', 20.0, 0.0, -2.0)));
}

#[test]
fn g76_is_written_back_for_linuxcnc_and_refused_by_fanuc_and_grbl() {
    use kezuri_nc::write::{program, Dialect as Out, WriteOptions};
    use kezuri_nc::ErrorKind;
    let t = path("G21 G90\nG0 X10 Z5\nS500 M3\nG91 G76 P1.5 Z-25 I-1 J0.3 K1 H2\nG90 G0 X20\nM2\n");
    let kept: Vec<_> = t.kept.iter().filter(|k| k.moves > 0).map(|k| (k.before, k.moves, k.text.as_str())).collect();
    assert_eq!(kept, [(1, 25, "G21 G90 G76 Z-20. P1.5 I-1. J0.3 K1. Q0. H2.")]);
    let options = |dialect| WriteOptions { dialect, ..WriteOptions::default() };
    let written = program(&t, &options(Out::LinuxCnc)).unwrap();
    assert!(written.contains("G76 Z-20. P1.5 I-1. J0.3 K1. Q0. H2.\n"), "{written}");
    assert_eq!(moves(&path(&written)), moves(&t), "{written}");
    // The tapers with it.
    let t = path("G21 G90\nG0 X10 Z5\nS500 M3\nG76 P1.5 Z-20 I-1 J0.3 K1 E2 L3\nM2\n");
    let written = program(&t, &options(Out::LinuxCnc)).unwrap();
    assert!(written.contains("G76 Z-20. P1.5 I-1. J0.3 K1. Q0. E2. L3\n"), "{written}");
    assert_eq!(moves(&path(&written)), moves(&t), "{written}");
    for out in [Out::Fanuc, Out::Grbl] {
        let e = program(&t, &options(out)).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Unsupported, "{e}");
        let e = e.to_string();
        assert!(e.contains("no 'G21 G90 G76 Z-20."), "{e}");
    }
}

#[test]
fn g76_degression_below_1_is_1() {
    // rs274 2.9: J0.1 K1 makes 10 feeds to the thread's end with R0.8 as
    // with R1 (32 with R1.5).
    let feeds = |r: &str| {
        let t = path(&format!("G18 G21\nM3 S100\nG0 X10 Z5\nG76 P1.5 Z-20 I-1 J0.1 K1 R{r}\nM2\n"));
        moves(&t).iter().filter(|m| m.0 != 'r').count()
    };
    assert_eq!(feeds("1"), 10);
    assert_eq!(feeds("0.8"), 10);
    assert_eq!(feeds("0.5"), 10);
    assert_eq!(feeds("1.5"), 32);
}
