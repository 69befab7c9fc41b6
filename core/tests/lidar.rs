//! Ray caster and LiDAR simulation: hits on the mesh, no leaks through closed
//! buildings, BVH equal to brute force, spinning and airborne scans.

use proptest::prelude::*;
use skyground_core::lidar::synthetic::{SyntheticBuilder, boxes_on_plane, dense_scene};
use skyground_core::lidar::{
    AirborneConfig, CastBackend, Caster, CasterError, FlightPattern, LidarConfig, Pose, Ray,
    airborne_scan, scan,
};
use skyground_core::scene::{ObjectKind, Scene, SceneCheckError, SceneObject};

/// A small deterministic generator for test inputs.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }

    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next()
    }

    fn unit(&mut self) -> [f32; 3] {
        loop {
            let v = [
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            ];
            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if n > 0.1 && n <= 1.0 {
                return v.map(|x| x / n);
            }
        }
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Distance from `p` to triangle `t` (f64, closest-point by regions).
fn point_triangle_distance(p: [f64; 3], t: [[f64; 3]; 3]) -> f64 {
    let [a, b, c] = t;
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    let closest = if d1 <= 0.0 && d2 <= 0.0 {
        a
    } else {
        let bp = sub(p, b);
        let (d3, d4) = (dot(ab, bp), dot(ac, bp));
        let cp = sub(p, c);
        let (d5, d6) = (dot(ab, cp), dot(ac, cp));
        let (vc, vb, va) = (d1 * d4 - d3 * d2, d5 * d2 - d1 * d6, d3 * d6 - d5 * d4);
        let lerp =
            |o: [f64; 3], d: [f64; 3], s: f64| [o[0] + s * d[0], o[1] + s * d[1], o[2] + s * d[2]];
        if d3 >= 0.0 && d4 <= d3 {
            b
        } else if d6 >= 0.0 && d5 <= d6 {
            c
        } else if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
            lerp(a, ab, d1 / (d1 - d3))
        } else if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
            lerp(a, ac, d2 / (d2 - d6))
        } else if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
            lerp(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)))
        } else {
            let denom = 1.0 / (va + vb + vc);
            let (v, w) = (vb * denom, vc * denom);
            [
                a[0] + ab[0] * v + ac[0] * w,
                a[1] + ab[1] * v + ac[1] * w,
                a[2] + ab[2] * v + ac[2] * w,
            ]
        }
    };
    let d = sub(p, closest);
    dot(d, d).sqrt()
}

fn triangle(scene: &Scene, t: u32) -> [[f64; 3]; 3] {
    scene.triangles[t as usize].map(|i| scene.vertices[i as usize].map(f64::from))
}

fn point_on_ray(ray: &Ray, t: f32) -> [f64; 3] {
    let d = ray.dir.map(f64::from);
    let n = dot(d, d).sqrt();
    std::array::from_fn(|k| f64::from(ray.origin[k]) + f64::from(t) * d[k] / n)
}

#[test]
fn hits_lie_on_the_hit_triangle() {
    let scene = dense_scene(60_000, 5);
    let caster = Caster::new(&scene).unwrap();
    let mut rng = Lcg(11);
    let mut hits = 0;
    for _ in 0..20_000 {
        let origin = [
            rng.range(0.0, 200.0),
            rng.range(0.0, 200.0),
            rng.range(2.0, 60.0),
        ];
        let ray = Ray::new(origin, rng.unit(), 300.0);
        let Some(hit) = caster.cast_ray(&ray) else {
            continue;
        };
        hits += 1;
        let d = point_triangle_distance(point_on_ray(&ray, hit.t), triangle(&scene, hit.triangle));
        assert!(d <= 1e-4, "hit {hit:?} is {d} m off its triangle");
        assert_eq!(hit.object, scene.triangle_object[hit.triangle as usize]);
        let n = hit.normal;
        assert!(((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) - 1.0).abs() < 1e-5);
    }
    assert!(hits > 5_000, "only {hits} hits");
}

