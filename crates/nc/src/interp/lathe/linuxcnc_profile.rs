//! The geometry of LinuxCNC's lathe cycles `G70` (finishing along a
//! profile), `G71` and `G72` (roughing down to it, along Z or along X), as
//! LinuxCNC's G-code reference describes them and its interpreter rs274
//! (2.9) cuts them, pass for pass.
//!
//! Points are complex numbers `z + i·x` in program units (X a radius). The
//! profile is first brought to a normal form: turned a quarter for a
//! facing cycle (`G72`), mirrored so that Z and X both decrease along it;
//! the cutting is planned there and every move mapped back. The roughing
//! cuts layers `I` apart from the start's X down, each ended on the profile
//! and left by `R` diagonally; pockets (where the profile climbs again) are
//! cut after the climb, unless `G7x.1` leaves them (or `G7x.2` cuts only
//! them).

use std::ops::{Add, Div, Mul, Neg, Sub};

/// How near two numbers must be to count as equal (program units).
const TOL: f64 = 1e-6;

mod cuts;

pub(super) use cuts::Profile;

/// A point `z + i·x`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct P {
    pub z: f64,
    pub x: f64,
}

impl P {
    pub(super) fn new(z: f64, x: f64) -> P {
        P { z, x }
    }
    fn conj(self) -> P {
        P::new(self.z, -self.x)
    }
    fn abs(self) -> f64 {
        self.z.hypot(self.x)
    }
    /// The square of the length.
    fn norm(self) -> f64 {
        self.z * self.z + self.x * self.x
    }
    /// Multiplied by i (a quarter turn).
    fn i(self) -> P {
        P::new(-self.x, self.z)
    }
    fn scale(self, k: f64) -> P {
        P::new(self.z * k, self.x * k)
    }
}

impl Add for P {
    type Output = P;
    fn add(self, o: P) -> P {
        P::new(self.z + o.z, self.x + o.x)
    }
}
impl Sub for P {
    type Output = P;
    fn sub(self, o: P) -> P {
        P::new(self.z - o.z, self.x - o.x)
    }
}
impl Neg for P {
    type Output = P;
    fn neg(self) -> P {
        P::new(-self.z, -self.x)
    }
}
impl Mul for P {
    type Output = P;
    fn mul(self, o: P) -> P {
        P::new(self.z * o.z - self.x * o.x, self.z * o.x + self.x * o.z)
    }
}
/// Division as C's complex division does it (Smith's method, as GCC's
/// runtime computes it for numbers of ordinary size): the profile's
/// geometry meets rs274's to the last bit, where a near tie between two
/// intersections is decided.
impl Div for P {
    type Output = P;
    fn div(self, o: P) -> P {
        let (a, b, c, d) = (self.z, self.x, o.z, o.x);
        if c.abs() < d.abs() {
            let ratio = c / d;
            let denom = c * ratio + d;
            if ratio.abs() > f64::MIN_POSITIVE {
                P::new((a * ratio + b) / denom, (b * ratio - a) / denom)
            } else {
                P::new((c * (a / d) + b) / denom, (c * (b / d) - a) / denom)
            }
        } else {
            let ratio = d / c;
            let denom = d * ratio + c;
            if ratio.abs() > f64::MIN_POSITIVE {
                P::new((b * ratio + a) / denom, (b - a * ratio) / denom)
            } else {
                P::new((a + d * (b / c)) / denom, (b - d * (a / c)) / denom)
            }
        }
    }
}

impl P {
    /// Each coordinate divided by `k`.
    fn over(self, k: f64) -> P {
        P::new(self.z / k, self.x / k)
    }
}

/// What a profile's corner word asks for at a segment's end: `A` a fillet
/// of that radius, `C` a chamfer of that size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Corner {
    Fillet(f64),
    Chamfer(f64),
}

/// One piece of the profile: a line, or an arc about `centre` (`ccw`: G3).
/// A corner not yet made is a piece of no length at the corner, `corner`
/// set.
#[derive(Clone, Copy, Debug)]
pub(super) struct Seg {
    pub start: P,
    pub end: P,
    /// `None`: a line.
    pub arc: Option<(P, bool)>,
    pub corner: Option<Corner>,
}

/// A move the cycle makes, in program coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Out {
    Rapid(P),
    Feed(P),
    /// An arc to the point about the centre, `true` for G3.
    Arc(P, P, bool),
}

