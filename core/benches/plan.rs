//! Planning benchmarks on the reference scene (aerial prior, ground-truth labels):
//! `cargo bench -p skyground-core --bench plan`.
//!
//! - `plan/graph_matrix_tour`: ground graph build + distance matrix + both tours (target ≤ 1 s);
//! - `plan/explore_cycle`: one explorer update with a VLP-16 scan + viewpoint reselection (target ≤ 100 ms);
//! - `plan/voxel_merge_40_scans`: 40 VLP-16 scans, 0.2 m apart (2 s of driving at 10 Hz), into the
//!   explorer's 5 cm de-duplication, as /resampled_cloud is kept;
//! - `plan/voxel_merge_40_scans_into_15M`: the same scans again into a merge holding 15 M voxels.

#[path = "../tests/planning_scene/mod.rs"]
mod planning_scene;

use std::hint::black_box;
use std::sync::Arc;

use criterion::{BatchSize, Criterion};
use planning_scene::{corner_region, graph, start, target_set, world};
use skyground_core::explore::{ExploreParams, Explorer, VoxelMerge};
use skyground_core::graph::{GraphParams, GroundGraph, polygon_contains};
use skyground_core::lidar::{LidarConfig, Pose, scan};
use skyground_core::metrics::SurfaceKind;
use skyground_core::route::{RouteParams, plan};

fn benches(c: &mut Criterion) {
    let w = world();
    let s = start(w);
    let targets = target_set(w);
    let mut group = c.benchmark_group("plan");
    group.sample_size(10);
    group.bench_function("graph_matrix_tour", |b| {
        b.iter(|| {
            let g = GroundGraph::build(black_box(&w.xyz), &w.labels, s, &GraphParams::default())
                .unwrap();
            plan(&g, &targets, s, &RouteParams::default())
                .unwrap()
                .length_m
        })
    });
    let g = Arc::new(graph());
    let region = corner_region(w, 2, 6.0, 12.0);
    // All wall samples of the corner (not only the missing ones): the heavier case.
    let surface: Vec<[f32; 3]> = (0..w.gt.len())
        .filter(|&i| {
            let p = w.gt.xyz[i];
            w.gt.building[i] == 2
                && w.gt.kind[i] == SurfaceKind::Wall
                && polygon_contains(&region.polygon, [f64::from(p[0]), f64::from(p[1])])
        })
        .map(|i| w.gt.xyz[i])
        .collect();
    let params = ExploreParams::default();
    let mut ex = Explorer::new(&region, surface.clone(), &w.xyz, g.clone(), &params).unwrap();
    let vp = ex.next_waypoints(s)[0];
    let pose = Pose::new([vp[0], vp[1], vp[2] + params.sensor_height_m], 0.0);
    let points = scan(&w.caster, &LidarConfig::default(), &pose, 0)
        .unwrap()
        .xyz;
    println!(
        "explore_cycle: {} surface samples, {} candidates, {} scan points",
        surface.len(),
        ex.candidates(),
        points.len()
    );
    group.bench_function("explore_cycle", |b| {
        b.iter_batched(
            || ex.clone(),
            |mut e| {
                e.update(vp, black_box(&points));
                e.done()
            },
            BatchSize::LargeInput,
        )
    });
    let scans: Vec<Vec<[f32; 3]>> = (0..40)
        .map(|k| {
            let at = [
                vp[0] + 0.2 * k as f32,
                vp[1],
                vp[2] + params.sensor_height_m,
            ];
            scan(&w.caster, &LidarConfig::default(), &Pose::new(at, 0.0), k)
                .unwrap()
                .xyz
        })
        .collect();
    println!(
        "voxel_merge: {} points in 40 scans",
        scans.iter().map(Vec::len).sum::<usize>()
    );
    group.bench_function("voxel_merge_40_scans", |b| {
        b.iter(|| {
            let mut m = VoxelMerge::new(0.05).unwrap();
            for s in &scans {
                for p in s {
                    m.add(black_box(*p));
                }
            }
            m.len()
        })
    });
    // The same scans once more into a merge that already holds them and a
    // whole mission's other voxels (15 M, as after the reference demo): what
    // every scan costs the explorer late in a mission.
    let mut full = VoxelMerge::new(0.05).unwrap();
    for i in 0..3873 {
        for j in 0..3873 {
            full.add([
                (i as f32 + 0.5) * 0.05 - 500.0,
                (j as f32 + 0.5) * 0.05 - 500.0,
                -50.0,
            ]);
        }
    }
    for s in &scans {
        for p in s {
            full.add(*p);
        }
    }
    println!("voxel_merge: {} voxels held", full.len());
    group.bench_function("voxel_merge_40_scans_into_15M", |b| {
        b.iter(|| {
            let mut new = 0;
            for s in &scans {
                for p in s {
                    new += usize::from(full.add(black_box(*p)));
                }
            }
            new
        })
    });
    group.finish();
}

criterion::criterion_group!(plan_benches, benches);
criterion::criterion_main!(plan_benches);
