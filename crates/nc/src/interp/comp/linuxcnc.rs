//! LinuxCNC's cutter compensation, as its interpreter does it
//! (`interp_convert.cc`: `convert_straight_comp1/2`, `convert_arc_comp1/2`;
//! `interp_queue.cc`: `move_endpoint_and_flush`), re-derived, not copied.
//!
//! The entry move goes straight (or along a re-centred arc) to the point
//! offset perpendicular to it at its end. At each later corner the angle
//! `beta` by which the path turns away from the tool decides: concave
//! corners move the previous move's end to the intersection of the offset
//! paths; convex corners (beta > 0.05 rad) get an arc of the tool radius
//! around the programmed corner, made as part of the next move (a straight
//! traverse for G00); nearly straight ones nothing. Moves without plane
//! travel are made at the end of the move before them, before any corner
//! arc, with no limit on how many. G40 leaves no vector: the cancel move
//! starts from the last offset point.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use super::plane::{intersect, normal, turn_angle, Element, Path, V2};
use super::{Alarm, Item, Run, Step};
use crate::Error;

/// `TOLERANCE_CONCAVE_CORNER` in LinuxCNC's `interp_internal.hh`, radians.
const SMALL: f64 = 0.05;

/// What a corner needs of the move before it.
struct Before {
    elem: Element,
    /// Its offset path (for the entry arc: the re-centred circle).
    path: Path,
    /// Unit tangent at its end.
    tangent: V2,
    /// The offset point at its end.
    end: V2,
}

pub(super) fn plan(run: &Run) -> Result<Vec<Step>, Error> {
    let (s, r) = (run.s, run.r);
    let mut steps = Vec::with_capacity(run.items.len() * 2 + 1);
    let mut items = run.items.iter().copied().peekable();
    // Dwells before the entry move happen where the tool is.
    while let Some(Item::Pass(index)) = items.peek().copied() {
        if !matches!(run.moves[index].kind, kezuri_geom::MoveKind::Dwell(_)) {
            return Err(Alarm::EntryTooShort { arc: false }.at(index, run.rules));
        }
        steps.push(Step::Pass { index });
        items.next();
    }
    let mut prev: Option<(Before, Step)> = None;
    let mut passes = Vec::new();
    for item in items {
        let b = match item {
            Item::Pass(index) => {
                passes.push(Step::Pass { index });
                continue;
            }
            Item::Plane(b) => b,
        };
        let Some((a, a_step)) = prev.take() else {
            prev = Some(entry(run, &b)?);
            continue;
        };
        let path_b = run.path(&b)?;
        let t2 = b.start_tangent();
        let phi = -s * turn_angle(a.tangent, t2);
        let beta = if phi < -FRAC_PI_2 { phi + TAU } else { phi };
        let concave = !(-SMALL..=PI + SMALL).contains(&beta)
            // The "h" and "m" shapes: a reversal over an arc the tool is
            // outside of is taken as concave.
            || (b.arc.is_none() && beta > PI - SMALL && a.elem.arc.is_some() && !a.elem.tool_inside(s))
            || (b.arc.is_some() && (beta - PI).abs() < SMALL && !b.tool_inside(s));
        let mut link = None;
        let a_end = if concave {
            let no = || Alarm::NoIntersection { from_arc: a.elem.arc.is_some(), to_arc: b.arc.is_some() };
            intersect(a.path, path_b, a.elem.to).ok_or_else(|| no().at(b.index, run.rules))?
        } else {
            if beta > SMALL {
                let to = b.offset_start(s, r);
                let around = (!b.rapid).then_some((a.elem.to, s < 0.0));
                link = Some(Step::Link { owner: b.index, to, around });
            }
            a.end
        };
        steps.push(with_end(a_step, a_end));
        steps.append(&mut passes);
        steps.extend(link);
        let end = b.offset_end(s, r);
        let step = run.cut(&b, end, Some(b.to.sub(b.from)));
        prev = Some((Before { elem: b, path: path_b, tangent: b.end_tangent(), end }, step));
    }
    if let Some((a, a_step)) = prev {
        steps.push(with_end(a_step, a.end));
    }
    steps.append(&mut passes);
    if let Some(x) = run.exit {
        if matches!(run.moves[x].kind, kezuri_geom::MoveKind::Arc(_)) {
            return Err(Alarm::ArcExit.at(x, run.rules));
        }
        steps.push(Step::Exit { index: x });
    }
    Ok(steps)
}

/// The step `step` with its end moved to `end`.
fn with_end(step: Step, end: V2) -> Step {
    match step {
        Step::Line { index, forward, .. } => Step::Line { index, end, forward },
        Step::Arc { index, centre, check, .. } => Step::Arc { index, end, centre, check },
        other => other,
    }
}

/// The entry move `e` from the tool's uncompensated point.
fn entry(run: &Run, e: &Element) -> Result<(Before, Step), Error> {
    let (s, r) = (run.s, run.r);
    let from = run.start;
    if from.dist(e.to) <= r {
        return Err(Alarm::EntryTooShort { arc: e.arc.is_some() }.at(e.index, run.rules));
    }
    let Some(c) = e.arc else {
        // Straight to the point offset perpendicular to the entry line at
        // its end. LinuxCNC queues the move with that perpendicular as
        // its direction, which a concave corner's trim must not reverse.
        let t = e.to.sub(from).unit();
        let n = normal(t, s);
        let end = e.to.add(n.scale(r));
        let before = Before { elem: *e, path: Path::Line { point: end, dir: t }, tangent: t, end };
        return Ok((before, Step::Line { index: e.index, end, forward: Some(n) }));
    };
    // An arc through the start and the offset end point whose centre lies
    // on the line from that end point to the programmed centre.
    let tangent = e.end_tangent();
    let end = e.to.add(normal(tangent, s).scale(r));
    let toward = c.centre.sub(end);
    let impossible = || Alarm::EntryArcImpossible.at(e.index, run.rules);
    if toward.len() < 1e-12 {
        return Err(impossible());
    }
    let toward = toward.unit();
    let chord = from.sub(end);
    let cos = chord.unit().dot(toward);
    if cos.abs() < 1e-6 {
        return Err(impossible());
    }
    let centre = end.add(toward.scale(chord.len() / 2.0 / cos));
    let path = Path::Circle { centre, radius: centre.dist(end) };
    let before = Before { elem: *e, path, tangent, end };
    Ok((before, Step::Arc { index: e.index, end, centre, check: false }))
}
