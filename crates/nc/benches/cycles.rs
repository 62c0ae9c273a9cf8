//! Canned cycles: a 1,000-hole G83 peck drilling program (10 pecks a hole)
//! and a 1,000-hole G81 program with G99, each parsed and run whole.
//! The goal for the G83 program is under 50 ms.
//!
//! `cargo bench -p kezuri-nc --bench cycles`. Figures are recorded in
//! BENCHMARKS.md at the repository root. With `KEZURI_BENCH_ONCE=1` the
//! binary parses and runs each program once, prints the times and exits.

use std::collections::BTreeMap;
use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, Criterion, Throughput};
use kezuri_nc::interp::{Outcome, Settings};

mod common;

/// The allocator the `kezuri` binary uses: huge pages for large blocks.
#[global_allocator]
static ALLOC: kezuri_geom::LargePages = kezuri_geom::LargePages;

/// Holes in each program.
const HOLES: usize = 1_000;

/// A drilling program: a 40 × 25 grid of holes at 5 mm pitch, in zig-zag
/// rows, the cycle block `cycle` on the first hole and the others one
/// `X.. Y..` block each, then `G80`.
fn drilling_program(cycle: &str) -> String {
    use std::fmt::Write;
    let mut s = String::with_capacity(HOLES * 20 + 400);
    s.push_str("%\nO0002 (DRILL 1000 HOLES)\nG90 G21 G17 G40 G49 G80 G94\nG54\nT1 M06\nS3000 M03\n");
    s.push_str("G00 X0. Y0.\nG43 Z50. H1\nM08\n");
    for k in 0..HOLES {
        let (row, col) = (k / 40, k % 40);
        let col = if row % 2 == 0 { col } else { 39 - col };
        let (x, y) = (col as f64 * 5.0, row as f64 * 5.0);
        if k == 0 {
            writeln!(s, "{cycle} X{x:.3} Y{y:.3}").unwrap();
        } else {
            writeln!(s, "X{x:.3} Y{y:.3}").unwrap();
        }
    }
    s.push_str("G80\nG00 Z50.\nM09\nM05\nG91 G28 Z0.\nM30\n%\n");
    s
}

/// G83 with G98: pecks of 1 mm from R 2 to 8 mm deep (10 pecks a hole).
fn g83_program() -> String {
    drilling_program("G98 G83 Z-8. R2. Q1. F200.")
}

/// G81 with G99: drill to 5 mm deep, back to R 2 between holes.
fn g81_program() -> String {
    drilling_program("G99 G81 Z-5. R2. F300.")
}

fn settings() -> Settings {
    Settings { tool_lengths: BTreeMap::from([(1, 100.0)]), ..Settings::default() }
}

/// Checks the program drills every hole and, for G83, pecks 10 times a
/// hole (one feed a peck; G81 one feed a hole).
fn check(name: &str, text: &str, settings: &Settings) -> Outcome {
    let outcome = common::parse_and_run("drill.nc", text, settings);
    assert!(outcome.completed, "{name}: {:?}", outcome.diagnostics.first());
    assert_eq!(outcome.holes, HOLES as u64, "{name}");
    let feeds = outcome.toolpath.moves.iter().filter(|m| matches!(m.kind, kezuri_geom::MoveKind::Feed)).count();
    let per_hole = if name.starts_with("g83") { 10 } else { 1 };
    assert_eq!(feeds, per_hole * HOLES, "{name}: feeds");
    outcome
}

fn bench(c: &mut Criterion) {
    let settings = settings();
    let mut group = c.benchmark_group("cycles");
    group.sample_size(50).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(5));
    for (name, text) in [("g83_1000_holes", g83_program()), ("g81_g99_1000_holes", g81_program())] {
        check(name, &text, &settings);
        group.throughput(Throughput::Elements(HOLES as u64));
        group.bench_function(name, |b| b.iter(|| common::parse_and_run("drill.nc", black_box(&text), &settings)));
    }
    group.finish();
}

/// Parses and runs each program once (see the module docs).
fn once() {
    let settings = settings();
    for (name, text) in [("g83_1000_holes", g83_program()), ("g81_g99_1000_holes", g81_program())] {
        let t0 = std::time::Instant::now();
        let outcome = check(name, &text, &settings);
        let t = t0.elapsed();
        let feeds = outcome.toolpath.moves.iter().filter(|m| matches!(m.kind, kezuri_geom::MoveKind::Feed)).count();
        println!(
            "{name}: {} bytes, {} blocks, {} holes, {} moves ({feeds} feeds); parse and run {t:?}",
            text.len(),
            outcome.blocks,
            outcome.holes,
            outcome.toolpath.moves.len()
        );
    }
}

criterion_group!(benches, bench);

fn main() {
    common::main(once, benches);
}
