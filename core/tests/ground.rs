//! Cloth Simulation Filter against ground truth: the producer's ground
//! class of Autzen, the simulated reference city (every point's class and
//! the true terrain are known), the CSF authors' sample, and small
//! hand-built clouds. Real files come from `../shared/data/real`
//! (`SKYGROUND_REAL_DATA` overrides; absent → `SKIPPED: ...`, test passes).

use std::collections::HashMap;

use skyground_core::cloud::{Cloud, class, read_cloud};
use skyground_core::density::Auto;
use skyground_core::ground::{CsfError, CsfParams, GroundSplit, csf};
use skyground_core::lidar::Ray;
use skyground_core::lidar::{AirborneConfig, Caster, airborne_scan};
use skyground_core::params::ParamError;
use skyground_core::scene::{ObjectKind, REFERENCE_SEED, Scene, reference_scene};

mod common;
use common::real_file;

fn real(name: &str) -> Option<Cloud> {
    let path = real_file(name)?;
    Some(read_cloud(&path).unwrap_or_else(|e| panic!("{name}: {e}")))
}

/// Agreement of `split` with the truth (`true` = ground), ISPRS style.
struct Errors {
    total: f64,
    type1: f64,
    type2: f64,
    kappa: f64,
}

fn errors(split: &GroundSplit, truth: &[bool]) -> Errors {
    let (mut gg, mut gn, mut ng, mut nn) = (0.0, 0.0, 0.0, 0.0);
    for (&t, &p) in truth.iter().zip(&split.is_ground) {
        match (t, p) {
            (true, true) => gg += 1.0,
            (true, false) => gn += 1.0,
            (false, true) => ng += 1.0,
            (false, false) => nn += 1.0,
        }
    }
    let n: f64 = gg + gn + ng + nn;
    let observed = (gg + nn) / n;
    let chance = ((gg + gn) * (gg + ng) + (ng + nn) * (gn + nn)) / (n * n);
    Errors {
        total: (gn + ng) / n,
        type1: gn / (gg + gn),
        type2: ng / (ng + nn),
        kappa: (observed - chance) / (1.0 - chance),
    }
}

fn print_errors(name: &str, e: &Errors, split: &GroundSplit) {
    println!(
        "{name}: total error {:.2} %, type I {:.2} %, type II {:.2} %, kappa {:.3}, {} steps",
        100.0 * e.total,
        100.0 * e.type1,
        100.0 * e.type2,
        e.kappa,
        split.iterations_run
    );
}

/// Height of the scene's Ground objects below `(x, y)`, by a ray cast down
/// onto a copy of the scene that holds only them.
struct TrueGround(Caster);

impl TrueGround {
    fn new(scene: &Scene) -> Self {
        let keep: Vec<usize> = (0..scene.triangles.len())
            .filter(|&t| {
                scene.objects[scene.triangle_object[t] as usize].kind == ObjectKind::Ground
            })
            .collect();
        let ground = Scene {
            triangles: keep.iter().map(|&t| scene.triangles[t]).collect(),
            triangle_object: keep.iter().map(|&t| scene.triangle_object[t]).collect(),
            ..scene.clone()
        };
        Self(Caster::new(&ground).unwrap())
    }

    fn at(&self, x: f32, y: f32) -> Option<f32> {
        let hit = self
            .0
            .cast_ray(&Ray::new([x, y, 1000.0], [0.0, 0.0, -1.0], 5000.0))?;
        Some(1000.0 - hit.t)
    }
}

fn mean_p95(mut v: Vec<f32>) -> (f32, f32) {
    v.sort_by(f32::total_cmp);
    let mean = v.iter().sum::<f32>() / v.len() as f32;
    (mean, v[v.len() * 95 / 100])
}