#[test]
fn noisy_ranges_stay_within_four_sigma() {
    let scene = dense_scene(60_000, 2);
    let caster = Caster::new(&scene).unwrap();
    let config = LidarConfig {
        range_noise_sigma: 0.05,
        ..LidarConfig::default()
    };
    let pose = skyground_core::lidar::bench::street_poses(&caster, 1)[0];
    let points = scan(&caster, &config, &pose, 3).unwrap();
    assert!(points.len() > 10_000);
    let mut worst = 0.0f32;
    for (p, &range) in points.xyz.iter().zip(&points.range) {
        let dir: [f32; 3] = std::array::from_fn(|k| p[k] - pose.position[k]);
        let truth = caster.cast(pose.position, dir, 200.0).unwrap();
        let err = (range - truth.t).abs();
        worst = worst.max(err);
        assert!(err <= 4.0 * config.range_noise_sigma + 1e-4, "error {err}");
    }
    // The noise is really there.
    assert!(
        worst > 2.0 * config.range_noise_sigma,
        "worst error {worst}"
    );
}

#[test]
fn rays_aimed_into_a_closed_box_hit_it_first() {
    let lo = [-3.0, -2.0, 0.0];
    let hi = [4.0, 5.0, 9.0];
    let scene = boxes_on_plane(50.0, &[(lo, hi)]);
    let caster = Caster::new(&scene).unwrap();
    let mut rng = Lcg(3);
    for i in 0..50_000 {
        // Interior targets, some a hair inside a face, an edge or a corner.
        let eps = [1e-3f32, 1e-4][i % 2];
        let mut target: [f32; 3] = std::array::from_fn(|k| rng.range(lo[k] + eps, hi[k] - eps));
        let snap = |rng: &mut Lcg, k: usize| {
            if rng.next() < 0.5 {
                lo[k] + eps
            } else {
                hi[k] - eps
            }
        };
        match i % 4 {
            1 => target[i % 3] = snap(&mut rng, i % 3),
            2 => {
                target[i % 3] = snap(&mut rng, i % 3);
                target[(i + 1) % 3] = snap(&mut rng, (i + 1) % 3);
            }
            3 => target = std::array::from_fn(|k| snap(&mut rng, k)),
            _ => {}
        }
        let origin = loop {
            let o = [
                rng.range(-30.0, 30.0),
                rng.range(-30.0, 30.0),
                rng.range(0.5, 30.0),
            ];
            let inside = (0..3).all(|k| o[k] >= lo[k] - 0.01 && o[k] <= hi[k] + 0.01);
            if !inside {
                break o;
            }
        };
        let dir: [f32; 3] = std::array::from_fn(|k| target[k] - origin[k]);
        let dist = dir.iter().map(|d| d * d).sum::<f32>().sqrt();
        let hit = caster.cast(origin, dir, 1000.0);
        let hit = hit.unwrap_or_else(|| panic!("ray {origin:?} → {target:?} leaked"));
        assert_eq!(hit.object, 1, "ray {origin:?} → {target:?} hit {hit:?}");
        assert!(hit.t <= dist * (1.0 + 1e-5) + 1e-4);
    }
}

#[test]
fn a_sensor_inside_a_closed_box_sees_only_the_box() {
    // Floating above the ground plane, so only the box is around the sensor.
    let scene = boxes_on_plane(50.0, &[([-3.0, -2.0, 0.5], [4.0, 5.0, 9.0])]);
    let caster = Caster::new(&scene).unwrap();
    for (pos, yaw, pitch) in [
        ([0.0, 0.0, 1.8], 0.0, 0.0),
        ([3.9, 4.9, 8.9], 0.3, 0.7),
        ([-2.99, 0.0, 0.51], 1.0, -0.4),
    ] {
        let pose = Pose {
            position: pos,
            yaw,
            pitch,
            roll: 0.2,
        };
        let config = LidarConfig {
            beams: 32,
            fov_min_deg: -90.0,
            fov_max_deg: 90.0,
            azimuth_step_deg: 0.5,
            min_range: 0.0,
            range_noise_sigma: 0.0,
            ..LidarConfig::default()
        };
        let points = scan(&caster, &config, &pose, 0).unwrap();
        assert_eq!(
            points.len(),
            config.columns() * 32,
            "rays escaped from {pos:?}"
        );
        assert!(points.label.iter().all(|&l| l == 6));
        assert!(points.building.iter().all(|&b| b == 1));
    }
}

