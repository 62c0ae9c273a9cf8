//! kezuri against LinuxCNC's own interpreter (`rs274`, Debian package
//! `linuxcnc-uspace`) on every lathe program LinuxCNC ships, read where the
//! package installed them (GPL: read at test time, never copied here).
//!
//! Each program runs on both sides with the lathe's start-up codes `G18 G7`
//! (the ZX plane, X a diameter) written before its first block: rs274 alone
//! does not run an INI file's `RS274NGC_STARTUP_CODE`. The lathe macros and
//! ngcgui's lathe subroutines are libraries: each is called as its user
//! interface calls it, with its own default arguments (`MACRODEFAULTS=`,
//! `#<name> = #n (=default …)`). Both interpreters get LinuxCNC's lathe
//! simulator's tool table (`sim/axis/lathe.tbl`, inches: diameters and
//! orientations) without its X and Z offsets: after a tool change rs274's
//! standalone canon gives back its last end point, the new offset left out,
//! where LinuxCNC (and kezuri) read the position back with it — every
//! program that changes tools would part there (the mill comparison's
//! `mmount.ngc` and `skeleton.ngc`), not on anything a lathe does.
//!
//! End points must agree within 1e-3 mm plus half the step rs274 prints;
//! where rs274 stops with an error, kezuri must stop too, for the same
//! reason (kezuri writes no motions when it stops: those before the stop
//! are not compared). Disagreements known today are listed in
//! [`EXPECTED_FAILURES`] with their cause; one that agrees fails the test so
//! the list stays true. Without rs274 the test skips, saying so, unless
//! `KEZURI_REQUIRE_RS274` is set (CI), where it fails. `cargo test -p kezuri
//! --test linuxcnc_lathe -- --nocapture` prints the table.

// The shared harness: this test reads rs274 with its own start-up, not its `rs274()`.
#[allow(dead_code)]
mod rs274;

use std::path::{Path, PathBuf};
use std::process::Command;

use rs274::{first_difference, kezuri_done, read_canon, rs274_here, run_limited, Motion};

/// Where the package puts its example programs.
const NCFILES: &str = "/usr/share/linuxcnc/ncfiles";

/// The lathe programs, relative to [`NCFILES`]; the macro and ngcgui
/// folders are read whole.
const PROGRAMS: &[&str] = &[
    "lathe-g76.ngc",
    "lathe_g70_71_demo.ngc",
    "lathe_g7x_face_boring.ngc",
    "lathe_g7x_quadrants.ngc",
    "lathe_pawn.ngc",
    "lathecomp.ngc",
    "g76.ngc",
    "threading.ngc",
];

/// Programs written for radius mode (their arcs meet their ends only with X
/// a radius): run a second time with `G18 G8`, LinuxCNC's power-on mode
/// and the start-up of its gmoccapy lathe configurations.
const RADIUS_MODE: &[&str] = &["lathe_g70_71_demo.ngc", "lathe_g7x_quadrants.ngc", "g76.ngc"];

/// Subroutine folders: each file is called with its defaults.
const LIBRARIES: &[&str] = &["macros/lathe", "ngcgui_lib/lathe"];

/// ngcgui's own subroutines (`o<loadtool>`), found by its lathe files as
/// ngcgui's configurations put them on the subroutine path.
const UTILITIES: &str = "ngcgui_lib/utilitysubs";

