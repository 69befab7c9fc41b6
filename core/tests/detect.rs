//! Missing-region detection end to end (DESIGN.md step 3): the reference
//! scene's simulated aerial prior scored against ground-truth wall cells,
//! the Zurich CityJSON scene, one real building (City3D 001, with its
//! footprint), and bad input reported rather than crashing.
//!
//! Real files come from `SKYGROUND_REAL_DATA` or `../shared/data/real`;
//! absent → `SKIPPED: ...` and the test passes.

use std::time::Instant;

use geo::{Area, Contains, Coord, LineString, MultiPolygon, Polygon};
use skyground_core::cloud::read_cloud;
use skyground_core::io::load_scene;
use skyground_core::metrics::sample_building_surfaces;
use skyground_core::missing::{
    BuildingDetection, DetectParams, Detection, GroundGrid, SkipReason, Strategy, detect_all,
    detect_all_on, detect_building, evaluate,
};
use skyground_core::scene::Scene;

mod common;
use common::real_file;
#[path = "planning_scene/mod.rs"]
mod planning_scene;

/// Building points, their ids, all points, and the terrain.
type Prior = (Vec<[f32; 3]>, Vec<u32>, Vec<[f32; 3]>, GroundGrid);

/// Building points and ids of a scene's airborne prior (ground-truth labels).
fn prior_buildings(scene: &Scene) -> Prior {
    let p = planning_scene::prior(scene);
    let terrain = p.terrain();
    (p.buildings, p.ids, p.xyz, terrain)
}

/// The header of [`row`]'s table.
const HEADER: &str = "building points slices structures boundary missing R_missing strategy";

/// One building's figures as a row under [`HEADER`].
fn row(b: &BuildingDetection) -> String {
    match &b.skipped {
        Some(r) => format!("{:>8} {:>6} skipped: {r}", b.building, b.points),
        None => format!(
            "{:>8} {:>6} {:>6} {:>10} {:>8} {:>7} {:>9.3} {:?}",
            b.building,
            b.points,
            b.slices.len(),
            b.structures.len(),
            b.boundary.len(),
            b.missing.len(),
            b.r_missing,
            b.strategy
        ),
    }
}

fn print_detection(det: &Detection) {
    println!("{HEADER}");
    for b in &det.buildings {
        println!("{}", row(b));
    }
}

#[test]
fn reference_prior_recall_and_precision() {
    let scene = load_scene("reference").unwrap();
    let (xyz, ids, all, terrain) = prior_buildings(&scene);
    // Tuning aid: SKYGROUND_DETECT_PARAMS='{"min_coverage": 0.6}' overrides defaults.
    let params: DetectParams = std::env::var("SKYGROUND_DETECT_PARAMS").map_or_else(
        |_| DetectParams::default(),
        |j| serde_json::from_str(&j).unwrap(),
    );
    let t = Instant::now();
    let det = detect_all_on(&xyz, &ids, None, Some(&terrain), &params).unwrap();
    println!(
        "detection: {} building points in {:.2?}",
        xyz.len(),
        t.elapsed()
    );
    print_detection(&det);
    let gt = sample_building_surfaces(&scene, 0.25);
    let score = evaluate(&gt, &all, &det.missing_points());
    println!("building cells truly_missing found recall missing_pts correct precision");
    for s in &score.per_building {
        println!(
            "{:>8} {:>5} {:>13} {:>5} {:>6.3} {:>11} {:>7} {:>9.3}",
            s.building,
            s.walls.cells,
            s.walls.truly_missing,
            s.walls.found,
            s.walls.recall,
            s.walls.missing_points,
            s.walls.correct_points,
            s.walls.precision
        );
    }
    println!(
        "TOTAL cells {} truly missing {} recall {:.3} precision {:.3} ({} missing points, R_missing {:.3})",
        score.walls.cells,
        score.walls.truly_missing,
        score.walls.recall,
        score.walls.precision,
        score.walls.missing_points,
        det.r_missing()
    );
    println!(
        "undersides (apart): cells {} truly missing {} found {}",
        score.underside_cells, score.underside_truly_missing, score.underside_found
    );
    assert!(
        score.walls.truly_missing > 100,
        "the prior should leave walls missing"
    );
    assert!(
        score.walls.recall >= 0.90,
        "recall {:.3}",
        score.walls.recall
    );
    // Measured 0.832, recall 0.936 since the prior's crowns are porous
    // (multiple returns): pulses now reach some walls behind trees, so
    // fewer cells are truly missing (2229) and the same few false cells on
    // fully seen buildings weigh more. 0.857 / 0.940 with opaque crowns;
    // 0.790 / 0.939 before open ground floors were told from missing walls.
    assert!(
        score.walls.precision >= 0.82,
        "precision {:.3}",
        score.walls.precision
    );
    // Every tested building gets a strategy consistent with θ.
    for b in det.buildings.iter().filter(|b| b.skipped.is_none()) {
        let want = if b.r_missing < params.theta {
            Strategy::PointBased
        } else {
            Strategy::RegionBased
        };
        assert_eq!(b.strategy, want);
        assert_eq!(
            b.missing.len(),
            b.boundary.iter().filter(|p| !p.collected).count()
        );
    }
}

