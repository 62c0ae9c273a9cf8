//! Issue 8's benchmark: the wear correction of 30,000 CL points of a ball
//! end mill finishing a dome (a mesh of 180,000 triangles), with a
//! measured profile of 1,127 samples (0.8 mm at 0.71 µm); the paper took
//! 45 ms per point, the goal is under 50 µs. One thread.
//!
//! `cargo bench -p kezuri-correct --bench wear`

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, Criterion, Throughput};
use kezuri_correct::wear::{correct, Nominal, Options, Surface};
use kezuri_geom::{Mesh, ToolProfile, Triangle, Vec3};

/// The dome: a sphere of radius 40 mm, 30 × 30 mm of it on a 0.1 mm grid.
const RS: f64 = 40.0;

fn height(x: f64, y: f64) -> f64 {
    (RS * RS - x * x - y * y).sqrt() - RS
}

fn dome() -> Mesh {
    let n = 300;
    let p = |i: usize, j: usize| {
        let (x, y) = (-15.0 + 0.1 * i as f64, -15.0 + 0.1 * j as f64);
        Vec3::new(x, y, height(x, y))
    };
    Mesh::from_triangles((0..n).flat_map(|i| {
        (0..n).flat_map(move |j| {
            [Triangle::new(p(i, j), p(i + 1, j), p(i + 1, j + 1)), Triangle::new(p(i, j), p(i + 1, j + 1), p(i, j + 1))]
        })
    }))
}

fn bench(c: &mut Criterion) {
    let mesh = dome();
    let surface = Surface::new(&mesh);
    let r = 0.5;
    let z: Vec<f64> = (0..1127).map(|k| 0.002 + 0.00071 * k as f64).collect();
    let radius = z.iter().map(|&z| if z < r { (z * (2.0 * r - z)).sqrt() } else { r } + 0.01).collect();
    let worn = ToolProfile::new(z, radius).unwrap();
    let nominal = Nominal { radius: r, corner: r };
    let axis = Vec3::new(0.0, 0.0, 1.0);
    let feed = Some(Vec3::new(1.0, 0.0, 0.0));
    // Raster rows along X over the dome: 150 rows of 200 points; the ball
    // touches the sphere along its normal.
    let points: Vec<Vec3> = (0..30_000)
        .map(|k| {
            let (x, y) = (-12.0 + 24.0 * (k % 200) as f64 / 200.0, -12.0 + 24.0 * (k / 200) as f64 / 150.0);
            let p = Vec3::new(x, y, height(x, y));
            let n = Vec3::new(x, y, p.z + RS) * (1.0 / RS);
            p + n * r - axis * r
        })
        .collect();
    let options = Options { reach: 0.05 };
    let mut group = c.benchmark_group("wear");
    group.sample_size(10).measurement_time(Duration::from_secs(10));
    group.throughput(Throughput::Elements(points.len() as u64));
    group.bench_function("ball_30000_points_dome_180k_triangles", |bench| {
        bench.iter(|| {
            let mut worst: f64 = 0.0;
            for &tip in &points {
                let fix = correct(&surface, nominal, &worn, tip, axis, feed, &options).unwrap().unwrap();
                worst = worst.max(fix.residual.abs());
            }
            black_box(worst)
        })
    });
    group.finish();
}

criterion_group!(benches, bench);

fn main() {
    benches();
    Criterion::default().configure_from_args().final_summary();
}
