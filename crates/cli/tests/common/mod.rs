//! What every test of the binary needs: run it, require success, name a
//! file in a folder. Each test crate uses its own part of it.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// Runs the `kezuri` binary with `args`.
pub fn kezuri(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_kezuri")).args(args).output().expect("kezuri runs")
}

/// The standard output of a run that must have succeeded.
pub fn ok(o: &Output) -> String {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// `dir/name` as a string for an argument.
pub fn path(dir: &Path, name: &str) -> String {
    dir.join(name).to_string_lossy().into_owned()
}

/// The end points of the feed moves of program `nc`, in order, from
/// `kezuri run --emit csv`.
pub fn feed_points(nc: &str) -> Vec<[f64; 3]> {
    let csv = ok(&kezuri(&["run", nc, "--emit", "csv"]));
    csv.lines()
        .skip(1)
        .filter(|l| l.split(',').nth(1) == Some("feed"))
        .map(|l| {
            let f: Vec<f64> = l.split(',').skip(2).take(3).map(|v| v.parse().unwrap()).collect();
            [f[0], f[1], f[2]]
        })
        .collect()
}
