//! Local exploration on the reference scene: the missing wall samples of a
//! building corner (ground truth without an aerial point within τ), simulated
//! VLP-16 scans at the viewpoints the explorer picks; coverage must rise with
//! every scan and the explorer must say it is done.

mod planning_scene;

use std::sync::Arc;

use planning_scene::{corner_region, graph, start, world};
use skyground_core::explore::{ExploreError, ExploreParams, Explorer, SurfaceSamples, resample};
use skyground_core::graph::{GroundGraph, polygon_contains};
use skyground_core::lidar::{LidarConfig, Pose, scan};
use skyground_core::metrics::{SurfaceKind, nearest_distances};
use skyground_core::params::ParamError;
use skyground_core::targets::Region;

/// Missing wall samples of building `b` inside `region`, thinned to 0.5 m, with normals.
fn missing_walls(region: &Region) -> SurfaceSamples {
    let w = world();
    let idx: Vec<usize> = (0..w.gt.len())
        .filter(|&i| {
            let p = w.gt.xyz[i];
            w.gt.building[i] == region.building
                && w.gt.kind[i] == SurfaceKind::Wall
                && polygon_contains(&region.polygon, [f64::from(p[0]), f64::from(p[1])])
        })
        .collect();
    let q: Vec<[f32; 3]> = idx.iter().map(|&i| w.gt.xyz[i]).collect();
    let d = nearest_distances(&q, &w.xyz);
    let missing: Vec<usize> = idx
        .iter()
        .zip(&d)
        .filter(|(_, d)| **d > 0.25)
        .map(|(&i, _)| i)
        .collect();
    let pts: Vec<[f32; 3]> = missing.iter().map(|&i| w.gt.xyz[i]).collect();
    let kept = resample(&pts, 0.5).unwrap();
    // Normals of the kept samples (resample keeps the first of each voxel, in order).
    let mut normal = Vec::with_capacity(kept.len());
    let mut j = 0;
    for p in &kept {
        while pts[j] != *p {
            j += 1;
        }
        normal.push(w.gt.normal[missing[j]]);
    }
    SurfaceSamples { xyz: kept, normal }
}

/// Coverage after scanning from every 4th graph node in the region.
fn reachable_coverage(
    g: &Arc<GroundGraph>,
    region: &Region,
    surface: &SurfaceSamples,
    params: &ExploreParams,
) -> f64 {
    let w = world();
    let mut ex = Explorer::new(region, surface.clone(), &[], g.clone(), params).unwrap();
    let mut all = Vec::new();
    for (k, &n) in g
        .nodes_in_polygon(&region.polygon)
        .iter()
        .enumerate()
        .step_by(4)
    {
        let p = g.positions()[n];
        let pose = Pose::new([p[0], p[1], p[2] + params.sensor_height_m], 0.0);
        all.extend(
            scan(&w.caster, &LidarConfig::default(), &pose, 1000 + k as u64)
                .unwrap()
                .xyz,
        );
    }
    ex.update([f32::NAN; 3], &all);
    ex.coverage()
}

