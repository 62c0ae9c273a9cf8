//! Line charts as SVG text (made PNGs by `plot::png_from_svg`): several
//! coloured lines over linear axes with ticks, labels and a legend — the
//! wear progression of `tool db show`, the demo's groove before and after.

use std::fmt::Write;

const COLOURS: [&str; 10] =
    ["#444444", "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22"];

/// One line of the chart: its legend and its points `(x, y)`.
pub struct Line {
    /// The legend's text.
    pub label: String,
    /// Points in z order.
    pub points: Vec<(f64, f64)>,
}

/// Tick positions over `lo..=hi`: steps of 1, 2 or 5 × 10ⁿ, about `n` of
/// them, and the decimals that print them.
pub(crate) fn ticks(lo: f64, hi: f64, n: f64) -> (Vec<f64>, usize) {
    let raw = ((hi - lo) / n).max(1e-12);
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0].into_iter().map(|k| k * mag).find(|s| *s >= raw).unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    ((first..=last).map(|k| k as f64 * step).collect(), decimals)
}

/// At most about `2 × bins` points of `points` (in z order) that keep the
/// lowest and highest value of each of `bins` equal spans of z: a line of
/// 200,000 samples drawn as the pixels would show it.
fn thin(points: &[(f64, f64)], bins: usize) -> Vec<(f64, f64)> {
    if points.len() <= 2 * bins {
        return points.to_vec();
    }
    let (z0, z1) = (points[0].0, points[points.len() - 1].0);
    let bin = |z: f64| (((z - z0) / (z1 - z0).max(1e-300)) * bins as f64).min(bins as f64 - 1.0) as usize;
    let mut out = Vec::with_capacity(2 * bins + 2);
    let mut i = 0;
    while i < points.len() {
        let b = bin(points[i].0);
        let mut j = i;
        let (mut lo, mut hi) = (i, i);
        while j < points.len() && bin(points[j].0) == b {
            if points[j].1 < points[lo].1 {
                lo = j;
            }
            if points[j].1 > points[hi].1 {
                hi = j;
            }
            j += 1;
        }
        out.push(points[lo.min(hi)]);
        if lo != hi {
            out.push(points[lo.max(hi)]);
        }
        i = j;
    }
    out
}

pub(crate) fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// Ticks in mm along the bottom and left of a frame at `(left, top)`,
/// `w` × `h` pixels, showing `[x0, x1, y0, y1]` (y up), and the names of the
/// two axes: the pictures' and the toolpath views' one way of drawing them.
pub(crate) fn frame_axes(out: &mut String, (left, top, w, h): (f64, f64, f64, f64), e: [f64; 4], names: [&str; 2]) {
    let base = top + h;
    let (tu, du) = ticks(e[0], e[1], (w / 80.0).max(3.0));
    for u in tu {
        let x = left + w * (u - e[0]) / (e[1] - e[0]).max(1e-6);
        let _ = writeln!(
            out,
            r##"<line x1="{x:.1}" x2="{x:.1}" y1="{base:.1}" y2="{:.1}" stroke="#444"/><text x="{x:.1}" y="{:.1}" text-anchor="middle">{u:.du$}</text>"##,
            base + 5.0,
            base + 18.0
        );
    }
    let (tv, dv) = ticks(e[2], e[3], (h / 60.0).max(3.0));
    for v in tv {
        let y = base - h * (v - e[2]) / (e[3] - e[2]).max(1e-6);
        let _ = writeln!(
            out,
            r##"<line x1="{:.1}" x2="{left:.1}" y1="{y:.1}" y2="{y:.1}" stroke="#444"/><text x="{:.1}" y="{:.1}" text-anchor="end">{v:.dv$}</text>"##,
            left - 5.0,
            left - 7.0,
            y + 4.0
        );
    }
    let _ = writeln!(
        out,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
        left + w / 2.0,
        base + 34.0,
        escape(names[0])
    );
    let _ = writeln!(
        out,
        r#"<text transform="translate({:.1} {:.1}) rotate(-90)" text-anchor="middle">{}</text>"#,
        left - 50.0,
        top + h / 2.0,
        escape(names[1])
    );
}