#[test]
#[ignore = "5 min in the dev profile (airborne scan + GT of the whole city block): run with --ignored"]
fn zurich_cityjson_prior() {
    let Some(path) = real_file("zurich_subset_lod2.json") else {
        return;
    };
    let scene = load_scene(path.to_str().unwrap()).unwrap();
    let (xyz, ids, all, terrain) = prior_buildings(&scene);
    let det = detect_all_on(&xyz, &ids, None, Some(&terrain), &DetectParams::default()).unwrap();
    print_detection(&det);
    let gt = sample_building_surfaces(&scene, 0.25);
    let score = evaluate(&gt, &all, &det.missing_points());
    println!(
        "ZURICH cells {} truly missing {} recall {:.3} precision {:.3} ({} missing points)",
        score.walls.cells,
        score.walls.truly_missing,
        score.walls.recall,
        score.walls.precision,
        score.walls.missing_points
    );
    assert!(det.buildings.iter().filter(|b| b.skipped.is_none()).count() > 10);
    // A real city block is harder than the reference; require the method to
    // still find most truly missing wall. Measured recall 0.605, precision
    // 0.526 (0.556 / 0.485 while a wall seen lower down could still be
    // taken for an open ground floor).
    assert!(
        score.walls.recall >= 0.6,
        "recall {:.3}",
        score.walls.recall
    );
}

/// The footprint OBJ's `v` and `f` lines as one polygon (z dropped).
fn obj_polygon(text: &str) -> Polygon<f64> {
    let verts: Vec<Coord<f64>> = text
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|t| t.parse().unwrap()).collect();
            Coord { x: v[0], y: v[1] }
        })
        .collect();
    let face = text.lines().find_map(|l| l.strip_prefix("f ")).unwrap();
    let ring: Vec<Coord<f64>> = face
        .split_whitespace()
        .map(|t| verts[t.split('/').next().unwrap().parse::<usize>().unwrap() - 1])
        .collect();
    Polygon::new(LineString::new(ring), vec![])
}

#[test]
fn city3d_building_with_footprint() {
    let Some(path) = real_file("city3d_001.ply") else {
        return;
    };
    let cloud = read_cloud(&path).unwrap();
    let fp_text = std::fs::read_to_string(real_file("city3d_001_footprint.obj").unwrap()).unwrap();
    let o = cloud.origin;
    let mut fp = obj_polygon(&fp_text);
    fp.exterior_mut(|ring| {
        ring.0.iter_mut().for_each(|c| {
            c.x -= o[0];
            c.y -= o[1];
        })
    });
    let fp = MultiPolygon(vec![fp]);
    // The file holds the building's surroundings too: individualize it with
    // its footprint as step 2 does (point in polygon), ground at the
    // footprint's height.
    let ground = fp_text
        .lines()
        .find_map(|l| l.strip_prefix("v "))
        .and_then(|l| l.split_whitespace().nth(2))
        .map(|z| (z.parse::<f64>().unwrap() - o[2]) as f32);
    let inside: Vec<[f32; 3]> = cloud
        .xyz
        .iter()
        .filter(|p| fp.contains(&geo::Point::new(p[0] as f64, p[1] as f64)))
        .copied()
        .collect();
    println!(
        "CITY3D {} of {} points inside the footprint",
        inside.len(),
        cloud.xyz.len()
    );
    let params = DetectParams::default();
    let with = detect_building(1, &inside, Some(&fp), ground, &params).unwrap();
    let without = detect_building(1, &inside, None, ground, &params).unwrap();
    for (name, d) in [("footprint", &with), ("derived", &without)] {
        assert!(d.skipped.is_none(), "{:?}", d.skipped);
        println!(
            "CITY3D {name}: ground {:.1} top {:.1}\n{HEADER}\n{}",
            d.ground_z,
            d.top_z,
            row(d)
        );
        for s in &d.slices {
            println!(
                "  slice z {:6.1}: {:6} points, {:4} boundary, {:4} missing",
                s.height, s.points, s.boundary, s.missing
            );
        }
        assert!(d.boundary.len() > 100);
    }
    // The footprint is C_building; the derived outline should agree with it.
    let (a, b) = (fp.unsigned_area(), without.global_contour.unsigned_area());
    println!("CITY3D footprint area {a:.0} m², derived outline {b:.0} m²");
    assert!((a - b).abs() / a < 0.15, "{a} vs {b}");
}

