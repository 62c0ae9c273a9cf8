//! Every numeric option of every command at its extremes — 0, negative,
//! tiny (1e-300), huge (1e300), NaN and inf for decimals; 0 and u64::MAX
//! for counts; 0, -1 and the i64 extremes for signed whole numbers — each
//! run of the binary under a 4 GB address-space limit and a 10 s time
//! limit. Each must end in a clear error (exit 1 or 2 with a message) or a
//! successful run: never a panic, an abort, a signal or a timeout. A
//! successful run must not print or write NaN or an infinity: its standard
//! output and every text file it leaves are searched for them.
//!
//! The options come from clap's own description of the command line
//! (`kezuri::Cli::command()`), so a new option is covered without a word
//! here; only the base invocation of a new command (`BASES`) must be added,
//! and the test says so. Failures not yet fixed are listed in `KNOWN`, each
//! with its reason; a known failure that no longer happens fails the test too,
//! so the list is kept short.
//!
//! About 725 runs, 20 s on two cores (the slowest run takes under 2 s);
//! `KEZURI_RESOURCE_TEST="mill,probe mill" cargo test -p kezuri --test resources -- --nocapture`
//! runs those commands only, and prints the table of options and the
//! slowest runs.

use std::any::TypeId;
use std::fs::File;
use std::io::Write;
use std::os::fd::FromRawFd;
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use clap::CommandFactory;

/// Address space a run may take.
const MEMORY: u64 = 4 << 30;
/// Largest file a run may write (a guard for the disk, not part of the check).
const FILE_SIZE: u64 = 1 << 30;
/// Time a run may take.
const TIME: Duration = Duration::from_secs(10);

/// A minimal valid invocation of each command that has a numeric option,
/// its words split at spaces: `{in}` is the folder of inputs `inputs` makes, `{samples}` the bundled
/// samples, `{port}` a pseudo-terminal where an instrument sends a reading
/// every 400 ms; outputs go to the run's own folder.
const BASES: &[(&str, &str)] = &[
    ("check", "{in}/part.nc"),
    ("run", "{in}/part.nc -o out.nc"),
    ("scallop", "--tool ball:6 --angle 30 --cusp 0.01"),
    ("engage", "--tool oval:16,24 --angle 45 --pick-feed 0.8 --depth 0.8 --feed-per-tooth 0.16 --csv out.csv"),
    ("dropcut", "{in}/part.stl --tool ball:2 --grid 0,0,10,10,1 -o out.cl"),
    ("mill", "{in}/part.stl --tool ball:2 --stepover 1 -o out.nc"),
    ("sim", "{in}/part.nc --tool ball:2 --res 0.5 --compare {in}/part.stl --deviation-png dev.png"),
    ("view", "{in}/part.nc --sim --tool ball:2 --res 0.5 --compare {in}/part.stl -o page.html"),
    ("probe plan", "--origin 0,0 --count 3,3 --pitch 1 --safe-z 10 --plunge 5 -o out.nc"),
    ("probe capture", "--port {port} --count 2,2 -o out.csv"),
    ("probe level", "{in}/data.txt -o out.txt"),
    ("probe export", "{in}/data.txt --png out.png"),
    ("probe mill", "{in}/data.txt --stylus ball:2 --tool ball:2 -o out.nc"),
    ("probe simulate", "{in}/part.stl --count 5,5 --pitch 2 --stylus ball:2 -o out.txt"),
    ("relief", "{samples}/plum-sketch.png --width 20 --depth 1 --tool ball:2 --stepover 1 -o out.nc"),
    ("convert", "{in}/part.rml -o out.nc"),
    ("texture", "{in}/part.nc --seed 7 -o out.nc"),
    ("thermal plan", "--machine {in}/mill-turn.toml -o out.nc"),
    ("thermal edge", "{in}/edge.csv"),
    ("thermal fit", "{in}/meas.csv -o model.json"),
    ("thermal apply", "{in}/part.nc --model {in}/model.json -o out.nc"),
    ("tool profile", "{in}/tool.png --pixel-um 20 --tip-row 100 -o out.csv"),
    ("wear apply", "{in}/groove.nc --nominal ball:2 --surface {in}/plate.stl --profile {in}/profile.csv -o out.nc"),
];

