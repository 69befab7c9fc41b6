//! Cloth Simulation Filter benchmark: `cargo bench -p skyground-core --bench ground`.
//!
//! Runs CSF with the default parameters on the reference city's aerial
//! prior, subsampled to 1 M points and whole (~1.95 M).

use std::hint::black_box;

use criterion::{Criterion, Throughput};
use skyground_core::ground::{CsfParams, csf};
use skyground_core::lidar::{AirborneConfig, Caster, airborne_scan};
use skyground_core::scene::{REFERENCE_SEED, reference_scene};

fn benches(c: &mut Criterion) {
    let scene = reference_scene(REFERENCE_SEED);
    let Ok(cloud) = Caster::new(&scene)
        .map_err(|e| e.to_string())
        .and_then(|caster| {
            airborne_scan(&caster, &AirborneConfig::default()).map_err(|e| e.to_string())
        })
    else {
        eprintln!("reference scene did not scan");
        return;
    };
    let every = cloud.len().div_ceil(1_000_000).max(1);
    let million: Vec<[f32; 3]> = cloud
        .xyz
        .iter()
        .step_by(every)
        .copied()
        .take(1_000_000)
        .collect();
    let params = CsfParams::default();
    let mut g = c.benchmark_group("csf");
    g.sample_size(10);
    for (name, pts) in [("reference_1M", &million), ("reference_all", &cloud.xyz)] {
        g.throughput(Throughput::Elements(pts.len() as u64));
        g.bench_function(name, |b| {
            b.iter(|| csf(black_box(pts), &params).map(|s| s.iterations_run))
        });
    }
    g.finish();
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    benches(&mut c);
    c.final_summary();
}
