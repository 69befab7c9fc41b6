//! Neighbourhood sizes of the features.

use serde::{Deserialize, Serialize};

use super::error::FeatureError;

/// Neighbourhood sizes; the defaults suit airborne clouds of 2–50 pts/m².
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FeatureParams {
    /// Nearest neighbours of the fine, density-adaptive scale.
    pub k: usize,
    /// Edge of the voxels that thin the cloud for the radius scales, metres.
    pub voxel_m: f32,
    /// Radius of the middle scale (on voxel centroids), metres.
    pub radius_small_m: f32,
    /// Radius of the coarse scale (on voxel centroids), metres.
    pub radius_large_m: f32,
    /// Radius of the vertical column whose extent above / below a point is
    /// measured, metres.
    pub column_radius_m: f32,
}

impl Default for FeatureParams {
    fn default() -> Self {
        Self {
            k: 12,
            voxel_m: 0.5,
            radius_small_m: 1.5,
            radius_large_m: 3.0,
            column_radius_m: 1.5,
        }
    }
}

impl FeatureParams {
    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), FeatureError> {
        let bad = |field, value: f64, rule| Err(FeatureError::Param { field, value, rule });
        if !(3..=256).contains(&self.k) {
            return bad("k", self.k as f64, "must be in 3..=256");
        }
        let pos = |v: f32| v.is_finite() && v > 0.0;
        if !pos(self.voxel_m) {
            return bad("voxel_m", self.voxel_m.into(), "must be > 0");
        }
        if !pos(self.radius_small_m) || self.radius_small_m < self.voxel_m {
            return bad(
                "radius_small_m",
                self.radius_small_m.into(),
                "must be ≥ voxel_m",
            );
        }
        if !pos(self.radius_large_m) || self.radius_large_m <= self.radius_small_m {
            return bad(
                "radius_large_m",
                self.radius_large_m.into(),
                "must be > radius_small_m",
            );
        }
        if !pos(self.column_radius_m) {
            return bad(
                "column_radius_m",
                self.column_radius_m.into(),
                "must be > 0",
            );
        }
        Ok(())
    }

    /// Smallest cloud the features are defined on.
    pub fn min_points(&self) -> usize {
        4
    }
}
