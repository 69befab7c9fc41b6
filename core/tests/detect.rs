//! Missing-region detection end to end (DESIGN.md step 3): the reference
//! scene's simulated aerial prior scored against ground-truth wall cells,
//! the Zurich CityJSON scene, one real building (City3D 001, with its
//! footprint), and bad input reported rather than crashing.
//!
//! Real files come from `SKYGROUND_REAL_DATA` or `../shared/data/real`;
//! absent → `SKIPPED: ...` and the test passes.

use std::path::PathBuf;
use std::time::Instant;

use geo::{Coord, LineString, MultiPolygon, Polygon};
use skyground_core::cloud::{class, read_cloud};
use skyground_core::lidar::{AirborneConfig, Caster, airborne_scan};
use skyground_core::metrics::sample_building_surfaces;
use skyground_core::missing::{
    DetectParams, Detection, SkipReason, Strategy, detect_all, detect_building, evaluate,
};
use skyground_core::scene::{Scene, load_scene};

fn real_file(name: &str) -> Option<PathBuf> {
    let dir = std::env::var_os("SKYGROUND_REAL_DATA").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/real"),
        PathBuf::from,
    );
    if !dir.is_dir() {
        eprintln!("SKIPPED: ../shared/data/real not found (looked in {})", dir.display());
        return None;
    }
    Some(dir.join(name))
}

/// Building points and ids of a scene's airborne prior (ground-truth labels).
fn prior_buildings(scene: &Scene) -> (Vec<[f32; 3]>, Vec<u32>, Vec<[f32; 3]>) {
    let caster = Caster::new(scene).unwrap();
    let cloud = airborne_scan(&caster, &AirborneConfig::default()).unwrap();
    let labels = cloud.label.as_ref().unwrap();
    let ids = cloud.building.as_ref().unwrap();
    let (mut xyz, mut bid) = (Vec::new(), Vec::new());
    for k in 0..cloud.xyz.len() {
        if labels[k] == class::BUILDING && ids[k] > 0 {
            xyz.push(cloud.xyz[k]);
            bid.push(ids[k]);
        }
    }
    (xyz, bid, cloud.xyz)
}

fn print_detection(det: &Detection) {
    println!("building points slices structures boundary missing R_missing strategy");
    for b in &det.buildings {
        match &b.skipped {
            Some(r) => println!("{:>8} {:>6} skipped: {r}", b.building, b.points),
            None => println!(
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
}

#[test]
fn reference_prior_recall_and_precision() {
    let scene = load_scene("reference").unwrap();
    let (xyz, ids, all) = prior_buildings(&scene);
    let params = DetectParams::default();
    let t = Instant::now();
    let det = detect_all(&xyz, &ids, None, &params).unwrap();
    println!("detection: {} building points in {:.2?}", xyz.len(), t.elapsed());
    print_detection(&det);
    let gt = sample_building_surfaces(&scene, 0.25);
    let score = evaluate(&gt, &all, &det.missing_points());
    println!("building cells truly_missing found recall missing_pts correct precision");
    for s in &score.per_building {
        println!(
            "{:>8} {:>5} {:>13} {:>5} {:>6.3} {:>11} {:>7} {:>9.3}",
            s.building, s.cells, s.truly_missing, s.found, s.recall, s.missing_points, s.correct_points, s.precision
        );
    }
    println!(
        "TOTAL cells {} truly missing {} recall {:.3} precision {:.3} ({} missing points, R_missing {:.3})",
        score.cells,
        score.truly_missing,
        score.recall,
        score.precision,
        score.missing_points,
        det.r_missing()
    );
    assert!(score.truly_missing > 100, "the prior should leave walls missing");
    assert!(score.recall >= 0.90, "recall {:.3}", score.recall);
    assert!(score.precision >= 0.85, "precision {:.3}", score.precision);
}
