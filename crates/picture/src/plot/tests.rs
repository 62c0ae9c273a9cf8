//! The toolpath picture's and the charts' tests: drawn to PNG with the
//! bundled font.

use super::*;

/// Pixels of `png` darker than mid grey (and opaque) within `x0..x1`.
fn dark(png: &image::RgbaImage, x0: u32, x1: u32) -> usize {
    png.enumerate_pixels()
        .filter(|(x, _, p)| (x0..x1).contains(x) && p[3] > 128 && (p[0] as u32 + p[1] as u32 + p[2] as u32) < 384)
        .count()
}

#[test]
fn a_chart_becomes_a_png_of_its_size_with_its_text_and_lines_drawn() {
    let svg = log_chart("wear", "point", "mm", 1e-4, &[("before", "black", vec![0.1, 0.01, 0.001])]);
    let png = png_from_svg(&svg).unwrap();
    let img = image::load_from_memory_with_format(&png, image::ImageFormat::Png).unwrap().to_rgba8();
    assert_eq!(img.dimensions(), (720, 380));
    // The left 60 pixels hold only the axis labels (text): drawn in the
    // bundled font, whatever this machine has installed.
    assert!(dark(&img, 0, 60) > 200, "{} dark pixels of text", dark(&img, 0, 60));
    // The series' line and its name.
    assert!(dark(&img, 70, 720) > 500, "{}", dark(&img, 70, 720));
    // The white background is painted.
    assert_eq!(img.get_pixel(715, 375).0, [255, 255, 255, 255]);
}

