//! Golden NC corpus: adding a case is adding a file.
//!
//! - `testdata/interp/<case>.nc` runs to completion without an error; its
//!   expected output `<case>.csv` is the CSV motion dump
//!   ([`kezuri_nc::write::csv`]) followed by the `DPRNT` lines, the rendered
//!   warnings and the block count.
//! - `testdata/diagnostics/<case>.nc` must give at least one error; its
//!   expected output `<case>.err` is every diagnostic, rendered with
//!   [`kezuri_nc::Diagnostic::render`]. A program with parse errors is not
//!   run (as the CLI does); otherwise the run's diagnostics follow.
//!
//! A case may start with a settings comment, for example
//! `(TEST: integer-input=units clock-seed=7 step-limit=1000 block-delete H1=100. D1=3. G55=10,20,0 home=0,0,300)`.
//! Programs `O####` a case calls but does not hold are read from
//! `testdata/library/O####.nc`.
//!
//! `UPDATE_EXPECT=1 cargo test -p kezuri-nc --test corpus` rewrites the
//! expected files; read every changed one before accepting it.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use kezuri_geom::{Axes, Coolant, MoveKind, Spindle, Toolpath};
use kezuri_nc::interp::{self, IntegerInput, Library, Settings};
use kezuri_nc::{parse, write, Program, SourceFile, Sources};

fn testdata() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("testdata")
}

/// `O####.nc` files of `testdata/library`.
struct Folder;

impl Library for Folder {
    fn load(&mut self, number: u32) -> Option<SourceFile> {
        let name = format!("O{number:04}.nc");
        let text = std::fs::read(testdata().join("library").join(&name)).ok()?;
        Some(SourceFile::new(name, String::from_utf8_lossy(&text).into_owned()))
    }
}

fn axes(text: &str) -> Axes {
    let v: Vec<f64> = text.split(',').map(|s| s.parse().expect("a number in a TEST: axes list")).collect();
    let mut a = [0.0; Axes::COUNT];
    a[..v.len()].copy_from_slice(&v);
    Axes::from_array(a)
}

/// Settings from the `(TEST: …)` comment, if the case has one.
fn settings(text: &str) -> Settings {
    let mut s = Settings::default();
    let Some(start) = text.find("(TEST:") else { return s };
    let end = text[start..].find(')').map_or(text.len(), |e| start + e);
    for item in text[start + 6..end].split_whitespace() {
        let (key, value) = item.split_once('=').unwrap_or((item, ""));
        match key {
            "integer-input" => {
                s.integer_input = if value == "units" { IntegerInput::Units } else { IntegerInput::Increments }
            }
            "clock-seed" => s.clock_seed = Some(value.parse().expect("clock-seed")),
            "step-limit" => s.step_limit = value.parse().expect("step-limit"),
            "block-delete" => s.block_delete = true,
            "home" => s.home = axes(value),
            _ if key.starts_with('H') => {
                s.tool_lengths.insert(key[1..].parse().expect("H number"), value.parse().expect("length"));
            }
            _ if key.starts_with('D') => {
                s.tool_radii.insert(key[1..].parse().expect("D number"), value.parse().expect("radius"));
            }
            _ if key.starts_with("G5") => {
                let g: usize = key[1..].parse().expect("G54..G59");
                s.work_offsets[g - 54] = axes(value);
            }
            _ => panic!("unknown TEST: setting {key}"),
        }
    }
    s
}

