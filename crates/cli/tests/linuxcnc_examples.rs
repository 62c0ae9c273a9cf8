//! kezuri against LinuxCNC's own interpreter (`rs274`, Debian package
//! `linuxcnc-uspace`) on the example programs LinuxCNC ships, read where the
//! package installed them (GPL: read at test time, never copied here).
//!
//! Each file is classed from its own words and from what rs274 made of it —
//! never from kezuri's result: lathe, probing, splines, HAL pins, remaps and
//! custom M-codes, subroutine libraries, user-interface files, rs274 errors
//! and programs without motion are listed with their reason; every other file
//! is a mill program, which kezuri runs (`run --emit csv`) and whose end
//! points must agree with rs274's canonical calls within 1e-3 mm plus half the
//! step rs274 prints. Disagreements known today are listed in
//! [`EXPECTED_FAILURES`] with their cause; one that agrees fails the test so
//! that the list stays true.
//!
//! Also between dialects: a Fanuc macro program written by `kezuri run --emit
//! linuxcnc` runs in rs274 to the motions kezuri makes of the original, and a
//! LinuxCNC O-word program written by `kezuri run --emit fanuc` runs in
//! kezuri's Fanuc mode to the motions rs274 makes of the original.
//!
//! Without rs274 the tests skip, saying so, unless `KEZURI_REQUIRE_RS274` is
//! set (CI), where they fail. `cargo test -p kezuri --test linuxcnc_examples
//! -- --nocapture` prints the table. Running the two interpreters, reading
//! their motions and comparing them is `rs274/mod.rs`.

mod common;
mod rs274;

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use rs274::{
    first_difference, kezuri_done, kezuri_linuxcnc, read_canon, read_csv, rs274, rs274_here, run_limited, Class, Kind,
    Motion,
};

/// Mill programs that disagree today, each with its cause. A file named here
/// that agrees, or that is no longer a mill program, fails the test.
const EXPECTED_FAILURES: &[(&str, &str)] = &[
    (
        "ncfiles/mmount.ngc",
        "rs274's standalone canon, as skeleton.ngc: `T1 M6 G43` (line 61), then G00 X0 Y0 without Z: kezuri's \
         tip is the tool's length (2.54 mm) lower, as LinuxCNC has it; every other motion agrees (G33.1, G81 \
         in G99) when kezuri is made to drop that offset as rs274 does",
    ),
    (
        "ncfiles/skeleton.ngc",
        "rs274's standalone canon, not LinuxCNC: `T1 M06 G43 H1` (line 10), then G0 X1 Y1 without Z: LinuxCNC \
         reads the position back after M6 with the tool offset taken off (emccanon's GET_EXTERNAL_POSITION), \
         so the tip's Z is the tool's length (2.54 mm) below where it was, as kezuri has it; rs274's canon \
         gives back its last move's end point (Z0), offset or not",
    ),
];

/// The tool table both interpreters get: rs274 reads it in inches (its
/// standalone canon has no INI file that says otherwise), kezuri imports it
/// with `units = "inch"`. Tool n: length 0.1·n in, diameter 0.05 + 0.01·n in;
/// T100 for the 5-axis demo.
fn tool_table() -> String {
    let mut t = String::new();
    for n in (1..=20).chain([100]) {
        let _ = writeln!(t, "T{n} P{n} Z{:.2} D{:.3}", 0.1 * f64::from(n), 0.05 + 0.01 * f64::from(n));
    }
    t
}

// ---------------------------------------------------------------- classes

/// The words a program uses, comments and names left out.
#[derive(Default)]
struct Words {
    g: BTreeSet<String>,
    m: BTreeSet<u32>,
    /// `#<_hal[…]>` parameters: HAL pins read by the program.
    hal: bool,
    /// Only `sub` … `endsub` (and `%`, M2/M30) outside comments.
    subs_only: bool,
}

