//! Chamfering and corner rounding between a move and the next:
//! FANUC Series 0i-TF Plus Operator's Manual (B-64604EN), lathe system,
//! "Chamfering and corner R".
//!
//! - System A (and Haas), a move along one axis: `G01 X(U)_ C±k` (or
//!   `K±k`) chamfers toward ±Z by k, `G01 Z(W)_ C±i` (or `I±i`) toward ±X
//!   by i (a radius); `R±r`
//!   rounds the corner with radius r the same way. The next block must be
//!   a G01 along the other axis, in that direction, by at least the size.
//!   (A Fanuc reads C there as the chamfer, not the C axis, as with
//!   parameter 3405 bit 4 CCR set; a Haas lathe's C is always its axis, and
//!   its chamfer is I or K.)
//! - Any system, any two straight moves: `,C` is the chamfer's distance
//!   from the corner along both moves, `,R` the radius of an arc tangent to
//!   both; where one of them is an arc, [`super::corner_arc`] makes it.
//!
//! The block's move is made to the corner; the next block that moves cuts
//! it back to where the chamfer or arc begins, adds the chamfer or arc
//! (at the first block's feed, in its line) and starts from its end.

use kezuri_geom::{Arc, MoveKind};

use super::super::modal::{GCode, Motion};
use super::super::words::Words;
use super::super::State;
use crate::source::{Diagnostic, Span};

/// A chamfer or corner rounding a block asked for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(in super::super) struct Corner {
    /// The size: the chamfer's leg or the corner's radius, mm.
    pub size: f64,
    /// `true` for a corner radius, `false` for a chamfer.
    pub round: bool,
    /// System A's one-axis form: the axis the next move must go along (0
    /// X, 2 Z) and its direction (the word's sign). `None`: `,C` `,R`.
    pub toward: Toward,
    /// Where the word is written.
    pub span: Span,
    /// The block's move in the toolpath, once made.
    pub at: Option<usize>,
}

/// System A's one-axis form: the axis the next move goes along and its
/// direction.
type Toward = Option<(usize, f64)>;

/// Unit vector and length from `a` to `b` (X Y Z).
fn direction(a: [f64; 3], b: [f64; 3]) -> ([f64; 3], f64) {
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    if l == 0.0 {
        return ([0.0; 3], 0.0);
    }
    ([d[0] / l, d[1] / l, d[2] / l], l)
}

impl State {
    /// Reads a block's chamfer or corner words (before its motion), taking
    /// them out of the words: `C`/`R` after a one-axis G01 in system A,
    /// `,C`/`,R` anywhere.
    pub(in super::super) fn corner_words(
        &mut self,
        w: &mut Words,
        codes: &[Option<(GCode, Span)>],
        next: Option<&[crate::ast::Word]>,
    ) -> Result<(), Diagnostic> {
        let Some(turning) = &self.turning else { return Ok(()) };
        let motion = codes.iter().flatten().find_map(|(c, _)| match c {
            GCode::Motion(m) => Some(Some(*m)),
            GCode::SingleCycle(_) | GCode::Threading => Some(None),
            _ => None,
        });
        let motion = motion.unwrap_or(if turning.motion.is_some() { None } else { Some(self.modal.motion) });
        let linear = motion == Some(Motion::Linear);
        let one_shot = codes.iter().flatten().any(|(c, _)| c.group() == 0);
        let system_a = turning.fanuc && turning.system == super::GCodeSystem::A;
        let (x, z) = (w.has(b'X'), w.has(b'Z'));
        let one_axis = x != z && !w.has(b'Y');
        // Direct drawing dimensions: the line's angle gives its other end
        // coordinate; a corner waiting on the block before is the corner
        // between that block and this line, whatever their directions.
        let angle = linear && !one_shot && self.drawing_angle(w, next)?;
        let Some(turning) = &mut self.turning else { return Ok(()) };
        if angle {
            if let Some(c) = &mut turning.corner {
                c.toward = None;
            }
        }
        let drawing = system_a && turning.drawing;
        let mut found: Option<(u8, bool, Toward)> = None;
        for (letter, round) in [(b'c', false), (b'r', true)] {
            if w.has(letter) {
                if found.is_some() {
                    return Err(Diagnostic::error(
                        w.span(letter),
                        ",C and ,R in one block: a corner is chamfered or rounded, not both",
                    ));
                }
                found = Some((letter, round, None));
            }
        }
        if drawing && linear && !one_shot && found.is_none() {
            // C and R without the comma, as the direct drawing corners.
            for (letter, round) in [(b'R', true), (b'C', false)] {
                if w.has(letter) {
                    if found.is_some() {
                        return Err(Diagnostic::error(
                            w.span(letter),
                            "C and R in one block: a corner is chamfered or rounded, not both",
                        ));
                    }
                    found = Some((letter, round, None));
                }
            }
        }
        if system_a && linear && !one_shot && one_axis && found.is_none() {
            // I (after a move along Z) and K (along X) are the chamfer's
            // other addresses (parameter 3405 bit 4, CCR, chooses C or I K).
            // A Haas lathe's C is always its C axis: I K R only there.
            let other = if x { b'K' } else { b'I' };
            let c = if self.settings.dialect.is_haas() { None } else { Some((b'C', false)) };
            for (letter, round) in [(b'R', true), (other, false)].into_iter().chain(c) {
                if let Some(v) = w.get(letter) {
                    if found.is_some() {
                        return Err(Diagnostic::error(
                            w.span(letter),
                            "two chamfer or corner R words in one block (C, R, I or K): a corner is chamfered or \
                             rounded once (the control stops with an alarm)",
                        ));
                    }
                    // Along X the next move goes along Z, and the other way.
                    let other = if x { 2 } else { 0 };
                    found = Some((letter, round, Some((other, v.signum()))));
                }
            }
        }
        let Some((letter, round, toward)) = found else { return Ok(()) };
        let (size, span) = (w.get(letter).unwrap_or(0.0), w.span(letter));
        *w = w.without(letter);
        let name = match letter {
            b'c' => ",C",
            b'r' => ",R",
            b'C' => "C",
            b'I' => "I",
            b'K' => "K",
            _ => "R",
        };
        let arc = matches!(motion, Some(Motion::Cw | Motion::Ccw)) && toward.is_none() && matches!(letter, b'c' | b'r');
        if !(linear || arc) || one_shot {
            return Err(Diagnostic::error(
                span,
                format!("{name} (a chamfer or corner R) is read only in a G01, G02 or G03 block"),
            ));
        }
        let size = self.mm(size.abs());
        if size.is_nan() || size == 0.0 {
            return Err(Diagnostic::error(span, format!("{name}0: a chamfer or corner R needs a size greater than 0")));
        }
        if let Some(t) = &mut self.turning {
            t.asked = Some(Corner { size, round, toward, span, at: None });
        }
        Ok(())
    }

