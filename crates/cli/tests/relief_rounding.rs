//! `kezuri relief` rounds to the output's last digit on the safe side: for
//! every cutter, at 2 and 3 decimals and in RML-1's 0.01 mm steps, the
//! carving `kezuri sim` makes of the written program cuts no deeper into
//! the relief than the path band (`--gouge-tol 0.001`). The plum sketch at 20 mm has
//! flanks as steep as a 2 mm flat cutter's rim can meet: written at 0.01
//! mm, the straight moves between neighbouring positions cut up to 0.035 mm
//! into them before the heights there were lifted.

mod common;
use common::{kezuri, ok, path};

/// The band: the written program's deepest cut into the relief.
const BAND: f64 = 0.001;

fn deepest_cut(tool: &str) {
    let dir = tempfile::tempdir().unwrap();
    let sketch = concat!(env!("CARGO_MANIFEST_DIR"), "/../../samples/plum-sketch.png");
    let stl = path(dir.path(), "plum.stl");
    // The tightest allowance relief takes, so that rounding is what is tried.
    let relief = [
        "relief",
        sketch,
        "--width",
        "20",
        "--depth",
        "3",
        "--tool",
        tool,
        "--stepover",
        "0.5",
        "--gouge-tol",
        "0.001",
    ];
    let mut found = Vec::new();
    for output in [&["--digits", "2"][..], &["--digits", "3"], &["--to", "rml"]] {
        let written = path(dir.path(), "plum.out");
        ok(&kezuri(&[&relief[..], output, &["--surface-stl", &stl, "-o", &written]].concat()));
        let nc = if output[0] == "--to" {
            let nc = path(dir.path(), "plum.nc");
            ok(&kezuri(&["convert", &written, "--safe-z", "5", "-o", &nc]));
            nc
        } else {
            written
        };
        let sim = ok(&kezuri(&["sim", &nc, "--tool", tool, "--res", "0.05", "--compare", &stl, "--json"]));
        let v: serde_json::Value = serde_json::from_str(&sim).expect("JSON");
        found.push((output.join(" "), v["max_gouge_mm"].as_f64().unwrap(), v["max_gouge_at"].clone()));
    }
    assert!(found.iter().all(|f| f.1 <= BAND), "{tool}: {found:?}");
}

#[test]
fn flat() {
    deepest_cut("flat:2");
}

#[test]
fn ball() {
    deepest_cut("ball:3");
}

#[test]
fn bull() {
    deepest_cut("bull:3,0.5");
}

#[test]
fn v_bit() {
    deepest_cut("v:3,90");
}
