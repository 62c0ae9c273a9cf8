//! The portability rule over real programs: a program expanded with one
//! machine file (machine A) and run on another (machine B) makes the same
//! motions as the source program run on machine B.
//!
//! The programs: every program of `corpus/shop` (read as its `SOURCES.tsv`
//! row says: `no_decimal` `units` or `increments`), the test programs of
//! `crates/nc/testdata` (`interp`, `seeds`, `write`, `rml`, `fuzz`, `library`, `shop`),
//! `samples/*.nc` and `bench/programs`. Each runs as given and with `G10 L2 P1 X.. Y.. Z..` put
//! after its first line (a work offset the program sets itself).
//!
//! For each program that runs to its end on machine A, the run's motions are
//! written as `kezuri run` writes them (the programmed contour with its
//! G41/G42 D where the program uses cutter compensation, else the toolpath)
//! in the Fanuc and the LinuxCNC dialect; the written text is run on machine
//! B and compared with the source run on machine B: the same number of
//! moves, the same kinds (arc direction and plane included), ends and arc
//! centres within 1e-3 mm plus half a unit of the third decimal, dwells
//! equal, and the same frames (work offset, tool length register).
//!
//! Machines A and B differ in everything the rule is about: G54–G59 (far
//! from zero, different on every axis), tool lengths H1–H99 and radii
//! D1–D99, and the reference points (G28 and G30 P2–P4).
//!
//! Programs that read the machine's state into their motions (`#5221`,
//! `#5063`, the clock) are not portable by nature: what such an expansion
//! fixes is the value read on machine A. They are listed in [`KNOWN`] with
//! the reason, and the test checks they still differ (so a change that makes
//! them agree shows up).
//!
//! `cargo test -p kezuri-nc --test portable_corpus -- --nocapture` prints
//! every case.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use kezuri_geom::{Axes, MoveKind, Toolpath};
use kezuri_nc::interp::comp::Rules;
use kezuri_nc::interp::{self, IntegerInput, Library, Outcome, Settings};
use kezuri_nc::write::{csv, may_move_uvw, program, CsvWriter, Dialect, ProgramWriter, WriteOptions};
use kezuri_nc::{parse, Program, SourceFile, Sources};

mod common;

use common::corpus::Folder;

/// How far apart two ends may be: 1e-3 mm plus half a unit of the last of
/// the three decimals written.
const TOLERANCE: f64 = 1e-3 + 5e-4;

/// The least number of (program, variant) pairs compared: every program
/// found that runs on machine A and on machine B, as given and with the G10
/// line. Pinned so that the test cannot pass by comparing nothing.
const AT_LEAST_COMPARED: usize = 207;

/// Cases (`<program> <variant> <dialect>`, a prefix of the case name) known
/// to differ, with why. Each must still differ.
const KNOWN: &[(&str, &str)] = &[
    (
        "bench/programs/comp-linuxcnc.ngc as given Fanuc",
        "G41.1 D (compensation by a diameter) is LinuxCNC's alone: the Fanuc writer refuses it, with its line",
    ),
    (
        "bench/programs/comp-linuxcnc.ngc with G10 Fanuc",
        "G41.1 D (compensation by a diameter) is LinuxCNC's alone: the Fanuc writer refuses it, with its line",
    ),
    (
        "crates/nc/testdata/interp/set_position_g92.nc as given",
        "reads the machine: #5003 and #5023 (machine positions) become move ends",
    ),
    (
        "crates/nc/testdata/interp/tool_length_g43.nc",
        "reads the machine: #5023 (the gauge line's machine Z) becomes move ends",
    ),
    ("crates/nc/testdata/interp/work_offsets.nc", "reads the machine: #5001 and #5021 (positions) become move ends"),
];

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A program of the corpus and how it is read.
struct Case {
    /// Its path from the repository root.
    name: String,
    text: String,
    /// How axis words without a decimal point are read.
    integer_input: IntegerInput,
    /// Settings of a `(TEST: …)` comment that are not the machine's.
    clock_seed: Option<u64>,
    step_limit: Option<u64>,
    block_delete: bool,
    /// Folders subprograms are read from.
    library: Vec<PathBuf>,
}