/// Why a profile cannot be cut (rs274's "G7X error: …").
pub(super) type Fault = String;

impl Seg {
    pub(super) fn line(start: P, end: P) -> Seg {
        Seg { start, end, arc: None, corner: None }
    }
    pub(super) fn arc(ccw: bool, start: P, centre: P, end: P) -> Seg {
        Seg { start, end, arc: Some((centre, ccw)), corner: None }
    }
    pub(super) fn corner(corner: Corner, at: P) -> Seg {
        let arc = matches!(corner, Corner::Fillet(_)).then_some((at, false));
        Seg { start: at, end: at, arc, corner: Some(corner) }
    }

    /// The corner's size still to be made (0 once made or for none).
    fn finish(&self) -> f64 {
        match self.corner {
            Some(Corner::Fillet(d) | Corner::Chamfer(d)) => d,
            None => 0.0,
        }
    }

    /// The Z of each place where the piece is at `x`.
    fn crossings(&self, x: f64) -> Vec<f64> {
        let mut is = Vec::new();
        match self.arc {
            None => {
                let (s, e) = (self.start, self.end);
                if s.x.min(e.x) > x + TOL || s.x.max(e.x) < x - TOL {
                    return is;
                }
                if (s.x - e.x).abs() < TOL {
                    is.push(s.z);
                    is.push(e.z);
                } else {
                    is.push((x - s.x) / (e.x - s.x) * (e.z - s.z) + s.z);
                }
            }
            Some((c, _)) => {
                let r = (self.start - c).abs();
                let mut s = -(x - r - c.x) * (x + r - c.x);
                if s < -TOL {
                    return is;
                }
                s = s.max(0.0).sqrt();
                for p in [P::new(c.z + s, x), P::new(c.z - s, x)] {
                    if self.on_arc(p) {
                        is.push(p.z);
                    }
                }
            }
        }
        is
    }

    /// Whether `p` (on the circle) lies between the arc's ends.
    fn on_arc(&self, p: P) -> bool {
        let Some((c, ccw)) = self.arc else { return true };
        let a = ((self.start - c).conj() * (p - c)).x;
        let b = ((self.end - c).conj() * (p - c)).x;
        if ccw {
            a >= -TOL && b <= TOL
        } else {
            a <= TOL && b >= -TOL
        }
    }

    /// The move along the piece to `to`.
    fn draw_to(&self, to: P, out: &mut Vec<Out>) {
        match self.arc {
            None => out.push(Out::Feed(to)),
            Some((c, ccw)) => out.push(Out::Arc(to, c, ccw)),
        }
    }

    /// Along a rising piece from `at`: true where the piece does not rise
    /// (the climb stops there).
    fn climb(&self, at: &mut P, out: &mut Vec<Out>) -> Result<bool, Fault> {
        match self.arc {
            None => {
                if self.end.x + TOL < self.start.x {
                    return Ok(true);
                }
                if (*at - self.start).abs() > TOL {
                    return Err("How did we get here?".into());
                }
                out.push(Out::Feed(self.end));
                *at = self.end;
                Ok(false)
            }
            Some((c, false)) => {
                if at.z > c.z {
                    return Ok(true);
                }
                if (*at - self.end).abs() > 1e-3 {
                    out.push(Out::Arc(self.end, c, false));
                }
                *at = self.end;
                Ok(false)
            }
            Some((c, true)) => {
                if at.z < c.z {
                    return Ok(true);
                }
                let top = self.top_of_ccw(c);
                if (*at - top).abs() > 1e-3 {
                    out.push(Out::Arc(top, c, true));
                }
                *at = top;
                Ok(true)
            }
        }
    }

    /// Where a G3 piece climbing from `at` stops: its end, or the top of
    /// its circle where the end is past it.
    fn top_of_ccw(&self, c: P) -> P {
        if self.end.z < c.z {
            P::new(c.z, c.x + (self.start - c).abs())
        } else {
            self.end
        }
    }

