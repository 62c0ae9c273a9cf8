//! A grid cut in tiles of rows gives the grid cut whole, cell for cell:
//! every height (in whole nanometres), the tool that lowered each cell
//! last, each tool's volume and the rapids that cut. And heights a cell
//! cannot keep are clear errors.

use std::time::Instant;

use kezuri_cam::sim::{
    simulate_tiles, simulate_tools, tile_rows, Cylinder, Grid, SimOptions, Start, Stock, Tool, Tooling, ZMap,
    CELL_BYTES, LOWEST,
};
use kezuri_cam::{Error, ErrorKind};
use kezuri_geom::{Axes, Move, MoveKind, Toolpath};

fn at(x: f64, y: f64, z: f64) -> Axes {
    Axes { x, y, z, ..Axes::ZERO }
}

fn mv(kind: MoveKind, a: [f64; 3], b: [f64; 3], tool: u32) -> Move {
    Move { kind, start: at(a[0], a[1], a[2]), end: at(b[0], b[1], b[2]), tool, line: 1, ..Move::default() }
}

/// Over a `size` mm square: a flat:6 (T1) roughing along X every 4 mm at
/// Z −1, a ball:2 (T2) finishing along Y every 0.7 mm over a wavy floor in
/// 2.5 mm pieces and a bull-nose (T3) diagonal; first a rapid across the
/// part at Z −0.5, into the stock.
fn job(size: f64) -> Toolpath {
    let mut moves = vec![mv(MoveKind::Rapid, [0.0, 0.3 * size, -0.5], [size, 0.7 * size, -0.5], 1)];
    let mut y = 1.0;
    while y < size - 1.0 {
        moves.push(mv(MoveKind::Feed, [0.0, y, -1.0], [size, y + 0.5, -1.0], 1));
        y += 4.0;
    }
    let floor = |x: f64, y: f64| -0.9 + 0.3 * (x * 0.37).sin() * (y * 0.23).cos();
    let mut x = 0.35;
    while x < size {
        let mut y = 0.0;
        while y < size {
            let y1 = (y + 2.5).min(size);
            moves.push(mv(MoveKind::Feed, [x, y, floor(x, y)], [x, y1, floor(x, y1)], 2));
            y = y1;
        }
        x += 0.7;
    }
    moves.push(mv(MoveKind::Feed, [size, 0.0, -0.8], [0.0, size, -1.6], 3));
    Toolpath::from(moves)
}

fn table() -> Vec<(u32, Tool)> {
    ["flat:6", "ball:2", "bull:4,1"]
        .iter()
        .enumerate()
        .map(|(k, s)| (k as u32 + 1, Tool::Cutter(s.parse().unwrap())))
        .collect()
}

/// The job over a `size` mm box at `res`, whole and in tiles of `rows`
/// rows: asserts they agree cell for cell; returns the cells and tiles.
fn whole_against_tiles(size: f64, res: f64, rows: usize) -> (usize, usize) {
    let path = job(size);
    let table = table();
    let stock = Stock { x0: 0.0, y0: 0.0, x1: size, y1: size, top: 0.0 };
    let mut options = SimOptions::new(res);
    options.max_memory = u64::MAX;
    let t0 = Instant::now();
    let mut whole = ZMap::new(&stock, &options).unwrap();
    let want = simulate_tools(&path, Tooling::Table(&table), &mut whole, &options, &|_, _| {}).unwrap();
    let t1 = Instant::now();
    let (mut nm, mut cut_by, mut tiles) = (Vec::new(), Vec::new(), 0);
    let got = simulate_tiles::<Error>(
        &path,
        Tooling::Table(&table),
        &Start::Box(stock),
        &options,
        rows,
        &|_, _| {},
        &mut |tile, by, top| {
            assert_eq!(top, 0.0, "the stock's top before cutting");
            assert_eq!(tile.first_row, nm.len() / tile.nx, "tiles come bottom up, rows in order");
            assert!(tile.ny <= rows);
            nm.extend_from_slice(&tile.nm);
            cut_by.extend_from_slice(by);
            tiles += 1;
            Ok(())
        },
    )
    .unwrap();
    eprintln!(
        "{} cells: whole {:.2} s, {tiles} tiles of {rows} rows {:.2} s",
        whole.cells(),
        (t1 - t0).as_secs_f64(),
        t1.elapsed().as_secs_f64()
    );
    assert_eq!(nm.len(), whole.cells());
    let differ = nm.iter().zip(&whole.nm).filter(|(a, b)| a != b).count();
    assert_eq!(differ, 0, "cells whose height differs");
    assert_eq!(cut_by, want.cut_by, "the tool that lowered each cell last");
    assert!(got.cut_by.is_empty());
    // Everything else the report says is the same, to the bit: volumes are
    // whole nanometres summed, rapids the deepest per move.
    let mut want = want;
    want.cut_by.clear();
    assert_eq!(got, want);
    assert_eq!(got.tools.len(), 3);
    assert!(got.tools.iter().all(|t| t.volume > 0.0), "{:?}", got.tools);
    assert_eq!(got.rapid_hits.len(), 1, "the rapid at Z −0.5 through the stock");
    // The job cuts most of the cells, and not all with one tool.
    let cut = |k: u8| cut_by.iter().filter(|&&b| b == k).count();
    let some = whole.cells() / 100;
    assert!(cut(0) > some && cut(1) > some && cut(2) > some, "{} {} {}", cut(0), cut(1), cut(2));
    (whole.cells(), tiles)
}