impl Case {
    /// Cutter compensation rules as `kezuri run` picks them: LinuxCNC's for
    /// a `.ngc` file or a program read with whole-unit words, else Fanuc's.
    fn rules(&self) -> Rules {
        if self.integer_input == IntegerInput::Units || self.name.to_lowercase().ends_with(".ngc") {
            Rules::LinuxCnc
        } else {
            Rules::default()
        }
    }

    fn settings(&self, machine: &Settings) -> Settings {
        let mut s = Settings {
            integer_input: self.integer_input,
            comp_rules: self.rules(),
            clock_seed: self.clock_seed,
            block_delete: self.block_delete,
            ..machine.clone()
        };
        if let Some(limit) = self.step_limit {
            s.step_limit = limit;
        }
        s
    }
}

fn read(path: &Path) -> String {
    String::from_utf8_lossy(&std::fs::read(path).expect("a program file")).into_owned()
}

fn relative(path: &Path) -> String {
    let root = root().canonicalize().unwrap();
    let path = path.canonicalize().unwrap();
    path.strip_prefix(&root).unwrap_or(&path).display().to_string()
}

fn files(dir: &Path, keep: impl Fn(&Path) -> bool) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.is_file() && keep(p))
        .collect();
    out.sort();
    out
}

/// Every program of the corpus.
fn corpus() -> Vec<Case> {
    let root = root();
    let mut cases = Vec::new();
    // corpus/shop, as SOURCES.tsv reads each.
    let shop = root.join("corpus/shop");
    let tsv = read(&shop.join("SOURCES.tsv"));
    let mut header = tsv.lines().next().expect("a header").split('\t');
    let path_col = header.position(|c| c == "path").expect("a path column");
    let no_decimal_col = tsv.lines().next().unwrap().split('\t').position(|c| c == "no_decimal").expect("no_decimal");
    for row in tsv.lines().skip(1).filter(|l| !l.trim().is_empty()) {
        let cols: Vec<&str> = row.split('\t').collect();
        let path = shop.join(cols[path_col]);
        let integer_input = match cols[no_decimal_col] {
            "units" => IntegerInput::Units,
            "increments" => IntegerInput::Increments,
            other => panic!("{}: no_decimal {other}", cols[path_col]),
        };
        cases.push(Case {
            name: relative(&path),
            text: read(&path),
            integer_input,
            clock_seed: None,
            step_limit: None,
            block_delete: false,
            library: vec![path.parent().unwrap().to_path_buf()],
        });
    }
    // Every program file of corpus/shop has its row.
    let listed = cases.len();
    let on_disk = common::corpus::programs(&shop).len();
    assert_eq!(listed, on_disk, "corpus/shop: every program has its SOURCES.tsv row");

    // crates/nc/testdata: the interp cases with their (TEST: …) settings.
    let testdata = root.join("crates/nc/testdata");
    let library = testdata.join("library");
    for path in files(&testdata.join("interp"), |p| p.extension().is_some_and(|e| e == "nc")) {
        let text = read(&path);
        let mut case = Case {
            name: relative(&path),
            text: text.clone(),
            integer_input: IntegerInput::Increments,
            clock_seed: None,
            step_limit: None,
            block_delete: false,
            library: vec![path.parent().unwrap().to_path_buf(), library.clone()],
        };
        if let Some(start) = text.find("(TEST:") {
            let end = text[start..].find(')').map_or(text.len(), |e| start + e);
            for item in text[start + 6..end].split_whitespace() {
                let (key, value) = item.split_once('=').unwrap_or((item, ""));
                match key {
                    "integer-input" if value == "units" => case.integer_input = IntegerInput::Units,
                    "clock-seed" => case.clock_seed = Some(value.parse().unwrap()),
                    "step-limit" => case.step_limit = Some(value.parse().unwrap()),
                    "block-delete" => case.block_delete = true,
                    // Offsets, lengths, radii and the reference point are the
                    // machines' below.
                    _ => {}
                }
            }
        }
        cases.push(case);
    }
    // The other test programs and the samples: `.ngc` read as LinuxCNC does.
    let mut others = Vec::new();
    for dir in ["seeds", "write", "rml", "fuzz", "library", "shop"] {
        others.extend(files(&testdata.join(dir), |p| {
            let name = p.to_string_lossy().to_lowercase();
            name.ends_with(".nc") || name.ends_with(".ngc")
        }));
    }
    others.extend(files(&root.join("samples"), |p| p.extension().is_some_and(|e| e == "nc")));
    others.extend(files(&root.join("bench/programs"), |p| p.extension().is_some_and(|e| e == "nc" || e == "ngc")));
    for path in others {
        let name = path.to_string_lossy().to_lowercase();
        // LinuxCNC and GRBL programs read `X10` as 10 mm and `G4 P` in seconds.
        let ngc = name.ends_with(".ngc") || name.contains(".grbl.") || name.contains(".linuxcnc.");
        cases.push(Case {
            name: relative(&path),
            text: read(&path),
            integer_input: if ngc { IntegerInput::Units } else { IntegerInput::Increments },
            clock_seed: None,
            step_limit: None,
            block_delete: false,
            library: vec![path.parent().unwrap().to_path_buf(), library.clone()],
        });
    }
    cases
}

