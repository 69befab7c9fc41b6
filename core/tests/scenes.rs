//! Scenes and metrics end to end: the reference scene's promises, ground-truth
//! sampling and completeness on hand-built scenes, scene files through
//! `load_scene`, and the real CityJSON files in `../shared/data/real`
//! (`SKYGROUND_REAL_DATA` overrides; absent → `SKIPPED: ...`, test passes).

use std::path::PathBuf;
use std::time::Instant;

use skyground_core::cloud::Cloud;
use skyground_core::io::{SceneError, load_scene};
use skyground_core::metrics::{
    SurfaceKind, cloud_to_mesh_distances, completeness, completeness_of_cloud, mean_cloud_to_mesh,
    mean_gt_distance, sample_building_surfaces,
};
use skyground_core::scene::{
    MeshPart, ObjectKind, REFERENCE_SEED, ReferenceTerrain, Scene, SceneBuilder, reference_scene,
};

mod common;
use common::real_file;

// ---------------------------------------------------------------- helpers

/// Heights (m) along `dir` from `origin` at which the ray hits triangles of
/// object `object`, with the hit triangle's normal z.
fn ray_hits(scene: &Scene, object: u32, origin: [f64; 3], dir: [f64; 3]) -> Vec<(f64, f64)> {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let mut hits = Vec::new();
    for t in scene.object_triangles(object) {
        let [a, b, c] = scene.triangle_corners(t).unwrap().map(|p| p.map(f64::from));
        let (e1, e2) = (sub(b, a), sub(c, a));
        let p = cross(dir, e2);
        let det = dot(e1, p);
        if det.abs() < 1e-12 {
            continue;
        }
        let s = sub(origin, a);
        let u = dot(s, p) / det;
        let q = cross(s, e1);
        let v = dot(dir, q) / det;
        let dist = dot(e2, q) / det;
        if u >= 0.0 && v >= 0.0 && u + v <= 1.0 && dist > 0.0 {
            let n = cross(e1, e2);
            hits.push((dist, n[2] / dot(n, n).sqrt()));
        }
    }
    hits.sort_by(|a, b| a.0.total_cmp(&b.0));
    hits
}

fn object_named(scene: &Scene, part: &str) -> Vec<u32> {
    (0..scene.objects.len() as u32)
        .filter(|&o| scene.objects[o as usize].name.contains(part))
        .collect()
}

