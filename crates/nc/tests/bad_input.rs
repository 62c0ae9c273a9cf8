//! Bad input: every case ends with a located error (or a clean run), never
//! a panic or a hang. The single cases with their exact messages are golden
//! files in `testdata/diagnostics`; here are the sweeps.

use kezuri_nc::interp::{self, Outcome, Settings};
use kezuri_nc::{parse, Diagnostic, Program, SourceFile, Sources};

/// Parses and (when it parsed) runs `text`; renders every diagnostic, so a
/// span that points outside the file would panic here.
fn parse_run(text: &str, settings: &Settings) -> (Vec<Diagnostic>, Option<Outcome>) {
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("bad.nc", text));
    let mut program = Program::default();
    let diagnostics = parse(&mut program, file, text);
    for d in &diagnostics {
        assert!(!d.render(&sources).is_empty());
    }
    if diagnostics.iter().any(Diagnostic::is_error) {
        return (diagnostics, None);
    }
    let mut outcome = None;
    for main in 0..program.units.len() {
        let o = interp::run(&mut program, &mut sources, main, &mut interp::NoLibrary, settings);
        for d in &o.diagnostics {
            assert!(!d.render(&sources).is_empty());
        }
        // Each block once, then at most the limit run again.
        let once = program.blocks.len() as u64;
        assert!(o.statements <= settings.step_limit + 1 + once, "the step limit holds");
        assert!(o.completed || o.diagnostics.iter().any(Diagnostic::is_error), "a run that stops says why");
        outcome.get_or_insert(o);
    }
    (diagnostics, outcome)
}

fn seed(name: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("testdata/seeds").join(name);
    std::fs::read_to_string(path).unwrap()
}

#[test]
fn truncated_at_every_byte() {
    let settings = Settings { step_limit: 20_000, clock_seed: Some(1), ..Settings::default() };
    for name in ["o7023_texture.nc", "o1011_digitize.nc", "o2007_thermal.nc"] {
        let text = seed(name);
        let mut errors = 0;
        for end in (0..=text.len()).filter(|&i| text.is_char_boundary(i)) {
            let (diagnostics, outcome) = parse_run(&text[..end], &settings);
            let failed = diagnostics.iter().any(Diagnostic::is_error)
                || outcome.is_some_and(|o| o.diagnostics.iter().any(Diagnostic::is_error));
            errors += usize::from(failed);
        }
        assert!(errors > 0, "{name}: some truncations must be errors (a cut inside `#30=FIX[`…)");
    }
}

#[test]
fn binary_garbage() {
    // A small deterministic generator: xorshift64*.
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut next = move || {
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        state.wrapping_mul(0x2545_F491_4F6C_DD1D)
    };
    let settings = Settings { step_limit: 10_000, ..Settings::default() };
    let alphabet = b"#[]()=+-*/.0123456789GXYZMPLIJKRFN%OEQWHDO \n\n\r\t;IFGOTOWHILEDOEND";
    for round in 0..2000 {
        let len = (next() % 200) as usize;
        let bytes: Vec<u8> = if round % 2 == 0 {
            (0..len).map(|_| next() as u8).collect()
        } else {
            (0..len).map(|_| alphabet[(next() % alphabet.len() as u64) as usize]).collect()
        };
        parse_run(&String::from_utf8_lossy(&bytes), &settings);
    }
}

#[test]
fn deep_nesting_and_long_lines_are_errors_not_overflows() {
    let settings = Settings::default();
    let deep = format!("#1={}1{}\nM30\n", "[".repeat(100_000), "]".repeat(100_000));
    let (d, _) = parse_run(&deep, &settings);
    assert_eq!(d[0].message, "brackets nested deeper than 64");
    let signs = format!("#1={}1\nM30\n", "-".repeat(100_000));
    let (d, _) = parse_run(&signs, &settings);
    assert_eq!(d[0].message, "too many signs in a row");
    let functions = format!("#1={}1{}\nM30\n", "SIN[".repeat(10_000), "]".repeat(10_000));
    let (d, _) = parse_run(&functions, &settings);
    assert_eq!(d[0].message, "brackets nested deeper than 64");
    let long = format!("G01 {} F100.\nM30\n", "X1.".repeat(200_000));
    let (_, outcome) = parse_run(&long, &settings);
    assert_eq!(outcome.unwrap().diagnostics[0].message, "address X appears twice in this block");
    let number = format!("G01 X{}.\nM30\n", "9".repeat(400));
    let (d, _) = parse_run(&number, &settings);
    assert_eq!(d[0].message, "number is too large");
}

