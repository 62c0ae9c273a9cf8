//! Drop-cutter time per point against the number of triangles at constant
//! triangle size (issue 3): a wavy surface of 0.5 mm squares (two triangles
//! each) over 25 × 25 mm (5,000 triangles) and 100 × 100 mm (80,000), a
//! `ball:6` dropped at 51 × 51 points kept a cutter radius inside the
//! border, so every point sees a full disk of triangles. One thread.
//!
//! `cargo bench -p kezuri-cam --bench dropcut`

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, BenchmarkId, Criterion, Throughput};
use kezuri_cam::dropcut::{drop_cutter, MeshSurface};
use kezuri_cam::Cutter;
use kezuri_geom::{Mesh, Triangle, Vec3};

/// The surface of `bench/ocl_dropcut.py`.
fn z(x: f64, y: f64) -> f64 {
    use std::f64::consts::TAU;
    4.0 * (TAU * x / 23.0).sin() * (TAU * y / 17.0).cos() + 1.5 * (TAU * (x + y) / 9.0).sin()
}

fn wavy(size: f64) -> Mesh {
    let n = (size / 0.5) as usize;
    let p = |i: usize, j: usize| {
        let (x, y) = (i as f64 * 0.5, j as f64 * 0.5);
        Vec3::new(x, y, z(x, y))
    };
    Mesh::from_triangles((0..n).flat_map(|j| {
        (0..n).flat_map(move |i| {
            [Triangle::new(p(i, j), p(i + 1, j), p(i + 1, j + 1)), Triangle::new(p(i, j), p(i + 1, j + 1), p(i, j + 1))]
        })
    }))
}

fn bench(c: &mut Criterion) {
    let ball: Cutter = "ball:6".parse().unwrap();
    let mut group = c.benchmark_group("dropcut");
    group.sample_size(20).measurement_time(Duration::from_secs(4));
    // The third case drops the same 51 × 51 points as the first (spread
    // over 25 mm) on the large surface: the same work per point, so any
    // difference from the first case is the triangle count itself; the
    // second spreads them over the whole 100 mm (less cache reuse).
    for (size, spread) in [(25.0, 25.0), (100.0, 100.0), (100.0, 25.0)] {
        let surface = MeshSurface::new(wavy(size));
        let r = ball.radius();
        let points: Vec<(f64, f64)> = (0..51)
            .flat_map(|j| (0..51).map(move |i| (i, j)))
            .map(|(i, j)| (r + (spread - 2.0 * r) * i as f64 / 50.0, r + (spread - 2.0 * r) * j as f64 / 50.0))
            .collect();
        group.throughput(Throughput::Elements(points.len() as u64));
        let id = BenchmarkId::new("ball6", format!("{} triangles, points over {spread} mm", surface.mesh().len()));
        group.bench_with_input(id, &points, |b, points| {
            b.iter(|| {
                for &(x, y) in points {
                    black_box(drop_cutter(&ball, &surface, x, y));
                }
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);

fn main() {
    benches();
    Criterion::default().configure_from_args().final_summary();
}
