//! The texture paper's random "hand-carved" texture, baked into a toolpath.
//!
//! Along the cutting path, every `segment` mm of XY travel ends at a
//! *knot* with a random depth offset; between knots the offset runs
//! linearly, so each segment is one chisel stroke from the last depth to
//! the next, as the paper's macro cuts it. A long move is split at its
//! knots; consecutive short moves (a 3D finishing program's) are measured
//! together, so they are textured too. The offset is added to the
//! program's own Z there (or, with `base`, to a fixed depth, the paper's
//! −2.0 mm), and never goes below `max_depth`.
//!
//! Only straight cutting moves with XY travel are textured. Rapids, arcs,
//! Z-only moves and the rest pass as the control would run them under the
//! paper's macro: the axes their block names go where it says, the others
//! stay where the tool is (so an arc with no Z stays at the depth the last
//! stroke left, as on the paper's nameplate); an arc in the XZ or YZ plane
//! first goes back to the program's Z, since a change of Z would change
//! its radius. A run of textured moves
//! starts from wherever the tool is; its knots count from its first move.
//!
//! The offsets: `digits` is the paper's distribution as the authors meant
//! it (a digit 0–9: 0–4 shallower by 0, ¼ … 1 spread, 5–9 deeper by the
//! same, so ten digits fall on nine depths and the base is twice as
//! likely; the printed macro's `GT 5` made 5 a tenth depth); `uniform`,
//! `normal` (σ = spread / 2, clamped to the spread) and `smooth` (value
//! noise over XY, three segments to a wavelength, taken at every point of
//! the path where it is split: neighbouring passes, either way along, look
//! like related strokes, and so do successive ones). All are rounded to `quantum`. `step_range`
//! keeps successive knots apart by the authors' design rule (0.2–1.6 mm);
//! the first knot of a run, entered from wherever the tool was, is free.

use kezuri_geom::{Axes, Move, MoveKind, Plane, SplitMix64, Toolpath};

use crate::error::{Error, ErrorKind};

/// How the knots' offsets are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dist {
    /// The texture paper's: a digit 0–9 onto nine depths, the middle twice as likely.
    Digits,
    /// Every multiple of `quantum` within the spread equally likely.
    Uniform,
    /// Normal with σ = spread / 2, clamped to the spread.
    Normal,
    /// Smooth value noise over XY (wavelength: three segments).
    Smooth,
}

/// What [`bake`] does. Lengths in mm.
#[derive(Clone, Copy, Debug)]
pub struct TextureOptions {
    /// XY travel per knot (the texture paper: 20).
    pub segment: f64,
    /// A fixed depth the offsets are added to (the texture paper: −2.0); `None`:
    /// the program's own Z on the move.
    pub base: Option<f64>,
    /// Largest offset either way (the texture paper: 0.8).
    pub spread: f64,
    /// Offsets are multiples of this (the texture paper: 0.2); 0: not rounded.
    pub quantum: f64,
    /// How offsets are drawn.
    pub dist: Dist,
    /// Successive knots differ by at least and at most these.
    pub step_range: Option<[f64; 2]>,
    /// No point of the textured path goes below this Z.
    pub max_depth: Option<f64>,
    /// The same seed gives the same path.
    pub seed: u64,
}

impl Default for TextureOptions {
    /// The texture paper's numbers, relative to the program's Z.
    fn default() -> TextureOptions {
        TextureOptions {
            segment: 20.0,
            base: None,
            spread: 0.8,
            quantum: 0.2,
            dist: Dist::Digits,
            step_range: None,
            max_depth: None,
            seed: 0,
        }
    }
}

/// A textured toolpath and what was done.
#[derive(Clone, Debug)]
pub struct Textured {
    /// The toolpath.
    pub toolpath: Toolpath,
    /// Cutting moves textured (before splitting).
    pub moves: usize,
    /// Knots placed (each a new random depth).
    pub knots: usize,
}

