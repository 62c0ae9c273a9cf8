//! `probe_plan`: every style × pattern × grid size is run through kezuri's
//! own interpreter; the plunge bottoms must be exactly the grid points, in
//! the order a capture numbers them, each with its trigger (or a G31 probe
//! move and a DPRNT line), and the stylus never moves in plan below z-safe.

use kezuri_geom::{Axes, Move, MoveKind};
use kezuri_nc::interp::{self, Outcome, Settings};
use kezuri_nc::probe_plan::{grid_index, order, read_as, Pattern, Plan, Style};
use kezuri_nc::write::{Dialect, WriteOptions, PRESETS};
use kezuri_nc::{parse, ErrorKind, Program, SourceFile, Sources};

const STYLES: [Style; 3] = [Style::Subprogram, Style::Expanded, Style::G31];
const PATTERNS: [Pattern; 2] = [Pattern::Zigzag, Pattern::OneWay];
const SIZES: [[u32; 2]; 8] = [[1, 1], [1, 5], [6, 1], [4, 3], [4, 4], [2, 2], [3, 2], [85, 105]];

/// The machine's reference point: Z above everything the tests use (machine
/// zero, G53 Z0., is work Z0.); the stylus's length offset H1; the
/// dialect's reading of `G4 P`.
fn settings(dialect: Dialect) -> Settings {
    Settings {
        home: Axes { z: 200.0, ..Axes::ZERO },
        tool_lengths: [(1, 50.0)].into_iter().collect(),
        ..read_as(dialect)
    }
}

fn run_text(text: &str) -> Outcome {
    run_as(text, Dialect::Fanuc)
}

fn run_as(text: &str, dialect: Dialect) -> Outcome {
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("plan.nc", text.to_string()));
    let mut program = Program::default();
    let diagnostics = parse(&mut program, file, text);
    let rendered: Vec<String> = diagnostics.iter().map(|d| d.render(&sources)).collect();
    assert!(diagnostics.is_empty(), "the plan parses without diagnostics:\n{}", rendered.join("\n"));
    let outcome = interp::run(&mut program, &mut sources, 0, &mut interp::NoLibrary, &settings(dialect));
    let all: Vec<String> = outcome.diagnostics.iter().map(|d| d.render(&sources)).collect();
    assert!(all.is_empty(), "the plan runs without errors or warnings:\n{}", all.join("\n"));
    assert!(outcome.completed, "the plan runs to its M30");
    outcome
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

