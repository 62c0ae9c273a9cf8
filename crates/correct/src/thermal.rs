//! The thermal error model and the corrected command (the thermal and
//! wear report).
//!
//! The machine, warm, puts the tool at its ideal place for the command plus
//! the sum over the linear axes of each axis's error vector, a function of
//! the command on that axis alone: `tip(c) = forward(c) + Σₐ Eₐ(cₐ)`
//! (the thermal and wear report's model). Each `Eₐ` is kept per indexed B angle, as three
//! polynomials (the errors along X, Y and Z) in the command, fitted by
//! least squares to measurements; the degree, unless given, is the lowest
//! whose leave-one-out error is within 1 % (or (1 nm)²) of the least.
//!
//! [`ErrorModel::correct`] finds the command whose deformed tip lands on a
//! target: Newton's method on the three linear commands, the rotary axes
//! as the program indexes them, from the ideal inverse, to 1 nm.
//! [`ErrorModel::correct_by_grid`] is the report's brute force for
//! comparison: candidates on a grid about the first-order estimate.
//! [`correct_moves`] corrects every end of a program's moves by either, and
//! says how far the correction went and where it was extrapolated.

use crate::kinematics::{solve3, Kinematics, AXES};
use crate::{Error, ErrorKind};

mod measurement;
pub mod model_file;
mod program;

pub use measurement::{is_warm, linear_axis, stop_error, warm_less_cold};
pub use program::{correct_moves, Corrected, Correcting, Solver, Summary, MOST_EXTRAPOLATED};

/// One measurement: the command on one axis and the error there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measurement {
    /// The commanded axis (0 X, 1 Y, 2 Z).
    pub axis: usize,
    /// The indexed B angle, degrees.
    pub b_deg: f64,
    /// The command on that axis, mm.
    pub command: f64,
    /// Where the tool was less where it should have been, X Y Z, mm.
    pub error: [f64; 3],
}

/// A polynomial in `(c − center) / scale` for each of X, Y, Z.
#[derive(Clone, Debug, PartialEq)]
pub struct Polynomial {
    /// Middle of the fitted commands.
    pub center: f64,
    /// Half their range (1 for a single command).
    pub scale: f64,
    /// Coefficients from the constant up, per direction.
    pub coefficients: [Vec<f64>; 3],
}

impl Polynomial {
    /// The error vector at command `c`.
    pub fn at(&self, c: f64) -> [f64; 3] {
        let t = (c - self.center) / self.scale;
        std::array::from_fn(|k| self.coefficients[k].iter().rev().fold(0.0, |acc, &a| acc * t + a))
    }

    /// Its derivative by the command.
    pub fn slope(&self, c: f64) -> [f64; 3] {
        let t = (c - self.center) / self.scale;
        std::array::from_fn(|k| {
            let k = &self.coefficients[k];
            k.iter().enumerate().skip(1).rev().fold(0.0, |acc, (n, &a)| acc * t + n as f64 * a) / self.scale
        })
    }
}

/// The error function of one axis at one B angle.
#[derive(Clone, Debug, PartialEq)]
pub struct AxisError {
    /// The axis (0 X, 1 Y, 2 Z).
    pub axis: usize,
    /// The indexed B angle, degrees.
    pub b_deg: f64,
    /// The polynomials.
    pub polynomial: Polynomial,
    /// Their degree.
    pub degree: usize,
    /// Root mean square residual of the fit, per direction, mm.
    pub rms_mm: [f64; 3],
    /// Measurements fitted.
    pub points: usize,
}

/// Every axis's error functions.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ErrorModel {
    /// The functions, by axis and angle.
    pub functions: Vec<AxisError>,
}

/// The linear axes do not span space at this command.
fn singular() -> Error {
    Error::new(ErrorKind::Singular, "the linear axes do not span space at this command")
}

/// Highest degree tried by cross-validation.
pub const MAX_DEGREE: usize = 5;

/// B angles closer than this are the same indexed angle, degrees.
const SAME_ANGLE: f64 = 1e-6;

