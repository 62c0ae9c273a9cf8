//! A lathe's cycles: the single cycles G90/G92/G94 (system A), G77/G78/G79
//! (B), G20/G21/G24 (C), with and without taper; G74/G75 grooving and peck
//! drilling; G76 multiple threading; Haas's one-block forms.
//!
//! Every expected number is worked out by hand in the comments from the
//! definitions of FANUC Series 0i-TF Plus Operator's Manual (B-64604EN),
//! lathe system ("Canned cycle (G90, G92, G94)"; "Multiple
//! repetitive cycle": G74, G75, G76) and the Haas Lathe Operator's Manual
//! (G-codes chapter), before the output was looked at. Positions are the
//! tool's: X a radius (a diameter X50. is 25 from the axis).

use kezuri_geom::{MoveKind, Toolpath};
use kezuri_nc::interp::GCodeSystem;

mod common;

use common::lathe::{error, fanuc, haas, lathe, outcome, path};

#[derive(Clone, Copy, Debug, PartialEq)]
enum K {
    R,
    F,
}

/// The moves from index `from` on are these, in kind and end (X radius, Z).
fn expect(t: &Toolpath, from: usize, want: &[(K, f64, f64)]) {
    let got: Vec<_> = t.moves[from..from + want.len().min(t.moves.len() - from)]
        .iter()
        .map(|m| (if m.kind == MoveKind::Rapid { K::R } else { K::F }, m.end.x, m.end.z))
        .collect();
    let ok = got.len() == want.len()
        && got.iter().zip(want).all(|(g, w)| g.0 == w.0 && (g.1 - w.1).abs() < 1e-6 && (g.2 - w.2).abs() < 1e-6);
    assert!(ok, "moves from {from}:\n got  {got:?}\n want {want:?}");
}

// "Outer diameter/internal diameter cutting cycle (G90)", straight: from the
// start point A the tool goes (1) at rapid in X to the end point's X, (2)
// feeds in Z to Z, (3) feeds out in X to A's X, (4) rapid in Z back to A.
// A = X50. Z2. is (25, 2); X40. Z-30. is (20, -30): (R 20 2) (F 20 -30)
// (F 25 -30) (R 25 2). X Z and R are modal in the cycle ("Usage of canned
// cycles"): the next block X35. cuts at radius 17.5 to Z-30 again. F0.2 a
// turn at S1000 is 200 mm/min.
#[test]
fn g90_straight_in_x_then_repeated() {
    let t = path("S1000 M03\nG00 X50. Z2.\nG90 X40. Z-30. F0.2\nX35.\nG00 X100. Z100.\nM30\n", &fanuc());
    assert_eq!(t.moves.len(), 10);
    expect(
        &t,
        1,
        &[
            (K::R, 20.0, 2.0),
            (K::F, 20.0, -30.0),
            (K::F, 25.0, -30.0),
            (K::R, 25.0, 2.0),
            (K::R, 17.5, 2.0),
            (K::F, 17.5, -30.0),
            (K::F, 25.0, -30.0),
            (K::R, 25.0, 2.0),
            (K::R, 50.0, 100.0),
        ],
    );
    assert!((t.moves[2].feed - 200.0).abs() < 1e-9, "feed {}", t.moves[2].feed);
    assert_eq!(t.moves[1].feed, 0.0);
}

// The same cycle in the U W form: U is the end point's diameter less A's
// (U-10. is -5 in radius: 25 - 5 = 20), W its Z less A's (2 - 32 = -30).
// The repeat U-15. is from A again: 25 - 7.5 = 17.5.
#[test]
fn g90_straight_in_u_w_then_repeated() {
    let t = path("S1000 M03\nG00 X50. Z2.\nG90 U-10. W-32. F0.2\nU-15.\nM30\n", &fanuc());
    expect(
        &t,
        1,
        &[
            (K::R, 20.0, 2.0),
            (K::F, 20.0, -30.0),
            (K::F, 25.0, -30.0),
            (K::R, 25.0, 2.0),
            (K::R, 17.5, 2.0),
            (K::F, 17.5, -30.0),
            (K::F, 25.0, -30.0),
            (K::R, 25.0, 2.0),
        ],
    );
}

