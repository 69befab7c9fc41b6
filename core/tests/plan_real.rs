//! The plan on our own classes, on real tiles the model never saw (AHN3
//! Delft 1 and 2 with the shipped model; each IGN tile with a model trained
//! on the other): the classifier, then detection, targets, the ground graph
//! and the set-downs, checked against the producer's classes.
//!
//! - Our classes cut the graph no more than the producer's do: with the
//!   same obstacle rule (AHN3 has no vegetation class, so its trees block
//!   only in the vehicle's height band, i.e. `canopy_is_obstacle: false`)
//!   the piece `skyground plan` starts on holds ≥ 90 % of the nodes it holds
//!   on the producer's classes. The 90 % of all candidate nodes
//!   cannot be met here by any classes: docs/density.md.
//! - Detection on our classes puts ≥ 95 % of its missing points within
//!   0.5 m (in plan) of a producer building point, and every target within
//!   30 m of one: the bars, in plan (the 3D bar cannot hold:
//!   docs/density.md).
//! - At 2 pts/m² (Delft 2 kept to 22 % of its pulses) the outlines are
//!   drawn in cells of the spacing, and ≥ 95 % of missing points lie
//!   within that cell of a producer building point.
//! - A canal without a drivable bridge leaves targets on the far bank:
//!   more set-downs reach targets the first does not, and every set-down
//!   stands on the producer's ground, never on a roof.
//!
//! Absent data → `SKIPPED`, the test passes.

use skyground_core::classify::{Model, SceneClassifier};
use skyground_core::cloud::{Cloud, read_cloud};
use skyground_core::graph::{GraphParams, GroundGraph, drivable};
use skyground_core::ground::CsfParams;
use skyground_core::metrics::{ProducerCheck, producer_check};
use skyground_core::missing::{SceneParams, detect_scene};
use skyground_core::route::{Ground, RouteParams, plan_set_downs};
use skyground_core::targets::{Site, TargetParams, TargetSet, generate};

mod common;
use common::{IGN, real_file, shipped, sparse_delft_2, trained_on};