/// Programs of this test's own for what the package's programs leave out:
/// corners (`A` fillets, `C` chamfers), `U` `W` under `G7` and an R arc in
/// the profile, `G70` in passes with `E`; `G71.1`/`G71.2` and pockets in
/// radius mode; `G72.1`/`G72.2` in inches with a G3 and corners; a profile
/// read in `G91`. Each sets its own modes.
const OWN: &[(&str, &str)] = &[
    (
        "own: corners, U W under G7, G70 passes",
        "G18 G7 G21 G90\n\
F200\n\
o200 sub\n\
  G0 X10 Z2\n\
  G1 Z0 C1\n\
  X20 A2\n\
  W-15\n\
  U10 Z-20 A1\n\
  G2 X40 Z-30 R10\n\
  G1 Z-40\n\
  X50\n\
o200 endsub\n\
G0 X60 Z5\n\
G71 Q200 X60 Z5 D0.4 I1.5 R0.5\n\
G70 Q200 X60 Z5 D0.5 E0.1 P3\n\
G0 X60 Z5\n\
M2\n",
    ),
    (
        "own: G71.1 G71.2 G71 with pockets, G8",
        "G18 G8 G21 G90\n\
F150\n\
o300 sub\n\
  G0 X5 Z1\n\
  G1 Z-5\n\
  X8 Z-8\n\
  Z-12\n\
  X4 Z-16\n\
  Z-20\n\
  X12\n\
o300 endsub\n\
G0 X14 Z3\n\
G71.1 Q300 X14 Z3 D0.2 I0.7 R0.3\n\
G71.2 Q300 X14 Z3 D0.1 I0.7 R0.3\n\
G71 Q300 X14 Z3 D0 I0.5 R0.2\n\
G0 X14 Z3\n\
M2\n",
    ),
    (
        "own: G72.1 G72.2 G70 in inches, corners",
        "G18 G7 G20 G90\n\
F5\n\
o400 sub\n\
  G1 X0.2 Z0.05\n\
  G1 Z0\n\
  G3 X0.6 Z-0.2 K-0.2 I0\n\
  G1 Z-0.6 A0.05\n\
  X1.0 C0.03\n\
  Z-1.0\n\
o400 endsub\n\
G0 X1.2 Z0.2\n\
G72.1 Q400 X1.2 Z0.2 D0.01 I0.05 R0.02\n\
G72.2 Q400 X1.2 Z0.2 D0.005 I0.05 R0.02\n\
G70 Q400 X1.2 Z0.2\n\
M2\n",
    ),
    (
        "own: profile without motion codes after a G2, the mode after the cycle",
        "G18 G8 G21 F100\no1 sub\nX2 Z0\nZ-10\nX5\no1 endsub\nG2 X5 Z1 R3\nG71 Q1 X5 Z1 D0 I1 R0.5\nX8\nG0 X9 Z3\nM2\n",
    ),
    (
        "own: profile read in G91",
        "G18 G7 G21 G91\n\
F100\n\
o500 sub\n\
  G0 X-10 Z-1\n\
  G1 Z-10\n\
  X4 Z-4\n\
  G3 X6 Z-3 R3\n\
  G1 Z-8\n\
  X6\n\
o500 endsub\n\
G90 G0 X40 Z2\n\
G91\n\
G71 Q500 X0 Z0 D0.3 I1 R0.5\n\
G90 G0 X40 Z2\n\
G72 Q500 D0.3 I0.8 R0.5\n\
G90 G0 X40 Z2\n\
G70 Q500 D1 P2\n\
M2\n",
    ),
];

/// Programs that disagree today, each with its cause. A file named here
/// that agrees fails the test.
const EXPECTED_FAILURES: &[(&str, &str)] = &[(
    "macros/lathe/probe-hole.ngc",
    "probing: rs274's standalone canon (saicanon.cc, STRAIGHT_PROBE) ends every probe move at its commanded end \
     (#5061-#5069 that end, #5070 0: no contact), then puts the tool 0.01 in (0.254 mm) back toward its start, \
     where no machine puts it (LinuxCNC's motion stops past the trip point, or at the end without contact); \
     kezuri ends the move at its end, as G38.3 without contact does. The first move, G91 G38.3 Z0.00001, \
     leaves rs274 at Z-0.00999 in and kezuri at Z0.00001 in, and no later block names Z: every later end point \
     is 0.254 mm apart in Z; X and Y agree, the probes' averages too",
)];

/// The lathe simulator's tool table, where the package puts it.
const TOOL_TABLE: &str = "/usr/share/doc/linuxcnc/examples/sample-configs/sim/axis/lathe.tbl";

/// One program to run: its name for the table, the text both interpreters
/// run and the folder its subroutines are found in.
struct Case {
    name: String,
    text: String,
    dir: PathBuf,
}

/// `text` with the start-up codes before its first block (after a leading
/// `%` line).
fn with_startup(text: &str) -> String {
    startup(text, "G18 G7\n")
}

/// `text` with `codes` before its first block (after a leading `%` line).
fn startup(text: &str, codes: &str) -> String {
    match text.split_once('\n') {
        Some((first, rest)) if first.trim() == "%" => format!("{first}\n{codes}{rest}"),
        _ => format!("{codes}{text}"),
    }
}

