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

use std::collections::VecDeque;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// How near two numbers must be to count as equal (program units).
const TOL: f64 = 1e-6;

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
impl Div for P {
    type Output = P;
    fn div(self, o: P) -> P {
        self * o.conj().scale(1.0 / o.norm())
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
                let v = (self.start - self.end).i().scale(d / (self.start - self.end).abs());
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
                let rot = (self.start - self.end).conj().scale(1.0 / (self.start - self.end).abs());
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
                let rot = (self.start - self.end).conj().scale(1.0 / (self.start - self.end).abs());
                let (pe, pc) = ((prev.end - self.end) * rot, (c - self.end) * rot);
                self.nearer_on_line(pe, pc, rot, self.end)
            }
            (None, Some((c, _))) => {
                if (self.start - prev.end).abs() < TOL {
                    return Ok(());
                }
                let rot = (prev.start - prev.end).conj().scale(1.0 / (prev.start - prev.end).abs());
                let (pe, pc) = ((self.end - prev.end) * rot, (c - prev.end) * rot);
                self.nearer_on_line(pe, pc, rot, prev.end)
            }
            (Some((pc, _)), Some((c, _))) => {
                let a = (self.start - c).abs();
                let b = (prev.start - pc).abs();
                let d = (c - pc).abs();
                let cos = (d * d + a * a - b * b) / 2.0 / a / d;
                let rot = P::new(cos, (1.0 - (cos * cos).min(1.0)).sqrt());
                (rot * (pc - c)).scale(a / d) + c
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

/// A profile and how it was turned and mirrored into the normal form.
#[derive(Clone, Debug)]
pub(super) struct Profile {
    pub segs: Vec<Seg>,
    /// Bit 4: turned a quarter; 2: X mirrored; 1: Z mirrored.
    flips: u8,
}

impl Profile {
    pub(super) fn new(segs: Vec<Seg>) -> Profile {
        Profile { segs, flips: 0 }
    }

    fn turn(&mut self) {
        for s in &mut self.segs {
            s.map(|p| -p.i(), false);
        }
        self.flips ^= 4;
    }

    /// Mirrors the profile so that X and Z decrease from its first
    /// piece's end to its last's.
    fn normalise(&mut self) {
        let (first, last) = (self.segs[0].end, self.segs[self.segs.len() - 1].end);
        if first.x - last.x > 0.0 {
            for s in &mut self.segs {
                s.map(P::conj, true);
            }
            self.flips ^= 2;
        }
        if first.z - last.z < 0.0 {
            for s in &mut self.segs {
                s.map(|p| -p.conj(), true);
            }
            self.flips ^= 1;
        }
    }

    /// A point of the normal form back in the program's coordinates, and
    /// whether an arc's direction reverses.
    fn back(&self, p: P) -> (P, bool) {
        let i = P::new(0.0, 1.0);
        match self.flips {
            1 => (-p.conj(), true),
            2 => (p.conj(), true),
            3 => (-p, false),
            4 => (i * p, false),
            5 => ((i * p).conj(), true),
            6 => (-(i * p).conj(), true),
            7 => (-(i * p), false),
            _ => (p, false),
        }
    }

    /// The moves planned in the normal form, back in the program's.
    fn emit(&self, planned: Vec<Out>, out: &mut Vec<Out>) {
        for m in planned {
            out.push(match m {
                Out::Rapid(p) => Out::Rapid(self.back(p).0),
                Out::Feed(p) => Out::Feed(self.back(p).0),
                Out::Arc(p, c, ccw) => {
                    let (p, mirror) = self.back(p);
                    Out::Arc(p, self.back(c).0, ccw != mirror)
                }
            });
        }
    }

    fn check_monotonic(&mut self) -> Result<(), Fault> {
        if self.segs[0].end.z - self.segs[0].start.z > 0.0 {
            self.segs[0].start.z = self.segs[0].end.z;
        }
        if self.segs.iter().all(Seg::monotonic) {
            Ok(())
        } else {
            Err("Not monotonic".into())
        }
    }

    /// Makes the fillets and chamfers; drops pieces of no size.
    fn make_corners(&mut self) -> Result<(), Fault> {
        for h in 1..self.segs.len().saturating_sub(1) {
            let finish = self.segs[h].finish();
            if finish == 0.0 {
                continue;
            }
            let (mut prev, mut next) = (self.segs[h - 1], self.segs[h + 1]);
            let (start, end, centre) = make_corner(finish, &mut prev, &mut next)?;
            self.segs[h - 1] = prev;
            self.segs[h + 1] = next;
            let seg = &mut self.segs[h];
            seg.start = start;
            seg.end = end;
            if let Some(Corner::Fillet(_)) = seg.corner {
                let ccw = (start - centre).x > 0.0 || (end - centre).x > 0.0;
                seg.arc = Some((centre, ccw));
                seg.corner = None;
            }
        }
        self.segs.retain(|s| s.size() >= 1e-3);
        Ok(())
    }

    /// The profile moved `distance` away from it on the side of the cycle's
    /// start, in steps no larger than half the smallest piece; pieces that
    /// part are joined by arcs, those that vanish or turn back dropped.
    fn add_distance(&mut self, distance: f64) -> Result<(), Fault> {
        let first = self.segs.remove(0);
        let last = self.segs[self.segs.len() - 1];
        let (v1, v2) = (first.end - first.start, last.start - first.start);
        let distance = if (v1 / v2).x < 0.0 { -distance } else { distance };
        let mut done = 0.0;
        let mut steps = 0;
        while done != distance {
            steps += 1;
            if steps > 100_000 || self.segs.is_empty() {
                return Err("the profile cannot be moved by D (its pieces vanish)".into());
            }
            let mut step = self.segs.iter().map(|s| s.size() / 2.0).fold(1e9, f64::min);
            step = step.min((distance - done).abs());
            if distance < 0.0 {
                step = -step;
            }
            for s in &mut self.segs {
                s.offset(step);
            }
            self.segs.retain(|s| s.size() >= 1e-3);
            let mut k = 0;
            while k + 1 < self.segs.len() {
                let (p, n) = (self.segs[k], self.segs[k + 1]);
                if p.end.z - n.start.z > 1e-2 {
                    let (mut s, mut e) = (p, n);
                    s.offset(-step);
                    e.offset(-step);
                    let centre = (s.end + e.start).scale(0.5);
                    self.segs.insert(k + 1, Seg::arc(distance > 0.0, p.end, centre, n.start));
                    k += 1;
                }
                k += 1;
            }
            let mut k = 0;
            while k + 1 < self.segs.len() {
                if !self.segs[k].monotonic() {
                    if k == 0 {
                        return Err("Not monotonic".into());
                    }
                    let drop = if self.segs[k].size() < self.segs[k - 1].size() { k } else { k - 1 };
                    self.segs.remove(drop);
                    k = 0;
                    if self.segs.len() < 2 {
                        break;
                    }
                }
                if self.segs[k].size() < 1e-3 {
                    self.segs.remove(k);
                    k = 1;
                    continue;
                }
                let (head, tail) = self.segs.split_at_mut(k + 1);
                tail[0].meet(&mut head[k])?;
                k += 1;
            }
            done += step;
        }
        for k in 0..self.segs.len().saturating_sub(1) {
            let mid = (self.segs[k].end + self.segs[k + 1].start).scale(0.5);
            self.segs[k].end = mid;
            self.segs[k + 1].start = mid;
        }
        let Some(start) = self.segs.first().map(|s| s.start) else {
            return Err("the profile cannot be moved by D (its pieces vanish)".into());
        };
        let mut first = first;
        first.end = start;
        self.segs.insert(0, first);
        Ok(())
    }

    /// `G70`: from (x, z) the profile `passes` times, each at
    /// (pass − 1)(D − E)/P + E from it, the last at E.
    pub(super) fn finish(mut self, x: f64, z: f64, d: f64, e: f64, passes: f64) -> Result<Vec<Out>, Fault> {
        self.segs[0].start = P::new(z, x);
        let mut trial = self.clone();
        trial.segs.remove(0);
        trial.normalise();
        if !trial.segs.iter().all(Seg::monotonic) {
            trial.turn();
            trial.normalise();
        }
        trial.check_monotonic()?;
        if trial.flips & 4 != 0 {
            self.turn();
        }
        self.normalise();
        self.make_corners()?;
        self.check_monotonic()?;
        let mut out = Vec::new();
        let mut pass = passes as i64;
        while pass > 0 {
            let distance = (pass as f64 - 1.0) * (d - e) / passes + e;
            let mut path = self.clone();
            path.add_distance(distance)?;
            let mut planned = vec![Out::Rapid(path.segs[0].start), Out::Rapid(path.segs[0].end)];
            for s in &path.segs[1..] {
                s.draw_to(s.end, &mut planned);
            }
            self.emit(planned, &mut out);
            pass -= 1;
        }
        Ok(out)
    }

    /// `G71` (`turned`: `G72`) and their `.1` and `.2` (`kind`): roughing
    /// from (x, z) down to the profile moved D away and by (W, U), layers
    /// I apart, each left by R.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn rough(
        mut self,
        turned: bool,
        kind: u8,
        (x, z): (f64, f64),
        (u, w): (f64, f64),
        d: f64,
        i: f64,
        r: f64,
    ) -> Result<Vec<Out>, Fault> {
        self.segs[0].start = P::new(z, x);
        if turned {
            self.turn();
        }
        self.normalise();
        self.make_corners()?;
        self.check_monotonic()?;
        self.add_distance(d)?;
        let shift = P::new(w, u);
        for s in &mut self.segs {
            s.map(|p| p + shift, false);
        }
        let start = self.segs[0].start;
        let last = self.segs[self.segs.len() - 1].end;
        if last.x < start.x {
            self.segs.push(Seg::line(last, P::new(last.z, start.x)));
        }
        let mut rough = Rough {
            segs: &self.segs,
            layer: i.max(2.0 * TOL),
            escape: P::new(r, r),
            starts: VecDeque::from([start]),
            out: vec![Out::Rapid(start)],
            steps: 0,
        };
        rough.pocket(kind, start, 0)?;
        let planned = std::mem::take(&mut rough.out);
        let mut out = Vec::new();
        self.emit(planned, &mut out);
        Ok(out)
    }
}

/// The roughing's plan in the normal form.
struct Rough<'a> {
    segs: &'a [Seg],
    layer: f64,
    escape: P,
    /// Where the pockets cut so far began.
    starts: VecDeque<P>,
    out: Vec<Out>,
    /// Layers and pieces gone through: a bound on a profile the cutting
    /// never gets down.
    steps: u64,
}

