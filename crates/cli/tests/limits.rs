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
    std::fs::write(&nc, "G90 G21\nG0 X0. Y0. Z5.\nG1 Z-1. F100.\nG1 X10. Y5.\nM30\n").unwrap();
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

#[test]
fn lengths_from_a_nanometre_to_a_kilometre() {
    let dir = tempfile::tempdir().unwrap();
    let out = path(dir.path(), "plan.nc");
    for (args, words) in [
        (
            &[
                "probe", "plan", "--origin", "0,0", "--count", "3,3", "--pitch", "1e-300", "--safe-z", "5", "--plunge",
                "1",
            ][..],
            "'--pitch <MM>': it must be a length from 0.000001 to 1000000 mm, got 1e-300",
        ),
        (
            &["probe", "plan", "--origin", "0,0", "--count", "3,3", "--pitch", "NaN", "--safe-z", "5", "--plunge", "1"],
            "'NaN' for '--pitch <MM>'",
        ),
        (
            &["probe", "plan", "--origin", "0,0", "--count", "3,3", "--pitch", "1", "--safe-z", "inf", "--plunge", "1"],
            "coordinate from -1000000 to 1000000 mm, got inf",
        ),
        (
            &["probe", "simulate", "model.stl", "--count", "3,3", "--pitch", "1e-300", "--stylus", "ball:1"],
            "'--pitch <MM>': it must be a length",
        ),
        (
            &["probe", "capture", "--port", "/dev/null", "--count", "3,3", "--pitch", "1e-300"],
            "'--pitch <P>': it must be a length",
        ),
        (&["probe", "capture", "--port", "/dev/null", "--count", "3,3", "--channel", "100"], "'--channel <N>'"),
    ] {
        let o = kezuri(&[args, &["-o", &out]].concat());
        refused(&o, words);
    }
    let stl = path(dir.path(), "flat.stl");
    std::fs::write(&stl, "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid s\n").unwrap();
    let o = kezuri(&["dropcut", &stl, "--tool", "ball:1e-300", "--grid", "0,0,1,1,0.5"]);
    refused(&o, "the diameter must be a length from 0.000001");
}

#[test]
fn dropcut_points_are_counted_before_the_work() {
    // The points are written as they are dropped (memory does not grow
    // with the grid), but a grid is still bounded: 1/0.00005 + 1 = 20,001
    // points a side, 4.0e8 in all, over the 100 million allowed.
    let dir = tempfile::tempdir().unwrap();
    let stl = path(dir.path(), "flat.stl");
    std::fs::write(&stl, "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid s\n").unwrap();
    let o = kezuri(&["dropcut", &stl, "--tool", "ball:1", "--grid", "0,0,1,1,0.00005"]);
    refused(&o, "the grid has 20001 x 20001 points, more than 100 million");
}

/// A binary STL of two triangles: a 50 mm square ramp.
fn square(dir: &std::path::Path) -> String {
    let stl = path(dir, "square.stl");
    let mut b = vec![0u8; 80];
    b.extend(2u32.to_le_bytes());
    for t in [
        [[0.0f32, 0.0, 0.0], [50.0, 0.0, 0.0], [50.0, 50.0, 1.0]],
        [[0.0, 0.0, 0.0], [50.0, 50.0, 1.0], [0.0, 50.0, 1.0]],
    ] {
        b.extend([0f32; 3].iter().chain(t.iter().flatten()).flat_map(|v| v.to_le_bytes()));
        b.extend([0, 0]);
    }
    std::fs::write(&stl, b).unwrap();
    stl
}

#[test]
fn a_cusp_height_is_weighed_by_its_rows_before_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let stl = square(dir.path());
    let nc = path(dir.path(), "m.nc");
    let t = std::time::Instant::now();
    let args =
        ["mill", &stl, "--tool", "ball:6", "--stepover", "1", "--cusp", "1e-6", "--step", "0.001", "--safe-z", "10"];
    let o = kezuri(&[&args[..], &["-o", &nc]].concat());
    refused(&o, "10208 rows (the pick feed of the cusp height on the flat");
    assert!(t.elapsed().as_secs() < 5, "{:?}", t.elapsed());
}

#[test]
fn texture_knots_are_weighed_by_the_travel_before_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let nc = program(dir.path());
    let out = path(dir.path(), "t.nc");
    let o = kezuri(&["texture", &nc, "--seed", "1", "--segment", "1e-6", "-o", &out]);
    refused(&o, "--segment 0.000001 mm: 11 mm of cutting travel would make 1.118e7 knots, more than 10 million");
}

/// A PNG of a few bytes whose header declares `w` × `h` pixels.
fn declared_png(file: &str, w: u32, h: u32) {
    let mut png = Vec::new();
    image::GrayImage::new(8, 8).write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png).unwrap();
    png[16..20].copy_from_slice(&w.to_be_bytes());
    png[20..24].copy_from_slice(&h.to_be_bytes());
    // The IHDR chunk's CRC-32, over its type and data.
    let mut crc = !0u32;
    for &b in &png[12..29] {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 { (crc >> 1) ^ 0xEDB8_8320 } else { crc >> 1 };
        }
    }
    png[29..33].copy_from_slice(&(!crc).to_be_bytes());
    std::fs::write(file, png).unwrap();
}

