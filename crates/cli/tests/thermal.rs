//! `kezuri thermal edge` on profiles written to files, as a user runs it.

mod common;

use common::{kezuri, ok, path};

/// A profile across a corner at (0.25, -1.5) mm, sides at 40° and -50°,
/// 1 µm of noise (a fixed pattern) and every 20th point 30 µm off.
fn profile() -> String {
    let mut t = String::from("x_mm,z_mm\n");
    for k in 0..=400 {
        let x = 0.25 - 1.0 + k as f64 * 0.005;
        let dx = x - 0.25;
        let side = if dx < 0.0 { dx * 40f64.to_radians().tan() } else { -dx * 50f64.to_radians().tan() };
        let noise = 0.001 * ((k * 7919 % 200) as f64 / 100.0 - 1.0);
        let outlier = if k % 20 == 7 { 0.03 } else { 0.0 };
        t += &format!("{x:.6},{:.6}\n", -1.5 + side + noise + outlier);
    }
    t
}

#[test]
fn the_edge_of_a_profile_file() {
    let dir = tempfile::tempdir().unwrap();
    let file = path(dir.path(), "sensor1.csv");
    std::fs::write(&file, profile()).unwrap();
    let v: serde_json::Value = serde_json::from_str(&ok(&kezuri(&["thermal", "edge", &file, "--json"]))).unwrap();
    let edge = [v["edge"][0].as_f64().unwrap(), v["edge"][1].as_f64().unwrap()];
    assert!((edge[0] - 0.25).hypot(edge[1] + 1.5) < 0.0005, "{v}");
    assert!((v["angle_deg"].as_f64().unwrap() - 90.0).abs() < 0.1, "{v}");
    assert!(v["rms_residual_mm"].as_f64().unwrap() < 0.001, "{v}");
    assert!(v["outliers"].as_u64().unwrap() >= 20, "{v}");
    let text = ok(&kezuri(&["thermal", "edge", &file]));
    assert!(text.contains("edge       x 0.2500") && text.contains("angle      89.99"), "{text}");
}

#[test]
fn bad_profiles_are_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let file = path(dir.path(), "p.csv");
    for (text, words) in [
        ("x_mm,z_mm\n0,0\n0.1,0.1\n0.2,abc\n", "p.csv: line 4, column 5: 'abc' is not a number (z_mm)"),
        ("x,z\n0,0\n", "p.csv: line 1: no column 'x_mm'"),
        ("x_mm,z_mm\n0,0\n1,1\n", "at least 6 points"),
        (
            "x_mm,z_mm\n0,0\n0.1,0.05\n0.2,0.1\n0.3,0.15\n0.4,0.2\n0.5,0.25\n0.6,0.3\n0.7,0.35\n",
            "the profile has no corner",
        ),
    ] {
        std::fs::write(&file, text).unwrap();
        let o = kezuri(&["thermal", "edge", &file]);
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.code() == Some(1) && e.contains(words), "{text}: {e}");
    }
}