    /// After a block's motion: the corner a block before asked for is made
    /// with this block's first move, and this block's own is noted. Returns
    /// the first move whose end or start changed.
    pub(in super::super) fn corner_moves(&mut self, first: usize, span: Span) -> Result<usize, Diagnostic> {
        let Some(turning) = &mut self.turning else { return Ok(first) };
        let asked = turning.asked.take();
        let pending = turning.corner;
        let made = self.toolpath.moves.len() > first;
        let mut changed = first;
        // This block's own move: after a corner made, the one after it.
        let mut own = first;
        if let Some(corner) = pending.filter(|_| made) {
            if let Some(t) = &mut self.turning {
                t.corner = None;
            }
            self.make_corner(corner, first, span)?;
            changed = corner.at.unwrap_or(first).min(first);
            own = first + 1;
        }
        if let Some(mut corner) = asked {
            let n = self.toolpath.moves.len();
            if n != own + 1 || !matches!(self.toolpath.moves[own].kind, MoveKind::Feed | MoveKind::Arc(_)) {
                return Err(Diagnostic::error(
                    corner.span,
                    "a chamfer or corner R needs its block to make one G01, G02 or G03 move",
                ));
            }
            corner.at = Some(own);
            if let Some(t) = &mut self.turning {
                t.corner = Some(corner);
            }
        }
        Ok(changed)
    }

    /// At the end of the program: a chamfer or corner R still waiting for
    /// its next move is an error (the control stops: no move after it).
    pub(in super::super) fn corner_left(&self) -> Result<(), Diagnostic> {
        match self.turning.as_ref().and_then(|t| t.corner) {
            Some(corner) => Err(Diagnostic::error(
                corner.span,
                format!(
                    "the program ends before the move after this {}: a chamfer or corner R needs the next block's \
                     G01 move (the control stops with an alarm)",
                    if corner.round { "corner R" } else { "chamfer" }
                ),
            )),
            None => Ok(()),
        }
    }

