//! A lathe's stock removal cycle: one `G71` of 10,000 cuts (depth of cut
//! 0.01 mm over 100.001 mm of radius), parsed and run whole. The goal is
//! under 50 ms.
//!
//! `cargo bench -p kezuri-nc --bench lathe_contour`. Figures are recorded
//! in BENCHMARKS.md at the repository root. With `KEZURI_BENCH_ONCE=1` the
//! binary parses and runs the program once, prints the time and exits.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, Criterion, Throughput};
use kezuri_geom::MoveKind;
use kezuri_nc::interp::{Outcome, Settings};
use kezuri_nc::Dialect;

mod common;

/// The allocator the `kezuri` binary uses: huge pages for large blocks.
#[global_allocator]
static ALLOC: kezuri_geom::LargePages = kezuri_geom::LargePages;

/// Cuts by depth the cycle makes.
const CUTS: usize = 10_000;

/// From Ø210 (radius 105) down to Ø9.998 (radius 4.999) over 52 mm of Z,
/// 0.01 mm a cut: depths 0.01 … 100.00, 10,000 cuts, then the cut along
/// the shape.
const PROGRAM: &str = "%
O0071 (G71 10000 CUTS)
G18 G21 G99 G97 S1000 M03
T0101
G00 X210. Z2.
G71 U0.01 R0.005
G71 P10 Q20 U0 W0 F0.2
N10 G00 X9.998
G01 Z-50.
N20 X212.
G00 X250. Z50.
M30
%
";

fn settings() -> Settings {
    Settings { dialect: Dialect::FanucLathe, ..Settings::default() }
}

/// Checks the run makes every cut: one feed along Z a cut, two along the
/// shape.
fn check(text: &str, settings: &Settings) -> Outcome {
    let outcome = common::parse_and_run("g71.nc", text, settings);
    assert!(outcome.completed, "{:?}", outcome.diagnostics.first());
    let feeds = outcome.toolpath.moves.iter().filter(|m| m.kind == MoveKind::Feed).count();
    assert_eq!(feeds, CUTS + 2, "feeds");
    outcome
}

fn bench(c: &mut Criterion) {
    let settings = settings();
    check(PROGRAM, &settings);
    let mut group = c.benchmark_group("lathe_contour");
    group.sample_size(50).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(5));
    group.throughput(Throughput::Elements(CUTS as u64));
    group.bench_function("g71_10000_cuts", |b| {
        b.iter(|| common::parse_and_run("g71.nc", black_box(PROGRAM), &settings))
    });
    group.finish();
}

/// Parses and runs the program once (see the module docs).
fn once() {
    let settings = settings();
    let t0 = std::time::Instant::now();
    let outcome = check(PROGRAM, &settings);
    let t = t0.elapsed();
    println!("g71_10000_cuts: {} moves; parse and run {t:?}", outcome.toolpath.moves.len());
}

criterion_group!(benches, bench);

fn main() {
    common::main(once, benches);
}