#[test]
fn a_program_with_axes_the_machine_lacks_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let mill = path(dir.path(), "mill.toml");
    std::fs::write(&mill, "[kinematics]\ntool = [\"X\", \"Y\", \"Z\"]\n").unwrap();
    let turn = path(dir.path(), "turn.toml");
    std::fs::write(&turn, "[kinematics]\ntool = [\"X\", \"Z\", \"B\"]\nwork = [\"Y\", \"C\"]\n").unwrap();
    let o2007 = concat!(env!("CARGO_MANIFEST_DIR"), "/../../samples/o2007-thermal.nc");
    let o = kezuri(&["check", o2007, "--machine", &mill, "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let warnings = v["warnings"].to_string();
    assert!(warnings.contains("the machine has no B axis, and the program commands it (line 23)"), "{warnings}");
    let v: serde_json::Value =
        serde_json::from_slice(&kezuri(&["check", o2007, "--machine", &turn, "--json"]).stdout).unwrap();
    assert!(!v["warnings"].to_string().contains("the machine has no"), "{v}");
}

/// Cold and warm measurements shaped like the paper's drift: X moves 50 µm
/// off in X and 0–50 µm in Y across the travel (and a little in Z), Y
/// moves slightly, Z moves within 20 µm.
fn measurements() -> String {
    let near = [(-22.0, -2.0), (-10.0, 10.0), (-94.0, -74.0)];
    measurements_over(&[(0.0, near), (-90.0, near)])
}

/// [`measurements`] over the command ranges given per B angle.
fn measurements_over(ranges: &[(f64, [(f64, f64); 3])]) -> String {
    let truth = |axis: usize, b: f64, c: f64| -> [f64; 3] {
        let s = if b == 0.0 { 1.0 } else { 0.8 };
        match axis {
            0 => [s * 0.05, s * 0.05 * (c + 22.0) / 20.0, 0.002 * (c / 20.0).powi(2)],
            1 => [0.001, 0.003 * c / 50.0, 0.0],
            _ => [s * 0.015 * (c + 74.0) / 20.0, 0.0, -0.018 + 0.0005 * c * c / 100.0],
        }
    };
    let mut t = String::from("axis,command_mm,ex_mm,ey_mm,ez_mm,b_deg,state\n");
    for &(b, axes) in ranges {
        for (axis, (from, to)) in axes.into_iter().enumerate() {
            for k in 0..6 {
                let c = from + (to - from) * k as f64 / 5.0;
                let cold = [0.001 * k as f64, 0.0, -0.0005];
                let e = truth(axis, b, c);
                let name = ["X", "Y", "Z"][axis];
                t += &format!("{name},{c},{},{},{},{b},cold\n", cold[0], cold[1], cold[2]);
                t += &format!("{name},{c},{},{},{},{b},warm\n", cold[0] + e[0], cold[1] + e[1], cold[2] + e[2]);
            }
        }
    }
    t
}

#[test]
fn the_fit_of_cold_and_warm_measurements() {
    let dir = tempfile::tempdir().unwrap();
    let meas = path(dir.path(), "meas.csv");
    std::fs::write(&meas, measurements()).unwrap();
    let model = path(dir.path(), "model.json");
    let turn = path(dir.path(), "turn.toml");
    std::fs::write(&turn, "[kinematics]\ntool = [\"X\", \"Z\", \"B\"]\nwork = [\"Y\", \"C\"]\n").unwrap();
    ok(&kezuri(&["thermal", "fit", &meas, "--machine", &turn, "-o", &model]));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&model).unwrap()).unwrap();
    assert_eq!(v["machine"]["work"], serde_json::json!(["Y", "C"]));
    let functions = v["functions"].as_array().unwrap();
    assert_eq!(functions.len(), 6);
    for f in functions {
        // Y is linear in its command; X and Z carry a square.
        let want = if f["axis"] == "Y" { 1 } else { 2 };
        assert_eq!(f["degree"], want, "{f}");
        // At X -2 (the end of the travel) at B 0 the warm X errs 50 µm in X and Y.
        if f["axis"] == "X" && f["b_deg"] == 0.0 {
            let t = (-2.0 - f["center_mm"].as_f64().unwrap()) / f["scale_mm"].as_f64().unwrap();
            let at = |k: usize| {
                f["coefficients_mm"][k]
                    .as_array()
                    .unwrap()
                    .iter()
                    .rev()
                    .fold(0.0, |acc, a| acc * t + a.as_f64().unwrap())
            };
            assert!((at(0) - 0.05).abs() < 1e-9 && (at(1) - 0.05).abs() < 1e-9, "{f}");
        }
    }
}

#[test]
fn bad_measurements_are_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let meas = path(dir.path(), "m.csv");
    let model = path(dir.path(), "model.json");
    for (text, args, words) in [
        (
            "axis,command_mm,ex_mm,ey_mm,ez_mm\nQ,1,0,0,0\n",
            &[][..],
            "m.csv: line 2, column 1: 'Q' is not a linear axis",
        ),
        (
            "axis,command_mm,ex_mm,ey_mm,ez_mm,state\nX,1,0,0,0,warm\n",
            &[],
            "line 2, column 3: no cold measurement of axis X at 1 mm",
        ),
        ("axis,command_mm,ex_mm,ey_mm\nX,1,0,0\n", &[], "no column 'ez_mm'"),
        (
            "axis,command_mm,ex_mm,ey_mm,ez_mm\nX,1,0,0,0\nX,2,0,0,0\n",
            &["--degree", "2"],
            "2 measurement(s), too few for a polynomial of degree 2",
        ),
    ] {
        std::fs::write(&meas, text).unwrap();
        let o = kezuri(&[&["thermal", "fit", &meas, "-o", &model][..], args].concat());
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.code() == Some(1) && e.contains(words), "{text}: {e}");
        assert!(!std::path::Path::new(&model).exists());
    }
}

