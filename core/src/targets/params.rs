//! Parameters of target generation (docs/design.md step 4; θ lives in detection).

use serde::{Deserialize, Serialize};

use crate::params::{Checks, ParamError};

/// How targets are made from missing points.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TargetParams {
    /// Distances from the wall at which point targets are sampled, metres.
    pub standoffs: Vec<f32>,
    /// Height of the ground sensor above the ground, metres.
    pub sensor_height: f32,
    /// Half vertical field of view of the ground sensor, degrees (VLP-16: 15).
    pub half_fov_deg: f32,
    /// Point targets closer than this to each other (same building) are merged, metres.
    pub downsample: f32,
    /// Region-based: outward push of the missing boundary, metres.
    pub region_buffer: f32,
    /// Region-based: missing points closer than this form one region, metres.
    pub region_link: f32,
    /// Least distance from building and vegetation cells, metres.
    pub clearance: f32,
    /// Cell of the site grid, metres.
    pub cell: f32,
    /// Consolidation: a stop serves the gaps within this range it sees,
    /// metres (0: every generated target is kept).
    pub stop_range: f32,
    /// Consolidation: a gap is seen from at most this far off its wall's normal, degrees.
    pub max_incidence_deg: f32,
}

impl Default for TargetParams {
    fn default() -> Self {
        TargetParams {
            standoffs: vec![6.0, 10.0, 14.0, 22.0],
            sensor_height: 1.0,
            half_fov_deg: 15.0,
            downsample: 5.0,
            region_buffer: 4.0,
            region_link: 3.0,
            clearance: 1.0,
            cell: 1.0,
            stop_range: 20.0,
            max_incidence_deg: 70.0,
        }
    }
}

impl TargetParams {
    /// Checks every field is usable.
    pub fn validate(&self) -> Result<(), ParamError> {
        let c = Checks("target");
        let n = self.standoffs.len() as f64;
        c.that(n > 0.0, "standoffs", n, "must list at least one distance")?;
        for &value in &self.standoffs {
            c.positive("standoffs", value)?;
        }
        c.positive("downsample", self.downsample)?;
        c.positive("region_buffer", self.region_buffer)?;
        c.positive("region_link", self.region_link)?;
        c.positive("cell", self.cell)?;
        c.non_negative("clearance", self.clearance)?;
        c.non_negative("sensor_height", self.sensor_height)?;
        c.non_negative("stop_range", self.stop_range)?;
        let (inc, fov) = (self.max_incidence_deg, self.half_fov_deg);
        let acute = |a: f32| a > 0.0 && a < 90.0;
        c.that(acute(inc), "max_incidence_deg", inc, "must lie in (0, 90)")?;
        c.that(acute(fov), "half_fov_deg", fov, "must lie in (0, 90)")
    }
}
