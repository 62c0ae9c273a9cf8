//! kezuri beside LinuxCNC's own interpreter (`rs274`): each run with a time
//! limit, rs274's canonical calls and kezuri's CSV read as motions in
//! machine coordinates, the first place where the two part, and what a file
//! is to the comparison.

use std::fs::File;
use std::os::unix::process::ExitStatusExt;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// How long one interpreter may take on one file.
const LIMIT: Duration = Duration::from_secs(20);

// ---------------------------------------------------------------- rs274

/// Whether rs274 is here; when it is not, whether the test must fail
/// (`KEZURI_REQUIRE_RS274`, set by CI) or skip. As tests/post.rs does.
pub fn rs274_here() -> bool {
    if Command::new("rs274").arg("-h").stdin(Stdio::null()).output().is_err() {
        assert!(std::env::var_os("KEZURI_REQUIRE_RS274").is_none(), "rs274 is required and missing");
        eprintln!("rs274 (LinuxCNC's interpreter, Debian package linuxcnc-uspace) is not here: skipped");
        return false;
    }
    true
}

/// What a command did: exit status (`None`: stopped at [`LIMIT`]), its
/// standard output and error.
pub struct Done {
    pub status: Option<i32>,
    pub stdout: String,
    pub stderr: String,
}

/// Runs `cmd` in `dir` with standard input closed, stopping it after
/// [`LIMIT`]; its output goes through files in `scratch` (named `tag`).
pub fn run_limited(mut cmd: Command, dir: &Path, scratch: &Path, tag: &str) -> Done {
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
pub enum Kind {
    Rapid,
    Feed,
    Cw,
    Ccw,
    Probe,
}

/// One end point: machine coordinates of the tool tip in mm (degrees for
/// A, B, C), as kezuri's CSV gives them.
#[derive(Clone, Debug)]
pub struct Motion {
    pub kind: Kind,
    pub end: [f64; 6],
    /// How far this end point may be from the other's: 1e-3 mm plus half
    /// the step of the printed numbers it was reckoned from.
    pub tol: f64,
    /// Where it came from, for the report.
    pub at: String,
}

/// rs274's output: the motions, and whether it ran to the end.
pub struct Canon {
    pub motions: Vec<Motion>,
    /// The first probing move or spline (from a subroutine in another file,
    /// where the program's own words do not show it).
    pub probe_or_spline: Option<Class>,
    /// The error rs274 stopped with (the first line of its report).
    pub error: Option<String>,
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
pub fn read_canon(text: &str) -> Vec<Motion> {
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
pub fn rs274(file: &Path, dir: &Path, table: &Path, scratch: &Path) -> Canon {
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
pub fn read_csv(text: &str) -> Vec<Motion> {
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
pub fn kezuri_linuxcnc(file: &Path, dir: &Path, machine: &Path, scratch: &Path) -> Result<Vec<Motion>, String> {
    let csv = scratch.join("kezuri.csv");
    let _ = std::fs::remove_file(&csv);
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_kezuri"));
    cmd.arg("run").arg(file).args(["--dialect", "linuxcnc"]);
    cmd.arg("--lib").arg(dir).arg("--machine").arg(machine).args(["--emit", "csv", "-o"]).arg(&csv);
    kezuri_done(run_limited(cmd, dir, scratch, "kezuri"), &csv)
}

/// kezuri's motions from the CSV it wrote, or its first error.
pub fn kezuri_done(done: Done, csv: &Path) -> Result<Vec<Motion>, String> {
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
/// to its start is a full circle and stays. Within 1e-3 mm on both sides:
/// a move shorter than that is lost in rs274's printed step (a lathe
/// cycle's last 1 µm to the profile), so kezuri's is dropped as rs274's is.
fn stays(m: &Motion, from: &[f64; 6]) -> bool {
    matches!(m.kind, Kind::Rapid | Kind::Feed) && (0..6).all(|k| (m.end[k] - from[k]).abs() <= 1e-9 + m.tol.max(1e-3))
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
pub fn first_difference(ours: &[Motion], theirs: &[Motion]) -> Option<String> {
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

/// What a file is, with the reason.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Class {
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
    pub fn name(&self) -> &'static str {
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

    pub fn reason(&self) -> String {
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