impl Rough<'_> {
    /// Cuts from `at` on piece `p`, layer by layer, then along the profile
    /// to the next pocket, which it cuts the same way.
    fn pocket(&mut self, mut kind: u8, mut at: P, mut p: usize) -> Result<(), Fault> {
        let segs = self.segs;
        let mut x = self.starts.back().map_or(at.x, |s| s.x);
        if kind == 2 {
            while p < segs.len() {
                if segs[p].dive(&mut at, -1e9, &mut self.out, p == 0)? {
                    break;
                }
                p += 1;
            }
            kind = 3;
        }
        while p < segs.len() {
            self.steps += 1;
            if self.steps > 1_000_000 {
                return Err("the roughing does not get down the profile (LinuxCNC 2.9 loops here)".into());
            }
            while x - TOL > at.x {
                x -= self.layer;
            }
            if segs[p].dive(&mut at, x, &mut self.out, p == 0)? {
                if kind == 1 {
                    for s in &segs[p..] {
                        s.climb_only(&mut at, &mut self.out);
                    }
                    return Ok(());
                }
                while p < segs.len() {
                    if segs[p].climb(&mut at, &mut self.out)? {
                        if kind == 3 {
                            if self.starts.len() > 1 && at.x > self.starts.back().map_or(at.x, |s| s.x) {
                                self.starts.pop_back();
                            }
                            if self.starts.len() == 1 {
                                self.starts.push_back(at);
                            }
                        }
                        return self.pocket(kind, at, p);
                    }
                    p += 1;
                }
                return Ok(());
            }
            if (at.x - x).abs() > TOL {
                p += 1;
                continue;
            }
            for ip in p..segs.len() {
                let is = segs[ip].crossings(at.x);
                let (Some(&first), Some(&last)) = (is.first(), is.last()) else { continue };
                let to_z = if ip != p { first } else { last };
                let distance = (to_z - at.z).abs();
                if to_z - TOL > at.z {
                    continue;
                }
                if distance < TOL {
                    if p == ip {
                        continue;
                    } else if (at - segs[ip].start).abs() < TOL {
                        p = ip;
                        break;
                    }
                    x -= self.layer;
                    break;
                }
                // A layer: feed to the profile, away by R diagonally, back
                // over the layer, down to where it began.
                let mut to = P::new(to_z, at.x);
                self.out.push(Out::Feed(to));
                let away = self.escape.scale((distance / 2.0 / self.escape.z).min(1.0));
                to = to + away;
                self.out.push(Out::Rapid(to));
                self.out.push(Out::Rapid(at - away.conj()));
                self.out.push(if p == 0 { Out::Rapid(at) } else { Out::Feed(at) });
                x -= self.layer;
                break;
            }
        }
        Ok(())
    }
}
