//! The pictures kezuri writes explain themselves: a title naming the file
//! and tool, axes in mm, a colour bar or legend where colour means
//! something, the views in which a toolpath shows — and the same bytes on
//! every run (no dates).

use std::fmt::Write as _;
use std::path::Path;

mod common;
use common::{kezuri, ok, path};

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = path(dir, name);
    std::fs::write(&p, text).unwrap();
    p
}

/// The drawing of `program` by `kezuri run --svg`, made twice (in two
/// folders, the same names): the same text.
fn svg(dir: &Path, program: &str) -> String {
    let nc = write(dir, "p.nc", program);
    let drawn = |folder: &str| {
        let out = dir.join(folder);
        std::fs::create_dir(&out).unwrap();
        let svg = path(&out, "p.svg");
        ok(&kezuri(&["run", &nc, "--svg", &svg, "-o", &path(&out, "p-out.nc")]));
        std::fs::read_to_string(&svg).unwrap()
    };
    let text = drawn("a");
    assert_eq!(text, drawn("b"), "the same drawing each run");
    assert!(text.contains(">p-out.nc: P.NC<"), "titled with the program written and its source");
    text
}

#[test]
fn a_path_in_one_plane_is_drawn_where_it_shows_with_axes_and_a_legend() {
    let dir = tempfile::tempdir().unwrap();
    // Every move at Y 0 (the thermal sample's shape): from above, a line.
    let text = svg(
        dir.path(),
        "G90 G21\nG00 X0. Y0. Z0.\nG01 X-20. Z-50. F500\nG01 X-40.\nG00 Z0.\nG00 X-60.\nG01 Z-30.\nG00 Z0.\nM30\n",
    );
    assert!(text.contains("front (X right, Z up)"), "{text}");
    assert!(!text.contains(">top (X right, Y up)<"), "no top view: the path is a line in it");
    assert!(text.contains("no top view: the path is a line in it"));
    for want in ["X, mm", "Z, mm", ">-40<", "rapid (G0): dashed", "feed (G1, G2, G3): solid, by Z", "Z -50.000 mm"] {
        assert!(text.contains(want), "{want}: {text}");
    }
    assert!(text.contains("stroke-dasharray"), "rapids dashed");
}

#[test]
fn a_raster_is_seen_across_its_passes_thin_from_the_front_and_as_its_form_from_the_top() {
    let dir = tempfile::tempdir().unwrap();
    // Passes along X, 40 mm long, over a Y span of 60 mm: from the side
    // (the wider view) each pass would be a vertical line; from the front
    // its profile shows.
    let mut p = String::from("G90 G21\nG00 Z5.\nG00 X0. Y0.\nG01 Z0. F800\n");
    for k in 0..=300 {
        let y = 0.2 * f64::from(k);
        let (a, b) = if k % 2 == 0 { (0, 40) } else { (40, 0) };
        writeln!(p, "G01 Y{y:.1} X{a}. Z{:.3}", 0.5 * (y / 10.0).sin()).unwrap();
        for s in 1..=20 {
            let x = f64::from(a) + f64::from(b - a) * f64::from(s) / 20.0;
            writeln!(p, "G01 X{x:.2} Z{:.3}", 2.0 * (x / 6.0).sin() + 0.5 * (y / 10.0).sin()).unwrap();
        }
    }
    p += "G00 Z5.\nM30\n";
    let text = svg(dir.path(), &p);
    assert!(text.contains(">top (X right, Y up)<") && text.contains("front (X right, Z up)"), "{}", &text[..600]);
    assert!(!text.contains("side (Y right"));
    let widths = |view: &str| -> Vec<f64> {
        view.lines()
            .filter(|l| l.starts_with("<path") && l.contains("stroke=\"rgb(") && !l.contains("stroke-linecap"))
            .filter_map(|l| l.split("stroke-width=\"").nth(1)?.split('"').next()?.parse().ok())
            .collect()
    };
    let (top, front) = text.split_once("clip-path=\"url(#view1)\"").unwrap();
    // From the front, 300 passes on top of each other in a view under 500
    // pixels: thin lines.
    let (top, front) = (widths(top), widths(front));
    assert!(!front.is_empty() && front.iter().all(|&w| w < 0.5), "{front:?}");
    // From the top the passes lie 1.6 pixels apart: drawn as wide, the
    // form shaded by depth, not a carpet of rows with white between.
    assert!(!top.is_empty() && top.iter().all(|&w| w >= 1.6), "{top:?}");
}

