//! What the interpreter's tests share: a program parsed (a parse error
//! fails the test) and run, and what the run said. The writer's tests share
//! [`writer`], the tests of LinuxCNC's program language [`ngc`] and those of
//! its motion words [`linuxcnc`], the tests of a Fanuc or Haas lathe
//! [`lathe`], those of the tool nose [`nose`], the corpus tests [`corpus`].

// Each test file uses a part of it.
#![allow(dead_code)]

use kezuri_geom::Toolpath;
use kezuri_nc::interp::{self, Outcome, Settings};
use kezuri_nc::{parse, Diagnostic, Program, SourceFile, Sources};

pub mod corpus;
pub mod lathe;
pub mod linuxcnc;
pub mod ngc;
pub mod nose;
pub mod writer;

/// A program run: its parse diagnostics, the outcome, the sources to
/// render diagnostics with.
pub struct Ran {
    pub parsed: Vec<Diagnostic>,
    pub outcome: Outcome,
    pub sources: Sources,
    text: String,
}

/// Parses `text` as file `name` and runs it with `settings`.
pub fn run(name: &str, text: &str, settings: &Settings) -> Ran {
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new(name, text));
    let mut program = Program::default();
    let parsed = parse(&mut program, file, text);
    if let Some(d) = parsed.iter().find(|d| d.is_error()) {
        panic!("{text}\ndoes not parse:\n{}", d.render(&sources));
    }
    let outcome = interp::run(&mut program, &mut sources, 0, &mut interp::NoLibrary, settings);
    Ran { parsed, outcome, sources, text: text.to_string() }
}

impl Ran {
    /// The error that stopped the run.
    pub fn error(&self) -> Option<&Diagnostic> {
        self.outcome.diagnostics.iter().find(|d| d.is_error())
    }

    /// The outcome of a run that must reach its end without an error.
    pub fn completed(self) -> Outcome {
        if let Some(d) = self.error() {
            panic!("{}\nstopped:\n{}", self.text, d.render(&self.sources));
        }
        assert!(self.outcome.completed, "{}: the run must reach its end", self.text);
        self.outcome
    }

    /// The toolpath of a run that must reach its end without an error.
    pub fn path(self) -> Toolpath {
        self.completed().toolpath
    }

    fn stopped(&self) -> &Diagnostic {
        self.error().unwrap_or_else(|| panic!("no error:\n{}", self.text))
    }

    /// The message of the error that stopped the run.
    pub fn message(&self) -> String {
        self.stopped().message.clone()
    }

    /// `file:line:col: error: …` of the error that stopped the run.
    pub fn headline(&self) -> String {
        assert!(!self.outcome.completed, "{}: the run must stop", self.text);
        self.stopped().headline(&self.sources)
    }

    /// The error that stopped the run, rendered with its line and caret.
    pub fn rendered(&self) -> String {
        self.stopped().render(&self.sources)
    }
}
