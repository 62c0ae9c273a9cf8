//! Inputs that once crashed or hung the parser or the interpreter, found by
//! the fuzz target `fuzz/fuzz_targets/parse_run.rs`: every file of
//! `testdata/fuzz` goes through the same steps as the fuzz target and must
//! end without a panic, within the step limit. Adding a case is adding a file
//! (see fuzz/README.md).

use std::path::Path;

use kezuri_nc::{interp, parse, Program, SourceFile, Sources};

/// What the fuzz target does with one input: parse it as lossy UTF-8, render
/// every diagnostic, and run the first two program units with a small step
/// limit. Returns the statements executed by each run.
fn parse_and_run(data: &[u8]) -> Vec<u64> {
    let text = String::from_utf8_lossy(data).into_owned();
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("fuzz.nc", text.clone()));
    let mut program = Program::default();
    for d in parse(&mut program, file, &text) {
        assert!(!d.render(&sources).is_empty());
    }
    let settings = interp::Settings { step_limit: 10_000, ..interp::Settings::default() };
    let mut statements = Vec::new();
    for main in 0..program.units.len().min(2) {
        let outcome = interp::run(&mut program, &mut sources, main, &mut interp::NoLibrary, &settings);
        for d in &outcome.diagnostics {
            assert!(!d.render(&sources).is_empty());
        }
        statements.push(outcome.statements);
    }
    statements
}

#[test]
fn every_saved_fuzz_input_ends_without_a_panic() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("testdata/fuzz");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .expect("testdata/fuzz")
        .map(|e| e.expect("a directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "nc"))
        .collect();
    paths.sort();
    assert!(!paths.is_empty(), "no .nc files in {}", dir.display());
    for path in paths {
        let data = std::fs::read(&path).expect("a fuzz input");
        let result = std::panic::catch_unwind(|| parse_and_run(&data));
        let statements = result.unwrap_or_else(|_| panic!("{} panics", path.display()));
        assert!(statements.iter().all(|&n| n <= 10_001), "{} runs past its step limit: {statements:?}", path.display());
    }
}
