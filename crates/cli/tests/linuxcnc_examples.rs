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
//! -- --nocapture` prints the table.

mod common;

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::fs::File;
use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

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

/// How long one interpreter may take on one file.
const LIMIT: Duration = Duration::from_secs(20);

// ---------------------------------------------------------------- rs274

/// Whether rs274 is here; when it is not, whether the test must fail
/// (`KEZURI_REQUIRE_RS274`, set by CI) or skip. As tests/post.rs does.
fn rs274_here() -> bool {
    if Command::new("rs274").arg("-h").stdin(Stdio::null()).output().is_err() {
        assert!(std::env::var_os("KEZURI_REQUIRE_RS274").is_none(), "rs274 is required and missing");
        eprintln!("rs274 (LinuxCNC's interpreter, Debian package linuxcnc-uspace) is not here: skipped");
        return false;
    }
    true
}

/// What a command did: exit status (`None`: stopped at [`LIMIT`]), its
/// standard output and error.
struct Done {
    status: Option<i32>,
    stdout: String,
    stderr: String,
}

/// Runs `cmd` in `dir` with standard input closed, stopping it after
/// [`LIMIT`]; its output goes through files in `scratch` (named `tag`).
fn run_limited(mut cmd: Command, dir: &Path, scratch: &Path, tag: &str) -> Done {
    let (out, err) = (scratch.join(format!("{tag}.stdout")), scratch.join(format!("{tag}.stderr")));
    cmd.current_dir(dir).stdin(Stdio::null()).stdout(File::create(&out).unwrap()).stderr(File::create(&err).unwrap());
    let mut child = cmd.spawn().expect("the command starts");
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break Some(s.code().unwrap_or_else(|| 128 + s.signal().unwrap_or(0)));
        }
        if start.elapsed() > LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let read = |p: &Path| String::from_utf8_lossy(&std::fs::read(p).unwrap_or_default()).into_owned();
    Done { status, stdout: read(&out), stderr: read(&err) }
}

/// What kind of motion a move is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Rapid,
    Feed,
    Cw,
    Ccw,
    Probe,
}

/// One end point: machine coordinates of the tool tip in mm (degrees for
/// A, B, C), as kezuri's CSV gives them.
#[derive(Clone, Debug)]
struct Motion {
    kind: Kind,
    end: [f64; 6],
    /// How far this end point may be from the other's: 1e-3 mm plus half
    /// the step of the printed numbers it was reckoned from.
    tol: f64,
    /// Where it came from, for the report.
    at: String,
}

/// rs274's output: the motions, and whether it ran to the end.
struct Canon {
    motions: Vec<Motion>,
    /// The first probing move or spline (from a subroutine in another file,
    /// where the program's own words do not show it).
    probe_or_spline: Option<Class>,
    /// The error rs274 stopped with (the first line of its report).
    error: Option<String>,
}

/// The arguments of a canonical call `NAME(a, b, …)` as numbers.
fn numbers(args: &str) -> Vec<f64> {
    args.split(',').filter_map(|a| a.trim().parse().ok()).collect()
}