/// Scans a program's text for its G and M words.
fn words(text: &str) -> Words {
    let mut w = Words::default();
    let (mut depth, mut subs, mut outside) = (0i32, 0, false);
    for raw in text.lines() {
        let lower = raw.to_ascii_lowercase();
        if lower.contains("_hal[") {
            w.hal = true;
        }
        // Comments: (…) and ; to the end of the line.
        let mut code = String::new();
        let mut in_paren = false;
        for c in lower.chars() {
            match c {
                '(' => in_paren = true,
                ')' if in_paren => in_paren = false,
                ';' if !in_paren => break,
                _ if !in_paren => code.push(c),
                _ => {}
            }
        }
        // Names: o<name>, #<name>.
        let mut plain = String::new();
        let mut in_name = false;
        for c in code.chars() {
            match c {
                '<' => in_name = true,
                '>' if in_name => in_name = false,
                _ if !in_name && !c.is_whitespace() => plain.push(c),
                _ => {}
            }
        }
        // The O-word's keyword.
        let keyword = plain
            .strip_prefix('o')
            .map(|r| r.trim_start_matches(|c: char| c.is_ascii_digit()))
            .map(|r| r.chars().take_while(char::is_ascii_alphabetic).collect::<String>());
        match keyword.as_deref() {
            Some("sub") => {
                depth += 1;
                subs += 1;
            }
            Some("endsub") => depth -= 1,
            _ if depth == 0 && !plain.is_empty() && !matches!(plain.as_str(), "%" | "m2" | "m02" | "m30") => {
                outside = true
            }
            _ => {}
        }
        let chars: Vec<char> = plain.chars().collect();
        let mut i = 0;
        while i < chars.len() {
            let c = chars[i];
            i += 1;
            if c != 'g' && c != 'm' {
                continue;
            }
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            let number: String = chars[start..i].iter().collect();
            let Ok(value) = number.parse::<f64>() else { continue };
            if c == 'g' {
                // G0 and G00, G5.1 and G05.1: the same code.
                w.g.insert(format!("{}", (value * 10.0).round() / 10.0));
            } else {
                w.m.insert(value as u32);
            }
        }
    }
    w.subs_only = subs > 0 && !outside;
    w
}

/// The first of `codes` the program uses, as `G…`.
fn uses_g(w: &Words, codes: &[&str]) -> Option<String> {
    codes.iter().find(|c| w.g.contains(**c)).map(|c| format!("G{c}"))
}

/// Classes a file from its path and words (before rs274 runs).
fn class_by_words(path: &str, w: &Words) -> Option<Class> {
    let lower = path.to_ascii_lowercase();
    for ui in ["/ngcgui", "/plasmac/"] {
        if lower.contains(ui) {
            return Some(Class::Interface(format!("path {ui}")));
        }
    }
    if lower.contains("lathe") {
        return Some(Class::Lathe("'lathe' in the path".into()));
    }
    // G7/G8 diameter/radius mode, G70–G72 turning cycles, G33 and G76
    // threading (G33.1, rigid tapping, is a mill's).
    if let Some(g) = uses_g(w, &["7", "8", "33", "70", "71", "71.1", "71.2", "72", "72.1", "72.2", "76"]) {
        return Some(Class::Lathe(g));
    }
    if let Some(g) = uses_g(w, &["38.2", "38.3", "38.4", "38.5"]) {
        return Some(Class::Probing(g));
    }
    if let Some(g) = uses_g(w, &["5", "5.1", "5.2", "5.3"]) {
        return Some(Class::Splines(g));
    }
    if w.hal {
        return Some(Class::Hal("#<_hal[…]> pin".into()));
    }
    if let Some(m) = w.m.iter().find(|m| (62..=68).contains(*m)) {
        return Some(Class::Hal(format!("M{m}")));
    }
    if let Some(m) = w.m.iter().find(|m| **m >= 100) {
        return Some(Class::Remap(format!("M{m}")));
    }
    if lower.contains("remap") || lower.contains("/nc_subroutines/") {
        return Some(Class::Remap("a remap's folder".into()));
    }
    if w.subs_only {
        return Some(Class::Library);
    }
    None
}

/// The path shown for a file: without the package's long prefixes.
fn short(path: &str) -> String {
    path.replace("/usr/share/doc/linuxcnc/examples/sample-configs/", "sample-configs/")
        .replace("/usr/share/linuxcnc/", "")
        .replace("/usr/share/", "")
}

