//! The documents' own programs, run: O1011/O1012/O1013 (the copy-milling
//! paper, digitizing), O7023 around its CAM blocks (the texture paper,
//! random texture) and O2007 (the thermal and wear report, thermal test).
//! The programs are in `testdata/seeds/`.

use std::collections::BTreeSet;

use kezuri_geom::{Axes, AxisSet, Move, MoveKind};
use kezuri_nc::interp::{self, Outcome, Settings};
use kezuri_nc::{parse, Program, SourceFile, Sources};

fn seed_text(name: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("testdata/seeds").join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Parses and runs the first program of a seed file; fails on any error.
fn run_seed(name: &str, settings: &Settings) -> Outcome {
    let text = seed_text(name);
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new(name, text.clone()));
    let mut program = Program::default();
    let diagnostics = parse(&mut program, file, &text);
    let rendered: Vec<String> = diagnostics.iter().map(|d| d.render(&sources)).collect();
    assert!(diagnostics.is_empty(), "{name} parses without diagnostics:\n{}", rendered.join("\n"));
    let outcome = interp::run(&mut program, &mut sources, 0, &mut interp::NoLibrary, settings);
    let errors: Vec<String> = outcome.diagnostics.iter().filter(|d| d.is_error()).map(|d| d.render(&sources)).collect();
    assert!(errors.is_empty(), "{name} runs without errors:\n{}", errors.join("\n"));
    assert!(outcome.completed, "{name} runs to its M30");
    outcome
}