/// Reads rs274's canonical calls: lengths are printed in the units of the
/// last USE_LENGTH_UNITS with 4 decimals, in program coordinates; the work
/// offset (SET_G5X_OFFSET), G92 offset and XY rotation are printed apart and
/// applied here as LinuxCNC's canon does (G92, then the rotation, then G5x)
/// to get the machine coordinates kezuri writes.
fn read_canon(text: &str) -> Vec<Motion> {
    let mut unit = 1.0; // mm per printed unit
    let mut plane = "XY";
    let (mut g5x, mut g92, mut rotation) = ([0.0; 6], [0.0; 6], 0.0f64);
    let mut motions = Vec::new();
    for line in text.lines() {
        // "   28 N..... STRAIGHT_FEED(-100.0000, 0.0000, …)"
        let mut parts = line.trim_start().splitn(3, ' ');
        let (Some(seq), Some(_n), Some(call)) = (parts.next(), parts.next(), parts.next()) else { continue };
        let call = call.trim();
        let Some((name, args)) = call.split_once('(') else { continue };
        let args = args.strip_suffix(')').unwrap_or(args);
        let v = numbers(args);
        let linear = |v: f64| v * unit;
        let half = 0.00005 * unit;
        match name {
            "USE_LENGTH_UNITS" => unit = if args.contains("INCH") { 25.4 } else { 1.0 },
            "SELECT_PLANE" => {
                plane = if args.contains("YZ") {
                    "YZ"
                } else if args.contains("XZ") {
                    "XZ"
                } else {
                    "XY"
                }
            }
            "SET_G5X_OFFSET" if v.len() >= 7 => {
                g5x = std::array::from_fn(|k| if k < 3 { linear(v[k + 1]) } else { v[k + 1] });
            }
            "SET_G92_OFFSET" if v.len() >= 6 => {
                g92 = std::array::from_fn(|k| if k < 3 { linear(v[k]) } else { v[k] });
            }
            "SET_XY_ROTATION" if !v.is_empty() => rotation = v[0],
            "STRAIGHT_TRAVERSE" | "STRAIGHT_FEED" | "STRAIGHT_PROBE" | "ARC_FEED" => {
                let (kind, p) = if name == "ARC_FEED" {
                    // (first end, second end, first centre, second centre,
                    // rotation, axis end, a, b, c); XZ's first axis is Z.
                    let (e1, e2, turn, axis) = (v[0], v[1], v[4], v[5]);
                    let xyz = match plane {
                        "YZ" => [axis, e1, e2],
                        "XZ" => [e2, axis, e1],
                        _ => [e1, e2, axis],
                    };
                    let kind = if turn > 0.0 { Kind::Ccw } else { Kind::Cw };
                    (kind, [xyz[0], xyz[1], xyz[2], v[6], v[7], v[8]])
                } else {
                    let kind = match name {
                        "STRAIGHT_TRAVERSE" => Kind::Rapid,
                        "STRAIGHT_FEED" => Kind::Feed,
                        _ => Kind::Probe,
                    };
                    (kind, [v[0], v[1], v[2], v[3], v[4], v[5]])
                };
                let mut q: [f64; 6] = std::array::from_fn(|k| if k < 3 { linear(p[k]) } else { p[k] } + g92[k]);
                let (s, c) = rotation.to_radians().sin_cos();
                (q[0], q[1]) = (q[0] * c - q[1] * s, q[0] * s + q[1] * c);
                let end: [f64; 6] = std::array::from_fn(|k| q[k] + g5x[k]);
                // Each printed offset adds its own rounding.
                let offsets = [g5x, g92].iter().filter(|o| o.iter().any(|v| *v != 0.0)).count();
                let tol = 1e-3 + half * (1 + offsets) as f64;
                motions.push(Motion { kind, end, tol, at: format!("canon {seq}: {call}") });
            }
            "RIGID_TAP" if v.len() >= 3 => {
                // G33.1: a feed to (x, y, z) and back to where it began.
                let back = motions.last().map_or([0.0; 6], |m: &Motion| m.end);
                let mut q: [f64; 6] = std::array::from_fn(|k| if k < 3 { linear(v[k]) + g92[k] } else { 0.0 });
                let (s, c) = rotation.to_radians().sin_cos();
                (q[0], q[1]) = (q[0] * c - q[1] * s, q[0] * s + q[1] * c);
                let end: [f64; 6] = std::array::from_fn(|k| if k < 3 { q[k] + g5x[k] } else { back[k] });
                let offsets = [g5x, g92].iter().filter(|o| o.iter().any(|v| *v != 0.0)).count();
                let tol = 1e-3 + half * (1 + offsets) as f64;
                motions.push(Motion { kind: Kind::Feed, end, tol, at: format!("canon {seq}: {call}") });
                motions.push(Motion { kind: Kind::Feed, end: back, tol, at: format!("canon {seq}: {call}, back") });
            }
            _ => {}
        }
    }
    motions
}

