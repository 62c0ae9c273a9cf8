//! Transforms of moves and toolpaths: an arc as straight pieces, a
//! toolpath scaled.

use super::{Axes, Move, MoveKind, Plane, Toolpath};

impl Move {
    /// The points the move passes through as straight pieces, its end
    /// last: an arc as the fewest equal chords that stay within
    /// `tolerance` of it (its rotary axes and helical axis vary linearly),
    /// any other move as its end. A tolerance that is not positive, or an
    /// arc that would need more than a million chords, is taken at the
    /// tolerance of a million.
    pub fn linearize(&self, tolerance: f64) -> Vec<Axes> {
        let MoveKind::Arc(arc) = self.kind else { return vec![self.end] };
        let r = arc.radius(self.start);
        let sweep = arc.sweep(self.start, self.end);
        let n = if tolerance > 0.0 && r > tolerance {
            let step = 2.0 * (1.0 - tolerance / r).acos();
            (sweep / step).ceil()
        } else if tolerance > 0.0 {
            // Every chord of a circle this small is within the tolerance.
            (sweep / std::f64::consts::FRAC_PI_2).ceil()
        } else {
            f64::INFINITY
        };
        let n = if n.is_finite() { n.clamp(1.0, 1e6) as usize } else { 1_000_000 };
        let mut points: Vec<Axes> = (1..n).map(|k| arc.point_at(self.start, self.end, k as f64 / n as f64)).collect();
        points.push(self.end);
        points
    }
}

impl Toolpath {
    /// The toolpath scaled by `k` in X and Y (U and V) and `s` in Z (W) about each move's
    /// program zero. An arc outside the XY plane scaled unevenly is no
    /// longer an arc: it becomes chords within 0.0005 mm of the scaled
    /// curve. Returns to the reference point and machine-coordinate moves
    /// are machine positions and keep theirs.
    pub fn scaled(&self, k: f64, s: f64) -> Toolpath {
        self.scaled_after(k, s, None)
    }

