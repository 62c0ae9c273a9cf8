//! A program's moves corrected for thermal drift (`kezuri thermal apply`):
//! every end point commanded where the warm machine puts the tool on the
//! CAM target, and what that came to.

use kezuri_geom::{Axes, Move, MoveKind};

use super::{Corrector, ErrorModel};
use crate::kinematics::Kinematics;
use crate::{Error, ErrorKind};

/// The share of a program's points beyond the measured range above which
/// its correction is refused unless extrapolation is allowed.
pub const MOST_EXTRAPOLATED: f64 = 0.1;

/// Which way the corrected command is found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Solver {
    /// Newton's method to 1 nm ([`Corrector`], one per setting of the
    /// rotary axes).
    Newton,
    /// A grid search: ±50 candidates per axis 1 µm apart about the
    /// first-order estimate ([`ErrorModel::correct_by_grid`]).
    Grid,
}

/// What correcting a program's moves came to.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Summary {
    /// Points corrected: every move's end but returns to the reference
    /// point and dwells.
    pub checked: usize,
    /// The largest correction, mm.
    pub largest_correction: f64,
    /// The largest residual left by the solver, mm.
    pub largest_residual: f64,
    /// The largest change of the correction from an arc's start to its
    /// end (its centre moves with its end), mm.
    pub arc_correction_change: f64,
    /// Points whose correction is extrapolated: beyond the measured range
    /// of their axis's error function.
    pub extrapolated: usize,
    /// The program line of the first of them.
    pub first_extrapolated_line: Option<u32>,
}

impl Summary {
    /// What a machinist is told where some points' corrections are
    /// extrapolated (`None` where none are): how many, their share and the
    /// line of the first. Refused where more than [`MOST_EXTRAPOLATED`] of
    /// the points are, unless `allowed`.
    pub fn extrapolation(&self, allowed: bool) -> Result<Option<String>, Error> {
        let Some(line) = self.first_extrapolated_line else { return Ok(None) };
        let share = self.extrapolated as f64 / self.checked.max(1) as f64;
        let said = format!(
            "{} of {} points ({:.1} %) lie beyond the measured range of their axis's error function (the first at \
             line {line})",
            self.extrapolated,
            self.checked,
            share * 100.0
        );
        if share > MOST_EXTRAPOLATED && !allowed {
            return Err(Error::new(
                ErrorKind::Extrapolated,
                format!(
                    "{said}: more than {:.0} % of the program would be corrected by extrapolating the fitted curves. \
                     Measure over the program's travel (thermal plan), or give --allow-extrapolation",
                    MOST_EXTRAPOLATED * 100.0
                ),
            ));
        }
        Ok(Some(format!("{said}: their correction is extrapolated")))
    }
}

/// The corrected moves.
#[derive(Clone, Debug, PartialEq)]
pub struct Corrected {
    /// Each move's corrected end, in order (returns to the reference point
    /// and dwells as they were).
    pub ends: Vec<Axes>,
    /// What the correction came to.
    pub summary: Summary,
}

/// Every end of `moves` corrected by `model` on the machine `k`, found by
/// `solver`; an error carries the line of its move.
pub fn correct_moves(model: &ErrorModel, k: &Kinematics, moves: &[Move], solver: Solver) -> Result<Corrected, Error> {
    let mut correcting = Correcting::new(model, k.clone(), solver);
    let ends = correcting.ends(moves)?;
    Ok(Corrected { ends, summary: correcting.summary })
}

/// A program's moves corrected as they come, in pieces (a run's, handed
/// on): the pieces' ends are the ends [`correct_moves`] gives of the
/// whole, and the summary after the last piece its summary.
pub struct Correcting<'a> {
    model: &'a ErrorModel,
    k: Kinematics,
    solver: Solver,
    /// One per setting of the rotary axes met so far (Newton).
    correctors: Vec<Corrector<'a>>,
    /// The correction of the last point corrected.
    last_shift: [f64; 3],
    /// What the correction came to so far.
    pub summary: Summary,
}

impl<'a> Correcting<'a> {
    /// The correction by `model` on the machine `k`, found by `solver`,
    /// before its first move.
    pub fn new(model: &'a ErrorModel, k: Kinematics, solver: Solver) -> Correcting<'a> {
        Correcting { model, k, solver, correctors: Vec::new(), last_shift: [0.0; 3], summary: Summary::default() }
    }

    /// The corrected ends of `moves`, the next moves of the program; an
    /// error carries the line of its move.
    pub fn ends(&mut self, moves: &[Move]) -> Result<Vec<Axes>, Error> {
        let (model, k, summary) = (self.model, &self.k, &mut self.summary);
        let mut ends: Vec<Axes> = Vec::with_capacity(moves.len());
        for m in moves {
            // A return to the reference point goes where the control knows; a
            // dwell stays: neither is a commanded position.
            if matches!(m.kind, MoveKind::Home | MoveKind::Dwell(_)) {
                ends.push(m.end);
                continue;
            }
            summary.checked += 1;
            let c = m.end.xyzabc();
            let target = k.forward(&c);
            let (x, residual) = match self.solver {
                Solver::Newton => {
                    let at = match self.correctors.iter().position(|r| r.fits(&c)) {
                        Some(at) => at,
                        None => {
                            self.correctors.push(Corrector::new(model, k, &c).map_err(|e| e.at_line(m.line))?);
                            self.correctors.len() - 1
                        }
                    };
                    self.correctors[at].correct(target)
                }
                Solver::Grid => model.correct_by_grid(k, target, &c, 0.001, 50),
            }
            .map_err(|e| e.at_line(m.line))?;
            // A command beyond the measured range of its axis's function is
            // extrapolated: said, not hidden. A corrected stop at the range's
            // edge lands a correction beyond it; a twentieth of the range (a
            // tenth of the half-span) is not counted.
            let outside = model.functions.iter().any(|f| {
                (f.b_deg - c[4]).abs() < 1e-6
                    && (x[f.axis] - f.polynomial.center).abs() > f.polynomial.scale * 1.1 + 1e-9
            });
            if outside {
                summary.first_extrapolated_line.get_or_insert(m.line);
                summary.extrapolated += 1;
            }
            let shift = [x[0] - c[0], x[1] - c[1], x[2] - c[2]];
            summary.largest_correction = summary
                .largest_correction
                .max((shift[0] * shift[0] + shift[1] * shift[1] + shift[2] * shift[2]).sqrt());
            summary.largest_residual = summary.largest_residual.max(residual);
            if matches!(m.kind, MoveKind::Arc(_)) {
                let last = self.last_shift;
                let d = [shift[0] - last[0], shift[1] - last[1], shift[2] - last[2]];
                summary.arc_correction_change =
                    summary.arc_correction_change.max((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt());
            }
            self.last_shift = shift;
            ends.push(m.end.with_xyzabc(x));
        }
        Ok(ends)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extrapolated_points_are_said_and_too_many_refused() {
        let mut s = Summary { checked: 28, ..Summary::default() };
        assert_eq!(s.extrapolation(false), Ok(None));
        s.extrapolated = 2;
        s.first_extrapolated_line = Some(7);
        let said = "2 of 28 points (7.1 %) lie beyond the measured range of their axis's error function (the first \
                    at line 7): their correction is extrapolated";
        assert_eq!(s.extrapolation(false).unwrap().as_deref(), Some(said));
        s.extrapolated = 5;
        let e = s.extrapolation(false).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Extrapolated);
        assert!(e.to_string().contains("(17.9 %)") && e.to_string().contains("more than 10 % of the program"), "{e}");
        assert!(s.extrapolation(true).unwrap().is_some());
    }
}
