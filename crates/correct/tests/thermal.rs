//! The thermal model: fitted to measurements shaped like the paper's, and
//! the corrected command by Newton and by the paper's grid search.

use kezuri_correct::kinematics::Kinematics;
use kezuri_correct::thermal::{fit, Measurement};
use kezuri_correct::ErrorKind;
use kezuri_geom::SplitMix64;

/// The paper's drift at B 0 and -90: X moves ~50 µm off in X and 0–50 µm
/// in Y across the travel; Z moves within 20 µm; Y small.
fn truth(axis: usize, b: f64, c: f64) -> [f64; 3] {
    let s = if b == 0.0 { 1.0 } else { 0.8 };
    match axis {
        0 => [s * 0.050, s * 0.050 * (c + 22.0) / 20.0, 0.002 * (c / 20.0).powi(2)],
        1 => [0.001, 0.003 * c / 50.0, 0.0],
        _ => [s * 0.015 * ((c + 74.0) / 20.0), 0.0, -0.018 + 0.0005 * c * c / 100.0],
    }
}

fn measurements(noise: f64, seed: u64) -> Vec<Measurement> {
    let mut rng = SplitMix64::new(seed);
    let mut out = Vec::new();
    for b in [0.0, -90.0] {
        for axis in 0..3 {
            let (from, to) = match axis {
                0 => (-22.0, -2.0),
                1 => (-10.0, 10.0),
                _ => (-94.0, -74.0),
            };
            for k in 0..=5 {
                let c = from + (to - from) * k as f64 / 5.0;
                let e = truth(axis, b, c).map(|v| v + noise * (2.0 * rng.next_f64() - 1.0));
                out.push(Measurement { axis, b_deg: b, command: c, error: e });
            }
        }
    }
    out
}

fn mill_turn() -> Kinematics {
    Kinematics::mill_turn([0.0, 0.0, 120.0], [0.0, 0.0, 70.0])
}

#[test]
fn the_fit_recovers_the_drift_and_chooses_a_degree() {
    let model = fit(&measurements(0.0, 1), None).unwrap();
    assert_eq!(model.functions.len(), 6);
    for f in &model.functions {
        for k in 0..=20 {
            let c = match f.axis {
                0 => -22.0 + k as f64,
                1 => -10.0 + k as f64,
                _ => -94.0 + k as f64,
            };
            let (got, want) = (f.polynomial.at(c), truth(f.axis, f.b_deg, c));
            assert!(
                (0..3).all(|i| (got[i] - want[i]).abs() < 1e-9),
                "axis {} B {}: {got:?} vs {want:?}",
                f.axis,
                f.b_deg
            );
        }
        // X needs degree 2 (its Z error is quadratic); a line would not do.
        if f.axis == 0 {
            assert_eq!(f.degree, 2, "{f:?}");
        }
    }
    // Too few measurements for a degree asked.
    assert_eq!(fit(&measurements(0.0, 1), Some(6)).unwrap_err().kind, ErrorKind::TooFewMeasurements);
}

#[test]
fn newton_lands_the_warm_tip_within_a_nanometre_and_the_grid_agrees_within_its_spacing() {
    let k = mill_turn();
    let model = fit(&measurements(0.0002, 2), None).unwrap();
    let mut rng = SplitMix64::new(9);
    let mut largest: f64 = 0.0;
    for b in [0.0, -90.0] {
        for _ in 0..200 {
            let c = [
                -22.0 + 20.0 * rng.next_f64(),
                -10.0 + 20.0 * rng.next_f64(),
                -94.0 + 20.0 * rng.next_f64(),
                0.0,
                b,
                0.0,
            ];
            let target = k.forward(&c);
            let uncorrected = model.deformed(&k, &c).unwrap();
            let miss = (0..3).map(|i| (uncorrected[i] - target[i]).powi(2)).sum::<f64>().sqrt();
            largest = largest.max(miss);
            let (x, residual) = model.correct(&k, target, &c).unwrap();
            assert!(residual < 1e-6, "{residual}");
            let landed = model.deformed(&k, &x).unwrap();
            assert!((0..3).all(|i| (landed[i] - target[i]).abs() < 1e-6), "{landed:?} vs {target:?}");
            assert_eq!((x[4], x[5]), (b, 0.0));
        }
    }
    assert!(largest > 0.04, "uncorrected up to {largest} mm");
    // The grid search: 1 µm spacing, ±50 candidates per axis.
    for b in [0.0, -90.0] {
        let c = [-12.0, 3.0, -80.0, 0.0, b, 0.0];
        let target = k.forward(&c);
        let (newton, _) = model.correct(&k, target, &c).unwrap();
        let (grid, miss) = model.correct_by_grid(&k, target, &c, 0.001, 50).unwrap();
        assert!((0..3).all(|i| (grid[i] - newton[i]).abs() <= 0.001), "{grid:?} vs {newton:?}");
        assert!(miss < 0.001, "{miss}");
    }
}

#[test]
fn a_model_without_the_angle_is_a_clear_error() {
    let k = mill_turn();
    let model = fit(&measurements(0.0, 1), None).unwrap();
    let c = [-12.0, 3.0, -80.0, 0.0, -45.0, 0.0];
    let e = model.correct(&k, k.forward(&c), &c).unwrap_err();
    assert_eq!(e.kind, ErrorKind::NoErrorFunction);
    assert!(e.to_string().contains("no error function for axis X at B -45°"));
}

#[test]
fn a_programs_moves_land_on_their_targets_and_the_extrapolated_ones_are_counted() {
    use kezuri_correct::thermal::{correct_moves, Solver};
    use kezuri_geom::{Axes, Move, MoveKind};
    let k = mill_turn();
    let model = fit(&measurements(0.0, 1), None).unwrap();
    let at = |x: f64, z: f64| Axes { x, z, ..Axes::ZERO };
    let step = |kind: MoveKind, end: Axes, line: u32| Move { kind, end, line, ..Move::default() };
    let moves = [
        step(MoveKind::Feed, at(-12.0, -80.0), 1),
        step(MoveKind::Dwell(1.0), at(-12.0, -80.0), 2),
        // Beyond the measured travel of Z (-94 to -74).
        step(MoveKind::Feed, at(-12.0, -60.0), 3),
        step(MoveKind::Home, at(0.0, 0.0), 4),
    ];
    let c = correct_moves(&model, &k, &moves, Solver::Newton).unwrap();
    assert_eq!(c.ends.len(), moves.len());
    assert_eq!((c.ends[1], c.ends[3]), (moves[1].end, moves[3].end));
    for i in [0, 2] {
        let (target, landed) = (k.forward(&moves[i].end.xyzabc()), model.deformed(&k, &c.ends[i].xyzabc()));
        let landed = landed.unwrap();
        assert!((0..3).all(|j| (landed[j] - target[j]).abs() < 1e-6), "{landed:?} vs {target:?}");
    }
    let s = c.summary;
    assert_eq!((s.checked, s.extrapolated, s.first_extrapolated_line), (2, 1, Some(3)));
    assert!(s.largest_correction > 0.01 && s.largest_residual < 1e-6, "{s:?}");
    // The model knows no B 45: the error says which move.
    let tilted = [step(MoveKind::Feed, Axes { b: 45.0, ..at(-12.0, -80.0) }, 7)];
    let e = correct_moves(&model, &k, &tilted, Solver::Newton).unwrap_err();
    assert_eq!((e.kind, e.line), (ErrorKind::NoErrorFunction, Some(7)));
}