/// Whether the texture applies to `m`: a straight cutting move with XY
/// travel.
pub fn is_textured(m: &Move) -> bool {
    m.kind == MoveKind::Feed && (m.end.x - m.start.x).hypot(m.end.y - m.start.y) > 1e-9
}

/// Checks the options.
pub fn check(o: &TextureOptions) -> Result<(), Error> {
    let bad = |m: String| Err(Error::new(ErrorKind::Option, m));
    if let Err(e) = kezuri_geom::limits::length(o.segment, "--segment") {
        return bad(e);
    }
    if !(o.spread.is_finite() && o.spread >= 0.0) {
        return bad(format!("--spread must be zero or a positive length, got {}", o.spread));
    }
    if !(o.quantum.is_finite() && o.quantum >= 0.0) {
        return bad(format!("--quantum must be zero or a positive length, got {}", o.quantum));
    }
    if o.quantum > o.spread && o.spread > 0.0 {
        return bad(format!(
            "--quantum {} is larger than --spread {}: every offset would round to 0",
            o.quantum, o.spread
        ));
    }
    if o.base.is_some_and(|b| !b.is_finite()) || o.max_depth.is_some_and(|z| !z.is_finite()) {
        return bad("--base and --max-depth must be finite heights".into());
    }
    if let Some([lo, hi]) = o.step_range {
        if !(lo.is_finite() && hi.is_finite() && 0.0 <= lo && lo <= hi) {
            return bad(format!("--step-range needs 0 ≤ MIN ≤ MAX, got {lo},{hi}"));
        }
        if o.dist == Dist::Smooth {
            return bad("--step-range needs a random distribution (digits, uniform, normal), not smooth noise".into());
        }
        // Every depth the distribution gives must have a next one within
        // the range (continuous offsets: the ends of the spread decide).
        let values = Depths::new(o).values();
        let reachable = |v: f64| values.iter().any(|w| (lo - 1e-9..=hi + 1e-9).contains(&(w - v).abs()));
        let stuck = match values.len() {
            0 => (lo > 2.0 * o.spread + 1e-9 || hi < 0.0).then_some(o.spread),
            _ => values.iter().copied().find(|&v| !reachable(v)),
        };
        if let Some(v) = stuck {
            return bad(format!(
                "--step-range {lo},{hi}: after a depth offset of {v:+} no offset the distribution gives (±{} in \
                 steps of {}) is within the range",
                o.spread, o.quantum
            ));
        }
    }
    Ok(())
}

/// Most knots a baked texture may have (a move each, some 200 bytes).
pub const MAX_KNOTS: f64 = 10e6;

