//! Fanuc cutter compensation C.
//!
//! Corner vectors belong to the move before the corner: the moves without
//! plane travel between two plane moves are made after them, at the start
//! of the next move's offset path. Fanuc reads ahead past at most
//! [`LOOKAHEAD`] such moves; with more, the vector at the end of the move
//! before them stays perpendicular to it. A run that a multiple
//! repetitive cycle's return to its start point ends keeps the
//! perpendicular vector at its last move's end too: the cycle's offset
//! ends with its shape.

use super::plane::{classify, intersect, Element, Path, Turn, V2};
use super::{Alarm, Approach, Item, Run, Step};
use crate::Error;

/// How many moves without plane travel Fanuc reads past to find the next
/// plane move (one start-up or corner calculation).
pub(super) const LOOKAHEAD: usize = 2;

/// The end of a move's own offset path and the corner moves after it.
struct Corner {
    end: V2,
    links: Vec<V2>,
}

pub(super) fn plan(run: &Run, approach: Approach) -> Result<Vec<Step>, Error> {
    let planes: Vec<usize> =
        run.items.iter().enumerate().filter(|(_, it)| matches!(it, Item::Plane(_))).map(|(k, _)| k).collect();
    let elem = |k: usize| match run.items[planes[k]] {
        Item::Plane(e) => e,
        Item::Pass(_) => unreachable!("planes index plane items"),
    };
    let pass = |pos: usize| match run.items[pos] {
        Item::Pass(index) => Step::Pass { index },
        Item::Plane(_) => unreachable!("between plane items are passes"),
    };
    let mut steps = Vec::with_capacity(run.items.len() + 2 * planes.len() + 1);
    let first = planes.first().copied().unwrap_or(run.items.len());
    steps.extend((0..first).map(pass));
    if !planes.is_empty() {
        let e0 = elem(0);
        if e0.arc.is_some() {
            return Err(Alarm::ArcStartUp.at(e0.index, run.rules));
        }
        let exit = run.exit_element();
        if let (Some(x), None) = (run.exit, exit) {
            if matches!(run.moves[x].kind, kezuri_geom::MoveKind::Arc(_)) {
                return Err(Alarm::ArcExit.at(x, run.rules));
            }
        }
        let mut before: Option<Step> = None;
        for k in 0..planes.len() {
            let a = elem(k);
            run.path(&a)?;
            steps.extend(before.take());
            let next_pos = planes.get(k + 1).copied().unwrap_or(run.items.len());
            let gap = next_pos - planes[k] - 1;
            let seen = gap <= LOOKAHEAD;
            let corner = match planes.get(k + 1) {
                Some(_) if seen && k == 0 => start_up(run, &a, &elem(k + 1), approach)?,
                Some(_) if seen => corner(run, &a, &elem(k + 1))?,
                Some(_) => {
                    // Past the look-ahead: the next move starts from this
                    // perpendicular vector (an arc after a link to its own).
                    let b = elem(k + 1);
                    if b.arc.is_some() {
                        before = Some(Step::Link { owner: b.index, to: b.offset_start(run.s, run.r), around: None });
                    }
                    perpendicular(run, &a)
                }
                None => match exit {
                    Some(c) if seen && k > 0 && !run.cycle_return => cancel(run, &a, &c, approach)?,
                    _ => perpendicular(run, &a),
                },
            };
            let forward = (k > 0).then(|| a.to.sub(a.from));
            steps.push(run.cut(&a, corner.end, forward));
            steps.extend(corner.links.into_iter().map(|to| Step::Link { owner: a.index, to, around: None }));
            steps.extend((planes[k] + 1..next_pos).map(pass));
        }
    }
    steps.extend(run.exit.map(|index| Step::Exit { index }));
    Ok(steps)
}

/// The end of `a` on the vector perpendicular to it.
fn perpendicular(run: &Run, a: &Element) -> Corner {
    Corner { end: a.offset_end(run.s, run.r), links: Vec::new() }
}

/// Start-up from the uncompensated start of line `a` toward `b`: inside
/// corners take the intersection; outside corners the perpendicular
/// vector of `b` (type A) or the type C corner vectors (type B).
fn start_up(run: &Run, a: &Element, b: &Element, approach: Approach) -> Result<Corner, Error> {
    let turn = classify(a.end_tangent(), b.start_tangent(), run.s);
    match (turn, approach) {
        (Turn::OutsideObtuse | Turn::OutsideAcute, Approach::A) => {
            Ok(Corner { end: b.offset_start(run.s, run.r), links: Vec::new() })
        }
        _ => corner(run, a, b),
    }
}

/// Cancel after `a` by straight move `c`: the mirror of start-up.
fn cancel(run: &Run, a: &Element, c: &Element, approach: Approach) -> Result<Corner, Error> {
    let turn = classify(a.end_tangent(), c.start_tangent(), run.s);
    match (turn, approach) {
        (Turn::OutsideObtuse | Turn::OutsideAcute, Approach::A) => Ok(perpendicular(run, a)),
        _ => corner(run, a, c),
    }
}

/// The type C corner from `a` to `b` at the programmed point `a.to`.
///
/// Inside: the intersection of the offset paths. Outside, an arc counts as
/// its tangent at the corner (the tangent-extension rule): obtuse, the
/// intersection of the two offset tangent lines; acute, each offset
/// tangent line extended by `r` past the perpendicular vector and the two
/// ends joined by a straight move. An arc ends at its own perpendicular
/// vector and reaches the tangent line's point by a straight move; an arc
/// after the corner starts from its perpendicular vector the same way.
fn corner(run: &Run, a: &Element, b: &Element) -> Result<Corner, Error> {
    let (s, r) = (run.s, run.r);
    let (t1, t2) = (a.end_tangent(), b.start_tangent());
    let p = a.to;
    let ea = a.offset_end(s, r);
    let sb = b.offset_start(s, r);
    let mut links = Vec::new();
    let end = match classify(t1, t2, s) {
        Turn::Straight => ea,
        Turn::Inside => {
            let no =
                || Alarm::NoIntersection { from_arc: a.arc.is_some(), to_arc: b.arc.is_some() }.at(b.index, run.rules);
            intersect(run.path(a)?, run.path(b)?, p).ok_or_else(no)?
        }
        Turn::OutsideObtuse => {
            let x = intersect(Path::Line { point: ea, dir: t1 }, Path::Line { point: sb, dir: t2 }, p)
                .ok_or_else(|| Alarm::Numeric.at(b.index, run.rules))?;
            tangent_point(a, ea, x, &mut links)
        }
        Turn::OutsideAcute => {
            let far = ea.add(t1.scale(r));
            let end = tangent_point(a, ea, far, &mut links);
            links.push(sb.sub(t2.scale(r)));
            end
        }
    };
    if b.arc.is_some() && !matches!(classify(t1, t2, s), Turn::Inside | Turn::Straight) {
        links.push(sb);
    }
    Ok(Corner { end, links })
}

/// Where `a` itself ends when its corner point on the tangent line is
/// `point`: a line is extended to it, an arc ends at `ea` and a link goes on.
fn tangent_point(a: &Element, ea: V2, point: V2, links: &mut Vec<V2>) -> V2 {
    if a.arc.is_some() {
        links.push(point);
        ea
    } else {
        point
    }
}
