//! `kezuri sim` as a user runs it: JSON keys, pictures, STL, comparison,
//! rapids into the stock, bad input.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Output;

mod common;
use common::kezuri;

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn json(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "{}", stderr(o));
    serde_json::from_str(&stdout(o)).expect("one JSON object")
}

fn write(dir: &Path, name: &str, data: &[u8]) -> String {
    let p: PathBuf = dir.join(name);
    std::fs::write(&p, data).unwrap();
    p.to_string_lossy().into_owned()
}

/// Level raster rows along X at Y = 0, 1, …, 6 and Z −1: a 1 mm pick feed.
fn raster(rows: usize) -> String {
    let mut s = String::from("G90 G21 G17\nG00 Z5.\nG00 X0. Y0.\nG01 Z-1. F600\n");
    for k in 0..rows {
        let x = if k % 2 == 0 { 10 } else { 0 };
        writeln!(s, "G01 X{x}.").unwrap();
        if k + 1 < rows {
            writeln!(s, "G01 Y{}.", k + 1).unwrap();
        }
    }
    s + "G00 Z5.\nM30\n"
}

/// A binary STL of the level plane z = `z` over a box.
fn plane_stl(x0: f64, y0: f64, x1: f64, y1: f64, z: f64) -> Vec<u8> {
    let mut out = vec![0u8; 80];
    out.extend_from_slice(&2u32.to_le_bytes());
    for t in [[[x0, y0], [x1, y0], [x1, y1]], [[x0, y0], [x1, y1], [x0, y1]]] {
        for v in [0.0, 0.0, 1.0] {
            out.extend_from_slice(&(v as f32).to_le_bytes());
        }
        for p in t {
            for v in [p[0], p[1], z] {
                out.extend_from_slice(&(v as f32).to_le_bytes());
            }
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}

#[test]
fn json_keys_and_the_trough() {
    let dir = tempfile::tempdir().unwrap();
    let nc = write(dir.path(), "line.nc", b"G90 G21\nG00 Z5.\nG00 X2. Y5.\nG01 Z-1. F300\nG01 X8.\nG00 Z5.\nM30\n");
    let v = json(&kezuri(&["sim", &nc, "--tool", "ball:4", "--res", "0.5", "--stock", "0,0,10,10,0", "--json"]));
    assert_eq!(v["cells"], 400);
    assert_eq!(v["moves"], 5);
    // The cells nearest the line are 0.25 mm off its axis.
    let want = -1.0 + 2.0 - (4.0f64 - 0.0625).sqrt();
    // Heights are kept in whole nanometres.
    assert!((v["min_z_mm"].as_f64().unwrap() - want).abs() <= 0.5e-6 + 1e-12, "{v}");
    assert_eq!(v["rapids_into_stock"], 0);
    assert!(v["first_rapid_into_stock_line"].is_null());
    assert!(v.get("max_gouge_mm").is_none());
}

#[test]
fn comparison_with_the_plane_finds_the_scallop() {
    let dir = tempfile::tempdir().unwrap();
    let nc = write(dir.path(), "raster.nc", raster(7).as_bytes());
    let stl = write(dir.path(), "plane.stl", &plane_stl(-10.0, -10.0, 20.0, 20.0, -1.0));
    let png = dir.path().join("h.png");
    let surface = dir.path().join("cut.stl");
    // Cells on the cusps: centres at 2 + 0.01·(i + ½) and y = 1 + 0.01·j
    // (the stock starts half a cell below 1).
    let o = kezuri(&[
        "sim",
        &nc,
        "--tool",
        "ball:6",
        "--res",
        "0.01",
        "--stock",
        "2,0.995,8,5.005,0",
        "--compare",
        &stl,
        "-o",
        png.to_str().unwrap(),
        "--stl",
        surface.to_str().unwrap(),
        "--json",
    ]);
    let v = json(&o);
    let h = 3.0 - (9.0f64 - 0.25).sqrt();
    let left = v["max_left_mm"].as_f64().unwrap();
    // The target is stored in f32: −1 is exact.
    // Heights are kept in whole nanometres.
    assert!((left - h).abs() <= 0.5e-6 + 1e-9, "{left} vs {h}");
    assert_eq!(v["max_gouge_mm"].as_f64().unwrap(), 0.0);
    let mean = v["mean_abs_dev_mm"].as_f64().unwrap();
    assert!(mean > 0.2 * h && mean < 0.6 * h, "{mean}");
    let counts: u64 = v["histogram"]["counts"].as_array().unwrap().iter().map(|c| c.as_u64().unwrap()).sum();
    assert_eq!(counts, v["cells"].as_u64().unwrap());
    assert_eq!(v["histogram"]["edges_mm"].as_array().unwrap().len(), 11);
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    assert_eq!(&std::fs::read(dir.path().join("h-deviation.png")).unwrap()[1..4], b"PNG");
    let cut = std::fs::read(&surface).unwrap();
    let (nx, ny) = (v["nx"].as_u64().unwrap(), v["ny"].as_u64().unwrap());
    assert_eq!(cut.len() as u64, 84 + 50 * 2 * (nx - 1) * (ny - 1));

    // The text report has the legend and the histogram.
    let o = kezuri(&[
        "sim",
        &nc,
        "--tool",
        "ball:6",
        "--res",
        "0.05",
        "--compare",
        &stl,
        "--deviation-png",
        dir.path().join("d.png").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    for want in ["max gouge", "max left", "mean |dev|", "red = below the target", "…"] {
        assert!(text.contains(want), "{want}: {text}");
    }
}

#[test]
fn a_height_grid_is_a_target_too() {
    let dir = tempfile::tempdir().unwrap();
    let nc = write(dir.path(), "raster.nc", raster(7).as_bytes());
    let mut grid = String::from("x,y,z\n");
    for j in 0..=6 {
        for i in 0..=10 {
            writeln!(grid, "{i},{j},-1.02").unwrap();
        }
    }
    let target = write(dir.path(), "grid.csv", grid.as_bytes());
    // The stock given: the program cuts above this target's top (which
    // would otherwise be the stock's).
    let v = json(&kezuri(&[
        "sim",
        &nc,
        "--tool",
        "ball:6",
        "--res",
        "0.05",
        "--stock",
        "-3,-3,13,9,0",
        "--compare",
        &target,
        "--json",
    ]));
    // Nowhere below −1: 0.02 mm left at least where the target is.
    assert_eq!(v["max_gouge_mm"].as_f64().unwrap(), 0.0);
    assert!(v["cells_without_target"].as_u64().unwrap() > 0);
    let lowest = v["deviation_range_mm"][0].as_f64().unwrap();
    // 0.02 mm, plus the ball's rise at the nearest cell centres, 0.025 mm
    // off the passes.
    assert!((0.02 - 1e-9..0.0202).contains(&lowest), "{lowest}");
}

#[test]
fn a_rapid_into_the_stock_is_reported_with_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let nc = write(
        dir.path(),
        "crash.nc",
        b"G90 G21\nG00 Z5.\nG00 X0. Y0.\nG01 Z-1. F300\nG01 X10.\nG00 Z1.\nG00 Y10.\nG00 Z-0.5\nG00 X0.\nG00 Z5.\nM30\n",
    );
    let args = ["sim", &nc, "--tool", "ball:6", "--res", "0.1", "--stock", "-5,-5,15,15,0", "--json"];
    let o = kezuri(&args);
    let v = json(&o);
    // The lift to Z1 (line 6) and the move across above the stock are air;
    // the rapid down into it and the one across inside it are not.
    assert_eq!(v["rapids_into_stock"], 2);
    assert_eq!(v["first_rapid_into_stock_line"], 8);
    assert_eq!(v["rapid_hits"][1]["line"], 9);
    assert!(stderr(&o).contains("line 8"), "{}", stderr(&o));
    let o = kezuri(&[&args[..], &["--fail-on-rapid"]].concat());
    assert_eq!(o.status.code(), Some(1));
    // Without --stock the top is the highest feed that moves in X or Y,
    // Z−1 (not Z5, where the plunge starts), and the box is the cut's,
    // Y −3 to 3: the move across at Z1 is above that stock, the later ones
    // are beyond it.
    let v = json(&kezuri(&["sim", &nc, "--tool", "ball:6", "--res", "0.1", "--json"]));
    assert_eq!(v["stock"], serde_json::json!({"x0": -3.0, "y0": -3.0, "x1": 13.0, "y1": 3.0, "top": -1.0}));
    assert_eq!(v["rapids_into_stock"], 0);
}

/// The uncut corners: without --stock the stock stood up to the
/// clearance height the program plunges from, posts in the pictures and
/// air in the volume. Its top is the target's, else the highest feed that
/// moves in X or Y; the report says which.
#[test]
fn without_stock_the_top_is_the_parts_not_the_clearance() {
    let dir = tempfile::tempdir().unwrap();
    // Plunges at the feed from Z5, rows at Z−1.
    let nc = write(dir.path(), "raster.nc", raster(7).as_bytes());
    let run = |extra: &[&str]| {
        let args = [&["sim", nc.as_str(), "--tool", "ball:6", "--res", "0.1", "--json"][..], extra].concat();
        json(&kezuri(&args))
    };
    let v = run(&[]);
    assert_eq!(v["stock_top_mm"], -1.0, "{v}");
    assert_eq!(v["stock_top_from"], "cutting-moves");
    // No posts at the clearance height: nothing stands above the rows.
    assert_eq!(v["max_z_mm"], -1.0, "{v}");
    let text = stdout(&kezuri(&["sim", &nc, "--tool", "ball:6", "--res", "0.1"]));
    assert!(text.contains("top -1 (from the feed moves)"), "{text}");
    // With a target, the target's top: the plane at Z−0.8.
    let stl = write(dir.path(), "plane.stl", &plane_stl(-10.0, -10.0, 20.0, 20.0, -0.8));
    let v = run(&["--compare", &stl]);
    assert!((v["stock_top_mm"].as_f64().unwrap() + 0.8).abs() < 1e-6, "{v}");
    assert_eq!(v["stock_top_from"], "target");
    assert!(v["max_z_mm"].as_f64().unwrap() < -0.79, "{v}");
    // A stock given is the stock.
    let v = run(&["--stock", "-5,-5,15,15,2"]);
    assert_eq!((v["stock_top_mm"].as_f64(), v["stock_top_from"].as_str()), (Some(2.0), Some("given")));
}

/// A program like plum.nc drilled: holes by G81, then a feed sideways at
/// Z−3 (line 9). The drill is the cone of v:6,118, but a drill cuts along
/// its axis only: the sideways feed in material is flagged, with its line.
#[test]
fn a_drill_fed_sideways_in_the_material_is_flagged() {
    let dir = tempfile::tempdir().unwrap();
    let nc = write(
        dir.path(),
        "drill.nc",
        b"G90 G21 G17\nT3 M06\nG00 X10. Y10. Z5.\nG81 X10. Y10. Z-5. R2. F200\nX20.\nG80\nG00 Z2.\n\
          G01 Z-3. F100\nG01 X30. F100\nG00 Z5.\nM30\n",
    );
    let sim = |tool: &str| kezuri(&["sim", &nc, "--tool", tool, "--res", "0.2", "--stock", "0,0,40,20,0", "--json"]);
    let o = sim("drill:6,118");
    let drill = json(&o);
    assert_eq!(drill["drill_side_moves"], 1, "{drill}");
    assert_eq!(drill["first_drill_side_move_line"], 9);
    assert_eq!(drill["tools"][0]["shape"], "drill:6,118");
    let err = stderr(&o);
    assert!(err.contains("1 feed move takes a drill sideways") && err.contains("line 9"), "{err}");
    // The same solid as the V-bit, which may cut sideways.
    let vee = json(&sim("v:6,118"));
    assert_eq!(vee["drill_side_moves"], 0);
    assert_eq!(vee["min_z_mm"], drill["min_z_mm"]);
    assert_eq!(vee["volume_mm3"], drill["volume_mm3"]);
    let text = stdout(&kezuri(&["sim", &nc, "--tool", "drill:6,118", "--res", "0.2", "--stock", "0,0,40,20,0"]));
    assert!(text.contains("DRILL      1 feed sideways in the material; first at line 9"), "{text}");
    // Holes alone are no warning.
    let holes =
        write(dir.path(), "holes.nc", b"G90 G21\nG00 X10. Y10. Z5.\nG81 X10. Y10. Z-5. R2. F200\nX20.\nG80\nM30\n");
    let o = kezuri(&["sim", &holes, "--tool", "drill:6,118", "--res", "0.2", "--stock", "0,0,40,20,0", "--json"]);
    assert_eq!(json(&o)["drill_side_moves"], 0);
    assert!(!stderr(&o).contains("sideways"), "{}", stderr(&o));
}

#[test]
fn bad_input_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let nc = write(dir.path(), "line.nc", b"G00 Z5.\nG01 X10. Z-1. F100\nM30\n");
    let empty = write(dir.path(), "empty.nc", b"%\nO0001\nM30\n%\n");
    let junk = write(dir.path(), "junk.txt", b"hello\nworld\n");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["sim", &nc, "--tool", "ball:6", "--res", "0"], "'--res <MM>': it must be a length from 0.000001"),
        (vec!["sim", &nc, "--tool", "ball:6", "--res", "-1"], "it must be a length"),
        (vec!["sim", &nc, "--tool", "ball:6", "--res", "NaN"], "it must be a length"),
        (vec!["sim", &nc, "--tool", "ball:-6", "--res", "0.1"], "the diameter must be a length"),
        (vec!["sim", &empty, "--tool", "ball:6", "--res", "0.1"], "no motion"),
        (vec!["sim", &nc, "--tool", "ball:6", "--res", "0.1", "--stock", "0,0,10"], "five numbers"),
        (vec!["sim", &nc, "--tool", "ball:6", "--res", "0.1", "--stock", "10,0,0,10,0"], "X0 < X1"),
        (
            vec!["sim", &nc, "--tool", "ball:6", "--res", "0.0001", "--stock", "0,0,1000,1000,0"],
            "10000000 × 10000000 = 100000000000000 cells",
        ),
        (vec!["sim", &nc, "--tool", "ball:6", "--res", "0.1", "--compare", &junk], "not an STL and not a height grid"),
        (vec!["sim", &nc, "--tool", "ball:6", "--res", "0.1", "--compare", "/no/such/file.stl"], "cannot read"),
    ];
    for (args, want) in cases {
        let o = kezuri(&args);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(want), "{args:?}: {}", stderr(&o));
        assert!(stdout(&o).is_empty(), "{args:?}");
    }
    // Bad usage: exit code 2.
    assert_eq!(kezuri(&["sim", &nc, "--tool", "ball:6", "--res"]).status.code(), Some(2));
}