// G90 taper: R is the radius where the cut starts less the end point's
// (the manual's first figure: U < 0, W < 0, R < 0). A = X52. Z2. (26, 2),
// end X50. Z-30. (25, -30), R-2.: the rapid goes in to 25 - 2 = 23, the
// cut runs from (23, 2) to (25, -30), then out to 26 and back.
#[test]
fn g90_taper() {
    let t = path("S1000 M03\nG00 X52. Z2.\nG90 X50. Z-30. R-2. F0.2\nM30\n", &fanuc());
    expect(&t, 1, &[(K::R, 23.0, 2.0), (K::F, 25.0, -30.0), (K::F, 26.0, -30.0), (K::R, 26.0, 2.0)]);
    // The third figure's limit: R and U/2 of opposite signs need |R| <=
    // |U/2|; here U/2 = -1 and R+1.5 would start the cut outside A.
    let (m, at) = error("S1000 M03\nG00 X52. Z2.\nG90 X50. Z-30. R1.5 F0.2\nM30\n", &fanuc());
    assert_eq!(at, "R1.5");
    assert!(m.contains("beyond the start point"), "{m}");
}

// "End face turning cycle (G94)": (1) rapid in Z to Z, (2) feed in X to
// X, (3) feed out in Z to A's Z, (4) rapid in X back to A. A = (26, 2),
// X10. Z-2.: (R 26 -2) (F 5 -2) (F 5 2) (R 26 2); the repeat Z-4. faces
// again at -4 down to X10. With R-3. (the Z where the cut starts less
// the end point's Z) the rapid goes to Z -2 - 3 = -5 and the cut runs
// from (26, -5) to (5, -2).
#[test]
fn g94_straight_repeated_and_tapered() {
    let t = path("S1000 M03\nG00 X52. Z2.\nG94 X10. Z-2. F0.2\nZ-4.\nM30\n", &fanuc());
    expect(
        &t,
        1,
        &[
            (K::R, 26.0, -2.0),
            (K::F, 5.0, -2.0),
            (K::F, 5.0, 2.0),
            (K::R, 26.0, 2.0),
            (K::R, 26.0, -4.0),
            (K::F, 5.0, -4.0),
            (K::F, 5.0, 2.0),
            (K::R, 26.0, 2.0),
        ],
    );
    let t = path("S1000 M03\nG00 X52. Z2.\nG94 U-42. W-4. R-3. F0.2\nM30\n", &fanuc());
    expect(&t, 1, &[(K::R, 26.0, -5.0), (K::F, 5.0, -2.0), (K::F, 5.0, 2.0), (K::R, 26.0, 2.0)]);
}

// "Threading cycle (G92)": as G90, the cut threaded at F the lead and the
// way out in X at rapid. A = X25. Z5. (12.5, 5), X19.2 Z-20. F1.5:
// (R 9.6 5) (thread 9.6 -20) (R 12.5 -20) (R 12.5 5); the repeat X18.8
// threads at 9.4. Each pass is a thread of lead 1.5 from (9.6, 5) to
// (9.6, -20); the feed is the lead at the spindle speed, 1.5 x 500 = 750
// mm/min. With R-1. the pass starts at radius 9.6 - 1 = 8.6.
#[test]
fn g92_threads_each_pass() {
    let o = outcome("S500 M03\nG00 X25. Z5.\nG92 X19.2 Z-20. F1.5\nX18.8\nM30\n", &fanuc());
    let t = &o.toolpath;
    expect(
        t,
        1,
        &[
            (K::R, 9.6, 5.0),
            (K::F, 9.6, -20.0),
            (K::R, 12.5, -20.0),
            (K::R, 12.5, 5.0),
            (K::R, 9.4, 5.0),
            (K::F, 9.4, -20.0),
            (K::R, 12.5, -20.0),
            (K::R, 12.5, 5.0),
        ],
    );
    assert!((t.moves[2].feed - 750.0).abs() < 1e-9, "feed {}", t.moves[2].feed);
    assert_eq!(o.threads.len(), 2);
    assert_eq!(o.threads[0].lead, 1.5);
    assert!((o.threads[0].start.x - 9.6).abs() < 1e-9 && o.threads[0].start.z == 5.0);
    assert!((o.threads[1].end.x - 9.4).abs() < 1e-9 && o.threads[1].end.z == -20.0);
    let t = path("S500 M03\nG00 X25. Z5.\nG92 X19.2 Z-20. R-1. F1.5\nM30\n", &fanuc());
    expect(&t, 1, &[(K::R, 8.6, 5.0), (K::F, 9.6, -20.0), (K::R, 12.5, -20.0), (K::R, 12.5, 5.0)]);
}