#[test]
fn a_grid_cut_in_tiles_is_the_grid_cut_whole_cell_for_cell() {
    // 40 mm at 0.04: 1,000,000 cells; 37 rows a tile: 28 tiles, the last
    // short, tile edges falling inside the bands of the whole grid.
    let (cells, tiles) = whole_against_tiles(40.0, 0.04, 37);
    assert_eq!((cells, tiles), (1_000_000, 28));
    // One row a tile.
    whole_against_tiles(6.0, 0.1, 1);
}

/// The 10⁸-cell case (100 mm at 0.01), in tiles of a 40 MB budget. Minutes
/// in a debug build: run it with `cargo test --release -p kezuri-cam --test
/// sim_tiles -- --ignored`.
#[test]
#[ignore]
fn a_hundred_million_cells_in_tiles_are_the_whole_grid() {
    let grid = Grid { x0: 0.0, y0: 0.0, res: 0.01, nx: 10_000, ny: 10_000 };
    let rows = tile_rows(&grid, CELL_BYTES, 40_000_000).unwrap();
    assert_eq!(rows, 800);
    let (cells, tiles) = whole_against_tiles(100.0, 0.01, rows);
    assert_eq!((cells, tiles), (100_000_000, 13));
}

#[test]
fn a_tile_is_as_many_rows_as_the_memory_allows() {
    let grid = Grid { x0: 0.0, y0: 0.0, res: 0.005, nx: 44_000, ny: 44_000 };
    // 2 GiB at 5 bytes a cell: 9761 rows of 44,000 cells.
    assert_eq!(tile_rows(&grid, CELL_BYTES, 2 << 30).unwrap(), (2u64 << 30) as usize / 220_000);
    assert_eq!(tile_rows(&grid, CELL_BYTES, 1 << 40).unwrap(), 44_000, "the whole grid when it fits");
    let e = tile_rows(&grid, CELL_BYTES, 100_000).unwrap_err();
    assert_eq!(e.kind, ErrorKind::TooManyCells);
    assert!(e.to_string().contains("one row of the grid (44000 cells, 0.2 MB)"), "{e}");
}

#[test]
fn a_cylinder_in_tiles_is_the_cylinder_whole() {
    let c = Cylinder { x: 5.0, y: 5.0, diameter: 9.0, height: 3.0, top: 0.2 };
    let options = SimOptions::new(0.1);
    let whole = ZMap::cylinder(&c, &options).unwrap();
    let start = Start::Cylinder(c);
    let grid = start.grid(&options).unwrap();
    let mut nm = Vec::new();
    for rows in kezuri_cam::sim::tiles::tiles(&grid, 13) {
        let tile = start.rows(&options, rows).unwrap();
        nm.extend_from_slice(&tile.nm);
    }
    assert_eq!(nm, whole.nm);
}

#[test]
fn heights_a_cell_cannot_keep_are_clear_errors() {
    // A cell keeps whole nanometres in 32 bits: −2147.483648 … 2147.483647 mm.
    assert_eq!(LOWEST, -2147.483648);
    let options = SimOptions::new(0.5);
    let high = Stock { x0: 0.0, y0: 0.0, x1: 10.0, y1: 10.0, top: 2500.0 };
    let e = ZMap::new(&high, &options).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Stock);
    assert!(e.to_string().contains("a height of 2500 mm is beyond what the grid holds"), "{e}");
    let stock = Stock { top: 0.0, ..high };
    let mut zmap = ZMap::new(&stock, &options).unwrap();
    let mut deep = mv(MoveKind::Feed, [1.0, 1.0, -3000.0], [9.0, 9.0, -3000.0], 1);
    deep.line = 7;
    let path = Toolpath::from(vec![deep]);
    let tool = Tool::Cutter("ball:2".parse().unwrap());
    let e = simulate_tools(&path, Tooling::One(&tool), &mut zmap, &options, &|_, _| {}).unwrap_err();
    assert_eq!(e.kind, ErrorKind::HeightRange);
    assert!(e.to_string().starts_with("move 0 (line 7) goes down to Z -3000 mm, below the lowest height"), "{e}");
    assert!(zmap.nm.iter().all(|&n| n == 0), "nothing cut, nothing wrapped");
    // The deepest a cell keeps is cut exactly.
    let floor = mv(MoveKind::Feed, [1.0, 5.0, -2147.0], [9.0, 5.0, -2147.0], 1);
    let flat = Tool::Cutter("flat:2".parse().unwrap());
    simulate_tools(&Toolpath::from(vec![floor]), Tooling::One(&flat), &mut zmap, &options, &|_, _| {}).unwrap();
    assert_eq!(zmap.range().0, -2147.0);
}

#[test]
fn heights_round_to_the_nearest_nanometre() {
    use kezuri_cam::sim::{from_nm, to_nm};
    assert_eq!(to_nm(-1.0), Some(-1_000_000));
    assert_eq!(to_nm(0.0012344), Some(1234));
    assert_eq!(to_nm(-0.0012346), Some(-1235));
    assert_eq!(to_nm(2147.483647), Some(i32::MAX));
    assert_eq!(to_nm(-2147.483648), Some(i32::MIN));
    for z in [2147.4836475, -2147.4836486, 1e300, f64::NAN, f64::INFINITY] {
        assert_eq!(to_nm(z), None, "{z}");
    }
    for n in [0, 1, -1, 7_286_539, -2_999_982, i32::MAX, i32::MIN] {
        assert_eq!(to_nm(from_nm(n)), Some(n), "{n}");
    }
}