/// The defaults a library file gives its arguments: the macro's
/// `MACRODEFAULTS=` list (true 1, false 0), or ngcgui's `#<name> = #n
/// (=default …)` comments in the order of n. `None`: not a subroutine for
/// a user interface.
fn defaults(text: &str) -> Option<Vec<String>> {
    if let Some(list) = text.lines().find_map(|l| l.trim().strip_prefix("; MACRODEFAULTS=")) {
        let value = |v: &str| match v.trim().to_ascii_lowercase().as_str() {
            "true" => "1".to_string(),
            "false" => "0".to_string(),
            v => v.to_string(),
        };
        return Some(list.split(',').map(value).collect());
    }
    let mut found: Vec<(u32, String)> = Vec::new();
    for line in text.lines() {
        // `#<name> = #3 (=0.010 Depth of Cut)`
        let Some((_, rest)) = line.split_once('=') else { continue };
        let rest = rest.trim_start();
        let Some(rest) = rest.strip_prefix('#') else { continue };
        let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
        let Ok(n) = digits.parse::<u32>() else { continue };
        let Some((_, comment)) = rest.split_once("(=") else { continue };
        let value = comment.split_whitespace().next().map(|v| v.trim_end_matches(')').to_string());
        if let Some(v) = value.filter(|v| v.parse::<f64>().is_ok()) {
            found.push((n, v));
        }
    }
    found.sort_by_key(|(n, _)| *n);
    (!found.is_empty()).then(|| found.into_iter().map(|(_, v)| v).collect())
}

/// The subroutine's name: `o<name> sub`.
fn sub_name(text: &str) -> Option<String> {
    text.lines().find_map(|l| {
        let l = l.trim().to_ascii_lowercase();
        let rest = l.strip_prefix("o<")?;
        let (name, after) = rest.split_once('>')?;
        (after.trim() == "sub").then(|| name.to_string())
    })
}

/// Every lathe program of the package, as it is run.
fn cases() -> Vec<Case> {
    let root = Path::new(NCFILES);
    let mut cases = Vec::new();
    for p in PROGRAMS {
        let file = root.join(p);
        let Ok(text) = std::fs::read_to_string(&file) else { continue };
        cases.push(Case { name: p.to_string(), text: with_startup(&text), dir: root.to_path_buf() });
        if RADIUS_MODE.contains(p) {
            let name = format!("{p} (G8)");
            cases.push(Case { name, text: startup(&text, "G18 G8\n"), dir: root.to_path_buf() });
        }
    }
    for (name, text) in OWN {
        cases.push(Case { name: name.to_string(), text: text.to_string(), dir: root.to_path_buf() });
    }
    for lib in LIBRARIES {
        let dir = root.join(lib);
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        let mut files: Vec<PathBuf> =
            entries.flatten().map(|e| e.path()).filter(|p| p.extension().is_some_and(|e| e == "ngc")).collect();
        files.sort();
        for file in files {
            let text = String::from_utf8_lossy(&std::fs::read(&file).unwrap()).into_owned();
            let name = format!("{lib}/{}", file.file_name().unwrap().to_string_lossy());
            let Some(sub) = sub_name(&text) else {
                // A preamble, not a subroutine: run as a program.
                cases.push(Case { name, text: with_startup(&text), dir: dir.clone() });
                continue;
            };
            let args: String = defaults(&text).unwrap_or_default().iter().map(|v| format!(" [{v}]")).collect();
            let call = format!("G18 G7\no<{sub}> call{args}\nM2\n");
            cases.push(Case { name, text: call, dir: dir.clone() });
        }
    }
    cases
}

/// The lathe simulator's tool table without X and Z offsets, written into
/// `scratch`.
fn tool_table(scratch: &Path) -> PathBuf {
    let table = scratch.join("lathe.tbl");
    let text = std::fs::read_to_string(TOOL_TABLE).unwrap();
    let mut out = String::new();
    for line in text.lines() {
        let entry = line.split(';').next().unwrap_or("");
        let kept: Vec<&str> = entry.split_whitespace().filter(|w| !w.starts_with(['X', 'x', 'Z', 'z'])).collect();
        if !kept.is_empty() {
            out.push_str(&kept.join(" "));
            out.push('\n');
        }
    }
    std::fs::write(&table, out).unwrap();
    table
}

