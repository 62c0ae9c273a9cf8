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
//!
//! A jump (`Run::jumps`: LinuxCNC's G70, whose reading of its profile
//! leaves the tool position the compensation works from at the profile's
//! end) changes the next corner only. `beta` is then taken from the line
//! from the programmed point to the jumped point, as if that line were the
//! radius to the tool (LinuxCNC's `theta`); moves without plane travel go
//! to the jumped point; a convex corner (the moves before moved to the
//! jumped point) or a straight one then proceeds as above, a concave one
//! after a straight move backs from the jumped point, square to that line,
//! by r / tan(half the inside corner), and moves the moves before there.

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
    // Where a G70's profile took the tool centre the compensation works
    // from (`run.jumps`), until the next move with plane travel.
    let mut jump = None;
    for item in items {
        let (Item::Pass(index) | Item::Plane(Element { index, .. })) = item;
        jump = run.jump_before(index).or(jump);
        let b = match item {
            // A move without plane travel goes to that point (a dwell stays).
            Item::Pass(index) => {
                let dwell = matches!(run.moves[index].kind, kezuri_geom::MoveKind::Dwell(_));
                passes.push(match jump {
                    Some(end) if !dwell => Step::Line { index, end, forward: None },
                    _ => Step::Pass { index },
                });
                continue;
            }
            Item::Plane(b) => b,
        };
        let Some((a, a_step)) = prev.take() else {
            prev = Some(entry(run, &b, jump.take().unwrap_or(run.start))?);
            continue;
        };
        let path_b = run.path(&b)?;
        let t2 = b.start_tangent();
        // The tool's direction before the corner: along the move before,
        // or square to the line from its programmed end to the point a
        // jump took the tool centre to.
        let jumped = jump.take().map(|c| (c, radial(c.sub(a.elem.to))));
        let t1 = jumped.map_or(a.tangent, |(_, v)| v.left().scale(-s));
        let phi = -s * turn_angle(t1, t2);
        let beta = if phi < -FRAC_PI_2 { phi + TAU } else { phi };
        let concave = !(-SMALL..=PI + SMALL).contains(&beta)
            // The "h" and "m" shapes: a reversal over an arc the tool is
            // outside of is taken as concave.
            || (b.arc.is_none() && beta > PI - SMALL && a.elem.arc.is_some() && !a.elem.tool_inside(s))
            || (b.arc.is_some() && (beta - PI).abs() < SMALL && !b.tool_inside(s));
        if jumped.is_some() && (b.arc.is_some() || (!concave && beta > SMALL && !b.rapid)) {
            return Err(Alarm::AfterJump.at(b.index, run.rules));
        }
        let mut link = None;
        let a_end = match jumped {
            // From the jumped point LinuxCNC backs along the line square to
            // that radial by r / tan(half the inside corner).
            Some((c, v)) if concave && a.elem.arc.is_none() => {
                let half = (beta + PI) / 2.0;
                if half == 0.0 {
                    return Err(Alarm::NoIntersection { from_arc: false, to_arc: false }.at(b.index, run.rules));
                }
                c.add(normal(v, s).scale(r / half.tan()))
            }
            _ if concave => {
                let no = || Alarm::NoIntersection { from_arc: a.elem.arc.is_some(), to_arc: b.arc.is_some() };
                intersect(a.path, path_b, a.elem.to).ok_or_else(|| no().at(b.index, run.rules))?
            }
            _ => {
                if beta > SMALL {
                    let to = b.offset_start(s, r);
                    let around = (!b.rapid).then_some((a.elem.to, s < 0.0));
                    link = Some(Step::Link { owner: b.index, to, around });
                }
                // A convex corner after a jump flushes the moves before
                // to the jumped point; a straight one leaves them.
                match jumped {
                    Some((c, _)) if beta > SMALL => c,
                    _ => a.end,
                }
            }
        };
        steps.push(with_end(a_step, a_end));
        // The moves without plane travel end where the move before now does.
        let moved = jumped.is_some() && (concave || beta > SMALL);
        steps.extend(passes.drain(..).map(|p| if moved { with_end(p, a_end) } else { p }));
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

/// The unit vector along `v`; along +u where `v` is none (C's `atan2(0, 0)`).
fn radial(v: V2) -> V2 {
    if v.len() > 0.0 {
        v.unit()
    } else {
        V2::new(1.0, 0.0)
    }
}

/// The entry move `e` from the tool's uncompensated point `from`.
fn entry(run: &Run, e: &Element, from: V2) -> Result<(Before, Step), Error> {
    let (s, r) = (run.s, run.r);
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
