//! `kezuri mill` as a user runs it, proven with `kezuri sim --compare`: the
//! program never cuts into the surface by more than its tolerance, and with
//! `--cusp` the material left between rows stays within the target.

use std::fmt::Write as _;
use std::path::Path;
use std::process::Output;

mod common;
use common::kezuri;

fn json(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).expect("one JSON object")
}

/// A height grid `x y z` of `f` over `[-size, size]²` at `step`.
fn grid(dir: &Path, name: &str, size: f64, step: f64, f: impl Fn(f64, f64) -> f64) -> String {
    let n = (2.0 * size / step).round() as usize;
    let mut text = String::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (-size + i as f64 * step, -size + j as f64 * step);
            writeln!(text, "{x} {y} {}", f(x, y)).unwrap();
        }
    }
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_string_lossy().into_owned()
}

fn sim(program: &str, tool: &str, target: &str, res: &str) -> serde_json::Value {
    json(&kezuri(&["sim", program, "--tool", tool, "--res", res, "--compare", target, "--json"]))
}

#[test]
fn a_dome_is_milled_within_the_tolerance() {
    let dir = tempfile::tempdir().unwrap();
    let dome = grid(dir.path(), "dome.xyz", 20.0, 0.5, |x, y| ((625.0 - x * x - y * y).max(0.0)).sqrt() - 15.0);
    let nc = dir.path().join("dome.nc").to_string_lossy().into_owned();
    for tool in ["ball:6", "bull:6,1", "flat:4", "oval:6,5"] {
        let o = kezuri(&["mill", &dome, "--tool", tool, "--stepover", "0.8", "--gouge-tol", "0.01", "-o", &nc]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let v = sim(&nc, tool, &dome, "0.1");
        let gouge = v["max_gouge_mm"].as_f64().unwrap();
        assert!(gouge <= 0.01, "{tool}: gouge {gouge}");
        assert_eq!(v["rapids_into_stock"], 0, "{tool}");
    }
}

/// kezuri's own finishing program, simulated against its surface, passes
/// kezuri's own gouge check: the program carries mill's allowance in its
/// header and sim reads it back (it painted the 0.007 mm dips between
/// samples as gouges past 0.001 mm before); the deepest point stays the
/// raw figure, and a --gouge-tol given wins.
#[test]
fn the_program_carries_its_gouge_allowance_and_sim_agrees() {
    let dir = tempfile::tempdir().unwrap();
    let bump = grid(dir.path(), "bump.xyz", 10.0, 0.5, |x, y| 4.0 * (-(x * x + y * y) / 30.0).exp());
    let nc = dir.path().join("bump.nc").to_string_lossy().into_owned();
    let o = kezuri(&["mill", &bump, "--tool", "ball:4", "--stepover", "0.5", "-o", &nc]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&nc).unwrap();
    assert!(text.lines().take(4).any(|l| l == "(KEZURI GOUGE-TOL 0.010)"), "{text:.300}");
    let own = sim(&nc, "ball:4", &bump, "0.05");
    assert_eq!((own["gouge_tol_mm"].as_f64(), own["gouge_tol_from"].as_str()), (Some(0.01), Some("program")));
    assert_eq!(own["gouge_cells"], 0, "{own}");
    let raw = own["max_gouge_mm"].as_f64().unwrap();
    assert!(raw > 0.001 && raw <= 0.01, "{raw}");
    let o = kezuri(&["sim", &nc, "--tool", "ball:4", "--res", "0.05", "--compare", &bump]);
    let report = String::from_utf8_lossy(&o.stdout);
    assert!(report.contains("allowance  0.0100 mm (the program's header): no cell deeper"), "{report}");
    let strict = json(&kezuri(&[
        "sim",
        &nc,
        "--tool",
        "ball:4",
        "--res",
        "0.05",
        "--compare",
        &bump,
        "--gouge-tol",
        "0.001",
        "--json",
    ]));
    assert_eq!(strict["gouge_tol_from"], "given");
    assert!(strict["gouge_cells"].as_u64().unwrap() > 0, "{strict}");
    assert_eq!(strict["max_gouge_mm"], own["max_gouge_mm"]);
    // view --sim reads it back too, and says so.
    let page = dir.path().join("bump.html").to_string_lossy().into_owned();
    let o = kezuri(&["view", &nc, "--sim", "--res", "0.1", "--tool", "ball:4", "--compare", &bump, "-o", &page]);
    let said = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && said.contains("(gouges past 0.01 mm, the program's header)"), "{said}");
}

