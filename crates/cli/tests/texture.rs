//! `kezuri texture`: baked and macro textures run through kezuri's own
//! interpreter, the digits distribution in both modes, the paper's O7023 as
//! printed, and bad input.

mod common;

use std::collections::BTreeMap;

use common::{kezuri, ok, path};

/// A nameplate's area clearing as the texture paper's CAM wrote it: CAM Z 0, zig-zag
/// rows of 212 mm with 3 mm steps, an arc, a retract, a Z-only plunge.
fn nameplate() -> String {
    let mut t = String::from(
        "%\nO0002 (NAMEPLATE)\nG90 G17 G21 G54\nG00 X106. Y-58. S6000 M03\nZ20.\nG01 Z2. F1000\nZ0. F20\n",
    );
    let (mut x, mut y) = (106.0, -58.0);
    for _ in 0..6 {
        x = -x;
        t += &format!("X{x:.1}\n");
        y -= 3.0;
        t += &format!("Y{y:.1}\n");
    }
    t += &format!("G02 X{x:.1} Y{:.1} I0. J-3.\n", y - 6.0);
    t += "G00 Z2.54\nX-85.207 Y-25.293\nG01 Z0.\nX-87.747 F20\nX-30.\nG03 X-20. Y-25.293 I5. J0.\nG01 X20.\nG00 Z100.\nM30\n%\n";
    t
}

/// The `kind, x, y, z` of each move of `kezuri run FILE --emit csv`.
fn moves(file: &str, clock_seed: Option<&str>) -> Vec<(String, [f64; 3])> {
    let mut args = vec!["run", file, "--emit", "csv"];
    if let Some(s) = clock_seed {
        args.extend(["--clock-seed", s]);
    }
    ok(&kezuri(&args))
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[1].to_string(), [f[2].parse().unwrap(), f[3].parse().unwrap(), f[4].parse().unwrap()])
        })
        .collect()
}

/// Offsets allowed by the paper's numbers about `base`.
fn on_a_depth(z: f64, base: f64) -> bool {
    let k = (z - base) / 0.2;
    (k - k.round()).abs() < 1e-6 && (z - base).abs() <= 0.8 + 1e-9
}

/// Checks a textured nameplate against the plain one: strokes of 20 mm of
/// XY travel on the cutting rows, each knot on one of the nine depths,
/// rapids and arcs where the plain program has them.
fn check_strokes(plain: &[(String, [f64; 3])], textured: &[(String, [f64; 3])]) {
    // Arcs and rapids: the same XY, in the same order.
    let xy = |v: &[(String, [f64; 3])], kinds: &[&str]| {
        v.iter().filter(|m| kinds.contains(&m.0.as_str())).map(|m| (m.1[0], m.1[1])).collect::<Vec<_>>()
    };
    for kinds in [&["cw", "ccw"][..], &["rapid"]] {
        assert!(!xy(plain, kinds).is_empty());
        assert_eq!(xy(plain, kinds), xy(textured, kinds), "{kinds:?}");
    }
    // The first run: from the plunge at (106, -58) along the rows, a knot
    // every 20 mm of XY travel.
    let first = textured.iter().position(|m| m.0 == "feed" && m.1[2] < -0.5).unwrap() - 1;
    let mut travel = 0.0;
    let mut knots = 0;
    for w in textured[first..].windows(2) {
        if w[1].0 != "feed" || (w[1].1[0] - w[0].1[0]).hypot(w[1].1[1] - w[0].1[1]) < 1e-9 {
            break;
        }
        travel += (w[1].1[0] - w[0].1[0]).hypot(w[1].1[1] - w[0].1[1]);
        if (travel / 20.0 - (travel / 20.0).round()).abs() < 1e-6 {
            knots += 1;
            assert!(on_a_depth(w[1].1[2], -2.0), "knot at {travel} mm: z {}", w[1].1[2]);
        }
        assert!((-2.8 - 1e-9..=0.0).contains(&w[1].1[2]), "{:?}", w[1]);
    }
    assert!(knots >= 60, "{knots} knots over {travel} mm");
}

