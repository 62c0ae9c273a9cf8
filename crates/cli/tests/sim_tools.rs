//! `kezuri sim` with every tool of a program: the machine file's tool
//! table, what each tool removed and gouged, the error naming the tools a
//! program needs, and real stock (a cylinder, a solid's top).

use std::collections::HashMap;
use std::path::Path;

mod common;
use common::{kezuri, ok, path};

fn json(o: &std::process::Output) -> serde_json::Value {
    serde_json::from_str(&ok(o)).expect("one JSON object")
}

fn write(dir: &Path, name: &str, data: &[u8]) -> String {
    std::fs::write(dir.join(name), data).unwrap();
    path(dir, name)
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn num(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("{v} is not a number"))
}

/// The tools of a `sim --json` report: number → (shape, volume, gouge).
fn tools(v: &serde_json::Value) -> Vec<(u64, String, f64, Option<f64>)> {
    let list = v["tools"].as_array().expect("tools");
    list.iter()
        .map(|t| {
            let shape = t["shape"].as_str().unwrap().to_string();
            (t["number"].as_u64().unwrap(), shape, num(&t["volume_mm3"]), t["max_gouge_mm"].as_f64())
        })
        .collect()
}

/// A binary STL of triangles (f32, as the format has it).
fn stl(triangles: &[[[f64; 3]; 3]]) -> Vec<u8> {
    let mut out = vec![0u8; 80];
    out.extend_from_slice(&(triangles.len() as u32).to_le_bytes());
    for t in triangles {
        out.extend_from_slice(&[0u8; 12]);
        for v in t.iter().flatten() {
            out.extend_from_slice(&(*v as f32).to_le_bytes());
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}

/// The cell-centre heights in a surface STL written by `sim --stl`: its
/// vertices, each once.
fn cell_heights(file: &str) -> Vec<f64> {
    let bytes = std::fs::read(file).unwrap();
    let mut cells: HashMap<(u32, u32), f32> = HashMap::new();
    for t in bytes[84..].chunks_exact(50) {
        for v in t[12..48].chunks_exact(12) {
            let f = |k: usize| f32::from_le_bytes(v[4 * k..4 * k + 4].try_into().unwrap());
            cells.insert((f(0).to_bits(), f(1).to_bits()), f(2));
        }
    }
    cells.into_values().map(f64::from).collect()
}

const TWO_TOOLS: &str = "[tools.T1]\nshape = \"flat:6\"\n[tools.T2]\nshape = \"ball:3\"\n";

/// The relief of the task: roughed with a flat:6 (T1), finished with a
/// ball:3 (T2), and its surface.
fn plum_relief(dir: &Path) -> (String, String) {
    let sketch = concat!(env!("CARGO_MANIFEST_DIR"), "/../../samples/plum-sketch.png");
    let (nc, surface) = (path(dir, "r.nc"), path(dir, "r.stl"));
    let args = ["--width", "40", "--depth", "3", "--tool", "ball:3", "--rough", "flat:6", "--stepover", "1"];
    ok(&kezuri(&[&["relief", sketch][..], &args, &["--surface-stl", &surface, "-o", &nc]].concat()));
    (nc, surface)
}

#[test]
fn a_two_tool_relief_is_cut_by_both_tools_and_the_volumes_add_up() {
    let dir = tempfile::tempdir().unwrap();
    let (nc, surface) = plum_relief(dir.path());
    let text = std::fs::read_to_string(&nc).unwrap();
    let (t1, t2) = (text.find("T1 M06").expect("T1"), text.find("T2 M06").expect("T2"));
    assert!(t1 < t2, "roughing first");
    let machine = write(dir.path(), "m.toml", TWO_TOOLS.as_bytes());
    let cut = path(dir.path(), "cut.stl");
    let stock = ["--res", "0.1", "--stock", "0,0,40,30,0"];
    let sim = |program: &str, extra: &[&str]| {
        json(&kezuri(&[&["sim", program, "--machine", &machine][..], &stock, extra, &["--json"]].concat()))
    };
    let v = sim(&nc, &["--compare", &surface, "--stl", &cut]);
    let t = tools(&v);
    assert_eq!(t.iter().map(|t| (t.0, t.1.as_str())).collect::<Vec<_>>(), [(1, "flat:6"), (2, "ball:3")]);
    assert!(t[0].2 > 0.0 && t[1].2 > 0.0, "both tools cut: {t:?}");
    // No gouge beyond the relief's own allowance (0.01 mm below the cutter
    // locations, which its header carries) and the STL's single-precision
    // heights.
    assert!(num(&v["max_gouge_mm"]) < 0.01 + 1e-5, "{}", v["max_gouge_mm"]);
    assert_eq!((v["gouge_tol_from"].as_str(), v["gouge_cells"].as_u64()), (Some("program"), Some(0)));
    // (d) The tools' volumes add up to all that was removed: every cell of
    // the cut surface (read back from its STL) below the top at 0.
    let cells = cell_heights(&cut);
    assert_eq!(cells.len(), 400 * 300);
    let removed: f64 = cells.iter().map(|z| -z * 0.01).sum();
    let sum: f64 = t.iter().map(|t| t.2).sum();
    assert!((sum - removed).abs() <= 1e-6 * removed, "{sum} against {removed}");
    assert!((num(&v["volume_mm3"]) - sum).abs() <= 1e-9 * sum);
    // What T1 removed is what the roughing alone removes: the program up
    // to the tool change, simulated by itself.
    let rough = write(dir.path(), "rough.nc", format!("{}M30\n%\n", &text[..t2]).as_bytes());
    let alone = sim(&rough, &[]);
    let roughed = num(&alone["volume_mm3"]);
    assert!((t[0].2 - roughed).abs() <= 1e-9 * roughed, "{} against {roughed}", t[0].2);
    // Each tool's time is its share of the whole.
    let times: Vec<f64> = v["tools"].as_array().unwrap().iter().map(|t| num(&t["time_s"])).collect();
    assert!(times.iter().all(|&s| s > 0.0), "{times:?}");
}

/// A slot along Y at X 7 roughed for a flat:6 (T1: its edge on the wall at
/// X 10), then a pass of a ball:2 (T2) at X 4, both at Z −2; the part is a
/// floor at Z −2 for X < 10 and its top, Z 0, beyond.
const SLOT: &str = "%\nO0100 (SLOT)\nG90 G21 G17\nT1 M06\nG00 Z5.\nX7. Y0.\nG01 Z-2. F300\nY20.\nG00 Z5.\n\
T2 M06\nX4. Y0.\nG01 Z-2. F300\nY20.\nG00 Z5.\nM30\n%\n";

fn step_part() -> Vec<u8> {
    let rect = |x0: f64, x1: f64, z: f64| {
        [[[x0, 0.0, z], [x1, 0.0, z], [x1, 20.0, z]], [[x0, 0.0, z], [x1, 20.0, z], [x0, 20.0, z]]]
    };
    stl(&[rect(0.0, 10.0, -2.0), rect(10.0, 16.0, 0.0)].concat())
}

#[test]
fn a_roughing_tool_too_big_gouges_and_only_the_tool_table_finds_it() {
    let dir = tempfile::tempdir().unwrap();
    let nc = write(dir.path(), "slot.nc", SLOT.as_bytes());
    let part = write(dir.path(), "part.stl", &step_part());
    let right = write(dir.path(), "right.toml", b"[tools.T1]\nshape = \"flat:6\"\n[tools.T2]\nshape = \"ball:2\"\n");
    let big = write(dir.path(), "big.toml", b"[tools.T1]\nshape = \"flat:10\"\n[tools.T2]\nshape = \"ball:2\"\n");
    let common = ["--res", "0.5", "--stock", "0,0,16,20,0", "--compare", &part, "--json"];
    let sim = |extra: &[&str]| json(&kezuri(&[&["sim", &nc][..], extra, &common].concat()));
    // The pocket holds a flat:10: it reaches X 12, 2 mm past the wall, and
    // takes the top there (Z 0) down to Z −2: a gouge of 2 mm by T1.
    let v = sim(&["--machine", &big]);
    assert_eq!(num(&v["max_gouge_mm"]), 2.0);
    assert_eq!(v["max_gouge_tool"], 1);
    let at = num(&v["max_gouge_at"][0]);
    assert!(at > 10.0 && at < 12.0, "{at}");
    let t = tools(&v);
    assert_eq!((t[0].3, t[1].3), (Some(2.0), Some(0.0)));
    // The table's flat:6 touches the wall and no more.
    assert_eq!(num(&sim(&["--machine", &right])["max_gouge_mm"]), 0.0);
    // Today's way, the finishing ball for every move (1 mm radius at X 7):
    // nothing to see.
    let ball = sim(&["--tool", "ball:2", "--same-tool-for-all"]);
    assert_eq!(num(&ball["max_gouge_mm"]), 0.0);
    assert_eq!(ball["tools_from"], "--same-tool-for-all");
}

#[test]
fn the_tools_a_program_needs_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let nc = write(dir.path(), "slot.nc", SLOT.as_bytes());
    let run = |extra: &[&str]| kezuri(&[&["sim", &nc, "--res", "0.5"][..], extra].concat());
    let refused = |extra: &[&str], want: &str| {
        let o = run(extra);
        assert_eq!(o.status.code(), Some(1), "{extra:?}");
        assert!(stderr(&o).contains(want), "{extra:?}: {}", stderr(&o));
        assert!(!stderr(&o).contains("panicked"));
    };
    refused(&["--tool", "ball:2"], "the program uses T1 and T2: give their shapes in the machine file's tool table");
    refused(&["--tool", "ball:2"], "T1 = ?, T2 = ?");
    refused(&["--tool", "ball:2"], "--same-tool-for-all");
    refused(&[], "T1 = ?, T2 = ?");
    let half = write(dir.path(), "half.toml", b"[tools.T1]\nshape = \"flat:6\"\n");
    refused(&["--machine", &half], "T1 = flat:6, T2 = ?");
    let both = write(dir.path(), "both.toml", b"[tools.T1]\nshape = \"flat:6\"\n[tools.T2]\nshape = \"ball:2\"\n");
    refused(&["--machine", &both, "--tool", "ball:2"], "leave out --tool");
    refused(&["--same-tool-for-all"], "--same-tool-for-all needs the one tool");
    // A program with one tool: --tool as ever; against the table, only the same shape.
    let one = write(dir.path(), "one.nc", b"G90 G21\nT1 M06\nG00 Z5.\nX1. Y1.\nG01 Z-1. F300\nX4.\nG00 Z5.\nM30\n");
    let one_run = |extra: &[&str]| kezuri(&[&["sim", &one, "--res", "0.5", "--json"][..], extra].concat());
    assert_eq!(json(&one_run(&["--tool", "ball:2"]))["tool"], "ball:2");
    assert_eq!(json(&one_run(&["--machine", &both]))["tool"], "flat:6");
    assert_eq!(json(&one_run(&["--machine", &both, "--tool", "flat:6"]))["tools"][0]["number"], 1);
    let o = one_run(&["--machine", &both, "--tool", "ball:2"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("the machine file's tool table says T1 is flat:6"), "{}", stderr(&o));
    // A program that loads no tool needs --tool.
    let none = write(dir.path(), "none.nc", b"G90 G21\nG00 Z5.\nX1. Y1.\nG01 Z-1. F300\nX4.\nM30\n");
    let o = kezuri(&["sim", &none, "--res", "0.5", "--machine", &both]);
    assert!(stderr(&o).contains("the program loads no tool"), "{}", stderr(&o));
}

/// Two rapid plunges to Z −1 with a ball:2: at (5, 5) and at (`x`, `y`).
fn plunges(x: f64, y: f64) -> String {
    format!("G90 G21\nT1 M06\nG00 Z5.\nX5. Y5.\nZ-1.\nZ5.\nX{x:.3} Y{y:.3}\nZ-1.\nZ5.\nM30\n")
}

#[test]
fn a_rapid_into_a_cylinder_is_found_and_one_beside_it_is_not() {
    let dir = tempfile::tempdir().unwrap();
    // A cylinder Ø20 × 10 on X 0 Y 0, top at Z 0 (cyl:D,H); a plunge at
    // (5, 5), 7.07 from its axis, and one at (8.5, 8.5), 12.02 from it:
    // the ball's 1 mm radius keeps it 1.02 mm off the cylinder.
    let nc = write(dir.path(), "p.nc", plunges(8.5, 8.5).as_bytes());
    let run =
        |stock: &str| json(&kezuri(&["sim", &nc, "--tool", "ball:2", "--res", "0.5", "--stock", stock, "--json"]));
    let v = run("cyl:20,10");
    assert_eq!(v["rapids_into_stock"], 1, "{v}");
    assert_eq!(v["first_rapid_into_stock_line"], 5);
    // (5, 5) is a cell corner: the nearest centres are 0.3536 off the axis,
    // where the ball's tip is 1 − √(1 − 0.125) above its lowest point.
    let depth = 1.0 - (1.0 - (1.0 - 0.125f64).sqrt());
    assert!((num(&v["rapid_hits"][0]["depth_mm"]) - depth).abs() < 1e-12, "{v}");
    assert_eq!(v["stock"]["cylinder"], serde_json::json!({"x": 0.0, "y": 0.0, "diameter": 20.0, "height": 10.0}));
    // The same square as a box: the second plunge is in it.
    assert_eq!(run("-10,-10,10,10,0")["rapids_into_stock"], 2);
    // Placed by its axis and top: cyl:6,10,8.5,8.5,0 holds the second
    // plunge; the first, 4.95 from its axis, stays 1.95 off it…
    let placed = run("cyl:6,10,8.5,8.5,0");
    assert_eq!(placed["rapids_into_stock"], 1);
    assert_eq!(placed["first_rapid_into_stock_line"], 8);
    assert!((num(&placed["rapid_hits"][0]["depth_mm"]) - depth).abs() < 1e-12, "{placed}");
    // …and its top 2 below the plunges' depth: none.
    assert_eq!(run("cyl:20,10,0,0,-2")["rapids_into_stock"], 0);
    for bad in ["cyl:20", "cyl:0,10", "cyl:20,-1", "cyl:a,b", "cyl:20,10,1,2"] {
        let o = kezuri(&["sim", &nc, "--tool", "ball:2", "--res", "0.5", "--stock", bad]);
        assert_eq!(o.status.code(), Some(1), "{bad}");
        assert!(stderr(&o).contains("--stock"), "{bad}: {}", stderr(&o));
    }
}

#[test]
fn a_rapid_into_a_solid_stock_is_found_and_one_beside_its_outline_is_not() {
    let dir = tempfile::tempdir().unwrap();
    // A prism: its top the triangle (0,0) (20,0) (0,20) at Z 0, its bottom
    // at Z −5, sides vertical. (15, 15) lies 7.07 beyond its sloping side.
    let (a, b, c) = ([0.0, 0.0], [20.0, 0.0], [0.0, 20.0]);
    let p = |q: [f64; 2], z: f64| [q[0], q[1], z];
    let mut solid = vec![[p(a, 0.0), p(b, 0.0), p(c, 0.0)], [p(a, -5.0), p(c, -5.0), p(b, -5.0)]];
    for (u, v) in [(a, b), (b, c), (c, a)] {
        solid.push([p(u, -5.0), p(v, -5.0), p(v, 0.0)]);
        solid.push([p(u, -5.0), p(v, 0.0), p(u, 0.0)]);
    }
    let stock = write(dir.path(), "prism.stl", &stl(&solid));
    let nc = write(dir.path(), "p.nc", plunges(15.0, 15.0).as_bytes());
    let v = json(&kezuri(&["sim", &nc, "--tool", "ball:2", "--res", "0.5", "--stock", &stock, "--json"]));
    assert_eq!(v["rapids_into_stock"], 1, "{v}");
    assert_eq!(v["first_rapid_into_stock_line"], 5);
    assert_eq!(v["stock"]["solid"], stock);
    assert_eq!((num(&v["stock"]["x1"]), num(&v["stock"]["top"])), (20.0, 0.0));
    // Beside the outline the grid starts at the bottom, Z −5: the second
    // plunge to Z −1 cuts nothing there.
    let cut = path(dir.path(), "cut.stl");
    ok(&kezuri(&["sim", &nc, "--tool", "ball:2", "--res", "0.5", "--stock", &stock, "--stl", &cut]));
    let lowest_beside = cell_heights(&cut).into_iter().filter(|&z| z < -4.0).count();
    // The cells past the side x + y = 20: centres 0.5·(i + j + 1) > 20,
    // i + j ≥ 40 for i, j in 0 … 39: 39 · 40 / 2 (those on the side, x + y
    // = 20 exactly, are in the top).
    assert_eq!(lowest_beside, 39 * 40 / 2);
    let o = kezuri(&["sim", &nc, "--tool", "ball:2", "--res", "0.5", "--stock", &path(dir.path(), "none.stl")]);
    assert_eq!(o.status.code(), Some(1));
}
