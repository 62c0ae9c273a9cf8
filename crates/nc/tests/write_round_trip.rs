//! The G-code writer's round trip: a generated toolpath written in every
//! dialect, parsed and run again, makes the same motions:
//! `interp(parse(program(toolpath))) ≈ toolpath`.

mod common;

use std::f64::consts::TAU;

use common::writer::{point, run, same_motion, Path};
use kezuri_geom::{Coolant, Plane, Spindle, Toolpath};
use kezuri_nc::write::{program, Dialect, WriteOptions};
use proptest::prelude::*;

/// One generated step after the first rapid.
#[derive(Clone, Debug)]
enum Step {
    Rapid([f64; 3]),
    Feed([f64; 3], f64),
    Probe([f64; 3], f64),
    Dwell(f64),
    /// Plane, ccw, radius, direction of the centre from the start, sweep
    /// (`None`: a full circle), rise along the normal, feed.
    Arc(Plane, bool, f64, f64, Option<f64>, f64, f64),
}

/// Spindle, coolant and tool before a step.
#[derive(Clone, Debug)]
struct State {
    spindle: Spindle,
    speed: f64,
    coolant: Coolant,
    tool: Option<u32>,
}

fn delta() -> impl Strategy<Value = f64> {
    prop_oneof![1 => Just(0.0), 3 => (0.01f64..80.0, any::<bool>()).prop_map(|(m, neg)| if neg { -m } else { m })]
}

/// A displacement that moves at least one linear axis.
fn displacement() -> impl Strategy<Value = [f64; 3]> {
    [delta(), delta(), delta()].prop_map(|mut d| {
        if d.iter().all(|&v| v == 0.0) {
            d[0] = 1.0;
        }
        d
    })
}

fn feed() -> impl Strategy<Value = f64> {
    prop_oneof![Just(500.0), 1.0f64..5000.0]
}

fn plane() -> impl Strategy<Value = Plane> {
    prop_oneof![Just(Plane::Xy), Just(Plane::Zx), Just(Plane::Yz)]
}

fn step() -> impl Strategy<Value = Step> {
    prop_oneof![
        displacement().prop_map(Step::Rapid),
        (displacement(), feed()).prop_map(|(d, f)| Step::Feed(d, f)),
        (displacement(), feed()).prop_map(|(d, f)| Step::Probe(d, f)),
        (0.0f64..10.0).prop_map(Step::Dwell),
        (
            plane(),
            any::<bool>(),
            1.0f64..60.0,
            0.0..TAU,
            prop_oneof![1 => Just(None), 4 => (0.05..TAU - 0.05).prop_map(Some)],
            prop_oneof![Just(0.0), -5.0f64..5.0],
            feed()
        )
            .prop_map(|(p, ccw, r, dir, sweep, rise, f)| Step::Arc(p, ccw, r, dir, sweep, rise, f)),
    ]
}

fn state() -> impl Strategy<Value = State> {
    let spindle = prop_oneof![Just(Spindle::Off), Just(Spindle::Cw), Just(Spindle::Ccw)];
    (spindle, prop_oneof![Just(10000.0), 0.0f64..30000.0], any::<(bool, bool)>(), proptest::option::of(0u32..4))
        .prop_map(|(spindle, speed, (mist, flood), tool)| State {
            spindle,
            speed,
            coolant: Coolant { mist, flood },
            tool,
        })
}

fn build(first: [f64; 3], steps: &[(Step, State)]) -> Toolpath {
    let mut p = Path::default();
    p.rapid(first[0], first[1], first[2]);
    for (step, state) in steps {
        p.spindle(state.spindle, state.speed).coolant(state.coolant.mist, state.coolant.flood);
        let a = p.at;
        match *step {
            Step::Rapid(d) => {
                // Tool changes come before rapids, as in real programs.
                if let Some(t) = state.tool {
                    p.tool(t);
                }
                p.rapid(a.x + d[0], a.y + d[1], a.z + d[2]);
            }
            Step::Feed(d, f) => {
                p.feed(a.x + d[0], a.y + d[1], a.z + d[2], f);
            }
            Step::Probe(d, f) => {
                p.probe(a.x + d[0], a.y + d[1], a.z + d[2], f);
            }
            Step::Dwell(s) => {
                p.dwell(s);
            }
            Step::Arc(plane, ccw, r, dir, sweep, rise, f) => {
                let (i, j, n) = plane.axes();
                let s = a.xyz();
                let mut center = s;
                center[i] += r * dir.cos();
                center[j] += r * dir.sin();
                let mut end = s;
                if let Some(sweep) = sweep {
                    let angle = dir + std::f64::consts::PI + if ccw { sweep } else { -sweep };
                    end[i] = center[i] + r * angle.cos();
                    end[j] = center[j] + r * angle.sin();
                }
                end[n] += rise;
                p.feed = f;
                p.arc(plane, ccw, center, end);
            }
        }
    }
    p.path.clone()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn round_trip_through_parse_and_interp(
        first in point(),
        steps in proptest::collection::vec((step(), state()), 0..40),
        digits in 2u8..=5,
        numbered in proptest::option::of(1u32..100),
    ) {
        let path = build(first, &steps);
        for d in Dialect::ALL {
            let options = WriteOptions { dialect: d, digits, line_numbers: numbered, ..WriteOptions::default() };
            let text = program(&path, &options).map_err(|e| TestCaseError::fail(e.to_string()))?;
            let (outcome, messages) = run(&text, d);
            prop_assert!(outcome.completed, "{d}: the run did not complete: {messages:#?}\n{text}");
            let decimal: Vec<&String> = messages.iter().filter(|m| m.contains("decimal point")).collect();
            prop_assert!(decimal.is_empty(), "{d}: {decimal:#?}\n{text}");
            let errors: Vec<&String> = messages.iter().filter(|m| m.contains(": error:")).collect();
            prop_assert!(errors.is_empty(), "{d}: {errors:#?}\n{text}");
            if let Err(e) = same_motion(&path, &outcome.toolpath, digits, d) {
                return Err(TestCaseError::fail(format!("{d}: {e}\n{text}")));
            }
        }
    }
}