// System B ("G code list": G77 G78 G79 are system A's G90 G92 G94; G90 G91
// absolute/incremental; G95 feed per revolution): the same cycles, the
// incremental form by G91 (X-10. a diameter: -5 in radius).
#[test]
fn system_b_single_cycles() {
    let b = lathe(GCodeSystem::B);
    let t = path("G95 S1000 M03\nG00 X50. Z2.\nG77 X40. Z-30. F0.2\nM30\n", &b);
    expect(&t, 1, &[(K::R, 20.0, 2.0), (K::F, 20.0, -30.0), (K::F, 25.0, -30.0), (K::R, 25.0, 2.0)]);
    assert!((t.moves[2].feed - 200.0).abs() < 1e-9);
    let t = path("G95 S1000 M03\nG00 X50. Z2.\nG91 G77 X-10. Z-32. R-1. F0.2\nM30\n", &b);
    expect(&t, 1, &[(K::R, 19.0, 2.0), (K::F, 20.0, -30.0), (K::F, 25.0, -30.0), (K::R, 25.0, 2.0)]);
    let o = outcome("G95 S500 M03\nG00 X25. Z5.\nG78 X19.2 Z-20. F1.5\nM30\n", &b);
    assert_eq!(o.threads.len(), 1);
    let t = path("G95 S1000 M03\nG00 X52. Z2.\nG79 X10. Z-2. F0.2\nM30\n", &b);
    expect(&t, 1, &[(K::R, 26.0, -2.0), (K::F, 5.0, -2.0), (K::F, 5.0, 2.0), (K::R, 26.0, 2.0)]);
}

// System C: G20 G21 G24 are the single cycles.
#[test]
fn system_c_single_cycles() {
    let c = lathe(GCodeSystem::C);
    let t = path("G95 S1000 M03\nG00 X50. Z2.\nG20 X40. Z-30. F0.2\nM30\n", &c);
    expect(&t, 1, &[(K::R, 20.0, 2.0), (K::F, 20.0, -30.0), (K::F, 25.0, -30.0), (K::R, 25.0, 2.0)]);
    let t = path("G95 S1000 M03\nG00 X52. Z2.\nG24 X10. Z-2. F0.2\nM30\n", &c);
    expect(&t, 1, &[(K::R, 26.0, -2.0), (K::F, 5.0, -2.0), (K::F, 5.0, 2.0), (K::R, 26.0, 2.0)]);
}

// "End face peck drilling cycle (G74)": G74 R(e) sets the return after
// each peck; G74 Z(W) Q(Δk) F pecks Δk (least increments: Q4000 is 4 mm)
// from A toward Z, returning e at rapid after each but the last, then
// back to A. A = (0, 2), e = 1, Δk = 4: (F 0 -2) (R 0 -1) (F 0 -6)
// (R 0 -5) (F 0 -10) (R 0 2). Feed 0.1 x 800 = 80 mm/min. Q without a
// decimal point is the manual's form: no warning.
#[test]
fn g74_peck_drilling() {
    let o = outcome("S800 M03\nG00 X0. Z2.\nG74 R1.\nG74 Z-10. Q4000 F0.1\nM30\n", &fanuc());
    let t = &o.toolpath;
    assert_eq!(t.moves.len(), 7);
    expect(
        t,
        1,
        &[
            (K::F, 0.0, -2.0),
            (K::R, 0.0, -1.0),
            (K::F, 0.0, -6.0),
            (K::R, 0.0, -5.0),
            (K::F, 0.0, -10.0),
            (K::R, 0.0, 2.0),
        ],
    );
    assert!((t.moves[1].feed - 80.0).abs() < 1e-9);
    assert!(o.diagnostics.is_empty(), "{:?}", o.diagnostics);
}