/// rs274's run of `program` (subroutines from `dir`): its motions and the
/// error it stopped with.
fn rs274_run(program: &Path, dir: &Path, scratch: &Path) -> (Vec<Motion>, Option<String>) {
    let ini = scratch.join("lathe.ini");
    std::fs::write(&ini, format!("[RS274NGC]\nSUBROUTINE_PATH = {}\n", dir.display())).unwrap();
    let canon = scratch.join("rs274.canon");
    let _ = std::fs::remove_file(&canon);
    let mut cmd = Command::new("rs274");
    // Its own HOME: rs274 shares its tool table through $HOME/.tool.mmap.
    cmd.env("HOME", scratch).arg("-i").arg(&ini).arg("-g").arg("-t").arg(tool_table(scratch));
    cmd.arg(program).arg(&canon);
    let done = run_limited(cmd, dir, scratch, "rs274");
    let text = String::from_utf8_lossy(&std::fs::read(&canon).unwrap_or_default()).into_owned();
    let error = match done.status {
        Some(0) => None,
        None => Some("rs274 ran past its time".to_string()),
        // run_limited gives a signal as 128 + its number.
        Some(code) if code > 128 => Some(format!("crashed (signal {})", code - 128)),
        Some(code) => {
            // rs274 says its error, then the block it stopped at.
            let said: Vec<&str> = done
                .stdout
                .lines()
                .chain(done.stderr.lines())
                .map(str::trim)
                .filter(|l| !l.is_empty() && *l != "executing" && !l.starts_with("Oops"))
                .collect();
            Some(match said.as_slice() {
                [.., error, block] => format!("{error}, at `{block}`"),
                [error] => error.to_string(),
                [] => format!("exit status {code}"),
            })
        }
    };
    (read_canon(&text), error)
}

/// kezuri's run of `program` in the `linuxcnc` dialect, subroutines from
/// `dir`, the tool table imported in inches.
fn kezuri_run(program: &Path, dir: &Path, scratch: &Path) -> Result<Vec<Motion>, String> {
    let machine = scratch.join("machine.toml");
    let table = tool_table(scratch);
    std::fs::write(&machine, format!("[tools]\nimport = \"{}\"\nunits = \"inch\"\n", table.display())).unwrap();
    let csv = scratch.join("kezuri.csv");
    let _ = std::fs::remove_file(&csv);
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_kezuri"));
    cmd.arg("run").arg(program).args(["--dialect", "linuxcnc", "--lib"]).arg(dir);
    cmd.arg("--machine").arg(&machine).args(["--emit", "csv", "-o"]).arg(&csv);
    kezuri_done(run_limited(cmd, dir, scratch, "kezuri"), &csv)
}

/// How one program compares: `Ok` with how they agree, or what differs.
fn compare(case: &Case, scratch: &Path) -> Result<String, String> {
    // One folder of subroutines: the program's own and ngcgui's utilities,
    // linked.
    let lib = scratch.join("lib");
    let _ = std::fs::remove_dir_all(&lib);
    std::fs::create_dir_all(&lib).unwrap();
    for dir in [Path::new(NCFILES).join(UTILITIES), case.dir.clone()] {
        for entry in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            let p = entry.path();
            if p.extension().is_some_and(|e| e == "ngc") {
                let link = lib.join(p.file_name().unwrap());
                let _ = std::fs::remove_file(&link);
                std::os::unix::fs::symlink(&p, link).unwrap();
            }
        }
    }
    let program = scratch.join("program.ngc");
    std::fs::write(&program, &case.text).unwrap();
    let (theirs, error) = rs274_run(&program, &lib, scratch);
    let ours = kezuri_run(&program, &lib, scratch);
    match (ours, error) {
        (Ok(ours), None) => match first_difference(&ours, &theirs) {
            None => Ok(format!("agrees: {} motions, every end point", theirs.len())),
            Some(d) => Err(d),
        },
        (Err(e), None) => Err(format!("kezuri stops: {e}; rs274 runs it ({} motions)", theirs.len())),
        (Ok(ours), Some(e)) => {
            Err(format!("rs274 stops ({e}) after {} motions; kezuri runs it ({} motions)", theirs.len(), ours.len()))
        }
        // Both refuse the program: agreement where kezuri gives rs274's
        // reason.
        (Err(ours), Some(theirs)) => {
            // rs274's reason, without its figures or the block.
            let reason = theirs.split([':', ',']).next().unwrap_or(&theirs);
            if theirs.starts_with("crashed") {
                Ok("kezuri refuses where rs274 crashes".into())
            } else if theirs.contains("ran past its time") && ours.contains("LinuxCNC 2.9 loops here") {
                Ok("kezuri refuses where rs274 loops".into())
            } else if ours.contains(reason) {
                // kezuri writes no motions when it stops: those before are
                // not compared.
                Ok(format!("agrees: both stop, for the same reason (rs274 after {} motions)", theirs.len()))
            } else {
                Err(format!("both stop: rs274 {theirs}; kezuri {ours}"))
            }
        }
    }
}

