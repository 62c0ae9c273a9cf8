//! LinuxCNC's lathe words in the linuxcnc dialect: G7 diameter and G8
//! radius mode, G33 spindle-synchronised motion, G76 in diameter mode and
//! G96 D. Each expectation is derived by hand from LinuxCNC's G-code
//! reference (sections "G7 Lathe Diameter Mode", "G8 Lathe Radius Mode",
//! "G33 Spindle Synchronized Motion", "G76 Threading Cycle", "G96, G97
//! Spindle Control Mode") and was confirmed with `rs274 -g` (LinuxCNC
//! 2.9.0~pre1): the tests pass without rs274.

mod common;

use common::linuxcnc::{error, moves, path, run_with, settings};

#[test]
fn g7_reads_x_as_a_diameter_and_g8_as_a_radius() {
    // G8 (power-on): X20 is 20 mm from the axis. G7 in the block: X20 is a
    // diameter, the tool at 10. G1 X10 Z0: radius 5. The arc's I stays a
    // radius: from (x 5, z 0) with I5 K0 the centre is at x 10, z 0, radius
    // 5; X20 (radius 10) Z-5 lies on it (√(0² + 5²) = 5). G8 X10: 10 again.
    let t = path("G18 G21\nG0 X20 Z5\nG7 G0 X20\nG1 X10 Z0 F100\nG2 X20 Z-5 I5 K0\nG8 G0 X10\nM2\n");
    assert_eq!(
        moves(&t),
        [
            ('r', 20.0, 0.0, 5.0),
            ('r', 10.0, 0.0, 5.0),
            ('f', 5.0, 0.0, 0.0),
            ('a', 10.0, 0.0, -5.0),
            ('r', 10.0, 0.0, -5.0),
        ]
    );
}

#[test]
fn g33_is_one_synchronised_feed_and_one_thread() {
    // Under G7, X20 is radius 10. G33 Z-10 K1.5 at 500 rpm: a feed of
    // 1.5 mm a turn × 500 = 750 mm/min, from Z2 to Z-10, one thread of lead
    // 1.5. Then X24 (radius 12).
    let text = "G18 G21 G7\nG0 X20 Z2\nS500 M3\nG33 Z-10 K1.5\nG0 X24\nM2\n";
    let t = path(text);
    assert_eq!(moves(&t), [('r', 10.0, 0.0, 2.0), ('f', 10.0, 0.0, -10.0), ('r', 12.0, 0.0, -10.0)]);
    assert_eq!(t.moves[1].feed, 750.0);
    let (outcome, _) = run_with(text, &settings()).unwrap();
    assert_eq!(outcome.threads.len(), 1);
    let thread = &outcome.threads[0];
    assert_eq!((thread.lead, thread.start.z, thread.end.z, thread.end.x, thread.line), (1.5, 2.0, -10.0, 10.0, 4));
    // Kept as its block for a written program (X a radius).
    assert!(t.kept.iter().any(|k| k.text == "G21 G90 G33 Z-10. K1.5"), "{:?}", t.kept);
}

#[test]
fn g33_refusals_are_rs274s() {
    assert!(
        error("G18 G21 S500 M3\nG33 Z-10 K1.5 F100\nM2\n").contains("F word used with G33"),
        "{}",
        error("G18 G21 S500 M3\nG33 Z-10 K1.5 F100\nM2\n")
    );
    assert!(error("G18 G21 S500 M3\nG33 Z-10\nM2\n").contains("K word missing with G33"));
    assert!(error("G18 G21\nG33 Z-10 K1.5\nM2\n").contains("Spindle not turning in G33"));
}

#[test]
fn g76_under_g7_reads_i_j_k_as_diameters() {
    // rs274 halves G76's I J K under G7, as it halves X: the program in
    // diameters makes the moves of the one in radii. Depths J·n (R1) under
    // K: 0.1 … 0.8 mm, 8 passes, then one at K = 0.9: nine threads.
    let common = "G18 G21\nS300 M3\n";
    let diameters = format!("{common}G7 G0 X22 Z3\nG76 P1.5 Z-20 I-2 J0.2 K1.8 Q29.5\nM2\n");
    let radii = format!("{common}G8 G0 X11 Z3\nG76 P1.5 Z-20 I-1 J0.1 K0.9 Q29.5\nM2\n");
    let (d, r) = (path(&diameters), path(&radii));
    assert_eq!(moves(&d), moves(&r));
    let (outcome, _) = run_with(&diameters, &settings()).unwrap();
    assert_eq!(outcome.threads.len(), 9);
    // The last pass at full depth: from x₀ + I − K·… the cut at
    // x = 11 − 1 − 0.9 = 9.1, Z from 3 to −20 (Q29.5: the start shifted by
    // depth·tan Q, the end by (K − depth)·tan Q = 0).
    let last = outcome.threads.last().unwrap();
    assert!((last.start.x - 9.1).abs() < 1e-9 && (last.end.z + 20.0).abs() < 1e-9, "{last:?}");
    assert!((last.start.z - (3.0 - 0.9 * 29.5f64.to_radians().tan())).abs() < 1e-9, "{last:?}");
    assert_eq!(last.lead, 1.5);
}

