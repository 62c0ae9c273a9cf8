//! Haas's circular pocket milling, `G12` (clockwise) and `G13`
//! (counter-clockwise), in the XY plane about the tool's position: circles
//! of radius I, I + Q, … up to K, less the radius of register D, each
//! reached by a half circle from the last, then a half circle back to the
//! centre, all at F; `L` repeats it, each time by Z deeper under G91. The
//! circles are Haas's manual's; how the control steps between them is drawn
//! only in its figure: the half circles are kezuri's reading of it
//! (`docs/gcode-support.md`, "G12, G13").

use kezuri_geom::{Arc, AxisSet, MoveKind, Plane};

use super::modal::{Distance, FeedMode};
use super::words::Words;
use super::{Control, State};
use crate::source::{Diagnostic, Span};

/// Most circles one G12/G13 block cuts (all its repeats together).
const MAX_CIRCLES: f64 = 100_000.0;

impl State {
    /// `G12`/`G13` (`cw`: G12) on a Haas control. Returns whether the tool
    /// moved.
    pub(super) fn circular_pocket(&mut self, cw: bool, w: &Words, gspan: Span, line: u32) -> Result<bool, Diagnostic> {
        let name = if cw { "G12" } else { "G13" };
        if self.settings.coords.control != Control::Haas {
            return Err(Diagnostic::error(
                gspan,
                format!("{name} is Haas's circular pocket milling: read the program with --dialect haas"),
            ));
        }
        if self.modal.plane != Plane::Xy {
            return Err(Diagnostic::error(gspan, format!("{name} mills in the XY plane: give G17 first")));
        }
        if self.comp_on() {
            return Err(Diagnostic::error(gspan, format!("{name} makes its own cutter compensation: give G40 first")));
        }
        if self.modal.feed_mode == FeedMode::InverseTime {
            return Err(Diagnostic::error(gspan, format!("{name} in inverse time feed (G93): give G94 first")));
        }
        let at = |l: u8| if w.has(l) { w.span(l) } else { gspan };
        let Some(first) = w.get(b'I').map(|i| self.mm(i)) else {
            return Err(Diagnostic::error(gspan, format!("{name} needs I, the radius of its (first) circle")));
        };
        let last = w.get(b'K').map(|k| self.mm(k));
        let step = w.get(b'Q').map(|q| self.mm(q));
        let d = w.get(b'D').map_or(Ok(0), |d| {
            if d.fract() != 0.0 || !(0.0..=999.0).contains(&d) {
                Err(Diagnostic::error(at(b'D'), format!("D{d} is not a tool offset number")))
            } else {
                Ok(d as u32)
            }
        })?;
        let tool = self.register_radius(d, at(b'D'), false)?;
        if first <= tool {
            return Err(Diagnostic::error(
                at(b'I'),
                format!("{name}: I ({first:.4} mm) must be greater than the tool radius of D{d} ({tool:.4} mm)"),
            ));
        }
        let mut radii = vec![first];
        match (last, step) {
            (None, None) => {}
            (Some(k), Some(q)) if k > first && q > 0.0 => {
                if (k - first) / q > MAX_CIRCLES {
                    return Err(Diagnostic::error(
                        at(b'Q'),
                        format!("{name} with Q{q} makes more than {MAX_CIRCLES} circles"),
                    ));
                }
                let mut r = first + q;
                while r < k - 1e-9 {
                    radii.push(r);
                    r += q;
                }
                radii.push(k);
            }
            (Some(k), Some(_)) => {
                return Err(Diagnostic::error(
                    at(if k <= first { b'K' } else { b'Q' }),
                    format!("{name}: K (the finished radius) must be greater than I, and Q (the step) greater than 0"),
                ))
            }
            _ => {
                return Err(Diagnostic::error(
                    gspan,
                    format!("{name}: K and Q go together (the finished radius and the step)"),
                ))
            }
        }
        let loops = match w.get(b'L') {
            None => 1,
            Some(l) if l.fract() == 0.0 && (1.0..=9999.0).contains(&l) => l as u32,
            Some(l) => return Err(Diagnostic::error(at(b'L'), format!("{name}: L{l} is not a repeat count from 1"))),
        };
        // The centre: X Y of the block, at rapid, at the current level.
        let place = w.without(b'Z');
        if place.any_axis() {
            let mut centre = self.target(&place);
            centre.z = self.tip.z;
            if centre != self.tip {
                self.push_move(MoveKind::Rapid, centre, 0.0, place.axes(), line);
            }
        }
        let feed = self.feed_mm_min(gspan)?;
        let c = self.tip;
        let xy = AxisSet::NONE.with(0).with(1);
        for _ in 0..loops {
            if let Some(z) = w.get(b'Z') {
                let depth = match self.modal.distance {
                    Distance::Incremental => self.tip.z + self.mm(z),
                    Distance::Absolute => self.target(&w.only(b'Z')).z,
                };
                let mut down = self.tip;
                down.z = depth;
                self.push_move(MoveKind::Feed, down, feed, AxisSet::NONE.with(2), line);
            }
            let level = self.tip.z;
            let mut from = 0.0;
            for &r in &radii {
                let to = r - tool;
                let half = Arc { center: [c.x + (from + to) / 2.0, c.y, level], plane: Plane::Xy, ccw: !cw, turns: 0 };
                let out = kezuri_geom::Axes { x: c.x + to, y: c.y, z: level, ..c };
                self.push_move(MoveKind::Arc(half), out, feed, xy, line);
                let circle = Arc { center: [c.x, c.y, level], plane: Plane::Xy, ccw: !cw, turns: 0 };
                self.push_move(MoveKind::Arc(circle), out, feed, xy, line);
                from = to;
            }
            let back = Arc { center: [c.x + from / 2.0, c.y, level], plane: Plane::Xy, ccw: !cw, turns: 0 };
            let centre = kezuri_geom::Axes { z: level, ..c };
            self.push_move(MoveKind::Arc(back), centre, feed, xy, line);
        }
        Ok(true)
    }
}