/// Fits a model to `measurements`: per axis and B angle, polynomials of
/// `degree`, or of the degree with the least leave-one-out error.
pub fn fit(measurements: &[Measurement], degree: Option<usize>) -> Result<ErrorModel, Error> {
    // No measurement is no model: an empty one would correct nothing.
    if measurements.is_empty() {
        return Err(Error::new(
            ErrorKind::TooFewMeasurements,
            "no measurements: nothing to fit a model to".to_string(),
        ));
    }
    if let Some(k) = measurements.iter().position(|m| {
        m.axis > 2 || !m.b_deg.is_finite() || !m.command.is_finite() || !m.error.iter().all(|e| e.is_finite())
    }) {
        return Err(Error::new(
            ErrorKind::BadMeasurement,
            format!("measurement {}: not finite, or not on X, Y or Z", k + 1),
        ));
    }
    let mut groups: Vec<(usize, f64, Vec<Measurement>)> = Vec::new();
    for m in measurements {
        match groups.iter_mut().find(|g| g.0 == m.axis && (g.1 - m.b_deg).abs() < SAME_ANGLE) {
            Some(g) => g.2.push(*m),
            None => groups.push((m.axis, m.b_deg, vec![*m])),
        }
    }
    let mut functions = Vec::new();
    for (axis, b_deg, ms) in groups {
        let n = ms.len();
        // A degree past any file's size asks for too many points, not an overflow.
        let need = degree.unwrap_or(0).saturating_add(1);
        if n < need {
            let degree = degree.unwrap_or(0);
            return Err(Error::new(
                ErrorKind::TooFewMeasurements,
                format!(
                    "axis {} at B {b_deg}°: {n} measurement(s), too few for a polynomial of degree {degree} ({need} at \
                     least)",
                    AXES[axis]
                ),
            ));
        }
        let degree = match degree {
            Some(d) => d,
            // One measurement: a constant (none to leave out).
            None if n < 2 => 0,
            None => {
                // The lowest degree whose leave-one-out error is within 1 %
                // (or (1 nm)²) of the least: more terms must earn their place.
                let errors: Vec<f64> =
                    (0..=MAX_DEGREE.min(n.saturating_sub(2))).map(|d| leave_one_out(&ms, d)).collect();
                let least = errors.iter().copied().fold(f64::INFINITY, f64::min);
                errors.iter().position(|&e| e <= least * 1.01 + 1e-12).unwrap_or(0)
            }
        };
        let polynomial = least_squares(&ms, degree);
        let rms_mm = std::array::from_fn(|k| {
            (ms.iter().map(|m| (polynomial.at(m.command)[k] - m.error[k]).powi(2)).sum::<f64>() / n as f64).sqrt()
        });
        functions.push(AxisError { axis, b_deg, polynomial, degree, rms_mm, points: n });
    }
    functions.sort_by(|a, b| (a.axis, a.b_deg).partial_cmp(&(b.axis, b.b_deg)).unwrap_or(std::cmp::Ordering::Equal));
    Ok(ErrorModel { functions })
}

/// Mean squared error of predicting each measurement from the others.
fn leave_one_out(ms: &[Measurement], degree: usize) -> f64 {
    let mut sum = 0.0;
    for k in 0..ms.len() {
        let rest: Vec<Measurement> = ms.iter().enumerate().filter(|(j, _)| *j != k).map(|(_, m)| *m).collect();
        let p = least_squares(&rest, degree);
        let e = p.at(ms[k].command);
        sum += (0..3).map(|i| (e[i] - ms[k].error[i]).powi(2)).sum::<f64>();
    }
    sum / ms.len() as f64
}

