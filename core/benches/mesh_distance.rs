//! Point-to-mesh distance on the reference scene, both indexes behind
//! `MeshDistance`: `cargo bench -p skyground-core --bench mesh_distance`.
//!
//! - `mesh_distance/grid`, `mesh_distance/parry`: the accuracy term
//!   (`cloud_to_mesh_distances`) of the simulated aerial prior's building
//!   points, index build included, as the evaluation runs it.

#[path = "../tests/planning_scene/mod.rs"]
mod planning_scene;

use std::hint::black_box;

use criterion::Criterion;
use planning_scene::world;
use skyground_core::cloud::class;
use skyground_core::metrics::{MeshBackend, cloud_to_mesh_distances_with};

fn benches(c: &mut Criterion) {
    let w = world();
    let building: Vec<[f32; 3]> = w
        .xyz
        .iter()
        .zip(&w.labels)
        .filter(|(_, l)| **l == class::BUILDING)
        .map(|(p, _)| *p)
        .collect();
    let mean = |b: MeshBackend| {
        let d = cloud_to_mesh_distances_with(&w.scene, &building, b);
        d.iter().map(|&v| f64::from(v)).sum::<f64>() / d.len() as f64
    };
    let (g, p) = (mean(MeshBackend::Grid), mean(MeshBackend::Parry));
    println!(
        "mesh_distance: {} building points; mean distance grid {g:.9} m, parry {p:.9} m, |Δ| {:.2e} m",
        building.len(),
        (g - p).abs()
    );
    let mut group = c.benchmark_group("mesh_distance");
    group.sample_size(10);
    for (name, backend) in [("grid", MeshBackend::Grid), ("parry", MeshBackend::Parry)] {
        group.bench_function(name, |b| {
            b.iter(|| cloud_to_mesh_distances_with(&w.scene, black_box(&building), backend))
        });
    }
    group.finish();
}

criterion::criterion_group!(group, benches);
criterion::criterion_main!(group);
