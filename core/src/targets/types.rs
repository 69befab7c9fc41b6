//! The target types shared by the target generator and the planners.

use serde::{Deserialize, Serialize};

/// A place on the ground where a sensor sees a missing part of a wall.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TargetPoint {
    /// Position on the ground (z = ground height), local frame, metres.
    pub xyz: [f32; 3],
    /// The building whose gap it looks at (1-based).
    pub building: u32,
}

/// An area around a large gap, to be explored locally.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Region {
    /// The building whose gap it surrounds (1-based).
    pub building: u32,
    /// Convex outline in xy, counter-clockwise, not closed (first != last).
    pub polygon: Vec<[f64; 2]>,
    /// Ground height the region lies at, metres (for drawing it).
    pub z: f32,
}

/// Everything the planner is asked to reach.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TargetSet {
    /// Point targets.
    pub points: Vec<TargetPoint>,
    /// Region targets.
    pub regions: Vec<Region>,
}

impl TargetSet {
    /// Where the targets stand: each point target and each region's
    /// corners, at its ground height (local frame).
    pub fn positions(&self) -> Vec<[f32; 3]> {
        let corners = self
            .regions
            .iter()
            .flat_map(|r| r.polygon.iter().map(|v| [v[0] as f32, v[1] as f32, r.z]));
        self.points.iter().map(|t| t.xyz).chain(corners).collect()
    }

    /// How many point targets and regions building `building` has.
    pub fn counts_of(&self, building: u32) -> (usize, usize) {
        (
            self.points
                .iter()
                .filter(|t| t.building == building)
                .count(),
            self.regions
                .iter()
                .filter(|r| r.building == building)
                .count(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_are_the_point_targets_then_each_regions_corners() {
        let set = TargetSet {
            points: vec![TargetPoint {
                xyz: [1.0, 2.0, 0.5],
                building: 1,
            }],
            regions: vec![Region {
                building: 2,
                polygon: vec![[0.0, 0.0], [4.0, 0.0], [4.0, 3.0]],
                z: 1.5,
            }],
        };
        assert_eq!(
            set.positions(),
            vec![
                [1.0, 2.0, 0.5],
                [0.0, 0.0, 1.5],
                [4.0, 0.0, 1.5],
                [4.0, 3.0, 1.5]
            ]
        );
    }
}
