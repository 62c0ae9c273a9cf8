//! The chip of one tooth on an inclined plane, and what the rake face cuts
//! of it at every rotation angle: area `A(θ)`, centroid `G`, its distance
//! `L_G` from the axis and the evaluation value `E_d = A·L_G` (a proxy for
//! the cutting torque), for every cutter shape. The model is that of Iwabe,
//! Kumaki and Hori's oval end mill study (contour passes on a plane inclined
//! at α about the feed direction X); `docs/engage.md` states every choice.
//!
//! # Frame
//! The tool axis is Z, the tip at the origin; X is the feed axis and the
//! plane rises in +Y. The spindle turns clockwise seen from above (M03).
//! Directions about the axis are measured clockwise from +Y: `u(ψ) =
//! (sin ψ, cos ψ)`.
//!
//! # The cutter, its edge and rake face
//! The body is the cutter's solid of revolution: radius
//! [`Cutter::body_radius`]`(z)` at height `z`. Each edge is a right-hand
//! helix of angle η on the cylinder of radius `R`, `dφ/dz = tan η / R`,
//! continued below the reference height `H` (the top of the profile, where
//! it meets the shank) and carried radially onto the profile. The rake face
//! is the radial segments from the axis to the edge at each height (zero
//! rake): at tool angle θ, the segment at height `z` points along
//! `u(θ + (H − z)·tan η / R)`. θ = 0 puts the edge's point at the
//! reference height on +Y; a right-hand helix turning clockwise leads with
//! its lower end.
//!
//! # The chip
//! This tooth's body, less the same body `S_z` behind along the feed (the
//! previous tooth), less everything the previous pass swept (the same body
//! `P_f` away along the slope, along its whole length), below the stock
//! plane (the finished plane, tangent to the tip's profile, offset `R_d`
//! along its normal). The rake face turns through it with the tool held
//! still. Along one rake segment each condition is an interval in ρ in
//! closed form (a disc: quadratic; the previous pass at this height, a
//! strip `|y − y₂| < w₂`: linear; the stock plane: linear), so the
//! segment's part in the chip is at most three intervals, over which the
//! true area of the helicoidal face, `√(1 + k²ρ²) dρ dz` with
//! `k = tan η / R`, and its first moments integrate in closed form. Over
//! height, Gauss–Kronrod quadrature between breakpoints found where an
//! interval begins, ends, or changes which constraint bounds it.
//!
//! # Example
//! ```
//! use kezuri_cam::engage::{sweep, Chip, Cut, Engagement, Step};
//! let e = Engagement {
//!     cutter: "oval:16,24".parse().unwrap(),
//!     flutes: 2,
//!     helix: 30f64.to_radians(),
//!     angle: 45f64.to_radians(),
//!     depth: 0.8,
//!     pick_feed: 0.8,
//!     feed_per_tooth: 0.16,
//!     step: Step::Up,
//!     cut: Cut::Down,
//! };
//! let chip = Chip::new(&e).unwrap();
//! let s = sweep(&chip, 360);
//! assert!(s.area_max > 0.05 && s.area_max < 0.5);
//! let (first, last) = s.engaged.unwrap();
//! assert!(last > first);
//! ```

mod error;
mod quad;
pub mod report;
mod section;
mod set;
mod volume;

use rayon::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

pub use crate::scallop::Step;

use crate::error::Error;
use crate::Cutter;
use quad::{integrate, Settings};

/// Climb or conventional milling, the spindle turning clockwise seen from
/// above (M03).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cut {
    /// Down-cut (climb): where it meets the chip the tooth moves against
    /// the tool's travel (with the work's motion relative to the tool),
    /// entering the chip at its thickest.
    Down,
    /// Up-cut (conventional): the tooth moves with the tool's travel where
    /// it meets the chip, entering it at zero thickness.
    Up,
}

