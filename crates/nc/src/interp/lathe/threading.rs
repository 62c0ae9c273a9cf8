//! `G76`, the multiple threading cycle (`G78` in G code system C). Fanuc's
//! two-block form (FANUC Series 0i-TF Plus Operator's Manual (B-64604EN),
//! lathe system, "Multiple repetitive cycle", "Multiple threading cycle
//! (G76)"):
//!
//! ```text
//! G76 P(m)(r)(a) Q(Δdmin) R(d);
//! G76 X(U) Z(W) R(i) P(k) Q(Δd) F(L);
//! ```
//!
//! m the finishing passes (two digits), r the chamfer at the thread's end
//! in tenths of the lead (two digits), a the tool's angle (80, 60, 55, 30,
//! 29 or 0); Δdmin the least depth of a cut, d the finishing allowance; X Z
//! the end of the thread at its root, i the taper (radius at the start less
//! that at the end), k the thread's height and Δd the first cut's depth
//! (Δdmin, k and Δd radius, in least increments without a decimal point), L
//! the lead. The cut n goes Δd·√n deep (each cut of the same area), no
//! deeper than k − d and at least Δdmin deeper than the last; then the
//! finishing cut at k, m times. One edge cuts: each cut starts along the
//! flank of angle a/2, the last at the start point. Haas's one-block form
//! (Haas Lathe Operator's Manual, G-codes, "G76 Threading Cycle, Multiple
//! Pass") is `G76 X(U) Z(W) K(height) D(first depth) F(lead) I(taper)
//! A(angle) P(method)`.

use super::super::modal::g_name;
use super::super::words::Words;
use super::super::State;
use super::single::{Refusal, Step};
use crate::source::{Diagnostic, Span};

/// Haas's least depth of a cut: Setting 99 (Thread Minimum Cut), which
/// kezuri does not read from the machine; taken at 0.001 inch.
const HAAS_LEAST_CUT: f64 = 0.0254;

/// What G76's first block sets (on the control, parameters 5140 to 5143
/// and 5130), kept until the next.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(in super::super) struct ThreadSettings {
    /// m: the finishing cuts.
    pub(super) finishing: u32,
    /// r: the chamfer at the thread's end, in tenths of the lead.
    pub(super) chamfer: u32,
    /// a: the tool's angle, degrees.
    pub(super) angle: u32,
    /// Δdmin: the least depth a cut adds, mm.
    pub(super) least: f64,
    /// d: the finishing allowance, mm.
    pub(super) allowance: f64,
}

/// What kezuri takes where a program gives no G76 first block: one
/// finishing cut, no chamfer, a 60° tool, no least cut, no allowance.
const THREAD_DEFAULTS: ThreadSettings =
    ThreadSettings { finishing: 1, chamfer: 0, angle: 60, least: 0.0, allowance: 0.0 };

/// Most cuts one G76 makes.
pub(crate) const MOST_CUTS: usize = 10_000;

/// The tool angles Fanuc's G76 takes (its P word's last two digits).
pub(crate) const FANUC_ANGLES: [u32; 6] = [80, 60, 55, 30, 29, 0];

/// How the depth of each roughing cut grows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Depths {
    /// The cut n at first·√n: each cut removes the same area (Fanuc;
    /// Haas P1, P2).
    SameArea,
    /// The cut n at n·first (Haas P3, P4).
    SameDepth,
}