#[test]
fn a_rapid_from_the_unknown_start_into_the_stock_is_caught() {
    // The first moves start wherever the machine is, so they are not
    // simulated; but G00 Z-5. ends 5 mm inside a stock whose top is 0.
    let dir = tempfile::tempdir().unwrap();
    let nc = write(dir.path(), "dive.nc", b"G21 G90\nG00 Z-5.\nX10. Y10.\nG01 Z0. F100\nX20.\nM30\n");
    let o = kezuri(&["sim", &nc, "--tool", "ball:6", "--res", "0.2", "--stock", "0,0,30,30,0", "--json"]);
    let v = json(&o);
    assert_eq!(v["rapids_into_stock"], 2);
    assert_eq!(v["first_rapid_into_stock_line"], 2);
    assert_eq!(v["unplaced_moves"], 2);
}

/// Over `--max-memory` the grid is cut in tiles: every figure of the JSON is
/// what the grid held whole gives, to the bit; only the histogram's counts
/// come from a sample of the cells.
#[test]
fn a_grid_over_the_memory_is_cut_in_tiles_to_the_same_figures() {
    let dir = tempfile::tempdir().unwrap();
    let nc = write(dir.path(), "raster.nc", raster(7).as_bytes());
    let stl = write(dir.path(), "plane.stl", &plane_stl(-10.0, -10.0, 20.0, 20.0, -1.0));
    // 600 × 401 cells, 13 bytes each with --compare: 3.1 MB.
    let run = |extra: &[&str]| {
        let args = [
            &["sim", &nc, "--tool", "ball:6", "--res", "0.01", "--stock", "2,0.995,8,5.005,0", "--compare"][..],
            &[&stl, "--json"],
            extra,
        ]
        .concat();
        json(&kezuri(&args))
    };
    let mut whole = run(&[]);
    let mut tiled = run(&["--max-memory", "1M"]);
    assert_eq!(whole["tiles"], 1);
    let tiles = tiled["tiles"].as_u64().unwrap();
    assert!(tiles >= 4, "{tiled}");
    // Each tile a pass: the sample's histogram has fewer cells.
    let count = |v: &serde_json::Value| {
        v["histogram"]["counts"].as_array().unwrap().iter().map(|c| c.as_u64().unwrap()).sum::<u64>()
    };
    assert_eq!(count(&whole), 600 * 401);
    assert!(count(&tiled) < 600 * 401 / 4, "{tiled}");
    for v in [&mut whole, &mut tiled] {
        let o = v.as_object_mut().unwrap();
        for key in ["tiles", "seconds"] {
            o.remove(key);
        }
        o["histogram"].as_object_mut().unwrap().remove("counts");
    }
    assert_eq!(whole, tiled);
    // --max-cells is --max-memory in cells of 5 bytes.
    let cells = run(&["--max-cells", "200000"]);
    assert!(cells["tiles"].as_u64().unwrap() > 1, "{cells}");
    let o = kezuri(&["sim", &nc, "--tool", "ball:6", "--max-memory", "2X"]);
    assert!(!o.status.success() && stderr(&o).contains("'2X' is not a size"), "{}", stderr(&o));
}
