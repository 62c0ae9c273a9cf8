//! `kezuri view`'s page: its data unpacked here as the page's viewer
//! unpacks it and held against the program (`run --emit csv`), the arcs'
//! chords against their circles, the page's safety with hostile text, and
//! what it refuses. The page in a real browser: `view_browser.rs`.

mod common;

use std::io::Read as _;

use base64::Engine as _;
use common::{kezuri, ok, path};
use serde_json::Value;

/// The page's meta, data and program text.
struct Page {
    html: String,
    meta: Value,
    data: Vec<u8>,
    text: Option<String>,
}

/// The content of `<script … id="ID">…</script>`.
fn element<'a>(html: &'a str, id: &str) -> Option<&'a str> {
    let open = html.find(&format!("id=\"{id}\">"))? + id.len() + 6;
    Some(&html[open..open + html[open..].find("</script>")?])
}

fn unpack(b64: &str) -> Vec<u8> {
    let gz = base64::engine::general_purpose::STANDARD.decode(b64.trim()).unwrap();
    let mut out = Vec::new();
    flate2::read::GzDecoder::new(&gz[..]).read_to_end(&mut out).unwrap();
    out
}

fn read_page(file: &str) -> Page {
    let html = std::fs::read_to_string(file).unwrap();
    let meta = serde_json::from_str(element(&html, "kz-meta").unwrap()).unwrap();
    let data = unpack(element(&html, "kz-data").unwrap());
    let text = element(&html, "kz-text").map(|t| String::from_utf8(unpack(t)).unwrap());
    Page { html, meta, data, text }
}

/// The packed columns, read in the page's order.
struct Columns {
    kind: Vec<u8>,
    tool: Vec<u16>,
    line: Vec<i64>,
    feed: Vec<f32>,
    seconds: Vec<f32>,
    counts: Vec<u32>,
    vertices: Vec<[f64; 3]>,
    breaks: Vec<u8>,
}

struct Reader<'a> {
    data: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn take(&mut self, n: usize) -> &[u8] {
        let s = &self.data[self.at..self.at + n];
        self.at = (self.at + n).next_multiple_of(4);
        s
    }
    fn i32s(&mut self, n: usize) -> Vec<i32> {
        self.take(4 * n).chunks(4).map(|c| i32::from_le_bytes(c.try_into().unwrap())).collect()
    }
}

