//! A turning contour as plain geometry: straight and circular pieces in a
//! frame of the cycle's own, `a` along the cut and `d` the depth into the
//! stock, both growing as the cycle works (the start point at (0, 0)).
//! What the multiple repetitive cycles ask of a contour is answered here:
//! where a depth crosses it, how shallow it gets between two places, which
//! way it runs.

use std::f64::consts::{PI, TAU};

/// A point: `[a, d]`.
pub(super) type P = [f64; 2];

/// Lengths under this are equal (mm).
pub(super) const EPS: f64 = 1e-9;

/// One piece of the contour, as one block of it moves the tool.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Piece {
    pub from: P,
    pub to: P,
    /// The arc's centre and turning (`true`: from +a towards +d), or
    /// `None` for a straight move.
    pub arc: Option<(P, bool)>,
    /// A rapid (`G00`) block of the contour.
    pub rapid: bool,
    /// Which block of the contour made it (an index into the cycle's list).
    pub block: usize,
}

/// A place on the contour: the piece and how far along it (0 to 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Spot {
    pub piece: usize,
    pub t: f64,
    pub at: P,
}

impl Piece {
    /// The arc's radius and its start angle and signed sweep (radians).
    fn arc_angles(&self) -> Option<(f64, f64, f64)> {
        let (c, ccw) = self.arc?;
        let r = (self.from[0] - c[0]).hypot(self.from[1] - c[1]);
        let a0 = (self.from[1] - c[1]).atan2(self.from[0] - c[0]);
        let a1 = (self.to[1] - c[1]).atan2(self.to[0] - c[0]);
        let mut sweep = if ccw { a1 - a0 } else { a0 - a1 };
        while sweep <= 1e-12 {
            sweep += TAU;
        }
        Some((r, a0, if ccw { sweep } else { -sweep }))
    }

    /// The point at `t` (0: `from`, 1: `to`).
    pub fn at(&self, t: f64) -> P {
        if t <= 0.0 {
            return self.from;
        }
        if t >= 1.0 {
            return self.to;
        }
        match (self.arc, self.arc_angles()) {
            (Some((c, _)), Some((r, a0, sweep))) => {
                let a = a0 + sweep * t;
                [c[0] + r * a.cos(), c[1] + r * a.sin()]
            }
            _ => [self.from[0] + (self.to[0] - self.from[0]) * t, self.from[1] + (self.to[1] - self.from[1]) * t],
        }
    }

    /// Where, strictly between its ends, the piece meets depth `level`
    /// (values of `t`, in order).
    fn meets(&self, level: f64) -> Vec<f64> {
        let mut ts = Vec::new();
        match (self.arc, self.arc_angles()) {
            (Some((c, _)), Some((r, a0, sweep))) => {
                let s = (level - c[1]) / r;
                if s.abs() < 1.0 {
                    let first = s.asin();
                    for angle in [first, PI - first] {
                        // The angle as a fraction of the sweep, from the start.
                        let mut delta = (angle - a0) * sweep.signum();
                        delta = delta.rem_euclid(TAU);
                        let t = delta / sweep.abs();
                        if t > 1e-12 && t < 1.0 - 1e-12 {
                            ts.push(t);
                        }
                    }
                }
            }
            _ => {
                let (d0, d1) = (self.from[1], self.to[1]);
                if (d0 - level) * (d1 - level) < 0.0 {
                    ts.push((level - d0) / (d1 - d0));
                }
            }
        }
        ts.sort_by(f64::total_cmp);
        ts
    }

    /// The shallowest depth the piece reaches.
    fn shallowest(&self) -> f64 {
        let ends = self.from[1].min(self.to[1]);
        match (self.arc, self.arc_angles()) {
            (Some((c, _)), Some((r, _, _))) if self.passes(-PI / 2.0) => ends.min(c[1] - r),
            _ => ends,
        }
    }

    /// Whether the arc passes angle `angle` strictly between its ends.
    pub fn passes(&self, angle: f64) -> bool {
        let Some((_, a0, sweep)) = self.arc_angles() else { return false };
        let delta = ((angle - a0) * sweep.signum()).rem_euclid(TAU);
        delta > 1e-9 && delta < sweep.abs() - 1e-9
    }