#[test]
fn g96_d_holds_the_spindle_to_its_top_speed() {
    // G96 S200 (200 m/min) at X100 (G7: radius 50 mm): 200 000 / (2π·50)
    // = 636.6 rpm. Feeding to X20 (radius 10): 3 183 rpm asked, D1000 holds
    // it to 1000 at the move's end.
    let t = path("G18 G21 G7\nG0 X100 Z0\nG96 D1000 S200 M3\nG95 G1 X20 F0.1\nM2\n");
    let free = 200_000.0 / (std::f64::consts::TAU * 50.0);
    assert!((t.moves[1].start.x - 50.0).abs() < 1e-9);
    assert!((t.moves[1].speed - 1000.0).abs() < 1e-6, "{}", t.moves[1].speed);
    assert!(free < 1000.0);
    assert!(error("G18 G21 G7\nG0 X100\nG96 D0 S200 M3\nM2\n").contains("G96 D0: D is the top spindle speed"));
}

#[test]
fn g7_is_linuxcncs() {
    // The Fanuc dialect has no G07: refused where it is written.
    let mut s = settings();
    s.dialect = kezuri_nc::Dialect::Fanuc;
    s.coords.control = kezuri_nc::interp::Control::Fanuc;
    let (outcome, sources) = run_with("G7 G0 X20\nM30\n", &s).unwrap();
    let e = outcome.diagnostics.iter().find(|d| d.is_error()).expect("an error");
    assert!(e.headline(&sources).contains("G07 (lathe diameter mode) is LinuxCNC's"), "{}", e.headline(&sources));
}

// ---- G70, G71, G72 along the Q subroutine's profile ----

/// A step: the profile from the cycle's start (X5 Z1, radius mode) down to
/// X2 at Z0, along Z to Z-10, up to X5.
const STEP: &str = "G18 G8 G21 F100\no1 sub\nG1 X2 Z0\nG1 Z-10\nX5\no1 endsub\nG0 X5 Z1\n";

#[test]
fn g71_cuts_layers_i_apart_and_leaves_each_by_r() {
    // LinuxCNC's reference: G71 removes layers while traversing Z, I the
    // cutting increment, R the retract. Layer by layer from the start's X
    // (5) down by I1: each a rapid down the lead-in (the line from (Z1 X5)
    // to (Z0 X2): at X4 Z = 1 − 1/3, at X3 Z = 1 − 2/3), a feed along Z to
    // the profile (its wall at Z-10), a rapid R0.5 away at 45°, a rapid
    // back over the layer to R before the layer's start, a rapid onto it.
    // At X2 the layer is the profile's floor: fed along, then up the wall.
    // (Confirmed with rs274 -g, move for move.)
    let t = path(&format!("{STEP}G71 Q1 X5 Z1 D0 I1 R0.5\nM2\n"));
    let third = 1.0 / 3.0;
    let r = |v: f64| (v * 1e4).round() / 1e4;
    // The program's G0, the cycle's rapid to its X Z and the roughing's
    // first rapid to its start: three rapids to where the tool is (both
    // interpreters make them).
    let mut want = vec![('r', 5.0, 0.0, 1.0); 3];
    for (x, z) in [(5.0, 1.0), (4.0, 1.0 - third), (3.0, 1.0 - 2.0 * third)] {
        want.extend([
            ('r', x, 0.0, r(z)),
            ('f', x, 0.0, -10.0),
            ('r', x + 0.5, 0.0, -9.5),
            ('r', x + 0.5, 0.0, r(z - 0.5)),
            ('r', x, 0.0, r(z)),
        ]);
    }
    want.extend([('r', 2.0, 0.0, 0.0), ('f', 2.0, 0.0, -10.0), ('f', 5.0, 0.0, -10.0)]);
    assert_eq!(moves(&t)[..], want[..]);
}

