//! `kezuri relief` as a user runs it: pictures of every format, the carving
//! checked by `kezuri sim` against the relief surface, a golden program,
//! and bad pictures.

use std::path::Path;

use image::{GrayImage, ImageBuffer, Luma, Rgb, RgbImage};

mod common;
use common::{kezuri, ok, path};

/// 64 × 48 pixels: a smooth dome (light high) beside a plateau with
/// vertical steps, the hard case for the chord between samples.
fn sketch() -> GrayImage {
    GrayImage::from_fn(64, 48, |c, r| {
        let (x, y) = (f64::from(c), f64::from(r));
        let dome = 1.0 - ((x - 20.0).powi(2) + (y - 24.0).powi(2)) / 300.0;
        let step = if (40..56).contains(&c) && (12..36).contains(&r) { 0.8 } else { 0.0 };
        Luma([(255.0 * dome.max(step).clamp(0.0, 1.0)).round() as u8])
    })
}

fn sim_json(nc: &str, tool: &str, stl: &str) -> serde_json::Value {
    let o = kezuri(&["sim", nc, "--tool", tool, "--res", "0.1", "--compare", stl, "--json"]);
    serde_json::from_str(&ok(&o)).expect("JSON")
}

#[test]
fn the_carving_never_cuts_into_the_relief_and_stays_within_the_cusp() {
    let dir = tempfile::tempdir().unwrap();
    let png = path(dir.path(), "sketch.png");
    sketch().save(&png).unwrap();
    let (nc, stl) = (path(dir.path(), "sketch.nc"), path(dir.path(), "sketch.stl"));
    let o = kezuri(&[
        "relief",
        &png,
        // A band of 0.001 mm below the cutter locations (the default is 0.01).
        "--gouge-tol",
        "0.001",
        "--pixel",
        "0.5",
        "--depth",
        "4",
        "--tool",
        "ball:3",
        "--stepover",
        "0.4",
        "--surface-stl",
        &stl,
        "-o",
        &nc,
    ]);
    ok(&o);
    let v = sim_json(&nc, "ball:3", &stl);
    // Into the relief: 0.001 mm of path band, the rest the simulation's
    // own sampling; the vertical steps included.
    let gouge = v["max_gouge_mm"].as_f64().unwrap();
    assert!(gouge <= 0.002, "gouge {gouge}: {v}");

    // Smooth waves (amplitude 2 mm, wavelength 16 mm: radius of curvature
    // ≥ 3.2 mm, slopes ≤ 38°), where the 3 mm ball reaches everywhere: the
    // material left is the cusp between rows. At 0.4 mm in plan, 0.51 mm
    // along a 38° slope, over a convex radius of 3.2 mm: (0.51²/8)·(1/1.5
    // + 1/3.2) = 0.032 mm across the surface, 0.040 mm in z, plus the
    // 0.01 mm path tolerance.
    let waves = GrayImage::from_fn(64, 64, |c, r| {
        let k = std::f64::consts::TAU / 32.0;
        Luma([(127.5 + 127.5 * (k * f64::from(c)).cos() * (k * f64::from(r)).cos()).round() as u8])
    });
    let png = path(dir.path(), "waves.png");
    waves.save(&png).unwrap();
    let (nc, stl) = (path(dir.path(), "waves.nc"), path(dir.path(), "waves.stl"));
    ok(&kezuri(&[
        "relief",
        &png,
        "--gouge-tol",
        "0.001",
        "--pixel",
        "0.5",
        "--depth",
        "4",
        "--tool",
        "ball:3",
        "--stepover",
        "0.4",
        "--surface-stl",
        &stl,
        "-o",
        &nc,
    ]));
    let v = sim_json(&nc, "ball:3", &stl);
    let (gouge, left) = (v["max_gouge_mm"].as_f64().unwrap(), v["max_left_mm"].as_f64().unwrap());
    assert!(gouge <= 0.002, "gouge {gouge}: {v}");
    // All but a few cells (within a cell of the picture's edge, where the
    // rows end) are inside the bound.
    let counts: Vec<u64> = v["histogram"]["counts"].as_array().unwrap().iter().map(|c| c.as_u64().unwrap()).collect();
    let edges: Vec<f64> = v["histogram"]["edges_mm"].as_array().unwrap().iter().map(|e| e.as_f64().unwrap()).collect();
    let beyond: u64 = counts.iter().zip(&edges).filter(|(_, lo)| **lo >= 0.050).map(|(c, _)| c).sum();
    assert!(beyond * 1000 <= counts.iter().sum::<u64>(), "{beyond} cells beyond 0.050 mm: {v}");
    assert!(left <= 0.060, "left {left}: {v}");
    assert!(left >= 0.010, "left {left}: the cusp is there");

    // RML-1 for a CAMM-3 (steps of 0.01 mm), read back by `kezuri convert`:
    // the same carving within the coarser step.
    let (rml, back) = (path(dir.path(), "waves.rml"), path(dir.path(), "waves-back.nc"));
    ok(&kezuri(&[
        "relief",
        &png,
        "--gouge-tol",
        "0.001",
        "--pixel",
        "0.5",
        "--depth",
        "4",
        "--tool",
        "ball:3",
        "--stepover",
        "0.4",
        "--to",
        "rml",
        "-o",
        &rml,
    ]));
    assert!(std::fs::read_to_string(&rml).unwrap().contains("^PA;"));
    ok(&kezuri(&["convert", &rml, "--safe-z", "5", "-o", &back]));
    let v = sim_json(&back, "ball:3", &stl);
    assert!(v["max_gouge_mm"].as_f64().unwrap() <= 0.003, "{v}");
    assert!(v["max_left_mm"].as_f64().unwrap() <= 0.070, "{v}");

    // Roughing first, with a flat cutter: still no cut into the relief,
    // and the roughing levels are 2 mm apart.
    let rough = path(dir.path(), "rough.nc");
    ok(&kezuri(&[
        "relief",
        &png,
        "--gouge-tol",
        "0.001",
        "--pixel",
        "0.5",
        "--depth",
        "4",
        "--tool",
        "ball:3",
        "--stepover",
        "0.4",
        "--rough",
        "flat:6",
        "--step-down",
        "2",
        "--allowance",
        "0.3",
        "-o",
        &rough,
    ]));
    let text = std::fs::read_to_string(&rough).unwrap();
    assert!(text.contains("T1") && text.contains("T2"), "two tools");
    let csv = ok(&kezuri(&["run", &rough, "--emit", "csv"]));
    let zs: Vec<f64> = csv.lines().skip(1).filter_map(|l| l.split(',').nth(4)?.parse().ok()).collect();
    assert!(zs.iter().any(|z| (z + 2.0).abs() < 1e-9), "a level at -2");
    // Each tool with its own cutter: the flat roughs (T1), the ball
    // finishes (T2).
    let tools = path(dir.path(), "tools.toml");
    std::fs::write(&tools, "[tools.T1]\nshape = \"flat:6\"\n[tools.T2]\nshape = \"ball:3\"\n").unwrap();
    let o = kezuri(&["sim", &rough, "--machine", &tools, "--res", "0.1", "--compare", &stl, "--json"]);
    let v: serde_json::Value = serde_json::from_str(&ok(&o)).unwrap();
    assert!(v["max_gouge_mm"].as_f64().unwrap() <= 0.002, "{v}");
    let volumes: Vec<f64> = v["tools"].as_array().unwrap().iter().map(|t| t["volume_mm3"].as_f64().unwrap()).collect();
    assert!(volumes.len() == 2 && volumes.iter().all(|&m| m > 0.0), "both tools cut: {v}");
}