/// Failures not fixed yet: command, option, value (`*` for every value),
/// and why.
const KNOWN: &[(&str, &str, &str, &str)] = &[];

/// The value type of an option, as far as this test cares.
#[derive(Clone, Copy)]
enum Kind {
    Decimal,
    Whole,
    Signed,
}

impl Kind {
    fn of(arg: &clap::Arg) -> Option<Kind> {
        let t = arg.get_value_parser().type_id();
        let any = |ids: &[TypeId]| ids.iter().any(|id| t == *id);
        if any(&[TypeId::of::<f64>(), TypeId::of::<f32>()]) {
            Some(Kind::Decimal)
        } else if any(&[
            TypeId::of::<u8>(),
            TypeId::of::<u16>(),
            TypeId::of::<u32>(),
            TypeId::of::<u64>(),
            TypeId::of::<usize>(),
        ]) {
            Some(Kind::Whole)
        } else if any(&[TypeId::of::<i8>(), TypeId::of::<i16>(), TypeId::of::<i32>(), TypeId::of::<i64>()]) {
            Some(Kind::Signed)
        } else {
            None
        }
    }

    fn extremes(self) -> &'static [&'static str] {
        match self {
            Kind::Decimal => &["0", "-1", "1e-300", "1e300", "-1e300", "NaN", "inf", "-inf"],
            Kind::Whole => &["0", "18446744073709551615"],
            Kind::Signed => &["0", "-1", "9223372036854775807", "-9223372036854775808"],
        }
    }
}

/// One leaf command (`probe mill`) with its numeric options.
struct Leaf {
    name: String,
    options: Vec<(String, Kind)>,
    /// Options that cannot be given with each option (clap's conflicts and
    /// exclusive groups): dropped from the base when that option is tried.
    conflicts: Vec<Vec<String>>,
}

/// Every leaf command of `command`, with its path of subcommand names.
fn leaves(command: &clap::Command, path: &[&str], out: &mut Vec<Leaf>) {
    let subcommands: Vec<_> = command.get_subcommands().filter(|s| s.get_name() != "help").collect();
    if subcommands.is_empty() {
        let mut leaf = Leaf { name: path.join(" "), options: Vec::new(), conflicts: Vec::new() };
        for arg in command.get_arguments() {
            let (Some(kind), Some(long)) = (Kind::of(arg), arg.get_long()) else { continue };
            let mut conflicts: Vec<String> = command
                .get_arg_conflicts_with(arg)
                .iter()
                .filter_map(|a| a.get_long().map(|l| format!("--{l}")))
                .collect();
            for group in command.get_groups().filter(|g| !(*g).clone().is_multiple()) {
                if group.get_args().any(|id| id == arg.get_id()) {
                    let others = group.get_args().filter(|id| *id != arg.get_id());
                    let longs = others.filter_map(|id| command.get_arguments().find(|a| a.get_id() == id));
                    conflicts.extend(longs.filter_map(|a| a.get_long().map(|l| format!("--{l}"))));
                }
            }
            leaf.options.push((format!("--{long}"), kind));
            leaf.conflicts.push(conflicts);
        }
        out.push(leaf);
    }
    for s in subcommands {
        let mut p = path.to_vec();
        p.push(s.get_name());
        leaves(s, &p, out);
    }
}

/// The base words of `base` with `option` set to `value`: its value in the
/// base replaced, or the option added; options it conflicts with dropped.
fn words(base: &[String], option: &str, value: &str, conflicts: &[String]) -> Vec<String> {
    let mut out = Vec::new();
    let mut set = false;
    let mut k = 0;
    while k < base.len() {
        let w = &base[k];
        if w == option {
            out.extend([w.clone(), value.to_string()]);
            set = true;
            k += 2;
        } else if conflicts.contains(w) {
            k += 2;
        } else {
            out.push(w.clone());
            k += 1;
        }
    }
    if !set {
        out.extend([option.to_string(), value.to_string()]);
    }
    out
}

/// A pseudo-terminal whose master sends a Mitutoyo reading every 400 ms
/// (the capture waits for 300 ms of quiet after opening the port) until it
/// is dropped; `path` is the port kezuri opens. The readings are on
/// channel 00, so `--channel 0` has readings to take.
struct Instrument {
    path: String,
    stop: Arc<AtomicBool>,
    _slave: File,
}

