//! Geometry in the compensation plane: 2-D vectors, the programmed elements
//! (a straight move or an arc seen in the plane), their offset paths and the
//! intersections of offset paths.
//!
//! Coordinates are (u, v) = the plane's first and second axis as
//! [`Plane::axes`] orders them, so that counter-clockwise (G03) is the
//! positive rotation and "left of the direction of travel" is the tangent
//! turned +90° in every plane.

use std::f64::consts::{PI, TAU};

use kezuri_geom::{Arc, Axes, Move, MoveKind, Plane};

/// Plane travel shorter than this (mm) counts as none.
pub(super) const MIN_TRAVEL: f64 = 1e-9;

/// A point or direction in the compensation plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct V2 {
    pub u: f64,
    pub v: f64,
}

impl V2 {
    pub fn new(u: f64, v: f64) -> V2 {
        V2 { u, v }
    }
    pub fn add(self, o: V2) -> V2 {
        V2::new(self.u + o.u, self.v + o.v)
    }
    pub fn sub(self, o: V2) -> V2 {
        V2::new(self.u - o.u, self.v - o.v)
    }
    pub fn scale(self, k: f64) -> V2 {
        V2::new(self.u * k, self.v * k)
    }
    pub fn dot(self, o: V2) -> f64 {
        self.u * o.u + self.v * o.v
    }
    /// The normal component of the cross product: positive when `o` turns
    /// counter-clockwise from `self`.
    pub fn cross(self, o: V2) -> f64 {
        self.u * o.v - self.v * o.u
    }
    pub fn len(self) -> f64 {
        self.u.hypot(self.v)
    }
    pub fn unit(self) -> V2 {
        self.scale(1.0 / self.len())
    }
    /// Turned +90° (counter-clockwise).
    pub fn left(self) -> V2 {
        V2::new(-self.v, self.u)
    }
    pub fn angle(self) -> f64 {
        self.v.atan2(self.u)
    }
    pub fn dist(self, o: V2) -> f64 {
        self.sub(o).len()
    }
}

/// The plane coordinates of a position.
pub(super) fn in_plane(p: Axes, plane: Plane) -> V2 {
    let (i, j, _) = plane.axes();
    let x = p.xyz();
    V2::new(x[i], x[j])
}

/// `p` with its plane coordinates replaced by `q`.
pub(super) fn with_plane(p: Axes, plane: Plane, q: V2) -> Axes {
    let (i, j, _) = plane.axes();
    let mut a = p.to_array();
    a[i] = q.u;
    a[j] = q.v;
    Axes::from_array(a)
}

/// Wraps an angle into (-π, π].
pub(super) fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(TAU);
    if w > PI {
        w - TAU
    } else {
        w
    }
}

/// The circle part of a programmed arc.
#[derive(Clone, Copy, Debug)]
pub(super) struct Circle {
    pub centre: V2,
    pub ccw: bool,
    /// Radius at the start.
    pub radius: f64,
    /// Programmed sweep in radians (extra turns included), always positive.
    pub sweep: f64,
}

/// A programmed move that travels in the compensation plane.
#[derive(Clone, Copy, Debug)]
pub(super) struct Element {
    /// Index of the move in the input.
    pub index: usize,
    pub from: V2,
    pub to: V2,
    /// `None` for a straight move.
    pub arc: Option<Circle>,
    /// A rapid (G00) straight move.
    pub rapid: bool,
}

/// The path the tool centre follows beside an element, or the extended
/// line a corner rule works with.
#[derive(Clone, Copy, Debug)]
pub(super) enum Path {
    /// The line through `point` with unit direction `dir`.
    Line { point: V2, dir: V2 },
    /// A circle.
    Circle { centre: V2, radius: f64 },
}

/// `+1` for left (G41), `-1` for right (G42).
pub(super) type SideSign = f64;

impl Element {
    /// The element for move `index`, or `None` when it has no travel in the
    /// plane. An arc in another plane is the caller's to refuse.
    pub fn of(m: &Move, index: usize, plane: Plane) -> Option<Element> {
        let from = in_plane(m.start, plane);
        let to = in_plane(m.end, plane);
        match m.kind {
            MoveKind::Arc(arc) => Some(Element { index, from, to, arc: Some(circle(&arc, m)), rapid: false }),
            MoveKind::Rapid | MoveKind::Feed if from.dist(to) > MIN_TRAVEL => {
                Some(Element { index, from, to, arc: None, rapid: m.kind == MoveKind::Rapid })
            }
            _ => None,
        }
    }

    /// Unit tangent (direction of travel) at `p`, a point of the element.
    fn tangent_at(&self, p: V2) -> V2 {
        match self.arc {
            None => self.to.sub(self.from).unit(),
            Some(c) => {
                let radial = p.sub(c.centre).unit().left();
                if c.ccw {
                    radial
                } else {
                    radial.scale(-1.0)
                }
            }
        }
    }

    /// Unit tangent at the start.
    pub fn start_tangent(&self) -> V2 {
        self.tangent_at(self.from)
    }