/// The example programs of the package: `dpkg -L linuxcnc-uspace`.
fn examples() -> Vec<PathBuf> {
    let Ok(o) = Command::new("dpkg").args(["-L", "linuxcnc-uspace"]).stdin(Stdio::null()).output() else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = String::from_utf8_lossy(&o.stdout)
        .lines()
        .filter(|l| l.ends_with(".ngc") || l.ends_with(".nc"))
        .map(PathBuf::from)
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    files
}

/// One file's row of the table.
struct Row {
    file: String,
    class: Class,
    /// For a mill program: `None` when kezuri agrees, else what differs.
    difference: Option<String>,
}

fn examine(file: &Path, table: &Path, machine: &Path, scratch: &Path) -> Row {
    let name = file.to_string_lossy().into_owned();
    let text = String::from_utf8_lossy(&std::fs::read(file).unwrap_or_default()).into_owned();
    let dir = file.parent().unwrap();
    let class_row = |class| Row { file: short(&name), class, difference: None };
    if let Some(class) = class_by_words(&name, &words(&text)) {
        return class_row(class);
    }
    let canon = rs274(file, dir, table, scratch);
    if let Some(class) = canon.probe_or_spline {
        return class_row(class);
    }
    if let Some(e) = canon.error {
        return class_row(Class::Rs274Error(e));
    }
    if canon.motions.is_empty() {
        // rs274 runs it without moving (parameters, messages, subroutine
        // returns): kezuri must run it too.
        let difference = kezuri_linuxcnc(file, dir, machine, scratch).err().map(|e| format!("kezuri error: {e}"));
        return Row { file: short(&name), class: Class::NoMotion, difference };
    }
    let difference = match kezuri_linuxcnc(file, dir, machine, scratch) {
        Err(e) => Some(format!("kezuri error: {e}")),
        Ok(ours) => first_difference(&ours, &canon.motions),
    };
    Row { file: short(&name), class: Class::Mill, difference }
}

/// Every example, classed; each mill program compared.
#[test]
fn linuxcnc_examples_agree_with_rs274() {
    if !rs274_here() {
        return;
    }
    let files = examples();
    if files.is_empty() {
        assert!(
            std::env::var_os("KEZURI_REQUIRE_RS274").is_none(),
            "rs274 is required and `dpkg -L linuxcnc-uspace` lists no example programs"
        );
        eprintln!("rs274 is here but `dpkg -L linuxcnc-uspace` lists no example programs: skipped");
        return;
    }
    let started = Instant::now();
    let dir = tempfile::tempdir().unwrap();
    let table = dir.path().join("tool.tbl");
    std::fs::write(&table, tool_table()).unwrap();
    let machine = dir.path().join("machine.toml");
    std::fs::write(&machine, "[tools]\nimport = \"tool.tbl\"\nunits = \"inch\"\n").unwrap();

    // A few workers: rs274 and kezuri are single-threaded.
    let next = AtomicUsize::new(0);
    let workers = std::thread::available_parallelism().map_or(2, |n| n.get()).clamp(2, 4);
    let mut rows: Vec<(usize, Row)> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..workers)
            .map(|w| {
                let (next, files, table, machine) = (&next, &files, &table, &machine);
                let scratch = dir.path().join(format!("worker{w}"));
                std::fs::create_dir_all(&scratch).unwrap();
                s.spawn(move || {
                    let mut rows = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(file) = files.get(i) else { break };
                        rows.push((i, examine(file, table, machine, &scratch)));
                    }
                    rows
                })
            })
            .collect();
        handles.into_iter().flat_map(|h| h.join().unwrap()).collect()
    });
    rows.sort_by_key(|(i, _)| *i);
    let rows: Vec<Row> = rows.into_iter().map(|(_, r)| r).collect();

    // The table.
    let width = rows.iter().map(|r| r.file.len()).max().unwrap_or(10);
    println!("{:width$}  {:18}  verdict", "file", "class");
    let mut failures = Vec::new();
    let mut agree = 0;
    for r in &rows {
        let expected = EXPECTED_FAILURES.iter().find(|(f, _)| *f == r.file).map(|(_, cause)| *cause);
        let verdict = match (&r.class, &r.difference, expected) {
            (Class::Mill, None, None) => {
                agree += 1;
                "agrees".to_string()
            }
            (Class::Mill, None, Some(_)) => {
                failures.push(format!("{}: agrees now: take it out of EXPECTED_FAILURES", r.file));
                "AGREES (listed as an expected failure)".to_string()
            }
            (Class::Mill, Some(d), Some(cause)) => format!("differs (expected: {cause})\n      {d}"),
            (Class::Mill, Some(d), None) => {
                failures.push(format!("{}: {d}", r.file));
                format!("DIFFERS\n      {d}")
            }
            (Class::NoMotion, Some(d), Some(cause)) => format!("kezuri stops (expected: {cause})\n      {d}"),
            (Class::NoMotion, Some(d), None) => {
                failures.push(format!("{}: rs274 runs it, {d}", r.file));
                format!("KEZURI STOPS\n      {d}")
            }
            (c, _, Some(_)) => {
                failures.push(format!("{}: listed in EXPECTED_FAILURES but classed {}", r.file, c.name()));
                c.reason()
            }
            (c, _, None) => c.reason(),
        };
        println!("{:width$}  {:18}  {verdict}", r.file, r.class.name());
    }
    for (f, _) in EXPECTED_FAILURES {
        if !rows.iter().any(|r| r.file == *f) {
            failures.push(format!("{f}: listed in EXPECTED_FAILURES but not among the package's files"));
        }
    }

    // The counts.
    let mut classes: Vec<(&str, usize)> = Vec::new();
    for r in &rows {
        match classes.iter_mut().find(|(n, _)| *n == r.class.name()) {
            Some((_, count)) => *count += 1,
            None => classes.push((r.class.name(), 1)),
        }
    }
    classes.sort_by_key(|(n, count)| (std::cmp::Reverse(*count), *n));
    let mill = rows.iter().filter(|r| r.class == Class::Mill).count();
    let expected_to_agree = mill - EXPECTED_FAILURES.iter().filter(|(f, _)| rows.iter().any(|r| r.file == *f)).count();
    println!("\n{} files in {:.1} s:", rows.len(), started.elapsed().as_secs_f64());
    for (name, count) in &classes {
        println!("  {count:4}  {name}");
    }
    println!(
        "{agree} of {mill} mill programs agree with rs274 ({expected_to_agree} expected to; {} expected failures)",
        mill - expected_to_agree
    );
    assert!(
        failures.is_empty(),
        "{} of the {expected_to_agree} mill programs expected to agree with rs274 ({agree} agree):\n{}",
        failures.len(),
        failures.join("\n")
    );
}

