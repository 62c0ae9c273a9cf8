//! A toolpath's end points replaced (a corrected program): each start
//! follows the end before, and an arc's centre moves as its end does.

use crate::{Axes, MoveKind, Toolpath};

/// What an arc's centre does when its end point is corrected.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArcCentre {
    /// Moves with the end point's correction: a correction that hardly
    /// changes over the arc (thermal drift) keeps the arc's turn.
    FollowsEnd,
    /// Moves the least that puts it on the perpendicular bisector of the
    /// corrected ends (in the arc's plane): a correction along the surface
    /// normal (wear) changes the arc's radius, as a contour's offset does,
    /// and both ends stay on one circle.
    OnChordBisector,
}

/// `path` with each move's end set to `ends` (one per move; dwells stay
/// where the tool is) and each start to the end before.
pub fn set_ends(path: &mut Toolpath, ends: &[Axes], arcs: ArcCentre) {
    set_ends_after(path, ends, arcs, None);
}

/// [`set_ends`] on a piece of a path (a run's, handed on): `before` is
/// where the piece before left the tool (its last corrected end), the
/// start of this piece's first move. Returns where this piece leaves it,
/// for the next: the pieces so corrected are the whole path corrected.
pub fn set_ends_after(path: &mut Toolpath, ends: &[Axes], arcs: ArcCentre, before: Option<Axes>) -> Option<Axes> {
    let mut start = before;
    for (m, end) in path.moves.iter_mut().zip(ends) {
        if let MoveKind::Dwell(_) = m.kind {
            if let Some(s) = start {
                (m.start, m.end) = (s, s);
            }
            continue;
        }
        let shift = [end.x - m.end.x, end.y - m.end.y, end.z - m.end.z];
        if let Some(s) = start {
            m.start = s;
        }
        if let MoveKind::Arc(arc) = &mut m.kind {
            match arcs {
                ArcCentre::FollowsEnd => {
                    for (c, d) in arc.center.iter_mut().zip(shift) {
                        *c += d;
                    }
                }
                ArcCentre::OnChordBisector => {
                    let (i, j, _) = arc.plane.axes();
                    let (s, e) = (m.start.xyz(), end.xyz());
                    let (mi, mj) = (0.5 * (s[i] + e[i]), 0.5 * (s[j] + e[j]));
                    let (di, dj) = (e[i] - s[i], e[j] - s[j]);
                    let len2 = di * di + dj * dj;
                    if len2 > 0.0 {
                        // The centre less its part along the chord from the midpoint.
                        let t = ((arc.center[i] - mi) * di + (arc.center[j] - mj) * dj) / len2;
                        arc.center[i] -= t * di;
                        arc.center[j] -= t * dj;
                    }
                }
            }
        }
        m.end = *end;
        start = Some(*end);
    }
    start
}
