//! The pictures kezuri writes explain themselves: a title naming the file
//! and tool, axes in mm, a legend, the views in which a toolpath shows —
//! and the same bytes on every run (no dates).

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
fn a_raster_is_seen_across_its_passes_and_dense_paths_are_thin() {
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
    // 300 passes in a view under 500 pixels: thin lines.
    let widths: Vec<f64> = text
        .lines()
        .filter(|l| l.starts_with("<path") && l.contains("stroke=\"rgb(") && !l.contains("stroke-linecap"))
        .filter_map(|l| l.split("stroke-width=\"").nth(1)?.split('"').next()?.parse().ok())
        .collect();
    assert!(!widths.is_empty() && widths.iter().all(|&w| w < 0.5), "{widths:?}");
}
