//! Forward kinematics and its ideal inverse on a 3-axis mill and the thermal and wear report's
//! Swiss-type mill-turn.

use kezuri_correct::kinematics::{Axis, Kinematics, Motion};
use kezuri_geom::SplitMix64;

fn linear(index: usize, direction: [f64; 3]) -> Axis {
    Axis { index, motion: Motion::Linear { direction } }
}

/// The paper's machine: the turning side carries Y and C, the milling
/// spindle X, Z and a B tilt about Y; a 50 mm tool below the B pivot.
fn mill_turn() -> Kinematics {
    Kinematics::mill_turn([0., 0., 120.], [0.0, 0.0, 70.0])
}

fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() < tol)
}

#[test]
fn a_mill_puts_the_tip_where_the_program_says() {
    let m = Kinematics::mill();
    m.check().unwrap();
    assert_eq!(m.forward(&[1.5, -2.0, 3.25, 0.0, 0.0, 0.0]), [1.5, -2.0, 3.25]);
    let c = m.inverse([4.0, 5.0, -6.0], &[0.0; 6]).unwrap();
    assert!(close([c[0], c[1], c[2]], [4.0, 5.0, -6.0], 1e-12));
}

#[test]
fn the_mill_turn_by_hand() {
    let m = mill_turn();
    m.check().unwrap();
    // All axes at zero: the tip where the machine file puts it.
    assert!(close(m.forward(&[0.0; 6]), [0.0, 0.0, 70.0], 1e-12));
    // B -90 about +Y through (0, 0, 120): the tip 50 mm below the pivot
    // swings to 50 mm along +X of it.
    assert!(close(m.forward(&[0.0, 0.0, 0.0, 0.0, -90.0, 0.0]), [50.0, 0.0, 120.0], 1e-9));
    // Y on the work side: the part moves -Y, the tool is at +Y on it.
    assert!(close(m.forward(&[0.0, 7.0, 0.0, 0.0, 0.0, 0.0]), [0.0, 7.0, 70.0], 1e-12));
    // C90 turns the part -90°: the tool at +X of the machine is at +Y of the part.
    assert!(close(m.forward(&[10.0, 0.0, 0.0, 0.0, 0.0, 90.0]), [0.0, 10.0, 70.0], 1e-9));
    // The tool axis, from the tip toward the pivot: up at B 0, toward -X at
    // B -90 (the tip swung to +X), and turned with the part by C.
    assert!(close(m.tool_axis(&[0.0; 6]), [0.0, 0.0, 1.0], 1e-12));
    assert!(close(m.tool_axis(&[0.0, 0.0, 0.0, 0.0, -90.0, 0.0]), [-1.0, 0.0, 0.0], 1e-12));
    assert!(close(m.tool_axis(&[0.0, 0.0, 0.0, 0.0, -90.0, 90.0]), [0.0, -1.0, 0.0], 1e-12));
}

#[test]
fn the_inverse_undoes_the_forward_at_every_indexed_angle() {
    let m = mill_turn();
    let mut rng = SplitMix64::new(5);
    for b in [0.0, -15.0, -90.0, 30.0, 105.0] {
        for c in [0.0, 90.0, 212.5] {
            for _ in 0..50 {
                let mut cmd = [0.0, 0.0, 0.0, 0.0, b, c];
                for v in cmd.iter_mut().take(3) {
                    *v = 250.0 * rng.next_f64() - 125.0;
                }
                let tip = m.forward(&cmd);
                let back = m.inverse(tip, &[0.0, 0.0, 0.0, 0.0, b, c]).unwrap();
                assert!(close([back[0], back[1], back[2]], [cmd[0], cmd[1], cmd[2]], 1e-9), "{cmd:?} → {back:?}");
                assert_eq!((back[4], back[5]), (b, c));
            }
        }
    }
}

#[test]
fn machines_that_are_not_are_refused() {
    let mut m = mill_turn();
    m.tool.push(linear(0, [1., 0., 0.]));
    assert!(m.check().unwrap_err().message.contains("axis X is on the machine twice"));
    let mut m = mill_turn();
    m.work.retain(|a| a.index != 1);
    assert!(m.check().unwrap_err().message.contains("no Y axis"));
    let mut m = mill_turn();
    m.tool[0] = linear(0, [0., 0., 1.]);
    assert!(m.check().unwrap_err().message.contains("do not span space"));
    let mut m = mill_turn();
    m.tool[1] = linear(2, [0., 0., 2.]);
    assert!(m.check().unwrap_err().message.contains("unit vector"));
    let mut m = mill_turn();
    m.tool[2] = linear(4, [1., 0., 0.]);
    assert!(m.check().unwrap_err().message.contains("axis B must be rotary"));
}