#[test]
fn linuxcnc_lathe_programs_agree_with_rs274() {
    if !rs274_here() {
        return;
    }
    let cases = cases();
    if cases.is_empty() || !Path::new(TOOL_TABLE).is_file() {
        assert!(
            std::env::var_os("KEZURI_REQUIRE_RS274").is_none(),
            "rs274 is required and the package's lathe programs or lathe.tbl are missing"
        );
        eprintln!("rs274 is here but not LinuxCNC's lathe programs: skipped");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut failures = Vec::new();
    let mut agree = 0;
    let width = cases.iter().map(|c| c.name.len()).max().unwrap_or(10);
    for case in &cases {
        let expected = EXPECTED_FAILURES.iter().find(|(f, _)| *f == case.name).map(|(_, c)| *c);
        let verdict = match (compare(case, dir.path()), expected) {
            (Ok(how), None) => {
                agree += 1;
                how
            }
            (Ok(_), Some(_)) => {
                failures.push(format!("{}: agrees now: take it out of EXPECTED_FAILURES", case.name));
                "AGREES (listed as an expected failure)".to_string()
            }
            (Err(d), Some(cause)) => format!("differs (expected: {cause})\n      {d}"),
            (Err(d), None) => {
                failures.push(format!("{}: {d}", case.name));
                format!("DIFFERS\n      {d}")
            }
        };
        println!("{:width$}  {verdict}", case.name);
    }
    println!("{agree} of {} lathe programs agree with rs274", cases.len());
    assert!(failures.is_empty(), "{} lathe programs differ from rs274:\n{}", failures.len(), failures.join("\n"));
}

// ---------------------------------------------------------------- random profiles

/// A small generator of numbers (a linear congruential one: the same
/// programs on every run).
struct Numbers(u64);

impl Numbers {
    /// A number in [lo, hi).
    fn within(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self.0.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }

    fn pick<'a>(&mut self, of: &[&'a str]) -> &'a str {
        of[(self.within(0.0, of.len() as f64) as usize).min(of.len() - 1)]
    }
}

/// A profile subroutine for a turning cycle: from a small X down Z in
/// two to six pieces, lines and R arcs that rise or dip (pockets), some
/// with a fillet (A) or a chamfer (C) at their end, then up; the cycle
/// (G71, G71.1, G71.2, G72, G70) from X24 Z2 with its words drawn too.
fn random_profile(n: &mut Numbers) -> String {
    let mode = n.pick(&["G7", "G8"]);
    let (mut x, mut z) = (n.within(1.0, 4.0), 0.0);
    let mut text = format!("G18 {mode} G21 F100\no1 sub\nG1 X{:.3} Z0\n", 2.0 * x);
    for _ in 0..(n.within(2.0, 7.0) as usize) {
        let nz = z - n.within(1.0, 8.0);
        let nx = (x + if n.within(0.0, 1.0) < 0.7 { n.within(-2.0, 4.0) } else { n.within(0.0, 3.0) }).max(0.5);
        let corner = match n.within(0.0, 1.0) {
            c if c < 0.3 => format!(" A{:.2}", n.within(0.1, 0.6)),
            c if c < 0.5 => format!(" C{:.2}", n.within(0.1, 0.6)),
            _ => String::new(),
        };
        if n.within(0.0, 1.0) < 0.3 && (nx - x).abs() > 0.5 {
            let r = (nx - x).hypot(nz - z) / 2.0 * n.within(2.0, 6.0);
            let g = n.pick(&["G2", "G3"]);
            text.push_str(&format!("{g} X{:.3} Z{nz:.3} R{r:.3}{corner}\n", 2.0 * nx));
        } else {
            text.push_str(&format!("G1 X{:.3} Z{nz:.3}{corner}\n", 2.0 * nx));
        }
        (x, z) = (nx, nz);
    }
    text.push_str(&format!("G1 X{:.3}\no1 endsub\nG0 X24 Z2\n", 2.0 * (x + 3.0)));
    let cycle = n.pick(&["G71", "G71.1", "G71.2", "G72", "G70"]);
    let d = n.pick(&["0", "0.2", "0.5"]);
    let words = if cycle == "G70" {
        format!("D{d} P{} E{}", n.within(1.0, 4.0) as u32, n.pick(&["0", "0.1"]))
    } else {
        format!("D{d} I{} R{}", n.pick(&["0.5", "1", "1.3"]), n.pick(&["0.3", "0.5"]))
    };
    text.push_str(&format!("{cycle} Q1 X24 Z2 {words}\nM2\n"));
    text
}

