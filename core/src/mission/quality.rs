//! Per-building quality attributes of a mission, named as a city model
//! carries them (`skyground_*`, next to 3DBAG's `b3_*`): completeness
//! before and after, walls, roofs, missing area, strategy, targets, rounds.

use std::collections::BTreeMap;

use serde_json::{Map, Value, json};

use crate::metrics::completeness::Coverage;
use crate::metrics::evaluation::Evaluation;
use crate::targets::TargetSet;

/// Attribute name prefix.
pub const PREFIX: &str = "skyground_";

/// How a mission supplemented one building, as [`building_attributes`] names it.
pub fn strategy(points: usize, regions: usize) -> &'static str {
    match (points > 0, regions > 0) {
        (true, true) => "point+region",
        (true, false) => "point",
        (false, true) => "region",
        (false, false) => "none",
    }
}

/// Uncovered GT samples times the area each stands for (spacing²), m².
fn missing_area(c: &Coverage, spacing: f32) -> f64 {
    (c.samples - c.covered.min(c.samples)) as f64 * f64::from(spacing).powi(2)
}

/// A share rounded to 1e-4 (JSON null when there is nothing to measure).
fn share(v: Option<f64>) -> Value {
    v.map_or(Value::Null, |v| json!((v * 1e4).round() / 1e4))
}

/// What a mission did, for [`building_attributes`].
#[derive(Debug, Clone, Copy)]
pub struct Mission<'a> {
    /// The targets of the last round planned.
    pub targets: &'a TargetSet,
    /// Rounds driven.
    pub rounds: usize,
}

/// The attributes of every evaluated building, by building id: shares
/// (0–1) of walls + roofs, walls and roofs covered before and after, the
/// missing area before and after (m², GT samples at `spacing` apart), and
/// with a `mission` the strategy and number of targets aimed at it and the
/// rounds driven.
pub fn building_attributes(
    e: &Evaluation,
    spacing: f32,
    mission: Option<Mission<'_>>,
) -> BTreeMap<u32, Map<String, Value>> {
    let mut out = BTreeMap::new();
    for b in &e.before.completeness.buildings {
        let after = e
            .after
            .completeness
            .buildings
            .iter()
            .find(|a| a.building == b.building);
        let mut m = Map::new();
        let mut put = |k: &str, v: Value| {
            m.insert(format!("{PREFIX}{k}"), v);
        };
        put("completeness_before", share(b.all.ratio));
        put("completeness_after", share(after.and_then(|a| a.all.ratio)));
        put("walls_before", share(b.walls.ratio));
        put("walls_after", share(after.and_then(|a| a.walls.ratio)));
        put("roofs_before", share(b.roofs.ratio));
        put("roofs_after", share(after.and_then(|a| a.roofs.ratio)));
        let area = |c: &Coverage| json!((missing_area(c, spacing) * 100.0).round() / 100.0);
        put("missing_area_before_m2", area(&b.all));
        put(
            "missing_area_after_m2",
            after.map_or(Value::Null, |a| area(&a.all)),
        );
        put("tau_m", json!(e.tau));
        if let Some(mission) = mission {
            let (points, regions) = mission.targets.counts_of(b.building);
            put("strategy", json!(strategy(points, regions)));
            put("target_points", json!(points));
            put("target_regions", json!(regions));
            put("rounds", json!(mission.rounds));
        }
        out.insert(b.building, m);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::Cloud;
    use crate::metrics::{evaluate, sample_building_surfaces};
    use crate::scene::reference_scene;
    use crate::targets::{Region, TargetPoint};

    #[test]
    fn attributes_follow_the_evaluation() {
        let scene = reference_scene(7);
        let gt = sample_building_surfaces(&scene, 1.0);
        // Before: nothing but building 1's samples; after: every sample.
        let one = gt.of_building(1);
        let e = evaluate(
            &scene,
            &gt,
            &Cloud::from_xyz(one),
            &Cloud::from_xyz(gt.xyz.clone()),
            0.25,
        );
        let targets = TargetSet {
            points: vec![TargetPoint {
                xyz: [0.0; 3],
                building: 2,
            }],
            regions: vec![Region {
                building: 2,
                polygon: vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
                z: 0.0,
            }],
        };
        let mission = Mission {
            targets: &targets,
            rounds: 2,
        };
        let a = building_attributes(&e, gt.spacing, Some(mission));
        let offline = building_attributes(&e, gt.spacing, None);
        assert!(!offline[&2].contains_key(&format!("{PREFIX}strategy")));
        assert_eq!(a.len(), scene.building_count());
        let get = |b: u32, k: &str| a[&b][&format!("{PREFIX}{k}")].clone();
        assert_eq!(get(1, "completeness_before"), json!(1.0));
        assert_eq!(get(1, "missing_area_before_m2"), json!(0.0));
        assert_eq!(get(1, "strategy"), json!("none"));
        assert!(get(2, "completeness_before").as_f64() < Some(0.05));
        assert_eq!(get(2, "completeness_after"), json!(1.0));
        assert_eq!(get(2, "missing_area_after_m2"), json!(0.0));
        assert_eq!(get(2, "strategy"), json!("point+region"));
        assert_eq!(get(2, "rounds"), json!(2));
        // Building 2's missing area before: nearly all its samples, 1 m² each.
        let samples = gt.building.iter().filter(|b| **b == 2).count() as f64;
        let missing = get(2, "missing_area_before_m2").as_f64().unwrap_or(0.0);
        assert!(
            missing > 0.95 * samples && missing <= samples,
            "{missing} of {samples}"
        );
    }
}