#[test]
fn text_alone_is_drawn_and_bad_svg_is_an_error() {
    let blank = r#"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="40"><rect width="100%" height="100%" fill="white"/></svg>"#;
    let text = blank
        .replace("</svg>", r#"<text x="4" y="28" font-family="sans-serif" font-size="20">Radius 3.0 mm</text></svg>"#);
    let img = |svg: &str| image::load_from_memory(&png_from_svg(svg).unwrap()).unwrap().to_rgba8();
    assert_eq!(dark(&img(blank), 0, 200), 0);
    assert!(dark(&img(&text), 0, 200) > 150, "{}", dark(&img(&text), 0, 200));
    assert!(png_from_svg("not svg").is_err());
    let huge = r#"<svg xmlns="http://www.w3.org/2000/svg" width="100000" height="10"/>"#;
    assert!(png_from_svg(huge).unwrap_err().to_string().contains("more than"));
}

fn at(x: f64, y: f64, z: f64) -> Axes {
    Axes { x, y, z, ..Axes::ZERO }
}

/// Moves from `from` through `to` of `kind`.
fn moves(kind: MoveKind, from: Axes, to: &[Axes]) -> Vec<kezuri_geom::Move> {
    let mut start = from;
    to.iter()
        .map(|&end| {
            let m = kezuri_geom::Move { kind, start, end, ..Default::default() };
            start = end;
            m
        })
        .collect()
}

/// The `x y width height` of the frame of view `k` in `svg`.
fn view_frame(svg: &str, k: usize) -> [f64; 4] {
    let line = svg.lines().filter(|l| l.contains(r##"fill="none" stroke="#ccc""##)).nth(k).unwrap();
    let number = |name: &str| -> f64 {
        let key = format!(" {name}=\"");
        line[line.find(&key).unwrap() + key.len()..].split('"').next().unwrap().parse().unwrap()
    };
    [number("x"), number("y"), number("width"), number("height")]
}

#[test]
fn the_motions_are_counted_as_check_counts_them() {
    // Six feed moves and a rapid, with a dwell at each stop: check says
    // 7 motions, not 13 moves.
    let mut path = Toolpath::default();
    let corners = [at(10.0, 0.0, 0.0), at(10.0, 10.0, -1.0), at(0.0, 10.0, -1.0), at(0.0, 0.0, 0.0)];
    path.moves.extend(moves(MoveKind::Rapid, at(0.0, 0.0, 5.0), &[at(0.0, 0.0, 0.0)]));
    for m in moves(MoveKind::Feed, at(0.0, 0.0, 0.0), &[&corners[..], &corners[..2]].concat()) {
        let dwell = kezuri_geom::Move { kind: MoveKind::Dwell(0.5), start: m.end, end: m.end, ..Default::default() };
        path.moves.extend([m, dwell]);
    }
    assert_eq!(path.moves.len(), 13);
    let svg = svg(&path, "box.nc");
    assert!(svg.contains(", 7 motions (moves without dwells, as check counts them)"), "{svg}");
}

#[test]
fn rapids_are_drawn_whole() {
    // A texture's approach: a rapid from 60 mm left of the cut and 20 mm
    // above it, down to the start (o7023's).
    let mut path = Toolpath::default();
    path.moves.extend(moves(MoveKind::Rapid, at(-60.0, 20.0, 20.0), &[at(0.0, 0.0, 20.0), at(0.0, 0.0, 0.0)]));
    path.moves.extend(moves(MoveKind::Feed, at(0.0, 0.0, 0.0), &[at(40.0, 0.0, -1.0), at(40.0, -10.0, -1.0)]));
    let svg = svg(&path, "texture.nc");
    let rapid = svg.lines().find(|l| l.contains(r##"stroke="#d33" stroke-dasharray"##)).unwrap();
    let d = rapid.split("d=\"").nth(1).unwrap().split('"').next().unwrap();
    let numbers: Vec<f64> = d.split(['M', 'L', ' ']).filter(|t| !t.is_empty()).map(|t| t.parse().unwrap()).collect();
    // Top view first, then front: every rapid point inside one of them.
    let frames = [view_frame(&svg, 0), view_frame(&svg, 1)];
    for p in numbers.chunks(2) {
        let inside = frames.iter().any(|f| {
            (f[0] - 0.5..=f[0] + f[2] + 0.5).contains(&p[0]) && (f[1] - 0.5..=f[1] + f[3] + 0.5).contains(&p[1])
        });
        assert!(inside, "rapid point {p:?} outside the views {frames:?}");
    }
}

#[test]
fn a_dense_raster_seen_from_the_top_is_its_form_not_rows() {
    // A dome 60 mm across finished by a raster 0.4 mm apart along X.
    let dome = |x: f64, y: f64| 10.0 * (1.0 - ((x - 30.0).powi(2) + (y - 30.0).powi(2)) / 1800.0).max(0.0);
    let mut path = Toolpath::default();
    let mut points = Vec::new();
    for row in 0..=150 {
        let y = 0.4 * row as f64;
        let xs: Vec<f64> = (0..=60).map(f64::from).collect();
        let xs: Vec<f64> = if row % 2 == 0 { xs } else { xs.into_iter().rev().collect() };
        points.extend(xs.into_iter().map(|x| at(x, y, dome(x, y))));
    }
    path.moves.extend(moves(MoveKind::Feed, points[0], &points[1..]));
    let svg = svg(&path, "dome.nc");
    let img = image::load_from_memory(&png_from_svg(&svg).unwrap()).unwrap().to_rgba8();
    let f = view_frame(&svg, 0);
    // Inside the top view (less 6 px at its edges) no white shows
    // between the rows.
    let (x0, y0, x1, y1) =
        ((f[0] + 6.0) as u32, (f[1] + 6.0) as u32, (f[0] + f[2] - 6.0) as u32, (f[1] + f[3] - 6.0) as u32);
    let (mut white, mut all) = (0, 0);
    for y in y0..y1 {
        for x in x0..x1 {
            let p = img.get_pixel(x, y).0;
            all += 1;
            if p[0] > 230 && p[1] > 230 && p[2] > 230 {
                white += 1;
            }
        }
    }
    assert!(white * 100 < all, "{white} of {all} pixels of the top view white: rows, not the form");
}
