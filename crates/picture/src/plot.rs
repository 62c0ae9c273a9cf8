//! A picture of a toolpath: SVG, the views in which the path shows (the top
//! view and the front or side view, whichever is wider; an isometric view
//! where one of them would be a line), with axes in mm and a legend. Feed
//! moves are solid and shaded by depth (a colour bar of Z), rapids dashed
//! red and framed whole, dense paths drawn thin but passes closer than a
//! few pixels seen from the top drawn as wide as they lie apart (the cut
//! form shaded by depth). The count is of motions, as `check` counts them.
//! Charts are SVG text too; [`png_from_svg`] makes any of them a PNG
//! picture.

use std::collections::{BTreeMap, HashSet};
use std::fmt::Write;
use std::sync::{Arc, OnceLock};

use kezuri_geom::{Axes, MoveKind, Toolpath};
use resvg::{tiny_skia, usvg};

use crate::chart::{escape, frame_axes};
use crate::{Error, ErrorKind};

/// The longest side of a view, pixels.
const PANEL: f64 = 480.0;
/// Left of the first view (its tick labels and axis name).
const LEFT: f64 = 70.0;
/// Between two views.
const GAP: f64 = 80.0;

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
    /// Red and green of the blue shade: 150 at the top, 0 at the bottom.
    Cut(u8),
}