    /// Unit tangent at the end.
    pub fn end_tangent(&self) -> V2 {
        self.tangent_at(self.to)
    }

    /// The offset point at the start: `r` along the normal toward the side.
    pub fn offset_start(&self, s: SideSign, r: f64) -> V2 {
        self.from.add(normal(self.start_tangent(), s).scale(r))
    }

    /// The offset point at the end.
    pub fn offset_end(&self, s: SideSign, r: f64) -> V2 {
        self.to.add(normal(self.end_tangent(), s).scale(r))
    }

    /// `true` when the tool is on the centre's side of an arc.
    pub fn tool_inside(&self, s: SideSign) -> bool {
        self.arc.is_some_and(|c| (s > 0.0) == c.ccw)
    }

    /// The tool centre's path beside the element: the parallel line, or the
    /// concentric circle of radius R ∓ r (R − r with the tool inside).
    pub fn offset_path(&self, s: SideSign, r: f64) -> Path {
        match self.arc {
            None => Path::Line { point: self.offset_start(s, r), dir: self.start_tangent() },
            Some(c) => {
                let radius = if self.tool_inside(s) { c.radius - r } else { c.radius + r };
                Path::Circle { centre: c.centre, radius }
            }
        }
    }
}

fn circle(arc: &Arc, m: &Move) -> Circle {
    let (i, j, _) = arc.plane.axes();
    Circle {
        centre: V2::new(arc.center[i], arc.center[j]),
        ccw: arc.ccw,
        radius: arc.radius(m.start),
        sweep: arc.sweep(m.start, m.end),
    }
}

/// The unit normal toward the compensation side of unit tangent `t`.
pub(super) fn normal(t: V2, s: SideSign) -> V2 {
    t.left().scale(s)
}

/// The intersection of two offset paths nearest to `near`, or `None` when
/// they do not meet (parallel lines count as not meeting unless they are
/// one line, when `near` projected on it is returned).
pub(super) fn intersect(a: Path, b: Path, near: V2) -> Option<V2> {
    match (a, b) {
        (Path::Line { point: p, dir: d }, Path::Line { point: q, dir: e }) => {
            let den = d.cross(e);
            if den.abs() < 1e-12 {
                let off = q.sub(p);
                return (off.cross(d).abs() < 1e-9).then(|| p.add(d.scale(near.sub(p).dot(d))));
            }
            let t = q.sub(p).cross(e) / den;
            Some(p.add(d.scale(t)))
        }
        (Path::Line { point, dir }, Path::Circle { centre, radius })
        | (Path::Circle { centre, radius }, Path::Line { point, dir }) => {
            // Foot of the centre on the line, then ± the half chord.
            let foot = point.add(dir.scale(centre.sub(point).dot(dir)));
            let h2 = radius * radius - foot.dist(centre).powi(2);
            if h2 < -1e-9 * radius.max(1.0) {
                return None;
            }
            let h = h2.max(0.0).sqrt();
            Some(nearest(foot.add(dir.scale(h)), foot.sub(dir.scale(h)), near))
        }
        (Path::Circle { centre: c1, radius: r1 }, Path::Circle { centre: c2, radius: r2 }) => {
            let d = c1.dist(c2);
            if d < 1e-12 {
                return None;
            }
            let a = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d);
            let h2 = r1 * r1 - a * a;
            if h2 < -1e-9 * r1.max(1.0) {
                return None;
            }
            let h = h2.max(0.0).sqrt();
            let axis = c2.sub(c1).scale(1.0 / d);
            let mid = c1.add(axis.scale(a));
            let across = axis.left().scale(h);
            Some(nearest(mid.add(across), mid.sub(across), near))
        }
    }
}

fn nearest(p: V2, q: V2, near: V2) -> V2 {
    if p.dist(near) <= q.dist(near) {
        p
    } else {
        q
    }
}

/// How a corner turns, seen from the tool.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Turn {
    /// The directions agree (a tangent joint).
    Straight,
    /// The tool is on the inside of the corner (Fanuc: α ≥ 180°).
    Inside,
    /// Outside, the angle on the work side between 90° and 180°.
    OutsideObtuse,
    /// Outside, the angle on the work side under 90° (a reversal included).
    OutsideAcute,
}

/// Classifies the corner from unit tangent `t1` (end of the first element)
/// to `t2` (start of the next) for a tool on side `s`.
pub(super) fn classify(t1: V2, t2: V2, s: SideSign) -> Turn {
    let (cross, dot) = (t1.cross(t2), t1.dot(t2));
    if cross.abs() <= 1e-12 {
        return if dot > 0.0 { Turn::Straight } else { Turn::OutsideAcute };
    }
    if s * cross > 0.0 {
        Turn::Inside
    } else if dot >= 0.0 {
        Turn::OutsideObtuse
    } else {
        Turn::OutsideAcute
    }
}

/// The signed turn angle from `t1` to `t2` in (-π, π], positive
/// counter-clockwise.
pub(super) fn turn_angle(t1: V2, t2: V2) -> f64 {
    t1.cross(t2).atan2(t1.dot(t2))
}
