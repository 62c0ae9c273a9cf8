//! Real lathe programs: every program of `corpus/lathe` runs as its
//! `SOURCES.tsv` row says a Fanuc or Haas lathe control would run it.
//!
//! Each row names the program (`path`), the control it is read for
//! (`dialect`: `fanuc-lathe` or `haas-lathe`), how an axis word without a
//! decimal point is read (`no_decimal`: `increments` as the control leaves
//! the factory, `units` where the program was written for calculator-type
//! input) and what the control does with it (`status`):
//!
//! - `complete`: it runs to its end without an alarm;
//! - `stops: <text>`: it stops with an alarm; the first error's message, or
//!   the source text the error points at, contains `<text>` (case ignored);
//! - `stops at line N: <text>`: the same, and the error is on line N.
//!
//! The statuses say what the control does, decided by reading each program
//! against the Fanuc lathe manual (FANUC Series 0i-TF Plus Operator's
//! Manual, B-64604EN, lathe system) or the Haas Lathe Operator's Manual, not
//! what kezuri happens to do: the `why` column says why a program stops (and,
//! for some that run, the reading a reviewer might doubt).
//!
//! Every program runs on its own thread: a panic, a move holding a value that
//! is not a finite number, or a run that does not end
//! within [`TIME_LIMIT`] is reported as a mismatch, and the step limit
//! bounds runaway loops. The test fails when any outcome differs from its
//! row, and prints every mismatch; the few programs kezuri is known to read
//! otherwise than the control are listed in [`KNOWN`] with why, and must
//! still differ.
//!
//! `cargo test -p kezuri-nc --test lathe_corpus -- --nocapture` prints every
//! program's outcome.

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

use kezuri_nc::interp::{self, IntegerInput, Settings};
use kezuri_nc::{parse_as, Dialect, Program, SourceFile, Sources};

mod common;

use common::corpus::Folder;

/// How long one program may run before it counts as a hang.
const TIME_LIMIT: Duration = Duration::from_secs(60);

/// Statements one run may execute (the settings' step limit).
const STEP_LIMIT: u64 = 2_000_000;

/// The machine's top spindle speed, rpm: every lathe has one, and a control
/// clamps constant surface speed to it where the program gives no G50 S
/// (the Haas ST-10's 6000 rpm).
const TOP_SPEED: f64 = 6000.0;

/// The least number of programs: pinned so that the test cannot pass by
/// finding none.
const AT_LEAST: usize = 20;

/// Programs (paths under `corpus/lathe`) whose outcome in kezuri is known to
/// differ from what the control does, with why. Each must still differ: one
/// that comes to agree is reported, to be taken off this list.
const KNOWN: &[(&str, &str)] = &[];

fn lathe_corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../corpus/lathe")
}

/// What a row says the control does.
#[derive(Debug, Clone, PartialEq)]
enum Expected {
    Complete,
    Stops { line: Option<u32>, text: String },
}

impl Expected {
    fn parse(status: &str) -> Result<Expected, String> {
        if status == "complete" {
            return Ok(Expected::Complete);
        }
        if let Some(text) = status.strip_prefix("stops: ") {
            return Ok(Expected::Stops { line: None, text: text.trim().to_string() });
        }
        if let Some(rest) = status.strip_prefix("stops at line ") {
            let (line, text) = rest.split_once(": ").ok_or_else(|| format!("status {status:?}: no ': '"))?;
            let line = line.trim().parse().map_err(|_| format!("status {status:?}: line {line:?} is not a number"))?;
            return Ok(Expected::Stops { line: Some(line), text: text.trim().to_string() });
        }
        Err(format!("status {status:?} is neither `complete`, `stops: …` nor `stops at line N: …`"))
    }
}

/// One program of the corpus, as its row reads it.
#[derive(Clone)]
struct Case {
    /// Its path under `corpus/lathe`.
    name: String,
    dialect: Dialect,
    integer_input: IntegerInput,
    expected: Expected,
}