#[test]
fn small_and_degenerate_buildings_are_reported_not_fatal() {
    let mut xyz = Vec::new();
    let mut ids = Vec::new();
    // building 1: a 10 × 10 × 6 m box roof + walls; building 2: 20 points
    for i in 0..40 {
        for j in 0..40 {
            xyz.push([i as f32 * 0.25, j as f32 * 0.25, 6.0]);
            ids.push(1);
        }
        for z in 0..24 {
            xyz.push([i as f32 * 0.25, 0.0, z as f32 * 0.25]);
            ids.push(1);
        }
    }
    for k in 0..20 {
        xyz.push([50.0 + k as f32 * 0.1, 50.0, 3.0]);
        ids.push(2);
    }
    let line = MultiPolygon(vec![Polygon::new(
        LineString::from(vec![(0.0, 0.0), (10.0, 0.0), (20.0, 0.0), (0.0, 0.0)]),
        vec![],
    )]);
    let fps = vec![(1, line), (3, MultiPolygon(vec![]))];
    let det = detect_all(&xyz, &ids, Some(&fps), &DetectParams::default()).unwrap();
    assert_eq!(det.buildings.len(), 3);
    assert!(matches!(
        det.buildings[0].skipped,
        Some(SkipReason::DegenerateFootprint { .. })
    ));
    assert!(matches!(
        det.buildings[1].skipped,
        Some(SkipReason::TooFewPoints { points: 20, .. })
    ));
    assert!(matches!(
        det.buildings[2].skipped,
        Some(SkipReason::TooFewPoints { points: 0, .. })
    ));
    // without footprints building 1 is analysed: its one observed wall (y = 0) is
    // collected, the three others are missing.
    let det = detect_all(&xyz, &ids, None, &DetectParams::default()).unwrap();
    let b = &det.buildings[0];
    assert!(b.skipped.is_none());
    let south: Vec<_> = b
        .boundary
        .iter()
        .filter(|p| p.xyz[1] < 0.5 && (1.0..9.0).contains(&p.xyz[0]))
        .collect();
    assert!(!south.is_empty() && south.iter().all(|p| p.collected));
    assert!(b.r_missing > 0.6 && b.r_missing < 0.85, "{}", b.r_missing);
    // bad params and mismatched ids are errors
    assert!(detect_all(&xyz, &ids[1..], None, &DetectParams::default()).is_err());
    let bad = DetectParams {
        delta: skyground_core::density::Auto::Value(-1.0),
        ..DetectParams::default()
    };
    assert!(detect_all(&xyz, &ids, None, &bad).is_err());
}

#[test]
#[ignore]
fn diagnose_reference() {
    use skyground_core::metrics::{SurfaceKind, nearest_distances};
    let scene = load_scene("reference").unwrap();
    let (xyz, ids, all, terrain) = prior_buildings(&scene);
    let det = detect_all_on(&xyz, &ids, None, Some(&terrain), &DetectParams::default()).unwrap();
    let gt = sample_building_surfaces(&scene, 0.25);
    let walls: Vec<usize> = (0..gt.len())
        .filter(|&i| gt.kind[i] == SurfaceKind::Wall)
        .collect();
    let wxyz: Vec<[f32; 3]> = walls.iter().map(|&i| gt.xyz[i]).collect();
    let cov = nearest_distances(&wxyz, &all);
    let miss = det.missing_xyz();
    let to_miss = nearest_distances(&wxyz, &miss);
    let bxyz: Vec<[f32; 3]> = det
        .buildings
        .iter()
        .flat_map(|b| b.boundary.iter().map(|p| p.xyz))
        .collect();
    let to_bound = nearest_distances(&wxyz, &bxyz);
    // uncovered wall samples not near a missing point: by building, height above ground, distance to any boundary point
    let mut hist = std::collections::BTreeMap::new();
    for (k, &i) in walls.iter().enumerate() {
        if cov[k] > 0.25 && to_miss[k] > 1.0 {
            let b = gt.building[i];
            let g = det
                .buildings
                .iter()
                .find(|d| d.building == b)
                .map_or(0.0, |d| d.ground_z);
            let zb = ((gt.xyz[i][2] - g) / 2.0).floor() as i32 * 2;
            let db = (to_bound[k].min(9.0)).floor() as i32;
            *hist.entry((b, zb, db)).or_insert(0) += 1;
        }
    }
    for ((b, z, d), n) in hist.iter().filter(|(_, n)| **n > 100) {
        println!("unfound b{b} z{z} dist_to_boundary {d}: {n}");
    }
    let to_wall_uncov: Vec<[f32; 3]> = walls
        .iter()
        .enumerate()
        .filter(|(k, _)| cov[*k] > 0.25)
        .map(|(_, &i)| gt.xyz[i])
        .collect();
    let to_any = nearest_distances(&miss, &wxyz);
    let to_unc = nearest_distances(&miss, &to_wall_uncov);
    let mut fh = std::collections::BTreeMap::new();
    for b in &det.buildings {
        for (k, m) in b.missing.iter().enumerate() {
            let _ = k;
            let idx = miss.iter().position(|p| p == &m.xyz).unwrap();
            if to_unc[idx] > 1.0 {
                let zb = ((m.xyz[2] - b.ground_z) / 2.0).floor() as i32 * 2;
                let da = (to_any[idx] * 2.0).floor().min(10.0) as i32;
                *fh.entry((b.building, zb, da)).or_insert(0) += 1;
            }
        }
    }
    for ((b, z, d), n) in fh.iter().filter(|(_, n)| **n > 10) {
        println!("false b{b} z{z} dist_to_wall/2 {d}: {n}");
    }
}