/// The depths (mm, from the thread's crest) of the cuts of a thread of
/// `height`: roughing cuts from `first` as `rule` grows them, each at
/// least `least` deeper than the one before, to `height − allowance`;
/// then `finishing` cuts at `height` (with no allowance, the last roughing
/// cut is at `height` and the finishing cuts repeat it).
pub(crate) fn depths(
    height: f64,
    first: f64,
    least: f64,
    allowance: f64,
    finishing: u32,
    rule: Depths,
) -> Result<Vec<f64>, Refusal> {
    if [height, first, least, allowance].iter().any(|v| !v.is_finite()) {
        return Err(Refusal { letter: None, message: "a figure of the thread is not a number".into() });
    }
    if height <= 0.0 {
        let h = crate::number::number(height, 6);
        return Err(Refusal::at(
            b'P',
            format!("the thread's height is {h} mm: there is no thread to cut; give it greater than 0"),
        ));
    }
    if first <= 0.0 {
        let f = crate::number::number(first, 6);
        return Err(Refusal::at(
            b'Q',
            format!("the first cut's depth is {f} mm: the cycle would never reach the thread's root; give it greater than 0"),
        ));
    }
    if allowance < 0.0 || allowance >= height {
        return Err(Refusal::at(
            b'R',
            format!("the finishing allowance {allowance} mm is not between 0 and the thread's height ({height} mm)"),
        ));
    }
    let rough = height - allowance;
    let mut cuts = Vec::new();
    let mut last = 0.0_f64;
    for n in 1.. {
        let mut d = match rule {
            Depths::SameArea => first * f64::from(n).sqrt(),
            Depths::SameDepth => first * f64::from(n),
        };
        if n > 1 && d - last < least {
            d = last + least;
        }
        if d >= rough - 1e-9 {
            cuts.push(rough);
            break;
        }
        cuts.push(d);
        last = d;
        if cuts.len() > MOST_CUTS {
            return Err(Refusal::at(
                b'Q',
                format!(
                    "more than {MOST_CUTS} cuts reach the thread's height {height} mm from a first cut of {first} mm: \
                     check the words' least increments"
                ),
            ));
        }
    }
    cuts.extend(std::iter::repeat_n(height, finishing as usize));
    Ok(cuts)
}

/// A thread's figures, mm (X a radius).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ThreadCut {
    /// The cycle's start point A (x, z): outside the thread.
    pub(crate) start: (f64, f64),
    /// The thread's end at its root (X, Z).
    pub(crate) end: (f64, f64),
    /// The radius at the thread's start less that at its end.
    pub(crate) taper: f64,
    /// The thread's height.
    pub(crate) height: f64,
    /// The tool's angle, degrees: the cuts start along its half (0: each
    /// cut straight in).
    pub(crate) angle: f64,
    /// The chamfer at the thread's end: the last `chamfer` of Z pulls out
    /// at 45°.
    pub(crate) chamfer: f64,
}

/// The moves of the cut at `depth` (from the crest): rapid along Z to the
/// cut's flank position, rapid in X to the depth, the threaded cut (the
/// chamfer pulling out at its end), rapid out in X to the start's, rapid
/// back along Z to the start point.
pub(crate) fn cut(t: &ThreadCut, depth: f64) -> Vec<Step> {
    let ((x0, z0), (x, z)) = (t.start, t.end);
    let out = if x0 >= x { 1.0 } else { -1.0 };
    let along = if z >= z0 { 1.0 } else { -1.0 };
    let above = t.height - depth;
    // The shallower the cut, the further back along the flank.
    let shift = -along * above * (t.angle.to_radians() / 2.0).tan();
    let (xs, zs) = (x + t.taper + out * above, z0 + shift);
    let (xe, ze) = (x + out * above, z + shift);
    let mut steps = Vec::with_capacity(6);
    if shift != 0.0 {
        steps.push(Step::rapid(x0, zs));
    }
    steps.push(Step::rapid(xs, zs));
    let length = (ze - zs).abs();
    if t.chamfer > 0.0 && length > 0.0 {
        let c = t.chamfer.min(length);
        let zc = ze - along * c;
        let xc = xe + t.taper * c / length;
        steps.push(Step::thread(xc, zc));
        steps.push(Step::thread(xe + out * c, ze));
    } else {
        steps.push(Step::thread(xe, ze));
    }
    steps.push(Step::rapid(x0, ze));
    steps.push(Step::rapid(x0, z0));
    steps
}

