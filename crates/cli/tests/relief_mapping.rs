//! `kezuri relief` height mapping and placement through the binary, pinned
//! to values worked out by hand (not snapshots of the program's own
//! output): every option on a 4 × 3 picture, PGM (P5 8 and 16 bit, P2),
//! colour as luma,
//! and the rows along X, Y or both in every dialect.

use std::collections::BTreeMap;
use std::path::Path;

use image::{GrayImage, ImageBuffer, Luma, Rgb, RgbImage};

mod common;
use common::{kezuri, ok, path};

/// The 4 × 3 picture, top row first.
const GRAYS: [[u8; 4]; 3] = [[0, 64, 128, 255], [255, 200, 100, 10], [30, 60, 90, 120]];

fn picture() -> GrayImage {
    GrayImage::from_fn(4, 3, |c, r| Luma([GRAYS[r as usize][c as usize]]))
}

/// The relief surface `kezuri relief PICTURE --tool ball:1 --stepover 1
/// EXTRA` writes with --surface-stl: z at each node (x, y), in µm keys.
fn nodes(dir: &Path, picture: &str, extra: &[&str]) -> BTreeMap<(i64, i64), f64> {
    let stl = path(dir, "surface.stl");
    let mut args = vec!["relief", picture, "--tool", "ball:1", "--stepover", "1", "--surface-stl", &stl, "-o"];
    let nc = path(dir, "out.nc");
    args.push(&nc);
    args.extend(extra);
    ok(&kezuri(&args));
    let bytes = std::fs::read(&stl).unwrap();
    let f = |at: usize| f64::from(f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()));
    let mut out = BTreeMap::new();
    for t in bytes[84..].chunks_exact(50).enumerate().map(|(k, _)| 84 + 50 * k) {
        for v in 0..3 {
            let at = t + 12 + 12 * v;
            out.insert(((f(at) * 1000.0).round() as i64, (f(at + 4) * 1000.0).round() as i64), f(at + 8));
        }
    }
    out
}

/// The top row of the relief (the picture's first row), left to right.
fn top_row(nodes: &BTreeMap<(i64, i64), f64>) -> Vec<f64> {
    let top = nodes.keys().map(|k| k.1).max().unwrap();
    nodes.iter().filter(|(k, _)| k.1 == top).map(|(_, z)| *z).collect()
}

fn assert_close(got: &[f64], want: &[f64], tolerance: f64, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: {got:?}");
    for (g, w) in got.iter().zip(want) {
        assert!((g - w).abs() <= tolerance, "{what}: {got:?}, want {want:?}");
    }
}

#[test]
fn every_mapping_option_gives_the_heights_worked_out_by_hand() {
    let dir = tempfile::tempdir().unwrap();
    let png = path(dir.path(), "g.png");
    picture().save(&png).unwrap();
    let d = 2.55;
    // z = −depth·(1 − v^gamma), v = gray/255: grays 0, 64, 128, 255.
    let linear = [-d, -d * (1.0 - 64.0 / 255.0), -d * (1.0 - 128.0 / 255.0), 0.0];
    let cases: [(&[&str], [f64; 4]); 5] = [
        (&["--pixel", "1", "--depth", "2.55"], linear),
        // Dark high: v → 1 − v.
        (&["--pixel", "1", "--depth", "2.55", "--invert"], [0.0, -d * 64.0 / 255.0, -d * 128.0 / 255.0, -d]),
        (
            &["--pixel", "1", "--depth", "2.55", "--gamma", "2"],
            [-d, -d * (1.0 - (64.0f64 / 255.0).powi(2)), -d * (1.0 - (128.0f64 / 255.0).powi(2)), 0.0],
        ),
        // The paper's per-region heights above the floor; the highest is the stock top.
        (&["--pixel", "1", "--levels", "0-63:0,64-191:2.5,192-255:5"], [-5.0, -2.5, -2.5, 0.0]),
        // A Gaussian of 1 pixel (kernel to 3σ, edges held), rows then
        // columns, worked out apart from kezuri.
        (&["--pixel", "1", "--depth", "2.55", "--smooth", "1"], [-1.799393, -1.575684, -1.239693, -0.893152]),
    ];
    for (extra, want) in cases {
        let got = nodes(dir.path(), &png, extra);
        assert_eq!(got.len(), 12, "{extra:?}");
        assert_close(&top_row(&got), &want, 2e-6, &format!("{extra:?}"));
    }
}