/// Runs `plan` and checks everything the capture relies on.
fn check(plan: &Plan) {
    let what = format!("{:?} {:?} {:?} pitch {}", plan.style, plan.pattern, plan.count, plan.pitch);
    let text = plan.program().unwrap_or_else(|e| panic!("{what}: {e}"));
    check_text(&text, &what, plan.post.dialect);
    let outcome = run_as(&text, plan.post.dialect);
    let moves = &outcome.toolpath.moves;
    let (zs, bottom) = (plan.z_safe, plan.bottom());
    // The grid, row by row from y0, the first row toward +X and (zig-zag)
    // every other row back toward -X: the capture's numbering.
    let [nx, ny] = plan.count;
    let mut expected = Vec::new();
    for j in 0..ny {
        let back = plan.pattern == Pattern::Zigzag && j % 2 == 1;
        for c in 0..nx {
            let i = if back { nx - 1 - c } else { c };
            let p = plan.pitch;
            expected.push([plan.origin[0] + f64::from(i) * p, plan.origin[1] + f64::from(j) * p, zs - plan.plunge]);
        }
    }
    assert_eq!(plan.points().len(), expected.len());
    for (a, b) in plan.points().iter().zip(&expected) {
        assert!((0..3).all(|k| close(a[k], b[k])), "{what}: Plan::points {a:?} is not the grid's {b:?}");
    }

    // Plunges: every move that ends at the bottom.
    let plunge_kind = if plan.style == Style::G31 { MoveKind::Probe } else { MoveKind::Feed };
    let plunges: Vec<(usize, &Move)> = moves.iter().enumerate().filter(|(_, m)| close(m.end.z, bottom)).collect();
    let bottoms: Vec<[f64; 3]> = plunges
        .iter()
        .filter(|(_, m)| !matches!(m.kind, MoveKind::Dwell(_)))
        .map(|(_, m)| [m.end.x, m.end.y, m.end.z])
        .collect();
    assert_eq!(bottoms.len(), expected.len(), "{what}: one plunge per grid point");
    for (k, (got, want)) in bottoms.iter().zip(&expected).enumerate() {
        let ok = (0..3).all(|a| close(got[a], want[a]));
        assert!(ok, "{what}: point {} is at {got:?}, the grid has {want:?}", k + 1);
    }

    let mut count = 0;
    for (k, m) in moves.iter().enumerate() {
        if matches!(m.kind, MoveKind::Dwell(_)) {
            continue;
        }
        if close(m.end.z, bottom) {
            // A vertical stroke from z-safe at the plunge feed.
            assert_eq!(m.kind, plunge_kind, "{what}: plunge {m:?}");
            assert!(close(m.start.z, zs) && m.start.x == m.end.x && m.start.y == m.end.y, "{what}: {m:?}");
            assert_eq!(m.feed, plan.plunge_feed, "{what}");
            assert!(!m.coolant.mist, "{what}: the air blow is off while the stylus moves");
            // Then the trigger (M07, G04 X0.5, M09) at the bottom, and the
            // retract straight up to z-safe with the air blow off.
            let mut next = k + 1;
            if plan.style != Style::G31 {
                let d = &moves[next];
                assert_eq!(d.kind, MoveKind::Dwell(0.5), "{what}: the dwell follows the plunge");
                assert!(d.coolant.mist, "{what}: M07 is on during the dwell");
                assert_eq!(d.end, m.end, "{what}: the dwell is at the bottom");
                next += 1;
            }
            let up = &moves[next];
            assert!(up.start == m.end && close(up.end.z, zs), "{what}: retract {up:?}");
            assert!(up.end.x == m.end.x && up.end.y == m.end.y, "{what}: the retract is vertical");
            assert!(!up.coolant.mist, "{what}: M09 before the retract");
            count += 1;
        } else if !matches!(m.kind, MoveKind::Home | MoveKind::Machine) {
            // Everything else happens at z-safe (the approach comes down to it
            // from the reference point), and nothing but a plunge goes lower.
            assert!(m.end.z > zs - 1e-9, "{what}: {m:?} ends below z-safe");
            if m.start.x != m.end.x || m.start.y != m.end.y {
                assert!(m.start.z > zs - 1e-9 && close(m.end.z, m.start.z), "{what}: plan move below z-safe {m:?}");
            }
            assert!(!m.coolant.mist, "{what}");
            assert!(m.kind == MoveKind::Rapid || m.kind == MoveKind::Feed, "{what}: {m:?}");
        }
    }
    assert_eq!(count, expected.len());
    let dwells = moves.iter().filter(|m| matches!(m.kind, MoveKind::Dwell(_))).count();
    assert_eq!(dwells, if plan.style == Style::G31 { 0 } else { expected.len() }, "{what}: one dwell per point");

    // G31: the control prints the touch points (here the bottoms) in order.
    if plan.style == Style::G31 {
        assert_eq!(outcome.prints.len(), expected.len(), "{what}: one DPRNT line per point");
        for (line, want) in outcome.prints.iter().zip(&expected) {
            let v: Vec<f64> = line.split_whitespace().map(|s| s.parse().unwrap()).collect();
            assert_eq!(v.len(), 3, "{what}: x y z in {line:?}");
            assert!((0..3).all(|a| (v[a] - want[a]).abs() < 5e-4), "{what}: {line:?} is not {want:?}");
        }
    } else {
        assert!(outcome.prints.is_empty());
    }

    // It ends at z-safe or above, then the post's retract and home (G28 or
    // G53; none on GRBL).
    let last = moves.last().unwrap();
    match last.kind {
        MoveKind::Home => assert!(last.start.z >= zs - 1e-9 && last.end.z >= zs, "{what}: {last:?}"),
        MoveKind::Machine => assert!(last.start.z >= zs - 1e-9, "{what}: {last:?}"),
        _ => assert!(plan.post.dialect == Dialect::Grbl && close(last.end.z, zs), "{what}: {last:?}"),
    }
}

/// The text itself: `%` framing, a decimal point on every axis word, and
/// (subprogram style) the repeats.
fn check_text(text: &str, what: &str, dialect: Dialect) {
    let lines: Vec<&str> = text.lines().collect();
    let fanuc = dialect == Dialect::Fanuc;
    assert_eq!(lines.first() == Some(&"%"), fanuc, "{what}: % first on Fanuc only");
    assert_eq!(lines.last() == Some(&"%"), fanuc, "{what}: % last on Fanuc only");
    for line in &lines {
        let code = match line.find('(') {
            Some(c) => &line[..c],
            None => line,
        };
        if code.starts_with("DPRNT") || code.starts_with('#') {
            continue;
        }
        for word in code.split_whitespace() {
            let letter = word.as_bytes()[0];
            if b"XYZIJKR".contains(&letter) && !(word.starts_with('X') && code.starts_with("G04")) && word != "G91.1" {
                assert!(word.contains('.'), "{what}: axis word without a decimal point: {word} in {line:?}");
            }
        }
    }
}