/// The rows of `SOURCES.tsv`, each checked for its columns.
fn cases() -> Result<Vec<Case>, String> {
    let tsv = std::fs::read_to_string(lathe_corpus().join("SOURCES.tsv")).map_err(|e| format!("SOURCES.tsv: {e}"))?;
    let mut lines = tsv.lines();
    let header: Vec<&str> = lines.next().ok_or("SOURCES.tsv is empty")?.split('\t').collect();
    let col = |name: &str| header.iter().position(|c| *c == name).ok_or(format!("SOURCES.tsv has no {name} column"));
    let (path, dialect, no_decimal, status) = (col("path")?, col("dialect")?, col("no_decimal")?, col("status")?);
    let why = col("why")?;
    let mut out = Vec::new();
    for (k, row) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let cols: Vec<&str> = row.split('\t').collect();
        if cols.len() != header.len() {
            return Err(format!("SOURCES.tsv row {}: {} columns, the header has {}", k + 2, cols.len(), header.len()));
        }
        let name = cols[path].to_string();
        let dialect = match cols[dialect] {
            "fanuc-lathe" => Dialect::FanucLathe,
            "haas-lathe" => Dialect::HaasLathe,
            other => return Err(format!("{name}: dialect {other:?} is not fanuc-lathe or haas-lathe")),
        };
        let integer_input = match cols[no_decimal] {
            "increments" => IntegerInput::Increments,
            "units" => IntegerInput::Units,
            other => return Err(format!("{name}: no_decimal {other:?} is not increments or units")),
        };
        let expected = Expected::parse(cols[status]).map_err(|e| format!("{name}: {e}"))?;
        if matches!(expected, Expected::Stops { .. }) && cols[why].trim().is_empty() {
            return Err(format!("{name}: stops, but its why column is empty"));
        }
        out.push(Case { name, dialect, integer_input, expected });
    }
    Ok(out)
}

/// The first error of a run.
#[derive(Debug)]
struct Stop {
    /// Its line in the file it is in (0: none).
    line: u32,
    /// Its message.
    message: String,
    /// The source text it points at (a word, a block).
    at: String,
    /// `file:line:col: error: message`, for the report.
    headline: String,
}

/// How a run ended: `Ok` when it reached its end without an error, else its
/// first error.
type Outcome = Result<(), Stop>;

fn no_error(message: &str) -> Stop {
    Stop { line: 0, message: message.into(), at: String::new(), headline: message.into() }
}

/// Parses and runs `text` as `case` says.
fn run(case: &Case, text: &str, folder: PathBuf) -> Outcome {
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new(case.name.clone(), text));
    let mut program = Program::default();
    let first_error = |d: &kezuri_nc::Diagnostic, sources: &Sources| {
        let file = sources.get(d.span.file);
        let at = file.text.get(d.span.start as usize..d.span.end as usize).unwrap_or("").to_string();
        Stop { line: file.line_col(d.span.start).0, message: d.message.clone(), at, headline: d.headline(sources) }
    };
    let parsed = parse_as(&mut program, file, text, case.dialect);
    if let Some(d) = parsed.iter().find(|d| d.is_error()) {
        return Err(first_error(d, &sources));
    }
    if program.units.is_empty() {
        return Err(no_error("no program in the file"));
    }
    let settings = Settings {
        dialect: case.dialect,
        integer_input: case.integer_input,
        step_limit: STEP_LIMIT,
        max_rpm: Some(TOP_SPEED),
        ..Settings::default()
    };
    let outcome = interp::run(&mut program, &mut sources, 0, &mut Folder(vec![folder]), &settings);
    // Whatever the outcome, no move may hold a value that is not a finite number.
    if let Some(m) = outcome.toolpath.moves.iter().find(|m| {
        let (s, e) = (m.start.to_array(), m.end.to_array());
        s.iter().chain(&e).any(|v| !v.is_finite()) || !m.feed.is_finite() || !m.speed.is_finite()
    }) {
        return Err(no_error(&format!("line {}: a move holds a value that is not a finite number", m.line)));
    }
    if let Some(d) = outcome.diagnostics.iter().find(|d| d.is_error()) {
        return Err(first_error(d, &sources));
    }
    if !outcome.completed {
        return Err(no_error("the run did not reach its end (no error given)"));
    }
    Ok(())
}

