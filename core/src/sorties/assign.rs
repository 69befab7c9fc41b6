//! Who takes which gap: the ground robot every gap one of its stops could
//! see (a spot on ground joined to its start, within its range, the gap
//! inside its LiDAR's vertical field of view and the sight line over the
//! prior's height map clear), the drone the rest: upper storeys above the
//! ground LiDAR's beams, closed courtyards, walls behind water or walls.

use serde::{Deserialize, Serialize};

use crate::airspace::{Airspace, GroundReach};
use crate::missing::MissingPoint;
use crate::params::{Checks, ParamError};

/// What a ground stop sees (the target generator's view model).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GroundView {
    /// The ground LiDAR's height above the ground, m.
    pub sensor_height_m: f32,
    /// Half its vertical field of view, degrees.
    pub half_fov_deg: f32,
    /// Farthest a stop may be from the gap, m.
    pub range_m: f32,
    /// Most a stop may be off the wall's normal, degrees.
    pub max_incidence_deg: f32,
    /// Highest step between neighbouring ground cells the robot drives, m.
    pub max_step_m: f32,
}

impl Default for GroundView {
    fn default() -> Self {
        Self {
            sensor_height_m: 1.8,
            half_fov_deg: 15.0,
            range_m: 20.0,
            max_incidence_deg: 60.0,
            max_step_m: 0.3,
        }
    }
}

impl GroundView {
    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), ParamError> {
        let c = Checks("ground_view");
        c.positive("sensor_height_m", self.sensor_height_m)?;
        c.positive("half_fov_deg", self.half_fov_deg)?;
        c.positive("range_m", self.range_m)?;
        c.positive("max_incidence_deg", self.max_incidence_deg)?;
        c.positive("max_step_m", self.max_step_m)
    }
}

/// Distances from the gap at which ground stops are tried, every this many m.
const STEP_M: f32 = 1.0;
/// The nearest a stop is tried, m.
const NEAREST_M: f32 = 2.0;
/// The sight line leaves out the wall's own last half metre.
const SKIP_END_M: f32 = 0.5;

/// Per gap, whether it goes to the drone: no ground stop on `reach` sees it.
pub fn for_the_drone(
    missing: &[MissingPoint],
    airspace: &Airspace,
    reach: &GroundReach,
    view: &GroundView,
) -> Vec<bool> {
    use rayon::prelude::*;
    missing
        .par_iter()
        .map(|m| !ground_sees(m, airspace, reach, view))
        .collect()
}

/// Whether a ground stop could see `m`: tried along its normal and turned
/// off it by up to the incidence allowed, every [`STEP_M`] out to the range.
fn ground_sees(m: &MissingPoint, air: &Airspace, reach: &GroundReach, v: &GroundView) -> bool {
    let max = v.max_incidence_deg.min(89.0);
    let turns = [0.0, 0.5, -0.5, 1.0, -1.0].map(|f: f32| (f * max).to_radians());
    let tan_fov = v.half_fov_deg.to_radians().tan();
    let steps = ((v.range_m - NEAREST_M) / STEP_M).floor().max(0.0) as usize;
    turns.iter().any(|&a| {
        let (s, c) = a.sin_cos();
        let dir = [
            m.normal[0] * c - m.normal[1] * s,
            m.normal[0] * s + m.normal[1] * c,
        ];
        (0..=steps).any(|k| {
            let d = NEAREST_M + k as f32 * STEP_M;
            let q = [m.xyz[0] + dir[0] * d, m.xyz[1] + dir[1] * d];
            if !air.can_stand(reach, q[0], q[1]) {
                return false;
            }
            let Some(z) = air.ground_at(q[0], q[1]) else {
                return false;
            };
            let sensor = [q[0], q[1], z + v.sensor_height_m];
            (m.xyz[2] - sensor[2]).abs() <= d * tan_fov
                && air.line_of_sight(sensor, m.xyz, SKIP_END_M)
        })
    })
}