    /// After the last layer of a `G7x.1`: onto the piece at the tool's X
    /// and along it where it rises.
    fn climb_only(&self, at: &mut P, out: &mut Vec<Out>) {
        let is = self.crossings(at.x);
        let (Some(&first), Some(&last)) = (is.first(), is.last()) else { return };
        match self.arc {
            None => {
                if self.end.x < self.start.x {
                    return;
                }
                at.z = first;
                out.push(Out::Feed(*at));
                out.push(Out::Feed(self.end));
                *at = self.end;
            }
            Some((c, false)) => {
                if last > c.z {
                    return;
                }
                at.z = last;
                out.push(Out::Feed(*at));
                if (*at - self.end).abs() > 1e-3 {
                    out.push(Out::Arc(self.end, c, false));
                }
                *at = self.end;
            }
            Some((c, true)) => {
                if first < c.z {
                    return;
                }
                at.z = first;
                out.push(Out::Feed(*at));
                let top = self.top_of_ccw(c);
                if (*at - top).abs() > 1e-3 {
                    out.push(Out::Arc(top, c, true));
                }
                *at = top;
            }
        }
    }

    /// Down a falling piece from `at` to the layer at `x` (its end where
    /// that is above the layer); `fast`: the first piece, a rapid. True
    /// where the piece does not fall (a pocket's climb begins).
    fn dive(&self, at: &mut P, x: f64, out: &mut Vec<Out>, fast: bool) -> Result<bool, Fault> {
        match self.arc {
            None => {
                if self.start.x <= self.end.x + TOL {
                    return Ok(true);
                }
                let to = if x < self.end.x {
                    self.end
                } else {
                    let is = self.crossings(x);
                    let Some(&z) = is.first() else { return Err("x too large in straight dive".into()) };
                    P::new(z, x)
                };
                out.push(if fast { Out::Rapid(to) } else { Out::Feed(to) });
                *at = to;
                Ok(false)
            }
            Some((c, ccw)) => {
                if (*at - self.end).abs() < TOL || at.z - self.end.z <= TOL {
                    *at = self.end;
                    return Ok(false);
                }
                let mut is = self.crossings(x);
                if is.is_empty() {
                    is = self.crossings(x - TOL);
                }
                if ccw {
                    if at.z - TOL > c.z {
                        return Ok(true);
                    }
                    let to = match is.last() {
                        Some(&z) if z <= c.z => P::new(z, x),
                        _ => self.end,
                    };
                    out.push(Out::Arc(to, c, true));
                    *at = to;
                } else {
                    if at.z <= c.z {
                        return Ok(true);
                    }
                    match is.first() {
                        None => {
                            out.push(Out::Arc(self.end, c, false));
                            *at = self.end;
                        }
                        // Only the far side is met: the next layer is lower.
                        Some(&z) if z < c.z => {}
                        Some(&z) => {
                            let to = P::new(z, x);
                            out.push(Out::Arc(to, c, false));
                            *at = to;
                        }
                    }
                }
                Ok(false)
            }
        }
    }

    /// The piece moved `d` to its side (to the left of its direction for
    /// a line; away from the centre of a G3, towards that of a G2).
    fn offset(&mut self, d: f64) {
        match self.arc {
            None => {
                // i·d·(start − end) / |start − end|, in that order.
                let v = self.start - self.end;
                let v = P::new(-(d * v.x), d * v.z).over(v.abs());
                self.start = self.start + v;
                self.end = self.end + v;
            }
            Some((c, ccw)) => {
                let r = (self.start - c).abs();
                let k = (r + if ccw { d } else { -d }) / r;
                self.start = (self.start - c).scale(k) + c;
                self.end = (self.end - c).scale(k) + c;
            }
        }
    }

    /// Its length for a line; for an arc the smaller of its chord and radius.
    fn size(&self) -> f64 {
        match self.arc {
            None => (self.start - self.end).abs(),
            Some((c, _)) => (self.start - self.end).abs().min((self.start - c).abs()),
        }
    }

    /// Whether the piece keeps Z from increasing (and an arc X on one side
    /// of its centre) as the roughing needs.
    fn monotonic(&self) -> bool {
        match self.arc {
            Some((c, ccw)) if self.finish() == 0.0 => {
                let (entry, exit) = ((self.start - c).x, (self.end - c).x);
                let dz = self.end.z - self.start.z;
                if ccw {
                    entry >= -1e-3 && exit >= -1e-3 && dz <= -1e-3
                } else {
                    entry <= 1e-3 && exit <= 1e-3 && dz <= -1e-3
                }
            }
            Some(_) => true,
            None => self.end.z - self.start.z <= 1e-3,
        }
    }