// G74 face grooving: X(U) the last groove's X, P(Δi) the step between
// grooves in X (radius, P2000 = 2 mm). A = X40. Z1. (20, 1), X30. (15):
// grooves at 20, 18, 16 and 15 (the last step short); each pecks Q2000 =
// 2 mm from Z1: to -1, return e 0.5 to -0.5, to -3; then rapid back to
// Z1, over to the next groove; after the last, back to A.
#[test]
fn g74_face_grooves() {
    let t = path("S800 M03\nG00 X40. Z1.\nG74 R0.5\nG74 X30. Z-3. P2000 Q2000 F0.05\nM30\n", &fanuc());
    let groove = |x: f64| [(K::F, x, -1.0), (K::R, x, -0.5), (K::F, x, -3.0), (K::R, x, 1.0)];
    let mut want = Vec::new();
    for (k, x) in [20.0, 18.0, 16.0, 15.0].into_iter().enumerate() {
        if k > 0 {
            want.push((K::R, x, 1.0));
        }
        want.extend(groove(x));
    }
    want.push((K::R, 20.0, 1.0));
    assert_eq!(t.moves.len(), 1 + want.len());
    expect(&t, 1, &want);
}

// "Outer diameter / internal diameter drilling cycle (G75)": G74 with X
// and Z swapped: P(Δi) the peck in X, Q(Δk) the step in Z. A = X42. Z-20.
// (21, -20), X30. Z-24. (15, -24), P3000 Q2000, e 0.5: grooves at Z -20,
// -22, -24, each pecked to 18, returned to 18.5, then to 15, then out to
// 21.
#[test]
fn g75_od_grooves() {
    let t = path("S800 M03\nG00 X42. Z-20.\nG75 R0.5\nG75 X30. Z-24. P3000 Q2000 F0.05\nM30\n", &fanuc());
    let groove = |z: f64| [(K::F, 18.0, z), (K::R, 18.5, z), (K::F, 15.0, z), (K::R, 21.0, z)];
    let mut want = Vec::new();
    for (k, z) in [-20.0, -22.0, -24.0].into_iter().enumerate() {
        if k > 0 {
            want.push((K::R, 21.0, z));
        }
        want.extend(groove(z));
    }
    want.push((K::R, 21.0, -20.0));
    expect(&t, 1, &want);
    assert_eq!(t.moves.len(), 1 + want.len());
}