#[test]
fn the_measuring_program_stops_where_it_was_planned_in_order() {
    let dir = tempfile::tempdir().unwrap();
    let turn = path(dir.path(), "turn.toml");
    std::fs::write(&turn, "[kinematics]\ntool = [\"X\", \"Z\", \"B\"]\nwork = [\"Y\", \"C\"]\n").unwrap();
    let program = path(dir.path(), "O2007.nc");
    ok(&kezuri(&["thermal", "plan", "--machine", &turn, "-o", &program]));
    // The paper's O2007: at B 0 Z -74 … -94 then X -2 … -22 at Z -94; at
    // B -90 Z -135 … -155 then X -145 … -165.
    let mut planned = Vec::new();
    for (b, x0, z0) in [(0.0, -2.0, -74.0), (-90.0, -145.0, -135.0)] {
        for k in 0..6 {
            planned.push([x0, z0 - 4.0 * k as f64, b]);
        }
        for k in 1..6 {
            planned.push([x0 - 4.0 * k as f64, z0 - 20.0, b]);
        }
    }
    let csv = ok(&kezuri(&["run", &program, "--emit", "csv"]));
    let stops: Vec<[f64; 3]> = csv
        .lines()
        .skip(1)
        .filter(|l| l.split(',').nth(1) == Some("feed"))
        .map(|l| {
            let f: Vec<f64> = l.split(',').skip(2).take(5).map(|v| v.parse().unwrap()).collect();
            [f[0], f[2], f[4]]
        })
        .collect();
    assert_eq!(stops, planned);
    // A dwell at every stop for the sensors.
    let text = std::fs::read_to_string(&program).unwrap();
    assert_eq!(text.matches("G04 X1.").count(), 22);
    // The paper's stations need a B axis.
    let o = kezuri(&["thermal", "plan", "-o", &path(dir.path(), "x.nc")]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("the machine has no B axis"));
    let o = kezuri(&["thermal", "plan", "--at", "0:1,2", "-o", &path(dir.path(), "x.nc")]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("--at '0:1,2': expected B:X,Y,Z"));
}

#[test]
fn the_corrected_program_lands_every_point_on_its_target() {
    let dir = tempfile::tempdir().unwrap();
    let (model, turn) = fitted(dir.path());
    // A cut inside the measured ranges, at B 0 and at B -90, with an arc.
    let program = path(dir.path(), "cut.nc");
    std::fs::write(
        &program,
        "G90 G17 G21\nG00 X-20. Y-5. Z-80. B0.\nG01 Z-90. F300\nX-4.\nY5.\nG02 X-8. Y9. I-4. J0.\nG01 Z-76.\n\
         G00 B-90.\nG01 X-18. Y-8. Z-92.\nX-3. Y8. Z-75.\nM30\n",
    )
    .unwrap();
    let corrected = path(dir.path(), "cut-warm.nc");
    let v: serde_json::Value = serde_json::from_str(&ok(&kezuri(&[
        "thermal",
        "apply",
        &program,
        "--model",
        &model,
        "--machine",
        &turn,
        "-o",
        &corrected,
        "--json",
    ])))
    .unwrap();
    assert_eq!(v["extrapolated_points"], 0, "{v}");
    assert!(v["max_residual_mm"].as_f64().unwrap() < 1e-6, "{v}");
    // The same model, fitted here: where does the warm machine put the
    // tool for each corrected command?
    let uncorrected = assert_lands(&truth_model(), &rows(&program), &rows(&corrected));
    assert!(uncorrected > 0.04, "uncorrected {uncorrected}");
    // A model for another machine.
    let mill = path(dir.path(), "mill.toml");
    std::fs::write(&mill, "[kinematics]\ntool = [\"X\", \"Y\", \"Z\"]\n").unwrap();
    let o = kezuri(&["thermal", "apply", &program, "--model", &model, "--machine", &mill, "-o", &corrected]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("the model is for a machine with tool axes"));
}