/// Autzen's producer labelled many ground-level points 1, not 2 (all its
/// ground is last return; ~60 % of its class-1 points lie within one unit
/// of the class-2 surface of their 10-unit cell), so no height-based
/// filter reaches a low total error against it: the figures are printed,
/// and what is asserted is that CSF finds the producer's ground (type I)
/// and rejects the class-1 points that stand clear of it (type II on
/// those). Units are the file's: US feet.
#[test]
fn autzen_matches_producer_ground_class() {
    let Some(cloud) = real("autzen_trim.las") else {
        return;
    };
    let labels = cloud.label.as_ref().unwrap();
    let truth: Vec<bool> = labels.iter().map(|&c| c == class::GROUND).collect();
    // A 2-unit (2 ft ≈ 0.6 m) cloth: Autzen's producer ground follows the
    // terrain closely; the metre defaults (4 m) bridge too much of it.
    let params = CsfParams {
        cloth_resolution: Auto::Value(2.0),
        ..CsfParams::default()
    };
    let split = csf(&cloud.xyz, &params).unwrap();
    let e = errors(&split, &truth);
    print_errors("autzen_trim.las (all points)", &e, &split);
    assert!(e.type1 <= 0.05, "type I {:.2} %", 100.0 * e.type1);

    // The producer's ground surface: mean class-2 height per 10-unit cell.
    let cell = 10.0f32;
    let key = |p: &[f32; 3]| ((p[0] / cell) as i32, (p[1] / cell) as i32);
    let mut surface: HashMap<(i32, i32), (f32, f32)> = HashMap::new();
    for (p, _) in cloud.xyz.iter().zip(&truth).filter(|(_, t)| **t) {
        let e = surface.entry(key(p)).or_default();
        *e = (e.0 + p[2], e.1 + 1.0);
    }
    let lift = |p: &[f32; 3]| surface.get(&key(p)).map(|&(s, n)| p[2] - s / n);
    let (mut level, mut clear, mut clear_as_ground) = (0, 0, 0);
    for (i, p) in cloud.xyz.iter().enumerate().filter(|&(i, _)| !truth[i]) {
        match lift(p) {
            Some(h) if h.abs() < 1.0 => level += 1,
            Some(h) if h > 2.0 => {
                clear += 1;
                clear_as_ground += usize::from(split.is_ground[i]);
            }
            _ => {}
        }
    }
    let clear_type2 = clear_as_ground as f64 / clear as f64;
    println!(
        "autzen_trim.las: {level} of {} class-1 points lie within 1 ft of the producer's ground; \
         {clear} stand > 2 ft above it, of which {:.2} % called ground",
        truth.iter().filter(|t| !**t).count(),
        100.0 * clear_type2
    );
    assert!(
        clear_type2 <= 0.05,
        "type II on clear points {:.2} %",
        100.0 * clear_type2
    );
}

#[test]
fn reference_city_ground_and_terrain_under_buildings() {
    let scene = reference_scene(REFERENCE_SEED);
    let caster = Caster::new(&scene).unwrap();
    let cloud = airborne_scan(&caster, &AirborneConfig::default()).unwrap();
    let labels = cloud.label.as_ref().unwrap();
    let truth: Vec<bool> = labels.iter().map(|&c| c == class::GROUND).collect();
    let split = csf(&cloud.xyz, &CsfParams::default()).unwrap();
    let e = errors(&split, &truth);
    print_errors("reference aerial prior", &e, &split);
    assert!(e.total <= 0.02, "total error {:.2} %", 100.0 * e.total);

    let truth_z = TrueGround::new(&scene);
    let (lo, hi) = cloud.bounds().unwrap();
    let mut everywhere = Vec::new();
    let mut x = lo[0];
    while x <= hi[0] {
        let mut y = lo[1];
        while y <= hi[1] {
            if let Some(z) = truth_z.at(x, y) {
                everywhere.push((split.dtm.height_at(x, y) - z).abs());
            }
            y += 1.0;
        }
        x += 1.0;
    }
    let under_buildings: Vec<f32> = cloud
        .xyz
        .iter()
        .zip(labels)
        .filter(|(_, c)| **c == class::BUILDING)
        .step_by(20)
        .filter_map(|(p, _)| {
            Some((split.dtm.height_at(p[0], p[1]) - truth_z.at(p[0], p[1])?).abs())
        })
        .collect();
    let (m_all, p_all) = mean_p95(everywhere);
    let (m_b, p_b) = mean_p95(under_buildings);
    println!(
        "reference DTM |DTM - truth|: 1 m grid mean {m_all:.3} m, p95 {p_all:.3} m; \
         under building points mean {m_b:.3} m, p95 {p_b:.3} m"
    );
    assert!(
        p_all <= 0.5 && p_b <= 0.5,
        "DTM error p95 {p_all} / {p_b} m"
    );
    let hag_ok = split
        .hag
        .iter()
        .zip(&cloud.xyz)
        .filter(|(_, p)| truth_z.at(p[0], p[1]).is_some())
        .step_by(50)
        .all(|(h, p)| (h - (p[2] - split.dtm.height_at(p[0], p[1]))).abs() < 1e-3);
    assert!(hag_ok, "hag is not z minus the DTM");
}