fn at(x: f64, y: f64, z: f64, a: f64, b: f64, c: f64) -> Axes {
    Axes { x, y, z, a, b, c, ..Axes::ZERO }
}

/// A machine: `k` = 0 for A, 1 for B. Every offset, length, radius and
/// reference point differs between the two and between the axes.
fn machine(k: usize) -> Settings {
    let s = if k == 0 { 1.0 } else { -1.0 };
    let mut work_offsets = [Axes::ZERO; 6];
    for (i, w) in work_offsets.iter_mut().enumerate() {
        let i = i as f64;
        *w = if k == 0 {
            at(-312.345 - 41.0 * i, -157.25 + 23.5 * i, -405.125 - 7.75 * i, 0.0, 0.0, 0.0)
        } else {
            at(148.765 + 37.0 * i, 263.5 - 19.25 * i, -268.875 - 11.5 * i, 0.0, 0.0, 0.0)
        };
    }
    let tool_lengths: BTreeMap<u32, f64> =
        (1..=99).map(|h| (h, if k == 0 { 101.25 + 1.375 * h as f64 } else { 63.5 + 2.125 * h as f64 })).collect();
    let tool_radii: BTreeMap<u32, f64> =
        (1..=99).map(|d| (d, if k == 0 { 0.5 + 0.0125 * d as f64 } else { 0.75 + 0.015 * d as f64 })).collect();
    let mut settings = Settings {
        tool_lengths,
        tool_radii,
        work_offsets,
        home: at(-510.25 * s + 3.0, -402.75 * s - 7.0, -5.5 + 40.0 * k as f64, 0.0, 0.0, 0.0),
        ..Settings::default()
    };
    for (p, r) in settings.coords.reference_points.iter_mut().enumerate() {
        let p = p as f64 + 1.0;
        *r = at(-100.0 * p * s + 1.5, 50.0 * p * s - 2.5, -20.0 * p - 30.0 * k as f64, 0.0, 0.0, 0.0);
    }
    settings
}

/// The line of the G10 variant: machine coordinates of G54's zero.
const G10: &str = "G10 L2 P1 X-123.456 Y78.9 Z-321.5";

/// The program with [`G10`] after its first line: the first line after a
/// leading `%` (a G10 before the `O` line would be a program of its own).
fn with_g10(text: &str) -> String {
    let mut at = 0;
    loop {
        let end = text[at..].find('\n').map_or(text.len(), |e| at + e);
        let line = text[at..end].trim();
        if (line.is_empty() || line == "%") && end < text.len() {
            at = end + 1;
            continue;
        }
        return if end < text.len() {
            format!("{}\n{G10}\n{}", &text[..end], &text[end + 1..])
        } else {
            format!("{text}\n{G10}\n")
        };
    }
}

/// Parses and runs `text`; `Err` with the first error when it does not run
/// to its end.
fn run(name: &str, text: &str, library: &mut dyn Library, settings: &Settings) -> Result<Outcome, String> {
    let mut sources = Sources::default();
    let file = sources.add(SourceFile::new(name, text));
    let mut program = Program::default();
    let parsed = parse(&mut program, file, text);
    if let Some(d) = parsed.iter().find(|d| d.is_error()) {
        return Err(d.headline(&sources));
    }
    if program.units.is_empty() {
        return Err("no program".into());
    }
    let outcome = interp::run(&mut program, &mut sources, 0, library, settings);
    if let Some(d) = outcome.diagnostics.iter().find(|d| d.is_error()) {
        return Err(d.headline(&sources));
    }
    if !outcome.completed {
        return Err("the run did not complete".into());
    }
    Ok(outcome)
}