#[test]
fn g70_follows_the_profile_and_u_is_a_diameter_under_g7() {
    // G70 P1 D0 (after the program's G0 and the cycle's rapid to its X Z):
    // a rapid to the cycle's start, one to the profile's, then its pieces. The same
    // step written under G7 with U and W (incremental X, Z; U a diameter:
    // U6 is 3 of radius) makes the same moves.
    let radius = path(&format!("{STEP}G70 Q1 X5 Z1\nM2\n"));
    let want = [
        ('r', 5.0, 0.0, 1.0),
        ('r', 5.0, 0.0, 1.0),
        ('r', 5.0, 0.0, 1.0),
        ('r', 2.0, 0.0, 0.0),
        ('f', 2.0, 0.0, -10.0),
        ('f', 5.0, 0.0, -10.0),
    ];
    assert_eq!(moves(&radius)[..], want[..]);
    let diameter = path("G18 G7 G21 F100\no1 sub\nG1 X4 Z0\nG1 W-10\nU6\no1 endsub\nG0 X10 Z1\nG70 Q1 X10 Z1\nM2\n");
    assert_eq!(moves(&diameter), moves(&radius));
}

#[test]
fn lathe_cycle_refusals_are_rs274s() {
    assert!(error(&format!("{STEP}G71 X5 Z1\nM2\n")).contains("G71 requires a Q word"));
    assert!(error(&format!("{STEP}G17\nG71 Q1 X5 Z1\nM2\n")).contains("G71 can only be used in XZ plane (G18)"));
    assert!(error(&format!("{STEP}G72 Q1 X5 Z1 I0\nM2\n")).contains("G7X error: I must be greater than zero"));
    let both = "G18 G8 G21 F100\no1 sub\nG1 X2 U1 Z0\no1 endsub\nG0 X5 Z1\nG71 Q1\nM2\n";
    assert!(error(both).contains("G7x error: Cannot use U and X in the same block"), "{}", error(both));
    // A profile that turns back in Z cannot be roughed along it.
    let back = "G18 G8 G21 F100\no1 sub\nG1 X2 Z0\nG1 Z-10\nG1 X4 Z-5\nX5\no1 endsub\nG0 X5 Z1\nG71 Q1\nM2\n";
    assert!(error(back).contains("Not monotonic"), "{}", error(back));
    // Fillets larger than the pieces they join: rs274 "Not monotonic".
    let fillets = "G18 G8 G21 F100\no1 sub\nG1 X2 Z0 A50\nG1 Z-10 A50\nX5\no1 endsub\nG0 X5 Z1\nG71 Q1 X5 Z1\nM2\n";
    assert!(error(fillets).contains("Not monotonic"), "{}", error(fillets));
    // A profile whose only piece is under 0.001 long: rs274 2.9 crashes
    // (a segmentation fault); refused, located at the cycle.
    let short = "G18 G8 G21 F100\no1 sub\nG1 X2 Z0\nG1 Z-0.0005\no1 endsub\nG0 X5 Z1\nG71 Q1 X5 Z1\nM2\n";
    assert!(error(short).contains("t.ngc:7:1: error: G7X error: the profile has no piece left"), "{}", error(short));
    // A G72.2 whose layers never get past a pocket's wall: rs274 2.9 loops
    // without end (its time limit in the rs274 comparison); refused.
    let endless = "G18 G8 G21 F100\no1 sub\nG1 X10 Z-0.835\nG1 X8.487 Z1.047\nG1 X6.261 Z2.885 C0.18\n\
                   G3 X3.306 Z4.545 R6.82\nG1 X1.441 Z5.312 A0.2\nG1 Z2.312\no1 endsub\nG0 X12 Z3\n\
                   G72.2 Q1 X12 Z3 D0 I0.8 R0.2\nM2\n";
    assert!(error(endless).contains("the roughing does not get down the profile"), "{}", error(endless));
}

#[test]
fn lathe_cycles_turn_at_constant_surface_speed() {
    // G96 S100 (100 m/min) D1000: at radius r mm the spindle turns
    // 100 000 / (2π·r) rpm, at most 1000 (the reference's G96 D). Every
    // move of the roughing ends at that speed: 318.3 rpm at X50, 795.8 at
    // X20.
    let t = path(
        "G18 G8 G21 G95 F0.2\no1 sub\nG1 X20 Z0\nG1 Z-10\nX50\no1 endsub\nG0 X50 Z1\nG96 S100 D1000 M3\n\
         G71 Q1 X50 Z1 D0 I10 R1\nM2\n",
    );
    let cut: Vec<_> = t.moves.iter().filter(|m| m.line == 9).collect();
    assert!(cut.len() > 8, "{}", cut.len());
    for m in cut {
        let want = (100_000.0 / (std::f64::consts::TAU * m.end.x)).min(1000.0);
        assert!((m.speed - want).abs() < 1e-6, "{m:?}: {want}");
    }
}

