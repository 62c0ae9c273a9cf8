//! A picture of a toolpath: SVG, top view (XY) beside a front view (XZ).
//! Cutting moves are solid and shaded by depth, rapids dashed red. Charts
//! are SVG text too; [`png_from_svg`] makes any of them a PNG picture.

use std::collections::{BTreeMap, HashSet};
use std::fmt::Write;
use std::sync::{Arc, OnceLock};

use anyhow::{anyhow, bail, Context};
use kezuri_geom::{Axes, MoveKind, Toolpath};
use resvg::{tiny_skia, usvg};

const PANEL: f64 = 480.0;
const MARGIN: f64 = 30.0;

/// Points along a move, arcs flattened to 2° steps.
fn points(m: &kezuri_geom::Move) -> Vec<Axes> {
    match m.kind {
        MoveKind::Arc(arc) => {
            let steps = ((arc.sweep(m.start, m.end).to_degrees() / 2.0).ceil() as usize).clamp(2, 2000);
            (0..=steps).map(|k| arc.point_at(m.start, m.end, k as f64 / steps as f64)).collect()
        }
        _ => vec![m.start, m.end],
    }
}

/// Whether `c` continues the segment `a`→`b` in the same direction.
fn straight_on(a: (i64, i64), b: (i64, i64), c: (i64, i64)) -> bool {
    let (u, v) = ((b.0 - a.0, b.1 - a.1), (c.0 - b.0, c.1 - b.1));
    u.0 * v.1 == u.1 * v.0 && u.0 * v.0 + u.1 * v.1 > 0
}

/// How a move is drawn: rapids dashed red, cuts blue, darker when deeper.
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
enum Stroke {
    Rapid,
    /// Red and green of the blue shade: 180 at the top, 0 at the bottom.
    Cut(u8),
}