/// Settings to read back a program written in `dialect` on `machine`:
/// LinuxCNC reads `X10` as 10 mm and applies its own compensation rules.
fn read_back(dialect: Dialect, machine: &Settings) -> Settings {
    match dialect {
        Dialect::LinuxCnc => {
            Settings { integer_input: IntegerInput::Units, comp_rules: Rules::LinuxCnc, ..machine.clone() }
        }
        _ => Settings { integer_input: IntegerInput::Increments, comp_rules: Rules::default(), ..machine.clone() },
    }
}

fn kind_name(kind: &MoveKind) -> String {
    match kind {
        MoveKind::Arc(a) => format!("{} arc in {:?}", if a.ccw { "ccw" } else { "cw" }, a.plane),
        other => format!("{other:?}"),
    }
}

/// The moves that move: a straight move whose end is its start (within
/// half a unit of the last decimal written) is left out, as the writer
/// leaves it out (`G01 Z10.` where the tool is at Z10 already, `G43 H1 Z50.`
/// where the tip stays at Z50).
fn motions(toolpath: &Toolpath) -> Vec<&kezuri_geom::Move> {
    toolpath
        .moves
        .iter()
        .filter(|m| {
            let still = {
                let (s, e) = (m.start.to_array(), m.end.to_array());
                (0..6).all(|i| (s[i] - e[i]).abs() < 5e-4)
            };
            !(still && matches!(m.kind, MoveKind::Rapid | MoveKind::Feed | MoveKind::Probe))
        })
        .collect()
}

/// The first difference between `want` (the source on B) and `got` (the
/// written program on B), if any.
fn first_difference(want: &Toolpath, got: &Toolpath) -> Option<String> {
    let (w, g) = (motions(want), motions(got));
    let (w, g) = (&w, &g);
    for (k, (a, b)) in w.iter().zip(g).enumerate() {
        let (a, b) = (*a, *b);
        let same_kind = match (&a.kind, &b.kind) {
            (MoveKind::Arc(x), MoveKind::Arc(y)) => x.ccw == y.ccw && x.plane == y.plane,
            // Written in milliseconds (Fanuc) or 3 decimals of a second.
            (MoveKind::Dwell(x), MoveKind::Dwell(y)) => (x - y).abs() <= 5e-4 + 1e-9,
            (x, y) => std::mem::discriminant(x) == std::mem::discriminant(y),
        };
        let where_ =
            |m: &kezuri_geom::Move| format!("line {} {} to {:?}", m.line, kind_name(&m.kind), m.end.to_array());
        if !same_kind {
            return Some(format!("move {k}: kind {} vs written {}", where_(a), where_(b)));
        }
        let (ae, be) = (a.end.to_array(), b.end.to_array());
        if let Some(i) = (0..6).find(|&i| (ae[i] - be[i]).abs() > TOLERANCE) {
            return Some(format!(
                "move {k}: axis {} {} vs {} ({}; written {})",
                "XYZABC".as_bytes()[i] as char,
                ae[i],
                be[i],
                where_(a),
                where_(b)
            ));
        }
        if let (MoveKind::Arc(x), MoveKind::Arc(y)) = (&a.kind, &b.kind) {
            if (0..3).any(|i| (x.center[i] - y.center[i]).abs() > TOLERANCE) {
                return Some(format!("move {k}: arc centre {:?} vs {:?} ({})", x.center, y.center, where_(a)));
            }
        }
        let (fa, fb) = (want.frame(a), got.frame(b));
        if fa.work != fb.work
            || fa.length.map(|l| (l.register, l.negative)) != fb.length.map(|l| (l.register, l.negative))
        {
            return Some(format!(
                "move {k}: frame G{} H{:?} vs written G{} H{:?} ({})",
                54 + fa.work,
                fa.length.map(|l| l.register),
                54 + fb.work,
                fb.length.map(|l| l.register),
                where_(a)
            ));
        }
    }
    if w.len() != g.len() {
        let extra = if w.len() > g.len() { w[g.len()] } else { g[w.len()] };
        return Some(format!(
            "{} moves vs written {} (first unmatched: line {} {} to {:?})",
            w.len(),
            g.len(),
            extra.line,
            kind_name(&extra.kind),
            extra.end.to_array()
        ));
    }
    None
}

