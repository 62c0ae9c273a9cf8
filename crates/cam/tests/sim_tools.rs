//! Simulation with the tool each move is made by: every cell against a
//! brute-force oracle (each move's envelope in program order, the volume
//! each tool removed counted cell by cell), the tool before the first
//! change, a tool the table lacks; cylinder and solid stock.

use kezuri_cam::sim::{
    simulate_tool, simulate_tools, swept_height_tool, Cylinder, SimOptions, Stock, Tool, Tooling, ZMap, UNCUT,
};
use kezuri_cam::ErrorKind;
use kezuri_geom::{Axes, Move, MoveKind, Toolpath};

fn at(x: f64, y: f64, z: f64) -> Axes {
    Axes { x, y, z, ..Axes::ZERO }
}

fn mv(kind: MoveKind, a: [f64; 3], b: [f64; 3], tool: u32) -> Move {
    Move { kind, start: at(a[0], a[1], a[2]), end: at(b[0], b[1], b[2]), tool, ..Move::default() }
}

fn tool(spec: &str) -> Tool {
    Tool::Cutter(spec.parse().unwrap())
}

/// The oracle: each cell lowered by each move in program order (the same
/// per-point envelope, evaluated alone), the removal counted per tool.
fn brute_force(path: &Toolpath, table: &[(u32, Tool)], zmap: &ZMap) -> (Vec<f64>, Vec<(u32, f64)>) {
    let mut z: Vec<f64> = zmap.heights().collect();
    let mut removed: Vec<(u32, f64)> = Vec::new();
    for m in &path.moves {
        let t = &table.iter().find(|(n, _)| *n == m.tool).unwrap().1;
        if !removed.iter().any(|(n, _)| *n == m.tool) {
            removed.push((m.tool, 0.0));
        }
        let slot = removed.iter().position(|(n, _)| *n == m.tool).unwrap();
        for j in 0..zmap.ny {
            for i in 0..zmap.nx {
                let [x, y] = zmap.centre(i, j);
                if let Some(h) = swept_height_tool(t, m.start.xyz(), m.end.xyz(), x, y) {
                    let c = &mut z[j * zmap.nx + i];
                    if h < *c {
                        removed[slot].1 += (*c - h) * zmap.res * zmap.res;
                        *c = h;
                    }
                }
            }
        }
    }
    (z, removed)
}

/// Roughing with a flat:6 (T1) and finishing with a ball:2 (T2), the tools
/// changing back and forth, over a 20 × 12 box.
fn two_tool_path() -> Toolpath {
    let mut moves = Vec::new();
    for k in 0..6 {
        let y = 2.0 + 1.5 * k as f64;
        let (t, z) = if k % 2 == 0 { (1, -1.0) } else { (2, -1.7 + 0.1 * k as f64) };
        moves.push(mv(MoveKind::Feed, [1.0, y, z], [19.0, y + 0.3, z - 0.2], t));
        moves.push(mv(MoveKind::Feed, [19.0, y + 0.3, z - 0.2], [10.0, y + 1.0, z], t));
    }
    Toolpath::from(moves)
}

#[test]
fn sim_each_move_is_cut_by_its_own_tool_and_the_volumes_add_up() {
    let path = two_tool_path();
    let table = [(1, tool("flat:6")), (2, tool("ball:2"))];
    let options = SimOptions::new(0.1);
    let mut zmap = ZMap::new(&Stock { x0: 0.0, y0: 0.0, x1: 20.0, y1: 12.0, top: 0.0 }, &options).unwrap();
    let (want_z, want_removed) = brute_force(&path, &table, &zmap);
    let report = simulate_tools(&path, Tooling::Table(&table), &mut zmap, &options, &|_, _| {}).unwrap();
    // Heights are kept to the nanometre: the oracle's, rounded.
    for (k, (got, &want)) in zmap.heights().zip(&want_z).enumerate() {
        assert!((got - want).abs() <= 0.5e-6 + 1e-12, "cell {k}: {got} against {want}");
    }
    assert_eq!(report.tools.iter().map(|t| (t.number, t.moves)).collect::<Vec<_>>(), [(1, 6), (2, 6)]);
    for (cut, (n, v)) in report.tools.iter().zip(&want_removed) {
        assert_eq!(cut.number, *n);
        assert!(*v > 1.0, "T{n} removes material");
        // Each cell's heights to the nanometre: at most half of one over its area each.
        let rounding = 0.5e-6 * zmap.res * zmap.res * zmap.cells() as f64;
        assert!((cut.volume - v).abs() <= rounding + 1e-9 * v, "T{n}: {} against {v}", cut.volume);
    }
    // Every lowered cell names a tool; the total is the sum of the tools'.
    let total: f64 = zmap.heights().map(|z| (0.0 - z) * 0.01).sum();
    let sum: f64 = report.tools.iter().map(|t| t.volume).sum();
    assert!((total - sum).abs() <= 1e-9 * total);
    for (z, &by) in zmap.heights().zip(&report.cut_by) {
        assert_eq!(z < 0.0, by != UNCUT);
    }
}