/// A profile file across an edge at (u, w) of the sensor's plane.
fn edge_profile(u: f64, w: f64) -> String {
    let mut t = String::from("x_mm,z_mm\n");
    for k in 0..=200 {
        let x = u - 1.0 + k as f64 * 0.01;
        let dx = x - u;
        let z = w + if dx < 0.0 { dx * 35f64.to_radians().tan() } else { -dx * 55f64.to_radians().tan() };
        t += &format!("{x:.9},{z:.9}\n");
    }
    t
}

#[test]
fn from_sensor_profiles_to_a_corrected_cut() {
    let table = measurements();
    let dir = tempfile::tempdir().unwrap();
    let (meas, model, turn) = model_from_profiles(dir.path(), &table);
    // The measurements found from the profiles are the truth's, warm less cold.
    let found = std::fs::read_to_string(&meas).unwrap();
    let warm_less_cold = |text: &str| -> Vec<f64> {
        let rows: Vec<Vec<f64>> =
            text.lines().skip(1).map(|l| l.split(',').skip(2).take(3).map(|v| v.parse().unwrap()).collect()).collect();
        rows.chunks(2).flat_map(|p| (0..3).map(|i| p[1][i] - p[0][i]).collect::<Vec<_>>()).collect()
    };
    for (a, b) in warm_less_cold(&found).iter().zip(warm_less_cold(&table)) {
        assert!((a - b).abs() < 1e-6, "{a} vs {b}");
    }
    // And the cut, corrected with the model from the profiles, lands on its
    // targets on the machine deformed by the truth.
    let program = path(dir.path(), "cut.nc");
    std::fs::write(
        &program,
        "G90 G17 G21\nG00 X-20. Y-5. Z-80. B0.\nG01 Z-90. F300\nX-4.\nY5.\nG00 B-90.\nG01 X-18. Y-8. Z-92.\nM30\n",
    )
    .unwrap();
    let corrected = path(dir.path(), "cut-warm.nc");
    ok(&kezuri(&["thermal", "apply", &program, "--model", &model, "--machine", &turn, "-o", &corrected]));
    assert_lands(&truth_model(), &rows(&program), &rows(&corrected));
}

#[test]
fn o2007_corrected_from_its_own_measurements() {
    // The paper's stations: B 0 at X -22 … -2, Z -94 … -74; B -90 at
    // X -165 … -145, Z -155 … -135 (and Y about zero): measured through the
    // sensors' profiles, fitted, and O2007 itself corrected.
    let table = measurements_over(&[
        (0.0, [(-22.0, -2.0), (-10.0, 10.0), (-94.0, -74.0)]),
        (-90.0, [(-165.0, -145.0), (-10.0, 10.0), (-155.0, -135.0)]),
    ]);
    let dir = tempfile::tempdir().unwrap();
    let (_, model, turn) = model_from_profiles(dir.path(), &table);
    let o2007 = concat!(env!("CARGO_MANIFEST_DIR"), "/../../samples/o2007-thermal.nc");
    let corrected = path(dir.path(), "o2007-warm.nc");
    // Its approach and retract at Z0 (5 of its 28 points) lie 74 mm above
    // the measured range: corrected only when allowed, and said.
    let o = kezuri(&["thermal", "apply", o2007, "--model", &model, "--machine", &turn, "-o", &corrected]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("5 of 28 points (17.9 %)"));
    ok(&kezuri(&[
        "thermal",
        "apply",
        o2007,
        "--model",
        &model,
        "--machine",
        &turn,
        "-o",
        &corrected,
        "--allow-extrapolation",
    ]));
    let truth = truth_model_of(&table);
    // The measuring stops, in order, before and after (the corrected ones
    // are within 0.1 mm of the planned; G28 and G92 are written anew, so
    // the other rows need not pair up).
    let measured = |p: &[f64; 6], slack: f64| {
        let (x, z) = if p[4] == 0.0 { ((-22.0, -2.0), (-94.0, -74.0)) } else { ((-165.0, -145.0), (-155.0, -135.0)) };
        (x.0 - slack..=x.1 + slack).contains(&p[0]) && (z.0 - slack..=z.1 + slack).contains(&p[2])
    };
    let mut plain: Vec<[f64; 6]> = rows(o2007).into_iter().filter(|p| measured(p, 0.0)).collect();
    let mut warm: Vec<[f64; 6]> = rows(&corrected).into_iter().filter(|p| measured(p, 1.0)).collect();
    // A move to where the tool already is (O2007's second X-145.) is no stop.
    plain.dedup();
    warm.dedup();
    assert_eq!(plain.len(), 22, "every measuring stop of O2007");
    let before = assert_lands(&truth, &plain, &warm);
    assert!(before > 0.04, "uncorrected up to {before} mm");
}

