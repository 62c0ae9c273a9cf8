//! A chamfer or corner R where an arc meets a line or another arc (`,C`,
//! `,R` between G01, G02 and G03 moves): FANUC Series 0i-TF Plus
//! Operator's Manual (B-64604EN), lathe system, "Chamfering and corner R"
//! (arbitrary angle chamfering and corner rounding between straight lines
//! and arcs).
//!
//! Both moves lie in the plane in force, in its coordinates (i, j). A
//! corner R is the arc of radius r tangent to both: its centre is where
//! the two moves' paths moved r toward the side the path turns to meet
//! (a line moved along its normal, an arc's circle made r smaller or
//! larger), its ends the points of tangency. A chamfer joins the points at
//! the length `,C` from the corner along each move (along an arc: that arc
//! length; kezuri's reading where the manual draws only lines). Where the
//! chamfer or arc does not fit on the moves, the control stops with an
//! alarm.

use std::f64::consts::TAU;

use kezuri_geom::{Move, MoveKind, Plane};

type V = [f64; 2];

fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1]]
}

fn add(a: V, b: V, k: f64) -> V {
    [a[0] + k * b[0], a[1] + k * b[1]]
}

fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn cross(a: V, b: V) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

fn norm(a: V) -> f64 {
    a[0].hypot(a[1])
}

fn unit(a: V) -> V {
    let n = norm(a);
    [a[0] / n, a[1] / n]
}

/// A move in the plane: a line, or an arc round `centre` of `radius`.
#[derive(Clone, Copy, Debug)]
struct Element {
    from: V,
    to: V,
    arc: Option<(V, f64, bool)>,
}

/// A circle or a line: what an element's path moved sideways is.
#[derive(Clone, Copy, Debug)]
enum Curve {
    Line { point: V, dir: V },
    Circle { centre: V, radius: f64 },
}

impl Element {
    /// The move in `plane`'s coordinates; `None` where it travels off the
    /// plane (a helix, another axis) or is a full circle.
    fn of(m: &Move, plane: Plane) -> Option<Element> {
        let (i, j, _) = plane.axes();
        let (s, e) = (m.start.to_array(), m.end.to_array());
        let off_plane = (0..6).filter(|&a| a != i && a != j).any(|a| (s[a] - e[a]).abs() > 1e-9);
        if off_plane {
            return None;
        }
        let (from, to) = ([s[i], s[j]], [e[i], e[j]]);
        let arc = match m.kind {
            MoveKind::Feed => None,
            MoveKind::Arc(a) if a.plane == plane && a.turns == 0 => {
                let c = [a.center[i], a.center[j]];
                Some((c, norm(sub(from, c)), a.ccw))
            }
            _ => return None,
        };
        // A full circle, an arc round its own end, a line of no length:
        // no direction to make a corner with.
        let degenerate = match arc {
            Some((_, r, _)) => r < 1e-9 || norm(sub(from, to)) < 1e-12,
            None => norm(sub(from, to)) < 1e-12,
        };
        (!degenerate).then_some(Element { from, to, arc })
    }

    /// +1 counter-clockwise, −1 clockwise.
    fn turn(ccw: bool) -> f64 {
        if ccw {
            1.0
        } else {
            -1.0
        }
    }

    /// An arc's sweep in its own direction, (0, 2π).
    fn sweep(&self, centre: V, ccw: bool) -> f64 {
        let (a0, a1) = (angle(sub(self.from, centre)), angle(sub(self.to, centre)));
        (Self::turn(ccw) * (a1 - a0)).rem_euclid(TAU)
    }

    fn length(&self) -> f64 {
        match self.arc {
            None => norm(sub(self.to, self.from)),
            Some((c, r, ccw)) => r * self.sweep(c, ccw),
        }
    }

    /// The unit direction of travel at `p` (a point of the element).
    fn tangent(&self, p: V) -> V {
        match self.arc {
            None => unit(sub(self.to, self.from)),
            Some((c, _, ccw)) => {
                let d = unit(sub(p, c));
                let k = Self::turn(ccw);
                [-k * d[1], k * d[0]]
            }
        }
    }