#[test]
fn every_style_pattern_and_size_plunges_at_the_grid_points() {
    for style in STYLES {
        for pattern in PATTERNS {
            for count in SIZES {
                let mut plan = Plan::new([10.0, 20.0], count, 1.0, 30.0, 50.0);
                plan.style = style;
                plan.pattern = pattern;
                check(&plan);
            }
        }
    }
}

#[test]
fn fractional_pitch_negative_origin_and_feeds() {
    for style in STYLES {
        for pattern in PATTERNS {
            for count in [[5, 4], [7, 3], [1, 2]] {
                let mut plan = Plan::new([-12.5, -7.25], count, 0.25, -80.0, 12.5);
                plan.style = style;
                plan.pattern = pattern;
                plan.feed = Some(3000.0);
                plan.plunge_feed = 150.0;
                check(&plan);
                plan.pitch = 0.1;
                plan.digits = 4;
                plan.origin = [0.0001, 3.3];
                check(&plan);
            }
        }
    }
}

#[test]
fn subprogram_style_repeats_the_paper_shape() {
    let plan = Plan::new([0.0, 0.0], [85, 105], 1.0, 30.0, 50.0);
    let text = plan.program().unwrap();
    // Zig-zag: 52 row pairs and the last row in the main program.
    for block in [
        "O1011 (KEZURI PROBE PLAN, SUBPROGRAM STYLE)",
        "T1 M06\nG90 G00 X0. Y0.\nG00 G43 H1 Z30.\n",
        "G91",
        "M98 P1012 L52",
        "M98 P1013 L84",
        "M98 P1014 L84",
        "O1012 (",
        "O1013 (",
        "O1014 (",
        "G00 X1.",
        "G00 X-1.",
        "G01 Z-50. F6000.",
        "M07\nG04 X0.5\nM09\nG00 Z50.",
        "G90\nG91 G28 Z0.\nG90\nG91 G28 X0. Y0.\nG90\nM30\nO1012 (",
    ] {
        assert!(text.contains(block), "{block:?} in\n{text}");
    }
    let mut one_way = plan.clone();
    one_way.pattern = Pattern::OneWay;
    let text = one_way.program().unwrap();
    for block in ["M98 P1012 L105", "M98 P1013 L84", "G00 X-84. Y1.", "G00 X1."] {
        assert!(text.contains(block), "{block:?} in\n{text}");
    }
    assert!(!text.contains("O1014"), "one-way needs no -X point");
    assert!(text.len() < 2000, "the subprogram style stays short: {} bytes", text.len());
}

#[test]
fn every_post_writes_the_expanded_style_in_its_own_words() {
    for name in PRESETS {
        let post = WriteOptions::preset(name).unwrap();
        let dialect = post.dialect;
        for pattern in PATTERNS {
            for count in [[4, 3], [1, 1], [3, 2]] {
                // Below machine zero, where G53 Z0. takes the gauge line (the tip 50 below).
                let mut plan = Plan::new([10.0, 20.0], count, 1.0, -60.0, 15.0);
                plan.trigger = kezuri_nc::probe_plan::default_trigger(&post).unwrap();
                plan.post = post.clone();
                plan.style = Style::Expanded;
                plan.pattern = pattern;
                check(&plan);
                let text = plan.program().unwrap();
                let short = dialect != Dialect::Fanuc;
                let (plunge, trigger) = if short {
                    ("G1 Z-75. F6000.", "M7\nG4 P0.5\nM9\nG0 Z-60.\n")
                } else {
                    ("G01 Z-75. F6000.", "M07\nG04 X0.5\nM09\nG00 Z-60.\n")
                };
                assert!(text.contains(plunge) && text.contains(trigger), "{name}:\n{text}");
                assert_eq!(text.contains("G00") || text.contains("G01") || text.contains("M07"), !short, "{name}");
            }
        }
        for style in [Style::Subprogram, Style::G31] {
            let plan = Plan { style, post: post.clone(), ..Plan::new([0.0, 0.0], [4, 3], 1.0, 30.0, 50.0) };
            match (dialect, plan.program()) {
                (Dialect::Fanuc, Ok(_)) => {}
                (_, Err(e)) if dialect != Dialect::Fanuc => {
                    assert_eq!(e.kind, ErrorKind::Plan, "{name}: {e}");
                    let e = e.to_string();
                    assert!(e.contains("only Fanuc and Haas") && e.contains("--style expanded"), "{name}: {e}");
                }
                (_, other) => panic!("{name} {style:?}: {other:?}"),
            }
        }
    }
}