#[test]
fn width_pixel_and_every_origin_place_the_picture() {
    let dir = tempfile::tempdir().unwrap();
    let png = path(dir.path(), "g.png");
    picture().save(&png).unwrap();
    // --width 8 over 4 pixels: 2 mm pixels, 8 × 6 mm; a node at each
    // pixel's centre. (x, y) of the top-left pixel and the carving's box.
    let cases: [(&[&str], (i64, i64)); 8] = [
        (&["--width", "8"], (1000, 5000)),
        (&["--pixel", "2"], (1000, 5000)),
        (&["--width", "8", "--origin", "lower-left"], (1000, 5000)),
        (&["--width", "8", "--origin", "lower-right"], (-7000, 5000)),
        (&["--width", "8", "--origin", "upper-left"], (1000, -1000)),
        (&["--width", "8", "--origin", "upper-right"], (-7000, -1000)),
        (&["--width", "8", "--origin", "centre"], (-3000, 2000)),
        (&["--width", "8", "--origin", "10,-5"], (11000, 0)),
    ];
    for (extra, top_left) in cases {
        let args: Vec<&str> = [&["--depth", "2.55"][..], extra].concat();
        let got = nodes(dir.path(), &png, &args);
        // The black pixel, the top left, is the deepest node.
        assert!((got[&top_left] + 2.55).abs() < 1e-6, "{extra:?}: {got:?}");
        let xs: Vec<i64> = got.keys().map(|k| k.0).collect();
        let ys: Vec<i64> = got.keys().map(|k| k.1).collect();
        let span =
            (xs.iter().max().unwrap() - xs.iter().min().unwrap(), ys.iter().max().unwrap() - ys.iter().min().unwrap());
        assert_eq!(span, (6000, 4000), "{extra:?}");
    }
    let o = kezuri(&[
        "relief",
        &png,
        "--width",
        "8",
        "--depth",
        "1",
        "--tool",
        "ball:1",
        "--stepover",
        "1",
        "--origin",
        "top",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--origin 'top': expected corner (lower-left), lower-right"));
}

/// Writes a 4 × 3 binary PGM (P5) of `samples`, 8 bit or, with
/// `maxval` above 255, 16 bit big-endian as netpbm has it. (`image`'s own
/// `.save("x.pgm")` writes PAM, P7, and its PGM encoder has no 16 bits.)
fn pgm(file: &str, samples: &[u16], maxval: u16) {
    let mut bytes = format!("P5\n4 3\n{maxval}\n").into_bytes();
    for v in samples {
        if maxval > 255 {
            bytes.extend(v.to_be_bytes());
        } else {
            bytes.push(*v as u8);
        }
    }
    std::fs::write(file, bytes).unwrap();
}

#[test]
fn pgm_eight_and_sixteen_bit_and_colour_read_as_luma() {
    let dir = tempfile::tempdir().unwrap();
    // 16 bits keep what 8 lose: 1000/65535 is between 8-bit grays 3 and 4.
    let wide: ImageBuffer<Luma<u16>, Vec<u16>> = ImageBuffer::from_fn(4, 3, |c, r| {
        Luma([if (c, r) == (1, 0) { 1000 } else { u16::from(GRAYS[r as usize][c as usize]) * 257 }])
    });
    let want = [-2.55, -2.55 * (1.0 - 1000.0 / 65535.0), -2.55 * (1.0 - 128.0 / 255.0), 0.0];
    for name in ["wide.pgm", "wide.png", "wide.tiff"] {
        let file = path(dir.path(), name);
        if name == "wide.pgm" {
            pgm(&file, wide.as_raw(), 65535);
        } else {
            wide.save(&file).unwrap();
        }
        let got = nodes(dir.path(), &file, &["--pixel", "1", "--depth", "2.55"]);
        assert_close(&top_row(&got), &want, 2e-6, name);
    }
    // 8-bit binary PGM, and the plain (ASCII) kind.
    let (p5, p2) = (path(dir.path(), "g.pgm"), path(dir.path(), "plain.pgm"));
    pgm(&p5, &picture().as_raw().iter().map(|&v| u16::from(v)).collect::<Vec<_>>(), 255);
    std::fs::write(&p2, "P2\n# plain\n4 3\n255\n0 64 128 255\n255 200 100 10\n30 60 90 120\n").unwrap();
    let linear = [-2.55, -2.55 * (1.0 - 64.0 / 255.0), -2.55 * (1.0 - 128.0 / 255.0), 0.0];
    for file in [p5, p2] {
        let got = nodes(dir.path(), &file, &["--pixel", "1", "--depth", "2.55"]);
        assert_close(&top_row(&got), &linear, 2e-6, &file);
    }
    // Colour is luma, Rec. 709 weights 0.2126 R + 0.7152 G + 0.0722 B:
    // pure red, green, blue and white.
    let colour = RgbImage::from_fn(4, 3, |c, r| match (c, r) {
        (0, 0) => Rgb([255, 0, 0]),
        (1, 0) => Rgb([0, 255, 0]),
        (2, 0) => Rgb([0, 0, 255]),
        _ => Rgb([255, 255, 255]),
    });
    let want = [-2.55 * (1.0 - 0.2126), -2.55 * (1.0 - 0.7152), -2.55 * (1.0 - 0.0722), 0.0];
    for name in ["colour.png", "colour.bmp", "colour.tiff"] {
        let file = path(dir.path(), name);
        colour.save(&file).unwrap();
        let got = nodes(dir.path(), &file, &["--pixel", "1", "--depth", "2.55"]);
        assert_close(&top_row(&got), &want, 2e-4, name);
    }
}

/// The feed moves of a program as (start, end) points, from `kezuri run
/// --emit csv` (a move starts where the one before it ended).
fn feeds(program: &str) -> Vec<[[f64; 3]; 2]> {
    let csv = ok(&kezuri(&["run", program, "--emit", "csv"]));
    let mut last = [f64::NAN; 3];
    let mut out = Vec::new();
    for l in csv.lines().skip(1) {
        let f: Vec<&str> = l.split(',').collect();
        let end = [f[2], f[3], f[4]].map(|v| v.parse::<f64>().unwrap());
        if f[1] == "feed" {
            out.push([last, end]);
        }
        last = end;
    }
    out
}

/// The rows of a raster along axis `along` (0: X, 1: Y) over a box whose
/// node centres run from `lo` to `hi` across it: every feed runs along a
/// row (its other coordinate fixed) or links two rows on the box's edge.
/// Returns the rows' other coordinates, in µm, in the order cut.
fn rows(feeds: &[[[f64; 3]; 2]], along: usize, lo: f64, hi: f64) -> Vec<i64> {
    let across = 1 - along;
    let mut out: Vec<i64> = Vec::new();
    for [a, b] in feeds {
        let on_edge = |p: &[f64; 3]| (p[along] - lo).abs() < 1e-9 || (p[along] - hi).abs() < 1e-9;
        if (a[across] - b[across]).abs() < 1e-9 {
            if (a[along] - b[along]).abs() > 1e-9 && out.last() != Some(&((a[across] * 1000.0).round() as i64)) {
                out.push((a[across] * 1000.0).round() as i64);
            }
        } else {
            assert!(on_edge(a) && on_edge(b), "a feed across the rows inside the box: {a:?} -> {b:?}");
        }
    }
    out
}

#[test]
fn rows_along_x_y_or_both_in_every_dialect() {
    let dir = tempfile::tempdir().unwrap();
    // A dome, 20 × 15 mm.
    let dome = GrayImage::from_fn(40, 30, |c, r| {
        let (x, y) = ((f64::from(c) - 19.5) / 19.5, (f64::from(r) - 14.5) / 14.5);
        Luma([(255.0 * (1.0 - x * x - y * y).clamp(0.0, 1.0)).round() as u8])
    });
    let png = path(dir.path(), "dome.png");
    dome.save(&png).unwrap();
    let base = ["--pixel", "0.5", "--depth", "3", "--tool", "ball:2", "--stepover", "1"];
    let run = |name: &str, extra: &[&str]| {
        let out = path(dir.path(), name);
        ok(&kezuri(&[&["relief", png.as_str()][..], &base, extra, &["-o", &out]].concat()));
        out
    };
    let x = feeds(&run("x.nc", &["--direction", "x"]));
    let y = feeds(&run("y.nc", &["--direction", "y"]));
    let both = feeds(&run("both.nc", &["--direction", "both"]));
    // Node centres 0.25 … 19.75 in X, 0.25 … 14.75 in Y; rows 1 mm apart
    // at most, from edge to edge.
    let (x_rows, y_rows) = (rows(&x, 0, 0.25, 19.75), rows(&y, 1, 0.25, 14.75));
    for (r, last) in [(&x_rows, 14750), (&y_rows, 19750)] {
        assert_eq!((r[0], r[r.len() - 1]), (250, last), "{r:?}");
        assert!(r.windows(2).all(|w| w[1] > w[0] && w[1] - w[0] <= 1000), "{r:?}");
    }
    assert!(x_rows.len() >= 15 && y_rows.len() >= 20, "{x_rows:?} {y_rows:?}");
    // Both: the X rows, then the Y rows.
    let (bx, by) = both.split_at(x.len());
    assert_eq!(bx, &x[..]);
    assert_eq!(rows(&by[1..], 1, 0.25, 14.75), y_rows);
    // Every dialect, and RML-1 in 0.01 mm steps.
    for (dialect, says) in [
        ("fanuc", "\nG01 Z-3. F300.\n"),
        ("linuxcnc", "\nG1 Z-3. F300.\n"),
        ("grbl", "\nG1 Z-3. F300.\n"),
        ("rml", "\nZ25,25,-300;\n"),
    ] {
        let file = run(&format!("dome.{dialect}"), &["--emit", dialect]);
        let text = std::fs::read_to_string(&file).unwrap();
        assert!(text.contains(says), "{dialect}: {}", &text[..text.len().min(400)]);
    }
}

#[test]
fn roughing_leaves_the_allowance_in_levels_step_down_apart() {
    let dir = tempfile::tempdir().unwrap();
    // A dome on a floor 3 mm down, 20 × 15 mm.
    let dome = GrayImage::from_fn(40, 30, |c, r| {
        let (x, y) = ((f64::from(c) - 19.5) / 12.0, (f64::from(r) - 14.5) / 10.0);
        Luma([(255.0 * (1.0 - x * x - y * y).clamp(0.0, 1.0)).round() as u8])
    });
    let (png, nc, stl) = (path(dir.path(), "dome.png"), path(dir.path(), "dome.nc"), path(dir.path(), "dome.stl"));
    dome.save(&png).unwrap();
    ok(&kezuri(&[
        "relief",
        &png,
        "--pixel",
        "0.5",
        "--depth",
        "3",
        "--tool",
        "ball:2",
        "--stepover",
        "1",
        "--rough",
        "flat:4",
        "--step-down",
        "1",
        "--allowance",
        "0.4",
        "--surface-stl",
        &stl,
        "-o",
        &nc,
    ]));
    // The roughing alone: the program up to the tool change.
    let text = std::fs::read_to_string(&nc).unwrap();
    let (rough, _) = text.split_once("\nT2").expect("a tool change to the finishing cutter");
    let rough_nc = path(dir.path(), "rough.nc");
    std::fs::write(&rough_nc, format!("{rough}\nM30\n%\n")).unwrap();
    // Its levels 1 mm apart, the last one on the floor plus the allowance.
    let mut levels: Vec<i64> =
        feeds(&rough_nc).iter().filter(|[a, b]| a[2] == b[2]).map(|[_, b]| (b[2] * 1000.0).round() as i64).collect();
    levels.sort_unstable();
    levels.dedup();
    assert_eq!((levels.first(), levels.contains(&-1000), levels.contains(&-2000)), (Some(&-2600), true, true));
    // Never closer to the relief than the allowance, and that close on the
    // floor. A stock up to Z5 (the clearance) over the cut's box: where the
    // roughing does not cut, far above the relief.
    let stock = "-1.75,-1.75,21.75,16.75,5";
    let o =
        kezuri(&["sim", &rough_nc, "--tool", "flat:4", "--res", "0.1", "--stock", stock, "--compare", &stl, "--json"]);
    let v: serde_json::Value = serde_json::from_str(&ok(&o)).unwrap();
    let closest = v["deviation_range_mm"][0].as_f64().unwrap();
    // (Within the gouge allowance, 0.01 mm, into the allowance.)
    assert!((0.4 - 0.01..=0.4 + 1e-3).contains(&closest), "{v}");
}