/// One tooth's cut: the cutter, its flutes, the plane and the feeds.
/// Lengths mm, angles radians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Engagement {
    /// The cutter (its body of revolution; the edge is built on it).
    pub cutter: Cutter,
    /// Number of flutes (≥ 1). Each tooth cuts the same chip, the next
    /// one `2π / flutes` later; [`Chip::section`] is one tooth's.
    pub flutes: u32,
    /// Helix angle η of the right-hand edges, `[0, π/2)`.
    pub helix: f64,
    /// Inclination α of the plane about the feed direction X, `[0, π/2)`.
    pub angle: f64,
    /// Depth of cut `R_d`, square to the plane.
    pub depth: f64,
    /// Pick feed `P_f` between passes, measured along the slope.
    pub pick_feed: f64,
    /// Feed per tooth `S_z`, along X.
    pub feed_per_tooth: f64,
    /// Where the previous pass is: [`Step::Up`] — this pass is higher, the
    /// previous one `P_f` down the slope; [`Step::Down`] — the previous
    /// pass `P_f` up the slope.
    pub step: Step,
    /// Down- or up-cut; with the side of the axis the chip is on, it sets
    /// the feed direction (see [`Chip::feed_direction`]).
    pub cut: Cut,
}

/// What the rake face cuts at one rotation angle.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Section {
    /// Area `A` of the rake face inside the chip, mm² (the true area of the
    /// helicoidal face).
    pub area: f64,
    /// Centroid `G` of that area, mm, in the tool's frame (tip at the
    /// origin); zeros where the area is 0.
    pub centroid: [f64; 3],
    /// `L_G = √(G_x² + G_y²)`, the centroid's distance from the axis, mm.
    pub lg: f64,
    /// `E_d = A·L_G`, mm³.
    pub ed: f64,
}

/// The chip of one tooth, prepared: [`Chip::section`] at any angle.
#[derive(Clone, Debug)]
pub struct Chip {
    e: Engagement,
    cutter: Cutter,
    feed_per_tooth: f64,
    /// `tan η / R`: the rake face's turn per mm of height.
    twist: f64,
    /// The reference height `H` (top of the profile).
    reference: f64,
    /// X of the axis of the body one tooth behind.
    behind: f64,
    /// +1 or −1: the feed direction along X.
    feed: f64,
    /// The previous pass's tip, `(y₂, z₂)`.
    y2: f64,
    z2: f64,
    /// `tan α`.
    slope: f64,
    /// The stock plane: `z = slope·y + stock`.
    stock: f64,
    /// Heights between which the chip lies.
    zlo: f64,
    zhi: f64,
    /// Joints of the profiles and other known breakpoints in height.
    fixed: Vec<f64>,
    /// The removed cross-section sampled over height, for finding which
    /// heights a rake segment can meet the chip at.
    rows: Vec<Row>,
    /// `(sin, cos)` of the rake face's turn `k·(H − z)` at each row.
    turns: Vec<(f64, f64)>,
    /// How far cos or sin of ψ can bulge between two rows.
    bulge: f64,
    /// Sample cells per row.
    sub: usize,
    volume: f64,
    cross_section: f64,
    cross_section_y: f64,
    settings: Settings<5>,
}

/// Sections over one revolution.
#[derive(Clone, Debug, PartialEq)]
pub struct Sweep {
    /// The angles, radians: `steps` equal steps over a window
    /// `[θ₀, θ₀ + 2π)`, θ₀ a multiple of the step in `[−π, π)` chosen in
    /// the middle of the longest run of angles with no chip, so that the
    /// engaged range is not split by the window's ends.
    pub theta: Vec<f64>,
    /// The section at each angle.
    pub sections: Vec<Section>,
    /// The first and last angle of the window with a positive area (radians,
    /// `first ≤ last`, both in the window); `None` where no angle cuts.
    pub engaged: Option<(f64, f64)>,
    /// Largest area, mm².
    pub area_max: f64,
    /// Largest `E_d`, mm³.
    pub ed_max: f64,
}

/// The removed cross-section at one height: the body's radius and the
/// hull `[ya, yb]` of the cross-section's y-intervals (`ya > yb`: none).
#[derive(Clone, Copy, Debug)]
struct Row {
    z: f64,
    w: f64,
    ya: f64,
    yb: f64,
}

/// The smallest feed per tooth, mm: the quadrature's tolerance scales with
/// `S_z·R_d`, so its work grows without bound as `S_z` shrinks (1e-4 mm
/// takes seconds, 1e-5 minutes), and no cutter cuts a chip thinner than a
/// micrometre.
pub const MIN_FEED_PER_TOOTH: f64 = 1e-3;