    /// [`Toolpath::scaled`] of a piece of a path (a run's, handed on)
    /// whose piece before ended with `before`: a move that starts where a
    /// return to the reference point or a machine-coordinate move left the
    /// tool starts there still. The pieces so scaled are the whole path
    /// scaled.
    pub fn scaled_after(&self, k: f64, s: f64, before: Option<&Move>) -> Toolpath {
        let mut out = Toolpath { moves: Vec::with_capacity(self.moves.len()), ..self.clone() };
        out.moves.clear();
        let mut fixed_end: Option<Axes> =
            before.filter(|m| matches!(m.kind, MoveKind::Home | MoveKind::Machine)).map(|m| m.end);
        let mut first = Vec::with_capacity(self.moves.len() + 1);
        for m in &self.moves {
            first.push(out.moves.len());
            let o = self.frame(m).origin;
            // U V W scale as the X Y Z they parallel.
            let sc = |p: Axes| Axes {
                x: o.x + (p.x - o.x) * k,
                y: o.y + (p.y - o.y) * k,
                z: o.z + (p.z - o.z) * s,
                u: o.u + (p.u - o.u) * k,
                v: o.v + (p.v - o.v) * k,
                w: o.w + (p.w - o.w) * s,
                ..p
            };
            let start = match fixed_end {
                Some(e) if e == m.start => m.start,
                _ => sc(m.start),
            };
            fixed_end = None;
            match m.kind {
                MoveKind::Home | MoveKind::Machine => {
                    out.moves.push(Move { start, ..*m });
                    fixed_end = Some(m.end);
                }
                MoveKind::Arc(arc) if arc.plane != Plane::Xy && k != s => {
                    let mut from = start;
                    for p in m.linearize(0.0005 / k.max(s)) {
                        let end = sc(p);
                        out.moves.push(Move { kind: MoveKind::Feed, start: from, end, ..*m });
                        from = end;
                    }
                }
                MoveKind::Arc(arc) => {
                    let c = arc.center;
                    let centre = sc(Axes { x: c[0], y: c[1], z: c[2], ..Axes::ZERO });
                    let arc = super::Arc { center: centre.xyz(), ..arc };
                    out.moves.push(Move { kind: MoveKind::Arc(arc), start, end: sc(m.end), ..*m });
                }
                _ => out.moves.push(Move { start, end: sc(m.end), ..*m }),
            }
        }
        first.push(out.moves.len());
        out.kept = self.kept_in(&first);
        out
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::super::Arc;
    use super::*;

    fn at(x: f64, y: f64, z: f64) -> Axes {
        Axes { x, y, z, ..Axes::ZERO }
    }

    #[test]
    fn arcs_become_chords_within_the_tolerance() {
        let arc = Arc { center: [0.0, 0.0, 0.0], plane: Plane::Xy, ccw: false, turns: 0 };
        let m =
            Move { kind: MoveKind::Arc(arc), start: at(10.0, 0.0, 0.0), end: at(-10.0, 0.0, -2.0), ..Move::default() };
        let tol = 0.005;
        let pts = m.linearize(tol);
        // Half a turn at 10 mm: chords of at most 2·acos(1 − 0.0005) each.
        let n = (PI / (2.0 * (1.0 - tol / 10.0).acos())).ceil() as usize;
        assert_eq!(pts.len(), n);
        assert_eq!(*pts.last().unwrap(), m.end);
        let mut prev = m.start;
        for p in &pts {
            assert!((p.x.hypot(p.y) - 10.0).abs() < 1e-9);
            assert!(p.y <= 1e-12, "clockwise from +X goes through -Y: {p:?}");
            let mid = ((prev.x + p.x) / 2.0).hypot((prev.y + p.y) / 2.0);
            assert!(10.0 - mid <= tol + 1e-12);
            prev = *p;
        }
        // Straight moves are their end.
        let line = Move { end: at(1.0, 2.0, 3.0), ..Move::default() };
        assert_eq!(line.linearize(tol), vec![line.end]);
    }

    #[test]
    fn scaling_keeps_arcs_and_home_moves() {
        let arc = Arc { center: [5.0, 0.0, -1.0], plane: Plane::Xy, ccw: true, turns: 0 };
        let zx = Arc { center: [10.0, 0.0, -2.0], plane: Plane::Zx, ccw: true, turns: 0 };
        let path = Toolpath::from(vec![
            Move { kind: MoveKind::Arc(arc), start: at(0.0, 0.0, -1.0), end: at(10.0, 0.0, -1.0), ..Move::default() },
            Move { kind: MoveKind::Arc(zx), start: at(10.0, 0.0, -1.0), end: at(10.0, 0.0, -3.0), ..Move::default() },
            Move { kind: MoveKind::Home, start: at(10.0, 0.0, -3.0), end: at(10.0, 0.0, 100.0), ..Move::default() },
            Move { kind: MoveKind::Rapid, start: at(10.0, 0.0, 100.0), end: at(1.0, 1.0, 100.0), ..Move::default() },
        ]);
        let scaled = path.scaled(2.0, 0.5);
        let MoveKind::Arc(a) = scaled.moves[0].kind else { panic!() };
        assert_eq!((a.center, scaled.moves[0].end), ([10.0, 0.0, -0.5], at(20.0, 0.0, -0.5)));
        // The ZX arc is chords of the scaled ellipse.
        let chords: Vec<&Move> = scaled.moves.iter().filter(|m| m.kind == MoveKind::Feed).collect();
        assert!(chords.len() > 10);
        assert_eq!(chords.last().unwrap().end, at(20.0, 0.0, -1.5));
        let home = scaled.moves.iter().find(|m| m.kind == MoveKind::Home).unwrap();
        assert_eq!(home.end, at(10.0, 0.0, 100.0));
        let last = scaled.moves.last().unwrap();
        assert_eq!((last.start, last.end), (at(10.0, 0.0, 100.0), at(2.0, 2.0, 50.0)));
    }
}