/// The texture paper's random texture on `path` (see the module docs).
pub fn bake(path: &Toolpath, o: &TextureOptions) -> Result<Textured, Error> {
    check(o)?;
    // Weighed before the work: one move a knot.
    let travel: f64 =
        path.moves.iter().filter(|m| is_textured(m)).map(|m| (m.end.x - m.start.x).hypot(m.end.y - m.start.y)).sum();
    let knots = (travel / o.segment).ceil();
    if knots > MAX_KNOTS {
        return Err(Error::new(
            ErrorKind::Option,
            format!(
            "--segment {} mm: {travel:.0} mm of cutting travel would make {knots:.3e} knots, more than {} million: \
             give a longer segment",
            o.segment,
            MAX_KNOTS / 1e6
        ),
        ));
    }
    let mut depths = Depths::new(o);
    let mut out = Toolpath { moves: Vec::with_capacity(path.moves.len()), ..path.clone() };
    let (mut moves, mut knots) = (0, 0);
    // Where the tool is (the program's position but for a textured Z).
    let mut at: Option<Axes> = None;
    let mut run: Option<Run> = None;
    // Smooth noise is a function of the place: every point takes its own.
    let smooth = o.dist == Dist::Smooth;
    // Kept blocks stay in place; the moves one stands for (a tap) are not
    // textured.
    let inside = path.covered();
    let mut first = Vec::with_capacity(path.moves.len() + 1);
    for (i, m) in path.moves.iter().enumerate() {
        first.push(out.moves.len());
        let start = at.unwrap_or(m.start);
        if inside[i] || !is_textured(m) {
            run = None;
            let (lifted, path_z) = (start.z != m.start.z, m.start.z);
            let mut m = *m;
            m.start = start;
            if !m.named.contains(2) {
                m.end.z = start.z;
            }
            match &mut m.kind {
                MoveKind::Arc(arc) if arc.plane == Plane::Xy => arc.center[2] = start.z,
                MoveKind::Arc(_) if lifted => {
                    // An arc across Z would change its radius: back to the
                    // program's Z first, then the arc as written.
                    let back = Axes { z: path_z, ..start };
                    out.moves.push(Move { kind: MoveKind::Feed, start, end: back, ..m });
                    m.start = back;
                    m.end.z = if m.named.contains(2) { m.end.z } else { path_z };
                }
                MoveKind::Dwell(_) => m.end = start,
                _ => {}
            }
            at = Some(m.end);
            out.moves.push(m);
            continue;
        }
        moves += 1;
        let reference = |p: Axes| o.base.unwrap_or(p.z);
        let depth = |p: Axes, offset: f64| {
            let z = reference(p) + offset;
            o.max_depth.map_or(z, |floor| z.max(floor))
        };
        let run = run.get_or_insert_with(|| {
            let prev = start.z - reference(m.start);
            knots += 1;
            // The first stroke enters from wherever the tool is: the step
            // range is between depths, not from the entry.
            Run { travel: 0.0, prev, next: depths.draw([start.x, start.y]) }
        });
        let length = (m.end.x - m.start.x).hypot(m.end.y - m.start.y);
        let mut done = 0.0;
        let mut from = start;
        loop {
            let to_knot = o.segment - run.travel;
            if done + to_knot < length - 1e-9 {
                done += to_knot;
                let mut p = lerp(m.start, m.end, done / length);
                let offset = if smooth { depths.draw([p.x, p.y]) } else { run.next };
                p.z = depth(p, offset);
                out.moves.push(Move { start: from, end: p, ..*m });
                from = p;
                run.advance(&mut depths, [p.x, p.y]);
                knots += 1;
            } else {
                run.travel += length - done;
                let offset = if smooth {
                    depths.draw([m.end.x, m.end.y])
                } else {
                    run.prev + (run.next - run.prev) * (run.travel / o.segment).min(1.0)
                };
                let mut p = m.end;
                p.z = depth(p, offset);
                out.moves.push(Move { start: from, end: p, ..*m });
                if run.travel >= o.segment - 1e-9 {
                    run.advance(&mut depths, [p.x, p.y]);
                    knots += 1;
                }
                at = Some(p);
                break;
            }
        }
    }
    first.push(out.moves.len());
    out.kept = path.kept_in(&first);
    Ok(Textured { toolpath: out, moves, knots })
}

/// A run of textured moves: XY travel since the last knot, the offset
/// there and at the next knot.
#[derive(Clone, Copy, Debug)]
struct Run {
    travel: f64,
    prev: f64,
    next: f64,
}

impl Run {
    /// At a knot at `xy`: its offset is the last, a new one is drawn.
    fn advance(&mut self, depths: &mut Depths, xy: [f64; 2]) {
        self.prev = self.next;
        self.travel = 0.0;
        self.next = depths.next(self.prev, xy);
    }
}

/// `a + (b − a)·t` on every axis.
fn lerp(a: Axes, b: Axes, t: f64) -> Axes {
    let (a, b) = (a.to_array(), b.to_array());
    Axes::from_array(std::array::from_fn(|k| a[k] + (b[k] - a[k]) * t))
}

/// The knots' offsets, drawn as the options say.
#[derive(Clone, Debug)]
pub struct Depths {
    o: TextureOptions,
    rng: SplitMix64,
}

impl Depths {
    /// Offsets for `o`, seeded by `o.seed`.
    pub fn new(o: &TextureOptions) -> Depths {
        Depths { o: *o, rng: SplitMix64::new(o.seed) }
    }

