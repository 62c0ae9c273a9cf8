//! Output files: a command's outputs are written all together or not at
//! all, through links, never over a file the user may not write, and no
//! temporary file is left on a failure or a signal.

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

mod common;
use common::{kezuri, ok, path};

/// A short program with a DPRNT line (an output of its own with --dprnt).
const PROGRAM: &str = "O0001\nG21 G90 G17\nG0 X0. Y0. Z5.\nG1 Z-1. F100.\nG1 X10. Y5.\n#100=2.5\nPOPEN\n\
                       DPRNT[DEPTH*#100[43]]\nPCLOS\nG0 Z5.\nM30\n";

fn program(dir: &Path) -> String {
    let p = path(dir, "p.nc");
    std::fs::write(&p, PROGRAM).unwrap();
    p
}

fn read(p: &str) -> String {
    std::fs::read_to_string(p).unwrap_or_default()
}

fn err(o: &std::process::Output) -> String {
    assert!(!o.status.success(), "should have failed");
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The temporary files left in `dir`.
fn temporaries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect()
}

#[test]
fn a_failing_output_leaves_every_old_file() {
    let dir = tempfile::tempdir().unwrap();
    let p = program(dir.path());
    let old = |name: &str| {
        let f = path(dir.path(), name);
        std::fs::write(&f, "old\n").unwrap();
        f
    };
    let missing = "/nonexistent/folder/x.out";
    // The program, then the drawing that cannot be written.
    let nc = old("a.nc");
    let e = err(&kezuri(&["run", &p, "-o", &nc, "--svg", missing]));
    // The error names no temporary file (the input's own folder, a
    // tempdir, is named by the dialect line).
    let error = e.lines().find(|l| l.starts_with("error:")).unwrap_or_default();
    assert!(error.contains(missing) && !error.contains(".tmp"), "{e}");
    assert_eq!(read(&nc), "old\n");
    // The DPRNT file, then the program.
    let d = old("d.txt");
    err(&kezuri(&["run", &p, "--dprnt", &d, "-o", missing]));
    assert_eq!(read(&d), "old\n");
    // The simulation's picture, then its STL.
    let png = old("a.png");
    err(&kezuri(&["sim", &p, "--tool", "flat:2", "--res", "0.5", "-o", &png, "--stl", missing]));
    assert_eq!(read(&png), "old\n");
    // The relief's program, then its surface.
    let picture = path(dir.path(), "r.png");
    image::GrayImage::from_fn(8, 8, |c, r| image::Luma([(c * 30 + r) as u8])).save(&picture).unwrap();
    let relief = ["relief", &picture, "--pixel", "1", "--depth", "1", "--tool", "ball:2", "--stepover", "1"];
    err(&kezuri(&[&relief[..], &["-o", &nc, "--surface-stl", missing]].concat()));
    assert_eq!(read(&nc), "old\n");
    // probe export: three files, then one that cannot be written.
    let data = path(dir.path(), "grid.csv");
    let grid: String = (0..9).map(|k| format!("{},{},{}\n", k % 3, k / 3, k)).collect();
    std::fs::write(&data, format!("x,y,z\n{grid}")).unwrap();
    let (dxf, stl, png2) = (old("g.dxf"), old("g.stl"), old("g.png"));
    err(&kezuri(&["probe", "export", &data, "--dxf", &dxf, "--stl", &stl, "--png", &png2, "--csv", missing]));
    assert!([&dxf, &stl, &png2].iter().all(|f| read(f) == "old\n"));
    assert!(temporaries(dir.path()).is_empty(), "{:?}", temporaries(dir.path()));
}

#[test]
fn a_link_is_written_through_and_stays_a_link() {
    let dir = tempfile::tempdir().unwrap();
    let p = program(dir.path());
    let (link, real) = (path(dir.path(), "link.nc"), path(dir.path(), "real.nc"));
    std::fs::write(&real, "old\n").unwrap();
    std::os::unix::fs::symlink("real.nc", &link).unwrap();
    ok(&kezuri(&["run", &p, "-o", &link]));
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink(), "the link is a link");
    assert!(read(&real).contains("X10. Y5."), "{}", read(&real));
}

#[test]
fn a_file_the_user_may_not_write_is_refused() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    std::fs::set_permissions(dir.path(), std::fs::Permissions::from_mode(0o777)).unwrap();
    let p = program(dir.path());
    let ro = path(dir.path(), "ro.nc");
    std::fs::write(&ro, "old\n").unwrap();
    std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o444)).unwrap();
    let bin = env!("CARGO_BIN_EXE_kezuri");
    // SAFETY: geteuid has no preconditions.
    let o = if unsafe { geteuid() } == 0 {
        // Root may write anything: run as nobody.
        let as_nobody = Command::new("setpriv")
            .args(["--reuid=nobody", "--regid=nogroup", "--clear-groups", bin, "run", &p, "-o", &ro])
            .output();
        match as_nobody {
            Ok(o) if !String::from_utf8_lossy(&o.stderr).contains("setpriv:") => o,
            _ => {
                eprintln!("skipped: running as root, and setpriv cannot run kezuri as nobody");
                return;
            }
        }
    } else {
        kezuri(&["run", &p, "-o", &ro])
    };
    let e = err(&o);
    assert!(e.contains(&ro) && e.contains("read-only"), "{e}");
    assert_eq!(read(&ro), "old\n");
    assert!(temporaries(dir.path()).is_empty());
}