/// Both sides at steep steps. Straight down, rows of one direction cannot
/// reach the foot of a wall parallel to them (the ball rides its edge), so
/// the bound is for rows along X and then Y (`--direction both`), against
/// what a ball can reach at all: the same carving at a quarter of the
/// stepover, simulated.
#[test]
fn steep_steps_cut_both_ways_stay_within_the_cusp_of_what_the_ball_reaches() {
    let dir = tempfile::tempdir().unwrap();
    let png = path(dir.path(), "sketch.png");
    sketch().save(&png).unwrap();
    let (coarse, fine) = (path(dir.path(), "coarse.nc"), path(dir.path(), "fine.nc"));
    let (stl, reach) = (path(dir.path(), "relief.stl"), path(dir.path(), "reach.stl"));
    let common = ["--pixel", "0.5", "--depth", "4", "--tool", "ball:3", "--direction", "both", "--gouge-tol", "0.001"];
    ok(&kezuri(
        &[&["relief", png.as_str()][..], &common, &["--stepover", "0.4", "--surface-stl", &stl, "-o", &coarse]]
            .concat(),
    ));
    // The reference at 4 decimals: where the written heights are lifted
    // over a steep flank (a grid step's rise, 3.2/0.5 × 0.001 = 0.0064 mm on
    // the wall at 3 decimals), it lifts them 10 times less.
    ok(&kezuri(
        &[
            &["relief", png.as_str()][..],
            &common,
            &["--stepover", "0.1", "--leave-tol", "0.002", "--digits", "4", "-o", &fine],
        ]
        .concat(),
    ));
    let o = kezuri(&["sim", &fine, "--tool", "ball:3", "--res", "0.1", "--stl", &reach, "--compare", &stl, "--json"]);
    let v: serde_json::Value = serde_json::from_str(&ok(&o)).unwrap();
    assert!(v["max_gouge_mm"].as_f64().unwrap() <= 0.002, "the reference: {v}");
    let v = sim_json(&coarse, "ball:3", &stl);
    assert!(v["max_gouge_mm"].as_f64().unwrap() <= 0.002, "{v}");
    // Against the reachable surface: no deeper, and above it by no more
    // than the cusp between rows 0.4 mm apart, R − √(R² − (s/2)²) = 0.0134
    // mm across the surface, which is 0.0866 mm in z on the steepest facet
    // of the relief (the plateau's wall, 3.2 mm over 0.5 mm), plus the
    // 0.01 mm path tolerance: 0.097 mm. (Measured: 0.058.)
    let v = sim_json(&coarse, "ball:3", &reach);
    let (gouge, left) = (v["max_gouge_mm"].as_f64().unwrap(), v["max_left_mm"].as_f64().unwrap());
    assert!(gouge <= 0.002, "gouge {gouge} below what the ball reaches: {v}");
    assert!((0.01..=0.097).contains(&left), "left {left}: {v}");
    assert!(v["mean_abs_dev_mm"].as_f64().unwrap() <= 0.01, "{v}");
}