/// Level raster rows along X at Y = 0, 1, …, 6 and Z −1.
fn raster() -> String {
    let mut s = String::from("G90 G21 G17\nG00 Z5.\nG00 X0. Y0.\nG01 Z-1. F600\n");
    for k in 0..7 {
        writeln!(s, "G01 X{}.", if k % 2 == 0 { 10 } else { 0 }).unwrap();
        if k < 6 {
            writeln!(s, "G01 Y{}.", k + 1).unwrap();
        }
    }
    s + "G00 Z5.\nM30\n"
}

/// `x y z` lines of the plane z = −1.01 (a target 10 µm under the cut's
/// bottom) over 0…10 × 0…6.
fn plane() -> String {
    let mut s = String::new();
    for j in 0..=12 {
        for i in 0..=20 {
            writeln!(s, "{} {} -1.01", f64::from(i) * 0.5, f64::from(j) * 0.5).unwrap();
        }
    }
    s
}

#[test]
fn sim_pictures_are_framed_and_the_same_each_run() {
    let dir = tempfile::tempdir().unwrap();
    let nc = write(dir.path(), "raster.nc", &raster());
    let target = write(dir.path(), "plane.xyz", &plane());
    let run = |name: &str| {
        let png = path(dir.path(), name);
        let o = kezuri(&[
            "sim",
            &nc,
            "--tool",
            "ball:3",
            "--res",
            "0.05",
            "--stock",
            "0,0,10,6,0",
            "--compare",
            &target,
            "-o",
            &png,
        ]);
        let text = ok(&o);
        let dev = png.replace(".png", "-deviation.png");
        (std::fs::read(&png).unwrap(), std::fs::read(&dev).unwrap(), text)
    };
    let (height, deviation, text) = run("a.png");
    let (height2, deviation2, _) = run("b.png");
    assert_eq!(height, height2, "the height picture, byte for byte");
    assert_eq!(deviation, deviation2, "the deviation picture, byte for byte");
    assert!(text.contains("99th percentile of |deviation|") && text.contains("magenta"), "{text}");
    // The grid is 200 × 120 cells; the picture holds it, drawn larger,
    // with a title, axes and a colour bar around it.
    let img = image::load_from_memory(&deviation).unwrap().to_rgb8();
    assert!(img.width() > 500 && img.height() > 300, "{:?}", img.dimensions());
    let dark = img.pixels().filter(|p| p.0.iter().all(|&c| c < 60)).count();
    assert!(dark > 500, "text drawn: {dark} dark pixels");
    let magenta = img.pixels().filter(|p| p.0[0] > 150 && p.0[1] < 100 && p.0[2] > 150).count();
    assert!(magenta > 0, "the gouge swatch");
}

#[test]
fn probe_export_png_is_framed() {
    let dir = tempfile::tempdir().unwrap();
    let mut csv = String::new();
    for j in 0..8 {
        for i in 0..10 {
            writeln!(csv, "{},{},{}", i, j, 0.1 * f64::from(i * j)).unwrap();
        }
    }
    let data = write(dir.path(), "grid.csv", &csv);
    let png = path(dir.path(), "g.png");
    ok(&kezuri(&["probe", "export", &data, "--png", &png]));
    let img = image::open(&png).unwrap();
    // 37 × 29 pixels of surface at 4 per pitch, drawn larger, framed.
    assert!(img.width() > 400 && img.height() > 300, "{} x {}", img.width(), img.height());
}