// "Multiple threading cycle (G76)": G76 P(m)(r)(a) Q(Δdmin) R(d); then
// G76 X Z P(k) Q(Δd) F(L). P010560: m = 1 finishing cut, r = 05 (a
// chamfer of 0.5 lead = 1 mm), a = 60°; Δdmin = Q100 = 0.1, d = 0.05;
// X21.4 (radius 10.7) the root at the end, k = P1300 = 1.3, Δd = Q450 =
// 0.45, L = 2. The cut n goes Δd√n deep, at least Δdmin deeper than the
// last, up to k - d = 1.25:
//   0.45, 0.6364 (√2), 0.7794 (√3), 0.9 (√4), 1.0062 (√5);
//   √6·0.45 = 1.1023 is only 0.096 deeper: 1.1062; √7·0.45 = 1.1906 only
//   0.084 deeper: 1.2062; √8·0.45 = 1.2728 only 0.067 deeper: 1.3062,
//   past 1.25: 1.25; then the finishing cut at k = 1.3. Nine threads.
// One edge cuts: a cut `h` above the root starts h·tan 30° back toward
// the start (+Z), its X at 10.7 + h, and ends as far back from Z-25; the
// last 1 mm of Z pulls out at 45° (1 mm up). A = X26. Z5. (13, 5).
// The first cut, h = 0.85, b = 0.85·tan 30° = 0.490748: (R 13 5.490748)
// (R 11.55 5.490748) (thread 11.55 -23.509252) (thread 12.55 -24.509252)
// (R 13 -24.509252) (R 13 5). The last, h = 0: (R 10.7 5) (thread 10.7
// -24) (thread 11.7 -25) (R 13 -25) (R 13 5). 8 × 6 + 5 = 53 moves.
#[test]
fn g76_two_blocks() {
    let o = outcome("S600 M03\nG00 X26. Z5.\nG76 P010560 Q100 R0.05\nG76 X21.4 Z-25. P1300 Q450 F2.\nM30\n", &fanuc());
    let t = &o.toolpath;
    assert_eq!(t.moves.len(), 1 + 53);
    let b = 0.85 * 30f64.to_radians().tan();
    expect(
        t,
        1,
        &[
            (K::R, 13.0, 5.0 + b),
            (K::R, 11.55, 5.0 + b),
            (K::F, 11.55, -24.0 + b),
            (K::F, 12.55, -25.0 + b),
            (K::R, 13.0, -25.0 + b),
            (K::R, 13.0, 5.0),
        ],
    );
    expect(
        t,
        49,
        &[(K::R, 10.7, 5.0), (K::F, 10.7, -24.0), (K::F, 11.7, -25.0), (K::R, 13.0, -25.0), (K::R, 13.0, 5.0)],
    );
    let depths = [0.45, 0.45 * 2f64.sqrt(), 0.45 * 3f64.sqrt(), 0.9, 0.45 * 5f64.sqrt()];
    let depths: Vec<f64> =
        depths.into_iter().chain([0.45 * 5f64.sqrt() + 0.1, 0.45 * 5f64.sqrt() + 0.2, 1.25, 1.3]).collect();
    assert_eq!(o.threads.len(), 9);
    for (th, d) in o.threads.iter().zip(&depths) {
        assert!((th.start.x - (10.7 + 1.3 - d)).abs() < 1e-6, "{th:?} at depth {d}");
        assert_eq!(th.lead, 2.0);
    }
    // The cut's feed is the lead at the spindle speed: 2 × 600.
    assert!((t.moves[3].feed - 1200.0).abs() < 1e-9);
}

// Haas "G76 Threading Cycle, Multiple Pass": one block, K the thread's
// height and D the first cut's depth (radius, with a decimal point), A the
// tool's angle, P1 (the default) one edge at the same area each cut; no
// finishing allowance (Setting 86 at 0) and no chamfer taken here. K1.3
// D0.45: 0.45√n up to √8·0.45 = 1.2728, then 1.3 (√9·0.45 = 1.35 is past
// it): nine cuts; every cut but the last 5 moves, the last 4: 44 moves.
#[test]
fn haas_g76_one_block() {
    let o = outcome("S600 M03\nG00 X26. Z5.\nG76 X21.4 Z-25. K1.3 D0.45 A60 F2.\nM30\n", &haas());
    assert_eq!(o.threads.len(), 9);
    assert_eq!(o.toolpath.moves.len(), 1 + 44);
    let b = 0.85 * 30f64.to_radians().tan();
    expect(&o.toolpath, 1, &[(K::R, 13.0, 5.0 + b), (K::R, 11.55, 5.0 + b), (K::F, 11.55, -25.0 + b)]);
    assert!((o.threads[7].start.x - (10.7 + 1.3 - 0.45 * 8f64.sqrt())).abs() < 1e-9);
}

// Haas "G74 End Face Grooving Cycle": one block, K the peck in Z (mm with
// its decimal point), I the step in X, the return after each peck Setting
// 22 (taken at 0.050 inch, 1.27 mm). From (0, 2): to -2, back to -0.73,
// to -6, back to -4.73, to -10, back to Z2.
#[test]
fn haas_g74_one_block() {
    let t = path("S800 M03\nG00 X0. Z2.\nG74 Z-10. K4. F0.1\nM30\n", &haas());
    expect(
        &t,
        1,
        &[
            (K::F, 0.0, -2.0),
            (K::R, 0.0, -0.73),
            (K::F, 0.0, -6.0),
            (K::R, 0.0, -4.73),
            (K::F, 0.0, -10.0),
            (K::R, 0.0, 2.0),
        ],
    );
}

