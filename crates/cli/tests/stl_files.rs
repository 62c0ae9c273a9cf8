//! STL files as read by every command that takes one: the unit they are
//! drawn in (`--units mm|inch`), the model's size said, a note where it may
//! be in inches; coordinates beyond the format's range and an ASCII file
//! cut short before its `endsolid`.

use std::path::Path;

mod common;
use common::{kezuri, path};

/// An ASCII STL ramp 4 × 3 mm rising 0.5 mm (or 4 × 3 × 0.5 inches).
const RAMP: &str = "solid ramp\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 4 0 0\nvertex 4 3 0.5\nendloop\n\
                    endfacet\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 4 3 0.5\nvertex 0 3 0\nendloop\n\
                    endfacet\nendsolid ramp\n";

const PROGRAM: &str = "G21 G90 G17\nG0 X0 Y0 Z5.\nG1 Z-0.5 F300.\nX100. Y75.\nG0 Z5.\nM30\n";

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Every command reading an STL, the model `stl` in `units` (none: the
/// default, mm).
fn commands(dir: &Path, stl: &str, units: Option<&str>) -> Vec<Vec<String>> {
    let nc = path(dir, "p.nc");
    std::fs::write(&nc, PROGRAM).unwrap();
    let prof = path(dir, "t.csv");
    std::fs::write(&prof, "z_mm,radius_mm\n0,0\n0.25,0.25\n").unwrap();
    let out = |n: &str| path(dir, n);
    let units = units.map(|u| ["--units".to_string(), u.to_string()]);
    let words = |w: &[&str]| w.iter().map(|s| s.to_string()).chain(units.clone().into_iter().flatten()).collect();
    vec![
        words(&["dropcut", stl, "--tool", "ball:2", "--grid", "0,0,4,3,1", "-o", &out("a.cl")]),
        words(&["mill", stl, "--tool", "ball:2", "--stepover", "1", "-o", &out("m.nc")]),
        words(&["probe", "simulate", stl, "--count", "3,3", "--pitch", "1", "--stylus", "ball:2", "-o", &out("d.txt")]),
        words(&["sim", &nc, "--res", "1", "--tool", "ball:2", "--compare", stl, "-o", &out("s.png")]),
        words(&["view", &nc, "--sim", "--res", "1", "--tool", "ball:2", "--compare", stl, "-o", &out("v.html")]),
        words(&[
            "wear",
            "apply",
            &nc,
            "--profile",
            &prof,
            "--nominal",
            "ball:0.5",
            "--surface",
            stl,
            "-o",
            &out("w.nc"),
        ]),
    ]
}

#[test]
fn every_stl_reader_takes_units_and_says_the_model_size() {
    let dir = tempfile::tempdir().unwrap();
    let stl = path(dir.path(), "ramp.stl");
    std::fs::write(&stl, RAMP).unwrap();
    for args in commands(dir.path(), &stl, None) {
        let o = kezuri(&args.iter().map(String::as_str).collect::<Vec<_>>());
        let err = stderr(&o);
        assert!(err.contains("model: 4.0 × 3.0 × 0.5 mm"), "{args:?}: {err}");
        assert!(err.contains("under 13 mm in every direction") && err.contains("--units inch"), "{args:?}: {err}");
    }
    // A unit given is a unit known: no note that it may be inches.
    for args in commands(dir.path(), &stl, Some("mm")) {
        let err = stderr(&kezuri(&args.iter().map(String::as_str).collect::<Vec<_>>()));
        assert!(err.contains("model: 4.0 × 3.0 × 0.5 mm") && !err.contains("under 13 mm"), "{args:?}: {err}");
    }
    for args in commands(dir.path(), &stl, Some("inch")) {
        let o = kezuri(&args.iter().map(String::as_str).collect::<Vec<_>>());
        let err = stderr(&o);
        assert!(err.contains("model: 101.6 × 76.2 × 12.7 mm (from inches)"), "{args:?}: {err}");
        assert!(!err.contains("under 13 mm"), "{args:?}: {err}");
    }
    // The inches are in the result: the drop-cutter grid reaches X100.
    let cl = path(dir.path(), "in.cl");
    let o = kezuri(&["dropcut", &stl, "--units", "inch", "--tool", "ball:2", "--grid", "0,0,100,75,25", "-o", &cl]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&cl).unwrap();
    assert!(text.lines().any(|l| l.starts_with("100")), "{text}");
}

#[test]
fn a_coordinate_beyond_the_format_is_a_located_error() {
    let dir = tempfile::tempdir().unwrap();
    let stl = path(dir.path(), "far.stl");
    std::fs::write(&stl, RAMP.replacen("vertex 4 0 0", "vertex 1e300 0 0", 1)).unwrap();
    for args in commands(dir.path(), &stl, None) {
        let o = kezuri(&args.iter().map(String::as_str).collect::<Vec<_>>());
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
        assert!(
            err.contains(&format!("{stl}:5:8: '1e300' is beyond the range of an STL coordinate")),
            "{args:?}: {err}"
        );
        assert!(!err.contains("degenerate"), "{args:?}: {err}");
    }
}

#[test]
fn an_ascii_stl_without_endsolid_is_said_to_be_cut_short() {
    let dir = tempfile::tempdir().unwrap();
    let stl = path(dir.path(), "cut.stl");
    std::fs::write(&stl, RAMP.replace("endsolid ramp\n", "")).unwrap();
    for args in commands(dir.path(), &stl, None) {
        let o = kezuri(&args.iter().map(String::as_str).collect::<Vec<_>>());
        let err = stderr(&o);
        assert!(
            err.contains("without its `endsolid` line: the file may be cut short (2 triangles read)"),
            "{args:?}: {err}"
        );
    }
    // A whole file says nothing of it.
    std::fs::write(&stl, RAMP).unwrap();
    let o = kezuri(&["dropcut", &stl, "--tool", "ball:2", "--grid", "0,0,4,3,1"]);
    assert!(!stderr(&o).contains("endsolid"));
}
