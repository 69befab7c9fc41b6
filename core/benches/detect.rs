//! Detection on the reference prior's building points (~0.7 M) and target
//! generation from it.

use criterion::{Criterion, criterion_group, criterion_main};
use skyground_core::cloud::class;
use skyground_core::lidar::{AirborneConfig, Caster, airborne_scan};
use skyground_core::missing::{DetectParams, GroundGrid, detect_all_on};
use skyground_core::scene::load_scene;
use skyground_core::targets::{Site, TargetParams, generate};

fn bench(c: &mut Criterion) {
    let scene = load_scene("reference").expect("reference scene");
    let caster = Caster::new(&scene).expect("caster");
    let cloud = airborne_scan(&caster, &AirborneConfig::default()).expect("scan");
    let labels = cloud.label.clone().unwrap_or_default();
    let ids = cloud.building.clone().unwrap_or_default();
    let (mut xyz, mut bid, mut ground) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..cloud.xyz.len() {
        if labels[k] == class::BUILDING && ids[k] > 0 {
            xyz.push(cloud.xyz[k]);
            bid.push(ids[k]);
        } else if labels[k] == class::GROUND {
            ground.push(cloud.xyz[k]);
        }
    }
    eprintln!("{} building points", xyz.len());
    let terrain = GroundGrid::from_points(&ground, 2.0, 40).expect("ground");
    let params = DetectParams::default();
    let mut g = c.benchmark_group("detect");
    g.sample_size(10);
    g.bench_function("detect_all reference prior", |b| {
        b.iter(|| detect_all_on(&xyz, &bid, None, Some(&terrain), &params).expect("detect"))
    });
    let det = detect_all_on(&xyz, &bid, None, Some(&terrain), &params).expect("detect");
    let tp = TargetParams::default();
    g.bench_function("site + generate", |b| {
        b.iter(|| {
            let site = Site::from_cloud(&cloud.xyz, &labels, tp.cell, tp.clearance).expect("site");
            generate(&det, &site, &tp).expect("targets")
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