/// A profile subroutine for a facing cycle: X down from 10 (a radius) in
/// two to six pieces while Z wanders (pockets along X), lines and R arcs,
/// some with a corner, then along Z; the cycle (G72, G72.1, G72.2, G70)
/// from X24 Z3.
fn random_face(n: &mut Numbers) -> String {
    let mode = n.pick(&["G7", "G8"]);
    let f = if mode == "G7" { 2.0 } else { 1.0 };
    let (mut x, mut z) = (10.0, -n.within(0.0, 3.0));
    let mut text = format!("G18 {mode} G21 F100\no1 sub\nG1 X{:.3} Z{z:.3}\n", x * f);
    for _ in 0..(n.within(2.0, 7.0) as usize) {
        let (nx, nz) = (x - n.within(0.5, 3.0), z + n.within(-2.0, 2.0));
        if nx < 0.5 {
            break;
        }
        let corner = match n.within(0.0, 1.0) {
            c if c < 0.2 => format!(" A{:.2}", n.within(0.1, 0.4)),
            c if c < 0.35 => format!(" C{:.2}", n.within(0.1, 0.4)),
            _ => String::new(),
        };
        if n.within(0.0, 1.0) < 0.3 {
            let r = (nx - x).hypot(nz - z) / 2.0 * n.within(2.0, 6.0);
            let g = n.pick(&["G2", "G3"]);
            text.push_str(&format!("{g} X{:.3} Z{nz:.3} R{r:.3}{corner}\n", nx * f));
        } else {
            text.push_str(&format!("G1 X{:.3} Z{nz:.3}{corner}\n", nx * f));
        }
        (x, z) = (nx, nz);
    }
    text.push_str(&format!("G1 Z{:.3}\no1 endsub\nG0 X{} Z3\n", z - 3.0, 12.0 * f));
    let cycle = n.pick(&["G72", "G72.1", "G72.2", "G70"]);
    let words = if cycle == "G70" {
        format!("D{} P{}", n.pick(&["0", "0.2"]), n.within(1.0, 4.0) as u32)
    } else {
        format!("D{} I{} R{}", n.pick(&["0", "0.2", "0.5"]), n.pick(&["0.4", "0.8"]), n.pick(&["0.2", "0.5"]))
    };
    text.push_str(&format!("{cycle} Q1 X{} Z3 {words}\nM2\n", 12.0 * f));
    text
}