impl Instrument {
    fn new() -> Instrument {
        let (mut m, mut s) = (0, 0);
        // SAFETY: openpty writes two descriptors; no name buffer, default settings.
        let r =
            unsafe { libc::openpty(&mut m, &mut s, std::ptr::null_mut(), std::ptr::null_mut(), std::ptr::null_mut()) };
        assert_eq!(r, 0, "openpty: {}", std::io::Error::last_os_error());
        // SAFETY: fcntl and termios on the descriptors just opened: not
        // inherited by other runs, raw, and a full buffer never blocks.
        unsafe {
            libc::fcntl(m, libc::F_SETFD, libc::FD_CLOEXEC);
            libc::fcntl(s, libc::F_SETFD, libc::FD_CLOEXEC);
            libc::fcntl(m, libc::F_SETFL, libc::fcntl(m, libc::F_GETFL) | libc::O_NONBLOCK);
            let mut t: libc::termios = std::mem::zeroed();
            libc::tcgetattr(s, &mut t);
            libc::cfmakeraw(&mut t);
            libc::tcsetattr(s, libc::TCSANOW, &t);
        }
        let path = std::fs::read_link(format!("/proc/self/fd/{s}")).expect("the port's path").display().to_string();
        // SAFETY: both descriptors are ours.
        let (mut master, slave) = unsafe { (File::from_raw_fd(m), File::from_raw_fd(s)) };
        let stop = Arc::new(AtomicBool::new(false));
        let stopped = Arc::clone(&stop);
        std::thread::spawn(move || {
            while !stopped.load(Ordering::Relaxed) {
                master.write_all(b"00A+0012.345\r\n").ok();
                std::thread::sleep(Duration::from_millis(400));
            }
        });
        Instrument { path, stop, _slave: slave }
    }
}

impl Drop for Instrument {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
    }
}

/// How a run ended: its exit code and last line of stderr when acceptable,
/// else what went wrong.
fn verdict(words: &[String], dir: &Path) -> Result<(i32, String), String> {
    let stderr_path = dir.join("stderr.txt");
    let stderr = std::fs::File::create(&stderr_path).map_err(|e| e.to_string())?;
    let stdout = std::fs::File::create(dir.join("stdout.txt")).map_err(|e| e.to_string())?;
    let mut command = Command::new(env!("CARGO_BIN_EXE_kezuri"));
    command.args(words).current_dir(dir).env("RUST_BACKTRACE", "0").stdin(Stdio::null()).stdout(stdout).stderr(stderr);
    // SAFETY: setrlimit is async-signal-safe and touches nothing of the parent.
    unsafe {
        command.pre_exec(|| {
            for (resource, limit) in [(libc::RLIMIT_AS, MEMORY), (libc::RLIMIT_FSIZE, FILE_SIZE)] {
                let l = libc::rlimit { rlim_cur: limit, rlim_max: limit };
                if libc::setrlimit(resource, &l) != 0 {
                    return Err(std::io::Error::last_os_error());
                }
            }
            Ok(())
        });
    }
    let mut child = command.spawn().map_err(|e| format!("cannot start kezuri: {e}"))?;
    let start = Instant::now();
    let status = loop {
        match child.try_wait().map_err(|e| e.to_string())? {
            Some(status) => break status,
            None if start.elapsed() > TIME => {
                child.kill().ok();
                child.wait().ok();
                return Err(format!("still running after {} s", TIME.as_secs()));
            }
            None => std::thread::sleep(Duration::from_millis(5)),
        }
    };
    let text = std::fs::read_to_string(&stderr_path).unwrap_or_default();
    let last = text.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or("").to_string();
    if text.contains("panicked") {
        let line = text.lines().find(|l| l.contains("panicked")).unwrap_or("");
        return Err(format!("panic: {line}"));
    }
    match (status.code(), status.signal()) {
        (Some(0), _) => match not_a_number(dir) {
            Some(found) => Err(format!("exit 0 with {found}")),
            None => Ok((0, last)),
        },
        (Some(code @ (1 | 2)), _) if !last.is_empty() => Ok((code, last)),
        (Some(1 | 2), _) => Err("an error without a message".to_string()),
        (Some(code), _) => Err(format!("exit {code}: {last}")),
        (None, Some(signal)) => Err(format!("killed by signal {signal}: {}", text.lines().next().unwrap_or(""))),
        (None, None) => Err("ended without an exit code".to_string()),
    }
}

