//! Material-removal simulation of a raster finishing program (issue 3's
//! goal): `ball:6` over a 100 × 100 mm stock at 0.05 mm (4,000,000 cells),
//! 200 zig-zag rows at 0.5 mm stepover of 1,000 feed moves each (0.1 mm
//! long, Z following a wavy surface): 200,000 cutting moves plus the 199
//! stepovers, built as a `Toolpath` in memory.
//!
//! `cargo bench -p kezuri-cam --bench sim`; with `KEZURI_BENCH_ONCE=1` the
//! binary simulates once, prints the time and exits.

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{criterion_group, Criterion, Throughput};
use kezuri_cam::sim::{simulate, SimOptions, Stock, ZMap};
use kezuri_cam::Cutter;
use kezuri_geom::{Axes, Move, MoveKind, Toolpath};

#[global_allocator]
static ALLOC: kezuri_geom::LargePages = kezuri_geom::LargePages;

const ROWS: usize = 200;
const PER_ROW: usize = 1000;

fn surface(x: f64, y: f64) -> f64 {
    -2.0 + (x / 7.0).sin() * (y / 11.0).cos() + 0.3 * (x / 3.0 + y / 5.0).sin()
}

/// The raster finishing program as a toolpath.
pub fn raster() -> Toolpath {
    let at = |x: f64, y: f64| Axes { x, y, z: surface(x, y), ..Axes::ZERO };
    let mut path = Toolpath::default();
    let mut last: Option<Axes> = None;
    for row in 0..ROWS {
        let y = 0.25 + 0.5 * row as f64;
        let step = 100.0 / PER_ROW as f64;
        let xs: Vec<f64> = (0..=PER_ROW).map(|k| k as f64 * step).collect();
        let ordered: Vec<f64> = if row % 2 == 0 { xs } else { xs.into_iter().rev().collect() };
        let mut prev = at(ordered[0], y);
        if let Some(l) = last {
            path.push(Move { kind: MoveKind::Feed, start: l, end: prev, feed: 2000.0, line: 0, ..Move::default() });
        }
        for &x in &ordered[1..] {
            let p = at(x, y);
            path.push(Move { kind: MoveKind::Feed, start: prev, end: p, feed: 2000.0, ..Move::default() });
            prev = p;
        }
        last = Some(prev);
    }
    path
}

fn run(path: &Toolpath, ball: &Cutter) -> ZMap {
    let stock = Stock { x0: 0.0, y0: 0.0, x1: 100.0, y1: 100.0, top: 0.0 };
    let options = SimOptions::new(0.05);
    let mut zmap = ZMap::new(&stock, &options).unwrap();
    simulate(path, ball, &mut zmap, &options).unwrap();
    zmap
}

fn bench(c: &mut Criterion) {
    let path = raster();
    let ball: Cutter = "ball:6".parse().unwrap();
    let mut group = c.benchmark_group("sim");
    group.sample_size(10).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(30));
    group.throughput(Throughput::Elements(path.moves.len() as u64));
    group.bench_function("raster_ball6_4M_cells", |b| b.iter(|| run(black_box(&path), &ball)));
    group.finish();
}

fn once() {
    let path = raster();
    let ball: Cutter = "ball:6".parse().unwrap();
    let t0 = Instant::now();
    let zmap = run(&path, &ball);
    let dt = t0.elapsed();
    let (lo, hi) = zmap.range();
    println!(
        "{} moves, {} cells, {} threads: {:?} (z {lo:.4} … {hi:.4})",
        path.moves.len(),
        zmap.cells(),
        rayon::current_num_threads(),
        dt
    );
}

criterion_group!(benches, bench);

fn main() {
    if std::env::var_os("KEZURI_BENCH_ONCE").is_some() {
        once();
        return;
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