#[test]
fn every_picture_format_gives_the_same_relief() {
    let dir = tempfile::tempdir().unwrap();
    let gray = sketch();
    let reference = path(dir.path(), "ref.png");
    gray.save(&reference).unwrap();
    let surface = |picture: &str, name: &str| {
        let stl = path(dir.path(), &format!("{name}.stl"));
        let nc = path(dir.path(), &format!("{name}.nc"));
        ok(&kezuri(&[
            "relief",
            picture,
            "--width",
            "32",
            "--depth",
            "4",
            "--tool",
            "ball:3",
            "--stepover",
            "2",
            "--surface-stl",
            &stl,
            "-o",
            &nc,
        ]));
        let bytes = std::fs::read(stl).unwrap();
        // Binary STL: the z of every vertex.
        bytes[84..]
            .chunks_exact(50)
            .flat_map(|t| (0..3).map(move |k| f32::from_le_bytes(t[20 + 12 * k..24 + 12 * k].try_into().unwrap())))
            .collect::<Vec<f32>>()
    };
    let want = surface(&reference, "ref");
    // 16-bit PNG, colour (as luma), BMP, TIFF, PGM exactly; JPEG within its loss.
    let wide: ImageBuffer<Luma<u16>, Vec<u16>> =
        ImageBuffer::from_fn(64, 48, |c, r| Luma([u16::from(gray.get_pixel(c, r)[0]) * 257]));
    let colour = RgbImage::from_fn(64, 48, |c, r| {
        let g = gray.get_pixel(c, r)[0];
        Rgb([g, g, g])
    });
    let files =
        [("wide.png", 0.0), ("colour.png", 0.0), ("g.bmp", 0.0), ("g.tiff", 0.0), ("g.pgm", 0.0), ("g.jpg", 0.2)];
    for (name, tolerance) in files {
        let file = path(dir.path(), name);
        match name {
            "wide.png" => wide.save(&file).unwrap(),
            "colour.png" => colour.save(&file).unwrap(),
            _ => gray.save(&file).unwrap(),
        }
        let got = surface(&file, name);
        assert_eq!(got.len(), want.len());
        let worst = got.iter().zip(&want).map(|(a, b)| (a - b).abs()).fold(0.0f32, f32::max);
        assert!(f64::from(worst) <= tolerance + 1e-5, "{name}: {worst} mm");
    }
}