/// A turning profile of [`random_profile`]'s finished by `G70` under
/// `G41.1`/`G42.1` (a nose diameter D, an orientation L), from a start
/// point drawn about X24 Z2 so that the corner at the cycle's start comes
/// out concave, convex or straight; some profiles end on the start's X
/// and begin on its Z, as `lathe_g70_71_demo` does.
fn random_comp_g70(n: &mut Numbers) -> String {
    let profile = random_profile(n);
    let (sub, _) = profile.split_once("G0 X24 Z2\n").expect("the profile's subroutine");
    let (x, z) = (n.within(20.0, 30.0), n.within(-1.0, 4.0));
    let mut sub = sub.to_string();
    if n.within(0.0, 1.0) < 0.3 {
        // The profile from the start's Z, back to its X (a diameter under G7).
        let f = if sub.starts_with("G18 G7") { 2.0 } else { 1.0 };
        sub = sub.replacen(" Z0\n", &format!(" Z{z:.3}\n"), 1);
        sub = sub.replace("o1 endsub", &format!("G0 X{:.3}\no1 endsub", x * f));
    }
    let f = if sub.starts_with("G18 G7") { 2.0 } else { 1.0 };
    let side = n.pick(&["G41.1", "G42.1", "G42.1", "G42.1"]);
    let (d, l) = (n.within(0.1, 0.5), n.within(1.0, 10.0) as u32);
    let passes = n.within(1.0, 3.0) as u32;
    format!(
        "{sub}G0 X{:.3} Z-40\n{side} D{d:.3} L{l}\nG70 Q1 X{:.3} Z{z:.3} D{} P{passes}\nG40 G0 X{:.3}\nM2\n",
        x * f,
        x * f,
        n.pick(&["0", "0.3"]),
        (x + 5.0) * f
    )
}

/// The seed of the facing profiles.
const FACES_SEED: u64 = 7;

/// 150 drawn turning profiles and 100 facing ones: each cut as rs274 cuts
/// it, or refused where rs274 refuses it for the same reason (a profile
/// that turns back: "Not monotonic"; an arc of the cycle off its circle).
#[test]
fn random_profiles_are_cut_as_rs274_cuts_them() {
    if !rs274_here() || !Path::new(TOOL_TABLE).is_file() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut n = Numbers(3);
    // The facing profiles from their own numbers: a set without the
    // G72.2 profiles on which rs274 2.9 loops (each would take rs274's
    // whole time limit; kezuri's refusal of them is tested in
    // kezuri-nc's linuxcnc_lathe.rs).
    let mut faces = Numbers(FACES_SEED);
    let (mut cut, mut refused, mut crashed, mut looped, mut failures) = (0, 0, 0, 0, Vec::new());
    for k in 0..250 {
        let text = if k < 150 { random_profile(&mut n) } else { random_face(&mut faces) };
        let case = Case { name: format!("profile {k}"), text, dir: dir.path().to_path_buf() };
        match compare(&case, dir.path()) {
            Ok(how) if how.starts_with("agrees: both stop") => refused += 1,
            Ok(how) if how.starts_with("agrees") => cut += 1,
            Ok(how) if how.contains("crashes") => crashed += 1,
            Ok(_) => looped += 1,
            Err(d) => failures.push(format!("{}:\n{}\n      {d}", case.name, case.text)),
        }
    }
    println!(
        "{cut} profiles cut as rs274 cuts them, {refused} refused by both, {crashed} refused by kezuri where rs274 \
         crashes, {looped} where it loops"
    );
    assert!(cut >= 150, "only {cut} of 250 drawn profiles could be cut: the test no longer tests");
    assert!(failures.is_empty(), "{} profiles differ:\n{}", failures.len(), failures.join("\n"));
}

/// 120 drawn profiles finished by `G70` under nose radius compensation
/// (`random_comp_g70`): each cut as rs274 cuts it, or refused where rs274
/// refuses it for the same reason. What they test is rs274's start of the
/// cycle: its compensation works from the profile's end after reading it
/// (kezuri-nc's `linuxcnc_g70_comp.rs` derives the rule by hand).
#[test]
fn g70_under_compensation_is_cut_as_rs274_cuts_it() {
    if !rs274_here() || !Path::new(TOOL_TABLE).is_file() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut n = Numbers(11);
    let (mut cut, mut refused, mut failures) = (0, 0, Vec::new());
    for k in 0..120 {
        let case = Case { name: format!("G70 {k}"), text: random_comp_g70(&mut n), dir: dir.path().to_path_buf() };
        match compare(&case, dir.path()) {
            Ok(how) if how.starts_with("agrees: both stop") => refused += 1,
            Ok(_) => cut += 1,
            Err(d) => failures.push(format!("{}:\n{}\n      {d}", case.name, case.text)),
        }
    }
    println!("{cut} G70 under compensation cut as rs274 cuts them, {refused} refused by both");
    assert!(failures.is_empty(), "{} G70s differ:\n{}", failures.len(), failures.join("\n"));
    assert!(cut >= 50, "only {cut} of 120 drawn G70s could be cut: the test no longer tests");
}