#[test]
fn baked_and_macro_textures_cut_the_same_kind_of_strokes() {
    let dir = tempfile::tempdir().unwrap();
    let plain = path(dir.path(), "plate.nc");
    std::fs::write(&plain, nameplate()).unwrap();
    let (baked, made) = (path(dir.path(), "baked.nc"), path(dir.path(), "macro.nc"));
    // The macro draws from the control's clock: no --seed, and one given is said to be unused.
    ok(&kezuri(&["texture", &plain, "--base", "-2", "--mode", "macro", "-o", &made]));
    let seeded = kezuri(&["texture", &plain, "--seed", "7", "--base", "-2", "--mode", "macro", "-o", &made]);
    ok(&seeded);
    assert!(String::from_utf8_lossy(&seeded.stderr).contains("warning: --seed is not used"));
    let unseeded = kezuri(&["texture", &plain, "--base", "-2", "-o", &baked]);
    assert!(String::from_utf8_lossy(&unseeded.stderr).contains("--seed N is needed to bake"));
    ok(&kezuri(&["texture", &plain, "--seed", "7", "--base", "-2", "-o", &baked]));
    let text = std::fs::read_to_string(&made).unwrap();
    assert!(text.contains("G66.1P7023") && text.contains("G67\n") && text.contains("O7023"), "{text}");
    let plain_moves = moves(&plain, None);
    check_strokes(&plain_moves, &moves(&baked, None));
    for seed in ["1", "2"] {
        check_strokes(&plain_moves, &moves(&made, Some(seed)));
    }
    // Each part comes out different on the control; the same seed bakes the same bytes.
    assert_ne!(moves(&made, Some("1")), moves(&made, Some("2")));
    let again = path(dir.path(), "again.nc");
    ok(&kezuri(&["texture", &plain, "--seed", "7", "--base", "-2", "-o", &again]));
    assert_eq!(std::fs::read(&baked).unwrap(), std::fs::read(&again).unwrap());
    ok(&kezuri(&["texture", &plain, "--seed", "8", "--base", "-2", "-o", &again]));
    assert_ne!(std::fs::read(&baked).unwrap(), std::fs::read(&again).unwrap());
}

/// Counts of the knots' offsets (in 0.2 mm steps) on a 200 m straight cut.
fn digit_counts(file: &str, clock_seed: Option<&str>) -> BTreeMap<i64, usize> {
    let mut h = BTreeMap::new();
    let ms = moves(file, clock_seed);
    let knot = |x: f64| x > 0.0 && (x / 20.0 - (x / 20.0).round()).abs() < 1e-9;
    for m in ms.iter().filter(|m| m.0 == "feed" && knot(m.1[0])) {
        *h.entry(((m.1[2] + 2.0) / 0.2).round() as i64).or_insert(0) += 1;
    }
    h
}

fn chi_square(h: &BTreeMap<i64, usize>, p: impl Fn(i64) -> f64) -> f64 {
    let n: usize = h.values().sum();
    (-4..=4).map(|k| (*h.get(&k).unwrap_or(&0) as f64 - p(k) * n as f64).powi(2) / (p(k) * n as f64)).sum()
}

#[test]
fn digits_fall_on_nine_depths_in_both_modes() {
    let dir = tempfile::tempdir().unwrap();
    let long = path(dir.path(), "long.nc");
    std::fs::write(&long, "G90 G21\nG00 X0 Y0 Z1.\nG01 Z0. F500\nX200000.\nG00 Z10.\nM30\n").unwrap();
    let (baked, made) = (path(dir.path(), "baked.nc"), path(dir.path(), "macro.nc"));
    ok(&kezuri(&["texture", &long, "--seed", "3", "--base", "-2", "--no-decimal", "units", "-o", &baked]));
    ok(&kezuri(&[
        "texture",
        &long,
        "--seed",
        "3",
        "--base",
        "-2",
        "--no-decimal",
        "units",
        "--mode",
        "macro",
        "-o",
        &made,
    ]));
    let paper = |k: i64| if k == 0 { 0.2 } else { 0.1 };
    let flat = |_: i64| 1.0 / 9.0;
    for (h, what) in [(digit_counts(&baked, None), "baked"), (digit_counts(&made, Some("5")), "macro")] {
        assert_eq!(h.values().sum::<usize>(), 10_000, "{what}: {h:?}");
        assert_eq!(h.keys().copied().collect::<Vec<_>>(), (-4..=4).collect::<Vec<_>>(), "{what}: nine depths");
        // 8 degrees of freedom: χ² beyond 26.1 has p < 0.001.
        let chi = chi_square(&h, paper);
        assert!(chi < 26.1, "{what}: χ² {chi:.1} {h:?}");
        assert!(chi_square(&h, flat) > 100.0, "{what}: the base is twice as likely");
    }
}