/// Writes `lines` (points in hundredths of a pixel) as one path drawn in
/// `style`.
fn draw(out: &mut String, style: Stroke, lines: Vec<Vec<(i64, i64)>>) {
    let mut d = String::new();
    for line in lines {
        for (i, (x, y)) in line.into_iter().enumerate() {
            let (x, y) = (x as f64 / 100.0, y as f64 / 100.0);
            let _ = write!(d, "{}{x:.2} {y:.2} ", if i == 0 { 'M' } else { 'L' });
        }
    }
    let _ = match style {
        Stroke::Cut(s) => {
            writeln!(out, r#"<path d="{}" fill="none" stroke="rgb({s},{s},255)" stroke-width="0.8"/>"#, d.trim_end())
        }
        Stroke::Rapid => writeln!(
            out,
            r##"<path d="{}" fill="none" stroke="#d33" stroke-dasharray="4 3" stroke-width="0.6"/>"##,
            d.trim_end()
        ),
    };
}

/// The SVG text for `path`, titled `title`.
pub fn svg(path: &Toolpath, title: &str) -> String {
    let (lo, hi) = path.bounds().unwrap_or(([0.0; 3], [1.0; 3]));
    let span = |k: usize| (hi[k] - lo[k]).max(1e-6);
    let scale = PANEL / span(0).max(span(1)).max(span(2));
    let width = 3.0 * MARGIN + scale * span(0) * 2.0;
    let height = 2.0 * MARGIN + 20.0 + scale * span(1).max(span(2));
    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.1} {height:.1}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(out, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let esc: String = title.chars().filter(|c| !matches!(c, '<' | '>' | '&' | '"')).collect();
    let _ = writeln!(out, r#"<text x="{MARGIN}" y="16">{esc} — top (X right, Y up) and front (X right, Z up)</text>"#);
    let top = MARGIN + 20.0;
    let panels: [(usize, usize, f64); 2] = [(0, 1, MARGIN), (0, 2, 2.0 * MARGIN + scale * span(0))];
    for (u, v, left) in panels {
        let base = top + scale * span(v);
        let _ = writeln!(
            out,
            r##"<rect x="{:.1}" y="{top:.1}" width="{:.1}" height="{:.1}" fill="none" stroke="#ccc"/>"##,
            left,
            scale * span(u),
            scale * span(v)
        );
        let depth = span(2);
        // One path per style, cuts first and rapids over them; a segment
        // already drawn in that style (a repeated plunge seen from the front)
        // is drawn once, and steps on along a line lengthen it.
        let mut drawn = HashSet::new();
        let mut styles: BTreeMap<Stroke, Vec<Vec<(i64, i64)>>> = BTreeMap::new();
        for m in &path.moves {
            if matches!(m.kind, MoveKind::Dwell(_)) {
                continue;
            }
            // Deeper cuts darker.
            let next = if m.is_rapid() {
                Stroke::Rapid
            } else {
                Stroke::Cut((180.0 * (1.0 - ((hi[2] - m.end.z) / depth).clamp(0.0, 1.0))) as u8)
            };
            let lines = styles.entry(next).or_default();
            // Points in hundredths of a pixel.
            let pts: Vec<(i64, i64)> = points(m)
                .iter()
                .map(|p| {
                    let p = p.xyz();
                    let x = left + scale * (p[u] - lo[u]);
                    let y = base - scale * (p[v] - lo[v]);
                    ((x * 100.0).round() as i64, (y * 100.0).round() as i64)
                })
                .collect();
            for pair in pts.windows(2) {
                let (a, b) = (pair[0], pair[1]);
                if a == b || !drawn.insert((next, a.min(b), a.max(b))) {
                    continue;
                }
                match lines.last_mut() {
                    Some(line) if line.last() == Some(&a) => {
                        // A step on along the same line moves its end.
                        let n = line.len();
                        if n >= 2 && straight_on(line[n - 2], a, b) {
                            line[n - 1] = b;
                        } else {
                            line.push(b);
                        }
                    }
                    _ => lines.push(vec![a, b]),
                }
            }
        }
        for (style, lines) in styles.into_iter().rev() {
            draw(&mut out, style, lines);
        }
        let _ = writeln!(
            out,
            r#"<text x="{left:.1}" y="{:.1}">{} {:.3} … {:.3}, {} {:.3} … {:.3} mm</text>"#,
            base + 16.0,
            ["X", "Y", "Z"][u],
            lo[u],
            hi[u],
            ["X", "Y", "Z"][v],
            lo[v],
            hi[v]
        );
    }
    out.push_str("</svg>\n");
    out
}

/// A chart of one or more series over the same points (`y` in the unit
/// named), each `(name, colour, values)`, on a logarithmic axis from
/// `floor` up: the before/after errors of a correction.
pub fn log_chart(title: &str, unit: &str, floor: f64, series: &[(&str, &str, Vec<f64>)]) -> String {
    let (w, h, left, bottom) = (720.0, 360.0, 70.0, 40.0);
    let n = series.iter().map(|s| s.2.len()).max().unwrap_or(0).max(2);
    let top = series.iter().flat_map(|s| s.2.iter().copied()).fold(floor * 10.0, f64::max);
    let (lo, hi) = (floor.log10().floor(), top.log10().ceil());
    let x = |k: usize| left + (w - left - 20.0) * k as f64 / (n - 1) as f64;
    let y = |v: f64| 20.0 + (h - bottom - 20.0) * (hi - v.max(floor).log10()) / (hi - lo);
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" font-family=\"sans-serif\" font-size=\"12\">\n\
         <rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<text x=\"{left}\" y=\"14\">{title}</text>\n"
    );
    for e in (lo as i32)..=(hi as i32) {
        let v = 10f64.powi(e);
        let _ = writeln!(
            s,
            "<line x1=\"{left}\" x2=\"{}\" y1=\"{y0:.1}\" y2=\"{y0:.1}\" stroke=\"#ddd\"/><text x=\"4\" y=\"{:.1}\">{v:e} {unit}</text>",
            w - 20.0,
            y(v) + 4.0,
            y0 = y(v),
        );
    }
    let _ = writeln!(s, "<text x=\"{left}\" y=\"{}\">point of the program (in order)</text>", h - 8.0);
    for (k, (name, colour, values)) in series.iter().enumerate() {
        let points: Vec<String> = values.iter().enumerate().map(|(i, &v)| format!("{:.1},{:.1}", x(i), y(v))).collect();
        let _ = writeln!(
            s,
            "<polyline fill=\"none\" stroke=\"{colour}\" stroke-width=\"2\" points=\"{}\"/>",
            points.join(" ")
        );
        let _ = writeln!(
            s,
            "<text x=\"{}\" y=\"{}\" fill=\"{colour}\">{name}</text>",
            w - 220.0,
            0.5 * h + 16.0 * k as f64
        );
    }
    s + "</svg>\n"
}

/// DejaVu Sans (assets/fonts, licence beside it): the one font of PNG
/// charts, so their text is drawn alike on every machine, fonts installed or
/// not.
static FONT: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");
const FONT_FAMILY: &str = "DejaVu Sans";
/// The largest side of a PNG picture, in pixels.
const MAX_SIDE: u32 = 16_384;

/// The font database of PNG charts: the bundled font alone, the family of
/// every generic name (`sans-serif`, `serif`, `monospace`, …).
fn fonts() -> Arc<usvg::fontdb::Database> {
    static FONTS: OnceLock<Arc<usvg::fontdb::Database>> = OnceLock::new();
    FONTS
        .get_or_init(|| {
            let mut db = usvg::fontdb::Database::new();
            db.load_font_source(usvg::fontdb::Source::Binary(Arc::new(FONT)));
            db.set_sans_serif_family(FONT_FAMILY);
            db.set_serif_family(FONT_FAMILY);
            db.set_monospace_family(FONT_FAMILY);
            db.set_cursive_family(FONT_FAMILY);
            db.set_fantasy_family(FONT_FAMILY);
            Arc::new(db)
        })
        .clone()
}

/// The SVG picture `svg` (the charts and toolpath pictures of this module)
/// as PNG bytes, one pixel per SVG user unit of its `width` × `height`; text
/// in the bundled DejaVu Sans; what the picture leaves unpainted is
/// transparent.
pub fn png_from_svg(svg: &str) -> anyhow::Result<Vec<u8>> {
    let options = usvg::Options { font_family: FONT_FAMILY.into(), fontdb: fonts(), ..usvg::Options::default() };
    let tree = usvg::Tree::from_str(svg, &options).context("cannot read the SVG picture")?;
    let size = tree.size().to_int_size();
    let (w, h) = (size.width(), size.height());
    if w > MAX_SIDE || h > MAX_SIDE {
        bail!("the picture is {w} x {h} pixels: more than {MAX_SIDE} on a side");
    }
    let mut pixmap = tiny_skia::Pixmap::new(w, h).ok_or_else(|| anyhow!("no picture of {w} x {h} pixels"))?;
    resvg::render(&tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
    pixmap.encode_png().map_err(|e| anyhow!("cannot encode the PNG picture: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pixels of `png` darker than mid grey (and opaque) within `x0..x1`.
    fn dark(png: &image::RgbaImage, x0: u32, x1: u32) -> usize {
        png.enumerate_pixels()
            .filter(|(x, _, p)| (x0..x1).contains(x) && p[3] > 128 && (p[0] as u32 + p[1] as u32 + p[2] as u32) < 384)
            .count()
    }

    #[test]
    fn a_chart_becomes_a_png_of_its_size_with_its_text_and_lines_drawn() {
        let svg = log_chart("wear", "mm", 1e-4, &[("before", "black", vec![0.1, 0.01, 0.001])]);
        let png = png_from_svg(&svg).unwrap();
        let img = image::load_from_memory_with_format(&png, image::ImageFormat::Png).unwrap().to_rgba8();
        assert_eq!(img.dimensions(), (720, 360));
        // The left 60 pixels hold only the axis labels (text): drawn in the
        // bundled font, whatever this machine has installed.
        assert!(dark(&img, 0, 60) > 200, "{} dark pixels of text", dark(&img, 0, 60));
        // The series' line and its name.
        assert!(dark(&img, 70, 720) > 500, "{}", dark(&img, 70, 720));
        // The white background is painted.
        assert_eq!(img.get_pixel(715, 355).0, [255, 255, 255, 255]);
    }

    #[test]
    fn text_alone_is_drawn_and_bad_svg_is_an_error() {
        let blank = r#"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="40"><rect width="100%" height="100%" fill="white"/></svg>"#;
        let text = blank.replace(
            "</svg>",
            r#"<text x="4" y="28" font-family="sans-serif" font-size="20">Radius 3.0 mm</text></svg>"#,
        );
        let img = |svg: &str| image::load_from_memory(&png_from_svg(svg).unwrap()).unwrap().to_rgba8();
        assert_eq!(dark(&img(blank), 0, 200), 0);
        assert!(dark(&img(&text), 0, 200) > 150, "{}", dark(&img(&text), 0, 200));
        assert!(png_from_svg("not svg").is_err());
        let huge = r#"<svg xmlns="http://www.w3.org/2000/svg" width="100000" height="10"/>"#;
        assert!(png_from_svg(huge).unwrap_err().to_string().contains("more than"));
    }
}
