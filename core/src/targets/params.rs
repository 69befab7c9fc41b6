//! Parameters of target generation (docs/design.md step 4; θ lives in detection).

use serde::{Deserialize, Serialize};
use thiserror::Error;

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

/// A target parameter out of range.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum TargetParamsError {
    /// A length that must be positive and finite is not.
    #[error("target parameter `{name}` must be a positive finite number, got {value}")]
    NotPositive {
        /// Parameter name.
        name: &'static str,
        /// Given value.
        value: f32,
    },
    /// No standoff distance given.
    #[error("target parameter `standoffs` must list at least one distance")]
    NoStandoff,
    /// The field of view is not in (0°, 90°).
    #[error("target parameter `half_fov_deg` must lie in (0, 90), got {0}")]
    Fov(f32),
    /// The largest incidence angle is not in (0°, 90°).
    #[error("target parameter `max_incidence_deg` must lie in (0, 90), got {0}")]
    Incidence(f32),
}

impl TargetParams {
    /// Checks every field is usable.
    pub fn validate(&self) -> Result<(), TargetParamsError> {
        if self.standoffs.is_empty() {
            return Err(TargetParamsError::NoStandoff);
        }
        for &value in &self.standoffs {
            if !(value.is_finite() && value > 0.0) {
                return Err(TargetParamsError::NotPositive {
                    name: "standoffs",
                    value,
                });
            }
        }
        let positive = [
            ("downsample", self.downsample),
            ("region_buffer", self.region_buffer),
            ("region_link", self.region_link),
            ("cell", self.cell),
        ];
        for (name, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Err(TargetParamsError::NotPositive { name, value });
            }
        }
        for (name, value) in [
            ("clearance", self.clearance),
            ("sensor_height", self.sensor_height),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(TargetParamsError::NotPositive { name, value });
            }
        }
        if !(self.stop_range.is_finite() && self.stop_range >= 0.0) {
            return Err(TargetParamsError::NotPositive {
                name: "stop_range",
                value: self.stop_range,
            });
        }
        if !(self.max_incidence_deg > 0.0 && self.max_incidence_deg < 90.0) {
            return Err(TargetParamsError::Incidence(self.max_incidence_deg));
        }
        if !(self.half_fov_deg > 0.0 && self.half_fov_deg < 90.0) {
            return Err(TargetParamsError::Fov(self.half_fov_deg));
        }
        Ok(())
    }
}
