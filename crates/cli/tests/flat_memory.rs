//! Memory stays flat as programs grow: the peak resident memory of
//! `kezuri check` and `kezuri run -o` on a generated raster of 4,000,000
//! blocks is at most 16 MiB above their peak on 100,000 blocks. Each peak
//! is the child's own (`wait4`'s resource use), not a timing: the test
//! cannot pass by being fast, only by holding no more. `kezuri view` holds
//! what its page can show: as much at 500,000 blocks as at 50,000 under a
//! 1 MB page.

use std::io::Write;
use std::os::unix::process::ExitStatusExt;
use std::path::Path;
use std::process::{Command, Stdio};

/// How far apart the two peaks may be.
const MIB_APART: i64 = 16;

/// A zig-zag raster of `blocks` `X… Y… Z…` lines under G1, rows of 1,000
/// (bench/scale.sh's program).
fn raster(path: &Path, blocks: usize) {
    let mut out = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    write!(out, "%\nO1000\nG21 G90 G17\nG0 X0 Y0 Z5.\nG1 Z-1. F1200.\n").unwrap();
    for k in 0..blocks {
        let (row, i) = (k / 1000, k % 1000);
        let i = if row % 2 == 1 { 999 - i } else { i };
        writeln!(out, "X{:.3} Y{:.3} Z{:.3}", i as f64 * 0.1, row as f64 * 0.5, -1.0 - 0.001 * (k % 7) as f64).unwrap();
    }
    write!(out, "G0 Z5.\nM30\n%\n").unwrap();
}

/// `kezuri ARGS` run to its end: its exit status and its peak resident
/// memory in KiB.
// The child is waited for by `wait4`, which gives its resource use.
#[allow(clippy::zombie_processes)]
fn peak_kib(args: &[&str]) -> (i32, i64) {
    let child = Command::new(env!("CARGO_BIN_EXE_kezuri"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("kezuri runs");
    let mut status = 0;
    // SAFETY: a zeroed rusage is a valid value for wait4 to fill.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: the child is ours and not waited for elsewhere.
    let pid = unsafe { libc::wait4(child.id() as i32, &mut status, 0, &mut usage) };
    assert_eq!(pid, child.id() as i32, "waited for the child");
    let code = std::process::ExitStatus::from_raw(status).code().unwrap_or(-1);
    (code, usage.ru_maxrss)
}

#[test]
fn check_and_run_hold_as_much_at_four_million_blocks_as_at_a_hundred_thousand() {
    let dir = tempfile::tempdir().unwrap();
    let (small, large) = (dir.path().join("small.nc"), dir.path().join("large.nc"));
    raster(&small, 100_000);
    raster(&large, 4_000_000);
    let out = dir.path().join("out.nc");
    for command in [&["check"][..], &["run", "-o", out.to_str().unwrap()][..]] {
        let with = |file: &Path| {
            let args: Vec<&str> = command.iter().copied().chain([file.to_str().unwrap()]).collect();
            let (code, kib) = peak_kib(&args);
            assert_eq!(code, 0, "kezuri {args:?}");
            kib
        };
        let (a, b) = (with(&small), with(&large));
        println!("{command:?}: {} MiB at 1e5 blocks, {} MiB at 4e6", a / 1024, b / 1024);
        assert!(b - a <= MIB_APART * 1024, "{command:?}: {} KiB at 1e5 blocks, {} KiB at 4e6", a, b);
    }
}

#[test]
fn view_holds_its_page_not_its_program() {
    // The page's budget bounds what `view` holds: with a 1 MB page, half
    // a million blocks (drawn simplified) take no more than fifty thousand
    // (drawn whole, some 0.5 MB).
    let dir = tempfile::tempdir().unwrap();
    let (small, large) = (dir.path().join("small.nc"), dir.path().join("large.nc"));
    raster(&small, 50_000);
    raster(&large, 500_000);
    let page = dir.path().join("page.html");
    let with = |file: &Path| {
        let args = ["view", file.to_str().unwrap(), "--max-page-mb", "1", "-o", page.to_str().unwrap()];
        let (code, kib) = peak_kib(&args);
        assert_eq!(code, 0, "kezuri {args:?}");
        assert!(std::fs::metadata(&page).unwrap().len() <= 1_000_000);
        kib
    };
    let (a, b) = (with(&small), with(&large));
    println!("view: {} MiB at 5e4 blocks, {} MiB at 5e5", a / 1024, b / 1024);
    assert!(b - a <= MIB_APART * 1024, "view: {} KiB at 5e4 blocks, {} KiB at 5e5", a, b);
}
