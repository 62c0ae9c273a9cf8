//! Parser and interpreter on arbitrary bytes, read as Fanuc and as LinuxCNC:
//! no input may panic or hang.
#![no_main]

use kezuri_nc::{interp, parse_as, Dialect, Program, SourceFile, Sources};
use libfuzzer_sys::fuzz_target;

/// Every LinuxCNC subroutine file (`o<name> call`) is the input again.
struct Itself(String);

impl interp::Library for Itself {
    fn load(&mut self, _: u32) -> Option<SourceFile> {
        None
    }

    fn load_ngc(&mut self, stem: &str) -> Option<SourceFile> {
        Some(SourceFile::new(format!("{stem}.ngc"), self.0.clone()))
    }
}

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data).into_owned();
    for dialect in [Dialect::Fanuc, Dialect::LinuxCnc] {
        run(&text, dialect);
    }
});

fn run(text: &str, dialect: Dialect) {
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("fuzz.nc", text.to_string()));
    let mut program = Program::default();
    let diagnostics = parse_as(&mut program, file, text, dialect);
    for d in &diagnostics {
        let _ = d.render(&sources);
    }
    let integer_input =
        if dialect == Dialect::LinuxCnc { interp::IntegerInput::Units } else { interp::IntegerInput::Increments };
    let settings = interp::Settings { step_limit: 10_000, dialect, integer_input, ..interp::Settings::default() };
    let mut library = Itself(text.to_string());
    for main in 0..program.units.len().min(2) {
        let outcome = interp::run(&mut program, &mut sources, main, &mut library, &settings);
        assert!(outcome.statements <= settings.step_limit + 1);
        for d in &outcome.diagnostics {
            let _ = d.render(&sources);
        }
    }
}