// Haas "G92 Thread Cutting Cycle" and "G90 O.D./I.D. Turning Cycle": the
// taper is I (radius), G94's K.
#[test]
fn haas_single_cycles_taper_with_i_and_k() {
    let t = path("S1000 M03\nG00 X52. Z2.\nG90 X50. Z-30. I-2. F0.2\nM30\n", &haas());
    expect(&t, 1, &[(K::R, 23.0, 2.0), (K::F, 25.0, -30.0)]);
    let t = path("S1000 M03\nG00 X52. Z2.\nG94 X10. Z-2. K-3. F0.2\nM30\n", &haas());
    expect(&t, 1, &[(K::R, 26.0, -5.0), (K::F, 5.0, -2.0)]);
    let o = outcome("S500 M03\nG00 X25. Z5.\nG92 X19.2 Z-20. I-1. F1.5\nM30\n", &haas());
    expect(&o.toolpath, 1, &[(K::R, 8.6, 5.0), (K::F, 9.6, -20.0)]);
    assert_eq!(o.threads.len(), 1);
}

// Bad input: located errors that say what the control's alarm means.
#[test]
fn g76_p_with_wrong_digits() {
    let text = |p: &str| format!("S600 M03\nG00 X26. Z5.\nG76 {p} Q100 R0.05\nG76 X21.4 Z-25. P1300 Q450 F2.\nM30\n");
    for p in ["P01060", "P0110600", "P011062", "P0105.6", "P-10560"] {
        let (m, at) = error(&text(p), &fanuc());
        assert_eq!(at, p);
        assert!(m.contains("P(m)(r)(a)"), "{m}");
    }
}

#[test]
fn threading_with_f0_or_s0() {
    let (m, at) = error("S500 M03\nG00 X25. Z5.\nG92 X19.2 Z-20. F0\nM30\n", &fanuc());
    assert_eq!(at, "F0");
    assert!(m.contains("lead"), "{m}");
    let (m, at) =
        error("S600 M03\nG00 X26. Z5.\nG76 P010560 Q100 R0.05\nG76 X21.4 Z-25. P1300 Q450 F0\nM30\n", &fanuc());
    assert_eq!(at, "F0");
    assert!(m.contains("lead"), "{m}");
    let (m, _) = error("S0 M03\nG00 X25. Z5.\nG92 X19.2 Z-20. F1.5\nM30\n", &fanuc());
    assert!(m.contains("spindle speed"), "{m}");
}

#[test]
fn grooving_with_depth_0_or_words_missing() {
    let (m, at) = error("S800 M03\nG00 X0. Z2.\nG74 R1.\nG74 Z-10. Q0 F0.1\nM30\n", &fanuc());
    assert_eq!(at, "Q0");
    assert!(m.contains("peck"), "{m}");
    let (m, at) = error("S800 M03\nG00 X0. Z2.\nG74 R1.\nG74 Z-10. F0.1\nM30\n", &fanuc());
    assert_eq!(at, "G74");
    assert!(m.contains("needs Q"), "{m}");
    let (m, at) = error("S800 M03\nG00 X42. Z-20.\nG75 R0.5\nG75 X30. Z-24. Q2000 F0.05\nM30\n", &fanuc());
    assert_eq!(at, "G75");
    assert!(m.contains("needs P"), "{m}");
    let (m, at) = error("S800 M03\nG00 X0. Z2.\nG74\nM30\n", &fanuc());
    assert_eq!(at, "G74");
    assert!(m.contains("R(e)"), "{m}");
    let (m, at) = error("S600 M03\nG00 X26. Z5.\nG76 P010560 Q100 R0.05\nG76 X21.4 Z-25. Q450 F2.\nM30\n", &fanuc());
    assert_eq!(at, "G76");
    assert!(m.contains("height"), "{m}");
}

