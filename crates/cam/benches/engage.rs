//! Sections of one tooth's chip (issue 17): one α and one combination at
//! 360 angles (the paper's oval:16,24 at α = 45°, step-up, down-cut, also
//! the slowest case, α = 15° step-down, where the tip's sliver is cut at
//! every angle), and the paper's whole grid: α = 0…75° by 15° × step
//! up/down × down/up-cut, 360 angles each, chips prepared included.
//!
//! `cargo bench -p kezuri-cam --bench engage`

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, Criterion};
use kezuri_cam::engage::{sweep, Chip, Cut, Engagement, Step};

fn paper(angle: f64, step: Step, cut: Cut) -> Engagement {
    Engagement {
        cutter: "oval:16,24".parse().unwrap(),
        flutes: 2,
        helix: 30f64.to_radians(),
        angle: angle.to_radians(),
        depth: 0.8,
        pick_feed: 0.8,
        feed_per_tooth: 0.16,
        step,
        cut,
    }
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("engage");
    group.sample_size(20).measurement_time(Duration::from_secs(4));
    for (name, angle, step) in [("45deg_up_down_360", 45.0, Step::Up), ("15deg_down_down_360", 15.0, Step::Down)] {
        let chip = Chip::new(&paper(angle, step, Cut::Down)).unwrap();
        group.bench_function(name, |b| b.iter(|| black_box(sweep(&chip, 360)).area_max));
    }
    group.bench_function("paper_grid_4x6_360", |b| {
        b.iter(|| {
            let mut total = 0.0;
            for a in [0.0, 15.0, 30.0, 45.0, 60.0, 75.0] {
                for (step, cut) in
                    [(Step::Up, Cut::Down), (Step::Down, Cut::Down), (Step::Up, Cut::Up), (Step::Down, Cut::Up)]
                {
                    let chip = Chip::new(&paper(a, step, cut)).unwrap();
                    total += sweep(&chip, 360).ed_max;
                }
            }
            black_box(total)
        })
    });
    group.finish();
}

criterion_group!(benches, bench);

fn main() {
    benches();
    Criterion::default().configure_from_args().final_summary();
}
