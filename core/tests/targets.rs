//! Target generation end to end (DESIGN.md step 4) on the reference scene:
//! targets are checked against the scene mesh (never inside a building or a
//! tree), point targets against their standoff range, regions against the
//! shape the planner expects.

use skyground_core::io::load_scene;
use skyground_core::missing::{DetectParams, Strategy, detect_all_on};
use skyground_core::scene::ObjectKind;
use skyground_core::targets::{Site, TargetParams, generate};

#[path = "planning_scene/mod.rs"]
mod planning_scene;

#[test]
fn reference_targets_are_outside_obstacles_and_in_range() {
    let scene = load_scene("reference").unwrap();
    let p = planning_scene::prior(&scene);
    let terrain = p.terrain();
    // θ low enough that both strategies occur on this scene.
    let dp = DetectParams {
        theta: 0.12,
        ..DetectParams::default()
    };
    let det = detect_all_on(&p.buildings, &p.ids, None, Some(&terrain), &dp).unwrap();
    let tp = TargetParams::default();
    let site = Site::from_cloud(&p.xyz, &p.labels, tp.cell, tp.clearance).unwrap();
    let (set, dropped) = generate(&det, &site, &tp).unwrap();
    let point_buildings = det
        .buildings
        .iter()
        .filter(|b| b.skipped.is_none() && b.strategy == Strategy::PointBased)
        .count();
    println!(
        "{} point targets, {} regions ({} point-based buildings); dropped {:?}",
        set.points.len(),
        set.regions.len(),
        point_buildings,
        dropped
    );
    assert!(set.points.len() > 50);
    assert!(!set.regions.is_empty());
    assert!(
        dropped.inside_building > 0,
        "some candidates must have been rejected"
    );

    // Inside test against the mesh: a ray straight up from inside a closed
    // solid leaves through a face whose normal points up (a back face).
    let mut inside = 0;
    for t in &set.points {
        let o = [t.xyz[0], t.xyz[1], t.xyz[2] + 0.3];
        if let Some(hit) = p.caster.cast(o, [0.0, 0.0, 1.0], 200.0) {
            let kind = p.caster.object(hit.object).map(|ob| ob.kind);
            let solid = matches!(kind, Some(ObjectKind::Building | ObjectKind::Vegetation));
            if solid && hit.normal[2] > 0.0 {
                inside += 1;
            }
        }
    }
    assert_eq!(inside, 0, "targets inside buildings or trees");

    // Every point target stands within the standoff range of a missing
    // point of its building, or nearer on open ground where every standoff
    // was blocked (an alley).
    let lo = tp.standoffs.iter().cloned().fold(f32::MAX, f32::min) - 0.01;
    let hi = tp.standoffs.iter().cloned().fold(f32::MIN, f32::max) + 0.01;
    let mut nearer = 0;
    for t in &set.points {
        let b = det
            .buildings
            .iter()
            .find(|b| b.building == t.building)
            .unwrap();
        let dists = b
            .missing
            .iter()
            .map(|m| (t.xyz[0] - m.xyz[0]).hypot(t.xyz[1] - m.xyz[1]))
            .collect::<Vec<_>>();
        if dists.iter().any(|d| (lo..=hi).contains(d)) {
            continue;
        }
        let k = site.index(t.xyz[0], t.xyz[1]).unwrap();
        assert!(
            dists.iter().any(|&d| d >= site.cell() && d < lo)
                && !site.building[k]
                && !site.vegetation[k],
            "target {t:?} neither in standoff range nor on open ground nearer"
        );
        nearer += 1;
    }
    println!("{nearer} targets nearer than the least standoff");
    // Regions: counter-clockwise, not closed, at least a triangle.
    for r in &set.regions {
        let p = &r.polygon;
        assert!(p.len() >= 3 && p.first() != p.last());
        let area2: f64 = (0..p.len())
            .map(|k| {
                let (a, b) = (p[k], p[(k + 1) % p.len()]);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum();
        assert!(area2 > 0.0, "region not counter-clockwise");
        let strategy = det
            .buildings
            .iter()
            .find(|b| b.building == r.building)
            .unwrap()
            .strategy;
        assert_eq!(strategy, Strategy::RegionBased);
    }
}

#[test]
fn bad_target_params_are_errors() {
    let p = TargetParams {
        standoffs: vec![],
        ..TargetParams::default()
    };
    assert!(p.validate().is_err());
    let p = TargetParams {
        half_fov_deg: 95.0,
        ..TargetParams::default()
    };
    assert!(p.validate().is_err());
}