// A decimal point in Q is warned of, and read as written (Q4. is 4 mm).
#[test]
fn decimal_point_in_q_is_warned_of() {
    let o = outcome("S800 M03\nG00 X0. Z2.\nG74 R1.\nG74 Z-10. Q4. F0.1\nM30\n", &fanuc());
    assert!(o.diagnostics.iter().any(|d| d.message.contains("least increments")), "{:?}", o.diagnostics);
    expect(&o.toolpath, 1, &[(K::F, 0.0, -2.0)]);
}

// G76 from a start point inside the thread (X22. is radius 11, the crest
// at the start 10.7 + 1.3 = 12): the first cut (0.85 above the root, at
// 11.55) begins beyond the start point, which is warned of; a start at
// the root's X (U0) cannot tell an outer thread from an inner one.
#[test]
fn g76_from_inside_the_thread() {
    let o = outcome("S600 M03\nG00 X22. Z5.\nG76 P010560 Q100 R0.05\nG76 X21.4 Z-25. P1300 Q450 F2.\nM30\n", &fanuc());
    assert!(o.diagnostics.iter().any(|d| d.message.contains("inside the thread")), "{:?}", o.diagnostics);
    let b = 0.85 * 30f64.to_radians().tan();
    expect(&o.toolpath, 1, &[(K::R, 11.0, 5.0 + b), (K::R, 11.55, 5.0 + b)]);
    let (m, at) =
        error("S600 M03\nG00 X21.4 Z5.\nG76 P010560 Q100 R0.05\nG76 X21.4 Z-25. P1300 Q450 F2.\nM30\n", &fanuc());
    assert_eq!(at, "X21.4");
    assert!(m.contains("root"), "{m}");
}

// G92's Q (the start angle, 0.001°) has no decimal point by the manual:
// no warning; Haas's E is the lead where no F is given.
#[test]
fn g92_start_angle_and_haas_e() {
    let o = outcome("S500 M03\nG00 X25. Z5.\nG92 X19.2 Z-20. F1.5 Q180000\nM30\n", &fanuc());
    assert!(o.diagnostics.is_empty(), "{:?}", o.diagnostics);
    let o = outcome("S500 M03\nG00 X25. Z5.\nG92 X19.2 Z-20. E1.25\nM30\n", &haas());
    assert_eq!(o.threads[0].lead, 1.25);
    assert!((o.toolpath.moves[2].feed - 625.0).abs() < 1e-9);
}

// G92 in the U W form: U-5.8 (a diameter: -2.9) from A's radius 12.5 is
// 9.6, W-25. from Z5. is -20: the same pass as X19.2 Z-20.
#[test]
fn g92_in_u_w() {
    let o = outcome("S500 M03\nG00 X25. Z5.\nG92 U-5.8 W-25. F1.5\nM30\n", &fanuc());
    expect(&o.toolpath, 1, &[(K::R, 9.6, 5.0), (K::F, 9.6, -20.0), (K::R, 12.5, -20.0), (K::R, 12.5, 5.0)]);
    assert_eq!(o.threads.len(), 1);
}

// Under G20 Q counts 0.0001 inch: Q2000 is 0.2 inch (5.08 mm). From Z0.1
// (2.54 mm), e = R0.02 (0.508 mm): to Z-0.1 (-2.54), back to -0.08
// (-2.032), to Z-0.3 (-7.62), back to 2.54.
#[test]
fn g74_in_inches() {
    let t = path("G20\nS800 M03\nG00 X0. Z0.1\nG74 R0.02\nG74 Z-0.3 Q2000 F0.004\nM30\n", &fanuc());
    expect(&t, 1, &[(K::F, 0.0, -2.54), (K::R, 0.0, -2.032), (K::F, 0.0, -7.62), (K::R, 0.0, 2.54)]);
}