    /// Every point through `f`, an arc's direction reversed where `mirror`.
    fn map(&mut self, f: impl Fn(P) -> P, mirror: bool) {
        self.start = f(self.start);
        self.end = f(self.end);
        if let Some((c, ccw)) = self.arc {
            self.arc = Some((f(c), ccw != mirror));
        }
    }

    /// Makes the end of `prev` and the start of `self` meet: where a line
    /// and a line cross, where a line and an arc meet nearest `self`'s
    /// start, where two circles meet.
    fn meet(&mut self, prev: &mut Seg) -> Result<(), Fault> {
        let point = match (prev.arc, self.arc) {
            (None, None) => {
                if self.start == self.end {
                    return Err("Cannot intersect a line of no length".into());
                }
                let rot = (self.start - self.end).conj().over((self.start - self.end).abs());
                let (ps, pe) = ((prev.start - self.end) * rot, (prev.end - self.end) * rot);
                if ps.x - pe.x == 0.0 {
                    return Err("Cannot intersect parallel lines".into());
                }
                let f = ps.x / (ps.x - pe.x);
                (ps + (pe - ps).scale(f)) / rot + self.end
            }
            (Some((c, _)), None) => {
                if (self.start - prev.end).abs() < TOL {
                    return Ok(());
                }
                let rot = (self.start - self.end).conj().over((self.start - self.end).abs());
                let (pe, pc) = ((prev.end - self.end) * rot, (c - self.end) * rot);
                self.nearer_on_line(pe, pc, rot, self.end)
            }
            (None, Some((c, _))) => {
                if (self.start - prev.end).abs() < TOL {
                    return Ok(());
                }
                let rot = (prev.start - prev.end).conj().over((prev.start - prev.end).abs());
                let (pe, pc) = ((self.end - prev.end) * rot, (c - prev.end) * rot);
                self.nearer_on_line(pe, pc, rot, prev.end)
            }
            (Some((pc, _)), Some((c, _))) => {
                let a = (self.start - c).abs();
                let b = (prev.start - pc).abs();
                let d = (c - pc).abs();
                if a == 0.0 || d == 0.0 {
                    return Err("Cannot intersect arcs about one centre".into());
                }
                let cos = (d * d + a * a - b * b) / 2.0 / a / d;
                let rot = P::new(cos, (1.0 - (cos * cos).min(1.0)).sqrt());
                (rot * (pc - c)).over(d).scale(a) + c
            }
        };
        prev.end = point;
        self.start = point;
        Ok(())
    }

    /// Of the two points where the circle through `pe` about `pc` (both
    /// turned by `rot` about `origin`) meets the line, the one nearer
    /// `self.start`.
    fn nearer_on_line(&self, pe: P, pc: P, rot: P, origin: P) -> P {
        let b = (pc - pe).norm() - pc.x * pc.x;
        let b = if b < 0.0 { 0.0 } else { b.sqrt() };
        let s1 = P::new(pc.z + b, 0.0) / rot + origin;
        let s2 = P::new(pc.z - b, 0.0) / rot + origin;
        if (self.start - s1).abs() < (self.start - s2).abs() {
            s1
        } else {
            s2
        }
    }
}

/// A corner piece made between `prev` and `next`: both moved its size to
/// the side where they meet, met, moved back; the corner from `prev`'s new
/// end to `next`'s new start, and the middle of the met ends (a fillet's
/// centre).
fn make_corner(finish: f64, prev: &mut Seg, next: &mut Seg) -> Result<(P, P, P), Fault> {
    let mut d = finish;
    let shifted = |d: f64| {
        let (mut p, mut n) = (*prev, *next);
        p.offset(d);
        n.offset(d);
        (p, n)
    };
    let (mut p, mut n) = shifted(d);
    if p.end.z - n.start.z > 1e-2 {
        d = -d;
        (p, n) = shifted(d);
    }
    if p.end.z - n.start.z > 1e-2 {
        return Err(format!("Corner finish failed at ({},{})", prev.end.z, prev.end.x));
    }
    n.meet(&mut p)?;
    let centre = (p.end + n.start).scale(0.5);
    p.offset(-d);
    n.offset(-d);
    prev.end = p.end;
    next.start = n.start;
    Ok((p.end, n.start, centre))
}
