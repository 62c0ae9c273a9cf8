//! Measurements as the measuring program takes them (`kezuri thermal
//! measure` and `fit`): the edge of each stop from the two line sensors,
//! the axis letters and states a measurements file names, and the drift,
//! warm less cold.

use super::{Measurement, SAME_ANGLE};
use crate::kinematics::AXES;
use crate::{Error, ErrorKind};

/// Commands closer than this are the same stop, mm.
const SAME_COMMAND: f64 = 1e-6;

/// The linear axis (0 X, 1 Y, 2 Z) of the letter a measurements file
/// names it by (either case).
pub fn linear_axis(letter: &str) -> Result<usize, Error> {
    let letter = letter.to_ascii_uppercase();
    ["X", "Y", "Z"]
        .iter()
        .position(|x| *x == letter)
        .ok_or_else(|| Error::new(ErrorKind::BadMeasurement, format!("'{letter}' is not a linear axis (X, Y or Z)")))
}

/// Whether a measurement's state, `cold` or `warm` (either case), is warm.
pub fn is_warm(state: &str) -> Result<bool, Error> {
    match state.to_ascii_lowercase().as_str() {
        "cold" => Ok(false),
        "warm" => Ok(true),
        other => Err(Error::new(ErrorKind::BadMeasurement, format!("state '{other}' is neither cold nor warm"))),
    }
}

/// The error of one stop along `axis` (0 X, 1 Y, 2 Z) at `command`: the
/// tool's edge in space from sensor 1's (X, Z) and sensor 2's (Y, Z), the
/// mean of their Z, less the command along its axis.
pub fn stop_error(axis: usize, command: f64, sensor_1: [f64; 2], sensor_2: [f64; 2]) -> [f64; 3] {
    let mut edge = [sensor_1[0], sensor_2[0], 0.5 * (sensor_1[1] + sensor_2[1])];
    edge[axis] -= command;
    edge
}

/// The drift: each warm measurement (its flag true) less the cold one at
/// the same axis, B angle and command, in order. The sensors' own places
/// cancel. Fails with the index of the first warm measurement that has no
/// cold one.
pub fn warm_less_cold(measurements: &[(Measurement, bool)]) -> Result<Vec<Measurement>, (usize, Error)> {
    let same = |p: &Measurement, q: &Measurement| {
        p.axis == q.axis && (p.b_deg - q.b_deg).abs() < SAME_ANGLE && (p.command - q.command).abs() < SAME_COMMAND
    };
    let mut out = Vec::new();
    for (k, (m, _)) in measurements.iter().enumerate().filter(|(_, (_, warm))| *warm) {
        let Some((cold, _)) = measurements.iter().find(|(c, warm)| !warm && same(c, m)) else {
            let message = format!("no cold measurement of axis {} at {} mm, B {}°", AXES[m.axis], m.command, m.b_deg);
            return Err((k, Error::new(ErrorKind::NoColdMeasurement, message)));
        };
        out.push(Measurement { error: std::array::from_fn(|k| m.error[k] - cold.error[k]), ..*m });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(axis: usize, command: f64, error: [f64; 3]) -> Measurement {
        Measurement { axis, b_deg: 0.0, command, error }
    }

    #[test]
    fn drift_is_warm_less_cold_at_the_same_stop() {
        let rows =
            [(at(0, 1.0, [0.1, 0.2, 0.3]), false), (at(0, 2.0, [0.0; 3]), false), (at(0, 1.0, [0.15, 0.2, 0.4]), true)];
        let d = warm_less_cold(&rows).unwrap();
        assert_eq!(d.len(), 1);
        assert_eq!(d[0].command, 1.0);
        assert!((d[0].error[0] - 0.05).abs() < 1e-12 && d[0].error[1].abs() < 1e-12);
        let (k, e) = warm_less_cold(&[(at(1, 3.0, [0.0; 3]), true)]).unwrap_err();
        assert_eq!(k, 0);
        assert_eq!(e.kind, ErrorKind::NoColdMeasurement);
        assert_eq!(e.to_string(), "no cold measurement of axis Y at 3 mm, B 0°");
    }

    #[test]
    fn letters_states_and_the_edge_of_a_stop() {
        assert_eq!(linear_axis("z").unwrap(), 2);
        assert_eq!(linear_axis("q").unwrap_err().to_string(), "'Q' is not a linear axis (X, Y or Z)");
        assert!(is_warm("WARM").unwrap() && !is_warm("cold").unwrap());
        assert_eq!(is_warm("Hot").unwrap_err().to_string(), "state 'hot' is neither cold nor warm");
        assert_eq!(stop_error(0, 10.0, [10.5, 1.0], [0.25, 3.0]), [0.5, 0.25, 2.0]);
    }
}
