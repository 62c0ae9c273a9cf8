//! A picture of a toolpath: SVG, top view (XY) beside a front view (XZ).
//! Cutting moves are solid and shaded by depth, rapids dashed red.

use std::fmt::Write;

use kezuri_geom::{Axes, MoveKind, Toolpath};

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
        for m in &path.moves {
            if matches!(m.kind, MoveKind::Dwell(_)) {
                continue;
            }
            let pts = points(m);
            let mut d = String::with_capacity(pts.len() * 16);
            for (i, p) in pts.iter().enumerate() {
                let p = p.xyz();
                let x = left + scale * (p[u] - lo[u]);
                let y = base - scale * (p[v] - lo[v]);
                let _ = write!(d, "{}{x:.2},{y:.2} ", if i == 0 { "M" } else { "L" });
            }
            let style = if m.is_rapid() {
                r##"stroke="#d33" stroke-dasharray="4 3" stroke-width="0.6""##.to_string()
            } else {
                // Deeper cuts darker.
                let t = ((hi[2] - m.end.z) / depth).clamp(0.0, 1.0);
                let shade = (180.0 * (1.0 - t)) as u8;
                format!(r#"stroke="rgb({shade},{shade},255)" stroke-width="0.8""#)
            };
            let _ = writeln!(out, r#"<path d="{d}" fill="none" {style}/>"#);
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