/// As relief does, mill says where its cutter cannot reach: a round groove
/// 2 mm wide and 1 mm deep holds a ball:1 but not a ball:6, which rests on
/// its edges 0.83 mm above its bottom.
#[test]
fn mill_warns_of_what_its_cutter_cannot_reach() {
    let dir = tempfile::tempdir().unwrap();
    let groove = grid(dir.path(), "groove.xyz", 8.0, 0.1, |x, _| -(1.0 - x * x).max(0.0).sqrt());
    let nc = dir.path().join("groove.nc").to_string_lossy().into_owned();
    let warned = |tool: &str| {
        let o = kezuri(&["mill", &groove, "--tool", tool, "--stepover", "2", "-o", &nc]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    let wide = warned("ball:6");
    // Up to 0.828 mm at the bottom (an upper bound within the check's grid).
    assert!(wide.contains("ball:6 cannot reach all of the surface: up to 0.8"), "{wide}");
    let narrow = warned("ball:1");
    assert!(!narrow.contains("cannot reach"), "{narrow}");
}

#[test]
fn pick_feed_control_keeps_the_cusp_on_a_slope() {
    // A plane rising 30° across the rows: a ball's cusp of 0.02 mm square
    // to the plane is 0.02 / cos 30° measured vertically.
    let dir = tempfile::tempdir().unwrap();
    let slope = 30f64.to_radians().tan();
    let plane = grid(dir.path(), "plane.xyz", 10.0, 0.5, |_, y| y * slope);
    // Compared away from the edges, where the ball touches the plane
    // 1.5 mm uphill of its centre and the first row cannot reach down.
    let inside = grid(dir.path(), "inside.xyz", 6.0, 0.5, |_, y| y * slope);
    let nc = dir.path().join("plane.nc").to_string_lossy().into_owned();
    let o = kezuri(&["mill", &plane, "--tool", "ball:6", "--stepover", "3", "--cusp", "0.02", "-o", &nc]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v = sim(&nc, "ball:6", &inside, "0.05");
    let left = v["max_left_mm"].as_f64().unwrap();
    let vertical = 0.02 / 30f64.to_radians().cos();
    // Heights are rounded up to the program's 0.001 mm, never down.
    assert!(left <= vertical * 1.02 + 0.001 && left > vertical * 0.7, "cusp {left} vs {vertical}");
    // Without control, the 3 mm stepover leaves far more.
    let o = kezuri(&["mill", &plane, "--tool", "ball:6", "--stepover", "3", "-o", &nc]);
    assert!(o.status.success());
    assert!(sim(&nc, "ball:6", &inside, "0.05")["max_left_mm"].as_f64().unwrap() > 5.0 * vertical);
}

#[test]
fn bad_input_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let flat = grid(dir.path(), "flat.xyz", 5.0, 1.0, |_, _| 0.0);
    for (args, why) in [
        (vec!["--tool", "ball:6", "--stepover", "0"], "stepover"),
        (vec!["--tool", "ball:-6", "--stepover", "1"], "the diameter must be a length"),
        (vec!["--tool", "ball:6", "--stepover", "1", "--cusp", "-1"], "--cusp"),
        (vec!["--tool", "ball:6", "--stepover", "1", "--region", "50,50,60,60"], "nothing to cut"),
        (vec!["--tool", "drill:6,118", "--stepover", "1"], "a drill cuts along its axis only"),
    ] {
        let mut all = vec!["mill", flat.as_str()];
        all.extend(args);
        let o = kezuri(&all);
        assert_eq!(o.status.code(), Some(1), "{all:?}");
        assert!(String::from_utf8_lossy(&o.stderr).contains(why), "{all:?}: {}", String::from_utf8_lossy(&o.stderr));
    }
    let o = kezuri(&["mill", "/nonexistent.stl", "--tool", "ball:6", "--stepover", "1"]);
    assert_eq!(o.status.code(), Some(1));
}

/// A program or CSV alone is written row by row as the rows are made; with
/// a drawing (`--svg`) the whole path is made first. Both give the same
/// bytes, in every post, zig-zag and one-way, both directions, and to
/// standard output; the summary line says the same.
#[test]
fn the_program_written_row_by_row_is_the_whole_paths() {
    let dir = tempfile::tempdir().unwrap();
    let wave = grid(dir.path(), "wave.xyz", 6.0, 0.25, |x, y| (x * 0.8).sin() + 0.5 * (y * 0.6).cos());
    let at = |name: &str| dir.path().join(name).to_string_lossy().into_owned();
    for (tool, extra) in [
        ("ball:3", &["--post", "fanuc"][..]),
        ("flat:2", &["--post", "haas", "--direction", "both", "--pattern", "oneway"][..]),
        ("bull:3,0.5", &["--post", "linuxcnc", "--direction", "y"][..]),
        ("ball:2", &["--post", "grbl", "--tool-number", "0"][..]),
        ("ball:2", &["--to", "csv"][..]),
    ] {
        let common = [&wave, "--tool", tool, "--stepover", "1.5"];
        let run = |out: &[&str]| {
            let args: Vec<&str> = ["mill"].iter().chain(&common).chain(extra).chain(out).copied().collect();
            let o = kezuri(&args);
            assert!(o.status.success(), "{tool} {extra:?}: {}", String::from_utf8_lossy(&o.stderr));
            o
        };
        let (streamed, whole, svg) = (at("streamed.nc"), at("whole.nc"), at("whole.svg"));
        let said = run(&["-o", &streamed]);
        let said_whole = run(&["-o", &whole, "--svg", &svg]);
        let text = std::fs::read(&streamed).unwrap();
        assert!(text.len() > 1000, "{tool} {extra:?}");
        assert_eq!(text, std::fs::read(&whole).unwrap(), "{tool} {extra:?}");
        assert_eq!(run(&[]).stdout, text, "{tool} {extra:?}: standard output");
        let summary = |o: &Output| {
            let e = String::from_utf8_lossy(&o.stderr).into_owned();
            e.lines().filter_map(|l| l.split_once(".nc: ").map(|s| s.1.to_string())).collect::<Vec<_>>()
        };
        assert_eq!(summary(&said), summary(&said_whole), "{tool} {extra:?}");
        assert_eq!(summary(&said).len(), 1, "{:?}", String::from_utf8_lossy(&said.stderr));
    }
}