#[test]
fn the_papers_o7023_runs_as_printed() {
    // The texture paper's own macro on its CAM blocks (samples/o7023-texture.nc),
    // with the clock set so that the first digit read is 5: the printed
    // `#28 GT 5` sends it to the shallow side, Z -2 + 5·0.2 = -1.0, a tenth
    // depth; and `G01 Z0.` inside the G66.1 section is dropped (its test
    // `[#24+#25] EQ #0` is never true), so the next cut stays at Z 2.54.
    let dir = tempfile::tempdir().unwrap();
    let sample =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../samples/o7023-texture.nc")).unwrap();
    // Without a seed each read of #3001 advances 16 ms: 65525 + 16 wraps to 5.
    let set = sample.replacen("G59G90G00", "#3001=65525\nG59G90G00", 1);
    let file = path(dir.path(), "o7023.nc");
    std::fs::write(&file, set).unwrap();
    let ms = moves(&file, None);
    let cut: Vec<&(String, [f64; 3])> = ms.iter().filter(|m| m.0 == "feed" && m.1[2] < -0.5).collect();
    assert_eq!(cut[0].1[2], -1.0, "{:?}", cut[0]);
    // Every other depth is one of the printed ones: -1.0 (d = 5) and -1.2 … -2.8.
    assert!(cut.iter().all(|m| m.1[2] == -1.0 || on_a_depth(m.1[2], -2.0)), "{cut:?}");
    let up = ms.iter().position(|m| m.0 == "rapid" && m.1[2] == 2.54).unwrap();
    assert!(
        ms[up + 1..].iter().take_while(|m| m.0 != "rapid" || m.1[2] != 100.0).all(|m| m.1[2] == 2.54),
        "{:?}",
        &ms[up..]
    );
}

#[test]
fn bad_input_gets_clear_messages() {
    let dir = tempfile::tempdir().unwrap();
    let plain = path(dir.path(), "plate.nc");
    std::fs::write(&plain, nameplate()).unwrap();
    let out = path(dir.path(), "out.nc");
    let fails = |args: &[&str], words: &str| {
        let o = kezuri(&[&["texture", &plain, "--seed", "1", "-o", &out][..], args].concat());
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && e.contains(words), "{args:?}: {e}");
        assert!(!std::path::Path::new(&out).exists(), "nothing written");
    };
    fails(&["--segment", "0"], "'--segment <MM>': it must be a length from 0.000001");
    fails(&["--spread", "-0.5"], "--spread must be zero or a positive length");
    fails(&["--step-range", "0.2"], "--step-range '0.2': expected MIN,MAX");
    fails(&["--mode", "macro", "--dist", "smooth"], "--dist digits or uniform");
    fails(&["--mode", "macro", "--emit", "linuxcnc"], "Fanuc Custom Macro B");
    fails(&["--mode", "macro", "--macro-vars", "5"], "--macro-vars 5: the macro keeps its state in seven common");
    fails(&["--mode", "macro", "--macro-number", "2"], "--macro-number 2: give 1-9999, not a program number");
    // A program that already calls a macro on every block.
    let sample = concat!(env!("CARGO_MANIFEST_DIR"), "/../../samples/o7023-texture.nc");
    let o = kezuri(&["texture", sample, "--seed", "1", "-o", &out]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && e.contains("line 9: the program already calls a macro"), "{e}");
    // No cutting move: a warning, the program copied through.
    let air = path(dir.path(), "air.nc");
    std::fs::write(&air, "G90\nG00 X10. Y10. Z5.\nG01 Z-1. F100\nM30\n").unwrap();
    let o = kezuri(&["texture", &air, "--seed", "1", "-o", &out]);
    assert!(o.status.success() && String::from_utf8_lossy(&o.stderr).contains("no straight cutting move"));
    assert_eq!(std::fs::read(&out).unwrap(), std::fs::read(&air).unwrap());
}

/// `kezuri sim … --json` of `nc` with a 6 mm ball: the JSON's numbers.
fn sim(nc: &str, extra: &[&str]) -> serde_json::Value {
    let args = [&["sim", nc, "--tool", "ball:6", "--res", "0.2", "--json"][..], extra].concat();
    serde_json::from_str(&ok(&kezuri(&args))).unwrap()
}