#[test]
fn csf_sample_ground_share_is_plausible() {
    let Some(cloud) = real("csf_sample.ply") else {
        return;
    };
    let split = csf(&cloud.xyz, &CsfParams::default()).unwrap();
    let share = split.is_ground.iter().filter(|g| **g).count() as f64 / cloud.len() as f64;
    println!(
        "csf_sample.ply: {:.1} % ground, {} steps",
        100.0 * share,
        split.iterations_run
    );
    assert!((0.15..=0.85).contains(&share), "ground share {share}");
}

fn plane(n: usize, spacing: f32, z: impl Fn(f32, f32) -> f32) -> Vec<[f32; 3]> {
    let mut pts = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (x, y) = (i as f32 * spacing, j as f32 * spacing);
            pts.push([x, y, z(x, y)]);
        }
    }
    pts
}

#[test]
fn bad_input_is_an_error() {
    let p = CsfParams::default();
    assert_eq!(csf(&[], &p), Err(CsfError::Empty));
    assert!(matches!(
        csf(&[[f32::NAN, 0.0, 0.0], [0.0, f32::INFINITY, 1.0]], &p),
        Err(CsfError::NoFinitePoints { count: 2 })
    ));
    let bad = CsfParams {
        class_threshold: Auto::Value(-1.0),
        ..CsfParams::default()
    };
    assert!(matches!(
        csf(&[[0.0, 0.0, 0.0]], &bad),
        Err(CsfError::Param(ParamError {
            field: "class_threshold",
            ..
        }))
    ));
}

#[test]
fn sloped_plane_is_all_ground_and_nan_points_are_skipped() {
    let mut pts = plane(100, 0.5, |x, y| 0.05 * x + 0.02 * y + 7.0);
    pts.push([10.0, f32::NAN, 3.0]);
    let n = pts.len() - 1;
    // A coarser cloth spans more of the slope between the points it rests
    // on, so it fits the plane less closely; both stay far under the 0.5 m
    // class threshold.
    for (cloth, tolerance) in [(2.0, 0.05), (4.0, 0.15)] {
        let params = CsfParams {
            cloth_resolution: Auto::Value(cloth),
            ..CsfParams::default()
        };
        let split = csf(&pts, &params).unwrap();
        assert!(split.is_ground[..n].iter().all(|g| *g));
        let worst = split.hag[..n].iter().fold(0.0f32, |m, h| m.max(h.abs()));
        assert!(
            worst < tolerance,
            "cloth {cloth} m: largest |height above ground| {worst:.3} m"
        );
        assert!(!split.is_ground[n] && split.hag[n].is_nan());
        let mid = split.dtm.height_at(20.0, 20.0) - (1.0 + 0.4 + 7.0);
        assert!(
            mid.abs() < tolerance,
            "cloth {cloth} m: DTM off by {mid:.3} m"
        );
    }
}