/// Two line sensors' profiles of every row of the measurements `table`
/// (cold and warm) written beside an index, then `thermal measure` and
/// `thermal fit` on the mill-turn: the paths of the measurements, the model
/// and the machine file.
fn model_from_profiles(dir: &std::path::Path, table: &str) -> (String, String, String) {
    // The sensors' planes hold the edge at (X, Z) and (Y, Z) plus where they sit.
    let mut index = String::from("axis,command_mm,b_deg,state,profile_1,profile_2\n");
    for (n, line) in table.lines().skip(1).enumerate() {
        let f: Vec<&str> = line.split(',').collect();
        let (axis, c, b, state) = (f[0], f[1].parse::<f64>().unwrap(), f[5], f[6]);
        let e: Vec<f64> = f[2..5].iter().map(|v| v.parse().unwrap()).collect();
        let k = ["X", "Y", "Z"].iter().position(|a| *a == axis).unwrap();
        // The edge: the sensors' origin, the command along its axis, the error.
        let mut edge = [0.3 + e[0], -0.2 + e[1], 0.1 + e[2]];
        edge[k] += c;
        let (p1, p2) = (format!("p{n}-1.csv"), format!("p{n}-2.csv"));
        std::fs::write(dir.join(&p1), edge_profile(edge[0], edge[2])).unwrap();
        std::fs::write(dir.join(&p2), edge_profile(edge[1], edge[2])).unwrap();
        index += &format!("{axis},{c},{b},{state},{p1},{p2}\n");
    }
    let index_file = path(dir, "index.csv");
    std::fs::write(&index_file, index).unwrap();
    let (meas, model) = (path(dir, "meas.csv"), path(dir, "model.json"));
    ok(&kezuri(&["thermal", "measure", &index_file, "-o", &meas]));
    let turn = path(dir, "turn.toml");
    std::fs::write(&turn, "[kinematics]\ntool = [\"X\", \"Z\", \"B\"]\nwork = [\"Y\", \"C\"]\n").unwrap();
    ok(&kezuri(&["thermal", "fit", &meas, "--machine", &turn, "-o", &model]));
    (meas, model, turn)
}

/// The X Y Z A B C of each motion of `kezuri run FILE --emit csv`.
fn rows(file: &str) -> Vec<[f64; 6]> {
    ok(&kezuri(&["run", file, "--emit", "csv"]))
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<f64> = l.split(',').skip(2).take(6).map(|v| v.parse().unwrap()).collect();
            [f[0], f[1], f[2], f[3], f[4], f[5]]
        })
        .collect()
}

/// The error model of `measurements()`, warm less cold, fitted here.
fn truth_model() -> kezuri_correct::thermal::ErrorModel {
    truth_model_of(&measurements())
}

/// The error model of a measurements table, warm less cold, fitted here.
fn truth_model_of(table: &str) -> kezuri_correct::thermal::ErrorModel {
    let table: Vec<kezuri_correct::thermal::Measurement> = table
        .lines()
        .skip(1)
        .collect::<Vec<_>>()
        .chunks(2)
        .map(|pair| {
            let [cold, warm] = [pair[0], pair[1]].map(|l| l.split(',').map(str::to_string).collect::<Vec<_>>());
            let n = |v: &Vec<String>, k: usize| v[k].parse::<f64>().unwrap();
            kezuri_correct::thermal::Measurement {
                axis: ["X", "Y", "Z"].iter().position(|a| *a == cold[0]).unwrap(),
                b_deg: n(&cold, 5),
                command: n(&cold, 1),
                error: [n(&warm, 2) - n(&cold, 2), n(&warm, 3) - n(&cold, 3), n(&warm, 4) - n(&cold, 4)],
            }
        })
        .collect();
    kezuri_correct::thermal::fit(&table, None).unwrap()
}