/// Runs rs274 on `file` from `dir`, the canonical calls written into
/// `scratch`.
fn rs274(file: &Path, dir: &Path, table: &Path, scratch: &Path) -> Canon {
    let canon = scratch.join("rs274.canon");
    let _ = std::fs::remove_file(&canon);
    let mut cmd = Command::new("rs274");
    // rs274 shares its tool table through $HOME/.tool.mmap, truncated by
    // each run: two at once (these workers, another test, another user)
    // die of SIGBUS. Each run gets its own HOME.
    cmd.env("HOME", scratch);
    cmd.arg("-g").arg("-t").arg(table).arg(file).arg(&canon);
    let done = run_limited(cmd, dir, scratch, "rs274");
    let text = String::from_utf8_lossy(&std::fs::read(&canon).unwrap_or_default()).into_owned();
    let error = match done.status {
        None => Some(format!("rs274 ran past {} s", LIMIT.as_secs())),
        Some(0) => None,
        Some(code) => {
            let said = done
                .stdout
                .lines()
                .chain(done.stderr.lines())
                .map(str::trim)
                .find(|l| !l.is_empty() && *l != "executing");
            Some(said.map_or_else(|| format!("exit status {code}"), str::to_string))
        }
    };
    let probe_or_spline = text.lines().find_map(|l| {
        if l.contains("STRAIGHT_PROBE(") {
            Some(Class::Probing("rs274 makes a STRAIGHT_PROBE".into()))
        } else if l.contains("NURBS_FEED(") {
            Some(Class::Splines("rs274 makes a NURBS_FEED".into()))
        } else {
            None
        }
    });
    Canon { motions: read_canon(&text), probe_or_spline, error }
}

// ---------------------------------------------------------------- kezuri

/// Reads kezuri's CSV (`line,kind,x,y,z,a,b,c,feed`).
fn read_csv(text: &str) -> Vec<Motion> {
    text.lines()
        .skip(1)
        .filter_map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let kind = match *f.get(1)? {
                "rapid" => Kind::Rapid,
                "feed" => Kind::Feed,
                "cw" => Kind::Cw,
                "ccw" => Kind::Ccw,
                _ => Kind::Probe,
            };
            let end = std::array::from_fn(|k| f[2 + k].parse().unwrap());
            Some(Motion { kind, end, tol: 0.0, at: format!("line {}: {l}", f[0]) })
        })
        .collect()
}

/// Runs kezuri on a LinuxCNC program `file` from `dir` (its `--lib`), the
/// tool table imported by `machine`: its motions, or the error it stopped
/// with.
fn kezuri_linuxcnc(file: &Path, dir: &Path, machine: &Path, scratch: &Path) -> Result<Vec<Motion>, String> {
    let csv = scratch.join("kezuri.csv");
    let _ = std::fs::remove_file(&csv);
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_kezuri"));
    cmd.arg("run").arg(file).args(["--dialect", "linuxcnc"]);
    cmd.arg("--lib").arg(dir).arg("--machine").arg(machine).args(["--emit", "csv", "-o"]).arg(&csv);
    kezuri_done(run_limited(cmd, dir, scratch, "kezuri"), &csv)
}

/// kezuri's motions from the CSV it wrote, or its first error.
fn kezuri_done(done: Done, csv: &Path) -> Result<Vec<Motion>, String> {
    match done.status {
        None => Err(format!("kezuri ran past {} s", LIMIT.as_secs())),
        Some(0) => Ok(read_csv(&std::fs::read_to_string(csv).unwrap_or_default())),
        Some(_) => {
            let first = done.stderr.lines().find(|l| l.contains("error")).or_else(|| done.stderr.lines().next());
            Err(first.unwrap_or("failed").trim().to_string())
        }
    }
}