    /// The point `s` along the element from its start (`from_end`: back
    /// from its end).
    fn at(&self, s: f64, from_end: bool) -> V {
        match self.arc {
            None => {
                let d = unit(sub(self.to, self.from));
                if from_end {
                    add(self.to, d, -s)
                } else {
                    add(self.from, d, s)
                }
            }
            Some((c, r, ccw)) => {
                let k = Self::turn(ccw) * if from_end { -1.0 } else { 1.0 };
                let base = if from_end { self.to } else { self.from };
                let a = angle(sub(base, c)) + k * s / r;
                [c[0] + r * a.cos(), c[1] + r * a.sin()]
            }
        }
    }

    /// How far along the element from its start the point `p` (on its path)
    /// lies.
    fn distance_to(&self, p: V) -> f64 {
        match self.arc {
            None => dot(sub(p, self.from), unit(sub(self.to, self.from))),
            Some((c, r, ccw)) => {
                let a = Self::turn(ccw) * (angle(sub(p, c)) - angle(sub(self.from, c)));
                let a = a.rem_euclid(TAU);
                // Just before the start reads as a whole turn: as before it.
                r * if a > TAU - 1e-9 { a - TAU } else { a }
            }
        }
    }

    /// The element's path moved `r` to its left (`side` +1) or right (−1).
    fn moved(&self, side: f64, r: f64) -> Option<Curve> {
        match self.arc {
            None => {
                let d = unit(sub(self.to, self.from));
                Some(Curve::Line { point: add(self.from, [-d[1], d[0]], side * r), dir: d })
            }
            Some((c, rho, ccw)) => {
                // Left of a counter-clockwise arc is toward its centre.
                let radius = rho - side * Self::turn(ccw) * r;
                (radius > 1e-9).then_some(Curve::Circle { centre: c, radius })
            }
        }
    }

    /// The point of the element's path nearest `p`: where a circle round
    /// `p` tangent to it touches it.
    fn foot(&self, p: V) -> V {
        match self.arc {
            None => {
                let d = unit(sub(self.to, self.from));
                add(self.from, d, dot(sub(p, self.from), d))
            }
            Some((c, r, _)) => add(c, unit(sub(p, c)), r),
        }
    }
}

fn angle(v: V) -> f64 {
    v[1].atan2(v[0])
}

/// The points where two curves meet.
fn meet(a: Curve, b: Curve) -> Vec<V> {
    match (a, b) {
        (Curve::Line { point: p, dir: d }, Curve::Line { point: q, dir: e }) => {
            let den = cross(d, e);
            if den.abs() < 1e-12 {
                return Vec::new();
            }
            vec![add(p, d, cross(sub(q, p), e) / den)]
        }
        (Curve::Line { point, dir }, Curve::Circle { centre, radius })
        | (Curve::Circle { centre, radius }, Curve::Line { point, dir }) => {
            let w = sub(point, centre);
            let (b, c) = (dot(w, dir), dot(w, w) - radius * radius);
            let disc = b * b - c;
            if disc < -1e-12 {
                return Vec::new();
            }
            let s = disc.max(0.0).sqrt();
            vec![add(point, dir, -b - s), add(point, dir, -b + s)]
        }
        (Curve::Circle { centre: c1, radius: r1 }, Curve::Circle { centre: c2, radius: r2 }) => {
            let d = norm(sub(c2, c1));
            if d < 1e-12 || d > r1 + r2 + 1e-12 || d < (r1 - r2).abs() - 1e-12 {
                return Vec::new();
            }
            let a = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d);
            let h = (r1 * r1 - a * a).max(0.0).sqrt();
            let u = unit(sub(c2, c1));
            let m = add(c1, u, a);
            vec![add(m, [-u[1], u[0]], h), add(m, [-u[1], u[0]], -h)]
        }
    }
}

/// What the corner becomes: the first move now ends at `a`, the corner
/// move (a chamfer, or an arc round `centre`) runs to `b`, where the second
/// move starts. Points in the plane's (i, j).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Made {
    pub a: V,
    pub b: V,
    /// The corner R's centre and turning sense; `None` for a chamfer.
    pub round: Option<(V, bool)>,
}