fn columns(page: &Page) -> Columns {
    let n = page.meta["moves"].as_u64().unwrap() as usize;
    let v = page.meta["vertices"].as_u64().unwrap() as usize;
    let mut r = Reader { data: &page.data, at: 0 };
    let kind = r.take(n).to_vec();
    let tool = r.take(2 * n).chunks(2).map(|c| u16::from_le_bytes([c[0], c[1]])).collect();
    let _frame = r.take(2 * n);
    let mut line = 0i64;
    let line = r.i32s(n).into_iter().map(|d| {
        line += i64::from(d);
        line
    });
    let line = line.collect();
    let f32s = |r: &mut Reader| -> Vec<f32> { r.i32s(n).into_iter().map(|b| f32::from_bits(b as u32)).collect() };
    let feed = f32s(&mut r);
    let seconds = f32s(&mut r);
    let counts = r.i32s(n).into_iter().map(|c| c as u32).collect();
    let (dx, dy, dz) = (r.i32s(v), r.i32s(v), r.i32s(v));
    let breaks = r.take(v).to_vec();
    let q = page.meta["quantum_mm"].as_f64().unwrap();
    let origin: Vec<f64> = page.meta["origin_mm"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    let mut at = [0i64; 3];
    let vertices = (0..v)
        .map(|k| {
            at = [at[0] + i64::from(dx[k]), at[1] + i64::from(dy[k]), at[2] + i64::from(dz[k])];
            std::array::from_fn(|a| origin[a] + q * at[a] as f64)
        })
        .collect();
    Columns { kind, tool, line, feed, seconds, counts, vertices, breaks }
}

const PROGRAM: &str = "\
%
O0100 (VIEW TEST)
G21 G90 G17 G54
T1 M6
G0 X0. Y0. Z5.
G1 Z-1. F100.
G2 X10. Y0. I5. J0. F200.
G18 G3 X20. Z-1. I5. K0.
G19 G2 Y10. Z-1. J5. K0.
G17 G4 P500
G0 Z5.
T2 M6
G92 X0. Y0.
G1 X1. Y1. F300.
G3 X1. Y1. Z-2. I1. J0.
M30
%
";

/// Every move's end, line, kind and feed as the program gives them; arcs'
/// chords on their circles within the stated tolerance; tools in order.
#[test]
fn the_page_holds_the_program_as_run() {
    let dir = tempfile::tempdir().unwrap();
    let nc = path(dir.path(), "part.nc");
    std::fs::write(&nc, PROGRAM).unwrap();
    let html = path(dir.path(), "part.html");
    ok(&kezuri(&["view", &nc, "--tool", "ball:6", "--arc-tol", "0.002", "-o", &html]));
    let page = read_page(&html);
    let c = columns(&page);
    assert_eq!(page.text.as_deref(), Some(PROGRAM));
    assert_eq!(page.meta["units"], "mm");

    // The moves against `run --emit csv` (line, kind, x, y, z, …, feed;
    // no row for a dwell).
    let csv = ok(&kezuri(&["run", &nc, "--emit", "csv"]));
    let mut rows = csv.lines().skip(1).map(|l| l.split(',').collect::<Vec<_>>());
    let mut vertex = 0usize;
    for i in 0..c.kind.len() {
        vertex += c.counts[i] as usize;
        if c.kind[i] == 5 {
            assert_eq!((c.counts[i], c.line[i]), (0, 10));
            continue;
        }
        let row = rows.next().expect("a row for every move but the dwell");
        let end = c.vertices[vertex - 1];
        let want: Vec<f64> = row[2..5].iter().map(|v| v.parse().unwrap()).collect();
        for a in 0..3 {
            assert!((end[a] - want[a]).abs() <= 0.5e-4 + 1e-12, "move {i} axis {a}: {end:?} vs {row:?}");
        }
        assert_eq!(c.line[i].to_string(), row[0], "move {i}");
        let kind = match c.kind[i] {
            0 => "rapid",
            1 | 3 => "feed",
            2 => "arc",
            k => panic!("kind {k}"),
        };
        let csv_kind = if row[1] == "cw" || row[1] == "ccw" { "arc" } else { row[1] };
        assert_eq!(kind, csv_kind, "move {i}");
        if kind != "rapid" {
            assert!((f64::from(c.feed[i]) - row[8].parse::<f64>().unwrap()).abs() < 1e-3, "move {i}");
        }
        assert!(c.seconds[i] >= 0.0);
    }
    assert!(rows.next().is_none());
    assert_eq!(vertex, c.vertices.len());
    assert_eq!(c.kind.iter().filter(|&&k| k == 3).count(), 1, "one plunge (G1 Z-1)");
    assert_eq!(c.breaks[0], 1);
    // G92 makes no jump in the machine's path: the tool stays where it is.
    assert_eq!(c.breaks.iter().filter(|&&b| b == 1).count(), 1);

    // Arcs: (centre, radius, plane axes) in machine coordinates.
    let arcs = [
        ([5.0, 0.0, -1.0], 5.0, (0, 1)),
        ([15.0, 0.0, -1.0], 5.0, (2, 0)),
        ([20.0, 5.0, -1.0], 5.0, (1, 2)),
        ([22.0, 11.0, 0.0], 1.0, (0, 1)),
    ];
    let tol = 0.002;
    let mut first = 0usize;
    let mut arc = 0;
    for i in 0..c.kind.len() {
        let range = first..first + c.counts[i] as usize;
        first = range.end;
        if c.kind[i] != 2 {
            continue;
        }
        let (centre, r, (p, q)) = arcs[arc];
        arc += 1;
        let mut prev = c.vertices[range.start - 1];
        assert!(range.len() > 10, "arc {arc}: {} chords", range.len());
        for k in range {
            let v = c.vertices[k];
            let d = (v[p] - centre[p]).hypot(v[q] - centre[q]);
            assert!((d - r).abs() < 2e-4, "arc {arc} vertex off the circle by {}", d - r);
            let mid = ((prev[p] + v[p]) / 2.0 - centre[p]).hypot((prev[q] + v[q]) / 2.0 - centre[q]);
            assert!(r - mid <= tol + 2e-4, "arc {arc}: sagitta {}", r - mid);
            prev = v;
        }
    }
    assert_eq!(arc, 4);

    // Tools in order of use, with their outline; T1 and T2 both ball:6 (--tool).
    let tools = page.meta["tools"].as_array().unwrap();
    assert_eq!(tools.iter().map(|t| t["number"].as_u64().unwrap()).collect::<Vec<_>>(), [1, 2]);
    assert_eq!(tools[0]["shape"], "ball:6");
    let outline = tools[0]["profile"].as_array().unwrap();
    assert_eq!(outline[0], serde_json::json!([0.0, 0.0]));
    assert!(c.tool.contains(&1));
    // Cycle time: the moves' times, the dwell's 0.5 s among them.
    let total: f64 = c.seconds.iter().map(|&s| f64::from(s)).sum();
    assert!((total - page.meta["cycle_time_s"].as_f64().unwrap()).abs() < 1e-3);
    assert!(c.seconds.iter().any(|&s| (s - 0.5).abs() < 1e-6));
}

/// A program that returns to the reference point (`G91 G28`, the relief's
/// own start and end) with tool lengths from the machine file: the returns,
/// and the move made before Z is named again, are kind 6 with no vertex
/// (not drawn, nor the tool there), and the page's box is the job's, not
/// the reference point's Z less the tool length (-31.75 mm).
#[test]
fn returns_to_the_reference_point_are_not_drawn() {
    let dir = tempfile::tempdir().unwrap();
    let nc = path(dir.path(), "returns.nc");
    let program = "%\nO0001\nG21\nG90 G17 G94 G40 G49 G80\nG54\nG91 G28 Z0.\nG90\nT1 M06\nS10000 M03\n\
                   G00 X5. Y5.\nG00 G43 H1 Z5.\nG01 Z-3. F300.\nX20. F1500.\nG00 Z5.\nG91 G28 Z0.\nG90\n\
                   G91 G28 X0. Y0.\nG90\nG53 Z0.\nM30\n%\n";
    std::fs::write(&nc, program).unwrap();
    let html = path(dir.path(), "returns.html");
    let machine = concat!(env!("CARGO_MANIFEST_DIR"), "/../../samples/tools/mill.toml");
    ok(&kezuri(&["view", &nc, "--machine", machine, "-o", &html]));
    let page = read_page(&html);
    let c = columns(&page);
    // G28 Z; X5 Y5 with Z at the reference point; G43 Z5 (its end alone);
    // the cut; Z5; G28 Z; G28 X Y; G53 Z.
    assert_eq!(c.kind, [6, 6, 0, 3, 1, 0, 6, 6, 6]);
    assert_eq!(c.counts, [0, 0, 1, 1, 1, 1, 0, 0, 0]);
    assert_eq!(c.breaks[0], 1);
    assert_eq!(page.meta["bbox_mm"], serde_json::json!([[5.0, 5.0, -3.0], [20.0, 5.0, 5.0]]));
    assert!(c.vertices.iter().all(|v| v[2] >= -3.0 - 1e-9), "{:?}", c.vertices);
    // With the reference point given, returns are known places, drawn; the
    // first still ends where the machine started in X and Y.
    let given = path(dir.path(), "given.toml");
    std::fs::write(&given, "[offsets]\nhome = [0, 0, 0]\n").unwrap();
    ok(&kezuri(&["view", &nc, "--machine", &given, "-o", &html]));
    assert_eq!(columns(&read_page(&html)).kind, [6, 0, 0, 3, 1, 0, 0, 0, 0]);
}

/// A comment holding `</script>` and HTML, and a file name holding `<`,
/// stay data: the page has exactly its own four script elements, and the
/// text comes back unchanged.
#[test]
fn hostile_text_cannot_become_markup() {
    let dir = tempfile::tempdir().unwrap();
    let nc = path(dir.path(), "a<b>&.nc");
    let program = "G21 G90\n(</script><script>alert 1</script>)\n(<img src=x onerror=alert>)\nG1 X10. F100.\nM30\n";
    std::fs::write(&nc, program).unwrap();
    let html = path(dir.path(), "p.html");
    ok(&kezuri(&["view", &nc, "-o", &html]));
    let page = read_page(&html);
    assert_eq!(page.html.matches("<script").count(), 4, "meta, data, text, viewer");
    assert_eq!(page.html.matches("</script>").count(), 4);
    assert!(!page.html.contains("<img") && !page.html.contains("alert"));
    assert_eq!(page.text.as_deref(), Some(program));
    assert!(page.meta["title"].as_str().unwrap().ends_with("a<b>&.nc"));
    let csp = "default-src 'none'; script-src 'sha256-";
    assert!(page.html.contains(csp));
}

/// A page no level of detail can bring under --max-page-mb (the viewer
/// alone is some 65 kB) is refused with what to do, and nothing is written;
/// an empty program makes a page that says so (0 moves).
#[test]
fn too_big_is_refused_and_empty_is_a_page() {
    let dir = tempfile::tempdir().unwrap();
    let nc = path(dir.path(), "long.nc");
    let mut program = String::from("G21 G90\nG0 X0 Y0 Z1\n");
    for k in 0..20_000 {
        program.push_str(&format!(
            "G1 X{:.3} Y{:.3} Z{:.3} F500\n",
            k as f64 * 0.01,
            (k as f64 * 0.1).sin(),
            -(k % 7) as f64 * 0.01
        ));
    }
    std::fs::write(&nc, &program).unwrap();
    let html = path(dir.path(), "long.html");
    let o = kezuri(&["view", &nc, "--max-page-mb", "0.05", "-o", &html]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--max-page-mb") && err.contains("MB"), "{err}");
    assert!(!std::path::Path::new(&html).exists());
    // --shorten merges and says so on the page.
    ok(&kezuri(&["view", &nc, "--shorten", "0.05", "--no-text", "-o", &html]));
    let page = read_page(&html);
    assert!(page.text.is_none());
    assert!(page.meta["notes"][0].as_str().unwrap().starts_with("shortened within 0.05 mm: 20001 moves drawn as"));

    let empty = path(dir.path(), "empty.nc");
    std::fs::write(&empty, "G21 G90\nM30\n").unwrap();
    ok(&kezuri(&["view", &empty, "-o", &html]));
    let page = read_page(&html);
    assert_eq!(page.meta["moves"], 0);
    assert_eq!(page.meta["bbox_mm"], Value::Null);
}

/// `sim --view` writes the page with its other outputs; the part's grid,
/// deviation and marks are there; `view --compare` needs `--sim`.
#[test]
fn the_simulated_part_and_its_deviation() {
    let dir = tempfile::tempdir().unwrap();
    let nc = path(dir.path(), "pocket.nc");
    // A 6 mm ball cuts a 1 mm deep groove; the target is flat at -0.5:
    // the groove's bottom is a 0.5 mm gouge, and a rapid crosses the stock.
    std::fs::write(&nc, "G21 G90\nG0 X-5. Y5. Z5.\nG1 Z-1. F100.\nG1 X25. F300.\nG0 Y1. Z-0.2\nG0 X-5.\nG0 Z5.\nM30\n")
        .unwrap();
    let target = path(dir.path(), "flat.xyz");
    let mut grid = String::new();
    for j in 0..=10 {
        for i in 0..=20 {
            grid.push_str(&format!("{} {} -0.5\n", i as f64, j as f64));
        }
    }
    std::fs::write(&target, grid).unwrap();
    let (png, html) = (path(dir.path(), "p.png"), path(dir.path(), "p.html"));
    // `sim` or `view --sim` of the groove against the flat target.
    let cut = |command: &[&str], extra: &[&str]| {
        let part = [&nc, "--tool", "ball:6", "--res", "0.25", "--stock", "0,0,20,10,0", "--compare", &target];
        kezuri(&[command, &part[..], extra].concat())
    };
    ok(&cut(&["sim"], &["-o", &png, "--view", &html]));
    assert!(std::path::Path::new(&png).exists());
    let page = read_page(&html);
    let sim = &page.meta["sim"];
    assert_eq!((sim["nx"].as_u64(), sim["ny"].as_u64()), (Some(80), Some(40)));
    let dev = &sim["deviation"];
    assert_eq!(dev["scale_basis"], "the 99th percentile of |deviation|");
    assert!((dev["scale_um"].as_f64().unwrap() - 500.0).abs() < 1.0, "{dev}");
    // The largest of each side, for the colours beyond the scale: 0.5 mm of
    // stock left over the flat target, the groove 0.5 mm below it.
    assert!((dev["left_max_um"].as_f64().unwrap() - 500.0).abs() < 1.0, "{dev}");
    assert!((dev["gouge_max_um"].as_f64().unwrap() - 500.0).abs() < 5.0, "{dev}");
    let kinds: Vec<&str> = page.meta["marks"].as_array().unwrap().iter().map(|m| m["kind"].as_str().unwrap()).collect();
    assert_eq!(kinds, ["rapid", "gouge"]);
    // The heights: delta coded after the path's columns; their sum's range
    // is the part's (0 to 1 mm deep).
    let c = columns(&page);
    let n = c.kind.len();
    let v = c.vertices.len();
    let start = n.next_multiple_of(4) + (2 * n).next_multiple_of(4) * 2 + 16 * n + 12 * v + v.next_multiple_of(4);
    let mut r = Reader { data: &page.data, at: start };
    let mut h = 0i64;
    let heights: Vec<f64> = r
        .i32s(80 * 40)
        .into_iter()
        .map(|d| {
            h += i64::from(d);
            sim["z0_mm"].as_f64().unwrap() + h as f64 * 1e-4
        })
        .collect();
    let (lo, hi) = heights.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &z| (a.min(z), b.max(z)));
    // The groove bottom between two rows of centres: 3 − √(9 − 0.125²) above Z−1.
    assert!((lo + 1.0 - (3.0 - (9.0f64 - 0.015625).sqrt())).abs() < 2e-4 && hi.abs() < 1e-4, "{lo} {hi}");

    // The program's own allowance: a 0.5 mm dip within --gouge-tol 0.6 is
    // no gouge, and no worst gouge is marked.
    ok(&cut(&["view", "--sim"], &["--gouge-tol", "0.6", "-o", &html]));
    let page = read_page(&html);
    assert_eq!(page.meta["sim"]["deviation"]["gouge_um"], 600.0);
    assert_eq!(page.meta["marks"].as_array().unwrap().len(), 1);

    let o = kezuri(&["view", &nc, "--compare", &target, "-o", &html]);
    assert!(!o.status.success());
}
