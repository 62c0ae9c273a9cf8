//! `sim` and `view --sim` without `--res`: the cell size they take, said
//! on standard error and in `sim --json`'s `res_mm`.

mod common;
use common::{kezuri, ok, path};

/// A groove along X at Z −1, 10 mm long.
const GROOVE: &[u8] = b"G90 G21\nG00 X0 Y0 Z5.\nG01 Z-1. F300\nG01 X10.\nG00 Z5.\nM30\n";

fn res_mm(args: &[&str]) -> (f64, String) {
    let o = kezuri(args);
    let json: serde_json::Value = serde_json::from_str(&ok(&o)).expect("one JSON object");
    (json["res_mm"].as_f64().expect("res_mm"), String::from_utf8_lossy(&o.stderr).into_owned())
}

#[test]
fn sim_without_res_takes_a_tenth_of_the_smallest_radius_at_most_a_tenth_of_a_millimetre() {
    let dir = tempfile::tempdir().unwrap();
    let nc = path(dir.path(), "groove.nc");
    std::fs::write(&nc, GROOVE).unwrap();
    // ball:6: 0.3 mm would be a tenth of the radius; 0.1 mm at most.
    let (res, said) = res_mm(&["sim", &nc, "--tool", "ball:6", "--json"]);
    assert_eq!(res, 0.1);
    assert!(said.contains("cells of 0.1 mm (no --res: a tenth of the smallest cutter's radius"), "{said}");
    // ball:0.5: a tenth of its 0.25 mm radius.
    let (res, _) = res_mm(&["sim", &nc, "--tool", "ball:0.5", "--json"]);
    assert!((res - 0.025).abs() < 1e-12, "{res}");
    // --res given: taken as given, nothing said.
    let (res, said) = res_mm(&["sim", &nc, "--tool", "ball:6", "--res", "0.5", "--json"]);
    assert_eq!(res, 0.5);
    assert!(!said.contains("no --res"), "{said}");
    // A stock of 1 m²: 0.1 mm cells would be 100 million; coarser, within 16 million.
    let (res, said) = res_mm(&["sim", &nc, "--tool", "ball:6", "--stock", "0,0,1000,1000,0", "--json"]);
    assert_eq!(res, 0.25, "{said}");
}

#[test]
fn view_sim_without_res_draws_the_part() {
    let dir = tempfile::tempdir().unwrap();
    let nc = path(dir.path(), "groove.nc");
    std::fs::write(&nc, GROOVE).unwrap();
    let html = path(dir.path(), "groove.html");
    let o = kezuri(&["view", &nc, "--sim", "--tool", "ball:6", "-o", &html]);
    ok(&o);
    let said = String::from_utf8_lossy(&o.stderr);
    assert!(said.contains("cells of 0.1 mm") && said.contains("and the simulated part"), "{said}");
    // --res without --sim is still bad usage.
    assert_eq!(kezuri(&["view", &nc, "--res", "0.1", "-o", &html]).status.code(), Some(2));
}
