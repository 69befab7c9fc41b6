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

/// A missing point within this distance (xy) of a producer building point
/// lies on that building's outline seen from above, metres: the slice
/// raster's cell at 4 pts/m² and above, the most an outline can stand off
/// its wall. Sparser surveys draw outlines in cells of their spacing, and
/// [`producer_check`] takes that cell instead.
pub const OUTLINE_REACH_M: f32 = 0.5;

/// Missing points and targets against the producer's building class.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProducerCheck {
    /// Missing points checked.
    pub missing_points: usize,
    /// Missing points whose nearest input point (3D) has producer class 6.
    pub missing_on_building: usize,
    /// `missing_on_building / missing_points` (1 when there are none).
    pub missing_on_building_share: f64,
    /// The plan distance (m) within which a missing point counts as on an
    /// outline: the detection's outline cell ([`OUTLINE_REACH_M`] at 4
    /// pts/m² and above).
    pub outline_reach_m: f32,
    /// Missing points within `outline_reach_m` (xy) of a producer building
    /// point: on a building's outline from above. A wall the survey missed
    /// has no points of its own, so its nearest point in 3D is often the
    /// ground at its foot or a tree before it; in plan it is the roof edge.
    pub missing_on_outline: usize,
    /// Missing points within [`OUTLINE_REACH_M`] (xy) of a producer building
    /// point, whatever the cell: the figure at every density on one scale.
    pub missing_within_half_metre: usize,
    /// `missing_on_outline / missing_points` (1 when there are none).
    pub missing_on_outline_share: f64,
    /// Target positions checked (point targets and region outline vertices).
    pub targets: usize,
    /// Largest xy distance from a target to a producer building point, metres
    /// (0 without targets, infinite without building points).
    pub target_building_max_m: f32,
    /// Targets farther than [`TARGET_REACH_M`] from every producer building point.
    pub targets_beyond_reach: usize,
}

/// Checks `missing` points and `targets` (local frame, like `xyz`) against
/// the producer's `labels` of the input points `xyz` (LAS classes); a
/// missing point within `outline_reach_m` in plan of a building point is on
/// its outline (NaN or less than [`OUTLINE_REACH_M`]: that).
/// Non-finite points are ignored.
pub fn producer_check(
    xyz: &[[f32; 3]],
    labels: &[u8],
    missing: &[[f32; 3]],
    targets: &[[f32; 3]],
    outline_reach_m: f32,
) -> ProducerCheck {
    let reach = outline_reach_m.max(OUTLINE_REACH_M);
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
    let roof_tree = ImmutableKdTree::<f32, 2>::new_from_slice(&roofs)
        .ok()
        .filter(|_| !roofs.is_empty());
    let to_roof = |q: &[f32; 3]| {
        roof_tree.as_ref().map_or(f32::INFINITY, |tree| {
            tree.query(&[q[0], q[1]])
                .nearest_one::<SquaredEuclidean<f32>>()
                .execute()
                .distance
                .sqrt()
        })
    };
    let distances: Vec<f32> = targets.par_iter().map(|q| to_roof(q)).collect();
    let to_missing: Vec<f32> = missing.par_iter().map(|q| to_roof(q)).collect();
    let on_outline = to_missing.iter().filter(|d| **d <= reach).count();
    let half_metre = to_missing.iter().filter(|d| **d <= OUTLINE_REACH_M).count();
    let share = |n: usize| {
        if missing.is_empty() {
            1.0
        } else {
            n as f64 / missing.len() as f64
        }
    };
    ProducerCheck {
        missing_points: missing.len(),
        missing_on_building: on_building,
        missing_on_building_share: share(on_building),
        outline_reach_m: reach,
        missing_on_outline: on_outline,
        missing_within_half_metre: half_metre,
        missing_on_outline_share: share(on_outline),
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
        let c = producer_check(&xyz, &labels, &missing, &targets, OUTLINE_REACH_M);
        assert_eq!((c.missing_points, c.missing_on_building), (3, 2));
        // In plan, 0.5 and 0.2 m from the wall; the third is 1 m from the tree.
        assert_eq!(c.missing_on_outline, 2);
        assert!((c.missing_on_building_share - 2.0 / 3.0).abs() < 1e-9);
        assert_eq!(c.targets, 2);
        assert!((c.target_building_max_m - 40.0).abs() < 1e-4);
        assert_eq!(c.targets_beyond_reach, 1);
        let none = producer_check(&xyz, &[1; 40], &missing, &targets, f32::NAN);
        assert_eq!(none.missing_on_building, 0);
        assert!(none.target_building_max_m.is_infinite());
    }

    #[test]
    fn a_sparse_outline_is_checked_within_its_cell() {
        // Roof points 1 m apart along x = 0; missing points 0.3 / 0.6 / 0.9
        // / 1.2 m out in plan.
        let xyz: Vec<[f32; 3]> = (0..20).map(|k| [0.0, k as f32, 6.0]).collect();
        let labels = vec![class::BUILDING; xyz.len()];
        let missing = [0.3, 0.6, 0.9, 1.2].map(|x| [x, 5.0, 2.0]);
        let at = |reach: f32| producer_check(&xyz, &labels, &missing, &[], reach);
        let dense = at(OUTLINE_REACH_M);
        assert_eq!(
            (dense.missing_on_outline, dense.missing_within_half_metre),
            (1, 1)
        );
        // A 1 m cell (1 pts/m²): an outline may stand a cell off its wall.
        let sparse = at(1.0);
        assert_eq!(
            (sparse.outline_reach_m, sparse.missing_on_outline),
            (1.0, 3)
        );
        assert_eq!(sparse.missing_within_half_metre, 1);
        // A finer cell than the dense one does not narrow the reach.
        assert_eq!(at(0.25).missing_on_outline, 1);
        assert_eq!(at(0.25).outline_reach_m, OUTLINE_REACH_M);
    }

    #[test]
    fn a_wall_unseen_from_the_air_is_on_the_outline_but_nearest_the_ground() {
        // A roof edge 8 m up at x = 0, ground from x = 1 out; the missing
        // point sits on the wall 1 m up, where the survey saw nothing.
        let mut xyz = Vec::new();
        let mut labels = Vec::new();
        for k in 0..20 {
            xyz.push([-(k as f32) * 0.5, 5.0, 8.0]);
            labels.push(class::BUILDING);
            xyz.push([1.0 + k as f32 * 0.5, 5.0, 0.0]);
            labels.push(class::GROUND);
        }
        let c = producer_check(&xyz, &labels, &[[0.2, 5.0, 1.0]], &[], OUTLINE_REACH_M);
        assert_eq!((c.missing_on_building, c.missing_on_outline), (0, 1));
        assert_eq!(c.missing_on_outline_share, 1.0);
    }
}