#[test]
fn g7_or_g8_in_a_g76_block_scales_its_depths_again_as_rs274_does() {
    // rs274 2.9 scales I J K when G7/G8 in the block changes the mode, and
    // G76 halves them under G7: G8 then `G7 G76` reads I-2 J0.2 as -0.5 and
    // 0.05, the first pass at 22 − 0.5 − 0.05 = 21.45 (X22 read in G8);
    // G7 then `G8 G76` as -4 and 0.4, at 11 − 4 − 0.4 = 6.6. A warning says
    // so. (rs274 -g: the same first feeds.)
    let first_feed = |pre: &str, block: &str| {
        let text = format!("G18 G21 {pre}\nS300 M3\nG0 X22 Z3\n{block} P1.5 Z-20 I-2 J0.2 K1.8 Q29.5\nM2\n");
        let (outcome, _) = run_with(&text, &settings()).unwrap();
        let warned = outcome.diagnostics.iter().any(|d| d.message.contains("in a block of its own"));
        let x = outcome.toolpath.moves.iter().find(|m| m.kind == kezuri_geom::MoveKind::Feed).unwrap().end.x;
        ((x * 1e4).round() / 1e4, warned)
    };
    assert_eq!(first_feed("G8", "G7 G76"), (21.45, true));
    assert_eq!(first_feed("G7", "G8 G76"), (6.6, true));
    assert_eq!(first_feed("G7", "G76"), (9.9, false));
    assert_eq!(first_feed("G8", "G76"), (19.8, false));
    assert_eq!(first_feed("G7", "G7 G76"), (9.9, false));
}

#[test]
fn the_modes_read_back_as_rs274_reads_them() {
    // #<_lathe_diameter_mode> is 1 under G7, #<_spindle_css_mode> under
    // G96: each read is written into X (radius mode) as a move.
    let t = path(
        "G18 G21\nG0 X#<_lathe_diameter_mode> Z0\nG7\nG8 G0 X[#<_lathe_radius_mode> * 0 + 2]\nG7\nG8 G0 X[3 + #<_lathe_diameter_mode>]\n\
         G96 D500 S50 M3\nG0 X#<_spindle_css_mode>\nG97 S100\nG0 X[4 + #<_spindle_css_mode>]\nM2\n",
    );
    // X0 (G8 at the start), 2, then 3 + 1 (the parameter read while the
    // line before left G7 in force; the line's own G8 leaves X a radius),
    // 1 (G96), 4 + 0 (G97). rs274 -g: the same five traverses.
    let xs: Vec<f64> = t.moves.iter().map(|m| m.end.x).collect();
    assert_eq!(xs, [0.0, 2.0, 4.0, 1.0, 4.0]);
}

/// 2,000 drawn profiles of any words (motion codes, X Z U W I K R A C of
/// odd values, G91, G20, every cycle with any of its words): each run
/// ends, with moves of finite numbers or an error, never a panic.
#[test]
fn any_profile_ends_without_a_panic_or_a_nan() {
    let mut seed = 7u64;
    let mut next = |n: usize| {
        seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        ((seed >> 33) as usize) % n
    };
    let values = ["0", "-0", "1", "-1", "0.001", "1e3", "-5", "2.5", "100", "-100", "0.5"];
    let codes = ["G0", "G1", "G2", "G3", "G91", "G90", "G91.1", "G90.1", "G7", "G8", "G20", "G21", "G80"];
    let cycles = ["G70", "G71", "G71.1", "G71.2", "G72", "G72.1", "G72.2"];
    let starts = ["G18 G7", "G18 G8", "G18 G7 G91", "G18 G8 G20"];
    for _ in 0..2000 {
        let mut text = format!("{} F100 S500 M3\no1 sub\n", starts[next(starts.len())]);
        for _ in 0..1 + next(8) {
            if next(10) < 6 {
                text.push_str(codes[next(codes.len())]);
            }
            for _ in 0..1 + next(4) {
                text.push_str(&format!(" {}{}", b"XZUWIKRAC"[next(9)] as char, values[next(values.len())]));
            }
            text.push('\n');
        }
        text.push_str(&format!("o1 endsub\nG0 X{} Z{}\n{} Q1", values[next(11)], values[next(11)], cycles[next(7)]));
        for _ in 0..next(6) {
            text.push_str(&format!(" {}{}", b"XZDEIPRUW"[next(9)] as char, values[next(values.len())]));
        }
        text.push_str("\nG0 X1\nM2\n");
        // A block naming a word twice is a parse error: also an end.
        let Ok((outcome, _)) = run_with(&text, &settings()) else { continue };
        for m in &outcome.toolpath.moves {
            let finite = m.end.to_array().iter().all(|v| v.is_finite()) && m.feed.is_finite();
            assert!(finite, "{text}\n{m:?}");
        }
    }
}