/// The least squares polynomials of `degree` (Householder QR on the
/// Vandermonde matrix of the scaled commands).
fn least_squares(ms: &[Measurement], degree: usize) -> Polynomial {
    let (lo, hi) =
        ms.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), m| (lo.min(m.command), hi.max(m.command)));
    let center = 0.5 * (lo + hi);
    let scale = if hi > lo { 0.5 * (hi - lo) } else { 1.0 };
    let cols = degree + 1;
    // Column by column: the Vandermonde matrix and the three error columns.
    let t: Vec<f64> = ms.iter().map(|m| (m.command - center) / scale).collect();
    let mut a: Vec<Vec<f64>> = (0..cols).map(|d| t.iter().map(|t| t.powi(d as i32)).collect()).collect();
    let mut b: [Vec<f64>; 3] = std::array::from_fn(|k| ms.iter().map(|m| m.error[k]).collect());
    let rows = t.len();
    // Householder reflections make `a` upper triangular; the same to `b`.
    for j in 0..cols.min(rows) {
        let norm = a[j][j..].iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm == 0.0 {
            continue;
        }
        let alpha = if a[j][j] > 0.0 { -norm } else { norm };
        let mut v: Vec<f64> = a[j][j..].to_vec();
        v[0] -= alpha;
        let vv: f64 = v.iter().map(|x| x * x).sum();
        if vv == 0.0 {
            continue;
        }
        let reflect = |col: &mut Vec<f64>| {
            let dot: f64 = v.iter().zip(&col[j..]).map(|(p, q)| p * q).sum();
            for (x, vi) in col[j..].iter_mut().zip(&v) {
                *x -= 2.0 * dot / vv * vi;
            }
        };
        a.iter_mut().skip(j).for_each(reflect);
        b.iter_mut().for_each(reflect);
    }
    let coefficients = std::array::from_fn(|k| {
        let mut x = vec![0.0; cols];
        for j in (0..cols).rev() {
            let s: f64 = (j + 1..cols).map(|c| a[c][j] * x[c]).sum();
            x[j] = if j < rows && a[j][j].abs() > 1e-300 { (b[k][j] - s) / a[j][j] } else { 0.0 };
        }
        x
    });
    Polynomial { center, scale, coefficients }
}

impl ErrorModel {
    /// The fit as a table: a header line, then for each error function
    /// its axis, B angle, degree, points and rms residual along X, Y and Z
    /// in µm, a line each.
    pub fn table(&self) -> String {
        let mut table = String::from("  axis  B deg  degree  points  rms X / Y / Z µm\n");
        for f in &self.functions {
            table += &format!(
                "  {}    {:>6.1}  {:>6}  {:>6}  {:.3} / {:.3} / {:.3}\n",
                AXES[f.axis],
                f.b_deg,
                f.degree,
                f.points,
                f.rms_mm[0] * 1e3,
                f.rms_mm[1] * 1e3,
                f.rms_mm[2] * 1e3
            );
        }
        table
    }

    /// The function of `axis` at the B angle `b_deg`.
    fn function(&self, axis: usize, b_deg: f64) -> Result<&AxisError, Error> {
        self.functions.iter().find(|f| f.axis == axis && (f.b_deg - b_deg).abs() < SAME_ANGLE).ok_or_else(|| {
            Error::new(
                ErrorKind::NoErrorFunction,
                format!("the model has no error function for axis {} at B {b_deg}°", AXES[axis]),
            )
        })
    }

    /// The error of the tip at command `c` (sum over X, Y, Z), and its
    /// derivative by each linear command (columns).
    pub fn error(&self, c: &[f64; 6]) -> Result<([f64; 3], [[f64; 3]; 3]), Error> {
        let mut e = [0.0; 3];
        let mut d = [[0.0; 3]; 3];
        for axis in 0..3 {
            let f = self.function(axis, c[4])?;
            let (v, s) = (f.polynomial.at(c[axis]), f.polynomial.slope(c[axis]));
            for i in 0..3 {
                e[i] += v[i];
                d[i][axis] = s[i];
            }
        }
        Ok((e, d))
    }

    /// Where the warm machine puts the tip for command `c`.
    pub fn deformed(&self, k: &Kinematics, c: &[f64; 6]) -> Result<[f64; 3], Error> {
        let (e, _) = self.error(c)?;
        let p = k.forward(c);
        Ok([p[0] + e[0], p[1] + e[1], p[2] + e[2]])
    }

    /// The command (linear axes changed; rotaries as in `c`) whose deformed
    /// tip lands on `target`, by Newton's method from the ideal inverse,
    /// to 1 nm; with the residual left. (For many points at the same
    /// rotary angles, [`Corrector`] does the kinematics once.)
    pub fn correct(&self, k: &Kinematics, target: [f64; 3], c: &[f64; 6]) -> Result<([f64; 6], f64), Error> {
        Corrector::new(self, k, c)?.correct(target)
    }