    /// The offset of a knot at `xy` after one of `prev`, within the step
    /// range if there is one.
    pub fn next(&mut self, prev: f64, xy: [f64; 2]) -> f64 {
        let Some([lo, hi]) = self.o.step_range else { return self.draw(xy) };
        // `check` saw to it that some offset is within range of any `prev`
        // within the spread; a start outside the spread (a tool entering
        // high) takes the nearest.
        let mut nearest = self.draw(xy);
        for _ in 0..10_000 {
            let d = self.draw(xy);
            let step = (d - prev).abs();
            if (lo - 1e-9..=hi + 1e-9).contains(&step) {
                return d;
            }
            let miss = |s: f64| (lo - s).max(s - hi);
            if miss(step) < miss((nearest - prev).abs()) {
                nearest = d;
            }
        }
        nearest
    }

    /// One offset, before the step range.
    pub fn draw(&mut self, xy: [f64; 2]) -> f64 {
        let s = self.o.spread;
        let v = match self.o.dist {
            Dist::Digits => {
                let d = self.rng.below(10) as f64;
                if d < 5.0 {
                    d * s / 4.0
                } else {
                    -(d - 5.0) * s / 4.0
                }
            }
            Dist::Uniform => match self.steps() {
                Some(n) => (self.rng.below(2 * n + 1) as f64 - n as f64) * self.o.quantum,
                None => (2.0 * self.rng.next_f64() - 1.0) * s,
            },
            Dist::Normal => (0.5 * s * self.rng.normal()).clamp(-s, s),
            Dist::Smooth => s * value_noise(self.o.seed, xy[0] / self.wavelength(), xy[1] / self.wavelength()),
        };
        self.round(v)
    }

    /// Every offset the distribution gives, where they are finitely many
    /// (empty for continuous offsets).
    fn values(&self) -> Vec<f64> {
        match (self.o.dist, self.steps()) {
            (Dist::Digits, _) => {
                let mut v: Vec<f64> = (0..10)
                    .map(|d| self.round(if d < 5 { d as f64 } else { -(d as f64 - 5.0) } * self.o.spread / 4.0))
                    .collect();
                v.sort_by(f64::total_cmp);
                v.dedup();
                v
            }
            (_, Some(n)) => (0..=2 * n).map(|k| (k as f64 - n as f64) * self.o.quantum).collect(),
            (_, None) => Vec::new(),
        }
    }

    /// The wavelength of the smooth noise: three segments, so that
    /// successive strokes are related too.
    fn wavelength(&self) -> f64 {
        3.0 * self.o.segment
    }

    /// Whole quanta within the spread.
    fn steps(&self) -> Option<u64> {
        (self.o.quantum > 0.0).then(|| (self.o.spread / self.o.quantum + 1e-9).floor() as u64)
    }

    /// `v` to a whole number of quanta, within the spread.
    fn round(&self, v: f64) -> f64 {
        match self.steps() {
            Some(n) => {
                let k = (v / self.o.quantum).round().clamp(-(n as f64), n as f64);
                k * self.o.quantum
            }
            None => v,
        }
    }
}

/// Smooth noise in `[−1, 1]` over the plane: random values on the integer
/// lattice, blended with a smoothstep.
fn value_noise(seed: u64, x: f64, y: f64) -> f64 {
    let lattice = |i: f64, j: f64| {
        let key = (i as i64 as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
            ^ (j as i64 as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
        2.0 * SplitMix64::new(seed ^ key).next_f64() - 1.0
    };
    let (i, j) = (x.floor(), y.floor());
    let smooth = |t: f64| t * t * (3.0 - 2.0 * t);
    let (u, v) = (smooth(x - i), smooth(y - j));
    let bottom = lattice(i, j) + (lattice(i + 1.0, j) - lattice(i, j)) * u;
    let top = lattice(i, j + 1.0) + (lattice(i + 1.0, j + 1.0) - lattice(i, j + 1.0)) * u;
    bottom + (top - bottom) * v
}
