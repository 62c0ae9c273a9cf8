//! LinuxCNC's splines in the XY plane: `G5.1` (quadratic) and `G5` (cubic),
//! as rs274 2.9 reads them: the motion of their own block only (the next
//! block without a motion code moves in the mode before the spline). A spline
//! becomes straight feed moves through points of the curve, no farther from
//! it than [`SPLINE_TOLERANCE`]; LinuxCNC's own canon makes biarcs through
//! the curve at 12 (G5.1) or 16 (G5) equal steps of its parameter, which
//! these moves pass within the same tolerance (`docs/linuxcnc.md`).

use kezuri_geom::{Axes, MoveKind};

use super::modal::FeedMode;
use super::words::Words;
use super::State;
use crate::source::{Diagnostic, Span};

/// Farthest a straight move may be from the curve it stands for, mm.
pub(super) const SPLINE_TOLERANCE: f64 = 0.001;

/// Most straight moves one spline block makes.
const MAX_SEGMENTS: f64 = 100_000.0;

/// The point at `t` (0 to 1) of the Bézier curve with control points `p`
/// (3 for a quadratic, 4 for a cubic), in the plane.
pub(super) fn bezier(p: &[[f64; 2]], t: f64) -> [f64; 2] {
    let s = 1.0 - t;
    let w: [f64; 4] = match p.len() {
        3 => [s * s, 2.0 * s * t, t * t, 0.0],
        _ => [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t],
    };
    let mut q = [0.0; 2];
    for (c, wk) in p.iter().zip(w) {
        q[0] += wk * c[0];
        q[1] += wk * c[1];
    }
    q
}

/// How many equal steps of the parameter keep every chord within `tol` of
/// the curve: a chord over a step h is off the curve by at most
/// h²·max|B''|/8, and |B''| is largest at an end (constant for a quadratic).
pub(super) fn segments(p: &[[f64; 2]], tol: f64) -> f64 {
    let second = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| (a[0] - 2.0 * b[0] + c[0]).hypot(a[1] - 2.0 * b[1] + c[1]);
    let bound = match p.len() {
        3 => 2.0 * second(p[0], p[1], p[2]),
        _ => 6.0 * second(p[0], p[1], p[2]).max(second(p[1], p[2], p[3])),
    };
    (bound / (8.0 * tol)).sqrt().ceil().max(1.0)
}

impl State {
    /// A block in LinuxCNC's spline mode (`code` 50: G5, 51: G5.1): the
    /// curve from where the tool is to the block's X Y, as feed moves.
    pub(super) fn spline_block(&mut self, code: u32, w: &Words, span: Span, line: u32) -> Result<bool, Diagnostic> {
        let name = if code == 51 { "G5.1" } else { "G5" };
        if self.modal.plane != kezuri_geom::Plane::Xy {
            return Err(Diagnostic::error(span, format!("{name} (a spline) needs the XY plane (G17)")));
        }
        for letter in *b"ZABC" {
            if w.has(letter) {
                return Err(Diagnostic::error(
                    w.span(letter),
                    "Splines may not have motion in Z, A, B, or C (LinuxCNC stops here)",
                ));
            }
        }
        if self.comp_on() {
            return Err(Diagnostic::error(
                span,
                format!("{name} with cutter compensation on (G41/G42): give G40 first"),
            ));
        }
        if self.modal.feed_mode == FeedMode::InverseTime {
            return Err(Diagnostic::error(span, format!("{name} in inverse time feed (G93): give G94 first")));
        }
        let both = |a: u8, b: u8| -> Result<Option<[f64; 2]>, Diagnostic> {
            match (w.get(a), w.get(b)) {
                (Some(x), Some(y)) => Ok(Some([self.mm(x), self.mm(y)])),
                (None, None) => Ok(None),
                _ => Err(Diagnostic::error(
                    span,
                    format!("Must specify both {} and {} with {name} (LinuxCNC stops here)", a as char, b as char),
                )),
            }
        };
        let (ij, pq) = (both(b'I', b'J')?, both(b'P', b'Q')?);
        if !w.any_axis() && ij.is_none() && pq.is_none() {
            return Ok(false);
        }
        let start = self.tip;
        let end = self.target(w);
        let s = [start.x, start.y];
        let e = [end.x, end.y];
        let add = |a: [f64; 2], d: [f64; 2]| [a[0] + d[0], a[1] + d[1]];
        let points: Vec<[f64; 2]> = if code == 51 {
            let Some(ij) = ij else {
                return Err(Diagnostic::error(span, "Must specify both I and J with G5.1 (LinuxCNC stops here)"));
            };
            vec![s, add(s, ij), e]
        } else {
            let Some(pq) = pq else {
                return Err(Diagnostic::error(span, "Must specify both P and Q with G5 (LinuxCNC stops here)"));
            };
            // Without I J the curve leaves along the last G5's end tangent.
            let ij = ij.unwrap_or([-self.spline_pq[0], -self.spline_pq[1]]);
            self.spline_pq = pq;
            vec![s, add(s, ij), add(e, pq), e]
        };
        let n = segments(&points, SPLINE_TOLERANCE);
        if n > MAX_SEGMENTS {
            return Err(Diagnostic::error(
                span,
                format!("{name} makes more than {MAX_SEGMENTS} straight moves within {SPLINE_TOLERANCE} mm: are I J (P Q) in the right units?"),
            ));
        }
        let feed = self.feed_mm_min(span)?;
        let steps = n as u32;
        for k in 1..=steps {
            let q = if k == steps { e } else { bezier(&points, f64::from(k) / n) };
            let at = Axes { x: q[0], y: q[1], ..end };
            self.push_move(MoveKind::Feed, at, feed, w.axes().with(0).with(1), line);
        }
        Ok(true)
    }
}
