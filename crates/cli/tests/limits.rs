//! No input makes kezuri panic or run away: each size a user can ask for is
//! refused with its figure before the work starts, and no NaN or infinity is
//! written. Every case here is quick because a refusal comes first.

mod common;

use common::{kezuri, path};
use std::process::Output;

/// A run that must fail with exit 1 (an error, never a panic's 101) and
/// say `words` on stderr.
fn refused(o: &Output, words: &str) {
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.code() == Some(1) || o.status.code() == Some(2), "exit {:?}: {e}", o.status.code());
    assert!(e.contains(words), "wanted '{words}' in: {e}");
    assert!(!e.contains("panicked"), "{e}");
}

/// A small program cutting one line, in `dir`.
fn program(dir: &std::path::Path) -> String {
    let nc = path(dir, "p.nc");
    std::fs::write(&nc, "G90 G21\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10 Y5\nM30\n").unwrap();
    nc
}

#[test]
fn a_fit_of_one_cold_and_warm_pair_is_a_constant() {
    let dir = tempfile::tempdir().unwrap();
    let meas = path(dir.path(), "one.csv");
    std::fs::write(&meas, "axis,command_mm,ex_mm,ey_mm,ez_mm,state\nX,1,0,0,0,cold\nX,1,0.01,0,0,warm\n").unwrap();
    let model = path(dir.path(), "model.json");
    let o = kezuri(&["thermal", "fit", &meas, "-o", &model]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&model).unwrap()).unwrap();
    assert_eq!(v["functions"][0]["degree"], 0, "{v}");
}

#[test]
fn a_capture_timeout_beyond_a_day_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let data = path(dir.path(), "x.dat");
    let o = kezuri(&["probe", "capture", "--port", "/nonexistent", "--count", "2,2", "-o", &data, "--timeout", "1e20"]);
    refused(&o, "at most 86400 s");
}

#[test]
fn histogram_bins_are_bounded() {
    let dir = tempfile::tempdir().unwrap();
    let nc = program(dir.path());
    let o = kezuri(&["sim", &nc, "--tool", "ball:2", "--res", "0.1", "--bins", "18446744073709551615"]);
    refused(&o, "--bins");
}