/// The mill-turn of the machine files here: tool X, Z, B; work Y, C; pivots and tip at zero.
fn plain_mill_turn() -> kezuri_correct::kinematics::Kinematics {
    kezuri_correct::kinematics::Kinematics::mill_turn([0.0; 3], [0.0; 3])
}

#[test]
fn the_program_text_kept_with_only_its_numbers_corrected() {
    let dir = tempfile::tempdir().unwrap();
    let (model, turn) = fitted(dir.path());
    let program = path(dir.path(), "cut.nc");
    std::fs::write(
        &program,
        "%\nO0001 (CUT)\nG90 G17 G21\nG00 X-20. Y-5. Z-80. B0. (START)\nG01 Z-90. F300\nX-4. (ALONG X)\nY5.\n\
         G02 X-8. Y9. I-4. J0.\nG01 Z-76. M08\nG00 B-90.\nG01 X-18. Y-8. Z-92.\nM30\n%\n",
    )
    .unwrap();
    let kept = path(dir.path(), "cut-kept.nc");
    ok(&kezuri(&["thermal", "apply", &program, "--model", &model, "--machine", &turn, "--keep-text", "-o", &kept]));
    let text = std::fs::read_to_string(&kept).unwrap();
    // Line for line the same program: comments, M08, layout; only numbers changed or added.
    assert_eq!(text.lines().count(), 13);
    for want in ["O0001 (CUT)", "(START)", "(ALONG X)", " M08", "G00 B-90."] {
        assert!(text.contains(want), "{want}: {text}");
    }
    assert_lands(&truth_model(), &rows(&program), &rows(&kept));
    // Macro statements that make no move stay as they are; a move made of
    // variables cannot be corrected in place; nor calls.
    std::fs::write(&program, "G90 G00 X-20. Y-5. Z-80. B0.\n#1=-90.\nG01 Z-90. F300 (#1 UNUSED)\nM30\n").unwrap();
    ok(&kezuri(&["thermal", "apply", &program, "--model", &model, "--machine", &turn, "--keep-text", "-o", &kept]));
    assert!(std::fs::read_to_string(&kept).unwrap().contains("\n#1=-90.\n"));
    for (text, words) in [
        (
            "G90 G00 X-20. Y-5. Z-80. B0.\n#1=-90.\nG01 Z#1 F300\nM30\n",
            "line 3: this block's move comes from macro variables",
        ),
        (
            "G90 G00 X-20. Y-5. Z-80. B0.\nM98 P1000\nM30\nO1000\nG01 Z-90. F300\nM99\n",
            "line 2: --keep-text rewrites G90 programs without calls",
        ),
    ] {
        std::fs::write(&program, text).unwrap();
        let o =
            kezuri(&["thermal", "apply", &program, "--model", &model, "--machine", &turn, "--keep-text", "-o", &kept]);
        assert!(String::from_utf8_lossy(&o.stderr).contains(words), "{text}: {}", String::from_utf8_lossy(&o.stderr));
    }
}

/// `measurements()` fitted by `kezuri thermal fit` on the mill-turn in
/// `dir`: the model's and the machine file's paths.
fn fitted(dir: &std::path::Path) -> (String, String) {
    let meas = path(dir, "meas.csv");
    std::fs::write(&meas, measurements()).unwrap();
    let turn = path(dir, "turn.toml");
    std::fs::write(&turn, "[kinematics]\ntool = [\"X\", \"Z\", \"B\"]\nwork = [\"Y\", \"C\"]\n").unwrap();
    let model = path(dir, "model.json");
    ok(&kezuri(&["thermal", "fit", &meas, "--machine", &turn, "-o", &model]));
    (model, turn)
}