/// A random soup of triangles plus a tessellated sheet with shared edges.
fn random_scene(seed: u64, n: usize) -> Scene {
    let mut rng = Lcg(seed);
    let mut b = SyntheticBuilder::new();
    let soup = b.object("soup", ObjectKind::Vegetation);
    for _ in 0..n {
        let c = [
            rng.range(-20.0, 20.0),
            rng.range(-20.0, 20.0),
            rng.range(-5.0, 15.0),
        ];
        let s = rng.range(0.05, 4.0);
        let v = [0, 1, 2].map(|_| std::array::from_fn(|k| c[k] + s * rng.range(-1.0, 1.0)));
        b.triangle(soup, v);
    }
    let ground = b.object("ground", ObjectKind::Ground);
    b.add_terrain(ground, [-25.0, -25.0], [25.0, 25.0], 20, |x, y| {
        0.1 * x - 0.05 * y
    });
    let house = b.object("house", ObjectKind::Building);
    b.add_box(house, [2.0, 2.0, -1.0], [7.0, 9.0, 6.0], 1.0);
    b.finish()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    #[test]
    fn bvh_equals_brute_force(seed in 0u64..1_000_000, n in 1usize..600) {
        let scene = random_scene(seed, n);
        let caster = Caster::new(&scene).unwrap();
        let mut rng = Lcg(seed ^ 0xABCD);
        for i in 0..400 {
            let origin = [rng.range(-30.0, 30.0), rng.range(-30.0, 30.0), rng.range(-8.0, 20.0)];
            // Some rays aimed exactly at vertices and along grid lines.
            let dir = if i % 5 == 0 {
                let v = scene.vertices[(i * 7919) % scene.vertices.len()];
                std::array::from_fn(|k| v[k] - origin[k])
            } else if i % 5 == 1 {
                [1.0, 0.0, 0.0]
            } else {
                rng.unit()
            };
            let ray = Ray::new(origin, dir, rng.range(1.0, 80.0));
            let fast = caster.cast_ray(&ray);
            let slow = caster.cast_brute_force(&ray);
            // Both find a hit or neither; where several triangles meet the
            // ray at one point (a shared vertex) their t differ in the last bits.
            prop_assert_eq!(fast.is_some(), slow.is_some(), "ray {:?}", ray);
            if let (Some(f), Some(s)) = (fast, slow) {
                prop_assert!((f.t - s.t).abs() <= 1e-5 * s.t.max(1.0), "{:?} vs {:?}", f, s);
            }
        }
        let rays: Vec<Ray> = (0..300)
            .map(|_| Ray::new([rng.range(-30.0, 30.0), rng.range(-30.0, 30.0), 25.0], rng.unit(), 100.0))
            .collect();
        let many = caster.cast_many(&rays);
        for (r, h) in rays.iter().zip(&many) {
            prop_assert_eq!(*h, caster.cast_ray(r));
        }
    }
}