/// The path's height at `x` on the row at `y`: linear between the feed
/// points of that row (`kezuri run --emit csv` lines).
fn z_on_row(csv: &str, y: f64, x: f64) -> Option<f64> {
    let points: Vec<(f64, f64)> = csv
        .lines()
        .skip(1)
        .filter_map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let (px, py, pz): (f64, f64, f64) = (f[2].parse().ok()?, f[3].parse().ok()?, f[4].parse().ok()?);
            (f[1] == "feed" && (py - y).abs() < 1e-9).then_some((px, pz))
        })
        .collect();
    points.windows(2).find_map(|w| {
        let ((xa, za), (xb, zb)) = (w[0], w[1]);
        let t = (x - xa) / (xb - xa);
        (xa != xb && (0.0..=1.0).contains(&t)).then_some(za + t * (zb - za))
    })
}

#[test]
fn levels_mask_and_the_picture_seen_from_above() {
    let dir = tempfile::tempdir().unwrap();
    // 24 × 16 pixels of 0.5 mm: the top-left 8 × 8 black, the next 8 × 8
    // gray 100, the rest white.
    let picture = GrayImage::from_fn(24, 16, |c, r| {
        Luma([match (c / 8, r / 8) {
            (0, 0) => 0,
            (1, 0) => 100,
            _ => 255,
        }])
    });
    let png = path(dir.path(), "blocks.png");
    picture.save(&png).unwrap();
    let nc = path(dir.path(), "blocks.nc");
    let levels = "0-63:0,64-191:2.5,192-255:5";
    let common = ["--pixel", "0.5", "--levels", levels, "--tool", "flat:0.5", "--stepover", "0.25"];
    ok(&kezuri(&[&["relief", png.as_str()][..], &common, &["-o", &nc]].concat()));
    // The whole program, against its golden copy (KEZURI_BLESS=1 writes it
    // anew after a deliberate change; review the diff).
    let golden = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/relief-blocks.nc");
    let text = std::fs::read_to_string(&nc).unwrap().replace(dir.path().to_str().unwrap(), "DIR");
    if std::env::var_os("KEZURI_BLESS").is_some() {
        std::fs::create_dir_all(golden.parent().unwrap()).unwrap();
        std::fs::write(&golden, &text).unwrap();
    }
    assert_eq!(text, std::fs::read_to_string(&golden).expect("the golden program"), "differs from {golden:?}");
    let csv = ok(&kezuri(&["run", &nc, "--emit", "csv"]));
    // Seen from above: the black block is the top left, x 0–4, y 4–8 mm,
    // cut to the floor 5 mm down; the gray one beside it 2.5 mm; the white
    // bottom half is the stock top.
    assert_eq!(z_on_row(&csv, 6.0, 2.0), Some(-5.0), "{csv}");
    assert_eq!(z_on_row(&csv, 6.0, 6.0), Some(-2.5));
    assert_eq!(z_on_row(&csv, 2.0, 2.0), Some(0.0));
    // A mask that leaves out the left third: the cutter's axis never
    // stands there.
    let mask = GrayImage::from_fn(24, 16, |c, _| Luma([if c < 8 { 0 } else { 255 }]));
    let mask_png = path(dir.path(), "mask.png");
    mask.save(&mask_png).unwrap();
    let masked = path(dir.path(), "masked.nc");
    ok(&kezuri(&[&["relief", png.as_str()][..], &common, &["--mask", &mask_png, "-o", &masked]].concat()));
    let csv = ok(&kezuri(&["run", &masked, "--emit", "csv"]));
    let xs: Vec<f64> = csv
        .lines()
        .skip(1)
        .filter(|l| l.split(',').nth(1) == Some("feed"))
        .filter_map(|l| l.split(',').nth(2)?.parse().ok())
        .collect();
    assert!(!xs.is_empty() && xs.iter().all(|x| *x >= 4.0), "{csv}");
    assert_eq!(z_on_row(&csv, 6.0, 6.0), Some(-2.5));
}