// ---------------------------------------------------------------- comparison

/// Whether `m` goes nowhere from `from`: a straight move to where the tool
/// is (rs274 and kezuri make such moves in different places: G28's
/// intermediate point, a block that names an axis without moving it). An arc
/// to its start is a full circle and stays.
fn stays(m: &Motion, from: &[f64; 6]) -> bool {
    matches!(m.kind, Kind::Rapid | Kind::Feed) && (0..6).all(|k| (m.end[k] - from[k]).abs() <= 1e-9 + m.tol.max(1e-6))
}

/// The motions without those that stay where the last one ended; the
/// start is the machine's zero, where both interpreters start.
fn moving(motions: Vec<Motion>) -> Vec<Motion> {
    let mut at = [0.0; 6];
    let mut out = Vec::with_capacity(motions.len());
    for m in motions {
        if !stays(&m, &at) {
            at = m.end;
            out.push(m);
        }
    }
    out
}

/// The first place where kezuri's motions (`ours`) and rs274's (`theirs`)
/// part, with how many of them differ: `None` when they agree.
fn first_difference(ours: &[Motion], theirs: &[Motion]) -> Option<String> {
    let (ours, theirs) = (moving(ours.to_vec()), moving(theirs.to_vec()));
    let mut first = None;
    let mut differing = 0;
    for (i, (o, t)) in ours.iter().zip(&theirs).enumerate() {
        let far = (0..6).map(|k| (o.end[k] - t.end[k]).abs()).fold(0.0, f64::max);
        if o.kind != t.kind || far > t.tol {
            differing += 1;
            first.get_or_insert_with(|| {
                format!(
                    "motion {}: kezuri {:?} at {}\n      rs274 {:?} at {} (off by {far:.4} mm)",
                    i + 1,
                    o.kind,
                    o.at,
                    t.kind,
                    t.at
                )
            });
        }
    }
    let (n, m) = (ours.len(), theirs.len());
    let count = format!("{differing} of {} motions differ; kezuri makes {n}, rs274 {m}", n.min(m));
    if let Some(first) = first {
        return Some(format!("{first}\n      {count}"));
    }
    match n.cmp(&m) {
        std::cmp::Ordering::Equal => None,
        std::cmp::Ordering::Less => {
            Some(format!("motion {}: kezuri stops; rs274 goes on at {}\n      {count}", n + 1, theirs[n].at))
        }
        std::cmp::Ordering::Greater => {
            Some(format!("motion {}: rs274 stops; kezuri goes on at {}\n      {count}", m + 1, ours[m].at))
        }
    }
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

/// What a file is, with the reason.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Class {
    /// ngcgui's and plasmac's files, made for a user interface.
    Interface(String),
    Lathe(String),
    Probing(String),
    Splines(String),
    Hal(String),
    Remap(String),
    /// Only subroutines: a library, not a program.
    Library,
    Rs274Error(String),
    NoMotion,
    Mill,
}

impl Class {
    fn name(&self) -> &'static str {
        match self {
            Class::Interface(_) => "user interface",
            Class::Lathe(_) => "lathe",
            Class::Probing(_) => "probing",
            Class::Splines(_) => "splines",
            Class::Hal(_) => "HAL pins/IO",
            Class::Remap(_) => "remap/custom M",
            Class::Library => "subroutine library",
            Class::Rs274Error(_) => "rs274 error",
            Class::NoMotion => "no motion",
            Class::Mill => "mill program",
        }
    }

    fn reason(&self) -> String {
        match self {
            Class::Interface(r)
            | Class::Lathe(r)
            | Class::Probing(r)
            | Class::Splines(r)
            | Class::Hal(r)
            | Class::Remap(r)
            | Class::Rs274Error(r) => r.clone(),
            Class::Library => "only sub/endsub".into(),
            Class::NoMotion => "rs274 makes no motion; kezuri runs it".into(),
            Class::Mill => String::new(),
        }
    }
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