/// What became of one case.
enum Result_ {
    Same,
    Differs(String),
}

#[test]
fn programs_expanded_on_one_machine_run_the_same_on_another() {
    let (a, b) = (machine(0), machine(1));
    let cases = corpus();
    let mut skipped = Vec::new();
    let mut compared = 0usize;
    let mut programs_compared = std::collections::BTreeSet::new();
    let mut results: Vec<(String, Result_)> = Vec::new();
    let mut comp_cases = 0usize;
    for case in &cases {
        for (variant, text) in [("as given", case.text.clone()), ("with G10", with_g10(&case.text))] {
            let mut library = Folder(case.library.clone());
            let on_a = match run(&case.name, &text, &mut library, &case.settings(&a)) {
                Ok(o) => o,
                Err(e) => {
                    skipped.push(format!("{} ({variant}): does not run on machine A: {e}", case.name));
                    continue;
                }
            };
            let on_b = match run(&case.name, &text, &mut library, &case.settings(&b)) {
                Ok(o) => o,
                Err(e) => {
                    skipped.push(format!("{} ({variant}): does not run on machine B: {e}", case.name));
                    continue;
                }
            };
            // With cutter compensation the written program is compensated by
            // the control that reads it: the source on B is compared under
            // the same rules (Fanuc type A for the Fanuc dialect, LinuxCNC's
            // for LinuxCNC). Without, the rules change nothing.
            let reference = |dialect: Dialect| -> Result<Toolpath, String> {
                let rules = read_back(dialect, &b).comp_rules;
                if on_b.programmed.is_none() || rules == case.rules() {
                    return Ok(on_b.toolpath.clone());
                }
                let settings = Settings { comp_rules: rules, ..case.settings(&b) };
                run(&case.name, &text, &mut Folder(case.library.clone()), &settings).map(|o| o.toolpath)
            };
            compared += 1;
            programs_compared.insert(case.name.clone());
            if on_a.programmed.is_some() {
                comp_cases += 1;
            }
            // What `kezuri run --emit fanuc|linuxcnc` writes.
            let source = on_a.programmed.as_ref().unwrap_or(&on_a.toolpath);
            for dialect in [Dialect::Fanuc, Dialect::LinuxCnc] {
                let label = format!("{} {variant} {dialect:?}", case.name);
                let options = WriteOptions { dialect, title: Some(case.name.clone()), ..WriteOptions::default() };
                let written = match program(source, &options) {
                    Ok(w) => w,
                    Err(e) => {
                        results.push((label, Result_::Differs(format!("not written: {e:?}"))));
                        continue;
                    }
                };
                let result = match (
                    reference(dialect),
                    run("written.nc", &written, &mut interp::NoLibrary, &read_back(dialect, &b)),
                ) {
                    (Err(e), _) => {
                        Result_::Differs(format!("the source does not run on B under {dialect:?} rules: {e}"))
                    }
                    (_, Err(e)) => Result_::Differs(format!("the written program does not run on B: {e}")),
                    (Ok(want), Ok(got)) => match first_difference(&want, &got.toolpath) {
                        None => Result_::Same,
                        Some(d) => Result_::Differs(d),
                    },
                };
                if let (Result_::Differs(_), Some(dir)) = (&result, std::env::var_os("PORTABLE_DUMP")) {
                    let stem = label.replace(['/', ' '], "_");
                    std::fs::write(Path::new(&dir).join(format!("{stem}.written")), &written).unwrap();
                }
                results.push((label, result));
            }
        }
    }
    for s in &skipped {
        eprintln!("skipped: {s}");
    }
    let mut unexpected = Vec::new();
    let mut known_seen = vec![false; KNOWN.len()];
    let mut same = 0;
    for (label, result) in &results {
        let known = KNOWN.iter().position(|(prefix, _)| label.starts_with(prefix));
        match result {
            Result_::Same => {
                same += 1;
                eprintln!("same:    {label}");
                if let Some(k) = known {
                    unexpected.push(format!("{label}: listed in KNOWN ({}) but now the same", KNOWN[k].1));
                }
            }
            Result_::Differs(d) => {
                eprintln!("DIFFERS: {label}: {d}");
                match known {
                    Some(k) => known_seen[k] = true,
                    None => unexpected.push(format!("{label}: {d}")),
                }
            }
        }
    }
    eprintln!(
        "{} programs found, {} (program, variant) pairs compared ({} programs, {} with cutter compensation), \
         {} skipped; {} written programs of {} the same on machine B",
        cases.len(),
        compared,
        programs_compared.len(),
        comp_cases,
        skipped.len(),
        same,
        results.len()
    );
    for (k, seen) in known_seen.iter().enumerate() {
        if !seen {
            unexpected.push(format!("{}: listed in KNOWN ({}) but no such case differs", KNOWN[k].0, KNOWN[k].1));
        }
    }
    assert!(compared >= AT_LEAST_COMPARED, "only {compared} pairs compared, at least {AT_LEAST_COMPARED} expected");
    assert!(unexpected.is_empty(), "{} cases:\n{}", unexpected.len(), unexpected.join("\n"));
}

