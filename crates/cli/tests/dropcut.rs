//! `kezuri dropcut` as a user runs it, on STL files made here.

use std::process::Output;

use kezuri_geom::{write_ascii_stl, write_binary_stl, Triangle, Vec3};

mod common;
use common::kezuri;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The plane z = 0.5·x + 1 over [0, 10]², as two triangles.
fn ramp() -> Vec<Triangle> {
    let p = |x: f64, y: f64| Vec3::new(x, y, 0.5 * x + 1.0);
    vec![Triangle::new(p(0., 0.), p(10., 0.), p(10., 10.)), Triangle::new(p(0., 0.), p(10., 10.), p(0., 10.))]
}

fn lines(o: &Output) -> Vec<Vec<f64>> {
    String::from_utf8_lossy(&o.stdout)
        .lines()
        .map(|l| l.split(' ').map(|w| w.parse().expect("a number")).collect())
        .collect()
}

#[test]
fn grid_order_precision_and_files() {
    let dir = tempfile::tempdir().unwrap();
    let stl = dir.path().join("ramp.stl");
    std::fs::write(&stl, write_binary_stl(&ramp())).unwrap();
    let stl = stl.to_str().unwrap();
    // x 2, 4.5, 7 (round(5/2.5) + 1 = 3 columns), y 3, 5.5: y outer, x inner.
    let o = kezuri(&["dropcut", stl, "--tool", "ball:2", "--grid", "2,3,7,5.5,2.5"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = lines(&o);
    let lift = (1.25f64).sqrt() - 1.0;
    let xy: Vec<(f64, f64)> = rows.iter().map(|r| (r[0], r[1])).collect();
    assert_eq!(xy, [(2.0, 3.0), (4.5, 3.0), (7.0, 3.0), (2.0, 5.5), (4.5, 5.5), (7.0, 5.5)]);
    for r in &rows {
        assert_eq!(r.len(), 3);
        assert!((r[2] - (0.5 * r[0] + 1.0 + lift)).abs() < 1e-12, "{r:?}");
    }
    // Full precision: the printed z reads back as the same f64 the library gives.
    let z = kezuri_like_library(2.0, 3.0);
    assert_eq!(rows[0][2], z);

    // -o writes the same text to a file; stdin works as the mesh.
    let out = dir.path().join("ramp.cl");
    let o2 = kezuri(&["dropcut", stl, "--tool", "ball:2", "--grid", "2,3,7,5.5,2.5", "-o", out.to_str().unwrap()]);
    assert!(o2.status.success() && o2.stdout.is_empty());
    assert_eq!(std::fs::read(&out).unwrap(), o.stdout);

    let ascii = dir.path().join("ramp_ascii.stl");
    std::fs::write(&ascii, write_ascii_stl("ramp", &ramp())).unwrap();
    let o3 = kezuri(&["dropcut", ascii.to_str().unwrap(), "--tool", "ball:2", "--grid", "2,3,7,5.5,2.5"]);
    assert_eq!(o3.stdout, o.stdout);
}

/// The z the library gives for ball:2 on the ramp at (x, y).
fn kezuri_like_library(x: f64, y: f64) -> f64 {
    use kezuri_cam::dropcut::{drop_cutter, MeshSurface};
    // Through the same f32 rounding as the binary STL.
    let tris: Vec<Triangle> = kezuri_geom::parse_stl(&write_binary_stl(&ramp())).unwrap();
    let surface = MeshSurface::new(kezuri_geom::Mesh::from_triangles(tris));
    drop_cutter(&"ball:2".parse().unwrap(), &surface, x, y).unwrap()
}

#[test]
fn points_off_the_mesh_are_left_out_or_filled_and_a_grid_off_the_mesh_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let stl = dir.path().join("ramp.stl");
    std::fs::write(&stl, write_binary_stl(&ramp())).unwrap();
    let stl = stl.to_str().unwrap();
    // x = -4, 0, 4, 8, 12, 16: the first and the last two are more than
    // the radius (1 mm) off the mesh.
    let o = kezuri(&["dropcut", stl, "--tool", "ball:2", "--grid", "-4,5,16,5,4"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let xs: Vec<f64> = lines(&o).iter().map(|r| r[0]).collect();
    assert_eq!(xs, [0.0, 4.0, 8.0]);
    assert!(stderr(&o).contains("3 of 6 grid points have no triangle"), "{}", stderr(&o));
    let o = kezuri(&["dropcut", stl, "--tool", "ball:2", "--grid", "-4,5,16,5,4", "--fill", "-7.5"]);
    let rows = lines(&o);
    assert_eq!(rows.len(), 6);
    assert_eq!((rows[0][2], rows[5][2]), (-7.5, -7.5));

    let o = kezuri(&["dropcut", stl, "--tool", "ball:2", "--grid", "50,50,60,60,1"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("lies off the mesh"), "{}", stderr(&o));
    assert!(o.stdout.is_empty());
}

#[test]
fn bad_input_is_exit_code_1_with_a_reason() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("ramp.stl");
    std::fs::write(&good, write_binary_stl(&ramp())).unwrap();
    let mut nan = write_binary_stl(&ramp());
    nan[84 + 12..84 + 16].copy_from_slice(&f32::NAN.to_le_bytes());
    let nan_path = dir.path().join("nan.stl");
    std::fs::write(&nan_path, nan).unwrap();
    let empty = dir.path().join("empty.stl");
    std::fs::write(&empty, "solid x\nendsolid x\n").unwrap();
    let short = dir.path().join("short.stl");
    std::fs::write(&short, &write_binary_stl(&ramp())[..120]).unwrap();
    let out = dir.path().join("never.cl");
    let good = good.to_str().unwrap();
    for (args, why) in [
        (vec![nan_path.to_str().unwrap(), "--tool", "ball:6", "--grid", "0,0,1,1,1"], "triangle 1 has a NaN"),
        (vec![empty.to_str().unwrap(), "--tool", "ball:6", "--grid", "0,0,1,1,1"], "empty STL"),
        (vec![short.to_str().unwrap(), "--tool", "ball:6", "--grid", "0,0,1,1,1"], "truncated"),
        (vec![good, "--tool", "ball:-3", "--grid", "0,0,1,1,1"], "the diameter must be a length"),
        (vec![good, "--tool", "ball:6", "--grid", "0,0,1,1,0"], "step must be positive"),
        (vec![good, "--tool", "ball:6", "--grid", "0,0,1"], "X0,Y0,X1,Y1,STEP"),
        (vec!["/nonexistent.stl", "--tool", "ball:6", "--grid", "0,0,1,1,1"], "cannot read"),
    ] {
        let mut a = vec!["dropcut"];
        a.extend(args.iter().copied());
        a.extend(["-o", out.to_str().unwrap()]);
        let o = kezuri(&a);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(why), "{args:?}: {}", stderr(&o));
        assert!(!out.exists());
    }
    // An oblate oval (a "spoon") is a real tool.
    let o = kezuri(&["dropcut", good, "--tool", "oval:16,4", "--grid", "5,5,5,5,1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let help = kezuri(&["dropcut", "--help"]);
    assert!(String::from_utf8_lossy(&help.stdout).contains("kezuri dropcut plum.stl --tool ball:6"));
}