#[test]
fn the_simulated_nameplate_is_never_cut_below_the_clamp() {
    let dir = tempfile::tempdir().unwrap();
    let plain = path(dir.path(), "plate.nc");
    std::fs::write(&plain, nameplate()).unwrap();
    let stock = ["--stock", "-110,-80,110,-20,0"];
    let (free, clamped) = (path(dir.path(), "free.nc"), path(dir.path(), "clamped.nc"));
    ok(&kezuri(&["texture", &plain, "--seed", "7", "--base", "-2", "-o", &free]));
    ok(&kezuri(&["texture", &plain, "--seed", "7", "--base", "-2", "--max-depth", "-2.4", "-o", &clamped]));
    let low = |v: &serde_json::Value| v["min_z_mm"].as_f64().unwrap();
    // Unclamped the strokes reach -2.8 mm; clamped, nothing below -2.4 anywhere.
    assert!(low(&sim(&free, &stock)) < -2.7);
    let v = sim(&clamped, &stock);
    assert!(low(&v) >= -2.4 - 1e-9, "{v}");
    assert_eq!(v["rapids_into_stock"], 0, "{v}");
}

#[test]
fn on_a_milled_dome_the_texture_stays_within_its_spread_of_the_surface() {
    let dir = tempfile::tempdir().unwrap();
    // A dome of radius 30, 8 mm high, on a 60 × 60 mm flat, as x y z lines.
    let mut grid = String::new();
    for j in 0..=120 {
        for i in 0..=120 {
            let (x, y) = (i as f64 * 0.5 - 30.0, j as f64 * 0.5 - 30.0);
            let z = ((900.0 - x * x - y * y).max(0.0).sqrt() - 22.0).max(0.0);
            grid += &format!("{x} {y} {z}\n");
        }
    }
    let dome = path(dir.path(), "dome.xyz");
    std::fs::write(&dome, grid).unwrap();
    let (milled, textured) = (path(dir.path(), "dome.nc"), path(dir.path(), "textured.nc"));
    ok(&kezuri(&["mill", &dome, "--tool", "ball:6", "--stepover", "1", "-o", &milled]));
    ok(&kezuri(&[
        "texture",
        &milled,
        "--seed",
        "3",
        "--segment",
        "5",
        "--spread",
        "0.3",
        "--quantum",
        "0.1",
        "-o",
        &textured,
    ]));
    let compare = ["--compare", &dome, "--stock", "-25,-25,25,25,9"];
    let gouge = |v: &serde_json::Value| v["max_gouge_mm"].as_f64().unwrap();
    let plain = sim(&milled, &compare);
    let v = sim(&textured, &compare);
    // The milled dome is within a hundredth; textured, the strokes go up to
    // the spread into it and no further (the simulation's own chord
    // tolerance and cell size aside).
    assert!(gouge(&plain) < 0.02, "{plain}");
    assert!(gouge(&v) > 0.2 && gouge(&v) <= 0.3 + 0.02, "{v}");
}

#[test]
fn arcs_keep_their_r_and_an_arc_across_z_starts_at_the_programs_z() {
    // The paper's macro used #18 (R) as scratch: an R-form arc inside the
    // section lost its radius. Here it runs as written.
    let dir = tempfile::tempdir().unwrap();
    let plain = path(dir.path(), "r.nc");
    std::fs::write(
        &plain,
        "G90 G17 G21\nG00 X0. Y0. Z5.\nG01 Z0. F300\nX50.\nG02 X60. Y-10. R10.\nG01 X0.\nG18 G03 X-10. Z-10. R10.\nG17 G01 X-50.\nG00 Z20.\nM30\n",
    )
    .unwrap();
    let (made, baked) = (path(dir.path(), "r-macro.nc"), path(dir.path(), "r-baked.nc"));
    ok(&kezuri(&["texture", &plain, "--seed", "1", "--base", "-2", "--mode", "macro", "-o", &made]));
    ok(&kezuri(&["texture", &plain, "--seed", "1", "--base", "-2", "-o", &baked]));
    let arcs = |v: &[(String, [f64; 3])]| {
        v.iter().filter(|m| m.0 == "cw" || m.0 == "ccw").map(|m| (m.0.clone(), m.1)).collect::<Vec<_>>()
    };
    let plain_arcs = arcs(&moves(&plain, None));
    for textured in [moves(&made, Some("3")), moves(&baked, None)] {
        // The XY arc at the stroke's depth; the XZ one, inside the section
        // too, as written (from the program's Z).
        let got = arcs(&textured);
        assert_eq!(got.len(), 2, "{textured:?}");
        assert_eq!((got[0].0.as_str(), got[0].1[0], got[0].1[1]), ("cw", 60.0, -10.0));
        assert_ne!(got[0].1[2], 0.0, "the XY arc runs at a stroke's depth");
        assert_eq!(got[1], plain_arcs[1]);
        // Before the XZ arc the tool went back to the program's Z (0).
        let xz = textured.iter().position(|m| m == &got[1]).unwrap();
        assert_eq!(textured[xz - 1].1, [0.0, -10.0, 0.0], "{:?}", &textured[xz - 2..=xz]);
    }
}