/// A sink that keeps the pieces as they come, to join them after.
#[derive(Default)]
struct Pieces {
    whole: kezuri_geom::WholePath,
    count: usize,
    /// Pieces that came with their programmed contour (a stretch of cutter
    /// compensation done with).
    compensated: usize,
}

impl kezuri_geom::PathSink for Pieces {
    fn take(&mut self, piece: &Toolpath, programmed: Option<&Toolpath>) {
        self.count += 1;
        self.compensated += usize::from(programmed.is_some());
        self.whole.take(piece, programmed);
    }
}

#[test]
fn a_run_handed_on_in_pieces_is_the_whole_run() {
    // Every program of the corpus (those that stop with an error too), run
    // whole and read in pages of 3 lines, 2 held at once (the others
    // dropped and read again from the text where the run comes back to
    // them), the path handed on a piece wherever it may be cut (pieces of
    // one move): the pieces joined are the whole path, move for move and
    // block for block, with the same diagnostics.
    let a = machine(0);
    let (mut programs, mut cut, mut read_again, mut compensated) = (0, 0, 0, 0);
    for case in corpus() {
        let mut sources = Sources::default();
        let file = sources.add(SourceFile::new(case.name.as_str(), case.text.as_str()));
        let mut whole_program = Program::default();
        let parsed = parse(&mut whole_program, file, &case.text);
        if parsed.iter().any(|d| d.is_error()) || whole_program.units.is_empty() {
            continue;
        }
        let mut program = Program::default();
        program.read_in_pages(3, 2);
        let paged = parse(&mut program, file, &case.text);
        assert_eq!(format!("{paged:?}"), format!("{parsed:?}"), "{}", case.name);
        let settings = Settings { piece_moves: 1, ..case.settings(&a) };
        let whole =
            interp::run(&mut whole_program, &mut sources.clone(), 0, &mut Folder(case.library.clone()), &settings);
        let mut pieces = Pieces::default();
        let handed =
            interp::run_into(&mut program, &mut sources, 0, &mut Folder(case.library.clone()), &settings, &mut pieces);
        assert!(handed.toolpath.moves.is_empty() && handed.programmed.is_none(), "{}", case.name);
        assert_eq!(pieces.whole.path, whole.toolpath, "{}", case.name);
        assert_eq!(pieces.whole.programmed, whole.programmed, "{}", case.name);
        assert_eq!(format!("{:?}", handed.diagnostics), format!("{:?}", whole.diagnostics), "{}", case.name);
        assert_eq!((handed.completed, handed.statements), (whole.completed, whole.statements), "{}", case.name);
        programs += 1;
        cut += usize::from(pieces.count > 2);
        read_again += usize::from(program.pages_read_again() > 0);
        // A stretch of compensation handed on before the run's end.
        compensated += usize::from(pieces.compensated > usize::from(whole.programmed.is_some()));
    }
    // Pinned, so that the test cannot pass by comparing nothing, cutting
    // nothing or reading nothing again.
    println!("{programs} programs, {cut} cut in pieces, {read_again} with pages read again, {compensated} with compensation handed on early");
    assert!(
        programs >= 116 && cut >= 90 && read_again >= 76 && compensated >= 1,
        "{programs} programs, {cut} cut, {read_again} read again, {compensated} compensated early"
    );
}

/// A writer fed the pieces of a run as they come: its text so far, or the
/// first error.
struct Fed<W> {
    writer: W,
    text: Result<String, String>,
}

impl<W> Fed<W> {
    fn new(writer: W) -> Fed<W> {
        Fed { writer, text: Ok(String::new()) }
    }

