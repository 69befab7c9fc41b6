//! Neighbourhood sizes of the features.

use serde::{Deserialize, Serialize};

use crate::params::{Checks, ParamError};

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
    pub fn validate(&self) -> Result<(), ParamError> {
        let c = Checks("feature");
        let (small, large) = (self.radius_small_m, self.radius_large_m);
        c.within("k", self.k as f64, 3.0, 256.0)?;
        c.positive("voxel_m", self.voxel_m)?;
        c.positive("radius_small_m", small)?;
        c.that(
            small >= self.voxel_m,
            "radius_small_m",
            small,
            "must be ≥ voxel_m",
        )?;
        c.positive("radius_large_m", large)?;
        c.that(
            large > small,
            "radius_large_m",
            large,
            "must be > radius_small_m",
        )?;
        c.positive("column_radius_m", self.column_radius_m)
    }

    /// Smallest cloud the features are defined on.
    pub fn min_points(&self) -> usize {
        4
    }
}
