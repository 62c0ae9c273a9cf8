//! Data that is not there is not a result: a thermal fit with no cold/warm
//! pair, a tool database's size that is no number, a full disk.

use std::os::unix::process::CommandExt;
use std::path::Path;
use std::process::{Command, Output};

mod common;
use common::{kezuri, path};

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs kezuri in `dir` with files limited to `bytes` (`ulimit -f`): a
/// write past it fails as a full disk does.
fn kezuri_limited(dir: &Path, bytes: u64, args: &[&str]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_kezuri"));
    c.current_dir(dir).args(args);
    // SAFETY: only setrlimit, async-signal-safe, between fork and exec.
    unsafe {
        c.pre_exec(move || {
            let limit = libc::rlimit { rlim_cur: bytes as libc::rlim_t, rlim_max: bytes as libc::rlim_t };
            if libc::setrlimit(libc::RLIMIT_FSIZE, &limit) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    c.output().expect("kezuri runs")
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> =
        std::fs::read_dir(dir).unwrap().flatten().map(|e| e.file_name().to_string_lossy().into_owned()).collect();
    v.sort();
    v
}

#[test]
fn a_thermal_fit_with_no_warm_measurement_writes_no_model() {
    let dir = tempfile::tempdir().unwrap();
    let meas = path(dir.path(), "meas.csv");
    std::fs::write(&meas, "axis,command_mm,ex_mm,ey_mm,ez_mm,state\nX,0,0,0,0,cold\nX,100,0.01,0,0,cold\n").unwrap();
    let model = path(dir.path(), "model.json");
    let o = kezuri(&["thermal", "fit", &meas, "-o", &model]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("no warm measurement (2 cold, 0 warm)"), "{}", stderr(&o));
    assert!(!Path::new(&model).exists());
    // No measurement at all is no model either.
    std::fs::write(&meas, "axis,command_mm,ex_mm,ey_mm,ez_mm\n").unwrap();
    let o = kezuri(&["thermal", "fit", &meas, "-o", &model]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(!Path::new(&model).exists());
}

#[test]
fn tool_db_list_never_prints_inf() {
    let dir = tempfile::tempdir().unwrap();
    let db = path(dir.path(), "t.sqlite");
    let csv = path(dir.path(), "p.csv");
    std::fs::write(&csv, "z_mm,radius_mm\n0,0\n0.25,0.25\n0.5,0.25\n").unwrap();
    common::ok(&kezuri(&["tool", "db", "add", "T1", &csv, "--db", &db]));
    // A size stored by another program as infinity (SQLite keeps it).
    let conn = rusqlite::Connection::open(&db).unwrap();
    conn.execute("UPDATE profile SET max_radius_mm = 1e999, tip_z_mm = -1e999", []).unwrap();
    drop(conn);
    let o = kezuri(&["tool", "db", "list", "--db", &db]);
    let (out, err) = (String::from_utf8_lossy(&o.stdout).into_owned(), stderr(&o));
    assert!(o.status.success(), "{err}");
    assert!(!out.to_lowercase().contains("inf") && !err.to_lowercase().contains("inf "), "{out}{err}");
    assert!(out.contains("T1") && err.contains("not a finite number"), "{out}{err}");
}

#[test]
fn a_full_disk_is_said_with_the_file_name_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("p.nc"), "G21 G90\nG0 X0 Y0 Z5.\nG1 Z-1. F100.\nX10. Y5.\nM30\n").unwrap();
    // A plain output: /dev/full, and a file past the size limit.
    let o = kezuri(&["view", &path(d, "p.nc"), "-o", "/dev/full"]);
    assert!(stderr(&o).contains("cannot write /dev/full: the disk is full"), "{}", stderr(&o));
    let o = kezuri_limited(d, 4096, &["view", "p.nc", "-o", "page.html"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("cannot write page.html: the file is past the size"), "{}", stderr(&o));
    assert_eq!(names(d), ["p.nc"]);
    // The tool database: a profile stored, then one more that finds no room.
    std::fs::write(d.join("p.csv"), "z_mm,radius_mm\n0,0\n0.25,0.25\n0.5,0.25\n").unwrap();
    common::ok(&kezuri_limited(d, 1 << 20, &["tool", "db", "add", "T1", "p.csv", "--db", "t.sqlite"]));
    let size = std::fs::metadata(d.join("t.sqlite")).unwrap().len();
    let o = kezuri_limited(d, size, &["tool", "db", "add", "T1", "p.csv", "--db", "t.sqlite"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("cannot write t.sqlite: the file is past the size"), "{}", stderr(&o));
    assert_eq!(names(d), ["p.csv", "p.nc", "t.sqlite"]);
    // What was stored is still there.
    let list = common::ok(&kezuri(&["tool", "db", "list", "--db", &path(d, "t.sqlite")]));
    assert!(list.lines().any(|l| l.starts_with("T1") && l.contains(" 1 ")), "{list}");
    // A new database that finds no room is no database left behind.
    let o = kezuri_limited(d, 6000, &["tool", "db", "add", "T1", "p.csv", "--db", "new.sqlite"]);
    assert!(stderr(&o).contains("cannot write new.sqlite"), "{}", stderr(&o));
    assert_eq!(names(d), ["p.csv", "p.nc", "t.sqlite"]);
}
