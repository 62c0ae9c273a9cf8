//! Raster pictures that explain themselves: the raster (a simulated
//! surface, its deviation, a probed grid, a tool's silhouette) framed by a
//! title, axes in mm and, where colour carries a value, a colour bar with
//! its unit — drawn as SVG around (and over) the raster and rendered to one
//! PNG with the bundled font ([`crate::png_from_svg`]'s).

use std::fmt::Write as _;

use resvg::tiny_skia;

use crate::chart::{escape, frame_axes, ticks};
use crate::plot::{canvas, encode, render_onto};
use crate::Error;

/// Pixels of a picture, RGB, rows top to bottom.
pub struct Raster {
    /// Pixels across.
    pub width: usize,
    /// Pixels down.
    pub height: usize,
    /// Red, green and blue of each pixel, row by row.
    pub rgb: Vec<u8>,
}

/// A line drawn over a raster, in its pixels (x right, y down).
pub struct Overlay {
    /// The line's points, in the raster's pixels.
    pub points: Vec<(f64, f64)>,
    /// An SVG colour.
    pub colour: String,
    /// Stroke width in pixels of the figure.
    pub width: f64,
}

/// One raster with its axes.
pub struct Panel {
    /// The picture itself.
    pub raster: Raster,
    /// What the raster covers, mm: left, right, bottom, top edge.
    pub extent: [f64; 4],
    /// The horizontal and vertical axis' names ("X, mm").
    pub axes: [String; 2],
    /// A line over the panel; empty for none.
    pub caption: String,
    /// Lines drawn over the raster.
    pub overlays: Vec<Overlay>,
}

/// What colour means: a bar of the colours from the lowest value to the
/// highest, with ticks, and swatches of colours outside it.
pub struct ColourBar {
    /// Values (in the unit of `label`) and their colours, lowest first;
    /// linear between.
    pub stops: Vec<(f64, [u8; 3])>,
    /// The value and its unit, over the bar ("Z, mm").
    pub label: String,
    /// Lines under the bar: what sets the scale, what lies beyond it.
    pub notes: Vec<String>,
    /// Colours the bar does not hold, and what each means.
    pub swatches: Vec<([u8; 3], String)>,
}

/// A framed picture.
pub struct Figure {
    /// The first line: file and tool.
    pub title: String,
    /// The line under it; empty for none.
    pub subtitle: String,
    /// Panels, all drawn at the scale of the first's pixels.
    pub panels: Vec<Panel>,
    /// Panels one above the other (else side by side).
    pub stacked: bool,
    /// What colour means, where it carries a value.
    pub bar: Option<ColourBar>,
    /// Lines of the legend under the panels: an SVG colour and its meaning.
    pub legend: Vec<(String, String)>,
}

/// A raster smaller than this on its longer side is drawn larger, a whole
/// number of pixels per pixel.
const MIN_SIDE: usize = 360;
const LEFT: f64 = 78.0;
const GAP: f64 = 84.0;
/// Under a panel: its tick labels and axis name.
const BELOW: f64 = 48.0;

/// Width of `text` at `size` px in DejaVu Sans, about (for the layout).
fn text_width(text: &str, size: f64) -> f64 {
    text.chars().count() as f64 * size * 0.6
}

fn rgb(c: [u8; 3]) -> String {
    format!("rgb({},{},{})", c[0], c[1], c[2])
}

/// Where the parts of a figure go.
struct Layout {
    /// Pixels of the figure per raster pixel.
    k: usize,
    /// Each panel's top-left corner.
    at: Vec<(f64, f64)>,
    width: f64,
    height: f64,
    /// The colour bar's left, top and height.
    bar: (f64, f64, f64),
}

