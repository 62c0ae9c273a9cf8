//! Parse and interpret throughput on a generated 1,000,000-block raster
//! finishing program, the kind of file a CAM system writes.
//!
//! `cargo bench -p kezuri-nc --bench raster`. Figures are recorded in
//! BENCHMARKS.md at the repository root.
//!
//! With `KEZURI_BENCH_ONCE=<blocks>` set, the binary instead parses and runs a
//! program of that many blocks once and exits: a fixed amount of work for
//! `valgrind --tool=callgrind`, whose instruction counts repeat exactly.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, BatchSize, Criterion, Throughput};
use kezuri_nc::{interp, parse, Program, SourceFile, Sources};

/// The allocator the `kezuri` binary uses: huge pages for large blocks.
#[global_allocator]
static ALLOC: kezuri_geom::LargePages = kezuri_geom::LargePages;

/// Cutting blocks in the generated program.
const BLOCKS: usize = 1_000_000;

/// A raster (zig-zag) finishing program: `blocks` motion blocks in rows along
/// X stepping over in Y with a wavy 3-decimal Z, a rapid lift, step-over and
/// plunge between rows (a row's end may add up to two more), inside
/// CAM-style framing.
fn raster_program(blocks: usize) -> String {
    use std::fmt::Write;
    const PER_ROW: usize = 500;
    let mut s = String::with_capacity(blocks * 30);
    s.push_str("%\nO0001 (RASTER FINISH)\n(T1 D6. BALL)\nG90 G21 G17 G40 G49 G80 G94\nG54\nT1 M06\n");
    s.push_str("S12000 M03\nG00 X0. Y0.\nG43 Z25. H1\nM08\nG01 Z-1. F1200.\n");
    // Deterministic xorshift for a realistic spread of digits.
    let mut rng = 0x2545_F491_4F6C_DD1Du64;
    let mut next = || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        rng
    };
    let mut written = 0;
    'rows: for row in 0.. {
        let y = row as f64 * 0.25 + 67.89;
        for k in 0..PER_ROW {
            if written >= blocks {
                break 'rows;
            }
            let i = if row % 2 == 0 { k } else { PER_ROW - 1 - k };
            let x = 12.345 + i as f64 * 0.2;
            let z = -1.234 - (next() % 2000) as f64 / 1000.0;
            writeln!(s, "G01 X{x:.3} Y{y:.3} Z{z:.3}").unwrap();
            written += 1;
        }
        // Lift, step over, plunge: the rapids between rows.
        writeln!(s, "G00 Z5.\nG00 Y{:.3}\nG01 Z-1.", y + 0.25).unwrap();
        written += 3;
    }
    s.push_str("G00 Z25.\nM09\nM05\nM30\n%\n");
    s
}

fn parse_fresh(text: &str) -> Program {
    let mut program = Program::default();
    let diagnostics = parse(&mut program, 0, text);
    assert!(diagnostics.is_empty(), "{:?}", diagnostics.first());
    program
}

fn bench(c: &mut Criterion) {
    let text = raster_program(BLOCKS);
    let mut sources = Sources::default();
    sources.add(SourceFile::new("raster.nc", text.clone()));

    let mut group = c.benchmark_group("raster");
    group.sample_size(10).warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(8));

    group.throughput(Throughput::BytesDecimal(text.len() as u64));
    // The parsed program is dropped outside the timed region: freeing it is
    // not parsing.
    group.bench_function("parse", |b| {
        b.iter_batched(|| (), |()| parse_fresh(black_box(&text)), BatchSize::PerIteration)
    });

    let program = parse_fresh(&text);
    let settings = interp::Settings::default();
    let check = interp::run(&mut program.clone(), &mut sources, 0, &mut interp::NoLibrary, &settings);
    assert!(check.completed, "{:?}", check.diagnostics);
    group.throughput(Throughput::Elements(check.blocks));
    group.bench_function("interpret", |b| {
        b.iter_batched_ref(
            || program.clone(),
            |p| interp::run(p, &mut sources, 0, &mut interp::NoLibrary, &settings),
            BatchSize::LargeInput,
        )
    });
    group.finish();
}

/// Parses and runs a program of `blocks` blocks once (see the module docs).
fn once(blocks: usize) {
    let text = raster_program(blocks);
    let mut sources = Sources::default();
    sources.add(SourceFile::new("raster.nc", text.clone()));
    let t0 = std::time::Instant::now();
    let mut program = parse_fresh(&text);
    let t1 = std::time::Instant::now();
    let outcome = interp::run(&mut program, &mut sources, 0, &mut interp::NoLibrary, &interp::Settings::default());
    let t2 = std::time::Instant::now();
    assert!(outcome.completed, "{:?}", outcome.diagnostics);
    println!(
        "{} bytes, {} blocks, {} moves; parse {:?}, interpret {:?}",
        text.len(),
        outcome.blocks,
        outcome.toolpath.moves.len(),
        t1 - t0,
        t2 - t1
    );
}

criterion_group!(benches, bench);

fn main() {
    if let Some(blocks) = std::env::var("KEZURI_BENCH_ONCE").ok().and_then(|v| v.parse().ok()) {
        once(blocks);
        return;
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
