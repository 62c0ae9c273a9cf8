//! What the tests of LinuxCNC's motion words share: a program run as
//! `t.ngc` in the linuxcnc dialect, with LinuxCNC's coordinate rules; its
//! toolpath, its error, its moves rounded.

use kezuri_geom::{MoveKind, Toolpath};
use kezuri_nc::interp::{self, Control, CoordSettings, IntegerInput, Outcome, Settings};
use kezuri_nc::{parse_as, Dialect, Program, SourceFile, Sources};

pub fn settings() -> Settings {
    Settings {
        dialect: Dialect::LinuxCnc,
        integer_input: IntegerInput::Units,
        coords: CoordSettings { control: Control::LinuxCnc, ..CoordSettings::default() },
        ..Settings::default()
    }
}

/// `text` parsed and run as `t.ngc` in the linuxcnc dialect with
/// `settings`: the outcome and the sources (for rendering), or the parse
/// error rendered.
pub fn run_with(text: &str, settings: &Settings) -> Result<(Outcome, Sources), String> {
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new("t.ngc", text));
    let mut program = Program::default();
    let parsed = parse_as(&mut program, file, text, Dialect::LinuxCnc);
    if let Some(d) = parsed.iter().find(|d| d.is_error()) {
        return Err(d.headline(&sources));
    }
    let outcome = interp::run(&mut program, &mut sources, 0, &mut interp::NoLibrary, settings);
    Ok((outcome, sources))
}

/// The toolpath of a run that must complete.
pub fn path(text: &str) -> Toolpath {
    path_with(text, &settings())
}

pub fn path_with(text: &str, settings: &Settings) -> Toolpath {
    let (outcome, sources) = run_with(text, settings).unwrap_or_else(|e| panic!("{text}\ndoes not parse: {e}"));
    if let Some(d) = outcome.diagnostics.iter().find(|d| d.is_error()) {
        panic!("{text}\nstopped: {}", d.render(&sources));
    }
    assert!(outcome.completed, "{text}: must complete");
    outcome.toolpath
}

/// `file:line:col: error: …` of the error that stops `text` (parse or run).
pub fn error(text: &str) -> String {
    match run_with(text, &settings()) {
        Err(e) => e,
        Ok((outcome, sources)) => {
            let d = outcome.diagnostics.iter().find(|d| d.is_error()).unwrap_or_else(|| panic!("{text}: no error"));
            assert!(!outcome.completed);
            d.headline(&sources)
        }
    }
}

/// Each move as (kind, x, y, z) rounded to 0.1 µm; dwells as ('d', s, 0, 0).
pub fn moves(t: &Toolpath) -> Vec<(char, f64, f64, f64)> {
    let r = |v: f64| (v * 1e4).round() / 1e4 + 0.0;
    t.moves
        .iter()
        .map(|m| match m.kind {
            MoveKind::Dwell(s) => ('d', s, 0.0, 0.0),
            MoveKind::Rapid => ('r', r(m.end.x), r(m.end.y), r(m.end.z)),
            MoveKind::Arc(_) => ('a', r(m.end.x), r(m.end.y), r(m.end.z)),
            _ => ('f', r(m.end.x), r(m.end.y), r(m.end.z)),
        })
        .collect()
}