impl Figure {
    fn layout(&self) -> Layout {
        let longest = self.panels.iter().map(|p| p.raster.width.max(p.raster.height)).max().unwrap_or(1).max(1);
        let k = (MIN_SIDE / longest).clamp(1, 16);
        let size = |p: &Panel| ((p.raster.width * k) as f64, (p.raster.height * k) as f64);
        let mut top: f64 = 30.0 + if self.subtitle.is_empty() { 0.0 } else { 18.0 };
        if self.panels.iter().any(|p| !p.caption.is_empty()) {
            top += 18.0;
        }
        let mut at = Vec::new();
        let (mut x, mut y) = (LEFT, top);
        let (mut right, mut bottom) = (LEFT, top);
        for p in &self.panels {
            let (w, h) = size(p);
            at.push((x, y));
            right = right.max(x + w);
            bottom = bottom.max(y + h + BELOW);
            if self.stacked {
                y += h + BELOW + if p.caption.is_empty() { 6.0 } else { 24.0 };
            } else {
                x += w + GAP;
            }
        }
        let mut width = right + 20.0;
        let mut height = bottom + 18.0 * self.legend.len() as f64 + 8.0;
        for (_, text) in &self.legend {
            width = width.max(LEFT + 40.0 + text_width(text, 12.0) + 10.0);
        }
        let title_width = text_width(&self.title, 14.0).max(text_width(&self.subtitle, 12.0));
        width = width.max(20.0 + title_width + 20.0);
        let mut bar = (0.0, top, 0.0);
        if let Some(b) = &self.bar {
            let panels = bottom - BELOW - top;
            let bar_h = panels.clamp(160.0, 320.0);
            let bx = right + 40.0;
            bar = (bx, top + 24.0, bar_h);
            let lines = b.notes.iter().chain(b.swatches.iter().map(|s| &s.1));
            let column = lines.map(|t| text_width(t, 12.0) + 24.0).fold(text_width(&b.label, 12.0), f64::max);
            width = width.max(bx + column.max(90.0) + 16.0);
            let under = 24.0 + bar_h + 22.0 + 18.0 * (b.notes.len() + b.swatches.len()) as f64;
            height = height.max(top + under + 10.0);
        }
        Layout { k, at, width: width.ceil(), height: height.ceil(), bar }
    }