#[test]
fn box_roof_on_a_plane_is_not_ground() {
    let mut pts = plane(120, 0.5, |_, _| 0.0);
    let inside = |p: &[f32; 3]| (20.0..40.0).contains(&p[0]) && (20.0..40.0).contains(&p[1]);
    for p in &mut pts {
        if inside(p) {
            p[2] = 12.0;
        }
    }
    let split = csf(&pts, &CsfParams::default()).unwrap();
    for (p, (&g, &h)) in pts.iter().zip(split.is_ground.iter().zip(&split.hag)) {
        if inside(p) {
            assert!(
                !g && (h - 12.0).abs() < 0.2,
                "roof point {p:?} ground {g} hag {h}"
            );
        } else {
            assert!(g, "plane point {p:?} not ground");
        }
    }
}

/// Producer building points the filter took for ground.
fn roof_as_ground(labels: &[u8], split: &GroundSplit) -> usize {
    labels
        .iter()
        .zip(&split.is_ground)
        .filter(|(l, g)| **l == class::BUILDING && **g)
        .count()
}

/// Where a roof runs to the survey's edge the cloth rests on it. The raised
/// ground check takes it out: sample_c.las's east edge (24 m up) and AHN3
/// Delft 1's south-west corner (2.8 m up), the two cases it was designed
/// on, losing no producer ground point.
#[test]
fn a_roof_where_the_survey_ends_is_not_ground() {
    let off = CsfParams {
        raised_step_m: 0.0,
        ..CsfParams::default()
    };
    for (name, roof_points) in [("sample_c.las", 500), ("ahn3_delft_1.laz", 500)] {
        let Some(cloud) = real(name) else {
            return;
        };
        let labels = cloud.label.as_deref().unwrap_or_default();
        let truth: Vec<bool> = labels.iter().map(|&c| c == class::GROUND).collect();
        let before = csf(&cloud.xyz, &off).unwrap();
        let after = csf(&cloud.xyz, &CsfParams::default()).unwrap();
        let (b, a) = (
            roof_as_ground(labels, &before),
            roof_as_ground(labels, &after),
        );
        println!(
            "{name}: {} raised piece(s), {} points; roof points taken for ground {b} → {a}",
            after.raised.pieces, after.raised.points
        );
        assert_eq!(before.raised.pieces, 0);
        assert!(after.raised.pieces >= 1, "{name}: nothing raised");
        assert!(a + roof_points <= b, "{name}: roof as ground {b} → {a}");
        let lost = truth
            .iter()
            .zip(before.is_ground.iter().zip(&after.is_ground))
            .filter(|(t, (was, is))| **t && **was && !**is)
            .count();
        assert_eq!(lost, 0, "{name}: producer ground points lost");
        // The terrain under the piece now comes from the street's side: the
        // roof points taken out stand clear of it (sample_c ~23 m; Delft's
        // 2.8 m roof 1.7 m, its terrain filled from cells beside the street).
        let (mut out, mut up) = (0usize, 0usize);
        for i in (0..labels.len()).filter(|&i| before.is_ground[i] && !after.is_ground[i]) {
            out += 1;
            up += usize::from(after.hag[i] > 1.0);
        }
        assert!(up * 10 >= out * 9, "{name}: {up} of {out} stand 1 m up");
    }
}

/// The check leaves the other real surveys alone: hills (St Barth), a
/// river bank the cloth misses (Autzen), forests on slopes, dense and
/// sparse city tiles, a snippet in feet.
#[test]
fn raised_ground_takes_nothing_from_surveys_without_a_cut_roof() {
    for name in [
        "ign_stbarth_100x100m.laz",
        "ign_montpellier_150x100m.laz",
        "ahn3_delft_2.laz",
        "autzen_trim.las",
        "lasr_bcts_forest_1.laz",
        "lidr_mixedconifer.laz",
        "laspy_nebraska_ftus.las",
    ] {
        let Some(cloud) = real(name) else {
            return;
        };
        let split = csf(&cloud.xyz, &CsfParams::default()).unwrap();
        assert_eq!((split.raised.pieces, split.raised.points), (0, 0), "{name}");
    }
}
