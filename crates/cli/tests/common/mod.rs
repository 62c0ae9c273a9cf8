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