    fn add(&mut self, piece: Result<String, kezuri_nc::Error>) {
        match (&mut self.text, piece) {
            (Ok(text), Ok(more)) => text.push_str(&more),
            (Ok(_), Err(e)) => self.text = Err(e.to_string()),
            (Err(_), _) => {}
        }
    }
}

/// The G-code writers (one per post) and the CSV writer, fed a run's
/// pieces.
struct Streamed {
    programs: Vec<Fed<ProgramWriter>>,
    csv: Fed<CsvWriter>,
    pieces: usize,
}

impl kezuri_geom::PathSink for Streamed {
    fn take(&mut self, piece: &Toolpath, programmed: Option<&Toolpath>) {
        self.pieces += 1;
        for fed in &mut self.programs {
            if fed.text.is_ok() {
                let text = fed.writer.piece(piece, programmed);
                fed.add(text);
            }
        }
        if self.csv.text.is_ok() {
            let text = self.csv.writer.piece(piece);
            self.csv.add(text);
        }
    }
}

/// The posts `kezuri run` writes a program read with (no start, tool
/// changes or end of their own), and two more: haas's as it writes a
/// program kezuri makes (pre-staging the next tool), and fanuc's
/// incremental with block numbers.
fn streaming_posts() -> Vec<(String, WriteOptions)> {
    let mut posts: Vec<(String, WriteOptions)> = ["fanuc", "haas", "linuxcnc", "grbl"]
        .iter()
        .map(|&name| {
            let o = WriteOptions { title: Some("STREAMED".into()), ..WriteOptions::preset(name).unwrap() };
            (name.to_string(), WriteOptions { setup: None, ..o })
        })
        .collect();
    posts.push(("haas made".into(), WriteOptions::preset("haas").unwrap()));
    let fanuc = WriteOptions::preset("fanuc").unwrap();
    let incremental = WriteOptions { setup: None, incremental: true, line_numbers: Some(10), ..fanuc };
    posts.push(("fanuc incremental".into(), incremental));
    posts
}

/// The tools `path` loads, in order.
fn tool_order(path: &Toolpath) -> Vec<u32> {
    let mut tools: Vec<u32> = Vec::new();
    for m in path.moves.iter().filter(|m| m.tool != 0) {
        if tools.last() != Some(&m.tool) {
            tools.push(m.tool);
        }
    }
    tools
}

#[test]
fn the_writers_fed_a_run_in_pieces_write_the_whole_program() {
    // Every program of the corpus, in the dialect its text and name say,
    // run whole and handed on in pieces of one move: each post's writer
    // fed the pieces writes the text `program` writes of the whole path
    // (the programmed contour where there is one), or the same error; the
    // CSV writer, its columns chosen before the run, the text `csv` writes.
    let a = machine(0);
    let posts = streaming_posts();
    let (mut compared, mut cut, mut errors) = (0, 0, 0);
    let mut differ = Vec::new();
    for case in corpus() {
        let dialect = kezuri_nc::detect(None, &case.name, &case.text).map_or(kezuri_nc::Dialect::Fanuc, |d| d.dialect);
        let mut sources = Sources::default();
        let file = sources.add(SourceFile::new(case.name.as_str(), case.text.as_str()));
        let mut parsed_program = Program::default();
        let parsed = kezuri_nc::parse_as(&mut parsed_program, file, &case.text, dialect);
        if parsed.iter().any(|d| d.is_error()) || parsed_program.units.is_empty() {
            continue;
        }
        let settings = Settings { piece_moves: 1, dialect, ..case.settings(&a) };
        let whole = interp::run(
            &mut parsed_program.clone(),
            &mut sources.clone(),
            0,
            &mut Folder(case.library.clone()),
            &settings,
        );
        let written = whole.programmed.as_ref().unwrap_or(&whole.toolpath);
        let mut streamed = Streamed {
            programs: posts
                .iter()
                .map(|(_, o)| {
                    let writer = ProgramWriter::new(o).unwrap().with_tool_order(tool_order(written));
                    Fed::new(writer)
                })
                .collect(),
            csv: Fed::new(CsvWriter::new(may_move_uvw(&parsed_program, dialect))),
            pieces: 0,
        };
        interp::run_into(
            &mut parsed_program,
            &mut sources,
            0,
            &mut Folder(case.library.clone()),
            &settings,
            &mut streamed,
        );
        for ((name, o), fed) in posts.iter().zip(streamed.programs) {
            let text = fed.text.and_then(|t| fed.writer.finish().map(|end| t + &end).map_err(|e| e.to_string()));
            let expected = program(written, o).map_err(|e| e.to_string());
            errors += usize::from(expected.is_err());
            if text != expected {
                differ.push(format!("{} {dialect} {name}", case.name));
            }
            compared += 1;
        }
        let csv_text = streamed.csv.text.map(|t| t + &streamed.csv.writer.finish());
        if csv_text.as_deref() != Ok(csv(&whole.toolpath).as_str()) {
            differ.push(format!("{} {dialect} csv: {:?}", case.name, csv_text.err()));
        }
        cut += usize::from(streamed.pieces > 2);
    }
    assert!(differ.is_empty(), "{} differ:\n{}", differ.len(), differ.join("\n"));
    // Pinned, so that the test cannot pass by comparing nothing.
    assert!(compared >= 700 && cut >= 90 && errors >= 20, "{compared} compared, {cut} cut in pieces, {errors} errors");
}