impl State {
    /// `G76` (`G78` in system C): Fanuc's first block `G76 P(m)(r)(a)
    /// Q(Δdmin) R(d);` sets the cycle's figures, the second (with the end
    /// point) cuts the thread; Haas's one block `G76 X(U) Z(W) K D F I A
    /// P`. Returns whether the tool moved.
    pub(in super::super) fn threading_block(&mut self, w: &Words, gspan: Span, line: u32) -> Result<bool, Diagnostic> {
        let name = g_name(self.lathe_cycle_number(76) * 10);
        let haas = self.settings.dialect == crate::Dialect::HaasLathe;
        let axes = w.has(b'X') || w.has(b'Z') || w.has(b'U') || w.has(b'W');
        if !axes && !haas {
            let mut t = self.cycles.thread.unwrap_or(THREAD_DEFAULTS);
            if w.has(b'P') {
                let (m, r, a) = self.thread_p_word(w, &name)?;
                (t.finishing, t.chamfer, t.angle) = (m, r, a);
            }
            if let Some(least) = self.count_word(w, b'Q', &name) {
                t.least = least;
            }
            if let Some(d) = w.get(b'R') {
                if d < 0.0 {
                    return Err(Diagnostic::error(
                        w.span(b'R'),
                        format!("{name} R{d}: the finishing allowance must not be negative"),
                    ));
                }
                t.allowance = self.mm(d);
            }
            self.cycles.thread = Some(t);
            return Ok(false);
        }
        if !axes {
            return Err(Diagnostic::error(gspan, format!("{name} needs the thread's end: X(U) and/or Z(W)")));
        }
        let mut e = *w;
        for l in *b"PQRIKDA" {
            e = e.without(l);
        }
        self.lathe_axes(&mut e)?;
        let end = self.target(&e);
        let lead = self.thread_lead(w, gspan)?;
        let (height_letter, first_letter, taper_letter) = if haas { (b'K', b'D', b'I') } else { (b'P', b'Q', b'R') };
        let what = |l: u8, x: &str| format!("{name} needs {}, {x}", l as char);
        let height = if haas { w.get(b'K').map(|k| self.mm(k)) } else { self.count_word(w, b'P', &name) };
        let Some(height) = height else {
            let form = if haas {
                "the thread's height (radius)"
            } else {
                "the thread's height (radius, least increments: P1300 is 1.3 mm)"
            };
            return Err(Diagnostic::error(gspan, what(height_letter, form)));
        };
        let first = if haas { w.get(b'D').map(|d| self.mm(d)) } else { self.count_word(w, b'Q', &name) };
        let Some(first) = first else {
            let form = if haas {
                "the first cut's depth (radius)"
            } else {
                "the first cut's depth (radius, least increments: Q450 is 0.45 mm)"
            };
            return Err(Diagnostic::error(gspan, what(first_letter, form)));
        };
        let taper = w.get(taper_letter).map_or(0.0, |i| self.mm(i));
        let (t, rule, flank) =
            if haas { self.haas_thread(w, &name)? } else { (self.fanuc_thread(gspan, &name), Depths::SameArea, true) };
        let blame = |r: Refusal| {
            let letter = match r.letter {
                Some(b'P') => Some(height_letter),
                Some(b'Q') => Some(first_letter),
                // The allowance is the first block's: the second's R is the taper.
                Some(b'R') => None,
                l => l,
            };
            Refusal { letter, ..r }
        };
        let cuts = depths(height, first, t.least, t.allowance, t.finishing, rule)
            .map_err(|r| self.refused(blame(r), w, gspan))?;
        let (x0, z0) = (self.tip.x, self.tip.z);
        // The start point's side of the root tells an outer thread from an
        // inner one; inside the crest, the first cuts begin beyond it.
        let at = if e.has(b'X') { e.span(b'X') } else { gspan };
        if x0 == end.x {
            return Err(Diagnostic::error(
                at,
                format!(
                    "{name}: the start point is at the thread's root X (U0): the cycle cannot tell an outer thread \
                     from an inner one; start the cycle outside the thread"
                ),
            ));
        }
        let crest = end.x + taper + (x0 - end.x).signum() * height;
        if (x0 - end.x).signum() != (x0 - crest).signum() && x0 != crest {
            self.warn(
                "thread-inside",
                at,
                format!(
                    "{name}: the start point (X radius {} mm) is inside the thread, whose crest is at radius {} mm where it \
                     starts: the first cuts begin beyond the start point",
                    crate::number::number(x0, 4),
                    crate::number::number(crest, 4)
                ),
            );
        }
        let cut_at = ThreadCut {
            start: (x0, z0),
            end: (end.x, end.z),
            taper,
            height,
            angle: if flank { f64::from(t.angle) } else { 0.0 },
            chamfer: f64::from(t.chamfer) / 10.0 * lead,
        };
        for d in cuts {
            self.run_steps(&cut(&cut_at, d), 0.0, lead, line);
        }
        Ok(true)
    }