#[test]
fn endless_loop_stops_at_the_step_limit_naming_the_loop() {
    // The default limit is ten million statements (about 8 s in a debug
    // build); a million shows the same here.
    assert_eq!(Settings::default().step_limit, 10_000_000);
    let text = "G90\nWHILE[1]DO1\nEND1\nM30\n";
    let (_, outcome) = parse_run(text, &Settings { step_limit: 1_000_000, ..Settings::default() });
    let outcome = outcome.unwrap();
    assert!(!outcome.completed);
    // G90, WHILE and END once, then a million of them run again.
    assert_eq!(outcome.statements, 1_000_004);
    let error = outcome.diagnostics.iter().find(|d| d.is_error()).unwrap();
    assert_eq!(
        error.message,
        "stopped after 1000000 statements: the WHILE … DO1 loop does not seem to end (raise the step limit if it should run longer)"
    );
    assert_eq!(error.span.start, 4, "the error points at the WHILE block");
}

#[test]
fn endless_subprogram_loop_is_stopped_too() {
    // M99 with a repeat count that never runs out, and a main program whose
    // M99 would restart it on a control.
    let settings = Settings { step_limit: 5_000, ..Settings::default() };
    let (_, outcome) = parse_run("O0001\nM98 P0002 L9999\nM30\nO0002\nG91 G01 X1. F1.\nM99\n", &settings);
    let outcome = outcome.unwrap();
    assert!(!outcome.completed);
    assert!(outcome.diagnostics.iter().any(|d| d.message.starts_with("stopped after 5000 statements")));
    let (_, outcome) = parse_run("G01 X1. F1.\nM99\n", &settings);
    let outcome = outcome.unwrap();
    assert!(outcome.completed);
    assert_eq!(
        outcome.diagnostics[0].message,
        "M99 in the main program restarts it on the control; the run stops here"
    );
}

#[test]
fn long_operator_chains_are_an_error_not_a_stack_overflow() {
    let settings = Settings::default();
    for op in ["+", "*", " AND ", "-"] {
        let fine = format!("#1=1{}\nM30\n", format!("{op}1").repeat(1000));
        let (diagnostics, outcome) = parse_run(&fine, &settings);
        assert!(diagnostics.is_empty(), "{:?}", diagnostics.first());
        assert!(outcome.unwrap().completed);
        let long = format!("G21\n#1=1{}\nM30\n", format!("{op}1").repeat(100_000));
        let (diagnostics, _) = parse_run(&long, &settings);
        let d = diagnostics.iter().find(|d| d.is_error()).expect("an error");
        assert!(d.message.contains("more than 1000 operators"), "{}", d.message);
        assert_eq!(d.headline(&sources_of(&long)).split(':').nth(1), Some("2"));
    }
    let signs = format!("#1={}1\nM30\n", "+".repeat(100_000));
    assert!(parse_run(&signs, &settings).0.is_empty());
}

fn sources_of(text: &str) -> Sources {
    let mut sources = Sources::default();
    sources.add(SourceFile::new("bad.nc", text));
    sources
}

#[test]
fn a_wait_loop_of_dwells_is_one_dwell() {
    // 50,000 turns of a dwell-only wait loop: one move of 50 s, not 50,000.
    let text = "O1\n#1=0\nWHILE [#1 LT 50000] DO1\nG04 P1000\n#1=#1+1\nEND1\nG04 P500\nM30\n";
    let (_, outcome) = parse_run(text, &Settings { step_limit: 1_000_000, ..Settings::default() });
    let o = outcome.unwrap();
    assert!(o.completed);
    let dwells: Vec<f64> = o
        .toolpath
        .moves
        .iter()
        .filter_map(|m| match m.kind {
            kezuri_geom::MoveKind::Dwell(s) => Some(s),
            _ => None,
        })
        .collect();
    assert_eq!((dwells.len(), dwells.first().copied()), (2, Some(50_000.0)), "dwells of the wait loop and after it");
}

#[test]
fn a_runaway_loop_that_moves_is_stopped_by_the_step_limit() {
    // No cap on moves: the step limit counts the statements run again, so a
    // loop that moves stops by it (three statements a turn, one move)…
    let text = "O1\nG90 G00 X0. Y0. Z5.\nM98 P2 L99999999\nM30\nO2\nG91 G01 X0.001 F100.\nG90\nM99\n";
    let settings = Settings { step_limit: 10_000, ..Settings::default() };
    let (_, outcome) = parse_run(text, &settings);
    let o = outcome.unwrap();
    let e = o.diagnostics.iter().find(|d| d.is_error()).expect("stopped").message.clone();
    assert!(e.starts_with("stopped after 10000 statements"), "{e}");
    // The G00, the first turn (run once), then turns 2 to 3335: the
    // 10,001st statement run again is the G90 of turn 3335, after its move.
    assert_eq!(o.toolpath.moves.len(), 1 + 1 + 3334);
    // …while a program read straight through runs whatever its length.
    let straight: String = (0..30_000).map(|k| format!("G01 X{}. F100.\n", k % 7)).collect::<String>() + "M30\n";
    let (_, outcome) = parse_run(&straight, &settings);
    let o = outcome.unwrap();
    assert!(o.completed, "{:?}", o.diagnostics.first());
    assert_eq!((o.statements, o.toolpath.moves.len()), (30_001, 30_000));
}