    /// Cuts move `corner.at` back, adds the chamfer or arc, and starts move
    /// `next` (the next block's first) at its end.
    fn make_corner(&mut self, corner: Corner, next: usize, span: Span) -> Result<(), Diagnostic> {
        let Some(k) = corner.at else { return Ok(()) };
        let refuse = |why: String| Err(Diagnostic::error(span, why));
        let what = if corner.round { "corner R" } else { "chamfer" };
        let (before, after) = (self.toolpath.moves[k], self.toolpath.moves[next]);
        let single = self.toolpath.moves.len() == next + 1;
        let cuts = |m: &kezuri_geom::Move| matches!(m.kind, MoveKind::Feed | MoveKind::Arc(_));
        if next != k + 1 || !single || !cuts(&after) || after.start != before.end {
            return refuse(format!(
                "the block after a {what} must be a G01, G02 or G03 move from the corner (the control stops with an \
                 alarm: no move after the chamfer or corner R)"
            ));
        }
        if matches!(after.kind, MoveKind::Arc(_)) && corner.toward.is_some() {
            return refuse(format!("after a {what} of G01's one-axis form the next block must be a G01 move"));
        }
        if matches!(before.kind, MoveKind::Arc(_)) || matches!(after.kind, MoveKind::Arc(_)) {
            let plane = self.modal.plane;
            let made = super::corner_arc::corner(&before, &after, plane, corner.size, corner.round)
                .map_err(|why| Diagnostic::error(corner.span, why))?;
            let (i, j, _) = plane.axes();
            let point = |v: [f64; 2]| {
                let mut p = before.end.to_array();
                (p[i], p[j]) = (v[0], v[1]);
                kezuri_geom::Axes::from_array(p)
            };
            let kind = match made.round {
                Some((c, ccw)) => {
                    let mut center = before.end.xyz();
                    (center[i], center[j]) = (c[0], c[1]);
                    MoveKind::Arc(Arc { center, plane, ccw, turns: 0 })
                }
                None => MoveKind::Feed,
            };
            self.put_corner(k, next, point(made.a), point(made.b), kind);
            return Ok(());
        }
        let (p0, p1, p2) = (before.start.xyz(), before.end.xyz(), after.end.xyz());
        let (u1, l1) = direction(p0, p1);
        let (u2, l2) = direction(p1, p2);
        if let Some((axis, sign)) = corner.toward {
            let along = u2[axis] * sign > 1.0 - 1e-9;
            if !along {
                let axis = if axis == 0 { "X" } else { "Z" };
                let to = if sign > 0.0 { "+" } else { "-" };
                return refuse(format!(
                    "after a {what} toward {to}{axis} the next block must move along {axis} only, toward {to}{axis} \
                     (the control stops with an alarm)"
                ));
            }
        }
        let cos = (u1[0] * u2[0] + u1[1] * u2[1] + u1[2] * u2[2]).clamp(-1.0, 1.0);
        let turn = cos.acos();
        if !(1e-9..=std::f64::consts::PI - 1e-9).contains(&turn) {
            return refuse(format!("a {what} between two moves along one line: there is no corner"));
        }
        // How far from the corner the chamfer or arc begins and ends.
        let leg = if corner.round { corner.size * (turn / 2.0).tan() } else { corner.size };
        if leg > l1 + 1e-9 || leg > l2 + 1e-9 {
            return Err(Diagnostic::error(
                corner.span,
                format!(
                    "the {what} ({:.4} mm from the corner) is longer than a move beside it ({:.4} mm and {:.4} mm): \
                     the control stops with an alarm",
                    leg, l1, l2
                ),
            ));
        }
        let a: [f64; 3] = std::array::from_fn(|i| p1[i] - leg * u1[i]);
        let b: [f64; 3] = std::array::from_fn(|i| p1[i] + leg * u2[i]);
        let point = |p: [f64; 3]| kezuri_geom::Axes { x: p[0], y: p[1], z: p[2], ..before.end };
        let kind = if corner.round {
            // The centre is the radius away from A, square to the first move,
            // on the side the path turns to.
            let side: [f64; 3] = std::array::from_fn(|i| u2[i] - cos * u1[i]);
            let norm = (side[0] * side[0] + side[1] * side[1] + side[2] * side[2]).sqrt();
            let center: [f64; 3] = std::array::from_fn(|i| a[i] + corner.size * side[i] / norm);
            let plane = self.modal.plane;
            let (i, j, _) = plane.axes();
            let ccw = u1[i] * u2[j] - u1[j] * u2[i] > 0.0;
            MoveKind::Arc(Arc { center, plane, ccw, turns: 0 })
        } else {
            MoveKind::Feed
        };
        self.put_corner(k, next, point(a), point(b), kind);
        Ok(())
    }

    /// Move `k` now ends at `a`; move `next` becomes the corner (`kind`,
    /// from `a` to `b`, at move `k`'s feed, in its line); the rest of the
    /// next block's move follows from `b`.
    fn put_corner(&mut self, k: usize, next: usize, a: kezuri_geom::Axes, b: kezuri_geom::Axes, kind: MoveKind) {
        let (before, after) = (self.toolpath.moves[k], self.toolpath.moves[next]);
        self.toolpath.moves[k].end = a;
        let mut cut = after;
        cut.kind = kind;
        cut.start = a;
        cut.end = b;
        cut.line = before.line;
        cut.feed = before.feed;
        cut.speed = before.speed;
        self.toolpath.moves[next] = cut;
        let rest = kezuri_geom::Move { start: b, ..after };
        self.comp_repeat_tag();
        self.toolpath.push(rest);
    }
}