/// `thermal fit -q -o MODEL` says nothing: its table is a summary.
#[test]
fn a_quiet_fit_prints_no_table() {
    let dir = tempfile::tempdir().unwrap();
    let meas = path(dir.path(), "meas.csv");
    std::fs::write(&meas, measurements()).unwrap();
    let model = path(dir.path(), "model.json");
    let o = kezuri(&["thermal", "fit", &meas, "-q", "-o", &model]);
    assert!(o.status.success() && o.stdout.is_empty() && o.stderr.is_empty(), "{o:?}");
    assert!(std::fs::read_to_string(&model).unwrap().contains("functions"));
}

#[test]
fn the_grid_search_agrees_with_newton_within_its_spacing() {
    let dir = tempfile::tempdir().unwrap();
    let (model, turn) = fitted(dir.path());
    let program = path(dir.path(), "cut.nc");
    std::fs::write(
        &program,
        "G90 G17 G21\nG00 X-20. Y-5. Z-80. B0.\nG01 Z-90. F300\nX-4.\nG00 B-90.\nG01 X-18. Y-8. Z-92.\nM30\n",
    )
    .unwrap();
    let apply = |solver: &str| {
        let out = path(dir.path(), &format!("{solver}.nc"));
        let v: serde_json::Value = serde_json::from_str(&ok(&kezuri(&[
            "thermal",
            "apply",
            &program,
            "--model",
            &model,
            "--machine",
            &turn,
            "--solver",
            solver,
            "-o",
            &out,
            "--json",
        ])))
        .unwrap();
        (rows(&out), v)
    };
    let ((newton, _), (grid, v)) = (apply("newton"), apply("grid"));
    assert_eq!(v["solver"], "grid");
    // The grid's nearest candidate is within half its 1 µm spacing of the landing point per axis.
    assert!(v["max_residual_mm"].as_f64().unwrap() < 0.001, "{v}");
    for (n, g) in newton.iter().zip(&grid) {
        assert!((0..3).all(|i| (n[i] - g[i]).abs() <= 0.001 + 1e-9), "{n:?} vs {g:?}");
    }
}

/// Asserts that each corrected command of `warm` puts the tool, on the
/// mill-turn deformed by `truth`, within 0.1 µm (written with 4 decimals)
/// of where the ideal machine puts it for the same command of `plain`;
/// returns the largest miss of `plain` itself on the warm machine.
fn assert_lands(truth: &kezuri_correct::thermal::ErrorModel, plain: &[[f64; 6]], warm: &[[f64; 6]]) -> f64 {
    assert_eq!(plain.len(), warm.len());
    let k = plain_mill_turn();
    let distance = |a: [f64; 3], b: [f64; 3]| (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt();
    let mut uncorrected: f64 = 0.0;
    for (p, w) in plain.iter().zip(warm) {
        let target = k.forward(p);
        let miss = distance(truth.deformed(&k, w).unwrap(), target);
        assert!(miss < 0.0001, "{p:?} → {w:?}: {:.3} µm", miss * 1e3);
        uncorrected = uncorrected.max(distance(truth.deformed(&k, p).unwrap(), target));
    }
    uncorrected
}

/// A program mostly beyond the measured ranges is refused: its correction
/// would be the fitted curves extrapolated. --allow-extrapolation corrects
/// it and says how much.
#[test]
fn a_program_mostly_beyond_the_measurements_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (model, turn) = fitted(dir.path());
    let program = path(dir.path(), "far.nc");
    std::fs::write(&program, "G90 G17 G21\nG00 X-20. Y-5. Z-80. B0.\nG01 X-60. F300\nX-70.\nX-80.\nM30\n").unwrap();
    let out = path(dir.path(), "far-warm.nc");
    let args = ["thermal", "apply", &program, "--model", &model, "--machine", &turn, "-o", &out];
    let o = kezuri(&args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && !std::path::Path::new(&out).exists());
    assert!(
        err.contains("3 of 4 points (75.0 %) lie beyond the measured range") && err.contains("--allow-extrapolation"),
        "{err}"
    );
    let o = kezuri(&[&args[..], &["--allow-extrapolation"]].concat());
    ok(&o);
    assert!(String::from_utf8_lossy(&o.stderr).contains("warning: "), "{}", String::from_utf8_lossy(&o.stderr));
}
