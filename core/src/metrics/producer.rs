//! Detection and targets checked against the classes a survey's producer
//! gave its points: do missing points sit on real buildings, do targets
//! stand beside them (not in a forest)?

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;
use serde::Serialize;

use crate::cloud::class;

/// A target farther than this (xy) from every producer building point is
/// not beside a building, metres.
pub const TARGET_REACH_M: f32 = 30.0;

/// Missing points and targets against the producer's building class.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProducerCheck {
    /// Missing points checked.
    pub missing_points: usize,
    /// Missing points whose nearest input point (3D) has producer class 6.
    pub missing_on_building: usize,
    /// `missing_on_building / missing_points` (1 when there are none).
    pub missing_on_building_share: f64,
    /// Target positions checked (point targets and region outline vertices).
    pub targets: usize,
    /// Largest xy distance from a target to a producer building point, metres
    /// (0 without targets, infinite without building points).
    pub target_building_max_m: f32,
    /// Targets farther than [`TARGET_REACH_M`] from every producer building point.
    pub targets_beyond_reach: usize,
}

/// Checks `missing` points and `targets` (local frame, like `xyz`) against
/// the producer's `labels` of the input points `xyz` (LAS classes).
/// Non-finite points are ignored.
pub fn producer_check(
    xyz: &[[f32; 3]],
    labels: &[u8],
    missing: &[[f32; 3]],
    targets: &[[f32; 3]],
) -> ProducerCheck {
    let finite = |p: &&[f32; 3]| p.iter().all(|v| v.is_finite());
    let (all, all_labels): (Vec<[f32; 3]>, Vec<u8>) = xyz
        .iter()
        .zip(labels)
        .filter(|(p, _)| finite(p))
        .map(|(p, l)| (*p, *l))
        .unzip();
    let missing: Vec<&[f32; 3]> = missing.iter().filter(finite).collect();
    let on_building = match ImmutableKdTree::<f32, 3>::new_from_slice(&all).ok() {
        Some(tree) if !all.is_empty() => missing
            .par_iter()
            .filter(|q| {
                let hit = tree
                    .query(q)
                    .nearest_one::<SquaredEuclidean<f32>>()
                    .execute();
                all_labels.get(hit.item as usize) == Some(&class::BUILDING)
            })
            .count(),
        _ => 0,
    };
    let roofs: Vec<[f32; 2]> = all
        .iter()
        .zip(&all_labels)
        .filter(|(_, l)| **l == class::BUILDING)
        .map(|(p, _)| [p[0], p[1]])
        .collect();
    let targets: Vec<&[f32; 3]> = targets.iter().filter(finite).collect();
    let distances: Vec<f32> = match ImmutableKdTree::<f32, 2>::new_from_slice(&roofs).ok() {
        Some(tree) if !roofs.is_empty() => targets
            .par_iter()
            .map(|q| {
                tree.query(&[q[0], q[1]])
                    .nearest_one::<SquaredEuclidean<f32>>()
                    .execute()
                    .distance
                    .sqrt()
            })
            .collect(),
        _ => vec![f32::INFINITY; targets.len()],
    };
    ProducerCheck {
        missing_points: missing.len(),
        missing_on_building: on_building,
        missing_on_building_share: if missing.is_empty() {
            1.0
        } else {
            on_building as f64 / missing.len() as f64
        },
        targets: targets.len(),
        target_building_max_m: distances.iter().copied().fold(0.0, f32::max),
        targets_beyond_reach: distances.iter().filter(|d| **d > TARGET_REACH_M).count(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_points_and_targets_against_producer_classes() {
        // A wall of building points at x = 0, a tree at x = 50.
        let mut xyz = Vec::new();
        let mut labels = Vec::new();
        for k in 0..20 {
            xyz.push([0.0, k as f32, 5.0]);
            labels.push(class::BUILDING);
            xyz.push([50.0, k as f32, 5.0]);
            labels.push(class::VEGETATION);
        }
        let missing = [[0.5, 3.0, 5.0], [0.2, 8.0, 4.0], [49.0, 2.0, 5.0]];
        let targets = [[6.0, 5.0, 0.0], [40.0, 5.0, 0.0], [f32::NAN, 0.0, 0.0]];
        let c = producer_check(&xyz, &labels, &missing, &targets);
        assert_eq!((c.missing_points, c.missing_on_building), (3, 2));
        assert!((c.missing_on_building_share - 2.0 / 3.0).abs() < 1e-9);
        assert_eq!(c.targets, 2);
        assert!((c.target_building_max_m - 40.0).abs() < 1e-4);
        assert_eq!(c.targets_beyond_reach, 1);
        let none = producer_check(&xyz, &[1; 40], &missing, &targets);
        assert_eq!(none.missing_on_building, 0);
        assert!(none.target_building_max_m.is_infinite());
    }
}