#[test]
fn coverage_rises_with_every_scan_until_done() {
    let w = world();
    let g = Arc::new(graph());
    let params = ExploreParams::default();
    let lidar = LidarConfig::default();
    for b in [2u32, 9] {
        let region = corner_region(w, b, 6.0, 12.0);
        let surface = missing_walls(&region);
        assert!(
            surface.xyz.len() > 20,
            "building {b}: only {} missing samples",
            surface.xyz.len()
        );
        let mut ex = Explorer::new(&region, surface.clone(), &w.xyz, g.clone(), &params).unwrap();
        let mut pos = g.positions()[g
            .nearest_node([region.polygon[0][0] as f32, region.polygon[0][1] as f32])
            .unwrap()
            .0];
        let mut cov = ex.coverage();
        println!(
            "building {b}: {} samples, {} candidates, coverage {:.3}",
            surface.xyz.len(),
            ex.candidates(),
            cov
        );
        let mut steps = 0;
        while !ex.done() {
            let wps = ex.next_waypoints(pos);
            assert!(!wps.is_empty());
            pos = wps[0];
            let pose = Pose::new([pos[0], pos[1], pos[2] + params.sensor_height_m], 0.0);
            let s = scan(&w.caster, &lidar, &pose, steps as u64).unwrap();
            ex.update(pos, &s.xyz);
            let now = ex.coverage();
            steps += 1;
            println!(
                "  step {steps}: viewpoint ({:.1}, {:.1}), {} left, coverage {:.3}",
                pos[0],
                pos[1],
                wps.len() - 1,
                now
            );
            assert!(
                now > cov,
                "coverage did not rise at step {steps}: {cov} → {now}"
            );
            cov = now;
            assert!(steps < 25, "not done after 25 scans");
        }
        assert!(steps >= 1);
        // What a ground sensor can see at all from this region (upper walls
        // are above the ±15° fan): scans from every 4th node of the region.
        let best = reachable_coverage(&g, &region, &surface, &params);
        println!(
            "  done after {steps} scans: coverage {cov:.3} of at most {best:.3} (scans from every 4th region node)"
        );
        assert!(
            cov >= 0.9 * best,
            "building {b}: final coverage {cov} vs reachable {best}"
        );
        assert!(best > 0.3);
    }
}

#[test]
fn bad_input_gives_errors() {
    let w = world();
    let g = Arc::new(graph());
    let region = corner_region(w, 2, 6.0, 12.0);
    let p = ExploreParams::default();
    let bad = SurfaceSamples {
        xyz: vec![[0.0; 3]; 3],
        normal: vec![[1.0, 0.0, 0.0]],
    };
    assert!(matches!(
        Explorer::new(&region, bad, &[], g.clone(), &p),
        Err(ExploreError::NormalLength { .. })
    ));
    let line = Region {
        polygon: vec![[0.0, 0.0], [1.0, 1.0]],
        ..region.clone()
    };
    assert!(matches!(
        Explorer::new(&line, vec![], &[], g.clone(), &p),
        Err(ExploreError::DegenerateRegion { .. })
    ));
    let bad_p = ExploreParams {
        tau_m: 0.0,
        ..p.clone()
    };
    assert!(matches!(
        Explorer::new(&region, vec![], &[], g.clone(), &bad_p),
        Err(ExploreError::Param(ParamError { field: "tau_m", .. }))
    ));
    // Nothing to cover: done at once, full coverage.
    let ex = Explorer::new(&region, vec![], &[], g.clone(), &p).unwrap();
    assert!(ex.done() && ex.coverage() == 1.0);
}

#[test]
fn path_to_follows_graph_edges_to_the_target_node() {
    let w = world();
    let g = Arc::new(graph());
    let region = corner_region(w, 2, 6.0, 12.0);
    let ex = Explorer::new(&region, vec![], &[], g.clone(), &ExploreParams::default()).unwrap();
    let from = start(w);
    let target = [
        region.polygon[0][0] as f32,
        region.polygon[0][1] as f32,
        0.0,
    ];
    let path = ex.path_to(from, target);
    let a = g.nearest_node([from[0], from[1]]).unwrap().0;
    let b = g.nearest_node([target[0], target[1]]).unwrap().0;
    assert_eq!(path.first(), Some(&g.positions()[a]));
    assert_eq!(path.last(), Some(&g.positions()[b]));
    // Every leg is a graph edge: short and free of obstacles.
    let edge_max = g.params().d_threshold();
    for leg in path.windows(2) {
        let (p, q) = (leg[0], leg[1]);
        let d = ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt();
        assert!(d > 0.0 && d <= edge_max, "leg of {d} m");
        assert!(g.segment_free([p[0], p[1]], [q[0], q[1]]));
    }
    let straight = ((from[0] - target[0]).powi(2) + (from[1] - target[1]).powi(2)).sqrt();
    assert!(
        path.len() as f32 >= straight / edge_max,
        "{} nodes for {straight} m",
        path.len()
    );
    // Nowhere to start from: the target alone.
    assert_eq!(ex.path_to([f32::NAN; 3], target), vec![target]);
}
