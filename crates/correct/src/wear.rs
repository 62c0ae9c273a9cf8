//! The worn, eccentric tool put where the new one would have cut (the
//! thermal and wear report, tool wear and runout).
//!
//! For a CL point (tool tip `T`, tool axis `a`, feed direction `f`):
//! 1. The nominal tool's cutting point `p` on the finished surface: the
//!    point of the mesh nearest to the tool's centre of curvature there —
//!    the ball's centre, or for a bull-nose the point of its corner circle
//!    (radius `R − ρ` at height `ρ`) on the side of the surface, found by
//!    a few rounds of nearest point and normal. The surface normal `n` at
//!    `p` points from `p` to that centre; the nominal tool's gap is the
//!    distance less the corner radius `ρ` (0 where it touches).
//! 2. The surface near `p` is taken as the plane through `p` normal to `n`.
//!    The measured tool (a surface of revolution about `a`, its profile in
//!    tool coordinates, so a tilted B needs nothing more) is as far from
//!    that plane as `n·(T − p) + min over the profile of (z·cos φ −
//!    r·sin φ)`, `φ` the angle between `n` and `a`
//!    ([`ToolProfile::support`]).
//! 3. The tool is translated so that gap equals the nominal tool's: in the
//!    plane normal to the feed direction, along `n`'s part in it (the
//!    least move that does it), or along the tool axis where the feed runs
//!    within 30° of the normal (plunges and ramps into the surface). Where
//!    neither is short (feeding square into a wall with the tool along it)
//!    the point is skipped, and said ([`Skip::NoDirection`]).
//!
//! The translation keeps the tool's attitude, so the point of the profile
//! that touches the plane does not change and one step is exact: the
//! residual is rounding, and is reported, not assumed.
//!
//! [`correct_moves`] does this for every cutting end of a program's
//! toolpath, keeping and counting the points it skips.

use kezuri_geom::{Mesh, ToolProfile, Vec3, XyIndex};

use crate::{Error, ErrorKind};

mod program;

pub use program::{correct_moves, Corrected, Summary};

/// The nominal tool: a torus end mill (a ball when the corner radius is the
/// radius).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nominal {
    /// Radius `R`, mm.
    pub radius: f64,
    /// Corner radius `ρ` (0 < ρ ≤ R), mm.
    pub corner: f64,
}

/// How far the nominal tool may be from the surface for a point to be
/// corrected, and how the feed decides the direction.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// A point whose nominal tool is farther than this from the surface
    /// (or cuts deeper than this into it) is left as programmed, with a
    /// warning, mm.
    pub reach: f64,
}

/// One corrected point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Correction {
    /// The translation of the tool tip, mm.
    pub shift: [f64; 3],
    /// The nominal tool's gap to the surface (0 where it touches), mm.
    pub nominal_gap: f64,
    /// The measured tool's gap before correction, mm.
    pub worn_gap: f64,
    /// The measured tool's gap after, less the nominal's, mm.
    pub residual: f64,
    /// The cutting point on the surface.
    pub point: [f64; 3],
    /// The surface normal there.
    pub normal: [f64; 3],
    /// Height on the tool (z of the profile) that touches.
    pub contact_z: f64,
    /// Whether the correction runs along the tool axis (plunge or ramp).
    pub along_axis: bool,
}

/// Why a point is not corrected.
#[derive(Clone, Debug, PartialEq)]
pub enum Skip {
    /// No surface within reach of the nominal tool: its gap (∞ if none at
    /// all within the search).
    Far(f64),
    /// The nominal tool cuts into the surface by more than the reach.
    Gouges(f64),
    /// The feed runs within 60° of the surface normal and the tool axis
    /// lies within 6° of the surface (feeding square into a wall): the
    /// error (mm) is not corrected.
    NoDirection(f64),
}

/// The finished surface, indexed for nearest-point questions.
pub struct Surface<'a> {
    mesh: &'a Mesh,
    index: XyIndex,
}