    /// The thermal and wear report's search: `(2·half + 1)³` candidates `spacing` mm apart
    /// on each linear axis about the first-order estimate (the ideal
    /// inverse of the target less the error there); the one whose deformed
    /// tip lands nearest, with that distance.
    pub fn correct_by_grid(
        &self,
        k: &Kinematics,
        target: [f64; 3],
        c: &[f64; 6],
        spacing: f64,
        half: i32,
    ) -> Result<([f64; 6], f64), Error> {
        let ideal = k.inverse(target, c).ok_or_else(singular)?;
        let (e, _) = self.error(&ideal)?;
        let first = k.inverse([target[0] - e[0], target[1] - e[1], target[2] - e[2]], c).ok_or_else(singular)?;
        let mut best = (first, f64::INFINITY);
        let mut x = first;
        for i in -half..=half {
            x[0] = first[0] + f64::from(i) * spacing;
            for j in -half..=half {
                x[1] = first[1] + f64::from(j) * spacing;
                for l in -half..=half {
                    x[2] = first[2] + f64::from(l) * spacing;
                    let p = self.deformed(k, &x)?;
                    let d = (p[0] - target[0]).powi(2) + (p[1] - target[1]).powi(2) + (p[2] - target[2]).powi(2);
                    if d < best.1 {
                        best = (x, d);
                    }
                }
            }
        }
        Ok((best.0, best.1.sqrt()))
    }
}

/// The corrected command at one setting of the rotary axes: with them
/// fixed the ideal tip is affine in the linear commands, `p0 + J·x`, so the
/// kinematics are worked out once and Newton needs only the error model.
#[derive(Clone, Debug)]
pub struct Corrector<'m> {
    command: [f64; 6],
    p0: [f64; 3],
    j: [[f64; 3]; 3],
    functions: [&'m AxisError; 3],
}

impl<'m> Corrector<'m> {
    /// For the rotary angles (and the other axes) of `c`.
    pub fn new(model: &'m ErrorModel, k: &Kinematics, c: &[f64; 6]) -> Result<Corrector<'m>, Error> {
        let mut command = *c;
        command[..3].fill(0.0);
        let j = k.linear_jacobian(&command).ok_or_else(singular)?;
        let p0 = k.forward(&command);
        let function = |axis: usize| model.function(axis, c[4]);
        Ok(Corrector { command, p0, j, functions: [function(0)?, function(1)?, function(2)?] })
    }

    /// Whether `c`'s rotary angles are this corrector's.
    pub fn fits(&self, c: &[f64; 6]) -> bool {
        c[3..] == self.command[3..]
    }

    /// The command whose deformed tip lands on `target` (see
    /// [`ErrorModel::correct`]).
    pub fn correct(&self, target: [f64; 3]) -> Result<([f64; 6], f64), Error> {
        let (p0, j) = (self.p0, self.j);
        let mut x = solve3(j, [target[0] - p0[0], target[1] - p0[1], target[2] - p0[2]]).ok_or_else(singular)?;
        let mut residual = f64::INFINITY;
        for _ in 0..20 {
            let mut f: [f64; 3] =
                std::array::from_fn(|i| p0[i] + j[i][0] * x[0] + j[i][1] * x[1] + j[i][2] * x[2] - target[i]);
            let mut jj = j;
            for (a, function) in self.functions.iter().enumerate() {
                let (e, s) = (function.polynomial.at(x[a]), function.polynomial.slope(x[a]));
                for i in 0..3 {
                    f[i] += e[i];
                    jj[i][a] += s[i];
                }
            }
            residual = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
            if residual < 1e-7 {
                break;
            }
            let step = solve3(jj, f).ok_or_else(singular)?;
            for a in 0..3 {
                x[a] -= step[a];
            }
        }
        if residual >= 1e-6 {
            return Err(Error::new(
                ErrorKind::NotConverged,
                format!("the corrected command did not converge ({residual:.3e} mm left)"),
            ));
        }
        let mut out = self.command;
        out[..3].copy_from_slice(&x);
        Ok((out, residual))
    }
}