    /// The figures of Fanuc's first block, or the defaults with a warning.
    fn fanuc_thread(&mut self, gspan: Span, name: &str) -> ThreadSettings {
        if let Some(t) = self.cycles.thread {
            return t;
        }
        self.warn(
            "thread-first-block",
            gspan,
            format!(
                "{name} without its first block ({name} P(m)(r)(a) Q(Δdmin) R(d);): the control takes its parameters \
                 5140 to 5143; kezuri takes one finishing cut, no chamfer, a 60° tool, no least cut and no allowance"
            ),
        );
        THREAD_DEFAULTS
    }

    /// Haas's A (the tool's angle, 0–120, no decimal point) and P (the
    /// way of cutting: P1 one edge, the same area each cut; P2 both edges
    /// (straight in), the same area; P3 one edge, the same depth; P4 both
    /// edges, the same depth).
    fn haas_thread(&mut self, w: &Words, name: &str) -> Result<(ThreadSettings, Depths, bool), Diagnostic> {
        let angle = match w.get(b'A') {
            None => 0,
            Some(a) if a.fract() == 0.0 && (0.0..=120.0).contains(&a) => a as u32,
            Some(a) => {
                return Err(Diagnostic::error(
                    w.span(b'A'),
                    format!(
                    "{name} A{a}: the tool's angle is a whole number of degrees from 0 to 120, without a decimal point"
                ),
                ))
            }
        };
        let method = match w.get(b'P') {
            None => 1,
            Some(p) if [1.0, 2.0, 3.0, 4.0].contains(&p) => p as u32,
            Some(p) => {
                return Err(Diagnostic::error(
                    w.span(b'P'),
                    format!(
                    "{name} P{p}: the way of cutting is P1 to P4 (one or both edges, the same area or depth each cut)"
                ),
                ))
            }
        };
        let rule = if method <= 2 { Depths::SameArea } else { Depths::SameDepth };
        let t = ThreadSettings { finishing: 0, chamfer: 0, angle, least: HAAS_LEAST_CUT, allowance: 0.0 };
        Ok((t, rule, method % 2 == 1))
    }