/// The chamfer (`round` false, `size` its length along each move) or
/// corner R (`size` its radius) between `first`, which ends at the corner,
/// and `second`, which starts there, one of them an arc. `Err`: why the
/// control stops.
pub(super) fn corner(first: &Move, second: &Move, plane: Plane, size: f64, round: bool) -> Result<Made, String> {
    let what = if round { "corner R" } else { "chamfer" };
    let (Some(e1), Some(e2)) = (Element::of(first, plane), Element::of(second, plane)) else {
        return Err(format!(
            "a {what} next to an arc joins two moves in the plane in force: these leave it, one is a full circle or \
             one has no length (the control stops with an alarm)"
        ));
    };
    let p = e1.to;
    let (t1, t2) = (e1.tangent(p), e2.tangent(p));
    let turn = cross(t1, t2);
    if turn.abs() < 1e-9 {
        return Err(format!(
            "a {what} where the two moves meet tangent (or turn straight back): there is no corner (the control stops \
             with an alarm)"
        ));
    }
    let (l1, l2) = (e1.length(), e2.length());
    let too_long = |d1: f64, d2: f64| {
        format!(
            "the {what} ({size:.4} mm) does not fit: it needs {d1:.4} mm and {d2:.4} mm of the moves beside it, which \
             are {l1:.4} mm and {l2:.4} mm long (the control stops with an alarm)"
        )
    };
    if !round {
        if size > l1 + 1e-9 || size > l2 + 1e-9 {
            return Err(too_long(size, size));
        }
        let (a, b) = (e1.at(size, true), e2.at(size, false));
        if !(a.iter().chain(&b).all(|c| c.is_finite())) {
            return Err(too_long(size, size));
        }
        return Ok(Made { a, b, round: None });
    }
    // The corner arc's centre: both paths moved r toward the turn.
    let side = turn.signum();
    let (Some(c1), Some(c2)) = (e1.moved(side, size), e2.moved(side, size)) else {
        return Err(format!(
            "the corner R {size:.4} mm is larger than the arc it meets can hold on its inside (the control stops with \
             an alarm)"
        ));
    };
    let centre = meet(c1, c2).into_iter().min_by(|x, y| norm(sub(*x, p)).total_cmp(&norm(sub(*y, p))));
    let Some(centre) = centre else {
        return Err(format!("no corner R of {size:.4} mm touches both moves (the control stops with an alarm)"));
    };
    let (a, b) = (e1.foot(centre), e2.foot(centre));
    // How much of each move the arc takes, from the corner.
    let (d1, d2) = (l1 - e1.distance_to(a), e2.distance_to(b));
    if !(-1e-9..=l1 + 1e-9).contains(&d1) || !(-1e-9..=l2 + 1e-9).contains(&d2) {
        return Err(too_long(d1, d2));
    }
    let finite = [a, b, centre].iter().all(|v| v.iter().all(|c| c.is_finite()));
    if !finite {
        return Err(format!("no corner R of {size:.4} mm touches both moves (the control stops with an alarm)"));
    }
    Ok(Made { a, b, round: Some((centre, side > 0.0)) })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_move_of_no_length_beside_an_arc_is_refused_not_a_nan() {
        use kezuri_geom::{Arc, Axes};
        let at = |x: f64, z: f64| Axes { x, z, ..Axes::ZERO };
        let line = Move { kind: MoveKind::Feed, start: at(10.0, -10.0), end: at(10.0, -10.0), ..Move::default() };
        let arc = Arc { center: [10.0, 0.0, -20.0], plane: Plane::Zx, ccw: true, turns: 0 };
        let q = Move { kind: MoveKind::Arc(arc), start: at(10.0, -10.0), end: at(20.0, -20.0), ..Move::default() };
        for round in [false, true] {
            assert!(corner(&line, &q, Plane::Zx, 1.0, round).unwrap_err().contains("no length"));
        }
    }

    #[test]
    fn lines_meet_circles_where_the_equations_say() {
        // The line j = 1 meets the unit circle round (0, 1) at (±1, 1).
        let got = meet(
            Curve::Line { point: [-5.0, 1.0], dir: [1.0, 0.0] },
            Curve::Circle { centre: [0.0, 1.0], radius: 1.0 },
        );
        assert_eq!(got.len(), 2);
        assert!(got.iter().any(|p| (p[0] + 1.0).abs() < 1e-12) && got.iter().any(|p| (p[0] - 1.0).abs() < 1e-12));
        // Circles of radius 5 round (0, 0) and (8, 0) meet at (4, ±3).
        let got =
            meet(Curve::Circle { centre: [0.0, 0.0], radius: 5.0 }, Curve::Circle { centre: [8.0, 0.0], radius: 5.0 });
        assert!(got.iter().all(|p| (p[0] - 4.0).abs() < 1e-12 && (p[1].abs() - 3.0).abs() < 1e-12));
    }
}
