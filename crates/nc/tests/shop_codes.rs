//! Codes real programs use that each control reads its own way: the arc
//! radius tolerance of each dialect, `G65` arguments with a fraction on M,
//! LinuxCNC's `##n`, `G53` with `G31`, Haas `G101`/`G100`. The LinuxCNC
//! expectations were confirmed with `rs274 -g` (LinuxCNC 2.9.0~pre1), as
//! `crates/cli/tests/linuxcnc_codes.rs` does again where rs274 is installed.

use kezuri_geom::MoveKind;
use kezuri_nc::interp::{Control, CoordSettings, IntegerInput, Settings};
use kezuri_nc::Dialect;

mod common;

fn settings(dialect: Dialect) -> Settings {
    let units = matches!(dialect, Dialect::LinuxCnc | Dialect::Grbl);
    let control = match dialect {
        Dialect::LinuxCnc | Dialect::Grbl => Control::LinuxCnc,
        Dialect::Haas | Dialect::HaasLathe => Control::Haas,
        Dialect::Fanuc | Dialect::FanucLathe => Control::Fanuc,
    };
    Settings {
        dialect,
        integer_input: if units { IntegerInput::Units } else { IntegerInput::Increments },
        coords: CoordSettings { control, ..CoordSettings::default() },
        ..Settings::default()
    }
}

/// A G2 from X0 Y0 to `x` with its centre at I `i`: whether it runs.
fn arc_runs(x: &str, i: &str, settings: &Settings) -> bool {
    let text = format!("G21 G90 G17\nG0 X0. Y0. Z0.\nF100.\nG2 X{x} Y0. I{i} J0.\nM30\n");
    let run = common::run("a.nc", &text, settings);
    match run.error() {
        None => true,
        Some(d) => {
            assert!(d.message.contains("off its circle"), "{x} {i}: {}", d.message);
            false
        }
    }
}

#[test]
fn each_control_has_its_own_arc_radius_tolerance() {
    let lcnc = settings(Dialect::LinuxCnc);
    // rs274 runs a 0.0254 mm difference on a 50 mm radius (0.05 %), and
    // draws the arc to the end as given.
    let t = common::run(
        "a.ngc",
        "G21 G90 G17\nG0 X0 Y0 Z0\nF100\nG2 X100 Y0 I50.0127 J0\nG3 X0 Y0 I-49.9873 J0\nM2\n",
        &lcnc,
    )
    .path();
    assert_eq!(t.moves.iter().filter(|m| matches!(m.kind, MoveKind::Arc(_))).count(), 2);
    // rs274: refused past 0.02·√2 mm where that is also past 0.1 % of the
    // radius, and past 100 times 0.02·√2 mm whatever the radius.
    for (x, i, runs) in [
        ("10", "5.0141", true),
        ("10", "5.0142", false),
        ("100", "50.0142", true),
        ("100", "50.06", false),
        ("0.01", "0.0193", true),
        ("10000", "5001.41", true),
        ("10000", "5001.42", false),
    ] {
        assert_eq!(arc_runs(x, i, &lcnc), runs, "LinuxCNC X{x} I{i}");
    }
    // Fanuc: parameter 3410, 0.02 mm unless the machine file says.
    let fanuc = settings(Dialect::Fanuc);
    assert!(!arc_runs("100.", "50.0127", &fanuc));
    assert!(arc_runs("100.", "50.0127", &Settings { arc_tolerance: Some(0.03), ..fanuc.clone() }));
    assert!(arc_runs("10.", "5.009", &fanuc));
    // GRBL: past 0.005 mm and 0.1 % of the radius.
    let grbl = settings(Dialect::Grbl);
    assert!(!arc_runs("10", "5.005", &grbl));
    assert!(arc_runs("100", "50.0127", &grbl));
}