// ---------------------------------------------------------------- between dialects

/// A Fanuc Custom Macro B program: a WHILE loop of G65 calls with
/// arguments, IF … GOTO, an M98 subprogram with a G81 cycle, arcs by I J and
/// by R, a G28 return through an incremental point.
const FANUC_MACRO: &str = "%
O1000 (MACRO PROGRAM: WHILE, IF GOTO, G65, M98)
G21 G17 G90 G40 G49 G80
T1 M06
G54 G00 X0. Y0.
G43 H1 Z10.
#100=0
#101=5.
WHILE[#100LT3]DO1
#102=#100*12.+10.
G65 P9010 X#102 Y5. R#101 Z-1.
#100=#100+1
END1
IF[#101GT4.]GOTO20
G00 X100.
N20 G00 Z50.
M98 P2000
G91 G28 Z0.
G90
M30
O9010 (CIRCLE: X Y CENTRE, R RADIUS, Z DEPTH)
G00 X[#24+#18] Y#25
G01 Z#26 F200.
G02 I-#18 J0.
G03 X#24 Y[#25+#18] R#18
G00 Z5.
M99
O2000
G81 X10. Y20. Z-3. R2. F100.
X20.
G80
M99
%
";

/// A LinuxCNC program of O-words: a named subroutine with positional
/// arguments and a local named parameter, while, if/else, repeat.
const LINUXCNC_OWORDS: &str = "(LinuxCNC O-words: sub/call, while, if/else, repeat, named parameters)
G21 G17 G90 G40 G49 G80 G54
o<square> sub
  #<side> = #1
  G0 X#2 Y#3
  G1 Z-1 F200
  G91 G1 X#<side>
  Y#<side>
  X[-#<side>]
  Y[-#<side>]
  G90 G0 Z5
o<square> endsub
#<i> = 0
o100 while [#<i> LT 3]
  o<square> call [10 + #<i> * 2] [#<i> * 20] [0]
  #<i> = [#<i> + 1]
o100 endwhile
o101 if [#<i> EQ 3]
  G0 X100 Y0
o101 else
  G0 X0 Y100
o101 endif
o102 repeat [2]
  G91 G1 X5 F100
o102 endrepeat
G90 G2 X115 Y5 R5
G0 Z20
M2
";

/// The scratch folder, tool table (T1 1 in, T21 3 in long, read by rs274
/// in inches) and the machine file importing it for kezuri.
fn between_dialects_setup() -> (tempfile::TempDir, PathBuf, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let table = dir.path().join("tool.tbl");
    std::fs::write(&table, "T1 P1 Z1.0 D0.25\nT2 P2 Z2.0 D0.25\nT21 P21 Z3.0 D0.25\n").unwrap();
    let machine = dir.path().join("machine.toml");
    std::fs::write(&machine, "[tools]\nimport = \"tool.tbl\"\nunits = \"inch\"\n").unwrap();
    (dir, table, machine)
}

/// kezuri's run of `args` (a program, its options) into the CSV `csv`.
fn kezuri_csv(args: &[&str], dir: &Path, csv: &Path) -> Result<Vec<Motion>, String> {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_kezuri"));
    cmd.arg("run").args(args).args(["--emit", "csv", "-o"]).arg(csv);
    kezuri_done(run_limited(cmd, dir, dir, "kezuri"), csv)
}

/// `kezuri run --emit linuxcnc` of a Fanuc macro program: rs274 runs the
/// program written to the motions kezuri makes of the original.
#[test]
fn fanuc_macro_programs_written_for_linuxcnc_move_the_same_in_rs274() {
    if !rs274_here() {
        return;
    }
    let (dir, table, machine) = between_dialects_setup();
    let d = dir.path();
    let samples = concat!(env!("CARGO_MANIFEST_DIR"), "/../../samples");
    let macro_nc = d.join("o1000-macro.nc");
    std::fs::write(&macro_nc, FANUC_MACRO).unwrap();
    // The sample of G66.1 modal macro calls, #3001/#4001/#5001, WHILE, and the
    // one of M98 … L105 in G91 (26 883 motions).
    let programs =
        [macro_nc, Path::new(samples).join("o7023-texture.nc"), Path::new(samples).join("o1011-digitize.nc")];
    for program in &programs {
        let name = program.file_name().unwrap().to_string_lossy().into_owned();
        let p = program.to_string_lossy();
        let m = machine.to_string_lossy();
        let args = vec![&*p, "--machine", &*m, "--dialect", "fanuc"];
        let ours = kezuri_csv(&args, d, &d.join(format!("{name}.csv"))).unwrap_or_else(|e| panic!("{name}: {e}"));
        let ngc = d.join(format!("{name}.ngc"));
        let mut write = vec!["run"];
        write.extend(&args);
        let n = ngc.to_string_lossy();
        write.extend(["--emit", "linuxcnc", "-o", &*n]);
        common::ok(&common::kezuri(&write));
        let canon = rs274(&ngc, d, &table, d);
        let written = std::fs::read_to_string(&ngc).unwrap();
        assert!(canon.error.is_none(), "{name}: rs274 stopped: {:?}\n{written}", canon.error);
        assert!(ours.len() > 10, "{name}: {} motions", ours.len());
        if let Some(d) = first_difference(&ours, &canon.motions) {
            panic!("{name}: kezuri's LinuxCNC program moves otherwise in rs274:\n      {d}");
        }
        println!("{name}: {} motions, the same in rs274", ours.len());
    }
}

/// `kezuri run --emit fanuc` of a LinuxCNC O-word program: kezuri's Fanuc
/// mode runs the program written to the motions rs274 makes of the
/// original.
#[test]
fn linuxcnc_oword_program_written_for_fanuc_moves_as_rs274_does() {
    if !rs274_here() {
        return;
    }
    let (dir, table, machine) = between_dialects_setup();
    let d = dir.path();
    let original = d.join("owords.ngc");
    std::fs::write(&original, LINUXCNC_OWORDS).unwrap();
    let canon = rs274(&original, d, &table, d);
    assert!(canon.error.is_none(), "rs274 stopped: {:?}", canon.error);
    assert!(canon.motions.len() > 20, "rs274 made {} motions", canon.motions.len());

    // Written for Fanuc, then read back as Fanuc.
    let trip = || -> Result<Vec<Motion>, String> {
        let fanuc = d.join("owords-fanuc.nc");
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_kezuri"));
        cmd.arg("run").arg(&original).args(["--dialect", "linuxcnc"]);
        cmd.arg("--machine").arg(&machine).args(["--emit", "fanuc", "-o"]).arg(&fanuc);
        let done = run_limited(cmd, d, d, "to-fanuc");
        if done.status != Some(0) {
            let said = done.stderr.lines().find(|l| l.contains("error")).unwrap_or("failed");
            return Err(format!("kezuri run --emit fanuc: {said}"));
        }
        let (f, m) = (fanuc.to_string_lossy(), machine.to_string_lossy());
        let args = vec![&*f, "--machine", &*m, "--dialect", "fanuc"];
        let ours = kezuri_csv(&args, d, &d.join("owords-fanuc.csv"))?;
        match first_difference(&ours, &canon.motions) {
            Some(diff) => Err(format!("the Fanuc program moves otherwise than rs274:\n      {diff}")),
            None => Ok(ours),
        }
    };
    match trip() {
        Ok(ours) => println!("{} motions, as rs274's", ours.len()),
        Err(e) => panic!("{e}"),
    }
}

/// The reading of rs274's calls and the comparison themselves, without rs274:
/// inches, a work offset, a G92 offset, the XZ plane's argument order, the
/// tolerance, zero-length moves.
#[test]
fn canonical_calls_are_read_and_compared() {
    let canon = "    1 N..... USE_LENGTH_UNITS(CANON_UNITS_INCHES)
    2 N..... SET_G5X_OFFSET(2, 1.0000, 0.0000, -1.0000, 0.0000, 0.0000, 0.0000)
    3 N..... STRAIGHT_TRAVERSE(1.0000, 2.0000, 0.5000, 0.0000, 0.0000, 0.0000)
    4 N..... STRAIGHT_TRAVERSE(1.0000, 2.0000, 0.5000, 0.0000, 0.0000, 0.0000)
    5 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)
    6 N..... SET_G92_OFFSET(0.0000, 10.0000, 0.0000, 0.0000, 0.0000, 0.0000)
    7 N..... SELECT_PLANE(CANON_PLANE_XZ)
    8 N..... ARC_FEED(-5.0000, 40.0000, -5.0000, 35.0000, -1, 7.0000, 0.0000, 0.0000, 90.0000)
";
    let theirs = read_canon(canon);
    assert_eq!(theirs.len(), 3);
    assert_eq!(theirs[0].kind, Kind::Rapid);
    let near = |a: [f64; 6], b: [f64; 6]| (0..6).all(|k| (a[k] - b[k]).abs() < 1e-9);
    assert!(near(theirs[0].end, [50.8, 50.8, -12.7, 0.0, 0.0, 0.0]), "{:?}", theirs[0].end);
    assert!((theirs[0].tol - (1e-3 + 2.0 * 0.00127)).abs() < 1e-12);
    // XZ: first Z, second X, then Y; a clockwise arc; G92 then G5x.
    assert_eq!(theirs[2].kind, Kind::Cw);
    assert!(near(theirs[2].end, [65.4, 17.0, -30.4, 0.0, 0.0, 90.0]), "{:?}", theirs[2].end);

    let csv = "line,kind,x,y,z,a,b,c,feed
3,rapid,50.8,50.8,-12.7,0,0,0,
9,cw,65.4,17,-30.4,0,0,90,100
";
    let ours = read_csv(csv);
    assert_eq!(first_difference(&ours, &theirs), None, "the repeated point is no motion");
    let off = read_csv(&csv.replace("65.4,", "65.405,"));
    assert!(first_difference(&off, &theirs).is_some_and(|d| d.contains("motion 2")));
    let ccw = read_csv(&csv.replace("cw,", "ccw,"));
    assert!(first_difference(&ccw, &theirs).is_some());
    let short = read_csv("line,kind,x,y,z,a,b,c,feed\n3,rapid,50.8,50.8,-12.7,0,0,0,\n");
    assert!(first_difference(&short, &theirs).is_some_and(|d| d.contains("kezuri stops")));
}
