//! Detection on the reference prior's building points (~0.7 M) and target
//! generation from it.

#[path = "../tests/planning_scene/mod.rs"]
mod planning_scene;

use criterion::{Criterion, criterion_group, criterion_main};
use skyground_core::io::load_scene;
use skyground_core::missing::{DetectParams, detect_all_on};
use skyground_core::targets::{Site, TargetParams, generate};

fn bench(c: &mut Criterion) {
    let scene = load_scene("reference").expect("reference scene");
    let p = planning_scene::prior(&scene);
    eprintln!("{} building points", p.buildings.len());
    let terrain = p.terrain();
    let params = DetectParams::default();
    let mut g = c.benchmark_group("detect");
    g.sample_size(10);
    g.bench_function("detect_all reference prior", |b| {
        b.iter(|| {
            detect_all_on(&p.buildings, &p.ids, None, Some(&terrain), &params).expect("detect")
        })
    });
    let det = detect_all_on(&p.buildings, &p.ids, None, Some(&terrain), &params).expect("detect");
    let tp = TargetParams::default();
    g.bench_function("site + generate", |b| {
        b.iter(|| {
            let site = Site::from_cloud(&p.xyz, &p.labels, tp.cell, tp.clearance).expect("site");
            generate(&det, &site, &tp).expect("targets")
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