/// Rows of the table of the cross-section over the chip's height.
const ROWS: usize = 256;

/// Cells of signature samples per row where a rake segment may meet the
/// chip.
const SUB: usize = 2;

/// Relative tolerance of the quadrature, per piece, on `|Kronrod − Gauss|`
/// against the area scale `S_z·R_d`.
const TOLERANCE: f64 = 1e-10;

/// Cells in which the signature is first sampled over the chip's height.
const CELLS: usize = 48;

impl Chip {
    /// Checks the engagement and prepares its chip.
    pub fn new(e: &Engagement) -> Result<Chip, Error> {
        let e = *e;
        let cutter = e.cutter;
        let radius = cutter.radius();
        if e.flutes == 0 {
            return Err(error::flutes());
        }
        if !(e.helix.is_finite() && (0.0..FRAC_PI_2).contains(&e.helix) && e.helix.tan().is_finite()) {
            return Err(error::helix(e.helix));
        }
        if !(e.angle.is_finite() && (0.0..FRAC_PI_2).contains(&e.angle) && e.angle.cos() > 0.0) {
            return Err(error::angle(e.angle));
        }
        if !(e.depth.is_finite() && e.depth > 0.0) {
            return Err(error::depth(e.depth));
        }
        if !(e.pick_feed.is_finite() && e.pick_feed > 0.0) {
            return Err(error::pick_feed(e.pick_feed));
        }
        let (sin, cos) = e.angle.sin_cos();
        if e.pick_feed * cos > 2.0 * radius * (1.0 + 1e-12) {
            return Err(error::pick_feed_too_wide(e.pick_feed, crate::scallop::widest_pick_feed(&cutter, e.angle)));
        }
        if !(e.feed_per_tooth.is_finite() && e.feed_per_tooth >= MIN_FEED_PER_TOOTH) {
            return Err(error::feed_per_tooth(e.feed_per_tooth));
        }
        if e.feed_per_tooth >= 2.0 * radius {
            return Err(error::feed_per_tooth_too_wide(e.feed_per_tooth, 2.0 * radius));
        }
        let slope = e.angle.tan();
        let contact = cutter.facet_radius(slope);
        let finished = cutter.height(contact) - slope * contact;
        let stock = finished + e.depth * (1.0 + slope * slope).sqrt();
        let side = match e.step {
            Step::Down => 1.0,
            Step::Up => -1.0,
        };
        let reference = cutter.height(radius);
        let mut chip = Chip {
            e,
            cutter,
            feed_per_tooth: e.feed_per_tooth,
            twist: e.helix.tan() / radius,
            reference,
            behind: 0.0,
            feed: 1.0,
            y2: side * e.pick_feed * cos,
            z2: side * e.pick_feed * sin,
            slope,
            stock,
            zlo: 0.0,
            zhi: 0.0,
            fixed: Vec::new(),
            rows: Vec::new(),
            turns: Vec::new(),
            bulge: 0.0,
            sub: SUB,
            volume: 0.0,
            cross_section: 0.0,
            cross_section_y: 0.0,
            settings: Settings { cells: CELLS, tol: [0.0; 5], eps: 0.0, max_depth: 48, roots: [f64::NAN; 3] },
        };
        let (zlo, zhi) = chip.height_range().ok_or_else(error::no_chip)?;
        let flutes = reference + 2.0 * radius;
        if zhi > flutes {
            return Err(error::reach(zhi, flutes));
        }
        chip.zlo = zlo;
        chip.zhi = zhi;
        let mut fixed = vec![chip.z2, reference, chip.z2 + reference];
        for r in [e.feed_per_tooth, 0.5 * e.feed_per_tooth] {
            if r < radius {
                fixed.push(cutter.height(r));
            }
        }
        chip.fixed = fixed;
        let eps = 1e-14 * (zhi - zlo).max(zhi.abs());
        let scale = e.feed_per_tooth * e.depth;
        let tol = TOLERANCE * scale;
        let slab = volume::Slab { chip: &chip };
        let roots = [0.0, chip.z2, f64::NAN];
        let settings =
            Settings { cells: CELLS, tol: [tol * e.feed_per_tooth, tol, tol * radius], eps, max_depth: 48, roots };
        let ([v, a, m], _) = integrate(&slab, zlo, zhi, &chip.fixed, &settings);
        if v.is_nan() || v <= 0.0 {
            return Err(error::no_chip());
        }
        chip.tabulate(ROWS, TOLERANCE, SUB);
        chip.volume = v;
        chip.cross_section = a;
        chip.cross_section_y = m / a;
        // The chip's side of the axis and the turning sense give the feed.
        let chip_side = if chip.cross_section_y >= 0.0 { 1.0 } else { -1.0 };
        // A tooth on the +Y side moves toward +X. Climbing, it meets the
        // stock against the tool's travel (the chip thickest where it
        // enters): the tool feeds toward −X for a chip on +Y.
        chip.feed = match e.cut {
            Cut::Down => -chip_side,
            Cut::Up => chip_side,
        };
        chip.behind = -chip.feed * e.feed_per_tooth;
        Ok(chip)
    }