fn object_bounds(scene: &Scene, object: u32) -> ([f32; 3], [f32; 3]) {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for t in scene.object_triangles(object) {
        for p in scene.triangle_corners(t).unwrap() {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    (lo, hi)
}

/// An axis-aligned closed box (outward normals), optionally without its bottom.
fn box_mesh(lo: [f64; 3], hi: [f64; 3], bottom: bool) -> MeshPart {
    let mut m = MeshPart::default();
    let ring = [
        [lo[0], lo[1]],
        [hi[0], lo[1]],
        [hi[0], hi[1]],
        [lo[0], hi[1]],
    ];
    let b = m.ring(&ring, lo[2]);
    let t = m.ring(&ring, hi[2]);
    if bottom {
        m.cap(&[&b], false);
    }
    m.walls(&b, &t);
    m.cap(&[&t], true);
    m
}

fn ground_quad(size: f64, z: f64) -> MeshPart {
    let mut m = MeshPart::default();
    let r = m.ring(
        &[[-size, -size], [size, -size], [size, size], [-size, size]],
        z,
    );
    m.cap(&[&r], true);
    m
}

fn within(got: f64, want: f64, rel: f64) -> bool {
    (got - want).abs() <= rel * want
}

fn temp_file(dir: &std::path::Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

// ------------------------------------------------------- reference scene

#[test]
fn reference_scene_has_the_promised_buildings() {
    let t0 = Instant::now();
    let scene = reference_scene(REFERENCE_SEED);
    let built = t0.elapsed();
    scene.validate().unwrap();
    let terrain = ReferenceTerrain::new(REFERENCE_SEED);
    let ids = scene.building_ids();
    assert!((12..=20).contains(&ids.len()), "{} buildings", ids.len());
    assert_eq!(ids, (1..=ids.len() as u32).collect::<Vec<_>>());
    assert_eq!(scene.object_count(ObjectKind::Ground), 1);
    for o in 0..scene.objects.len() as u32 {
        let obj = &scene.objects[o as usize];
        if obj.kind != ObjectKind::Building {
            continue;
        }
        let d = scene.edge_defects(o);
        assert!(d.is_closed(), "{} not closed: {d:?}", obj.name);
        assert!(scene.signed_volume(o) > 0.0, "{} inside out", obj.name);
        let (lo, hi) = object_bounds(&scene, o);
        let (cx, cy) = (
            f64::from(lo[0] + hi[0]) / 2.0,
            f64::from(lo[1] + hi[1]) / 2.0,
        );
        let height = f64::from(hi[2]) - terrain.mesh_height(cx, cy);
        assert!(
            (5.0..=60.0).contains(&height),
            "{} is {height} m tall",
            obj.name
        );
        // Sits on the terrain: every bottom vertex is below the ground there.
        for t in scene.object_triangles(o) {
            for p in scene.triangle_corners(t).unwrap() {
                if p[2] == lo[2] {
                    let g = terrain.mesh_height(f64::from(p[0]), f64::from(p[1]));
                    assert!(
                        f64::from(p[2]) < g,
                        "{} floats at ({}, {})",
                        obj.name,
                        p[0],
                        p[1]
                    );
                }
            }
        }
    }
    let t1 = Instant::now();
    let gt = sample_building_surfaces(&scene, 0.25);
    let sampled = t1.elapsed();
    let t2 = Instant::now();
    let report = completeness(&gt, &gt.xyz, 0.25);
    let covered = t2.elapsed();
    let t3 = Instant::now();
    let accuracy = mean_cloud_to_mesh(&scene, &gt.xyz);
    let measured = t3.elapsed();
    assert_eq!(report.overall.ratio, Some(1.0));
    assert!(accuracy.is_some_and(|a| a < 1e-4));
    eprintln!(
        "reference scene: {} buildings, {} trees, {} triangles, built in {built:?}; {} GT samples at 0.25 m in \
         {sampled:?}; completeness of them against themselves {covered:?}, cloud-to-mesh {measured:?}",
        ids.len(),
        scene.object_count(ObjectKind::Vegetation),
        scene.triangles.len(),
        gt.len()
    );
}

#[test]
fn reference_scene_has_hollow_base_courtyard_alley_and_slope() {
    let scene = reference_scene(REFERENCE_SEED);
    let terrain = ReferenceTerrain::new(REFERENCE_SEED);

    // Hollow base: straight up from the ground under the slab, the first
    // thing hit is the slab's underside, well above the terrain.
    let pillars = object_named(&scene, "pillars");
    assert_eq!(pillars.len(), 1);
    let (lo, hi) = object_bounds(&scene, pillars[0]);
    let (cx, cy) = (
        f64::from(lo[0] + hi[0]) / 2.0,
        f64::from(lo[1] + hi[1]) / 2.0,
    );
    let ground = terrain.mesh_height(cx, cy);
    let hits = ray_hits(&scene, pillars[0], [cx, cy, ground + 0.05], [0.0, 0.0, 1.0]);
    let (first, nz) = hits.first().copied().expect("ray hits the slab");
    assert!(first > 2.5, "floor only {first} m above ground");
    assert!(nz < -0.9, "first hit is not an underside (n_z {nz})");

    // Courtyard: open to the sky in the middle, enclosed on four sides.
    let court = object_named(&scene, "courtyard");
    assert_eq!(court.len(), 1);
    let (lo, hi) = object_bounds(&scene, court[0]);
    let (cx, cy) = (
        f64::from(lo[0] + hi[0]) / 2.0,
        f64::from(lo[1] + hi[1]) / 2.0,
    );
    let mid = f64::from(lo[2] + hi[2]) / 2.0;
    assert!(
        ray_hits(
            &scene,
            court[0],
            [cx, cy, f64::from(lo[2]) - 1.0],
            [0.0, 0.0, 1.0]
        )
        .is_empty()
    );
    for dir in [
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
    ] {
        assert!(!ray_hits(&scene, court[0], [cx, cy, mid], dir).is_empty());
    }

    // Narrow alleys: some pairs of buildings 2–4 m apart, facing each other.
    let boxes: Vec<_> = scene
        .building_ids()
        .iter()
        .map(|&id| {
            let o = scene.objects.iter().position(|o| o.building == id).unwrap() as u32;
            object_bounds(&scene, o)
        })
        .collect();
    let mut alleys = 0;
    for (i, a) in boxes.iter().enumerate() {
        for b in &boxes[i + 1..] {
            for (k, j) in [(0, 1), (1, 0)] {
                let gap = (b.0[k] - a.1[k]).max(a.0[k] - b.1[k]);
                let overlap = a.1[j].min(b.1[j]) - a.0[j].max(b.0[j]);
                if (2.0..=4.0).contains(&gap) && overlap > 5.0 {
                    alleys += 1;
                }
            }
        }
    }
    assert!(alleys >= 2, "{alleys} alleys");

    // Terrain: one plane fit gives a 2–4 % slope.
    let g = scene.object_triangles(0).count();
    assert!(g > 10_000);
    let [gx, gy] = terrain.gradient();
    let (z0, zx, zy) = (
        terrain.mesh_height(20.0, 20.0),
        terrain.mesh_height(180.0, 20.0),
        terrain.mesh_height(20.0, 180.0),
    );
    let fit = (((zx - z0) / 160.0).powi(2) + ((zy - z0) / 160.0).powi(2)).sqrt();
    assert!((0.015..=0.045).contains(&fit), "slope {fit}");
    assert!((0.02..=0.04).contains(&(gx * gx + gy * gy).sqrt()));
}

#[test]
fn reference_trees_stand_near_facades() {
    let scene = reference_scene(REFERENCE_SEED);
    let terrain = ReferenceTerrain::new(REFERENCE_SEED);
    let mut trunks = Vec::new();
    for o in 0..scene.objects.len() as u32 {
        if scene.objects[o as usize].kind != ObjectKind::Vegetation {
            continue;
        }
        let (lo, hi) = object_bounds(&scene, o);
        let width = hi[0] - lo[0];
        assert!((4.0..=10.0).contains(&width), "crown {width} m wide");
        let (x, y) = ((lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0);
        let g = terrain.mesh_height(f64::from(x), f64::from(y)) as f32;
        trunks.push([x, y, g + 1.0]);
    }
    assert!(trunks.len() >= 10, "{} trees", trunks.len());
    let d = cloud_to_mesh_distances(&scene, &trunks);
    let near = d.iter().filter(|&&v| (1.5..=5.0).contains(&v)).count();
    assert!(near >= 5, "only {near} trees within 5 m of a facade: {d:?}");
    assert!(
        d.iter().all(|&v| v >= 1.5),
        "a trunk touches a building: {d:?}"
    );
}

#[test]
fn reference_scene_is_reproducible_per_seed() {
    let a = reference_scene(7);
    assert_eq!(a, reference_scene(7));
    let b = reference_scene(8);
    assert_ne!(a, b);
    assert_ne!(a.vertices, b.vertices);
    assert_eq!(load_scene("reference:7").unwrap(), a);
    assert_eq!(
        load_scene("reference").unwrap(),
        reference_scene(REFERENCE_SEED)
    );
}

#[test]
fn reference_promises_hold_for_many_seeds() {
    for seed in 0..24 {
        let scene = reference_scene(seed);
        let terrain = ReferenceTerrain::new(seed);
        assert!((12..=20).contains(&scene.building_count()), "seed {seed}");
        let mut trunks = Vec::new();
        for o in 0..scene.objects.len() as u32 {
            let obj = &scene.objects[o as usize];
            let (lo, hi) = object_bounds(&scene, o);
            let (cx, cy) = (
                f64::from(lo[0] + hi[0]) / 2.0,
                f64::from(lo[1] + hi[1]) / 2.0,
            );
            let ground = terrain.mesh_height(cx, cy);
            match obj.kind {
                ObjectKind::Building => {
                    assert!(
                        scene.edge_defects(o).is_closed(),
                        "seed {seed} {}",
                        obj.name
                    );
                    let h = f64::from(hi[2]) - ground;
                    assert!((5.0..=60.0).contains(&h), "seed {seed} {} {h} m", obj.name);
                    if obj.name.contains("pillars") {
                        let hits = ray_hits(&scene, o, [cx, cy, ground + 0.05], [0.0, 0.0, 1.0]);
                        assert!(
                            hits.first().is_some_and(|h| h.0 > 2.5 && h.1 < -0.9),
                            "seed {seed}"
                        );
                    }
                }
                ObjectKind::Vegetation => {
                    assert!((4.0..=10.0).contains(&(hi[0] - lo[0])), "seed {seed}");
                    trunks.push([
                        (lo[0] + hi[0]) / 2.0,
                        (lo[1] + hi[1]) / 2.0,
                        ground as f32 + 1.0,
                    ]);
                }
                ObjectKind::Ground => {}
            }
        }
        let d = cloud_to_mesh_distances(&scene, &trunks);
        assert!(
            d.iter().filter(|&&v| v <= 5.0).count() >= 3,
            "seed {seed}: {d:?}"
        );
        assert!(d.iter().all(|&v| v >= 1.5), "seed {seed}: {d:?}");
    }
}

// ------------------------------------------------- ground truth + metrics

/// A 10 × 8 × 6 m box building standing on a ground quad at z = 0.
fn box_scene(with_ground: bool) -> Scene {
    let mut b = SceneBuilder::new([0.0; 3]);
    if with_ground {
        b.add("ground", ObjectKind::Ground, 0, &ground_quad(50.0, 0.0));
    }
    b.add(
        "building_1",
        ObjectKind::Building,
        1,
        &box_mesh([0.0, 0.0, 0.0], [10.0, 8.0, 6.0], true),
    );
    b.finish()
}

#[test]
fn gt_density_surface_and_kinds_on_a_box() {
    for with_ground in [true, false] {
        let scene = box_scene(with_ground);
        let s = 0.25;
        let gt = sample_building_surfaces(&scene, s);
        let walls = gt.kind.iter().filter(|k| **k == SurfaceKind::Wall).count() as f64;
        let roofs = gt.kind.iter().filter(|k| **k == SurfaceKind::Roof).count() as f64;
        let per = f64::from(s * s);
        // Walls 2 (10 + 8) 6 = 216 m², roof 80 m², bottom excluded.
        assert!(within(walls * per, 216.0, 0.10), "walls {}", walls * per);
        assert!(within(roofs * per, 80.0, 0.10), "roof {}", roofs * per);
        assert!(within(gt.len() as f64 * per, 296.0, 0.05));
        for ((p, n), k) in gt.xyz.iter().zip(&gt.normal).zip(&gt.kind) {
            assert!(n[2] > -0.5, "bottom sampled at {p:?}");
            match k {
                SurfaceKind::Roof => assert!((p[2] - 6.0).abs() < 1e-4 && n[2] > 0.99),
                SurfaceKind::Wall => assert!(n[2].abs() < 1e-6 && (p[2] >= 0.05 || !with_ground)),
            }
        }
        assert!(gt.building.iter().all(|&b| b == 1));
        let d = cloud_to_mesh_distances(&scene, &gt.xyz);
        assert!(d.iter().all(|&v| v < 1e-4), "a sample is off the surface");
    }
}

#[test]
fn gt_leaves_out_buried_and_shared_faces() {
    // A podium with a tower standing on it (separate objects, same building)
    // and a second building sharing the podium's east wall.
    let mut b = SceneBuilder::new([0.0; 3]);
    b.add("ground", ObjectKind::Ground, 0, &ground_quad(100.0, 0.0));
    b.add(
        "building_podium",
        ObjectKind::Building,
        1,
        &box_mesh([0.0, 0.0, -0.5], [20.0, 20.0, 5.0], true),
    );
    b.add(
        "building_tower",
        ObjectKind::Building,
        1,
        &box_mesh([5.0, 5.0, 5.0], [15.0, 15.0, 25.0], true),
    );
    b.add(
        "building_next",
        ObjectKind::Building,
        2,
        &box_mesh([20.0, 0.0, -0.5], [30.0, 20.0, 8.0], true),
    );
    let scene = b.finish();
    let gt = sample_building_surfaces(&scene, 0.25);
    let area = gt.len() as f64 * 0.0625;
    // Podium: 3 free walls 3 × 20 × 5 + roof 400 − 100 under the tower.
    // Tower: walls 4 × 10 × 20 + roof 100. Next: walls 20×8 + 2×10×8 + the
    // part of its west wall above the podium (20 × 3) + roof 200.
    let want = (300.0 + 300.0) + (800.0 + 100.0) + (160.0 + 160.0 + 60.0 + 200.0);
    assert!(within(area, want, 0.05), "GT area {area}, want {want}");
    // Nothing sampled on the tower's foot or on the podium under it.
    assert!(!gt.xyz.iter().any(|p| (p[2] - 5.0).abs() < 0.01
        && p[0] > 5.1
        && p[0] < 14.9
        && p[1] > 5.1
        && p[1] < 14.9));
    // Nothing on the party wall at x = 20 below the podium's roof.
    assert!(
        !gt.xyz
            .iter()
            .any(|p| (p[0] - 20.0).abs() < 0.01 && p[2] < 4.9)
    );
}

#[test]
fn completeness_full_empty_and_partial() {
    let mut b = SceneBuilder::new([0.0; 3]);
    b.add("ground", ObjectKind::Ground, 0, &ground_quad(100.0, 0.0));
    b.add(
        "building_a",
        ObjectKind::Building,
        1,
        &box_mesh([0.0, 0.0, 0.0], [10.0, 10.0, 10.0], true),
    );
    b.add(
        "building_b",
        ObjectKind::Building,
        2,
        &box_mesh([40.0, 0.0, 0.0], [50.0, 20.0, 5.0], true),
    );
    let scene = b.finish();
    let gt = sample_building_surfaces(&scene, 0.25);

    let full = completeness(&gt, &gt.xyz, 0.25);
    assert_eq!(full.overall.ratio, Some(1.0));
    assert_eq!(full.walls.ratio, Some(1.0));
    assert_eq!(full.roofs.ratio, Some(1.0));
    assert_eq!(full.mean_gt_distance, Some(0.0));
    assert_eq!(full.buildings.len(), 2);

    let empty = completeness(&gt, &[], 0.25);
    assert_eq!(empty.overall.ratio, Some(0.0));
    assert_eq!(empty.overall.samples, gt.len());
    assert_eq!(empty.mean_gt_distance, None);
    assert_eq!(mean_gt_distance(&gt, &[]), None);

    // Building 2 deleted from the cloud: exactly building 1's share remains.
    let kept = gt.of_building(1);
    let half = completeness(&gt, &kept, 0.25);
    let share = kept.len() as f64 / gt.len() as f64;
    assert!((half.overall.ratio.unwrap() - share).abs() < 1e-12);
    assert_eq!(half.buildings[0].all.ratio, Some(1.0));
    assert_eq!(half.buildings[1].all.ratio, Some(0.0));
    // Building 2's samples are 30–50 m from building 1.
    let gap = half.buildings[1].mean_gt_distance.unwrap();
    assert!((30.0..60.0).contains(&gap), "gap {gap}");

    // Points 0.1 m off the surface along the normal: accuracy 0.1, all covered.
    let off: Vec<[f32; 3]> = gt
        .xyz
        .iter()
        .zip(&gt.normal)
        .map(|(p, n)| [p[0] + 0.1 * n[0], p[1] + 0.1 * n[1], p[2] + 0.1 * n[2]])
        .collect();
    let acc = mean_cloud_to_mesh(&scene, &off).unwrap();
    assert!((acc - 0.1).abs() < 2e-3, "accuracy {acc}");
    assert_eq!(completeness(&gt, &off, 0.25).overall.ratio, Some(1.0));
    // A cloud in another frame is moved into the samples' frame first.
    let mut cloud = Cloud::from_xyz(
        kept.iter()
            .map(|p| [p[0] - 100.0, p[1], p[2] + 5.0])
            .collect(),
    );
    cloud.origin = [100.0, 0.0, -5.0];
    let moved = completeness_of_cloud(&gt, &cloud, 0.25);
    assert_eq!(moved.overall.covered, half.overall.covered);
    assert_eq!(mean_cloud_to_mesh(&scene, &[]), None);
    let json = serde_json::to_string(&half).unwrap();
    assert!(json.contains("\"buildings\""));
}

#[test]
fn gt_samples_write_as_ply() {
    let gt = sample_building_surfaces(&box_scene(true), 1.0);
    let mut bytes = Vec::new();
    gt.write_ply(&mut bytes).unwrap();
    let cloud = skyground_core::cloud::parse_ply(&bytes).unwrap();
    assert_eq!(cloud.len(), gt.len());
    let labels = cloud.label.unwrap();
    let roofs = gt.kind.iter().filter(|k| **k == SurfaceKind::Roof).count();
    assert_eq!(labels.iter().filter(|&&l| l == 1).count(), roofs);
    assert!(cloud.building.unwrap().iter().all(|&b| b == 1));
}

// ------------------------------------------------------------ scene files

#[test]
fn load_scene_dispatches_and_names_file_and_line() {
    let tmp = tempfile::tempdir().unwrap();
    let obj = temp_file(
        tmp.path(),
        "two.obj",
        b"o ground\nv 0 0 0\nv 10 0 0\nv 10 10 0\nf 1 2 3\no building_1\nv 1 1 0\nv 2 1 0\nv 2 2 1\nf -3 -2 -1\n",
    );
    let s = load_scene(obj.to_str().unwrap()).unwrap();
    assert_eq!((s.objects.len(), s.building_count()), (2, 1));

    let bad = temp_file(
        tmp.path(),
        "bad.obj",
        b"o building_1\nv 0 0 0\nv 1 0 0\nf 1 2 7\n",
    );
    let err = load_scene(bad.to_str().unwrap()).unwrap_err();
    assert!(matches!(err, SceneError::Obj { .. }));
    let msg = err.to_string();
    assert!(msg.contains("bad.obj") && msg.contains("line 4"), "{msg}");

    let ply = temp_file(
        tmp.path(),
        "tri.PLY",
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    );
    assert_eq!(
        load_scene(ply.to_str().unwrap()).unwrap().triangles.len(),
        1
    );

    let city = temp_file(
        tmp.path(),
        "bad.city.json",
        b"{\"type\": \"CityJSON\", \"version\": \"2.0\",\n \"CityObjects\": [}",
    );
    let msg = load_scene(city.to_str().unwrap()).unwrap_err().to_string();
    assert!(
        msg.contains("bad.city.json") && msg.contains("line 2"),
        "{msg}"
    );

    assert!(matches!(
        load_scene("scene.stl"),
        Err(SceneError::UnknownFormat { .. })
    ));
    assert!(matches!(
        load_scene("reference:x"),
        Err(SceneError::BadSeed { .. })
    ));
    assert!(matches!(
        load_scene("/nonexistent/x.obj"),
        Err(SceneError::Io(_))
    ));
}

fn check_real_city(name: &str, buildings: usize) {
    let Some(path) = real_file(name) else { return };
    let t0 = Instant::now();
    let scene = load_scene(path.to_str().unwrap()).unwrap();
    let loaded = t0.elapsed();
    scene.validate().unwrap();
    assert_eq!(scene.building_count(), buildings, "{name}");
    assert_eq!(
        scene.building_ids(),
        (1..=buildings as u32).collect::<Vec<_>>()
    );
    assert!(
        scene.origin[0].abs() > 10_000.0 && scene.origin[1].abs() > 10_000.0,
        "{:?}",
        scene.origin
    );
    assert_eq!(scene.origin.map(f64::fract), [0.0; 3]);
    let (lo, hi) = scene.bounds_of(|k| k == ObjectKind::Building).unwrap();
    assert!(
        lo.iter().all(|v| (0.0..1.0).contains(v)),
        "local min {lo:?}"
    );
    assert!(hi.iter().all(|v| *v < 20_000.0), "local max {hi:?}");
    // The built ground, plus the file's own roads and land use (delft.json).
    assert!(
        scene
            .objects
            .iter()
            .any(|o| o.name == "terrain" && o.kind == ObjectKind::Ground)
    );
    let building_tris: Vec<usize> = (0..scene.triangles.len())
        .filter(|&t| scene.triangle_kind(t).unwrap().kind == ObjectKind::Building)
        .collect();
    let thin = building_tris
        .iter()
        .filter(|&&t| scene.triangle_area(t) < 1e-4)
        .count();
    assert!(
        thin * 100 <= building_tris.len(),
        "{thin} near-degenerate triangles"
    );
    let t1 = Instant::now();
    let gt = sample_building_surfaces(&scene, 0.25);
    eprintln!(
        "{name}: {buildings} buildings in {} objects, {} building + {} terrain triangles, origin {:?}, \
         loaded in {loaded:?}; {} GT samples at 0.25 m in {:?}",
        scene.object_count(ObjectKind::Building),
        building_tris.len(),
        scene.triangles.len() - building_tris.len(),
        scene.origin,
        gt.len(),
        t1.elapsed()
    );
    assert!(gt.len() > 100_000);
}

#[test]
fn zurich_lod2_loads_with_parts_merged() {
    check_real_city("zurich_subset_lod2.json", 49);
}

#[test]
fn delft_lod1_loads() {
    check_real_city("delft.json", 160);
}
