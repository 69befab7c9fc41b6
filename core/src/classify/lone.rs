//! Lone points: where a survey is so sparse that a point has no other point
//! within the forest's largest sphere, its features are empty and its
//! height above the cloth is a guess, so the terrain decides instead.
//!
//! PDAL's 1,065-point Autzen snippet (3.4 × 4.6 km) is such a survey: its
//! points lie tens of metres apart, the cloth between them is a patchwork
//! of the nearest points' heights, and on a hillside a bare-earth point
//! stands metres above the patch it falls on. The test is the slope-based
//! filter's (Vosselman 2000): a lone point is ground when no point called
//! ground lies below it by more than the steepest terrain slope allows.

use std::num::NonZeroUsize;

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;

use crate::cloud::class::GROUND;

/// Steepest terrain slope (rise over run) a lone point may stand above the
/// ground round it: the steepest between producer ground points 32–64 m
/// apart on the training files (St Barth 0.21, the BC forest 0.22,
/// Montpellier 0.03), as lone points lie tens of metres from any other.
pub const STEEPEST_SLOPE: f32 = 0.22;

/// A point is judged by the terrain only when no point called ground lies
/// within this many cloth cells of it in plan: nearer, the cloth was held
/// by ground close by and the forest's height above it stands.
pub const REACH_CELLS: f32 = 4.0;

/// Nearest ground points (in plan) whose slope cones a lone point is tested
/// against.
const GROUND_NEIGHBOURS: usize = 16;

/// Makes ground every lone point (no other point within `radius_m` in 3D)
/// that the terrain calls ground: no point labelled ground within `reach_m`
/// in plan, and none of the nearest ground points lower than
/// [`STEEPEST_SLOPE`] × distance below it. Returns how many became ground.
/// The cone is tested against the ground as labelled on entry, so the
/// result does not depend on the order of the points.
pub fn lone_ground(xyz: &[[f32; 3]], labels: &mut [u8], radius_m: f32, reach_m: f32) -> usize {
    let finite = |p: &[f32; 3]| p.iter().all(|v| v.is_finite());
    let ground: Vec<[f32; 3]> = xyz
        .iter()
        .zip(labels.iter())
        .filter(|(p, l)| **l == GROUND && finite(p))
        .map(|(p, _)| *p)
        .collect();
    let kept: Vec<[f32; 3]> = xyz.iter().copied().filter(|p| finite(p)).collect();
    if ground.is_empty() || kept.len() < 2 {
        return 0;
    }
    let plan: Vec<[f32; 2]> = ground.iter().map(|p| [p[0], p[1]]).collect();
    let (Ok(all), Ok(grounds)) = (
        ImmutableKdTree::<f32, 3>::new_from_slice(&kept),
        ImmutableKdTree::<f32, 2>::new_from_slice(&plan),
    ) else {
        return 0;
    };
    let two = NonZeroUsize::new(2).unwrap_or(NonZeroUsize::MIN);
    let k = NonZeroUsize::new(GROUND_NEIGHBOURS.min(ground.len())).unwrap_or(NonZeroUsize::MIN);
    let r2 = radius_m * radius_m;
    let lone: Vec<bool> = xyz
        .par_iter()
        .zip(labels.par_iter())
        .map(|(p, &l)| {
            if l == GROUND || !finite(p) {
                return false;
            }
            // The nearest is the point itself (or a duplicate of it).
            let near = all
                .query(p)
                .nearest_n::<SquaredEuclidean<f32>>(two)
                .execute();
            if near.get(1).is_none_or(|n| n.distance <= r2) {
                return false;
            }
            let around = grounds
                .query(&[p[0], p[1]])
                .nearest_n::<SquaredEuclidean<f32>>(k)
                .execute();
            let beyond_reach = around.first().is_some_and(|n| n.distance.sqrt() > reach_m);
            beyond_reach
                && around.iter().all(|n| {
                    let q = ground[n.item as usize];
                    p[2] <= q[2] + STEEPEST_SLOPE * n.distance.sqrt()
                })
        })
        .collect();
    let mut made = 0;
    for (l, is) in labels.iter_mut().zip(lone) {
        if is {
            *l = GROUND;
            made += 1;
        }
    }
    made
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::class::VEGETATION;

    /// Ground on a 0.2 slope sampled every 50 m, one lone point 40 m past
    /// the last ground point at `rise` over it, and a dense pair.
    fn hillside(rise: f32) -> (Vec<[f32; 3]>, Vec<u8>) {
        let mut xyz: Vec<[f32; 3]> = (0..5)
            .map(|i| {
                let x = 50.0 * i as f32;
                [x, 0.0, 0.2 * x]
            })
            .collect();
        let mut labels = vec![GROUND; xyz.len()];
        xyz.push([240.0, 0.0, 0.2 * 200.0 + rise]);
        labels.push(VEGETATION);
        xyz.extend([[100.0, 100.0, 30.0], [100.5, 100.0, 30.0]]);
        labels.extend([VEGETATION, VEGETATION]);
        (xyz, labels)
    }

    #[test]
    fn a_lone_point_on_the_slope_is_ground_one_above_it_is_not() {
        // 40 m on, the terrain may rise 0.22 × 40 = 8.8 m.
        let (xyz, mut labels) = hillside(8.0);
        assert_eq!(lone_ground(&xyz, &mut labels, 3.0, 32.0), 1);
        assert_eq!(labels[5], GROUND);
        // The dense pair is the forest's: each has a neighbour within 3 m.
        assert_eq!(&labels[6..], &[VEGETATION, VEGETATION]);
        let (xyz, mut labels) = hillside(12.0);
        assert_eq!(lone_ground(&xyz, &mut labels, 3.0, 32.0), 0);
        assert_eq!(labels[5], VEGETATION);
    }

    #[test]
    fn ground_within_reach_leaves_the_forest_its_verdict() {
        let (xyz, mut labels) = hillside(8.0);
        assert_eq!(lone_ground(&xyz, &mut labels, 3.0, 45.0), 0);
        // No ground at all: nothing to judge against.
        let (xyz, _) = hillside(8.0);
        let mut none = vec![VEGETATION; xyz.len()];
        assert_eq!(lone_ground(&xyz, &mut none, 3.0, 32.0), 0);
        // Non-finite points are neither judged nor judged against.
        let (mut xyz, mut labels) = hillside(8.0);
        xyz[5] = [f32::NAN, 0.0, 0.0];
        assert_eq!(lone_ground(&xyz, &mut labels, 3.0, 32.0), 0);
    }
}
