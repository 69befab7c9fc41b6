//! LoD2 reconstruction of every building of the reference scene from its
//! simulated aerial prior (derived footprints, ~0.7 M building points).

use criterion::{Criterion, criterion_group, criterion_main};
use skyground_core::io::load_scene;
use skyground_core::lidar::{AirborneConfig, Caster, airborne_scan};
use skyground_core::reconstruct::{ReconstructParams, reconstruct_cloud};

fn bench(c: &mut Criterion) {
    let scene = load_scene("reference").expect("reference scene");
    let caster = Caster::new(&scene).expect("caster");
    let cloud = airborne_scan(&caster, &AirborneConfig::default()).expect("scan");
    let params = ReconstructParams::default();
    let rec = reconstruct_cloud(&cloud, None, &params).expect("reconstruct");
    eprintln!("{} models from {} points", rec.models.len(), cloud.len());
    let mut g = c.benchmark_group("reconstruct");
    g.sample_size(10);
    g.bench_function("reference prior, all buildings", |b| {
        b.iter(|| reconstruct_cloud(&cloud, None, &params).expect("reconstruct"))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
