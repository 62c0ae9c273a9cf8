//! A program's cutting moves corrected for the measured tool (`kezuri wear
//! apply`): each end of a feed or an arc moved by [`correct`], the points
//! it skips kept as programmed and counted.

use kezuri_geom::{Axes, Frame, MoveKind, ToolProfile, Toolpath, Vec3};

use super::{correct, Nominal, Options, Skip, Surface};
use crate::kinematics::Kinematics;
use crate::{Error, ErrorKind};

/// What correcting a program's cutting moves came to.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Summary {
    /// Points corrected.
    pub corrected: usize,
    /// Of them, corrected along the tool axis (plunges and ramps).
    pub along_axis: usize,
    /// The largest correction, mm.
    pub largest_correction: f64,
    /// The largest residual left, mm.
    pub largest_residual: f64,
    /// The largest error of the measured tool before correction, mm.
    pub largest_error_before: f64,
    /// The lines of cutting points kept because the new tool is farther
    /// than the reach from the surface.
    pub far: Vec<u32>,
    /// The lines of points kept because the new tool itself cuts more
    /// than the reach into the surface, with how deep, mm.
    pub gouging: Vec<(u32, f64)>,
    /// The lines of points kept because they are fed square into a wall
    /// along the tool, with the error left, mm.
    pub square: Vec<(u32, f64)>,
}

/// The corrected moves.
#[derive(Clone, Debug, PartialEq)]
pub struct Corrected {
    /// Each move's end, in order: corrected, or as programmed (rapids and
    /// the other moves that do not cut, and the points kept).
    pub ends: Vec<Axes>,
    /// What the correction came to.
    pub summary: Summary,
}

/// The unit direction of `v`, `None` for a standstill.
fn unit(v: Vec3) -> Option<Vec3> {
    let n = v.norm();
    (n > 1e-12).then(|| v * (1.0 / n))
}

/// Every cutting end of `path` (feeds and arcs; the machine `k`) moved so
/// the measured tool `worn` cuts `surface` where the `nominal` tool would
/// have; an error carries the line of its move.
pub fn correct_moves(
    surface: &Surface,
    nominal: Nominal,
    worn: &ToolProfile,
    k: &Kinematics,
    path: &Toolpath,
    options: &Options,
) -> Result<Corrected, Error> {
    let mut ends: Vec<Axes> = Vec::with_capacity(path.moves.len());
    let mut summary = Summary::default();
    let to_vec = |p: [f64; 3]| Vec3::new(p[0], p[1], p[2]);
    for m in &path.moves {
        let cutting = matches!(m.kind, MoveKind::Feed | MoveKind::Arc(_));
        if !cutting {
            ends.push(m.end);
            continue;
        }
        let c = m.end.xyzabc();
        let tip = to_vec(k.forward(&c));
        let axis = to_vec(k.tool_axis(&c));
        if path.frame(m) != Frame::default() {
            return Err(Error::new(
                ErrorKind::OffsetInForce,
                "a work or tool offset is in force; the surface is in program coordinates: run the program without \
                 offsets",
            )
            .at_line(m.line));
        }
        let before = match m.kind {
            // A hair back along the arc's tangent at its end.
            MoveKind::Arc(arc) => {
                let (i, j, _) = arc.plane.axes();
                let (e, mut back) = (m.end.xyzabc(), m.end.xyzabc());
                let (ri, rj) = (e[i] - arc.center[i], e[j] - arc.center[j]);
                let r = ri.hypot(rj).max(1e-12);
                let sign = if arc.ccw { 1.0 } else { -1.0 };
                back[i] += sign * 1e-4 * rj / r;
                back[j] -= sign * 1e-4 * ri / r;
                to_vec(k.forward(&back))
            }
            _ => to_vec(k.forward(&m.start.xyzabc())),
        };
        let feed = unit(tip - before);
        match correct(surface, nominal, worn, tip, axis, feed, options).map_err(|e| e.at_line(m.line))? {
            Ok(fix) => {
                let target = [tip.x + fix.shift[0], tip.y + fix.shift[1], tip.z + fix.shift[2]];
                let x = k
                    .inverse(target, &c)
                    .ok_or_else(|| Error::new(ErrorKind::Unreachable, "no command reaches").at_line(m.line))?;
                summary.largest_correction = summary.largest_correction.max(to_vec(fix.shift).norm());
                summary.largest_residual = summary.largest_residual.max(fix.residual.abs());
                summary.largest_error_before = summary.largest_error_before.max((fix.worn_gap - fix.nominal_gap).abs());
                summary.corrected += 1;
                summary.along_axis += usize::from(fix.along_axis);
                ends.push(m.end.with_xyzabc(x));
            }
            Err(Skip::Far(_)) => {
                summary.far.push(m.line);
                ends.push(m.end);
            }
            Err(Skip::Gouges(d)) => {
                summary.gouging.push((m.line, d));
                ends.push(m.end);
            }
            Err(Skip::NoDirection(e)) => {
                summary.square.push((m.line, e));
                ends.push(m.end);
            }
        }
    }
    Ok(Corrected { ends, summary })
}
