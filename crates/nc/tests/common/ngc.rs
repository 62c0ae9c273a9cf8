//! What the tests of LinuxCNC's program language share: subroutine files
//! by stem, a program run as `t.ngc` in the linuxcnc dialect, its first
//! error and its end points.

use std::collections::BTreeMap;

use kezuri_nc::interp::{self, IntegerInput, Library, Outcome, Settings};
use kezuri_nc::{parse_as, Diagnostic, Dialect, Program, SourceFile, Sources};

/// Subroutine files by stem (`name` for `name.ngc`).
#[derive(Default)]
pub struct Files(BTreeMap<String, String>);

impl Library for Files {
    fn load(&mut self, _: u32) -> Option<SourceFile> {
        None
    }

    fn load_ngc(&mut self, stem: &str) -> Option<SourceFile> {
        self.0.get(stem).map(|text| SourceFile::new(format!("{stem}.ngc"), text.clone()))
    }
}

pub fn settings() -> Settings {
    Settings { dialect: Dialect::LinuxCnc, integer_input: IntegerInput::Units, ..Settings::default() }
}

pub struct Ran {
    pub outcome: Outcome,
    pub sources: Sources,
    pub parse_errors: Vec<Diagnostic>,
}

impl Ran {
    /// The first error, parse or run, rendered `t.ngc:line:col: error: …`.
    pub fn error(&self) -> Option<String> {
        let d = self.parse_errors.first().or_else(|| self.outcome.diagnostics.iter().find(|d| d.is_error()))?;
        Some(d.render(&self.sources))
    }

    /// Move end points (x, y, z), mm.
    pub fn ends(&self) -> Vec<[f64; 3]> {
        self.outcome.toolpath.moves.iter().map(|m| [m.end.x, m.end.y, m.end.z]).collect()
    }

    pub fn ok(self) -> Ran {
        if let Some(e) = self.error() {
            panic!("unexpected error:\n{e}");
        }
        assert!(self.outcome.completed, "the run did not end");
        self
    }
}

pub fn run_with(text: &str, files: &[(&str, &str)], settings: &Settings) -> Ran {
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("t.ngc", text));
    let mut program = Program::default();
    let parse_errors: Vec<_> =
        parse_as(&mut program, file, text, Dialect::LinuxCnc).into_iter().filter(Diagnostic::is_error).collect();
    let mut library = Files(files.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect());
    let outcome = interp::run(&mut program, &mut sources, 0, &mut library, settings);
    Ran { outcome, sources, parse_errors }
}

pub fn run(text: &str) -> Ran {
    run_with(text, &[], &settings())
}

pub fn assert_ends(ran: &Ran, want: &[[f64; 3]]) {
    let got = ran.ends();
    assert_eq!(got.len(), want.len(), "moves: got {got:?}, want {want:?}");
    for (g, w) in got.iter().zip(want) {
        assert!(g.iter().zip(w).all(|(a, b)| (a - b).abs() < 1e-9), "got {got:?}, want {want:?}");
    }
}

/// The first error of `text`, which must be located at `line` of t.ngc.
/// (A block that does not parse is an error and an empty block, as in
/// the Fanuc dialect; an O-word that does not match stops the run too.)
pub fn error_at(text: &str, line: u32) -> String {
    let ran = run(text);
    let e = ran.error().unwrap_or_else(|| panic!("no error for\n{text}"));
    assert!(e.starts_with(&format!("t.ngc:{line}:")), "want line {line}:\n{e}");
    e
}