    /// The figure as SVG: what is drawn under the rasters (each raster's
    /// place a white rectangle) and what is drawn over them.
    fn layers(&self, l: &Layout) -> (String, String) {
        let (w, h) = (l.width, l.height);
        let head = format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{h:.0}" viewBox="0 0 {w:.0} {h:.0}" font-family="sans-serif" font-size="12">"#
        );
        let mut under = head.clone() + "\n";
        let mut over = head + "\n";
        let _ = writeln!(under, r#"<rect width="100%" height="100%" fill="white"/>"#);
        let _ = writeln!(under, r#"<text x="20" y="20" font-size="14">{}</text>"#, escape(&self.title));
        if !self.subtitle.is_empty() {
            let _ = writeln!(under, r##"<text x="20" y="38" fill="#444">{}</text>"##, escape(&self.subtitle));
        }
        let k = l.k as f64;
        for (p, &(x, y)) in self.panels.iter().zip(&l.at) {
            let (pw, ph) = (p.raster.width as f64 * k, p.raster.height as f64 * k);
            let _ = writeln!(under, r#"<rect x="{x}" y="{y}" width="{pw}" height="{ph}" fill="white"/>"#);
            if !p.caption.is_empty() {
                let _ = writeln!(under, r#"<text x="{x}" y="{:.1}">{}</text>"#, y - 8.0, escape(&p.caption));
            }
            frame_axes(&mut under, (x, y, pw, ph), p.extent, [&p.axes[0], &p.axes[1]]);
            for o in &p.overlays {
                let points: Vec<String> =
                    o.points.iter().map(|&(u, v)| format!("{:.1},{:.1}", x + u * k, y + v * k)).collect();
                let _ = writeln!(
                    over,
                    r#"<polyline fill="none" stroke="{}" stroke-width="{}" stroke-linejoin="round" points="{}"/>"#,
                    o.colour,
                    o.width,
                    points.join(" ")
                );
            }
            let _ = writeln!(over, r##"<rect x="{x}" y="{y}" width="{pw}" height="{ph}" fill="none" stroke="#444"/>"##);
        }
        let legend_top =
            l.at.iter().zip(&self.panels).map(|(a, p)| a.1 + p.raster.height as f64 * k).fold(0.0, f64::max) + BELOW;
        for (i, (colour, text)) in self.legend.iter().enumerate() {
            let ly = legend_top + 18.0 * i as f64 + 6.0;
            let _ = writeln!(
                under,
                r#"<rect x="{LEFT}" y="{:.1}" width="28" height="10" fill="{colour}" stroke="{colour}"/><text x="{:.1}" y="{:.1}">{}</text>"#,
                ly - 9.0,
                LEFT + 36.0,
                ly,
                escape(text)
            );
        }
        if let Some(b) = &self.bar {
            self.colour_bar(&mut under, b, l.bar);
        }
        (under + "</svg>\n", over + "</svg>\n")
    }

    fn colour_bar(&self, s: &mut String, b: &ColourBar, (bx, by, bh): (f64, f64, f64)) {
        let _ = writeln!(s, r#"<text x="{bx:.1}" y="{:.1}">{}</text>"#, by - 14.0, escape(&b.label));
        let (lo, hi) = (b.stops.first().map_or(0.0, |s| s.0), b.stops.last().map_or(1.0, |s| s.0));
        let span = (hi - lo).max(1e-300);
        let _ = writeln!(s, r#"<linearGradient id="bar" x1="0" y1="1" x2="0" y2="0">"#);
        for &(v, c) in &b.stops {
            let _ = writeln!(s, r#"<stop offset="{:.4}" stop-color="{}"/>"#, (v - lo) / span, rgb(c));
        }
        let _ = writeln!(s, "</linearGradient>");
        let _ = writeln!(
            s,
            r##"<rect class="colour-bar" x="{bx:.1}" y="{by:.1}" width="18" height="{bh:.1}" fill="url(#bar)" stroke="#444"/>"##
        );
        let (t, d) = ticks(lo, hi, (bh / 40.0).max(2.0));
        let plus = lo < 0.0 && hi > 0.0;
        for v in t {
            let y = by + bh - bh * (v - lo) / span;
            let _ = writeln!(
                s,
                r##"<line x1="{:.1}" x2="{:.1}" y1="{y:.1}" y2="{y:.1}" stroke="#444"/><text x="{:.1}" y="{:.1}">{}</text>"##,
                bx + 18.0,
                bx + 23.0,
                bx + 26.0,
                y + 4.0,
                signed(v, d, plus)
            );
        }
        let mut y = by + bh + 22.0;
        for n in &b.notes {
            let _ = writeln!(s, r#"<text x="{bx:.1}" y="{y:.1}">{}</text>"#, escape(n));
            y += 18.0;
        }
        for (c, n) in &b.swatches {
            let _ = writeln!(
                s,
                r##"<rect x="{bx:.1}" y="{:.1}" width="18" height="12" fill="{}" stroke="#444"/><text x="{:.1}" y="{y:.1}">{}</text>"##,
                y - 10.0,
                rgb(*c),
                bx + 24.0,
                escape(n)
            );
            y += 18.0;
        }
    }

    /// The figure as one SVG text (each raster's place left white): what
    /// the PNG shows but the rasters.
    #[cfg(test)]
    pub fn svg(&self) -> String {
        let l = self.layout();
        let (under, over) = self.layers(&l);
        let body = over.split_once('\n').map_or("", |(_, rest)| rest);
        under.trim_end().trim_end_matches("</svg>").to_string() + body
    }

    /// The figure as PNG bytes.
    pub fn png(&self) -> Result<Vec<u8>, Error> {
        let l = self.layout();
        let mut pixmap = canvas(l.width as u32, l.height as u32)?;
        let (under, over) = self.layers(&l);
        render_onto(&under, &mut pixmap)?;
        for (p, &(x, y)) in self.panels.iter().zip(&l.at) {
            blit(&mut pixmap, &p.raster, x as usize, y as usize, l.k);
        }
        render_onto(&over, &mut pixmap)?;
        encode(&pixmap)
    }
}

/// A tick value, with `+` before it when `plus` and it is above zero.
fn signed(v: f64, decimals: usize, plus: bool) -> String {
    let v = if v.abs() < 0.5 * 10f64.powi(-(decimals as i32)) { 0.0 } else { v };
    if plus && v > 0.0 {
        format!("+{v:.decimals$}")
    } else {
        format!("{v:.decimals$}")
    }
}

/// Copies `r` into `pixmap` at `(x, y)`, `k` pixels a side per pixel.
fn blit(pixmap: &mut tiny_skia::Pixmap, r: &Raster, x: usize, y: usize, k: usize) {
    let width = pixmap.width() as usize;
    let data = pixmap.data_mut();
    for row in 0..r.height * k {
        for col in 0..r.width * k {
            let src = 3 * ((row / k) * r.width + col / k);
            let dst = 4 * ((y + row) * width + x + col);
            if dst + 4 <= data.len() {
                data[dst..dst + 3].copy_from_slice(&r.rgb[src..src + 3]);
                data[dst + 3] = 255;
            }
        }
    }
}

/// The colour at `v` of a bar's `stops`.
pub fn colour_at(stops: &[(f64, [u8; 3])], v: f64) -> [u8; 3] {
    let Some(first) = stops.first() else { return [0; 3] };
    if v <= first.0 {
        return first.1;
    }
    for pair in stops.windows(2) {
        let ((a, ca), (b, cb)) = (pair[0], pair[1]);
        if v <= b {
            let t = if b > a { (v - a) / (b - a) } else { 1.0 };
            return [0, 1, 2].map(|i| (f64::from(ca[i]) + (f64::from(cb[i]) - f64::from(ca[i])) * t).round() as u8);
        }
    }
    stops[stops.len() - 1].1
}

#[cfg(test)]
mod tests {
    use super::*;

    fn figure(bar: bool) -> Figure {
        let raster = Raster { width: 400, height: 200, rgb: [10u8, 200, 30].repeat(400 * 200) };
        Figure {
            title: "part.nc: simulated surface, T1 ball:6".into(),
            subtitle: "a line under it".into(),
            panels: vec![Panel {
                raster,
                extent: [0.0, 40.0, -5.0, 15.0],
                axes: ["X, mm".into(), "Y, mm".into()],
                caption: "as programmed".into(),
                overlays: vec![Overlay {
                    points: vec![(0.0, 100.0), (400.0, 100.0)],
                    colour: "red".into(),
                    width: 3.0,
                }],
            }],
            stacked: false,
            bar: bar.then(|| ColourBar {
                stops: vec![(-4.0, [200, 20, 30]), (0.0, [255, 255, 255]), (4.0, [30, 70, 210])],
                label: "simulated − target, µm".into(),
                notes: vec!["±4 µm: the 99th percentile".into()],
                swatches: vec![([255, 0, 255], "gouge".into())],
            }),
            legend: vec![("red".into(), "a red line".into())],
        }
    }

    #[test]
    fn a_figure_frames_its_raster_with_title_axes_bar_and_legend() {
        let f = figure(true);
        let svg = f.svg();
        for want in [
            "part.nc: simulated surface, T1 ball:6",
            "X, mm",
            "Y, mm",
            "class=\"colour-bar\"",
            "simulated − target, µm",
            "the 99th percentile",
            "gouge",
            "a red line",
            ">40<",
            ">10<",
            ">+4<",
        ] {
            assert!(svg.contains(want), "{want}: {svg}");
        }
        let png = f.png().unwrap();
        assert_eq!(png, figure(true).png().unwrap(), "the same picture, byte for byte");
        let img = image::load_from_memory(&png).unwrap().to_rgb8();
        let l = f.layout();
        assert_eq!(l.k, 1);
        let (x, y) = (l.at[0].0 as u32, l.at[0].1 as u32);
        // The raster in its place, the overlay's line over it.
        assert_eq!(img.get_pixel(x + 50, y + 20).0, [10, 200, 30]);
        assert_eq!(img.get_pixel(x + 50, y + 100).0, [255, 0, 0]);
        // The bar's middle is white (zero), its bottom red.
        let (bx, by, bh) = l.bar;
        let middle = img.get_pixel(bx as u32 + 9, (by + bh / 2.0) as u32).0;
        assert!(middle.iter().all(|&c| c >= 250), "{middle:?}");
        let low = img.get_pixel(bx as u32 + 9, (by + bh - 2.0) as u32).0;
        assert!(low[0] > 190 && low[1] < 40, "{low:?}");
        assert!(img.width() as f64 >= bx + 100.0);
    }

    #[test]
    fn small_rasters_are_drawn_larger_and_colours_interpolate() {
        let mut f = figure(false);
        f.panels[0].raster = Raster { width: 20, height: 10, rgb: vec![90; 600] };
        let l = f.layout();
        assert_eq!(l.k, 16, "360 / 20 pixels a pixel, at most 16");
        let stops = [(0.0, [0, 0, 0]), (10.0, [200, 100, 0])];
        assert_eq!(colour_at(&stops, 5.0), [100, 50, 0]);
        assert_eq!(colour_at(&stops, -1.0), [0, 0, 0]);
        assert_eq!(colour_at(&stops, 11.0), [200, 100, 0]);
    }
}