#[test]
fn the_view_page_of_a_run_in_pieces_is_the_page_of_the_whole_run() {
    // Every program of the corpus, run whole and drawn on the page at once
    // (`fitted_page`, as `view --sim` draws it), and run again handed on in
    // pieces of one move to a `PathPage` (as `view` draws it), the program
    // text fed to it 7 bytes at a time: the same page to the byte, or the
    // same refusal, at the default budget and at budgets so small that the
    // path is simplified or the text left out.
    use kezuri_picture::view::{fitted_page, PathPage};
    use kezuri_picture::{Job, PageOptions};
    let a = machine(0);
    let dynamics = kezuri_geom::Dynamics::default();
    let (mut compared, mut simplified, mut left_out) = (0, 0, 0);
    for case in corpus() {
        let mut sources = Sources::default();
        let file = sources.add(SourceFile::new(case.name.as_str(), case.text.as_str()));
        let mut program = Program::default();
        let parsed = parse(&mut program, file, &case.text);
        if parsed.iter().any(|d| d.is_error()) || program.units.is_empty() {
            continue;
        }
        let settings = Settings { piece_moves: 1, ..case.settings(&a) };
        let whole =
            interp::run(&mut program.clone(), &mut sources.clone(), 0, &mut Folder(case.library.clone()), &settings);
        for max_page_mb in [32.0, 0.13, 0.1, 0.095] {
            let options = PageOptions { max_page_mb, ..PageOptions::default() };
            let job = Job {
                title: &case.name,
                path: &whole.toolpath,
                text: Some(&case.text),
                inch: whole.inch,
                dynamics: &dynamics,
                shapes: Vec::new(),
                any: None,
            };
            let at_once = fitted_page(&job, None, &options);
            let mut page = PathPage::new(&dynamics, &options, Vec::new());
            interp::run_into(
                &mut program.clone(),
                &mut sources.clone(),
                0,
                &mut Folder(case.library.clone()),
                &settings,
                &mut page,
            );
            let empty = Toolpath::default();
            let bytes = case.text.as_bytes();
            let mut text = |take: &mut dyn FnMut(&[u8]) -> bool| {
                for piece in bytes.chunks(7) {
                    if !take(piece) {
                        break;
                    }
                }
            };
            let in_pieces = page.finish(&Job { path: &empty, text: None, ..job }, None, Some(&mut text));
            match (&at_once, &in_pieces) {
                (Ok(a), Ok(b)) => {
                    assert!(a.html == b.html, "{} at {max_page_mb} MB: the pages differ", case.name);
                    assert_eq!(a.fitted, b.fitted, "{}", case.name);
                    simplified += usize::from(a.fitted.iter().any(|f| f.starts_with("simplified")));
                    left_out += usize::from(a.fitted.iter().any(|f| f.contains("text is left out")));
                }
                (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "{}", case.name),
                _ => panic!("{} at {max_page_mb} MB: one page made, the other refused", case.name),
            }
            compared += 1;
        }
    }
    println!("{compared} pages compared, {simplified} simplified, {left_out} without their text");
    assert!(
        compared >= 400 && simplified >= 10 && left_out >= 10,
        "{compared} compared, {simplified} simplified, {left_out} left out"
    );
}