    /// G76's P(m)(r)(a): six digits, m the finishing cuts 01–99, r the
    /// chamfer 00–99 (tenths of the lead), a the tool's angle.
    fn thread_p_word(&mut self, w: &Words, name: &str) -> Result<(u32, u32, u32), Diagnostic> {
        let span = w.span(b'P');
        let v = w.get(b'P').unwrap_or(0.0);
        let literal = !w.decimal(b'P');
        let digits = span.end.saturating_sub(span.start).saturating_sub(1);
        let form = format!(
            "{name} P is six digits without a decimal point, P(m)(r)(a): m the finishing cuts 01–99, r the chamfer \
             in tenths of the lead 00–99, a the tool's angle 80, 60, 55, 30, 29 or 00 (P021060)"
        );
        if !literal || v.fract() != 0.0 || !(0.0..1_000_000.0).contains(&v) || digits != 6 {
            return Err(Diagnostic::error(
                span,
                format!("{form}; the control stops with an alarm at P{}", crate::number::number(v, 6)),
            ));
        }
        let p = v as u32;
        let (m, r, a) = (p / 10_000, p / 100 % 100, p % 100);
        if m == 0 {
            self.warn(
                "thread-no-finish",
                span,
                format!(
                    "{name} P{p:06}: m = 00 finishing cuts, where the manual gives 01 to 99; kezuri cuts none, so the \
                     thread ends at the roughing depth (its height less the finishing allowance)"
                ),
            );
        }
        if !FANUC_ANGLES.contains(&a) {
            return Err(Diagnostic::error(
                span,
                format!("{form}; P{p:06} asks for a tool angle of {a}°, which the control refuses"),
            ));
        }
        Ok((m, r, a))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_area_depths_with_the_least_cut() {
        // k 1.0, Δd 0.4, Δdmin 0.1, d 0.05, m 2: 0.4, 0.566 (√2·0.4), 0.693
        // (√3·0.4), 0.8 (√4·0.4); √5·0.4 = 0.894 is only 0.094 deeper: 0.9;
        // √6·0.4 = 0.980 is 0.08 deeper: 1.0, past k − d: 0.95; then m = 2
        // finishing cuts at k.
        let d = depths(1.0, 0.4, 0.1, 0.05, 2, Depths::SameArea).unwrap();
        let want = [0.4, 0.4 * 2f64.sqrt(), 0.4 * 3f64.sqrt(), 0.8, 0.9, 0.95, 1.0, 1.0];
        assert_eq!(d.len(), want.len());
        for (a, b) in d.iter().zip(want) {
            assert!((a - b).abs() < 1e-12, "{d:?}");
        }
        // Δdmin 0.15: 0.4, 0.566, then 0.693 is only 0.127 deeper: 0.716.
        let d = depths(1.0, 0.4, 0.15, 0.0, 1, Depths::SameArea).unwrap();
        assert!((d[2] - (0.4 * 2f64.sqrt() + 0.15)).abs() < 1e-12);
    }

    #[test]
    fn straight_in_cut() {
        let t = ThreadCut { start: (12.0, 5.0), end: (9.0, -20.0), taper: 0.0, height: 1.0, angle: 0.0, chamfer: 0.0 };
        let s = cut(&t, 0.5);
        assert_eq!(
            s,
            vec![Step::rapid(9.5, 5.0), Step::thread(9.5, -20.0), Step::rapid(12.0, -20.0), Step::rapid(12.0, 5.0)]
        );
    }

    #[test]
    fn flank_cut_with_chamfer() {
        // a 60°: a cut 0.6 above the root starts 0.6·tan 30° = 0.3464 back
        // (toward +Z, the thread runs to -Z); the last 1 mm pulls out at 45°.
        let t = ThreadCut { start: (12.0, 5.0), end: (9.0, -20.0), taper: 0.0, height: 1.0, angle: 60.0, chamfer: 1.0 };
        let b = 0.6 * 30f64.to_radians().tan();
        let want = [
            Step::rapid(12.0, 5.0 + b),
            Step::rapid(9.6, 5.0 + b),
            Step::thread(9.6, -19.0 + b),
            Step::thread(10.6, -20.0 + b),
            Step::rapid(12.0, -20.0 + b),
            Step::rapid(12.0, 5.0),
        ];
        let s = cut(&t, 0.4);
        assert_eq!(s.len(), want.len());
        for (a, w) in s.iter().zip(want) {
            assert!(a.kind == w.kind && (a.x - w.x).abs() < 1e-12 && (a.z - w.z).abs() < 1e-12, "{s:?}");
        }
    }
}