/// The SVG chart titled `title`: `y_label` up against `x_label` right, a
/// zero line, ticks with their values, and a legend of the lines.
pub fn line_chart(title: &str, x_label: &str, y_label: &str, lines: &[Line]) -> String {
    let (left, top, plot_w, plot_h): (f64, f64, f64, f64) = (80.0, 40.0, 520.0, 340.0);
    let legend_x = left + plot_w + 30.0;
    // The legend's longest line (a swatch, then its text, in DejaVu Sans
    // at 12 px: at most 7.2 px a character) within the picture.
    let longest = lines.iter().map(|l| l.label.chars().count()).max().unwrap_or(0) as f64;
    let width = legend_x + (30.0 + 7.2 * longest + 10.0).max(230.0);
    let height = (top + plot_h + 50.0).max(top + 20.0 * lines.len() as f64 + 20.0);
    let all = || lines.iter().flat_map(|l| l.points.iter());
    let (mut z0, mut z1) = all().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
    if z0 > z1 {
        (z0, z1) = (0.0, 1.0);
    }
    if z1 - z0 < 1e-9 {
        (z0, z1) = (z0 - 0.5, z1 + 0.5);
    }
    let (mut v0, mut v1) = all().fold((0.0f64, 0.0f64), |(a, b), p| (a.min(p.1), b.max(p.1)));
    let pad = ((v1 - v0) * 0.05).max(1e-4);
    (v0, v1) = (v0 - pad, v1 + pad);
    let x = |z: f64| left + plot_w * (z - z0) / (z1 - z0);
    let y = |v: f64| top + plot_h * (v1 - v) / (v1 - v0);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(s, r#"<text x="{left}" y="22" font-size="14">{}</text>"#, escape(title));
    let (xt, xd) = ticks(z0, z1, 8.0);
    for z in xt {
        let _ = writeln!(
            s,
            r##"<line x1="{0:.1}" x2="{0:.1}" y1="{top}" y2="{1:.1}" stroke="#e4e4e4"/><text x="{0:.1}" y="{2:.1}" text-anchor="middle">{3:.4$}</text>"##,
            x(z),
            top + plot_h,
            top + plot_h + 16.0,
            z,
            xd
        );
    }
    let (yt, yd) = ticks(v0, v1, 6.0);
    for v in yt {
        let _ = writeln!(
            s,
            r##"<line x1="{left}" x2="{0:.1}" y1="{1:.1}" y2="{1:.1}" stroke="#e4e4e4"/><text x="{2:.1}" y="{3:.1}" text-anchor="end">{4:.5$}</text>"##,
            left + plot_w,
            y(v),
            left - 6.0,
            y(v) + 4.0,
            v,
            yd
        );
    }
    let _ = writeln!(
        s,
        r##"<rect x="{left}" y="{top}" width="{plot_w}" height="{plot_h}" fill="none" stroke="#888"/><line x1="{left}" x2="{:.1}" y1="{1:.1}" y2="{1:.1}" stroke="#888" stroke-dasharray="4 3"/>"##,
        left + plot_w,
        y(0.0)
    );
    let _ = writeln!(
        s,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
        left + 0.5 * plot_w,
        top + plot_h + 38.0,
        escape(x_label)
    );
    let _ = writeln!(
        s,
        r#"<text transform="translate(18 {:.1}) rotate(-90)" text-anchor="middle">{}</text>"#,
        top + 0.5 * plot_h,
        escape(y_label)
    );
    for (k, line) in lines.iter().enumerate() {
        let colour = COLOURS[k % COLOURS.len()];
        let points: Vec<String> =
            thin(&line.points, plot_w as usize).iter().map(|&(z, v)| format!("{:.2},{:.2}", x(z), y(v))).collect();
        if !points.is_empty() {
            let _ = writeln!(
                s,
                r#"<polyline fill="none" stroke="{colour}" stroke-width="1.5" points="{}"/>"#,
                points.join(" ")
            );
        }
        let ly = top + 8.0 + 20.0 * k as f64;
        let _ = writeln!(
            s,
            r#"<line x1="{legend_x}" x2="{:.1}" y1="{ly:.1}" y2="{ly:.1}" stroke="{colour}" stroke-width="3"/><text x="{:.1}" y="{:.1}">{}</text>"#,
            legend_x + 24.0,
            legend_x + 30.0,
            ly + 4.0,
            escape(&line.label)
        );
    }
    s + "</svg>\n"
}

/// The width and height of a chart made by [`line_chart`].
fn size(svg: &str) -> (f64, f64) {
    let attribute = |name: &str| {
        let key = format!(" {name}=\"");
        let start = svg.find(&key).map_or(0, |k| k + key.len());
        svg[start..].split('"').next().and_then(|v| v.parse().ok()).unwrap_or(0.0)
    };
    (attribute("width"), attribute("height"))
}

/// Charts made by [`line_chart`] one under the other, as one SVG picture.
pub fn stack(charts: &[String]) -> String {
    let sizes: Vec<(f64, f64)> = charts.iter().map(|c| size(c)).collect();
    let width = sizes.iter().map(|s| s.0).fold(0.0, f64::max);
    let height: f64 = sizes.iter().map(|s| s.1).sum();
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.0}\" height=\"{height:.0}\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    );
    let mut y = 0.0;
    for (chart, (_, h)) in charts.iter().zip(&sizes) {
        s += &chart.replacen("<svg ", &format!("<svg y=\"{y:.0}\" "), 1);
        y += h;
    }
    s + "</svg>\n"
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_thinning_keeps_the_extremes() {
        assert_eq!(ticks(0.0, 10.0, 5.0), (vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0], 0));
        let (t, d) = ticks(-0.0013, 0.0042, 6.0);
        assert_eq!(d, 3);
        assert_eq!(t.len(), 6, "{t:?}");
        let points: Vec<(f64, f64)> = (0..10_000).map(|i| (i as f64, if i == 5_003 { 9.0 } else { 0.0 })).collect();
        let thin = thin(&points, 100);
        assert!(thin.len() <= 200, "{}", thin.len());
        assert!(thin.contains(&(5_003.0, 9.0)));
        assert_eq!(thin[0], (0.0, 0.0));
        let svg =
            line_chart("a <b>", "x", "y", &[Line { label: "x & y".into(), points: vec![(0.0, 0.0), (1.0, 0.002)] }]);
        assert!(svg.contains("a &lt;b&gt;") && svg.contains("x &amp; y") && svg.contains("polyline"));
        let (w, h) = size(&svg);
        assert!(w > 600.0 && h > 400.0, "{w} x {h}");
        let two = stack(&[svg.clone(), svg.clone()]);
        assert_eq!(size(&two), (w, 2.0 * h));
        assert!(two.contains(&format!("<svg y=\"{h:.0}\" ")), "the second chart stands under the first");
    }

    #[test]
    fn a_long_legend_stays_inside_the_picture() {
        // The engage study's legend: a step and cut named after the tool.
        let label = "oval:16,24, step-down, down-cut";
        let points = vec![(0.0, 0.0), (75.0, 0.11)];
        let svg = line_chart(
            "Largest chip area per inclination, oval:16,24",
            "inclination α, deg",
            "A max, mm²",
            &[
                Line { label: "oval:16,24, step-up, down-cut".into(), points: points.clone() },
                Line { label: label.into(), points },
            ],
        );
        let png = crate::plot::png_from_svg(&svg).unwrap();
        let img = image::load_from_memory(&png).unwrap().to_rgba8();
        let (w, h) = img.dimensions();
        // Text reaching the right edge is cut off there: the last 8 columns
        // stay white.
        let inked = (w - 8..w).flat_map(|x| (0..h).map(move |y| (x, y))).filter(|&(x, y)| {
            let p = img.get_pixel(x, y).0;
            u32::from(p[0]) + u32::from(p[1]) + u32::from(p[2]) < 600
        });
        assert_eq!(inked.count(), 0, "the legend runs off the right edge of a {w} px chart");
        // And the legend's text is there, right of the plot.
        let text =
            (700..w).flat_map(|x| (40..80).map(move |y| (x, y))).filter(|&(x, y)| img.get_pixel(x, y).0[0] < 128);
        assert!(text.count() > 100);
    }
}