#[test]
fn a_g65_argument_m_may_have_a_fraction() {
    // `M0.070` is argument M, #13; other letters too take fractions.
    let text =
        "O1000\nG65 P9010 M0.070 A1.5\nG66.1 P9010 M2.5 A3.\nG00 M0.25 A0.5\nG67\nM30\nO9010\nG00 X#13 Y#1\nM99\n";
    let t = common::run("m.nc", text, &settings(Dialect::Fanuc)).path();
    let ends: Vec<[f64; 2]> = t.moves.iter().map(|m| [m.end.x, m.end.y]).collect();
    assert_eq!(ends, [[0.07, 1.5], [2.5, 3.0], [0.25, 0.5]]);
    // Outside a macro call it is no M code.
    let run = common::run("m.nc", "O1000\nG00 X1. M0.070\nM30\n", &settings(Dialect::Fanuc));
    assert_eq!(run.message(), "M0.07 is not an M code");
}

#[test]
fn linuxcnc_reads_hash_hash_n_as_an_indirect_parameter() {
    // rs274: STRAIGHT_TRAVERSE(7.5, 3, …), then (2, 3, …).
    let text = "G21 G90\n#1=2\n#2=7.5\n#3=3\nG0 X##1 Y#3\n##1=2\nG0 X#2\nM2\n";
    let t = common::linuxcnc::path(text);
    let ends: Vec<[f64; 2]> = t.moves.iter().map(|m| [m.end.x, m.end.y]).collect();
    assert_eq!(ends, [[7.5, 3.0], [2.0, 3.0]]);
    // Three deep: #[#[#1]].
    let t = common::linuxcnc::path("#1=2\n#2=3\n#3=4.5\nG0 X###1\nM2\n");
    assert_eq!(t.moves[0].end.x, 4.5);
}

#[test]
fn g53_with_g31_skips_to_a_machine_position_on_fanuc_and_haas() {
    let mut s = settings(Dialect::Fanuc);
    s.work_offsets[0] = kezuri_geom::Axes { x: 100.0, z: -200.0, ..kezuri_geom::Axes::ZERO };
    s.tool_lengths.insert(1, 50.0);
    // After mojimould/mould_moji, Created_NC_Programs/sub_programs/O919100.nc
    // (tool length measurement): `G91 G53 G31 P2 Z-#06 F#654`.
    let text = "O1000\nG90 G54 G00 X0. Y0. Z10.\nG43 H1 Z10.\nG53 G31 Z-300. F200.\n#100=#5063\nG91 G53 G31 P2 Z-5. F100.\nG90 G00 X#100\nM30\n";
    let run = common::run("s.nc", text, &s);
    let o = run.completed();
    let probes: Vec<[f64; 3]> =
        o.toolpath.moves.iter().filter(|m| m.kind == MoveKind::Probe).map(|m| [m.end.x, m.end.y, m.end.z]).collect();
    // The gauge line to machine Z-300: the tip 50 mm below; then 5 mm down.
    assert_eq!(probes, [[100.0, 0.0, -350.0], [100.0, 0.0, -355.0]]);
    // #5063: the skip position in work coordinates with the length offset,
    // -350 + 200 + 50 = -100; X-100 in G54 is machine X0.
    assert_eq!(o.toolpath.moves.last().unwrap().end.x, 0.0);
    assert!(o.diagnostics.iter().any(|d| d.message.contains("G53 under G91")));
    // Haas too; LinuxCNC stops ("Must use g0 or g1 with g53").
    common::run("s.nc", "G53 G31 Z-300. F200.\nM30\n", &settings(Dialect::Haas)).completed();
    let e = common::linuxcnc::error("G53 G38.2 Z-20 F100\nM2\n");
    assert!(e.contains("Must use G0 or G1 with G53"), "{e}");
}

#[test]
fn haas_g101_mirrors_the_named_axes_about_the_work_zero() {
    // Haas 96-8000 (June 1999), G101: "Mirror image will reflect
    // programmed motion around your work coordinate zero point"; one axis
    // of the plane mirrored reverses G02/G03.
    let text = "O1000\nG90 G54 G17\nG00 X0. Y0. Z5.\nG101 X5.\nG01 X10. Y5. F100.\nG02 X20. Y5. R5.\nG100 X0.\nG00 X10. Y5.\nM30\n";
    let t = common::run("m.nc", text, &settings(Dialect::Haas)).path();
    let ends: Vec<[f64; 2]> = t.moves.iter().map(|m| [m.end.x, m.end.y]).collect();
    assert_eq!(ends, [[0.0, 0.0], [-10.0, 5.0], [-20.0, 5.0], [10.0, 5.0]]);
    assert!(matches!(t.moves[2].kind, MoveKind::Arc(a) if a.ccw));
    let run = common::run("m.nc", text, &settings(Dialect::Fanuc));
    assert!(run.message().contains("Haas's mirror image"), "{}", run.message());
}