/// The first NaN or infinity in the standard output or a text file a run
/// left in `dir` (its stderr aside; of an HTML page, its data): a word
/// `nan`, `inf` or `infinity` in any case, alone or after one address
/// letter (`XNaN`, `Z-inf`).
fn not_a_number(dir: &Path) -> Option<String> {
    let entries = std::fs::read_dir(dir).ok()?;
    for entry in entries.flatten() {
        let path = entry.path();
        if path.file_name().is_some_and(|n| n == "stderr.txt") {
            continue;
        }
        let Ok(mut text) = std::fs::read_to_string(&path) else { continue };
        // A `view` page: its numbers are in the meta JSON (the viewer's
        // code names NaN and Infinity; the rest is base64).
        if path.extension().is_some_and(|e| e == "html") {
            let meta = text.split("id=\"kz-meta\">").nth(1).and_then(|t| t.split("</script>").next());
            text = meta.unwrap_or_default().to_string();
        }
        for (n, line) in text.lines().enumerate() {
            let bad = line.split(|c: char| !c.is_ascii_alphanumeric()).any(|word| {
                let word = word.to_ascii_lowercase();
                let bare = match word.as_bytes() {
                    [first, rest @ ..] if first.is_ascii_alphabetic() && rest.len() >= 3 => &word[1..],
                    _ => word.as_str(),
                };
                ["nan", "inf", "infinity"].contains(&word.as_str()) || ["nan", "inf", "infinity"].contains(&bare)
            });
            if bad {
                let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
                return Some(format!("a number that is not one in {name} line {}: {}", n + 1, line.trim()));
            }
        }
    }
    None
}

/// A binary STL of `triangles`.
fn stl(triangles: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut bytes = vec![0u8; 80];
    bytes.extend((triangles.len() as u32).to_le_bytes());
    for t in triangles {
        bytes.extend([0u8; 12]);
        bytes.extend(t.iter().flatten().flat_map(|c| c.to_le_bytes()));
        bytes.extend([0u8; 2]);
    }
    bytes
}

/// A backlit picture of a 4 mm ball-nose tool at 20 µm a pixel (100 px
/// radius would not fit: 40 px, 0.8 mm), tip on row 100.
fn tool_png(path: &Path) {
    let (w, h, tip, r) = (160u32, 120u32, 100i64, 40.0f64);
    let picture = image::GrayImage::from_fn(w, h, |x, y| {
        let d = (tip - i64::from(y)) as f64;
        let half = if d < 0.0 {
            -1.0
        } else if d < r {
            (r * r - (r - d) * (r - d)).sqrt()
        } else {
            r
        };
        let dark = (f64::from(x) - f64::from(w) / 2.0).abs() <= half;
        image::Luma([if dark { 20 } else { 235 }])
    });
    picture.save(path).expect("the tool picture");
}

/// Runs a setup step that must succeed.
fn setup(words: &[&str]) {
    let o = Command::new(env!("CARGO_BIN_EXE_kezuri")).args(words).output().expect("kezuri runs");
    assert!(o.status.success(), "setup `kezuri {}`: {}", words.join(" "), String::from_utf8_lossy(&o.stderr));
}

