//! The cutting of a profile: brought to its normal form, its corners
//! made, moved away by the stock to leave, then finished (`G70`) or
//! roughed layer by layer (`G71`, `G72`), every move mapped back.

use std::collections::VecDeque;

use super::{make_corner, Corner, Fault, Out, Seg, P, TOL};

/// A profile that has no piece to cut along (its pieces too short, or
/// taken by its corners).
const NO_PIECES: &str = "the profile has no piece left to cut along (pieces under 0.001, or taken by corners)";

/// A profile and how it was turned and mirrored into the normal form.
#[derive(Clone, Debug)]
pub(in crate::interp) struct Profile {
    segs: Vec<Seg>,
    /// Bit 4: turned a quarter; 2: X mirrored; 1: Z mirrored.
    flips: u8,
}

impl Profile {
    pub(in crate::interp) fn new(segs: Vec<Seg>) -> Profile {
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
        let (Some(first), Some(last)) = (self.segs.first(), self.segs.last()) else { return };
        let (first, last) = (first.end, last.end);
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
        let Some(first) = self.segs.first_mut() else { return Err(NO_PIECES.into()) };
        if first.end.z - first.start.z > 0.0 {
            first.start.z = first.end.z;
        }
        if self.segs.iter().all(Seg::monotonic) {
            Ok(())
        } else {
            Err("Not monotonic: the profile must run one way along Z for G71 (along X for G72), each arc on \
                 one side of its centre"
                .into())
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
        if self.segs.len() < 2 {
            return Err(NO_PIECES.into());
        }
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
    pub(in crate::interp) fn finish(mut self, x: f64, z: f64, d: f64, e: f64, passes: f64) -> Result<Vec<Out>, Fault> {
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
    pub(in crate::interp) fn rough(
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
            depth: 0,
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
    /// Pockets open, one inside the other.
    depth: u32,
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
                        self.depth += 1;
                        if self.depth > 10_000 {
                            return Err("the profile has more than 10,000 pockets".into());
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
            for (ip, seg) in segs.iter().enumerate().skip(p) {
                let is = seg.crossings(at.x);
                let (Some(&first), Some(&last)) = (is.first(), is.last()) else { continue };
                let to_z = if ip != p { first } else { last };
                let distance = (to_z - at.z).abs();
                if to_z - TOL > at.z {
                    continue;
                }
                if distance < TOL {
                    if p == ip {
                        continue;
                    } else if (at - seg.start).abs() < TOL {
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