    /// The table of rows, and the quadrature's settings: `tolerance`
    /// relative to `S_z·R_d`, `sub` sample cells per row.
    fn tabulate(&mut self, rows: usize, tolerance: f64, sub: usize) {
        let (zlo, zhi) = (self.zlo, self.zhi);
        let radius = self.cutter.radius();
        let tol = tolerance * self.feed_per_tooth * self.e.depth;
        self.settings = Settings {
            cells: CELLS,
            tol: [tol, tol * radius, tol * radius, tol * zhi, tol * radius],
            eps: 1e-12 * (zhi - zlo).max(zhi.abs()),
            max_depth: 48,
            roots: [0.0, self.z2, f64::NAN],
        };
        self.sub = sub;
        let slab = volume::Slab { chip: self };
        let table: Vec<Row> = (0..=rows)
            .map(|i| {
                let z = if i == rows { zhi } else { zlo + (zhi - zlo) * i as f64 / rows as f64 };
                let (set, w) = slab.line(z);
                let (mut ya, mut yb) = (f64::INFINITY, f64::NEG_INFINITY);
                for (lo, hi) in set.iter() {
                    ya = ya.min(lo);
                    yb = yb.max(hi);
                }
                Row { z, w, ya, yb }
            })
            .collect();
        self.turns = table.iter().map(|r| (self.twist * (self.reference - r.z)).sin_cos()).collect();
        self.rows = table;
        let arc = self.twist * (zhi - zlo) / rows as f64;
        self.bulge = arc * arc / 8.0 + 1e-12;
    }

    /// The same chip integrated far more finely (a thousandth of the
    /// tolerance, four times the rows and samples): for measuring the
    /// error of [`Chip::section`].
    #[doc(hidden)]
    pub fn refined(&self) -> Chip {
        let mut chip = self.clone();
        chip.tabulate(4 * ROWS, TOLERANCE / 1000.0, 4 * SUB);
        chip
    }

    /// Heights between which the removed cross-section lies (a cover of
    /// the chip): its ends found by bisection from a fine scan.
    fn height_range(&self) -> Option<(f64, f64)> {
        let top = self.stock + self.slope * self.cutter.radius();
        if top.is_nan() || top <= 0.0 {
            return None;
        }
        let slab = volume::Slab { chip: self };
        let full = |z: f64| !slab.line(z).0.is_empty();
        let n = 4096;
        let at = |i: usize| top * i as f64 / n as f64;
        let first = (0..=n).find(|&i| full(at(i)))?;
        let last = (0..=n).rev().find(|&i| full(at(i)))?;
        let edge = |mut empty: f64, mut inside: f64| {
            for _ in 0..200 {
                let m = 0.5 * (empty + inside);
                if m == empty || m == inside {
                    break;
                }
                if full(m) {
                    inside = m;
                } else {
                    empty = m;
                }
            }
            empty
        };
        let lo = if first == 0 { 0.0 } else { edge(at(first - 1), at(first)) };
        let hi = if last == n { top } else { edge(at(last + 1), at(last)) };
        Some((lo, hi))
    }