/// Writes the inputs the bases read into `dir`.
fn inputs(dir: &Path) {
    let at = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let write = |name: &str, bytes: &[u8]| std::fs::write(dir.join(name), bytes).expect("an input");
    write(
        "part.nc",
        b"%\nO0001\nG21 G90 G17\nS10000 M03\nG00 X1. Y1. Z5.\nG01 Z-0.5 F300.\n\
          G01 X9. F600.\nG02 X9. Y9. I0 J4.\nG01 X1.\nG00 Z5.\nM30\n%\n",
    );
    // A square pyramid, 10 × 10 mm, 3 mm high; a 10 × 10 mm plate at z = 0.
    let (apex, c) = ([5.0, 5.0, 3.0], [[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [10.0, 10.0, 0.0], [0.0, 10.0, 0.0]]);
    write("part.stl", &stl(&[[c[0], c[1], apex], [c[1], c[2], apex], [c[2], c[3], apex], [c[3], c[0], apex]]));
    write("plate.stl", &stl(&[[c[0], c[1], c[2]], [c[0], c[2], c[3]]]));
    write("groove.nc", b"G21 G90 G17\nG00 X1. Y5. Z5.\nG01 Z0 F300.\nG01 X9. F600.\nG00 Z5.\nM30\n");
    write("mill-turn.toml", b"[kinematics]\ntool = [\"X\", \"Z\", \"B\"]\nwork = [\"Y\", \"C\"]\n");
    let mut edge = String::from("x_mm,z_mm\n");
    for k in 0..=200 {
        let x = -1.0 + 0.01 * f64::from(k);
        edge += &format!("{x:.3},{:.3}\n", if x < 0.0 { 0.0 } else { -x });
    }
    write("edge.csv", edge.as_bytes());
    let mut meas = String::from("axis,command_mm,ex_mm,ey_mm,ez_mm,b_deg,state\n");
    for axis in ["X", "Y", "Z"] {
        for c in [-20, -10, 0, 10, 20] {
            let e = 0.3 + 0.001 * f64::from(c);
            meas += &format!("{axis},{c},{e},-0.2,0.1,0,cold\n{axis},{c},{},-0.19,0.1,0,warm\n", e + 0.05);
        }
    }
    write("meas.csv", meas.as_bytes());
    let mut profile = String::from("z_mm,radius_mm,wear_mm\n");
    for k in 0..=100 {
        let z = 0.01 * f64::from(k);
        profile += &format!("{z:.3},{:.5},0\n", (1.0 - (1.0 - z) * (1.0 - z)).sqrt());
    }
    write("profile.csv", profile.as_bytes());
    tool_png(&dir.join("tool.png"));
    setup(&[
        "probe",
        "simulate",
        &at("part.stl"),
        "--count",
        "5,5",
        "--pitch",
        "2",
        "--stylus",
        "ball:2",
        "-o",
        &at("data.txt"),
    ]);
    setup(&["convert", &at("part.nc"), "-o", &at("part.rml")]);
    setup(&["thermal", "fit", &at("meas.csv"), "-o", &at("model.json")]);
}

#[test]
fn every_numeric_option_at_its_extremes_ends_cleanly() {
    let only = std::env::var("KEZURI_RESOURCE_TEST").unwrap_or_default();
    let only: Vec<&str> = only.split(',').map(str::trim).filter(|c| !c.is_empty()).collect();
    let root = tempfile::tempdir().expect("a temporary folder");
    let input_dir = root.path().join("in");
    std::fs::create_dir(&input_dir).expect("the inputs folder");
    inputs(&input_dir);
    let samples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../samples");
    let expand =
        |w: &str| w.replace("{in}", &input_dir.to_string_lossy()).replace("{samples}", &samples.to_string_lossy());

    let mut all = Vec::new();
    leaves(&kezuri::Cli::command(), &[], &mut all);
    let mut runs: Vec<(String, String, String, Vec<String>)> = Vec::new();
    let mut missing = Vec::new();
    println!("{:<16} {:>7} {:>5}  options", "command", "options", "runs");
    for leaf in all.iter().filter(|l| !l.options.is_empty() && (only.is_empty() || only.contains(&l.name.as_str()))) {
        let Some((_, base)) = BASES.iter().find(|(name, _)| *name == leaf.name) else {
            missing.push(leaf.name.clone());
            continue;
        };
        let mut base_words: Vec<String> = leaf.name.split(' ').map(str::to_string).collect();
        let command_words = base_words.len();
        base_words.extend(base.split_whitespace().map(expand));
        runs.push((leaf.name.clone(), "(base)".into(), String::new(), base_words.clone()));
        let before = runs.len();
        for ((option, kind), conflicts) in leaf.options.iter().zip(&leaf.conflicts) {
            for value in kind.extremes() {
                let mut w = base_words[..command_words].to_vec();
                w.extend(words(&base_words[command_words..], option, value, conflicts));
                runs.push((leaf.name.clone(), option.clone(), value.to_string(), w));
            }
        }
        let names: Vec<&str> = leaf.options.iter().map(|(o, _)| o.as_str()).collect();
        println!("{:<16} {:>7} {:>5}  {}", leaf.name, leaf.options.len(), runs.len() - before, names.join(" "));
    }
    assert!(missing.is_empty(), "commands with numeric options but no base invocation in BASES: {missing:?}");

    let next = Mutex::new(0usize);
    let failures = Mutex::new(Vec::new());
    let times = Mutex::new(Vec::new());
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get()).min(4);
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| loop {
                let k = {
                    let mut n = next.lock().expect("the counter");
                    *n += 1;
                    *n - 1
                };
                let Some((command, option, value, w)) = runs.get(k) else { break };
                let dir = root.path().join(format!("run-{k}"));
                std::fs::create_dir(&dir).expect("a run folder");
                let instrument = w.iter().any(|w| w == "{port}").then(Instrument::new);
                let w: Vec<String> = match &instrument {
                    Some(i) => w.iter().map(|w| w.replace("{port}", &i.path)).collect(),
                    None => w.clone(),
                };
                let start = Instant::now();
                let verdict = verdict(&w, &dir);
                let run = format!("kezuri {command} {option} {value}");
                times.lock().expect("the times").push((start.elapsed(), run));
                let what = match verdict {
                    Ok((code, last)) if code != 0 && option == "(base)" => {
                        Some(format!("exit {code}, where the base must succeed: {last}"))
                    }
                    Ok(_) => None,
                    Err(what) => Some(what),
                };
                drop(instrument);
                if let Some(what) = what {
                    failures.lock().expect("the failures").push((command.clone(), option.clone(), value.clone(), what));
                }
                std::fs::remove_dir_all(&dir).ok();
            });
        }
    });
    let mut times = times.into_inner().expect("the times");
    times.sort_by_key(|t| std::cmp::Reverse(t.0));
    for (time, run) in times.iter().take(5) {
        println!("{:5.1} s  {run}", time.as_secs_f64());
    }
    let mut failures = failures.into_inner().expect("the failures");
    failures.sort();
    let base_failures: Vec<_> = failures.iter().filter(|f| f.1 == "(base)").collect();
    assert!(base_failures.is_empty(), "base invocations that fail: {base_failures:#?}");

    let known = |f: &(String, String, String, String)| {
        KNOWN.iter().find(|(c, o, v, _)| *c == f.0 && *o == f.1 && (*v == "*" || *v == f.2))
    };
    let mut report = String::new();
    for f in &failures {
        let tag = known(f).map_or("NEW".to_string(), |k| format!("known: {}", k.3));
        report += &format!("kezuri {} {} {}: {} [{tag}]\n", f.0, f.1, f.2, f.3);
    }
    std::io::stdout().write_all(report.as_bytes()).ok();
    println!("{} runs, {} failures", runs.len(), failures.len());
    let new: Vec<_> = failures.iter().filter(|f| known(f).is_none()).collect();
    assert!(new.is_empty(), "{} runs end in a panic, a signal or a timeout:\n{report}", new.len());
    let stale: Vec<_> = KNOWN
        .iter()
        .filter(|(c, _, _, _)| only.is_empty() || only.contains(c))
        .filter(|(c, o, v, _)| !failures.iter().any(|f| f.0 == *c && f.1 == *o && (*v == "*" || *v == f.2)))
        .collect();
    assert!(stale.is_empty(), "known failures that no longer happen (remove them from KNOWN): {stale:#?}");
}

#[test]
fn the_search_for_numbers_that_are_not_finds_them() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let write = |name: &str, text: &str| std::fs::write(dir.path().join(name), text).expect("a file");
    write("stderr.txt", "NaN here is only a message\n");
    write("out.nc", "G01 X1.5 Y-2.\n(information: infeed 0.5)\n");
    write("stdout.txt", "{\"snap\": 1, \"nanometres\": 2}\n");
    assert_eq!(not_a_number(dir.path()), None);
    for (line, text) in [("G01 XNaN Y1.", "out.nc"), ("G01 Z-inf", "out.nc"), ("cusp inf mm", "stdout.txt")] {
        write(text, line);
        let found = not_a_number(dir.path()).unwrap_or_default();
        assert!(found.contains(line), "{line:?} in {text} not found: {found:?}");
        write(text, "G01 X1.\n");
    }
}