// System C renumbers the multiple repetitive cycles by two: G76 is the end
// face peck drilling cycle there, G78 the multiple threading cycle.
#[test]
fn system_c_peck_drilling_and_threading() {
    let c = lathe(GCodeSystem::C);
    let t = path("G95 S800 M03\nG00 X0. Z2.\nG76 R1.\nG76 Z-10. Q4000 F0.1\nM30\n", &c);
    expect(
        &t,
        1,
        &[
            (K::F, 0.0, -2.0),
            (K::R, 0.0, -1.0),
            (K::F, 0.0, -6.0),
            (K::R, 0.0, -5.0),
            (K::F, 0.0, -10.0),
            (K::R, 0.0, 2.0),
        ],
    );
    let o = outcome("G95 S600 M03\nG00 X26. Z5.\nG78 P010560 Q100 R0.05\nG78 X21.4 Z-25. P1300 Q450 F2.\nM30\n", &c);
    assert_eq!(o.threads.len(), 9);
}

// Haas's K without a decimal point is read as any length word is (least
// increments: K4000 is 4 mm), not as the mill's repeat count of G74
// (left-hand tapping there).
#[test]
fn haas_k_is_a_length() {
    let t = path("S800 M03\nG00 X0. Z2.\nG74 Z-10. K4000 F0.1\nM30\n", &haas());
    expect(&t, 1, &[(K::F, 0.0, -2.0), (K::R, 0.0, -0.73), (K::F, 0.0, -6.0)]);
}

// Under constant surface speed ("Constant surface speed control (G96)")
// each move of a cycle ends at the speed of its end radius: V = 200 m/min
// is 200000 / (2π r) rpm, clamped by G50 S3000. G94 from (26, 2) to X10.
// Z-2.: the rapid to (26, -2) ends at 200000 / (2π·26) = 1224.28 rpm; the
// cut to radius 5 would need 6366 rpm: 3000, the clamp.
#[test]
fn cycle_moves_under_constant_surface_speed() {
    let t = path("G50 S3000\nG96 S200 M03\nG00 X52. Z2.\nG94 X10. Z-2. F0.2\nM30\n", &fanuc());
    let rpm = 200_000.0 / (2.0 * std::f64::consts::PI * 26.0);
    assert!((t.moves[1].speed - rpm).abs() < 0.01, "{}", t.moves[1].speed);
    assert!((t.moves[2].speed - 3000.0).abs() < 1e-9, "{}", t.moves[2].speed);
}

// "Canned cycle for drilling", face drilling G83 (B-64604EN): the hole
// along Z at the block's X (and C), R the distance from the initial level to
// point R (G code system A, parameter 5102#6 RAB at its default 0), Z the
// bottom, Q the depth of each peck; after each peck the tool returns to
// point R at rapid, then goes at rapid to d (parameter 5115, 0.1 mm) above
// the last depth; at the bottom it returns to the initial level (system A:
// G98/G99 are the feed modes).
// Initial level Z6., R-3. gives point R at Z3.; bottom Z-10., Q4.: pecks to
// Z-1, -5, -9, then -10. With G98 (feed per minute) F100 is 100 mm/min.
#[test]
fn g83_face_drilling_from_the_initial_level() {
    let text = "S1000 M03\nG98 G00 X0. Z6.\nG83 X0. Z-10. R-3. Q4. F100.\nG80\nM30\n";
    let t = path(text, &fanuc());
    expect(
        &t,
        1,
        &[
            (K::R, 0.0, 3.0),
            (K::F, 0.0, -1.0),
            (K::R, 0.0, 3.0),
            (K::R, 0.0, -0.9),
            (K::F, 0.0, -5.0),
            (K::R, 0.0, 3.0),
            (K::R, 0.0, -4.9),
            (K::F, 0.0, -9.0),
            (K::R, 0.0, 3.0),
            (K::R, 0.0, -8.9),
            (K::F, 0.0, -10.0),
            (K::R, 0.0, 6.0),
        ],
    );
    assert_eq!(t.moves.len(), 13);
    assert!((t.moves[2].feed - 100.0).abs() < 1e-9, "feed {}", t.moves[2].feed);
}
