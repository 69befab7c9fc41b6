//! Tunables of local exploration, filled from the explorer's params YAML.

use serde::{Deserialize, Serialize};

use crate::params::{Checks, ParamError};

/// How a region is explored (docs/design.md step 7).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ExploreParams {
    /// Candidate viewpoints are thinned to one per square cell this wide, metres.
    pub viewpoint_spacing_m: f32,
    /// Viewpoints keep this distance (xy) from obstacles, metres.
    pub collision_margin_m: f32,
    /// Sensor height above the ground, metres.
    pub sensor_height_m: f32,
    /// Surface farther than this counts as unseen (returns get sparse), metres.
    pub sensor_range_m: f32,
    /// Lowest beam elevation, degrees.
    pub fov_min_deg: f32,
    /// Highest beam elevation, degrees.
    pub fov_max_deg: f32,
    /// A surface sample is covered by a scan point within this distance, metres.
    pub tau_m: f32,
    /// Exploration ends when the best viewpoint sees fewer new samples per metre of driving.
    pub min_gain_per_m: f32,
    /// Viewpoints seeing fewer new samples are not worth a stop.
    pub min_gain: u32,
    /// Randomized restarts of the greedy selection (0: the plain greedy only).
    pub restarts: u32,
    /// Seed of the restarts.
    pub seed: u64,
    /// Voxel size of the occupancy used for line of sight, metres.
    pub voxel_m: f32,
    /// Known points this close to a sample do not hide it (its own wall), metres.
    pub own_neighbourhood_m: f32,
    /// A sample predicted visible from this many visited viewpoints but never
    /// covered is given up (not aimed at any more).
    pub max_attempts: u8,
}

impl Default for ExploreParams {
    fn default() -> Self {
        Self {
            viewpoint_spacing_m: 1.5,
            collision_margin_m: 0.8,
            sensor_height_m: 1.0,
            sensor_range_m: 30.0,
            fov_min_deg: -15.0,
            fov_max_deg: 15.0,
            tau_m: 0.25,
            min_gain_per_m: 1.0,
            min_gain: 4,
            restarts: 8,
            seed: 0,
            voxel_m: 0.5,
            own_neighbourhood_m: 0.75,
            max_attempts: 2,
        }
    }
}

impl ExploreParams {
    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), ParamError> {
        let c = Checks("explore");
        let (fov_min, fov_max) = (self.fov_min_deg, self.fov_max_deg);
        c.within("viewpoint_spacing_m", self.viewpoint_spacing_m, 0.1, 50.0)?;
        c.non_negative("collision_margin_m", self.collision_margin_m)?;
        c.non_negative("sensor_height_m", self.sensor_height_m)?;
        c.positive("sensor_range_m", self.sensor_range_m)?;
        c.within("sensor_range_m", self.sensor_range_m, 0.0, 500.0)?;
        let fov_ok = (-90.0..=90.0).contains(&fov_min) && fov_min < fov_max;
        c.that(
            fov_ok,
            "fov_min_deg",
            fov_min,
            "must be within ±90 and below fov_max_deg",
        )?;
        c.within("fov_max_deg", fov_max, -90.0, 90.0)?;
        c.positive("tau_m", self.tau_m)?;
        c.non_negative("min_gain_per_m", self.min_gain_per_m)?;
        c.within("voxel_m", self.voxel_m, 0.05, 5.0)?;
        c.non_negative("own_neighbourhood_m", self.own_neighbourhood_m)?;
        c.within("restarts", self.restarts, 0, 10_000)
    }
}