/// What the CSV dump does not show: arc centres, dwells, and changes of
/// tool, spindle and coolant.
fn beyond_csv(toolpath: &Toolpath) -> String {
    let mut out = String::new();
    let mut state = (0, Spindle::Off, 0.0, Coolant::default());
    for m in &toolpath.moves {
        match m.kind {
            MoveKind::Arc(arc) => {
                let [x, y, z] = arc.center;
                let dir = if arc.ccw { "ccw" } else { "cw" };
                let _ = writeln!(out, "{}: {dir} arc in {:?}, centre {x},{y},{z}", m.line, arc.plane);
            }
            MoveKind::Dwell(s) => {
                let _ = writeln!(out, "{}: dwell {s} s", m.line);
            }
            _ => {}
        }
        let now = (m.tool, m.spindle, m.speed, m.coolant);
        if now != state {
            let c = m.coolant;
            let _ = writeln!(
                out,
                "{}: tool {}, spindle {:?} {} rpm, mist {}, flood {}",
                m.line, m.tool, m.spindle, m.speed, c.mist, c.flood
            );
            state = now;
        }
    }
    if out.is_empty() {
        out
    } else {
        format!("-- arcs, dwells, tool/spindle/coolant changes\n{out}")
    }
}

/// Parses and runs one case; returns its rendered result and whether it had
/// an error.
fn run_case(path: &Path, interp_case: bool) -> (String, bool) {
    let bytes = std::fs::read(path).expect("case file");
    let text = String::from_utf8_lossy(&bytes).into_owned();
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new(name, text.clone()));
    let mut program = Program::default();
    let mut diagnostics = parse(&mut program, file, &text);
    let parse_failed = diagnostics.iter().any(|d| d.is_error());
    let mut out = String::new();
    let mut completed = false;
    if !parse_failed {
        let outcome = interp::run(&mut program, &mut sources, 0, &mut Folder, &settings(&text));
        completed = outcome.completed;
        diagnostics.extend(outcome.diagnostics);
        if interp_case {
            out.push_str(&write::csv(&outcome.toolpath));
            out.push_str(&beyond_csv(&outcome.toolpath));
            if !outcome.prints.is_empty() {
                out.push_str("-- DPRNT\n");
                for line in &outcome.prints {
                    out.push_str(line);
                    out.push('\n');
                }
            }
        }
        if interp_case {
            let _ = writeln!(out, "-- {} blocks, {} statements", outcome.blocks, outcome.statements);
        }
    }
    let error = diagnostics.iter().any(|d| d.is_error()) || !completed;
    if interp_case && !diagnostics.is_empty() {
        out.push_str("-- diagnostics\n");
    }
    for d in &diagnostics {
        out.push_str(&d.render(&sources));
        out.push_str("\n\n");
    }
    (out, error)
}

/// Runs every case of `testdata/<folder>` against its `<case>.<ext>`.
fn check_folder(folder: &str, ext: &str, interp_case: bool) {
    let dir = testdata().join(folder);
    let mut cases: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "nc"))
        .collect();
    cases.sort();
    assert!(!cases.is_empty(), "no cases in {}", dir.display());
    let update = std::env::var_os("UPDATE_EXPECT").is_some();
    let mut failures = Vec::new();
    for case in &cases {
        let (actual, error) = run_case(case, interp_case);
        let name = case.file_stem().unwrap().to_string_lossy().into_owned();
        if interp_case && error {
            failures.push(format!("{name}: an interp case must run to its end without an error:\n{actual}"));
            continue;
        }
        if !interp_case && !error {
            failures.push(format!("{name}: a diagnostics case must give an error:\n{actual}"));
            continue;
        }
        let expected_path = case.with_extension(ext);
        let expected = std::fs::read_to_string(&expected_path).unwrap_or_default();
        if expected == actual {
            continue;
        }
        if update {
            std::fs::write(&expected_path, &actual).expect("write the expected file");
            eprintln!("updated {}", expected_path.display());
        } else {
            failures.push(format!(
                "{name}: output differs from {}\n--- expected\n{expected}\n--- actual\n{actual}",
                expected_path.display()
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} cases failed (UPDATE_EXPECT=1 rewrites the expected files):\n\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n\n")
    );
}

#[test]
fn interp_corpus() {
    check_folder("interp", "csv", true);
}

#[test]
fn diagnostics_corpus() {
    check_folder("diagnostics", "err", false);
}