/// The point at `t` of the Bézier curve with control points `p`.
fn bezier(p: &[[f64; 2]], t: f64) -> [f64; 2] {
    let s = 1.0 - t;
    let w: Vec<f64> = if p.len() == 3 {
        vec![s * s, 2.0 * s * t, t * t]
    } else {
        vec![s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t]
    };
    let mut q = [0.0; 2];
    for (c, wk) in p.iter().zip(w) {
        q[0] += wk * c[0];
        q[1] += wk * c[1];
    }
    q
}

/// How far point `q` is from the polyline through `pts`.
fn off_polyline(q: [f64; 2], pts: &[[f64; 2]]) -> f64 {
    pts.windows(2)
        .map(|s| {
            let (a, b) = (s[0], s[1]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let len2 = dx * dx + dy * dy;
            let t = if len2 == 0.0 { 0.0 } else { (((q[0] - a[0]) * dx + (q[1] - a[1]) * dy) / len2).clamp(0.0, 1.0) };
            (q[0] - a[0] - t * dx).hypot(q[1] - a[1] - t * dy)
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn linuxcnc_splines_are_feed_moves_within_a_micrometre_of_the_curve() {
    // G5.1 from (0, 0), control point (0, 0) + I J, end X Y; then G5 from
    // there with I J P Q, and a G5 without I J leaving along the last P Q.
    let text = "G21 G90 G17\nG0 X0 Y0 Z0\nF100\nG5.1 X10 Y0 I5 J5\nG5 X20 Y5 I2 J-3 P-1 Q4\nG5 X30 Y0 P2 Q2\nX31\nM2\n";
    let t = common::linuxcnc::path(text);
    let feeds: Vec<(u32, [f64; 2])> =
        t.moves.iter().filter(|m| m.kind == MoveKind::Feed).map(|m| (m.line, [m.end.x, m.end.y])).collect();
    let curve = |line: u32, start: [f64; 2]| -> Vec<[f64; 2]> {
        std::iter::once(start).chain(feeds.iter().filter(|f| f.0 == line).map(|f| f.1)).collect()
    };
    let quad = [[0.0, 0.0], [5.0, 5.0], [10.0, 0.0]];
    let cubic = [[10.0, 0.0], [12.0, -3.0], [19.0, 9.0], [20.0, 5.0]];
    let tangent = [[20.0, 5.0], [21.0, 1.0], [32.0, 2.0], [30.0, 0.0]];
    for (line, p, steps) in [(4, &quad[..], 12.0), (5, &cubic[..], 16.0), (6, &tangent[..], 16.0)] {
        let pts = curve(line, p[0]);
        assert_eq!(*pts.last().unwrap(), p[p.len() - 1], "line {line} ends at X Y");
        // LinuxCNC's canon makes biarcs through the curve at 12 (G5.1) or
        // 16 (G5) equal steps: each of those points is within 0.001 mm.
        for k in 0..=steps as u32 {
            let q = bezier(p, f64::from(k) / steps);
            assert!(off_polyline(q, &pts) <= 0.001 + 1e-12, "line {line} at {k}/{steps}: {q:?}");
        }
        // And so is the curve between the moves' ends, everywhere.
        for k in 0..=1000 {
            let q = bezier(p, f64::from(k) / 1000.0);
            assert!(off_polyline(q, &pts) <= 0.001 + 1e-9, "line {line} at {k}/1000");
        }
        assert!(pts.len() > 10 && pts.len() < 200, "line {line}: {} moves", pts.len() - 1);
    }
    // The spline is its block's motion only: `X31` moves in the mode before
    // it (G0 here), as rs274 2.9 moves it.
    assert!(t.moves.last().is_some_and(|m| m.kind == MoveKind::Rapid && m.end.x == 31.0));
    for (block, said) in [
        ("G5.1 X10 Y0 I5", "Must specify both I and J with G5.1"),
        ("G5 X10 Y0 I1 J1", "Must specify both P and Q with G5"),
        ("G5.1 X10 Y0 Z1 I5 J5", "Splines may not have motion in Z"),
        ("G18 G5.1 X10 I5 J5", "needs the XY plane"),
    ] {
        let e = common::linuxcnc::error(&format!("G21 G90 G17\nG0 X0 Y0 Z0\nF100\n{block}\nM2\n"));
        assert!(e.contains(said), "{block}: {e}");
    }
}

#[test]
fn haas_g12_and_g13_mill_circular_pockets() {
    // After the Haas manual's sample G12 (as in CodeNameMPC/CNClingish,
    // test.nc), in mm: D1 a 3 mm radius.
    let mut s = settings(Dialect::Haas);
    s.tool_radii.insert(1, 3.0);
    let text = "O0098\nG21 G90 G17 G54\nG00 X10. Y20. Z2.\nG12 I8. F300. Z-5. D01\nG00 Z2.\nG13 X50. I5. K14. Q4. Z-3. F300. D01\nG00 Z2.\nM30\n";
    let t = common::run("p.nc", text, &s).path();
    let moves: Vec<(char, [f64; 3])> = t.moves[1..]
        .iter()
        .map(|m| {
            let k = match m.kind {
                MoveKind::Rapid => 'r',
                MoveKind::Feed => 'f',
                MoveKind::Arc(a) if a.ccw => 'l',
                MoveKind::Arc(_) => 'c',
                _ => '?',
            };
            (k, [m.end.x, m.end.y, m.end.z])
        })
        .collect();
    #[rustfmt::skip]
    let want = [
        // G12: down at the centre, out on a half circle to 8 - 3 = 5 mm,
        // the circle clockwise, back to the centre.
        ('f', [10.0, 20.0, -5.0]), ('c', [15.0, 20.0, -5.0]), ('c', [15.0, 20.0, -5.0]), ('c', [10.0, 20.0, -5.0]),
        ('r', [10.0, 20.0, 2.0]),
        // G13 X50.: to the centre at rapid, then circles of 5, 9, 13, 14 less 3.
        ('r', [50.0, 20.0, 2.0]), ('f', [50.0, 20.0, -3.0]),
        ('l', [52.0, 20.0, -3.0]), ('l', [52.0, 20.0, -3.0]), ('l', [56.0, 20.0, -3.0]), ('l', [56.0, 20.0, -3.0]),
        ('l', [60.0, 20.0, -3.0]), ('l', [60.0, 20.0, -3.0]), ('l', [61.0, 20.0, -3.0]), ('l', [61.0, 20.0, -3.0]),
        ('l', [50.0, 20.0, -3.0]),
        ('r', [50.0, 20.0, 2.0]),
    ];
    assert_eq!(moves, want);
    // The full circles: about the centre, start = end.
    assert!(matches!(t.moves[3].kind, MoveKind::Arc(a) if a.center[0] == 10.0 && a.center[1] == 20.0));
    // L with G91: each pass Z deeper.
    let t = common::run("p.nc", "G21 G90 G17\nG00 X0. Y0. Z0.\nG91 G12 I5. Z-2. L3 F100.\nM30\n", &s).path();
    let depths: Vec<f64> = t.moves.iter().filter(|m| m.kind == MoveKind::Feed).map(|m| m.end.z).collect();
    assert_eq!(depths, [-2.0, -4.0, -6.0]);
    for (block, said) in [
        ("G12 I3. D01 F100.", "must be greater than the tool radius"),
        ("G12 I5. K4. Q1. F100.", "K (the finished radius) must be greater than I"),
        ("G12 I5. K8. F100.", "K and Q go together"),
        ("G12 K8. F100.", "needs I"),
    ] {
        let run = common::run("p.nc", &format!("G21 G90 G17\nG00 X0. Y0. Z0.\n{block}\nM30\n"), &s);
        assert!(run.message().contains(said), "{block}: {}", run.message());
    }
    let run = common::run("p.nc", "G12 I5. F100.\nM30\n", &settings(Dialect::Fanuc));
    assert!(run.message().contains("Haas's circular pocket"), "{}", run.message());
}