/// The tile with its producer's classes, and our classes for it.
fn classified(name: &str, model: &Model) -> Option<(Cloud, Vec<u8>)> {
    let path = real_file(name)?;
    assert!(
        !model.training_files.iter().any(|f| f.starts_with(name)),
        "the model was trained on {name}"
    );
    let cloud = read_cloud(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    let classifier = SceneClassifier::new(CsfParams::default(), model.clone()).unwrap();
    let ours = classifier.classify_cloud(&cloud).unwrap().labels;
    Some((cloud, ours))
}

fn nodes(cloud: &Cloud, labels: &[u8], params: &GraphParams) -> usize {
    GroundGraph::build_largest(&cloud.xyz, labels, params)
        .unwrap()
        .len()
}

/// `skyground detect --classify` then the targets of `skyground plan`,
/// checked against the producer's building points.
fn detection_check(cloud: &Cloud, ours: &[u8]) -> (ProducerCheck, TargetSet) {
    let producer = cloud.label.as_deref().expect("a labelled tile");
    let mut ours_cloud = cloud.clone();
    ours_cloud.label = Some(ours.to_vec());
    let (detection, _) = detect_scene(&ours_cloud, None, None, &SceneParams::default()).unwrap();
    let tp = TargetParams::default();
    let site = Site::from_cloud(&cloud.xyz, ours, tp.cell, tp.clearance).unwrap();
    let (targets, _) = generate(&detection, &site, &tp).unwrap();
    let check = producer_check(
        &cloud.xyz,
        producer,
        &detection.missing_xyz(),
        &targets.positions(),
        detection.outline_cell_m() as f32,
    );
    (check, targets)
}

/// The share of missing points on a producer building (in plan) at least
/// the 0.95, and every target within reach of one.
fn assert_beside_buildings(name: &str, check: &ProducerCheck) {
    println!(
        "{name}: {} of {} missing points within {} m (plan) of a producer building point ({:.4}); \
         targets at most {:.1} m from one",
        check.missing_on_outline,
        check.missing_points,
        check.outline_reach_m,
        check.missing_on_outline_share,
        check.target_building_max_m
    );
    assert!(
        check.missing_on_outline_share >= 0.95,
        "{name}: {:.4} of missing points on a producer building's outline",
        check.missing_on_outline_share
    );
    assert_eq!(check.targets_beyond_reach, 0, "{name}: {check:?}");
}

/// Points within 1 m (xy) of `p`: (producer ground or bridge, all).
fn ground_near(cloud: &Cloud, producer: &[u8], p: [f32; 3]) -> (usize, usize) {
    let near = cloud
        .xyz
        .iter()
        .zip(producer)
        .filter(|(q, _)| (q[0] - p[0]).hypot(q[1] - p[1]) <= 1.0);
    near.fold((0, 0), |(g, n), (_, &l)| {
        (g + usize::from(drivable(l)), n + 1)
    })
}

#[test]
fn our_classes_reach_the_producers_ground_and_set_downs_cross_the_canals() {
    let model = shipped();
    for name in ["ahn3_delft_1.laz", "ahn3_delft_2.laz"] {
        let Some((cloud, ours)) = classified(name, &model) else {
            return;
        };
        let producer = cloud.label.clone().expect("a labelled tile");

        let band_only = GraphParams {
            canopy_is_obstacle: false,
            ..GraphParams::default()
        };
        let theirs_n = nodes(&cloud, &producer, &GraphParams::default());
        let ours_n = nodes(&cloud, &ours, &band_only);
        println!(
            "{name}: the start's piece holds {ours_n} nodes on our classes, {theirs_n} on the producer's ({:.3})",
            ours_n as f64 / theirs_n as f64
        );
        assert!(
            ours_n as f64 >= 0.90 * theirs_n as f64,
            "{name}: {ours_n} nodes on our classes against {theirs_n} on the producer's"
        );

        // `skyground detect --classify` then `skyground plan` (its defaults: 3 more set-downs).
        let (check, targets) = detection_check(&cloud, &ours);
        assert_beside_buildings(name, &check);
        let params = GraphParams::default();
        let first = GroundGraph::build_largest(&cloud.xyz, &ours, &params).unwrap();
        let start = first.positions()[first.start_node()];
        let ground = Ground {
            xyz: &cloud.xyz,
            labels: &ours,
            params: &params,
        };
        let plan = plan_set_downs(
            &ground,
            &targets,
            (first, start),
            &RouteParams::default(),
            3,
        )
        .unwrap();
        let from_first = plan.set_downs[0].route.order.len();
        let all: usize = plan.set_downs.iter().map(|s| s.route.order.len()).sum();
        println!(
            "{name}: {} targets; the first set-down reaches {from_first}, {} set-downs {all}",
            targets.points.len() + targets.regions.len(),
            plan.set_downs.len()
        );
        assert!(
            all > from_first,
            "{name}: more set-downs reach no more targets"
        );
        for (k, s) in plan.set_downs.iter().enumerate() {
            let (g, n) = ground_near(&cloud, &producer, s.start);
            assert!(
                n > 0 && g * 2 > n,
                "{name}: set-down {} at {:?} stands on {g} producer ground points of {n}",
                k + 1,
                s.start
            );
        }
    }
}

/// Each IGN tile, classified by a model trained on the other (and the BC
/// forest and the simulated surveys): detection's missing points lie on the
/// producer's buildings, not in the gardens' trees and hedges around them.
/// Measured: Montpellier 0.964, St Barth 0.975.
#[test]
fn ign_detection_on_classes_of_a_model_that_never_saw_the_tile() {
    for (name, other) in [(IGN[0], IGN[1]), (IGN[1], IGN[0])] {
        let Some(model) = trained_on(&[other]) else {
            return;
        };
        let Some((cloud, ours)) = classified(name, &model) else {
            return;
        };
        let (check, _) = detection_check(&cloud, &ours);
        assert_beside_buildings(name, &check);
    }
}

/// A sparse survey: outlines in cells of the building points' spacing
/// (0.82 m here), and missing points within that cell of a producer
/// building point in plan, targets within 30 m: 0.973 within the cell,
/// 0.83 within 0.5 m, which is finer than the survey's sampling.
#[test]
fn a_sparse_survey_puts_its_missing_points_beside_buildings() {
    let name = "ahn3_delft_2.laz";
    let Some(sparse) = sparse_delft_2() else {
        return;
    };
    let classifier = SceneClassifier::new(CsfParams::default(), shipped()).unwrap();
    let ours = classifier.classify_cloud(&sparse).unwrap().labels;
    let (check, _) = detection_check(&sparse, &ours);
    assert!(
        check.outline_reach_m > 0.7 && check.outline_reach_m < 1.0,
        "{check:?}"
    );
    assert!(
        check.missing_within_half_metre < check.missing_on_outline,
        "{check:?}"
    );
    println!(
        "{name} at 22 % of its pulses: {} within 0.5 m",
        check.missing_within_half_metre
    );
    assert_beside_buildings(&format!("{name} at 22 % of its pulses"), &check);
}