#[test]
fn the_design_rule_holds_between_strokes_in_both_modes() {
    let dir = tempfile::tempdir().unwrap();
    let long = path(dir.path(), "long.nc");
    std::fs::write(&long, "G90 G21\nG00 X0 Y0 Z1.\nG01 Z0. F500\nX20000.\nG00 Z10.\nM30\n").unwrap();
    let rule = ["--step-range", "0.2,1.6", "--base", "-2", "--no-decimal", "units"];
    let (baked, made) = (path(dir.path(), "baked.nc"), path(dir.path(), "macro.nc"));
    ok(&kezuri(&[&["texture", &long, "--seed", "4", "-o", &baked][..], &rule].concat()));
    ok(&kezuri(&[&["texture", &long, "--seed", "4", "--mode", "macro", "-o", &made][..], &rule].concat()));
    for ms in [moves(&baked, None), moves(&made, Some("9"))] {
        let knots: Vec<f64> = ms.iter().filter(|m| m.0 == "feed" && m.1[0] > 0.0).map(|m| m.1[2]).collect();
        assert_eq!(knots.len(), 1000);
        for w in knots.windows(2) {
            let step = (w[1] - w[0]).abs();
            assert!((0.2 - 1e-6..=1.6 + 1e-6).contains(&step), "{} → {}", w[0], w[1]);
        }
    }
}

#[test]
fn the_macro_keeps_the_spread_and_the_clamp_and_ends_before_a_closing_percent() {
    let dir = tempfile::tempdir().unwrap();
    // The last cut right before the closing %.
    let plain = path(dir.path(), "p.nc");
    std::fs::write(&plain, "%\nO0001\nG90 G21 G00 X0 Y0 Z1.\nG01 Z0. F500\nX2000.\n%\n").unwrap();
    let made = path(dir.path(), "m.nc");
    let odd = ["--seed", "1", "--base", "-2", "--spread", "0.8", "--quantum", "0.3", "--max-depth", "-2.5"];
    ok(&kezuri(&[&["texture", &plain, "--mode", "macro", "-o", &made][..], &odd].concat()));
    let text = std::fs::read_to_string(&made).unwrap();
    assert!(text.find("O7023").unwrap() < text.rfind('%').unwrap(), "the macro inside the % frame");
    for seed in ["1", "2", "3"] {
        let zs: Vec<f64> = moves(&made, Some(seed)).iter().filter(|m| m.1[0] > 0.0).map(|m| m.1[2]).collect();
        assert_eq!(zs.len(), 100);
        // Multiples of 0.3 within 0.8 (so ±0.6) about -2, and never below the clamp.
        assert!(zs.iter().all(|z| [-2.6, -2.3, -2.0, -1.7, -1.4, -2.5].iter().any(|d| (z - d).abs() < 1e-9)), "{zs:?}");
        assert!(zs.iter().any(|&z| z == -2.5) && zs.iter().any(|&z| (z - -1.4).abs() < 1e-9), "{zs:?}");
        assert!(!zs.iter().any(|&z| z < -2.5));
    }
}

#[test]
fn the_macro_refuses_a_section_it_would_change() {
    let dir = tempfile::tempdir().unwrap();
    let out = path(dir.path(), "out.nc");
    for (program, words) in [
        ("G90 G00 X0 Y0 Z1.\nG01 Z0. F300\nX50. M08\nX80.\nM30\n", "line 3: 'M08' inside the cutting section"),
        ("G90 G00 X0 Y0 Z1.\nG01 Z0. F300\nX50.\nG04 X1.\nX80.\nM30\n", "line 4: 'G04' inside the cutting section"),
        ("G91 G00 X0 Y0 Z1.\nG01 Z-1. F300\nX50.\nM30\n", "line 1: G91"),
    ] {
        let file = path(dir.path(), "in.nc");
        std::fs::write(&file, program).unwrap();
        let o = kezuri(&["texture", &file, "--seed", "1", "--mode", "macro", "-o", &out]);
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && e.contains(words), "{program}: {e}");
        // Bake textures them.
        ok(&kezuri(&["texture", &file, "--seed", "1", "-o", &out]));
        std::fs::remove_file(&out).unwrap();
    }
}