    /// The piece from `t0` to `t1` of it.
    pub fn part(&self, t0: f64, t1: f64) -> Piece {
        Piece { from: self.at(t0), to: self.at(t1), ..*self }
    }
}

/// Depth `level` as the contour crosses it: where the contour goes deeper
/// than it (`down`) or comes back up to it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Crossing {
    pub spot: Spot,
    pub down: bool,
}

/// The contour, start to end.
#[derive(Clone, Debug, Default)]
pub(super) struct Contour {
    pub pieces: Vec<Piece>,
}

impl Contour {
    /// Where the contour starts.
    pub fn start(&self) -> P {
        self.pieces.first().map_or([0.0, 0.0], |p| p.from)
    }

    /// Where it ends.
    pub fn end(&self) -> P {
        self.pieces.last().map_or([0.0, 0.0], |p| p.to)
    }

    /// Whether the contour starts deeper than `level`.
    pub fn starts_below(&self, level: f64) -> bool {
        self.start()[1] > level + EPS
    }

    /// The deepest point of the contour.
    pub fn deepest(&self) -> f64 {
        let mut deepest = f64::NEG_INFINITY;
        for p in &self.pieces {
            deepest = deepest.max(p.from[1]).max(p.to[1]);
            if let Some((c, _)) = p.arc {
                if p.passes(PI / 2.0) {
                    deepest = deepest.max(c[1] + (p.from[0] - c[0]).hypot(p.from[1] - c[1]));
                }
            }
        }
        deepest
    }

    /// Every crossing of depth `level`, in the contour's order. Being at
    /// the level is not being below it.
    pub fn crossings(&self, level: f64) -> Vec<Crossing> {
        let below = |p: P| p[1] > level + EPS;
        let mut out = Vec::new();
        let mut state = self.starts_below(level);
        for (k, piece) in self.pieces.iter().enumerate() {
            let mut ts = piece.meets(level);
            ts.push(1.0);
            let mut prev = 0.0;
            for &t in &ts {
                // The state between the last place and this one, from its middle.
                let mid = below(piece.at((prev + t) / 2.0));
                if mid != state {
                    out.push(Crossing { spot: Spot { piece: k, t: prev, at: piece.at(prev) }, down: mid });
                    state = mid;
                }
                prev = t;
            }
        }
        out
    }

    /// The shallowest depth of the contour over `a` from `a0` to `a1`
    /// (either order); pieces that reach into the range count whole.
    pub fn shallowest_between(&self, a0: f64, a1: f64) -> f64 {
        let (lo, hi) = (a0.min(a1) - EPS, a0.max(a1) + EPS);
        self.pieces
            .iter()
            .filter(|p| p.from[0].max(p.to[0]) >= lo && p.from[0].min(p.to[0]) <= hi)
            .map(Piece::shallowest)
            .fold(f64::INFINITY, f64::min)
    }

    /// The contour from `from` to `to` (`to` after `from` along it).
    pub fn between(&self, from: Spot, to: Spot) -> Vec<Piece> {
        let mut out = Vec::new();
        for k in from.piece..=to.piece.min(self.pieces.len().saturating_sub(1)) {
            let t0 = if k == from.piece { from.t } else { 0.0 };
            let t1 = if k == to.piece { to.t } else { 1.0 };
            if t1 > t0 + 1e-12 {
                out.push(self.pieces[k].part(t0, t1));
            }
        }
        out
    }

    /// The spot at the contour's end.
    pub fn end_spot(&self) -> Spot {
        Spot { piece: self.pieces.len().saturating_sub(1), t: 1.0, at: self.end() }
    }

    /// The first piece (by its index) that runs back along `a` (against
    /// the cut), if any: a contour a cycle cannot cut along `a`.
    pub fn first_backwards(&self) -> Option<usize> {
        self.pieces.iter().position(|p| p.to[0] < p.from[0] - EPS || p.passes(0.0) || p.passes(PI))
    }

    /// The first piece that goes deeper along the cut (against a contour
    /// that rises from its start to its end), if any.
    pub fn first_deeper(&self) -> Option<usize> {
        self.pieces.iter().position(|p| p.to[1] > p.from[1] + EPS || p.passes(PI / 2.0) || p.passes(-PI / 2.0))
    }

