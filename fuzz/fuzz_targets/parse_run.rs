//! Parser and interpreter on arbitrary bytes: no input may panic or hang.
#![no_main]

use kezuri_nc::{interp, parse, Program, SourceFile, Sources};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data).into_owned();
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("fuzz.nc", text.clone()));
    let mut program = Program::default();
    let diagnostics = parse(&mut program, file, &text);
    for d in &diagnostics {
        let _ = d.render(&sources);
    }
    let settings = interp::Settings { step_limit: 10_000, ..interp::Settings::default() };
    for main in 0..program.units.len().min(2) {
        let outcome = interp::run(&mut program, &mut sources, main, &mut interp::NoLibrary, &settings);
        assert!(outcome.statements <= settings.step_limit + 1);
        for d in &outcome.diagnostics {
            let _ = d.render(&sources);
        }
    }
});
