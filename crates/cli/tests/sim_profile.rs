//! `kezuri sim --profile`: simulating with a measured tool.

use std::path::{Path, PathBuf};
use std::process::Output;

mod common;
use common::kezuri;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn json(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "{}", stderr(o));
    serde_json::from_str(&String::from_utf8_lossy(&o.stdout)).expect("one JSON object")
}

fn write(dir: &Path, name: &str, data: &str) -> String {
    let p: PathBuf = dir.join(name);
    std::fs::write(&p, data).unwrap();
    p.to_string_lossy().into_owned()
}

/// A line along X at Y 5, Z −1, and a plunge beside it to Z −1.5.
const PROGRAM: &str = "G90 G21\nG00 Z5.\nG00 X2. Y5.\nG01 Z-1. F300\nG01 X8.\nG00 Z5.\nG00 X5. Y8.\n\
G01 Z-1.5\nG00 Z5.\nM30\n";

#[test]
fn a_cylinder_profile_cuts_as_the_flat_end_mill() {
    let dir = tempfile::tempdir().unwrap();
    let nc = write(dir.path(), "part.nc", PROGRAM);
    // A 2 mm flat end mill as measured: radius 1 from the tip up.
    let csv = write(dir.path(), "flat.csv", "z_mm,radius_mm\n0,1\n3,1\n");
    let common = ["--res", "0.25", "--stock", "0,0,10,10,0", "--json"];
    let mut with_profile = vec!["sim", nc.as_str(), "--profile", csv.as_str()];
    with_profile.extend(common);
    let mut with_spec = vec!["sim", nc.as_str(), "--tool", "flat:2"];
    with_spec.extend(common);
    let (p, f) = (json(&kezuri(&with_profile)), json(&kezuri(&with_spec)));
    for key in ["cells", "moves", "segments", "min_z_mm", "max_z_mm", "rapids_into_stock"] {
        assert_eq!(p[key], f[key], "{key}: {p} vs {f}");
    }
    assert_eq!(p["min_z_mm"], -1.5);
    assert_eq!(p["tool"], format!("profile:{csv}"));
    assert_eq!(p["tool_profile"]["samples"], 2);
    assert_eq!(p["tool_profile"]["diameter_mm"], 2.0);
    assert_eq!(p["tool_profile"]["tip_mm"], 0.0);
    assert_eq!(f["tool"], "flat:2");
    assert!(f.get("tool_profile").is_none());
}

#[test]
fn a_worn_tip_cuts_less_deep_and_the_default_stock_grows_by_the_widest_radius() {
    let dir = tempfile::tempdir().unwrap();
    let nc = write(dir.path(), "part.nc", PROGRAM);
    // Worn back 0.1 mm at the tip, a 1 mm flat there, then a 45° flank
    // out to radius 1.5 (a chamfer mill of sorts), a narrower waist above.
    let csv = write(dir.path(), "worn.csv", "z_mm,radius_mm,wear_mm\n0.1,0.5,0\n1.1,1.5,0\n1.5,1.2,0\n3,1.5,0\n");
    let v = json(&kezuri(&["sim", &nc, "--profile", &csv, "--res", "0.25", "--json"]));
    assert_eq!(v["min_z_mm"], -1.4);
    // The cutting moves span X 2…8, Y 5…8, Z −1.5…5 (the rapids are not
    // counted): grown by 1.5.
    assert_eq!(v["stock"]["x0"], 0.5);
    assert_eq!(v["stock"]["x1"], 9.5);
    assert_eq!(v["stock"]["y0"], 3.5);
    assert_eq!(v["stock"]["y1"], 9.5);
    assert_eq!(v["tool_profile"]["tip_mm"], 0.1);
    assert_eq!(v["tool_profile"]["diameter_mm"], 3.0);
    assert_eq!(v["rapids_into_stock"], 0);
}

#[test]
fn pictures_and_text_with_a_profile() {
    let dir = tempfile::tempdir().unwrap();
    let nc = write(dir.path(), "part.nc", PROGRAM);
    let csv = write(dir.path(), "ball.csv", "z_mm,radius_mm\n0,0\n0.1,0.4359\n0.5,0.8660\n1,1\n2,1\n");
    let png = dir.path().join("cut.png").to_string_lossy().into_owned();
    let stl = dir.path().join("cut.stl").to_string_lossy().into_owned();
    let o = kezuri(&["sim", &nc, "--profile", &csv, "--res", "0.25", "-o", &png, "--stl", &stl]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains(&format!("profile:{csv} (measured: Ø2.0000, tip at 0.0000, 5 samples)")), "{text}");
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    assert!(std::fs::metadata(&stl).unwrap().len() > 84);
}

#[test]
fn exactly_one_tool_and_a_bad_profile_is_refused_with_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let nc = write(dir.path(), "part.nc", PROGRAM);
    let csv = write(dir.path(), "p.csv", "z_mm,radius_mm\n0,0\n1,1\n");
    let both = kezuri(&["sim", &nc, "--tool", "ball:2", "--profile", &csv, "--res", "0.5"]);
    assert!(!both.status.success());
    assert!(stderr(&both).contains("--profile"), "{}", stderr(&both));
    let neither = kezuri(&["sim", &nc, "--res", "0.5"]);
    assert!(!neither.status.success());
    assert!(stderr(&neither).contains("--tool"), "{}", stderr(&neither));
    let bad = write(dir.path(), "bad.csv", "z_mm,radius_mm\n0,0\n1,1\n1,2\n");
    let o = kezuri(&["sim", &nc, "--profile", &bad, "--res", "0.5"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("line 4"), "{}", stderr(&o));
    let missing = kezuri(&["sim", &nc, "--profile", "/nonexistent/p.csv", "--res", "0.5"]);
    assert!(!missing.status.success());
}