extern "C" {
    fn geteuid() -> u32;
}

/// `kezuri run` writing its program into the named pipe `fifo` (it waits
/// there for a reader) after its other outputs are staged.
fn blocked_on_pipe(dir: &Path, extra: &[&str]) -> (Child, String) {
    let p = program(dir);
    let fifo = path(dir, "pipe.nc");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let mut child = Command::new(env!("CARGO_BIN_EXE_kezuri"))
        .args([&["run", &p, "-o", &fifo][..], extra].concat())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    while temporaries(dir).len() < extra.len() / 2 {
        if t0.elapsed() > Duration::from_secs(20) {
            child.kill().ok();
            panic!("the outputs were never staged");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    (child, fifo)
}

#[test]
fn temporary_files_are_removed_on_ctrl_c_and_sigterm() {
    for signal in ["-INT", "-TERM"] {
        let dir = tempfile::tempdir().unwrap();
        let svg = path(dir.path(), "a.svg");
        std::fs::write(&svg, "old\n").unwrap();
        let (mut child, _) = blocked_on_pipe(dir.path(), &["--svg", &svg]);
        assert!(Command::new("kill").args([signal, &child.id().to_string()]).status().unwrap().success());
        let status = child.wait().unwrap();
        assert!(!status.success(), "{signal}: {status}");
        assert!(temporaries(dir.path()).is_empty(), "{signal}: {:?}", temporaries(dir.path()));
        assert_eq!(read(&svg), "old\n", "{signal}");
    }
}

#[test]
fn a_failure_between_the_renames_names_what_was_replaced() {
    let dir = tempfile::tempdir().unwrap();
    let (d, svg) = (path(dir.path(), "d.txt"), path(dir.path(), "b.svg"));
    let (child, fifo) = blocked_on_pipe(dir.path(), &["--dprnt", &d, "--svg", &svg]);
    // While the program waits at the pipe, the drawing's name becomes a
    // folder with a file in it: its rename fails after the DPRNT file's.
    std::fs::create_dir(&svg).unwrap();
    std::fs::write(Path::new(&svg).join("x"), "x").unwrap();
    let mut program = String::new();
    std::io::Read::read_to_string(&mut std::fs::File::open(&fifo).unwrap(), &mut program).unwrap();
    assert!(program.contains("X10. Y5."), "{program}");
    let e = err(&child.wait_with_output().unwrap());
    assert!(e.contains(&format!("cannot write {svg}")) && e.contains(&format!("{d} written already")), "{e}");
    assert_eq!(read(&d), "DEPTH 2.500\n");
    assert!(temporaries(dir.path()).is_empty(), "{:?}", temporaries(dir.path()));
}

#[test]
fn a_split_job_refuses_the_parts_an_earlier_longer_one_left() {
    use std::fmt::Write as _;
    let dir = tempfile::tempdir().unwrap();
    // A pocket in a flat top, 21 × 15 readings 1 mm apart.
    let mut text = String::from("0,0\n");
    for k in 0..21 * 15 {
        let (i, j) = ((k % 21) as f64, (k / 21) as f64);
        let r = ((i - 10.0).powi(2) + (j - 7.0).powi(2)).sqrt();
        writeln!(text, "{},{:.4}", k + 1, 19.16 - if r < 5.0 { (25.0 - r * r).sqrt() * 0.6 } else { 0.0 }).unwrap();
    }
    let data = path(dir.path(), "ume.txt");
    std::fs::write(&data, &text).unwrap();
    let nc = path(dir.path(), "ume.nc");
    let mill = |extra: &[&str]| {
        let fixed = ["probe", "mill", &data, "--count", "21,15", "--pitch", "1", "--step", "0.25"];
        kezuri(&[&fixed[..], &["--stylus", "ball:10", "--tool", "ball:10", "-o", &nc], extra].concat())
    };
    ok(&mill(&[]));
    let whole = read(&nc).len();
    let parts = |dir: &Path| {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.starts_with("ume-"))
            .collect();
        names.sort();
        names
    };
    ok(&mill(&["--split-bytes", &(whole / 3).to_string()]));
    let three = parts(dir.path());
    assert!(three.len() >= 4, "{three:?}");
    let before: Vec<String> = three.iter().map(|n| read(&path(dir.path(), n))).collect();
    // Fewer, larger parts: the last ones of the earlier job would be left.
    let fewer = (whole / 2).to_string();
    let e = err(&mill(&["--split-bytes", &fewer]));
    let last = three.last().unwrap();
    assert!(e.contains(last.as_str()) && e.contains("--overwrite-parts"), "{e}");
    let after: Vec<String> = three.iter().map(|n| read(&path(dir.path(), n))).collect();
    assert_eq!(before, after, "nothing is written");
    ok(&mill(&["--split-bytes", &fewer, "--overwrite-parts"]));
    let now = parts(dir.path());
    assert!(now.len() < three.len() && !now.contains(last), "{now:?}");
    // One part (the whole program in ume.nc): every earlier part is in the way.
    let e = err(&mill(&["--split-bytes", &(2 * whole).to_string()]));
    assert!(now.iter().all(|n| e.contains(n.as_str())), "{e}");
}