    /// The five integrals over the rake face at `theta`:
    /// `[A, ∫x dA, ∫y dA, ∫z dA, ∫∫ρ dρ dz]`.
    fn integrals(&self, theta: f64) -> [f64; 5] {
        let theta = theta.rem_euclid(TAU);
        let rake = section::Rake { chip: self, theta };
        let mut sum = [0.0; 5];
        let mut run: Option<(usize, usize)> = None;
        let touch = self.touch(theta);
        let mut flush = |from: usize, to: usize| {
            let mut settings = self.settings.clone();
            settings.cells = self.sub * (to - from);
            settings.roots[2] = touch;
            let (v, _) = integrate(&rake, self.rows[from].z, self.rows[to].z, &self.fixed, &settings);
            for (s, v) in sum.iter_mut().zip(v) {
                *s += v;
            }
        };
        for i in 0..self.rows.len() - 1 {
            if self.may_meet(theta, i) {
                run = Some(run.map_or((i, i + 1), |(a, _)| (a, i + 1)));
            } else if let Some((a, b)) = run.take() {
                flush(a, b);
            }
        }
        if let Some((a, b)) = run {
            flush(a, b);
        }
        sum
    }

    /// Near the tip, where the body behind does not cover the axis: the
    /// height at which the rake segment's line starts to meet the body
    /// behind, `w(z) = S_z |cos ψ(z)|`. The integrand goes like a square
    /// root from there even where the chip's intervals keep their shape.
    /// NaN where that is not in the chip's heights.
    fn touch(&self, theta: f64) -> f64 {
        let s = self.feed_per_tooth;
        if s >= self.cutter.radius() || self.zlo >= self.cutter.height(s) {
            return f64::NAN;
        }
        // ψ hardly turns over these few micrometres: a fixed point.
        let mut z = 0.0;
        for _ in 0..4 {
            let psi = theta + self.twist * (self.reference - z);
            z = self.cutter.height(s * psi.cos().abs());
        }
        z
    }

    /// Whether the rake segments at heights between rows `i` and `i + 1`
    /// may meet the chip: a point of the chip at height `z` is within `S_z`
    /// of the body's rim (outside the body behind), its y in the removed
    /// cross-section's y-range (taken over the neighbouring rows and
    /// widened by their change), and on the feed's side of the body behind
    /// (`f·sin ψ > −S_z/(2w)` where `w > S_z`).
    fn may_meet(&self, theta: f64, i: usize) -> bool {
        let rows = &self.rows;
        let near = &rows[i.saturating_sub(1)..(i + 3).min(rows.len())];
        let (mut ya, mut yb) = (f64::INFINITY, f64::NEG_INFINITY);
        for r in near {
            ya = ya.min(r.ya);
            yb = yb.max(r.yb);
        }
        if ya > yb {
            return false;
        }
        let pad =
            (rows[i + 1].ya - rows[i].ya).abs().max((rows[i + 1].yb - rows[i].yb).abs()) + 1e-9 * (1.0 + yb.abs());
        let (ya, yb) = (ya - pad, yb + pad);
        let s = self.feed_per_tooth;
        let (w_lo, w_hi) = (rows[i].w, rows[i + 1].w);
        let r0 = (w_lo - s).max(0.0);
        // cos and sin of ψ at both ends of the rows' heights, widened by
        // the most they can bulge between (δ²/8 over an arc δ).
        let (st, ct) = theta.sin_cos();
        let (r1, r2) = (&self.turns[i], &self.turns[i + 1]);
        let (ca, sa) = (ct * r2.1 - st * r2.0, st * r2.1 + ct * r2.0);
        let (cb, sb) = (ct * r1.1 - st * r1.0, st * r1.1 + ct * r1.0);
        let bulge = self.bulge;
        let cmax = ca.max(cb) + bulge;
        let cmin = ca.min(cb) - bulge;
        let lo = (r0 * cmin).min(w_hi * cmin);
        let hi = (r0 * cmax).max(w_hi * cmax);
        if hi < ya || lo > yb {
            return false;
        }
        if w_lo > s {
            let q = if self.feed > 0.0 { sa.max(sb) } else { -(sa.min(sb)) } + bulge;
            if q < -s / (2.0 * w_lo) - 1e-9 {
                return false;
            }
        }
        true
    }