/// parry3d's mesh finds the same closest hits as the hand-written BVH on
/// the reference scene (VLP-16 revolutions from street poses): rays grazing
/// a shared edge may go either way, so at most 0.1 % may differ.
#[test]
fn parry_backend_equals_bvh_on_the_reference_scene() {
    let scene = skyground_core::scene::reference_scene(skyground_core::scene::REFERENCE_SEED);
    let bvh = Caster::with_backend(&scene, CastBackend::Bvh).unwrap();
    let parry = Caster::with_backend(&scene, CastBackend::Parry).unwrap();
    assert_eq!(parry.backend(), CastBackend::Parry);
    assert_eq!(bvh.triangle_count(), parry.triangle_count());
    let config = LidarConfig::default();
    let rays: Vec<Ray> = skyground_core::lidar::bench::street_poses(&bvh, 4)
        .iter()
        .flat_map(|p| skyground_core::lidar::spinning::revolution_rays(&config, p))
        .collect();
    let (a, b) = (bvh.cast_many(&rays), parry.cast_many(&rays));
    let hits = a.iter().flatten().count();
    assert!(hits > rays.len() / 4, "{hits} of {} rays hit", rays.len());
    let differ = a
        .iter()
        .zip(&b)
        .filter(|(x, y)| match (x, y) {
            (Some(x), Some(y)) => (x.t - y.t).abs() > 1e-4 * x.t.max(1.0) || x.object != y.object,
            (None, None) => false,
            _ => true,
        })
        .count();
    assert!(
        differ * 1000 <= rays.len(),
        "{differ} of {} rays differ",
        rays.len()
    );
}

/// A street along x at y = 0 between two rows of boxes, with a park and
/// open ground beyond.
fn street_scene() -> Scene {
    boxes_on_plane(
        300.0,
        &[
            ([-40.0, 8.0, -0.5], [-10.0, 25.0, 12.0]),
            ([-5.0, 8.0, -0.5], [30.0, 20.0, 25.0]),
            ([-30.0, -22.0, -0.5], [20.0, -9.0, 8.0]),
        ],
    )
}

#[test]
fn street_scan_stays_within_range_and_labels_what_it_hits() {
    let scene = street_scene();
    let caster = Caster::new(&scene).unwrap();
    let config = LidarConfig::default();
    let pose = Pose::new([0.0, 0.0, 1.8], 0.3);
    let points = scan(&caster, &config, &pose, 7).unwrap();
    assert!(points.len() > 10_000, "{} points", points.len());
    let n = points.len();
    for v in [
        points.range.len(),
        points.label.len(),
        points.building.len(),
        points.ring.len(),
        points.time.len(),
    ] {
        assert_eq!(v, n);
    }
    for i in 0..n {
        let p = points.xyz[i];
        let d: f32 = (0..3)
            .map(|k| (p[k] - pose.position[k]).powi(2))
            .sum::<f32>()
            .sqrt();
        assert!(
            d <= config.max_range + 1e-3 && d >= config.min_range,
            "point at {d} m"
        );
        assert!((d - points.range[i]).abs() < 1e-3);
        match points.label[i] {
            2 => {
                assert_eq!(points.building[i], 0);
                assert!(p[2].abs() < 0.1, "ground point at z {}", p[2]);
            }
            6 => {
                let b = points.building[i];
                assert!((1..=3).contains(&b));
                // The point lies on that box (within noise).
                let (lo, hi) = [
                    ([-40.0, 8.0, -0.5], [-10.0, 25.0, 12.0]),
                    ([-5.0, 8.0, -0.5], [30.0, 20.0, 25.0]),
                    ([-30.0, -22.0, -0.5], [20.0, -9.0, 8.0]),
                ][b as usize - 1];
                assert!((0..3).all(|k| p[k] >= lo[k] - 0.1 && p[k] <= hi[k] + 0.1));
            }
            l => panic!("unexpected label {l}"),
        }
        assert!(points.ring[i] < 16);
        assert!((0.0..0.1).contains(&points.time[i]));
    }
    // Both sides of the street and the ground are seen.
    for b in 1..=3 {
        assert!(points.building.contains(&b), "building {b} not seen");
    }
    assert!(points.label.contains(&2));
    // Same seed, same scan; another seed, other noise.
    assert_eq!(scan(&caster, &config, &pose, 7).unwrap(), points);
    assert_ne!(
        scan(&caster, &config, &pose, 8).unwrap().range,
        points.range
    );
}

#[test]
fn dropout_removes_about_its_share() {
    let caster = Caster::new(&street_scene()).unwrap();
    let pose = Pose::new([0.0, 0.0, 1.8], 0.0);
    let full = scan(&caster, &LidarConfig::default(), &pose, 1)
        .unwrap()
        .len() as f32;
    let config = LidarConfig {
        dropout: 0.25,
        ..LidarConfig::default()
    };
    let kept = scan(&caster, &config, &pose, 1).unwrap().len() as f32;
    assert!((kept / full - 0.75).abs() < 0.02, "{kept} of {full}");
}