#[test]
fn sim_the_last_tool_to_lower_a_cell_owns_it() {
    // A flat:6 slot at Z −1, then a ball:2 along its middle at Z −2 and
    // a ball:2 pass at Z −0.5 that stays above the slot's floor.
    let path = Toolpath::from(vec![
        mv(MoveKind::Feed, [2.0, 5.0, -1.0], [18.0, 5.0, -1.0], 1),
        mv(MoveKind::Feed, [2.0, 5.0, -2.0], [18.0, 5.0, -2.0], 2),
        mv(MoveKind::Feed, [2.0, 6.0, -0.5], [18.0, 6.0, -0.5], 2),
    ]);
    let table = [(1, tool("flat:6")), (2, tool("ball:2"))];
    let options = SimOptions::new(0.25);
    let mut zmap = ZMap::new(&Stock { x0: 0.0, y0: 0.0, x1: 20.0, y1: 10.0, top: 0.0 }, &options).unwrap();
    let report = simulate_tools(&path, Tooling::Table(&table), &mut zmap, &options, &|_, _| {}).unwrap();
    let cell = |x: f64, y: f64| ((y / 0.25) as usize) * zmap.nx + (x / 0.25) as usize;
    assert_eq!(report.cut_by[cell(10.1, 5.1)], 1, "the ball's groove in the middle");
    assert_eq!(report.cut_by[cell(10.1, 7.6)], 0, "the flat's floor beyond the ball's reach");
    assert_eq!(report.cut_by[cell(10.1, 5.6)], 1, "the ball went deeper there too");
    assert_eq!(report.cut_by[cell(10.1, 6.1)], 0, "the last pass stays above the floor");
    assert_eq!(report.cut_by[cell(10.1, 9.1)], UNCUT);
    // The flat removed its slot 1 deep: 16 × 6 and two half discs of radius
    // 3, less what of each disc lies past the grid's ends (a circular
    // segment 2 from the centre: r²·acos(d/r) − d·√(r² − d²)); the cells
    // measure it to about 1 %.
    let outside = 9.0 * (2.0f64 / 3.0).acos() - 2.0 * 5.0f64.sqrt();
    let slot = 16.0 * 6.0 + std::f64::consts::PI * 9.0 - 2.0 * outside;
    assert!((report.tools[0].volume - slot).abs() < 0.01 * slot, "{} against {slot}", report.tools[0].volume);
}

#[test]
fn sim_moves_before_the_first_change_cut_with_the_first_tool() {
    // A rapid down into the stock before T1 M06 (tool 0): found, as wide
    // as T1's flat:8 (a ball:2 would have lowered cells 1 mm off only).
    let path = Toolpath::from(vec![
        mv(MoveKind::Rapid, [10.0, 10.0, 5.0], [10.0, 10.0, -1.0], 0),
        mv(MoveKind::Feed, [10.0, 10.0, -1.0], [12.0, 10.0, -1.0], 1),
        mv(MoveKind::Feed, [12.0, 10.0, -1.0], [12.0, 10.0, 5.0], 2),
    ]);
    let table = [(1, tool("flat:8")), (2, tool("ball:2"))];
    let options = SimOptions::new(0.5);
    let mut zmap = ZMap::new(&Stock { x0: 0.0, y0: 0.0, x1: 20.0, y1: 20.0, top: 0.0 }, &options).unwrap();
    let report = simulate_tools(&path, Tooling::Table(&table), &mut zmap, &options, &|_, _| {}).unwrap();
    assert_eq!(report.rapid_hits.len(), 1);
    assert_eq!(report.tools.iter().map(|t| (t.number, t.moves)).collect::<Vec<_>>(), [(1, 2), (2, 1)]);
    // Centre (6.25, 10.25), 3.76 mm from the axis: inside the flat:8's 4 mm
    // radius, beyond the ball:2's.
    assert_eq!(zmap.height(12, 20), -1.0);
    // One tool for every move: the same result as the table giving it to both.
    let one = tool("flat:8");
    let mut again = ZMap::new(&Stock { x0: 0.0, y0: 0.0, x1: 20.0, y1: 20.0, top: 0.0 }, &options).unwrap();
    let same = simulate_tool(&path, &one, &mut again, &options).unwrap();
    let both = [(1, one.clone()), (2, one)];
    let mut table_grid = ZMap::new(&Stock { x0: 0.0, y0: 0.0, x1: 20.0, y1: 20.0, top: 0.0 }, &options).unwrap();
    let by_table = simulate_tools(&path, Tooling::Table(&both), &mut table_grid, &options, &|_, _| {}).unwrap();
    assert_eq!(again.nm, table_grid.nm);
    assert_eq!(same.tools, by_table.tools);
}