impl<'a> Surface<'a> {
    /// `mesh` indexed.
    pub fn new(mesh: &'a Mesh) -> Surface<'a> {
        Surface { mesh, index: XyIndex::new(mesh) }
    }

    /// The point of the surface nearest to `q` within `radius`, with the
    /// outward normal of its triangle; `None` when none is that close.
    pub fn nearest(&self, q: Vec3, radius: f64) -> Option<(Vec3, Vec3, f64)> {
        let mut best: Option<(Vec3, Vec3, f64)> = None;
        self.index.for_each_in_disk([q.x, q.y], radius, |t| {
            let tri = self.mesh.triangle(t as usize);
            let p = closest_on_triangle(q, tri.v);
            let d = (q - p).norm();
            if d <= radius && best.is_none_or(|b| d < b.2) {
                let face = tri.normal();
                best = Some((p, face * (1.0 / face.norm()), d));
            }
        });
        best
    }
}

/// The point of triangle `v` nearest to `p` (Ericson, Real-Time Collision
/// Detection, 5.1.5).
pub fn closest_on_triangle(p: Vec3, v: [Vec3; 3]) -> Vec3 {
    let [a, b, c] = v;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// `v` less its part along the unit vector `u`.
fn reject(v: Vec3, u: Vec3) -> Vec3 {
    v - u * v.dot(u)
}

/// The correction of the CL point `tip` (tool axis `axis`, unit, from the
/// tip up; `feed` the unit direction of the move into the point, `None`
/// when it has none) for the measured tool `worn`, or why it is skipped.
pub fn correct(
    surface: &Surface,
    nominal: Nominal,
    worn: &ToolProfile,
    tip: Vec3,
    axis: Vec3,
    feed: Option<Vec3>,
    options: &Options,
) -> Result<Result<Correction, Skip>, Error> {
    let (big_r, rho) = (nominal.radius, nominal.corner);
    let ring = big_r - rho;
    let centre = tip + axis * rho;
    // The corner circle's point toward the surface: from the nearest point
    // to the tool's middle, then from the normal there (a ball's corner
    // circle is its centre: one question).
    let Some(first) = surface.nearest(centre, big_r + options.reach) else {
        return Ok(Err(Skip::Far(f64::INFINITY)));
    };
    let mut toward = reject(first.0 - centre, axis);
    let mut found: Option<(Vec3, Vec3, f64)> = None;
    for _ in 0..8 {
        let k = if ring > 0.0 && toward.norm() > 1e-12 { centre + toward * (ring / toward.norm()) } else { centre };
        let near = if ring == 0.0 { Some(first) } else { surface.nearest(k, rho + options.reach) };
        let Some((p, face, d)) = near else {
            return Ok(Err(Skip::Far(f64::INFINITY)));
        };
        // The normal points out of the material toward the tool.
        let inside = (k - p).dot(face) < 0.0;
        let n = if d > 1e-9 * big_r { (k - p) * (if inside { -1.0 } else { 1.0 } / d) } else { face };
        let gap = if inside { -d - rho } else { d - rho };
        let again = reject(n * -1.0, axis);
        let settled = ring == 0.0 || found.is_some_and(|(_, m, _)| (m - n).norm() < 1e-12);
        found = Some((p, n, gap));
        if settled || again.norm() < 1e-12 {
            break;
        }
        toward = again;
    }
    let Some((p, n, nominal_gap)) = found else { unreachable!("the loop runs once") };
    if nominal_gap > options.reach {
        return Ok(Err(Skip::Far(nominal_gap)));
    }
    if nominal_gap < -options.reach {
        return Ok(Err(Skip::Gouges(-nominal_gap)));
    }
    let cos = n.dot(axis).clamp(-1.0, 1.0);
    let sin = reject(n, axis).norm();
    // The nominal tool touches at height ρ(1 − cos φ) on its corner.
    let nominal_z = rho * (1.0 - cos.max(0.0));
    if nominal_z > worn.top() {
        return Err(Error::new(
            ErrorKind::ProfileTooShort,
            format!(
                "the profile ends at z {:.4} mm but the tool cuts at z {nominal_z:.4} mm here: measure more of the tool",
                worn.top()
            ),
        ));
    }
    let support = worn.support(cos, sin);
    // At a wall along the tool (|cos φ| < 0.05) the shank's widest sample
    // cuts, wherever it is; elsewhere the top sample touching means the
    // tool goes on cutting above what was measured.
    if support.index + 1 == worn.z().len() && sin > 1e-9 && cos.abs() >= 0.05 {
        return Err(Error::new(
            ErrorKind::ProfileTooShort,
            format!(
                "the measured tool touches at the top of its profile (z {:.4} mm): the profile is shorter than the \
                 part of the tool that cuts here",
                worn.top()
            ),
        ));
    }
    let gap_of = |t: Vec3| n.dot(t - p) + support.value;
    let worn_gap = gap_of(tip);
    let error = worn_gap - nominal_gap;
    // In the plane normal to the feed, along the normal's part in it; with
    // no feed (a standstill) along the normal itself.
    let across = feed.map_or(n, |f| reject(n, f));
    let (shift, along_axis) = if across.norm() >= 0.5 {
        (across * (-error / across.dot(across)), false)
    } else if cos.abs() >= 0.1 {
        (axis * (-error / cos), true)
    } else {
        // Feeding into a wall square to the tool: no direction both keeps
        // to the plane normal to the feed and stays short.
        return Ok(Err(Skip::NoDirection(error)));
    };
    let moved = tip + shift;
    Ok(Ok(Correction {
        shift: [shift.x, shift.y, shift.z],
        nominal_gap,
        worn_gap,
        residual: gap_of(moved) - nominal_gap,
        point: [p.x, p.y, p.z],
        normal: [n.x, n.y, n.z],
        contact_z: worn.z()[support.index],
        along_axis,
    }))
}