    /// The first piece that rises along the cut (against a contour that
    /// goes deeper from its start to its end), if any.
    pub fn first_shallower(&self) -> Option<usize> {
        self.pieces.iter().position(|p| p.to[1] < p.from[1] - EPS || p.passes(PI / 2.0) || p.passes(-PI / 2.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(from: P, to: P) -> Piece {
        Piece { from, to, arc: None, rapid: false, block: 0 }
    }

    /// A step down then up: depth 10 from a 0 to 5, then 4 to a 12, then 0.
    fn stepped() -> Contour {
        Contour {
            pieces: vec![
                line([0.0, 10.0], [5.0, 10.0]),
                line([5.0, 10.0], [5.0, 4.0]),
                line([5.0, 4.0], [12.0, 4.0]),
                line([12.0, 4.0], [12.0, 0.0]),
            ],
        }
    }

    #[test]
    fn crossings_of_a_stepped_contour() {
        let c = stepped();
        // At depth 6 the contour starts below and comes up at the step, a = 5.
        let x = c.crossings(6.0);
        assert_eq!(x.len(), 1);
        assert!(!x[0].down);
        assert!((x[0].spot.at[0] - 5.0).abs() < 1e-12 && (x[0].spot.at[1] - 6.0).abs() < 1e-12);
        // At depth 2, the up crossing is on the last step, a = 12.
        let x = c.crossings(2.0);
        assert_eq!(x.len(), 1);
        assert!((x[0].spot.at[0] - 12.0).abs() < 1e-12);
        // At depth 4 (a flat at the level is not below it): at the step.
        let x = c.crossings(4.0);
        assert_eq!(x.len(), 1);
        assert!((x[0].spot.at[0] - 5.0).abs() < 1e-12);
        assert_eq!(c.deepest(), 10.0);
        assert_eq!(c.first_deeper(), None);
        assert_eq!(c.first_backwards(), None);
    }

    #[test]
    fn a_pocket_makes_two_intervals() {
        // Depth 8, up to 2 at a 4..6, down again to 8 at a 8..10, out at 10.
        let c = Contour {
            pieces: vec![
                line([0.0, 8.0], [2.0, 8.0]),
                line([2.0, 8.0], [4.0, 2.0]),
                line([4.0, 2.0], [6.0, 2.0]),
                line([6.0, 2.0], [8.0, 8.0]),
                line([8.0, 8.0], [10.0, 8.0]),
                line([10.0, 8.0], [10.0, -1.0]),
            ],
        };
        let x = c.crossings(5.0);
        // Up at a 3 (halfway down 8 → 2 over a 2..4), down at a 7, up at 10.
        let a: Vec<_> = x.iter().map(|c| (c.down, (c.spot.at[0] * 1e9).round() / 1e9)).collect();
        assert_eq!(a, vec![(false, 3.0), (true, 7.0), (false, 10.0)]);
        assert_eq!(c.shallowest_between(3.0, 7.0), 2.0);
        assert_eq!(c.first_deeper(), Some(3));
    }

    #[test]
    fn an_arc_crosses_where_its_circle_does() {
        // A quarter circle of radius 5 about (0, 10) from (0, 5)... as the
        // contour turns from depth 5 up to depth 10 at a = 5: from angle -90°
        // to 0°, counter-clockwise. Depth 7 is met at a = sqrt(25 - 9) = 4.
        let arc = Piece { from: [0.0, 5.0], to: [5.0, 10.0], arc: Some(([0.0, 10.0], true)), rapid: false, block: 0 };
        let t = arc.meets(7.0);
        assert_eq!(t.len(), 1);
        let p = arc.at(t[0]);
        assert!((p[0] - 4.0).abs() < 1e-12 && (p[1] - 7.0).abs() < 1e-12, "{p:?}");
        assert!(!arc.passes(0.0) && !arc.passes(PI));
        // The half circle through angle 0 runs back along a.
        let half = Piece { from: [0.0, 5.0], to: [0.0, 15.0], arc: Some(([0.0, 10.0], true)), rapid: false, block: 0 };
        assert!(half.passes(0.0));
        assert_eq!(Contour { pieces: vec![half] }.first_backwards(), Some(0));
        assert!((Contour { pieces: vec![half] }.deepest() - 15.0).abs() < 1e-12);
    }
}
