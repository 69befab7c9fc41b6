//! Footprint benchmarks on the reference scene's aerial prior:
//! `cargo bench -p skyground-core --bench footprint`.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use skyground_core::cloud::class::BUILDING;
use skyground_core::footprint::{
    DeriveParams, SplitParams, derive, footprints_of_scene, match_footprints, split,
};
use skyground_core::lidar::{AirborneConfig, Caster, airborne_scan};
use skyground_core::scene::{REFERENCE_SEED, reference_scene};

fn benches(c: &mut Criterion) {
    let scene = reference_scene(REFERENCE_SEED);
    let Ok(caster) = Caster::new(&scene) else {
        return;
    };
    let Ok(cloud) = airborne_scan(&caster, &AirborneConfig::default()) else {
        return;
    };
    let truth = footprints_of_scene(&scene);
    let building: Vec<[f32; 3]> = match &cloud.label {
        Some(l) => cloud
            .xyz
            .iter()
            .zip(l)
            .filter(|(_, l)| **l == BUILDING)
            .map(|(p, _)| *p)
            .collect(),
        None => Vec::new(),
    };
    let mut g = c.benchmark_group("footprint");
    g.sample_size(10);
    g.bench_function("footprints_of_scene", |b| {
        b.iter(|| footprints_of_scene(black_box(&scene)).len())
    });
    g.throughput(Throughput::Elements(cloud.xyz.len() as u64));
    g.bench_function("split_prior", |b| {
        b.iter(|| split(black_box(&cloud.xyz), &truth, &SplitParams::default()).map(|v| v.len()))
    });
    g.throughput(Throughput::Elements(building.len() as u64));
    g.bench_function("derive_building_points", |b| {
        b.iter(|| derive(black_box(&building), &DeriveParams::default()).map(|v| v.len()))
    });
    let derived = derive(&building, &DeriveParams::default()).unwrap_or_default();
    g.throughput(Throughput::Elements(truth.len() as u64));
    g.bench_function("match_footprints", |b| {
        b.iter(|| match_footprints(black_box(&derived), &truth).len())
    });
    g.finish();
}

criterion_group!(footprint, benches);
criterion_main!(footprint);
