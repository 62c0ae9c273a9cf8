//! A union of at most three intervals whose ends remember which constraint
//! made them: the part of one rake segment (or of one horizontal line of
//! the cross-section) inside the chip.

/// Most intervals a set holds: one body interval, split once by the body
/// one tooth behind and once by the previous pass.
const CAP: usize = 3;

/// Labels of interval ends (3 bits each).
pub(crate) mod label {
    /// The tool axis, `ρ = 0`.
    pub const AXIS: u8 = 1;
    /// This tooth's body (at `−w` for the cross-section).
    pub const BODY_LO: u8 = 2;
    /// This tooth's body, far end.
    pub const BODY_HI: u8 = 3;
    /// The body one tooth behind, near root.
    pub const BEHIND_LO: u8 = 4;
    /// The body one tooth behind, far root.
    pub const BEHIND_HI: u8 = 5;
    /// The previous pass, at `y₂ − w₂`.
    pub const PREV_LO: u8 = 6;
    /// The previous pass, at `y₂ + w₂`.
    pub const PREV_HI: u8 = 7;
    /// The stock plane (never both ends of one interval next to the body's).
    pub const PLANE: u8 = 0;
}

/// Intervals `[lo, hi]` in increasing order, each of positive length.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Set {
    n: usize,
    lo: [f64; CAP],
    hi: [f64; CAP],
    lab: [(u8, u8); CAP],
}

impl Set {
    /// `[lo, hi]`, or the empty set where `hi ≤ lo`.
    pub fn interval(lo: f64, hi: f64, llo: u8, lhi: u8) -> Set {
        let mut s = Set { n: 0, lo: [0.0; CAP], hi: [0.0; CAP], lab: [(0, 0); CAP] };
        if hi > lo {
            s.push(lo, hi, (llo, lhi));
        }
        s
    }

    fn push(&mut self, lo: f64, hi: f64, lab: (u8, u8)) {
        debug_assert!(self.n < CAP);
        self.lo[self.n] = lo;
        self.hi[self.n] = hi;
        self.lab[self.n] = lab;
        self.n += 1;
    }

    /// No interval left.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Empties the set.
    pub fn clear(&mut self) {
        self.n = 0;
    }

    /// Takes away the open interval `(p, q)`; ends it makes are labelled
    /// `lp` (at `p`) and `lq` (at `q`).
    pub fn remove(&mut self, p: f64, q: f64, lp: u8, lq: u8) {
        let old = *self;
        self.n = 0;
        for i in 0..old.n {
            let (l, h, (ll, lh)) = (old.lo[i], old.hi[i], old.lab[i]);
            if q <= l || p >= h {
                self.push(l, h, (ll, lh));
                continue;
            }
            if p > l {
                self.push(l, p, (ll, lp));
            }
            if q < h && self.n < CAP {
                self.push(q, h, (lq, lh));
            }
        }
    }

    /// Keeps what is at least `p`.
    pub fn keep_above(&mut self, p: f64, lp: u8) {
        let old = *self;
        self.n = 0;
        for i in 0..old.n {
            if old.hi[i] > p {
                if old.lo[i] >= p {
                    self.push(old.lo[i], old.hi[i], old.lab[i]);
                } else {
                    self.push(p, old.hi[i], (lp, old.lab[i].1));
                }
            }
        }
    }

    /// Keeps what is at most `q`.
    pub fn keep_below(&mut self, q: f64, lq: u8) {
        let old = *self;
        self.n = 0;
        for i in 0..old.n {
            if old.lo[i] < q {
                if old.hi[i] <= q {
                    self.push(old.lo[i], old.hi[i], old.lab[i]);
                } else {
                    self.push(old.lo[i], q, (old.lab[i].0, lq));
                }
            }
        }
    }

    /// The intervals.
    pub fn iter(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        (0..self.n).map(|i| (self.lo[i], self.hi[i]))
    }

    /// Which constraint makes each end, packed; 0 for the empty set.
    pub fn signature(&self) -> u64 {
        let mut s = 0u64;
        for i in 0..self.n {
            s = (s << 6) | (u64::from(self.lab[i].0) << 3) | u64::from(self.lab[i].1);
        }
        // The count keeps `PLANE`-only ends apart from the empty set.
        if self.n > 0 {
            s | ((self.n as u64) << 60)
        } else {
            0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn removing_and_clipping() {
        let mut s = Set::interval(0.0, 10.0, label::AXIS, label::BODY_HI);
        s.remove(-1.0, 2.0, label::BEHIND_LO, label::BEHIND_HI);
        s.remove(4.0, 5.0, label::PREV_LO, label::PREV_HI);
        assert_eq!(s.iter().collect::<Vec<_>>(), vec![(2.0, 4.0), (5.0, 10.0)]);
        s.keep_above(3.0, label::PLANE);
        assert_eq!(s.iter().collect::<Vec<_>>(), vec![(3.0, 4.0), (5.0, 10.0)]);
        s.keep_below(4.5, label::PLANE);
        assert_eq!(s.iter().collect::<Vec<_>>(), vec![(3.0, 4.0)]);
        assert_ne!(s.signature(), 0);
        s.remove(0.0, 11.0, label::PREV_LO, label::PREV_HI);
        assert!(s.is_empty());
        assert_eq!(s.signature(), 0);
    }
}