#[test]
fn relief_smoothing_is_weighed_from_the_pictures_header() {
    let dir = tempfile::tempdir().unwrap();
    let png = path(dir.path(), "huge.png");
    declared_png(&png, 7900, 7900);
    let nc = path(dir.path(), "r.nc");
    let args = ["relief", &png, "--width", "100", "--depth", "2", "--tool", "ball:3", "--stepover", "0.3"];
    let t = std::time::Instant::now();
    let o = kezuri(&[&args[..], &["--smooth", "100", "-o", &nc]].concat());
    refused(&o, "--smooth: smoothing 100 pixels over 7900 × 7900 pixels is 7.5e10 products");
    assert!(t.elapsed().as_secs() < 5, "{:?}", t.elapsed());
}

#[test]
fn huge_numbers_in_files_are_refused_where_they_are_read() {
    let dir = tempfile::tempdir().unwrap();
    // A profile of a corner drawn 1e305 mm wide: its fit overflows to NaN.
    let profile = path(dir.path(), "edge.csv");
    let mut text = String::from("x_mm,z_mm\n");
    for k in -200..=200 {
        text += &format!("{:e},{:e}\n", k as f64 * 1e305, (k as f64).abs() * 0.8e305);
    }
    std::fs::write(&profile, text).unwrap();
    refused(
        &kezuri(&["thermal", "edge", &profile, "--json"]),
        "line 2, column 1: '-2e307' (x_mm) must be a coordinate",
    );
    // Readings of 1e300 mm.
    let data = path(dir.path(), "huge.txt");
    std::fs::write(&data, "# grid nx=2 ny=2 pitch=1 origin=0,0 order=zigzag\n1,0\n2,1e300\n3,0\n4,0\n").unwrap();
    let out = path(dir.path(), "level.txt");
    refused(&kezuri(&["probe", "level", &data, "-o", &out]), "line 3, column 3: '1e300' must be a coordinate");
    // A tool length of 1e308 mm.
    let machine = path(dir.path(), "m.toml");
    std::fs::write(&machine, "[tools]\nlengths = { 1 = 1e308 }\n").unwrap();
    let nc = program(dir.path());
    refused(&kezuri(&["check", &nc, "--machine", &machine, "--json"]), "tools.lengths.1 must be a coordinate");
}

#[test]
fn a_simulated_tilt_is_a_slope() {
    let dir = tempfile::tempdir().unwrap();
    let stl = square(dir.path());
    let out = path(dir.path(), "r.txt");
    let o = kezuri(&[
        "probe", "simulate", &stl, "--count", "3,3", "--pitch", "1", "--stylus", "ball:1", "--tilt", "1e308,0", "-o",
        &out,
    ]);
    refused(&o, "--tilt 1e308,0: a slope is at most 1 mm per mm");
}

#[test]
fn the_chords_of_a_simulation_are_weighed_before_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let nc = path(dir.path(), "circles.nc");
    let text = "G90 G21\nG0 X0. Y0. Z5.\nG1 Z-1. F100.\n#1=0\nWHILE [#1 LT 700] DO1\nG02 I50.\n#1=#1+1\nEND1\nM30\n";
    std::fs::write(&nc, text).unwrap();
    let t = std::time::Instant::now();
    let o = kezuri(&["sim", &nc, "--tool", "ball:2", "--res", "1", "--chord-tol", "0.000001", "--json"]);
    refused(&o, "into 10995602 straight segments (arcs in chords), more than 10000000: raise the chord tolerance");
    assert!(t.elapsed().as_secs() < 5, "{:?}", t.elapsed());
}

/// A JPEG cut short (its start only, as a broken download leaves it) is
/// refused, not decoded to gray and carved; the whole file is carved.
#[test]
fn a_jpeg_cut_short_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let whole = path(dir.path(), "whole.jpg");
    let gray = image::GrayImage::from_fn(64, 48, |x, y| image::Luma([((x * 4 + y) % 256) as u8]));
    gray.save(&whole).unwrap();
    let bytes = std::fs::read(&whole).unwrap();
    let cut = path(dir.path(), "cut.jpg");
    std::fs::write(&cut, &bytes[..bytes.len() * 3 / 5]).unwrap();
    let out = path(dir.path(), "out.nc");
    let relief = |picture: &str| {
        kezuri(&["relief", picture, "--width", "20", "--depth", "1", "--tool", "ball:1", "--stepover", "1", "-o", &out])
    };
    assert!(relief(&whole).status.success());
    refused(&relief(&cut), "the JPEG ends before its picture does");
}

/// A damaged JPEG the picture fuzz target found (zune-jpeg multiplies past
/// its integers where overflow checks are on): a clear error, no panic.
/// Without overflow checks (a release build) the decoder wraps instead and
/// the file is a picture of 65,296 × 255 pixels of noise, which takes
/// minutes to carve: the test is for the checked build.
#[test]
#[cfg_attr(not(debug_assertions), ignore = "the decoder panics only where overflow checks are on")]
fn a_damaged_jpeg_found_by_the_fuzzer_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = path(dir.path(), "out.nc");
    let jpeg = concat!(env!("CARGO_MANIFEST_DIR"), "/testdata/fuzz/jpeg-bitstream-overflow.jpg");
    let o =
        kezuri(&["relief", jpeg, "--width", "20", "--depth", "1", "--tool", "ball:1", "--stepover", "1", "-o", &out]);
    refused(&o, "not a picture kezuri can read");
}
