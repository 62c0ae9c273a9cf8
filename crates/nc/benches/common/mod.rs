//! What the benchmarks that time a whole program share: the program parsed
//! and run, and the binary's `main`.

use criterion::Criterion;
use kezuri_nc::interp::{self, Outcome, Settings};
use kezuri_nc::{parse, Program, SourceFile, Sources};

/// Parses `text` (file `name`, which must parse without a word to say) and
/// runs it whole with `settings`: what is timed.
pub fn parse_and_run(name: &str, text: &str, settings: &Settings) -> Outcome {
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new(name, text));
    let mut program = Program::default();
    let diagnostics = parse(&mut program, file, text);
    assert!(diagnostics.is_empty(), "{:?}", diagnostics.first());
    interp::run(&mut program, &mut sources, 0, &mut interp::NoLibrary, settings)
}

/// The binary's `main`: with `KEZURI_BENCH_ONCE` set, `once` (each program
/// parsed and run once, its time printed), else the criterion `benches`.
pub fn main(once: fn(), benches: fn()) {
    if std::env::var_os("KEZURI_BENCH_ONCE").is_some() {
        once();
        return;
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