/// 1-based lines of `name` whose text, without spaces, is `block`.
fn lines_of(name: &str, block: &str) -> Vec<u32> {
    let lines: Vec<u32> = seed_text(name)
        .lines()
        .enumerate()
        .filter(|(_, l)| l.replace(' ', "") == block)
        .map(|(i, _)| i as u32 + 1)
        .collect();
    assert!(!lines.is_empty(), "{name} has a block {block}");
    lines
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

// ---------------------------------------------------------------- the copy-milling paper

#[test]
fn o1011_measures_every_grid_point_once() {
    let outcome = run_seed("o1011_digitize.nc", &Settings::default());
    assert!(outcome.diagnostics.is_empty(), "{:?}", outcome.diagnostics);
    let moves = &outcome.toolpath.moves;
    let plunge_line = lines_of("o1011_digitize.nc", "G01Z-50.")[0];
    let plunges: Vec<&Move> = moves.iter().filter(|m| m.line == plunge_line).collect();
    assert_eq!(plunges.len(), 4 * 3, "one plunge per grid point");
    // The stylus starts 50 mm above the bottom at Z30 and plunges to Z-20;
    // O1013 steps X before each plunge, so row j holds X11..X14 at Y20+j.
    let mut expected = Vec::new();
    for j in 0..3 {
        for i in 1..=4 {
            expected.push((10.0 + f64::from(i), 20.0 + f64::from(j)));
        }
    }
    let bottoms: Vec<(f64, f64)> = plunges.iter().map(|m| (m.end.x, m.end.y)).collect();
    assert_eq!(bottoms, expected);
    for m in &plunges {
        assert_eq!(m.kind, MoveKind::Feed);
        assert!(close(m.start.z, 30.0) && close(m.end.z, -20.0), "a 50 mm stroke from Z30: {m:?}");
        assert_eq!(m.feed, 6000.0);
        assert!(!m.coolant.mist, "the air blow is off while the stylus moves");
    }
    // At each bottom: M07 (air blow on = "read now"), G04 X0.5, M09.
    let dwells: Vec<&Move> = moves.iter().filter(|m| matches!(m.kind, MoveKind::Dwell(_))).collect();
    assert_eq!(dwells.len(), 12);
    for (d, p) in dwells.iter().zip(&plunges) {
        assert_eq!(d.kind, MoveKind::Dwell(0.5));
        assert!(d.coolant.mist, "M07 is on during the dwell");
        assert_eq!(d.end, p.end, "the dwell is at the plunge bottom");
    }
    // Every return stroke ends at Z30 with the air blow off; the run ends
    // with G28 Z0 going straight up to the reference point (machine Z0).
    let up_line = lines_of("o1011_digitize.nc", "Z50.")[0];
    let ups: Vec<&Move> = moves.iter().filter(|m| m.line == up_line).collect();
    assert_eq!(ups.len(), 12);
    assert!(ups.iter().all(|m| close(m.end.z, 30.0) && !m.coolant.mist));
    let last = moves.last().unwrap();
    assert!(last.is_rapid() && close(last.end.z, 0.0));
    assert_eq!((last.end.x, last.end.y), (10.0, 23.0), "G28 Z0 in G91 moves Z only");
    assert_eq!((last.kind, last.named), (MoveKind::Home, AxisSet(0b100)), "a return of Z alone");
    let before = &moves[moves.len() - 2];
    assert_ne!(before.start, before.end, "incremental G28 Z0: the intermediate point is where the tool is, no move");
}

// ---------------------------------------------------------------- the texture paper

const TEXTURE: &str = "o7023_texture.nc";

fn texture_settings(seed: Option<u64>) -> Settings {
    let mut settings = Settings { clock_seed: seed, ..Settings::default() };
    settings.tool_lengths.insert(21, 150.0);
    settings
}

/// Lines of O7023 that move to a random depth (`Z#111`, `Z#114`).
fn random_depth_lines() -> BTreeSet<u32> {
    let mut lines = BTreeSet::new();
    lines.extend(lines_of(TEXTURE, "G#1X#16Y#25Z#111F#9"));
    lines.extend(lines_of(TEXTURE, "G#1X#16Y#25Z#114F#9"));
    assert_eq!(lines.len(), 4);
    lines
}

/// The depths O7023 can give: d = 0..4 gives -2 + 0.2 d, d = 5 (its
/// `#28 GT 5` slip) -1.0, d = 6..9 gives -2 - 0.2 (d - 5).
fn producible_depths() -> Vec<f64> {
    (0..10)
        .map(|d| {
            let d = f64::from(d);
            if d <= 5.0 {
                -2.0 + d * 0.2
            } else {
                -2.0 - (d - 5.0) * 0.2
            }
        })
        .collect()
}

#[test]
fn o7023_cuts_only_depths_it_can_produce() {
    let random = random_depth_lines();
    let depths = producible_depths();
    let mut seen = Vec::new();
    for seed in 1..=8 {
        let outcome = run_seed(TEXTURE, &texture_settings(Some(seed)));
        let cuts: Vec<&Move> = outcome.toolpath.moves.iter().filter(|m| random.contains(&m.line)).collect();
        assert_eq!(cuts.len(), 10 + 10 + 4 + 4, "seed {seed}: one random depth per 20 mm segment");
        for m in &cuts {
            assert_eq!(m.kind, MoveKind::Feed, "seed {seed}: {m:?}");
            let z = m.end.z;
            assert!(depths.iter().any(|&d| (d - z).abs() < 1e-9), "seed {seed}: Z{z} is not a depth O7023 makes");
            seen.push(z);
        }
    }
    // Over eight seeds every digit turns up, the slip's -1.0 included.
    let distinct: BTreeSet<i64> = seen.iter().map(|z| (z * 10.0).round() as i64).collect();
    assert_eq!(distinct, depths.iter().map(|z| (z * 10.0).round() as i64).collect());
}

#[test]
fn o7023_walks_long_x_moves_in_20mm_segments() {
    let outcome = run_seed(TEXTURE, &texture_settings(Some(42)));
    let random = random_depth_lines();
    let pass_line = lines_of(TEXTURE, "G#1X#120Y#25Z#26I#4J#5F#9")[0];
    let moves = &outcome.toolpath.moves;
    // Each long X move of the CAM program becomes a run of random-depth
    // segments of 20 mm, closed by the pass-through block to the X word.
    let mut runs: Vec<Vec<&Move>> = Vec::new();
    let mut i = 0;
    while i < moves.len() {
        if random.contains(&moves[i].line) {
            let mut run = Vec::new();
            while random.contains(&moves[i].line) {
                run.push(&moves[i]);
                i += 1;
            }
            run.push(&moves[i]);
            runs.push(run);
        }
        i += 1;
    }
    // X-106., X106., G01X-106. and are longer than 20 mm.
    let ends: Vec<f64> = runs.iter().map(|r| r.last().unwrap().end.x).collect();
    assert_eq!(ends, [-106.0, 106.0, -106.0, -1.217]);
    let starts = [106.0, -106.0, -9.096, -84.902];
    for (run, start) in runs.iter().zip(starts) {
        let (segments, last) = run.split_at(run.len() - 1);
        let last = last[0];
        assert_eq!(last.line, pass_line);
        let total = last.end.x - start;
        let step = 20.0 * total.signum();
        for (k, m) in segments.iter().enumerate() {
            assert!(close(m.end.x, start + step * (k as f64 + 1.0)), "segment {k} of the move from X{start}: {m:?}");
            assert!(close(m.end.x - m.start.x, step));
            assert_eq!(m.start.y, m.end.y, "segments keep the row's Y");
        }
        assert_eq!(segments.len(), (total.abs() / 20.0).floor() as usize);
        let rest = (last.end.x - last.start.x).abs();
        assert!(rest > 0.0 && rest <= 20.0, "the last piece is what is left: {rest}");
        assert_eq!(last.end.z, last.start.z, "the pass-through block has no Z: the last depth stays");
        assert!(segments.iter().all(|m| m.feed == 20.0));
    }
}

#[test]
fn o7023_passes_arcs_rapids_and_steps_and_drops_z_only_moves() {
    let outcome = run_seed(TEXTURE, &texture_settings(Some(3)));
    let warnings: Vec<&str> = outcome.diagnostics.iter().map(|d| d.message.as_str()).collect();
    assert!(warnings.is_empty(), "{warnings:?}");
    let moves = &outcome.toolpath.moves;
    // Arcs pass through with their own I J: the centre is start + (I, J).
    let arcs: Vec<(&Move, [f64; 2], bool)> = moves
        .iter()
        .filter_map(|m| match m.kind {
            MoveKind::Arc(a) => Some((m, [a.center[0] - m.start.x, a.center[1] - m.start.y], a.ccw)),
            _ => None,
        })
        .collect();
    let expected = [
        ((6.681, -31.5), [-2.783, 8.074], false),
        ((5.974, -31.244), [0.661, 2.926], false),
        ((-9.096, -31.244), [-1.453, 9.372], false),
        ((-84.902, -22.317), [-20.565, 22.508], true),
        ((-7.587, 19.181), [2.299, 13.836], false),
    ];
    assert_eq!(arcs.len(), expected.len());
    for ((m, ij, ccw), ((x, y), want_ij, want_ccw)) in arcs.iter().zip(expected) {
        assert!(close(m.end.x, x) && close(m.end.y, y), "{m:?}");
        assert!(close(ij[0], want_ij[0]) && close(ij[1], want_ij[1]), "I J {ij:?}");
        assert_eq!(*ccw, want_ccw);
        assert_eq!(m.start.z, m.end.z, "an arc keeps its Z");
    }
    // Rapids pass through (#4001 = 0 goes straight to N10).
    let rapids: Vec<(f64, f64, f64)> =
        moves.iter().filter(|m| m.is_rapid()).map(|m| (m.end.x, m.end.y, m.end.z)).collect();
    assert!(rapids.contains(&(9.61, -31.035, 2.54)));
    assert!(rapids.contains(&(-85.207, -25.293, 2.54)));
    // Step-over moves without X go through N20 as G01 Y.
    let step_line = lines_of(TEXTURE, "G01Y#25F#9")[0];
    let steps: Vec<f64> = moves.iter().filter(|m| m.line == step_line).map(|m| m.end.y).collect();
    assert_eq!(steps, [-61.0, -64.0, -5.681]);
    // `IF[[#24+#25]EQ#0]` is never true (vacant + vacant = 0), so a Z-only
    // block goes to N20 too, whose G01 Y#25 F#9 has no word left: the plunge
    // to Z0 is dropped, N25 never runs, and the next cut is in the air.
    let plunge_line = lines_of(TEXTURE, "G01Z#26F10")[0];
    assert!(moves.iter().all(|m| m.line != plunge_line));
    let cam_plunges = lines_of(TEXTURE, "G01Z0.");
    assert_eq!(cam_plunges.len(), 2);
    let after_second = moves.iter().find(|m| close(m.end.x, -87.747)).expect("the X-87.747 cut");
    assert_eq!((after_second.start.z, after_second.end.z), (2.54, 2.54));
    assert_eq!(after_second.kind, MoveKind::Feed);
    // After G67 the program returns home with G91 G28: the spindle's gauge
    // line goes to the reference point (machine zero), so the tool tip hangs
    // H21 = 150 mm below it.
    let last = moves.last().unwrap();
    assert_eq!(last.end, Axes { z: -150.0, ..Axes::ZERO });
    assert!(last.is_rapid());
}

#[test]
fn o7023_same_seed_same_toolpath() {
    let a = run_seed(TEXTURE, &texture_settings(Some(11)));
    let b = run_seed(TEXTURE, &texture_settings(Some(11)));
    let c = run_seed(TEXTURE, &texture_settings(Some(12)));
    assert_eq!(a.toolpath, b.toolpath);
    assert_ne!(a.toolpath, c.toolpath);
    // Without a seed the clock ticks 16 ms per read, so its last digit is
    // even: only d = 0, 2, 4, 6, 8 and their depths appear.
    let random = random_depth_lines();
    let plain = run_seed(TEXTURE, &texture_settings(None));
    let depths: BTreeSet<i64> = plain
        .toolpath
        .moves
        .iter()
        .filter(|m| random.contains(&m.line))
        .map(|m| (m.end.z * 10.0).round() as i64)
        .collect();
    assert_eq!(depths, BTreeSet::from([-26, -22, -20, -16, -12]));
}

// ---------------------------------------------------------------- the thermal and wear report

#[test]
fn o2007_measures_at_the_programmed_positions() {
    // Reference point somewhere inside the travel, so that G92 matters.
    let home = Axes { x: 120.0, y: 10.0, z: 200.0, a: 0.0, b: 15.0, c: 30.0, ..Axes::ZERO };
    let settings = Settings { home, ..Settings::default() };
    let outcome = run_seed("o2007_thermal.nc", &settings);
    // The printed program's first G01 comes before any F: a warning here.
    let warnings: Vec<&str> = outcome.diagnostics.iter().map(|d| d.message.as_str()).collect();
    assert_eq!(warnings, ["a cutting move before any F word: the feed is unknown (0)"]);
    let moves = &outcome.toolpath.moves;
    // G91 G0 G28 X0 Y0 Z0 and G91 G28 C0 B0 home all axes; G92 there makes
    // the reference point the work zero of X Y Z (B and C keep theirs).
    let rel = |m: &Move| (m.end.x - home.x, m.end.y - home.y, m.end.z - home.z, m.end.b, m.end.c);
    let feeds: Vec<(f64, f64, f64, f64, f64)> = moves.iter().filter(|m| m.kind == MoveKind::Feed).map(rel).collect();
    let mut expected = vec![(-2.0, 0.0, 0.0, 15.0, 30.0)];
    expected.extend((0..6).map(|k| (-2.0, 0.0, -74.0 - 4.0 * f64::from(k), 15.0, 30.0)));
    expected.extend((1..6).map(|k| (-2.0 - 4.0 * f64::from(k), 0.0, -94.0, 15.0, 30.0)));
    expected.push((-22.0, 0.0, 0.0, 15.0, 30.0));
    expected.push((-145.0, 0.0, 0.0, 15.0, 30.0));
    expected.push((-145.0, 0.0, 0.0, -90.0, 30.0));
    expected.extend((0..6).map(|k| (-145.0, 0.0, -135.0 - 4.0 * f64::from(k), -90.0, 30.0)));
    expected.extend((0..6).map(|k| (-145.0 - 4.0 * f64::from(k), 0.0, -155.0, -90.0, 30.0)));
    expected.push((-165.0, 0.0, 0.0, -90.0, 30.0));
    assert_eq!(feeds, expected);
    let feed_of = |z: f64| moves.iter().find(|m| close(m.end.z - home.z, z)).unwrap().feed;
    assert_eq!((feed_of(-74.0), feed_of(-135.0)), (500.0, 100.0));
    // The G91 G28 returns at the end, one axis group per block, in order; in
    // G91 the intermediate point is where the tool is, so no move goes there.
    let homing: Vec<(Axes, AxisSet)> = moves.iter().rev().take(4).rev().map(|m| (m.end, m.named)).collect();
    let at = |x: f64, y: f64, z: f64, b: f64, c: f64| Axes { x, y, z, a: 0.0, b, c, ..Axes::ZERO };
    let (x, y) = (120.0 - 165.0, 10.0);
    assert_eq!(
        homing,
        [
            (at(x, y, 200.0, -90.0, 30.0), AxisSet(0b100)),
            (at(x, y, 200.0, 15.0, 30.0), AxisSet(0b1_0000)),
            (at(x, y, 200.0, 15.0, 30.0), AxisSet(0b10_0000)),
            (home, AxisSet(0b11)),
        ]
    );
    assert!(moves.iter().rev().take(4).all(|m| m.kind == MoveKind::Home));
}