/// A PNG that says it is `w × h` and has no pixels.
fn png_header(w: u32, h: u32) -> Vec<u8> {
    fn crc32(bytes: &[u8]) -> u32 {
        let mut c = 0xffff_ffffu32;
        for &b in bytes {
            c ^= u32::from(b);
            for _ in 0..8 {
                c = if c & 1 == 1 { 0xedb8_8320 ^ (c >> 1) } else { c >> 1 };
            }
        }
        !c
    }
    let chunk = |out: &mut Vec<u8>, body: &[u8]| {
        out.extend((body.len() as u32 - 4).to_be_bytes());
        out.extend(body);
        out.extend(crc32(body).to_be_bytes());
    };
    let mut ihdr = b"IHDR".to_vec();
    ihdr.extend(w.to_be_bytes());
    ihdr.extend(h.to_be_bytes());
    ihdr.extend([8, 0, 0, 0, 0]);
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    chunk(&mut out, &ihdr);
    chunk(&mut out, b"IDAT");
    chunk(&mut out, b"IEND");
    out
}

#[test]
fn bad_pictures_are_clear_errors_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let out = path(dir.path(), "out.nc");
    let one = path(dir.path(), "one.png");
    GrayImage::from_raw(1, 1, vec![128]).unwrap().save(&one).unwrap();
    let cases: [(&str, Vec<u8>, &str); 4] = [
        ("empty.png", Vec::new(), "not a picture kezuri can read"),
        ("corrupt.png", b"\x89PNG\r\n\x1a\nthis is not a png".to_vec(), "not a picture kezuri can read"),
        ("huge.png", png_header(30_000, 30_000), "900000000 pixels is more than 64000000"),
        ("one.png", std::fs::read(&one).unwrap(), "a 1 × 1 picture is too small"),
    ];
    for (name, bytes, says) in cases {
        let file = path(dir.path(), name);
        std::fs::write(&file, bytes).unwrap();
        let o = kezuri(&[
            "relief",
            &file,
            "--width",
            "10",
            "--depth",
            "2",
            "--tool",
            "ball:3",
            "--stepover",
            "1",
            "-o",
            &out,
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{name}: {err}");
        assert!(err.contains(says), "{name}: {err}");
        assert!(!Path::new(&out).exists(), "{name}: output written");
    }
    let png = path(dir.path(), "ok.png");
    sketch().save(&png).unwrap();
    for (extra, says) in [
        (&["--levels", "0-100:1"][..], "--levels leaves gray 101–255 without a height"),
        (&["--depth", "0"][..], "the depth must be a positive number"),
        (&["--depth", "2", "--smooth", "-1"][..], "the smoothing must be 0 to 100 pixels"),
    ] {
        let mut args = vec!["relief", png.as_str(), "--width", "10", "--tool", "ball:3", "--stepover", "1", "-o", &out];
        args.extend(extra);
        let o = kezuri(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(says), "{extra:?}: {err}");
        assert!(!Path::new(&out).exists());
    }
}

/// A dark line 0.4 mm wide and 1 mm deep in a white picture: a 3 mm ball
/// cannot reach its bottom and says where; a 0.2 mm flat end mill can, and
/// says nothing.
#[test]
fn a_cutter_too_big_for_the_detail_is_warned_of() {
    let dir = tempfile::tempdir().unwrap();
    let png = path(dir.path(), "line.png");
    GrayImage::from_fn(100, 40, |c, _| Luma([if (48..52).contains(&c) { 0 } else { 255 }])).save(&png).unwrap();
    let carve = |tool: &str| {
        let o = kezuri(&["relief", &png, "--pixel", "0.1", "--depth", "1", "--tool", tool, "--stepover", "0.5"]);
        ok(&o);
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    let warned = carve("ball:3");
    assert!(warned.contains("ball:3 cannot reach all of the relief: up to"), "{warned}");
    // The line's middle is X5.0 (pixels 48 to 51 of 0.1 mm, centres 4.85 … 5.15).
    let at: f64 = warned.split(" at X").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
    assert!((at - 5.0).abs() <= 0.2, "{warned}");
    assert!(!carve("flat:0.2").contains("cannot reach"));
}