/// A view of the path: its caption, the names of its axes and how a point
/// is projected onto it (right, up).
#[derive(Clone, Copy)]
struct View {
    caption: &'static str,
    axes: [&'static str; 2],
    /// Whether its axes are true lengths (not the isometric view).
    true_length: bool,
    project: fn([f64; 3]) -> (f64, f64),
}

const TOP: View =
    View { caption: "top (X right, Y up)", axes: ["X, mm", "Y, mm"], true_length: true, project: |p| (p[0], p[1]) };
const FRONT: View =
    View { caption: "front (X right, Z up)", axes: ["X, mm", "Z, mm"], true_length: true, project: |p| (p[0], p[2]) };
const SIDE: View =
    View { caption: "side (Y right, Z up)", axes: ["Y, mm", "Z, mm"], true_length: true, project: |p| (p[1], p[2]) };
/// Seen from the front right, above: X and Y 30° below the horizontal.
const ISO: View = View {
    caption: "isometric (from front right, above)",
    axes: ["", ""],
    true_length: false,
    project: |p| {
        let (c, s) = (30f64.to_radians().cos(), 0.5);
        (c * (p[0] + p[1]), p[2] + s * (p[1] - p[0]))
    },
};

/// The projected box of `pts` in `view`: `[u0, u1, v0, v1]`.
fn extent(view: &View, pts: &[[f64; 3]]) -> [f64; 4] {
    pts.iter().fold([f64::MAX, f64::MIN, f64::MAX, f64::MIN], |b, &p| {
        let (u, v) = (view.project)(p);
        [b[0].min(u), b[1].max(u), b[2].min(v), b[3].max(v)]
    })
}

/// Whether the path is (nearly) a line in a view of box `e`: one side under
/// 2 % of the other, or under a micrometre.
fn flat(e: &[f64; 4]) -> bool {
    let (a, b) = (e[1] - e[0], e[3] - e[2]);
    a.min(b) <= (0.02 * a.max(b)).max(1e-3)
}

/// A view as drawn: the box it shows (mm), its vertical axis drawn
/// `stretch` times its horizontal.
struct Shown {
    view: View,
    e: [f64; 4],
    stretch: f64,
}

/// The smallest of 1, 2, 5 × 10ⁿ at least `x` (at most 1000).
fn round_up(x: f64) -> f64 {
    let mag = 10f64.powf(x.max(1.0).log10().floor());
    [1.0, 2.0, 5.0, 10.0].into_iter().map(|k| k * mag).find(|s| *s >= x).unwrap_or(10.0 * mag).min(1000.0)
}

/// The views in which the path `pts` shows: the top view and the front or
/// side view, the one in which the `feeds` are longer (else the wider), less those in which it is a line (Z drawn
/// larger in a front or side view under an eighth as tall as wide); the
/// isometric view when neither shows it.
fn views(pts: &[[f64; 3]], feeds: &[Vec<[f64; 3]>]) -> (Vec<Shown>, Vec<&'static str>) {
    let e = |v: View| Shown { view: v, e: extent(&v, pts), stretch: 1.0 };
    let (top, front, side) = (e(TOP), e(FRONT), e(SIDE));
    // The view in which the feed moves are longer (a raster along X seen
    // from the front, not end-on), else the wider.
    let length = |v: &View| -> f64 {
        feeds
            .iter()
            .flat_map(|m| m.windows(2))
            .map(|p| {
                let (a, b) = ((v.project)(p[0]), (v.project)(p[1]));
                (b.0 - a.0).hypot(b.1 - a.1)
            })
            .sum()
    };
    let (lf, ls) = (length(&FRONT), length(&SIDE));
    let front_wins =
        if (lf - ls).abs() > 0.1 * lf.max(ls) { lf > ls } else { front.e[1] - front.e[0] >= side.e[1] - side.e[0] };
    let mut wide = if front_wins { front } else { side };
    let (su, sv) = (wide.e[1] - wide.e[0], wide.e[3] - wide.e[2]);
    if sv >= 1e-3 && sv < su / 8.0 {
        wide.stretch = round_up(su / 8.0 / sv);
    }
    let stretched = Shown { e: [wide.e[0], wide.e[1], 0.0, sv * wide.stretch], ..wide };
    let (mut out, mut left_out) = (Vec::new(), Vec::new());
    for (shown, box_) in [(top, None), (wide, Some(stretched.e))] {
        if flat(&box_.unwrap_or(shown.e)) {
            left_out.push(shown.view.caption.split(' ').next().unwrap_or(""));
        } else {
            out.push(shown);
        }
    }
    if out.is_empty() {
        out.push(e(ISO));
    }
    (out, left_out)
}

/// Writes `lines` (points in hundredths of a pixel) as one path drawn in
/// `style`, `width` pixels wide.
fn draw(out: &mut String, style: Stroke, lines: Vec<Vec<(i64, i64)>>, width: f64) {
    let mut d = String::new();
    for line in lines {
        for (i, (x, y)) in line.into_iter().enumerate() {
            let (x, y) = (x as f64 / 100.0, y as f64 / 100.0);
            let _ = write!(d, "{}{x:.2} {y:.2} ", if i == 0 { 'M' } else { 'L' });
        }
    }
    let _ = match style {
        Stroke::Cut(s) => writeln!(
            out,
            r#"<path d="{}" fill="none" stroke="{}" stroke-width="{width:.2}"/>"#,
            d.trim_end(),
            cut_colour(s)
        ),
        Stroke::Rapid => writeln!(
            out,
            r##"<path d="{}" fill="none" stroke="#d33" stroke-dasharray="{:.1} {:.1}" stroke-width="{width:.2}"/>"##,
            d.trim_end(),
            (6.0 * width).max(2.0),
            (4.0 * width).max(1.5)
        ),
    };
}

/// The colour of a cut at depth shade `s` (150 at the top, 0 at the
/// bottom): light blue high, dark blue deep, so heights read in every view.
fn cut_colour(s: u8) -> String {
    let t = f64::from(s.min(150)) / 150.0;
    let c = |lo: f64, hi: f64| (lo + (hi - lo) * t).round() as u8;
    format!("rgb({},{},{})", c(10.0, 190.0), c(20.0, 200.0), c(120.0, 255.0))
}

/// Width of a line of `length` pixels in all over `area` square pixels: a
/// pixel where the path is sparse, thinner as it covers more.
fn width_for(length: f64, area: f64, widest: f64) -> f64 {
    (0.3 * area / length.max(1.0)).clamp(0.25, widest)
}

/// The SVG text for `path`, titled `title` (the file and the tool).
pub fn svg(path: &Toolpath, title: &str) -> String {
    let drawn_moves = || path.moves.iter().filter(|m| !matches!(m.kind, MoveKind::Dwell(_)));
    let xyz = |m: &kezuri_geom::Move| points(m).into_iter().map(|p| p.xyz()).collect::<Vec<_>>();
    // The views frame the feed moves and the rapids (G0), drawn whole; a
    // return to the reference point or a G53 move (and a rapid on from one)
    // goes to a machine position the program does not name, and is cut off
    // at the view's edge.
    let feeds: Vec<Vec<[f64; 3]>> = drawn_moves().filter(|m| !m.is_rapid()).map(xyz).collect();
    let machine = |m: &kezuri_geom::Move| matches!(m.kind, MoveKind::Home | MoveKind::Machine);
    let mut framed: Vec<[f64; 3]> = feeds.concat();
    // A program's first move starts wherever the machine is: not framed.
    let mut after_machine = path.unknown_start;
    for m in drawn_moves() {
        if m.kind == MoveKind::Rapid {
            if !after_machine {
                framed.push(m.start.xyz());
            }
            framed.push(m.end.xyz());
        }
        after_machine = machine(m);
    }
    if framed.is_empty() {
        framed = drawn_moves().flat_map(xyz).collect();
    }
    if framed.is_empty() {
        framed = vec![[0.0; 3], [1.0; 3]];
    }
    // Feed moves shaded by their depth (the rapids' heights left out).
    let shaded: Vec<&[f64; 3]> =
        if feeds.is_empty() { framed.iter().collect() } else { feeds.iter().flatten().collect() };
    let (zlo, zhi) = shaded.iter().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p[2]), b.max(p[2])));
    // Whether a move from the unknown start, to or from a machine position
    // leaves the views' box.
    let (lo, hi) = framed.iter().fold(([f64::MAX; 3], [f64::MIN; 3]), |(lo, hi), p| {
        ([0, 1, 2].map(|i| lo[i].min(p[i])), [0, 1, 2].map(|i| hi[i].max(p[i])))
    });
    let outside = |p: Axes| (0..3).any(|i| p.xyz()[i] < lo[i] - 1e-6 || p.xyz()[i] > hi[i] + 1e-6);
    let cut_off = drawn_moves().any(|m| outside(m.start) || outside(m.end));
    let depth = (zhi - zlo).max(1e-9);
    let (shown, left_out) = views(&framed, &feeds);
    let span = |s: &Shown| ((s.e[1] - s.e[0]).max(1e-6), ((s.e[3] - s.e[2]) * s.stretch).max(1e-6));
    let largest = shown.iter().map(|s| span(s).0.max(span(s).1)).fold(0.0, f64::max);
    let scale = PANEL / largest;
    let top = 70.0;
    let mut left = LEFT;
    let mut placed = Vec::new();
    for s in &shown {
        let (su, sv) = span(s);
        placed.push((s, left, (scale * su).max(1.0), (scale * sv).max(1.0)));
        left += scale * su + GAP;
    }
    let tallest = placed.iter().map(|p| p.3).fold(0.0, f64::max);
    let legend_y = top + tallest + 56.0;
    let views_text: Vec<&str> = placed.iter().map(|p| p.0.view.caption).collect();
    let subtitle = format!(
        "{} {}, {} motions (moves without dwells, as check counts them){}",
        views_text.join(" and "),
        if placed.len() > 1 { "views" } else { "view" },
        drawn_moves().count(),
        if left_out.is_empty() {
            String::new()
        } else {
            format!("; no {} view: the path is a line in it", left_out.join(" or "))
        }
    );
    // The title (14 px), the subtitle and the legend's lines (12 px) within
    // the picture: DejaVu Sans is at most about 0.6 em a character.
    let text_width = |text: &str, size: f64| 0.6 * size * text.chars().count() as f64;
    let width = (left - GAP + 20.0)
        .max(LEFT + 560.0)
        .max(30.0 + text_width(title, 14.0))
        .max(30.0 + text_width(&subtitle, 12.0))
        .max(if cut_off { LEFT + 20.0 + text_width(CUT_OFF, 12.0) } else { 0.0 });
    let height = legend_y + 50.0 + if cut_off { 20.0 } else { 0.0 };
    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.1} {height:.1}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(out, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(out, r#"<text x="20" y="20" font-size="14">{}</text>"#, escape(title));
    let _ = writeln!(out, r##"<text x="20" y="38" fill="#444">{}</text>"##, escape(&subtitle));
    let mut rapids = false;
    for (k, (shown, left, pw, ph)) in placed.into_iter().enumerate() {
        let Shown { view, e, stretch } = *shown;
        let base = top + ph;
        let caption =
            if stretch > 1.0 { format!("{}, Z drawn ×{stretch}", view.caption) } else { view.caption.to_string() };
        let _ = writeln!(out, r#"<text x="{left:.1}" y="{:.1}">{caption}</text>"#, top - 8.0);
        let _ = writeln!(
            out,
            r##"<rect x="{left:.1}" y="{top:.1}" width="{pw:.1}" height="{ph:.1}" fill="none" stroke="#ccc"/>"##
        );
        let _ = writeln!(
            out,
            r#"<clipPath id="view{k}"><rect x="{:.1}" y="{:.1}" width="{:.1}" height="{:.1}"/></clipPath>"#,
            left - 4.0,
            top - 4.0,
            pw + 8.0,
            ph + 8.0
        );
        // One path per style, cuts first and rapids over them; a segment
        // already drawn in that style (a repeated plunge seen from the front)
        // is drawn once, and steps on along a line lengthen it.
        let mut drawn = HashSet::new();
        // The 8-pixel squares the cuts pass over: the area they cover (a
        // lone line covers 8 pixels each side of it, rows closer cover less).
        let mut covered = HashSet::new();
        let mut styles: BTreeMap<Stroke, Vec<Vec<(i64, i64)>>> = BTreeMap::new();
        let mut dots: BTreeMap<Stroke, Vec<(i64, i64)>> = BTreeMap::new();
        let (mut cut_length, mut rapid_length) = (0.0, 0.0);
        for m in &path.moves {
            if matches!(m.kind, MoveKind::Dwell(_)) {
                continue;
            }
            // Deeper cuts darker.
            let next = if m.is_rapid() {
                Stroke::Rapid
            } else {
                Stroke::Cut((150.0 * (1.0 - ((zhi - m.end.z) / depth).clamp(0.0, 1.0))) as u8)
            };
            let lines = styles.entry(next).or_default();
            // Points in hundredths of a pixel.
            let pts: Vec<(i64, i64)> = points(m)
                .iter()
                .map(|p| {
                    let (u, v) = (view.project)(p.xyz());
                    let x = left + scale * (u - e[0]);
                    let y = base - scale * stretch * (v - e[2]);
                    ((x * 100.0).round() as i64, (y * 100.0).round() as i64)
                })
                .collect();
            // A feed move seen end-on (a plunge from above) is a dot.
            if next != Stroke::Rapid && pts.iter().all(|p| *p == pts[0]) {
                if drawn.insert((next, pts[0], pts[0])) {
                    dots.entry(next).or_default().push(pts[0]);
                }
                continue;
            }
            for pair in pts.windows(2) {
                let (a, b) = (pair[0], pair[1]);
                if a == b || !drawn.insert((next, a.min(b), a.max(b))) {
                    continue;
                }
                let length = (((b.0 - a.0) as f64).hypot((b.1 - a.1) as f64)) / 100.0;
                if next == Stroke::Rapid {
                    rapid_length += length;
                } else {
                    cut_length += length;
                    let steps = (length / 4.0).ceil().max(1.0) as i64;
                    for k in 0..=steps {
                        let (x, y) = (a.0 + (b.0 - a.0) * k / steps, a.1 + (b.1 - a.1) * k / steps);
                        covered.insert((x.div_euclid(800), y.div_euclid(800)));
                    }
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
        let area = pw.max(20.0) * ph.max(20.0);
        let (mut cut_width, rapid_width) = (width_for(cut_length, area, 1.2), width_for(rapid_length, area, 0.8));
        // Seen from the top, passes closer than a few pixels (a raster, a
        // pocket's rows) are drawn as wide as they lie apart: the cut form,
        // shaded by depth, not a carpet of rows.
        let apart = 64.0 * covered.len() as f64 / cut_length.max(1.0);
        if view.caption == TOP.caption && apart < 7.0 {
            cut_width = cut_width.max(1.2 * apart);
        }
        let _ = writeln!(out, r#"<g clip-path="url(#view{k})">"#);
        for (style, lines) in styles.into_iter().rev() {
            if !lines.is_empty() {
                rapids |= style == Stroke::Rapid;
                draw(&mut out, style, lines, if style == Stroke::Rapid { rapid_width } else { cut_width });
            }
        }
        for (style, at) in dots.into_iter().rev() {
            if let Stroke::Cut(s) = style {
                let d: Vec<String> =
                    at.iter().map(|&(x, y)| format!("M{:.2} {:.2}h0.01", x as f64 / 100.0, y as f64 / 100.0)).collect();
                let _ = writeln!(
                    out,
                    r#"<path d="{}" fill="none" stroke="{}" stroke-width="{:.2}" stroke-linecap="round"/>"#,
                    d.join(""),
                    cut_colour(s),
                    (2.0 * cut_width).clamp(1.5, 2.5)
                );
            }
        }
        out.push_str("</g>\n");
        if view.true_length {
            frame_axes(&mut out, (left, top, pw, ph), e, view.axes);
        } else {
            triad(&mut out, &view, left - 20.0, base);
        }
    }
    legend(&mut out, legend_y, zlo, zhi, rapids, cut_off);
    out.push_str("</svg>\n");
    out
}

/// The directions of X, Y and Z in a view without true lengths, 30 pixels
/// long from `(x, y)`.
fn triad(out: &mut String, view: &View, x: f64, y: f64) {
    let o = (view.project)([0.0; 3]);
    for (k, name) in ["X", "Y", "Z"].iter().enumerate() {
        let mut p = [0.0; 3];
        p[k] = 1.0;
        let (u, v) = (view.project)(p);
        let (du, dv) = (u - o.0, v - o.1);
        let n = du.hypot(dv).max(1e-9);
        let (ex, ey) = (x - 30.0 + 24.0 * du / n, y - 24.0 - 24.0 * dv / n);
        let _ = writeln!(
            out,
            r##"<line x1="{:.1}" y1="{:.1}" x2="{ex:.1}" y2="{ey:.1}" stroke="#444"/><text x="{:.1}" y="{:.1}" font-size="10">{name}</text>"##,
            x - 30.0,
            y - 24.0,
            ex + 4.0 * du / n - 3.0,
            ey - 4.0 * dv / n + 4.0
        );
    }
}

/// `v` mm to 3 decimals, never "-0.000".
fn mm(v: f64) -> String {
    let t = format!("{v:.3}");
    if t == "-0.000" {
        "0.000".into()
    } else {
        t
    }
}

/// The legend's line for moves cut off at a view's edge.
const CUT_OFF: &str = "moves from where the machine stood at the start, or to or from the reference point \
                       (G28, G30) or a G53 position: cut off at the view's edge";

/// What the strokes mean: feed moves by depth (a bar of Z), rapids.
fn legend(out: &mut String, y: f64, zlo: f64, zhi: f64, rapids: bool, cut_off: bool) {
    let _ = writeln!(
        out,
        r#"<linearGradient id="depth" x1="0" x2="1"><stop offset="0" stop-color="{}"/><stop offset="1" stop-color="{}"/></linearGradient>"#,
        cut_colour(150),
        cut_colour(0)
    );
    let _ = writeln!(
        out,
        r##"<text x="{LEFT}" y="{y:.1}">feed (G1, G2, G3): solid, by Z</text><text x="{:.1}" y="{y:.1}" text-anchor="end">Z {}</text><rect class="legend-depth" x="{:.1}" y="{:.1}" width="120" height="10" fill="url(#depth)" stroke="#444"/><text x="{:.1}" y="{y:.1}">Z {} mm</text>"##,
        LEFT + 260.0,
        mm(zhi),
        LEFT + 266.0,
        y - 9.0,
        LEFT + 392.0,
        mm(zlo)
    );
    if rapids {
        let _ = writeln!(
            out,
            r##"<text x="{LEFT}" y="{:.1}">rapid (G0): dashed</text><line x1="{:.1}" x2="{:.1}" y1="{:.1}" y2="{:.1}" stroke="#d33" stroke-dasharray="6 4" stroke-width="1.5"/>"##,
            y + 20.0,
            LEFT + 266.0,
            LEFT + 386.0,
            y + 16.0,
            y + 16.0
        );
    }
    if cut_off {
        let _ = writeln!(out, r#"<text x="{LEFT}" y="{:.1}">{CUT_OFF}</text>"#, y + 40.0);
    }
}

/// A chart of one or more series over the same points (`y` in the unit
/// named), each `(name, colour, values)`, on a logarithmic axis from
/// `floor` up, the points numbered from 1 along `x_label`: the
/// before/after errors of a correction.
pub fn log_chart(title: &str, x_label: &str, unit: &str, floor: f64, series: &[(&str, &str, Vec<f64>)]) -> String {
    let (h, left, top, bottom) = (380.0, 80.0, 36.0, 50.0);
    let w = (left + 7.6 * title.chars().count() as f64 + 20.0).max(720.0).ceil();
    let right = w - 20.0;
    let n = series.iter().map(|s| s.2.len()).max().unwrap_or(0).max(2);
    let highest = series.iter().flat_map(|s| s.2.iter().copied()).fold(floor * 10.0, f64::max);
    let (lo, hi) = (floor.log10().floor(), highest.log10().ceil());
    let x = |k: usize| left + (right - left) * k as f64 / (n - 1) as f64;
    let y = |v: f64| top + (h - bottom - top) * (hi - v.max(floor).log10()) / (hi - lo);
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" font-family=\"sans-serif\" font-size=\"12\">\n\
         <rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<text x=\"{left}\" y=\"20\" font-size=\"14\">{}</text>\n",
        escape(title)
    );
    for e in (lo as i32)..=(hi as i32) {
        let v = 10f64.powi(e);
        let label = if e >= 0 { format!("{v:.0}") } else { format!("{v:.*}", (-e) as usize) };
        let _ = writeln!(
            s,
            "<line x1=\"{left}\" x2=\"{right}\" y1=\"{y0:.1}\" y2=\"{y0:.1}\" stroke=\"#ddd\"/><text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{label} {unit}</text>",
            left - 6.0,
            y(v) + 4.0,
            y0 = y(v),
        );
    }
    let every = n.div_ceil(12).max(1);
    for k in (0..n).filter(|k| k % every == 0 || *k == n - 1) {
        let _ = writeln!(
            s,
            "<line x1=\"{0:.1}\" x2=\"{0:.1}\" y1=\"{1:.1}\" y2=\"{2:.1}\" stroke=\"#444\"/><text x=\"{0:.1}\" y=\"{3:.1}\" text-anchor=\"middle\">{4}</text>",
            x(k),
            h - bottom,
            h - bottom + 5.0,
            h - bottom + 18.0,
            k + 1
        );
    }
    let _ = writeln!(
        s,
        "<rect x=\"{left}\" y=\"{top}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"none\" stroke=\"#888\"/>\n<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>",
        right - left,
        h - bottom - top,
        0.5 * (left + right),
        h - 12.0,
        escape(x_label)
    );
    for (k, (name, colour, values)) in series.iter().enumerate() {
        let points: Vec<String> = values.iter().enumerate().map(|(i, &v)| format!("{:.1},{:.1}", x(i), y(v))).collect();
        let _ = writeln!(
            s,
            "<polyline fill=\"none\" stroke=\"{colour}\" stroke-width=\"2\" points=\"{}\"/>",
            points.join(" ")
        );
        let ly = 0.5 * h + 18.0 * k as f64;
        let _ = writeln!(
            s,
            "<line x1=\"{:.1}\" x2=\"{:.1}\" y1=\"{:.1}\" y2=\"{:.1}\" stroke=\"{colour}\" stroke-width=\"3\"/><text x=\"{:.1}\" y=\"{ly:.1}\">{}</text>",
            right - 230.0,
            right - 206.0,
            ly - 4.0,
            ly - 4.0,
            right - 200.0,
            escape(name)
        );
    }
    s + "</svg>\n"
}

/// DejaVu Sans (assets/fonts, licence beside it): the one font of PNG
/// charts, so their text is drawn alike on every machine, fonts installed or
/// not.
static FONT: &[u8] = include_bytes!("../assets/fonts/DejaVuSans.ttf");
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

/// The SVG picture `svg` read, its text in the bundled DejaVu Sans.
fn tree(svg: &str) -> Result<usvg::Tree, Error> {
    let options = usvg::Options { font_family: FONT_FAMILY.into(), fontdb: fonts(), ..usvg::Options::default() };
    usvg::Tree::from_str(svg, &options)
        .map_err(|e| Error::new(ErrorKind::BadSvg, format!("cannot read the SVG picture: {e}")))
}

/// A transparent picture of `w` × `h` pixels, at most [`MAX_SIDE`] on a
/// side.
pub(crate) fn canvas(w: u32, h: u32) -> Result<tiny_skia::Pixmap, Error> {
    if w > MAX_SIDE || h > MAX_SIDE {
        return Err(Error::new(
            ErrorKind::PictureTooLarge,
            format!("the picture is {w} x {h} pixels: more than {MAX_SIDE} on a side"),
        ));
    }
    tiny_skia::Pixmap::new(w, h)
        .ok_or_else(|| Error::new(ErrorKind::EmptyPicture, format!("no picture of {w} x {h} pixels")))
}

/// `pixmap` as PNG bytes.
pub(crate) fn encode(pixmap: &tiny_skia::Pixmap) -> Result<Vec<u8>, Error> {
    pixmap.encode_png().map_err(|e| Error::new(ErrorKind::PngEncoding, format!("cannot encode the PNG picture: {e}")))
}

/// Draws the SVG picture `svg` onto `pixmap` (one pixel per SVG user unit,
/// from its top-left corner), text in the bundled DejaVu Sans.
pub(crate) fn render_onto(svg: &str, pixmap: &mut tiny_skia::Pixmap) -> Result<(), Error> {
    resvg::render(&tree(svg)?, tiny_skia::Transform::default(), &mut pixmap.as_mut());
    Ok(())
}

/// The SVG picture `svg` (the charts and toolpath pictures of this module)
/// as PNG bytes, one pixel per SVG user unit of its `width` × `height`; text
/// in the bundled DejaVu Sans; what the picture leaves unpainted is
/// transparent.
pub fn png_from_svg(svg: &str) -> Result<Vec<u8>, Error> {
    let tree = tree(svg)?;
    let size = tree.size().to_int_size();
    let mut pixmap = canvas(size.width(), size.height())?;
    resvg::render(&tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
    encode(&pixmap)
}

#[cfg(test)]
mod tests;