#[test]
fn custom_trigger_and_program_number() {
    let mut plan = Plan::new([0.0, 0.0], [3, 2], 2.0, 10.0, 5.0);
    plan.trigger = vec!["M08".into(), "G04 X1.".into(), "M09".into()];
    plan.program = 2000;
    for style in [Style::Subprogram, Style::Expanded] {
        plan.style = style;
        let text = plan.program().unwrap();
        assert!(text.contains("O2000 ") && text.contains("M08\nG04 X1.\nM09\n"), "{text}");
        let outcome = run_text(&text);
        let dwells: Vec<&Move> = outcome.toolpath.moves.iter().filter(|m| m.kind == MoveKind::Dwell(1.0)).collect();
        assert_eq!(dwells.len(), 6);
        assert!(dwells.iter().all(|m| m.coolant.flood && close(m.end.z, 5.0)));
    }
}

#[test]
fn order_matches_grid_index_and_points() {
    for pattern in PATTERNS {
        let plan = Plan { pattern, ..Plan::new([1.0, 2.0], [5, 4], 0.5, 0.0, 1.0) };
        let points = plan.points();
        for (k, ij) in order([5, 4], pattern).enumerate() {
            assert_eq!(grid_index(k as u64, [5, 4], pattern), Some(ij));
            let [i, j] = ij;
            assert_eq!(points[k], [1.0 + f64::from(i) * 0.5, 2.0 + f64::from(j) * 0.5, -1.0]);
        }
    }
}

#[test]
fn bad_plans_are_refused_with_clear_errors() {
    let good = Plan::new([0.0, 0.0], [4, 3], 1.0, 30.0, 50.0);
    assert_eq!(good.validate(), Ok(()));
    let cases: Vec<(Plan, &str)> = vec![
        (Plan { count: [0, 3], ..good.clone() }, "at least 1 point"),
        (Plan { count: [3, 0], ..good.clone() }, "at least 1 point"),
        (Plan { pitch: 0.0, ..good.clone() }, "pitch must be a positive"),
        (Plan { pitch: -1.0, ..good.clone() }, "pitch must be a positive"),
        (Plan { pitch: f64::NAN, ..good.clone() }, "pitch must be a positive"),
        (Plan { plunge: 0.0, ..good.clone() }, "plunge depth must be a positive"),
        (Plan { plunge: f64::INFINITY, ..good.clone() }, "plunge depth must be a positive"),
        (Plan { z_safe: f64::NAN, ..good.clone() }, "z-safe must be a finite"),
        (Plan { origin: [f64::NAN, 0.0], ..good.clone() }, "origin X must be a finite"),
        (Plan { pitch: 0.0005, ..good.clone() }, "at most 3 decimals"),
        (Plan { origin: [0.0, 1.23456], ..good.clone() }, "origin Y 1.23456 is not a whole number"),
        (Plan { plunge_feed: 0.0, ..good.clone() }, "plunge feed"),
        (Plan { feed: Some(-5.0), ..good.clone() }, "the feed must be"),
        (Plan { program: 0, ..good.clone() }, "program number"),
        (Plan { program: 9998, ..good.clone() }, "program number (it and the 3 after it)"),
        (Plan { digits: 7, ..good.clone() }, "digits"),
        (Plan { count: [20_000, 2], ..good.clone() }, "M98 repeats at most L9999"),
        (Plan { count: [2000, 2000], ..good.clone() }, "more than 1000000"),
        (Plan { pitch: 1e6, ..good.clone() }, "8 digits"),
        (Plan { trigger: vec![], ..good.clone() }, "at least one block"),
        (Plan { trigger: vec!["M07".into(), "G91".into()], ..good.clone() }, "trigger block 2 'G91'"),
        (Plan { trigger: vec!["G01 Z-5.".into()], ..good.clone() }, "trigger block 1"),
        (Plan { trigger: vec!["M07 X5.".into()], ..good.clone() }, "moves the stylus"),
        (Plan { trigger: vec!["M30".into()], ..good.clone() }, "must not end"),
    ];
    for (plan, want) in cases {
        let e = plan.program().expect_err(want);
        assert_eq!(e.kind, ErrorKind::Plan, "{want:?}: {e}");
        let e = e.to_string();
        assert!(e.contains(want), "{want:?} in {e:?}");
    }
    // The program-number and repeat limits belong to the subprogram style.
    let expanded = Plan { style: Style::Expanded, program: 9999, count: [20_000, 2], ..good.clone() };
    assert!(expanded.validate().is_ok());
    // G31 takes no trigger.
    assert!(Plan { style: Style::G31, trigger: vec![], ..good }.validate().is_ok());
}

#[test]
#[ignore = "prints the 4 x 3 programs; run with --ignored --nocapture"]
fn show_programs() {
    for style in STYLES {
        let plan = Plan { style, ..Plan::new([10.0, 20.0], [4, 3], 1.0, 30.0, 50.0) };
        println!("{}", plan.program().unwrap());
    }
}
