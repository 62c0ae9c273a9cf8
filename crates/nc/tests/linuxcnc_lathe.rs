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