    /// What the rake face of one tooth cuts at rotation angle `theta`
    /// (radians; 0 where the edge at the reference height is on +Y,
    /// increasing clockwise seen from above, the way the tool turns).
    pub fn section(&self, theta: f64) -> Section {
        let [a, mx, my, mz, _] = self.integrals(theta);
        if a.is_nan() || a <= 0.0 {
            return Section::default();
        }
        let centroid = [mx / a, my / a, mz / a];
        let lg = centroid[0].hypot(centroid[1]);
        Section { area: a, centroid, lg, ed: a * lg }
    }

    /// `M(θ) = ∫∫ ρ dρ dz` over the section in the `(ρ, z)` half-plane,
    /// mm³: its integral over a revolution (θ in radians) is
    /// [`Chip::volume`]; with a straight flute (helix 0) it is `E_d`.
    pub fn radial_moment(&self, theta: f64) -> f64 {
        self.integrals(theta)[4]
    }

    /// The chip's volume, mm³: the integral over the removed cross-section
    /// in YZ (below the stock plane, outside the previous pass, inside this
    /// pass) of `min(S_z, the tool's chord along X there)`.
    pub fn volume(&self) -> f64 {
        self.volume
    }

    /// Area of the removed cross-section in the YZ plane, mm²;
    /// `S_z` times it is slightly more than [`Chip::volume`].
    pub fn cross_section_area(&self) -> f64 {
        self.cross_section
    }

    /// Y of the removed cross-section's centroid, mm: the side of the axis
    /// the chip is on.
    pub fn chip_side(&self) -> f64 {
        self.cross_section_y
    }

    /// The feed direction along X, +1 or −1: with the spindle clockwise
    /// seen from above a tooth at `+Y` moves toward `+X`, so a down-cut
    /// (climbing, against the tool's travel) feeds toward `−X` when the chip
    /// is on the `+Y` side of the axis ([`Chip::chip_side`] ≥ 0) and an
    /// up-cut toward `+X`; the other way round for a chip on the `−Y` side.
    pub fn feed_direction(&self) -> f64 {
        self.feed
    }

    /// Heights above the tip between which the chip lies (a cover), mm.
    pub fn heights(&self) -> (f64, f64) {
        (self.zlo, self.zhi)
    }
}

/// The sections of one tooth at `steps` equal angles over one revolution
/// (at least 1), in a window chosen so that the engaged range is
/// contiguous (see [`Sweep::theta`]).
pub fn sweep(chip: &Chip, steps: usize) -> Sweep {
    let steps = steps.max(1);
    let step = TAU / steps as f64;
    let grid: Vec<Section> = (0..steps).into_par_iter().map(|j| chip.section(j as f64 * step)).collect();
    // The longest circular run of angles that cut nothing.
    let cuts = |j: usize| grid[j % steps].area > 0.0;
    let mut start = 0i64;
    if let Some(anchor) = (0..steps).find(|&j| cuts(j)) {
        let (mut best, mut best_len) = (0usize, 0usize);
        let mut j = anchor + 1;
        while j <= anchor + steps {
            if !cuts(j) {
                let from = j;
                while j < anchor + steps && !cuts(j) {
                    j += 1;
                }
                if j - from > best_len {
                    best = from;
                    best_len = j - from;
                }
            }
            j += 1;
        }
        if best_len > 0 {
            let mid = ((best + best_len / 2) % steps) as i64;
            start = if (mid as f64) * step >= PI { mid - steps as i64 } else { mid };
        }
    }
    let theta: Vec<f64> = (0..steps as i64).map(|i| (start + i) as f64 * step).collect();
    let sections: Vec<Section> =
        (0..steps as i64).map(|i| grid[(start + i).rem_euclid(steps as i64) as usize]).collect();
    let first = sections.iter().position(|s| s.area > 0.0);
    let last = sections.iter().rposition(|s| s.area > 0.0);
    let engaged = first.zip(last).map(|(f, l)| (theta[f], theta[l]));
    let area_max = sections.iter().map(|s| s.area).fold(0.0, f64::max);
    let ed_max = sections.iter().map(|s| s.ed).fold(0.0, f64::max);
    Sweep { theta, sections, engaged, area_max, ed_max }
}