#[test]
fn config_defaults_fill_missing_fields_and_bad_values_are_named() {
    let c: LidarConfig = serde_json::from_str(r#"{"beams": 32, "fov_min_deg": -30}"#).unwrap();
    assert_eq!(c.beams, 32);
    assert_eq!(c.fov_min_deg, -30.0);
    assert_eq!(c.azimuth_step_deg, 0.2);
    assert!(serde_json::from_str::<LidarConfig>(r#"{"beam": 32}"#).is_err());
    let bad = LidarConfig {
        azimuth_step_deg: 0.0,
        ..LidarConfig::default()
    };
    let caster = Caster::new(&street_scene()).unwrap();
    let err = scan(&caster, &bad, &Pose::default(), 0).unwrap_err();
    assert_eq!(err.field, "azimuth_step_deg");
    let a: AirborneConfig =
        serde_json::from_str(r#"{"pattern": "cross", "oblique_deg": 30}"#).unwrap();
    assert_eq!(a.pattern, FlightPattern::Cross);
    assert_eq!(a.oblique_deg, Some(30.0));
    assert_eq!(a.altitude_m, AirborneConfig::default().altitude_m);
}

#[test]
fn malformed_scenes_are_rejected_with_the_culprit() {
    let mut s = street_scene();
    s.triangle_object.pop();
    assert!(matches!(
        Caster::new(&s),
        Err(CasterError::Scene(
            SceneCheckError::TriangleObjectLength { .. }
        ))
    ));
    let mut s = street_scene();
    s.triangles[3][1] = 10_000;
    assert_eq!(
        Caster::new(&s).unwrap_err(),
        CasterError::Scene(SceneCheckError::VertexIndex {
            triangle: 3,
            vertex: 10_000,
            vertices: s.vertices.len()
        })
    );
    let mut s = street_scene();
    s.triangle_object[5] = 9;
    assert!(matches!(
        Caster::new(&s),
        Err(CasterError::Scene(SceneCheckError::ObjectIndex {
            triangle: 5,
            object: 9,
            ..
        }))
    ));
    // Empty scenes and degenerate triangles are fine.
    let empty = Caster::new(&Scene::default()).unwrap();
    assert!(empty.cast([0.0; 3], [0.0, 0.0, -1.0], 10.0).is_none());
    let s = Scene {
        vertices: vec![[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]],
        triangles: vec![[0, 1, 2]],
        triangle_object: vec![0],
        objects: vec![SceneObject {
            name: "line".into(),
            kind: ObjectKind::Ground,
            building: 0,
        }],
        origin: [0.0; 3],
    };
    assert_eq!(Caster::new(&s).unwrap().triangle_count(), 0);
}

/// Counts cloud points inside an axis-aligned region.
fn count_in(cloud: &skyground_core::cloud::Cloud, lo: [f32; 3], hi: [f32; 3]) -> usize {
    cloud
        .xyz
        .iter()
        .filter(|p| (0..3).all(|k| p[k] >= lo[k] && p[k] <= hi[k]))
        .count()
}

#[test]
fn airborne_roof_is_dense_walls_sparse_ground_under_the_box_empty() {
    // Off the middle strip, so its ±y walls face strips beside them.
    let (lo, hi) = ([-30.0, 40.0, -0.5], [30.0, 80.0, 20.0]);
    let scene = boxes_on_plane(120.0, &[(lo, hi)]);
    let caster = Caster::new(&scene).unwrap();
    let config = AirborneConfig {
        pulse_rate_hz: 100_000.0,
        ..AirborneConfig::default()
    };
    let cloud = airborne_scan(&caster, &config).unwrap();
    cloud.validate().unwrap();
    let labels = cloud.label.as_ref().unwrap();
    assert!(labels.iter().all(|&l| l == 2 || l == 6));

    let roof = count_in(&cloud, [-29.9, 40.1, 19.9], [29.9, 79.9, 20.1]) as f32 / (59.8 * 39.8);
    let nominal = config.nominal_density();
    assert!(
        roof > 0.6 * nominal && roof < 1.6 * nominal,
        "roof {roof} pts/m², nominal {nominal}"
    );
    // Walls: points within 5 cm of a wall plane, below the roof.
    let wall_points = cloud
        .xyz
        .iter()
        .zip(labels)
        .filter(|(p, l)| {
            **l == 6
                && p[2] < 19.5
                && ((p[0].abs() - 30.0).abs() < 0.15
                    || (p[1] - 40.0).abs() < 0.15
                    || (p[1] - 80.0).abs() < 0.15)
        })
        .count();
    let wall_area = 2.0 * (60.0 + 40.0) * 20.0;
    let wall = wall_points as f32 / wall_area;
    assert!(
        wall > 0.0 && wall < 0.5 * roof,
        "walls {wall} pts/m² vs roof {roof}"
    );
    // Nothing reaches the ground under the box.
    assert_eq!(
        count_in(
            &cloud,
            [lo[0] + 0.2, lo[1] + 0.2, -1.0],
            [hi[0] - 0.2, hi[1] - 0.2, 1.0]
        ),
        0
    );
    // Open ground far from the box is covered.
    let open = count_in(&cloud, [60.0, -20.0, -0.2], [80.0, 20.0, 0.2]) as f32 / 800.0;
    assert!(open < 1.6 * nominal, "open ground {open} pts/m²");
    assert!(open > 0.6 * nominal, "open ground {open} pts/m²");

    // Deterministic; the seed matters.
    assert_eq!(airborne_scan(&caster, &config).unwrap(), cloud);
    let other = AirborneConfig {
        seed: 99,
        ..config.clone()
    };
    assert_ne!(airborne_scan(&caster, &other).unwrap().xyz, cloud.xyz);
}

#[test]
fn airborne_oblique_cross_and_divergence_see_more_walls() {
    let (lo, hi) = ([-30.0, -20.0, -0.5], [30.0, 20.0, 20.0]);
    let scene = boxes_on_plane(120.0, &[(lo, hi)]);
    let caster = Caster::new(&scene).unwrap();
    let walls = |c: &AirborneConfig| {
        let cloud = airborne_scan(&caster, c).unwrap();
        cloud
            .xyz
            .iter()
            .filter(|p| p[2] < 19.5 && p[2] > 0.5)
            .count()
    };
    let base = AirborneConfig {
        pulse_rate_hz: 50_000.0,
        pattern: FlightPattern::AlongX,
        oblique_deg: None,
        ..AirborneConfig::default()
    };
    let nadir = walls(&base);
    let oblique = walls(&AirborneConfig {
        oblique_deg: Some(30.0),
        pattern: FlightPattern::Cross,
        ..base.clone()
    });
    assert!(oblique > 3 * nadir, "oblique {oblique} vs nadir {nadir}");
    let wide = AirborneConfig {
        beam_divergence_mrad: Some(3.0),
        ..base.clone()
    };
    let cloud = airborne_scan(&caster, &wide).unwrap();
    assert!(!cloud.is_empty());
    let strongest = AirborneConfig {
        return_mode: skyground_core::lidar::ReturnMode::Strongest,
        ..wide
    };
    assert!(!airborne_scan(&caster, &strongest).unwrap().is_empty());
}

/// Completeness of building points of an airborne scan of the reference scene.
fn reference_completeness(
    config: &AirborneConfig,
) -> (usize, skyground_core::metrics::CompletenessReport) {
    use skyground_core::metrics::{
        DEFAULT_SPACING, DEFAULT_TAU, completeness, sample_building_surfaces,
    };
    use skyground_core::scene::{REFERENCE_SEED, reference_scene};
    let seed = std::env::var("SCENE_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(REFERENCE_SEED);
    let scene = reference_scene(seed);
    let caster = Caster::new(&scene).unwrap();
    let cloud = airborne_scan(&caster, config).unwrap();
    let labels = cloud.label.clone().unwrap_or_default();
    let building: Vec<[f32; 3]> = cloud
        .xyz
        .iter()
        .zip(&labels)
        .filter(|(_, l)| **l == 6)
        .map(|(p, _)| *p)
        .collect();
    let gt = sample_building_surfaces(&scene, DEFAULT_SPACING);
    (cloud.len(), completeness(&gt, &building, DEFAULT_TAU))
}

#[test]
fn airborne_defaults_give_the_papers_completeness_on_the_reference_scene() {
    let (_, r) = reference_completeness(&AirborneConfig::default());
    let overall = r.overall.ratio.unwrap_or(0.0);
    assert!((0.75..=0.92).contains(&overall), "completeness {overall}");
    assert!(r.roofs.ratio.unwrap_or(0.0) > 0.95);
    assert!(
        r.walls.ratio.unwrap_or(1.0) < 0.9,
        "walls should stay incomplete"
    );
}

#[test]
#[ignore = "prints a sweep of airborne settings on the reference scene"]
fn airborne_completeness_sweep() {
    let base = AirborneConfig::default();
    let mut configs = vec![("default".to_owned(), base.clone())];
    let sweep: Vec<(FlightPattern, f32, f32, Option<f32>, f32, f32)> = std::env::var("SWEEP")
        .ok()
        .map(|s| {
            s.split(';')
                .filter_map(|item| {
                    let f: Vec<&str> = item.split(',').collect();
                    let pattern = match *f.first()? {
                        "x" => FlightPattern::AlongX,
                        "y" => FlightPattern::AlongY,
                        _ => FlightPattern::Cross,
                    };
                    let num = |i: usize| f.get(i).and_then(|v| v.parse::<f32>().ok());
                    Some((
                        pattern,
                        num(1)?,
                        num(2)?,
                        num(3).filter(|o| *o != 0.0),
                        num(4)?,
                        num(5).unwrap_or(300_000.0),
                    ))
                })
                .collect()
        })
        .unwrap_or_default();
    for (pattern, overlap, angle, oblique, altitude, prf) in sweep {
        configs.push((
            format!("{pattern:?} ov {overlap} ±{angle}° obl {oblique:?} alt {altitude} prf {prf}"),
            AirborneConfig {
                pattern,
                strip_overlap: overlap,
                scan_angle_deg: angle,
                oblique_deg: oblique,
                altitude_m: altitude,
                pulse_rate_hz: prf,
                ..base.clone()
            },
        ));
    }
    for (name, c) in configs {
        let t = std::time::Instant::now();
        let (n, r) = reference_completeness(&c);
        println!(
            "{name:58} {n:>9} pts {:5.1} pts/m² nominal: overall {:.3} walls {:.3} roofs {:.3} gap {:.3} m ({:.1} s)",
            c.nominal_density(),
            r.overall.ratio.unwrap_or(0.0),
            r.walls.ratio.unwrap_or(0.0),
            r.roofs.ratio.unwrap_or(0.0),
            r.mean_gt_distance.unwrap_or(f64::NAN),
            t.elapsed().as_secs_f64()
        );
    }
}

#[test]
fn scans_do_not_depend_on_the_thread_count() {
    let scene = dense_scene(30_000, 4);
    let caster = Caster::new(&scene).unwrap();
    let pose = skyground_core::lidar::bench::street_poses(&caster, 1)[0];
    let config = LidarConfig {
        dropout: 0.1,
        ..LidarConfig::default()
    };
    let survey = AirborneConfig {
        pulse_rate_hz: 20_000.0,
        dropout: 0.05,
        ..AirborneConfig::default()
    };
    let on_threads = |n: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap();
        pool.install(|| {
            (
                scan(&caster, &config, &pose, 5).unwrap(),
                airborne_scan(&caster, &survey).unwrap(),
            )
        })
    };
    let (s1, a1) = on_threads(1);
    let (s3, a3) = on_threads(3);
    assert_eq!(s1, s3);
    assert_eq!(a1, a3);
}