/// Runs `case` on a thread of its own: a panic or a hang becomes an error
/// message instead of ending the test.
fn run_guarded(case: Case) -> (Case, Result<Outcome, String>) {
    let path = lathe_corpus().join(&case.name);
    let text = match std::fs::read(&path) {
        Ok(bytes) => String::from_utf8_lossy(&bytes).into_owned(),
        Err(e) => return (case, Err(format!("cannot read {}: {e}", path.display()))),
    };
    let folder = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let (send, receive) = mpsc::channel();
    let shared = case.clone();
    let worker = std::thread::Builder::new()
        .name(case.name.clone())
        .spawn(move || {
            let outcome = run(&shared, &text, folder);
            let _ = send.send(outcome);
        })
        .expect("a thread for the run");
    let result = match receive.recv_timeout(TIME_LIMIT) {
        Ok(outcome) => Ok(outcome),
        Err(mpsc::RecvTimeoutError::Timeout) => Err(format!("did not finish within {} s", TIME_LIMIT.as_secs())),
        Err(mpsc::RecvTimeoutError::Disconnected) => {
            let message = match worker.join() {
                Err(panic) => panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_else(|| "a panic".into()),
                Ok(()) => "the run ended without an outcome".into(),
            };
            Err(format!("panicked: {message}"))
        }
    };
    (case, result)
}

/// Whether `outcome` is what `expected` says; `Err` says how it differs.
fn compare(expected: &Expected, outcome: &Outcome) -> Result<(), String> {
    match (expected, outcome) {
        (Expected::Complete, Ok(())) => Ok(()),
        (Expected::Complete, Err(stop)) => Err(format!("expected to run to its end, stops: {}", stop.headline)),
        (Expected::Stops { text, .. }, Ok(())) => Err(format!("expected to stop with {text:?}, runs to its end")),
        (Expected::Stops { line, text }, Err(stop)) => {
            let text = text.to_lowercase();
            let text_ok = stop.message.to_lowercase().contains(&text) || stop.at.to_lowercase().contains(&text);
            let line_ok = line.is_none_or(|l| l == stop.line);
            if text_ok && line_ok {
                Ok(())
            } else {
                let want = match line {
                    Some(l) => format!("line {l}: {text:?}"),
                    None => format!("{text:?}"),
                };
                Err(format!("expected to stop with {want}, stops: {}", stop.headline))
            }
        }
    }
}

#[test]
fn lathe_programs_run_as_the_control_runs_them() {
    let cases = match cases() {
        Ok(c) => c,
        Err(e) => panic!("corpus/lathe/SOURCES.tsv: {e}"),
    };
    // Every program file has its row, and every row its file.
    let on_disk = common::corpus::programs(&lathe_corpus());
    let mut listed: Vec<String> = cases.iter().map(|c| c.name.clone()).collect();
    listed.sort();
    assert_eq!(listed, on_disk, "corpus/lathe: every program has its SOURCES.tsv row and every row its file");
    assert!(cases.len() >= AT_LEAST, "only {} programs, at least {AT_LEAST} expected", cases.len());

    for (name, _) in KNOWN {
        assert!(cases.iter().any(|c| c.name == *name), "KNOWN names {name}, which SOURCES.tsv does not list");
    }

    let total = cases.len();
    let mut agree = 0;
    let mut unexpected = Vec::new();
    for case in cases {
        let (case, result) = run_guarded(case);
        let verdict = match &result {
            Ok(outcome) => compare(&case.expected, outcome),
            Err(e) => Err(e.clone()),
        };
        let known = KNOWN.iter().find(|(name, _)| *name == case.name).map(|(_, why)| *why);
        match (verdict, known) {
            (Ok(()), None) => {
                agree += 1;
                eprintln!("as expected: {} ({:?})", case.name, case.expected);
            }
            (Ok(()), Some(why)) => {
                agree += 1;
                eprintln!("as expected: {} ({:?})", case.name, case.expected);
                unexpected.push(format!("{}: listed in KNOWN ({why}) but now runs as the control does", case.name));
            }
            (Err(d), Some(_)) => eprintln!("KNOWN:       {}: {d}", case.name),
            (Err(d), None) => {
                eprintln!("MISMATCH:    {}: {d}", case.name);
                unexpected.push(format!("{}: {d}", case.name));
            }
        }
    }
    eprintln!("{agree} of {total} programs run as SOURCES.tsv says ({} known to differ)", KNOWN.len());
    assert!(unexpected.is_empty(), "{} of {total} programs:\n{}", unexpected.len(), unexpected.join("\n"));
}