#[test]
fn sim_a_tool_the_table_lacks_is_an_error() {
    let path = Toolpath::from(vec![
        mv(MoveKind::Feed, [0.0, 0.0, -1.0], [5.0, 0.0, -1.0], 1),
        Move { line: 12, ..mv(MoveKind::Feed, [5.0, 0.0, -1.0], [5.0, 5.0, -1.0], 3) },
    ]);
    let table = [(1, tool("flat:6"))];
    let options = SimOptions::new(0.5);
    let mut zmap = ZMap::new(&Stock { x0: -5.0, y0: -5.0, x1: 10.0, y1: 10.0, top: 0.0 }, &options).unwrap();
    let e = simulate_tools(&path, Tooling::Table(&table), &mut zmap, &options, &|_, _| {}).unwrap_err();
    assert_eq!(e.kind, ErrorKind::NoTool);
    assert_eq!(e.to_string(), "T3 (first moving at line 12) has no shape to cut with");
    assert!(e.to_string().contains("T3"), "{e}");
}

#[test]
fn sim_progress_counts_up_to_the_whole() {
    use std::sync::atomic::{AtomicU64, Ordering};
    let path = two_tool_path();
    let table = [(1, tool("flat:6")), (2, tool("ball:2"))];
    let options = SimOptions::new(0.1);
    let mut zmap = ZMap::new(&Stock { x0: 0.0, y0: 0.0, x1: 20.0, y1: 12.0, top: 0.0 }, &options).unwrap();
    let (most, whole) = (AtomicU64::new(0), AtomicU64::new(0));
    let seen = |done: u64, total: u64| {
        most.fetch_max(done, Ordering::Relaxed);
        whole.store(total, Ordering::Relaxed);
    };
    simulate_tools(&path, Tooling::Table(&table), &mut zmap, &options, &seen).unwrap();
    assert!(whole.load(Ordering::Relaxed) >= 12);
    assert_eq!(most.load(Ordering::Relaxed), whole.load(Ordering::Relaxed));
}

#[test]
fn sim_a_cylinder_stands_on_its_bottom() {
    let options = SimOptions::new(0.5);
    let c = Cylinder { x: 10.0, y: -4.0, diameter: 8.0, height: 5.0, top: 2.0 };
    let zmap = ZMap::cylinder(&c, &options).unwrap();
    assert_eq!((zmap.nx, zmap.ny, zmap.x0, zmap.y0), (16, 16, 6.0, -8.0));
    for j in 0..zmap.ny {
        for i in 0..zmap.nx {
            let [x, y] = zmap.centre(i, j);
            let inside = (x - 10.0).powi(2) + (y + 4.0).powi(2) <= 16.0;
            assert_eq!(zmap.height(i, j), if inside { 2.0 } else { -3.0 }, "({x}, {y})");
        }
    }
    // π r² over cells of 0.25 mm²: the cells in the circle, to a ring of cells.
    let inside = zmap.heights().filter(|&z| z == 2.0).count() as f64 * 0.25;
    assert!((inside - std::f64::consts::PI * 16.0).abs() < 2.0 * std::f64::consts::PI * 4.0 * 0.5);
    for bad in [Cylinder { diameter: 0.0, ..c }, Cylinder { height: -1.0, ..c }, Cylinder { top: f64::NAN, ..c }] {
        assert!(matches!(ZMap::cylinder(&bad, &options), Err(e) if e.kind == ErrorKind::Stock));
    }
}

#[test]
fn sim_a_solid_stock_is_its_top_surface() {
    // A roof over 0..10 × 0..4: ridge along Y = 2 at Z 3, eaves at Z 1;
    // its triangles only (no bottom face), over a grid of 10 × 4 cells.
    let tri = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| [a, b, c];
    let (p, q) = ([0.0, 2.0, 3.0], [10.0, 2.0, 3.0]);
    let roof = [
        tri([0.0, 0.0, 1.0], [10.0, 0.0, 1.0], q),
        tri([0.0, 0.0, 1.0], q, p),
        tri(p, q, [10.0, 4.0, 1.0]),
        tri(p, [10.0, 4.0, 1.0], [0.0, 4.0, 1.0]),
    ];
    let zmap = ZMap::top_of(&roof, &SimOptions::new(1.0)).unwrap();
    assert_eq!((zmap.nx, zmap.ny), (10, 4));
    // Centres at Y 0.5 and 1.5: 1 + 2·(y/2).
    for (j, want) in [(0, 1.5), (1, 2.5), (2, 2.5), (3, 1.5)] {
        assert!((zmap.height(4, j) - want).abs() <= 0.5e-6 + 1e-12, "row {j}: {}", zmap.height(4, j));
    }
    assert!(matches!(ZMap::top_of(&[], &SimOptions::new(1.0)), Err(e) if e.kind == ErrorKind::Stock));
}
