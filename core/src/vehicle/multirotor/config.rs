//! Limits, body and battery of the simulated multirotor.

use serde::{Deserialize, Serialize};

use crate::params::{Checks, ParamError};

/// Limits and shape of the multirotor (the `uav.*` params); every field has
/// a default (a survey quadcopter of ~2 kg carrying a Mid-360-class LiDAR).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MultirotorConfig {
    /// Top horizontal speed, m/s.
    pub max_speed: f32,
    /// Top climb rate, m/s.
    pub max_climb: f32,
    /// Top descent rate, m/s (slower than the climb: descending into its
    /// own downwash is what a multirotor does worst).
    pub max_descent: f32,
    /// Top acceleration, m/s².
    pub max_accel: f32,
    /// Top yaw rate, rad/s.
    pub max_yaw_rate: f32,
    /// Radius of the body sphere (rotor tips included), m.
    pub radius: f32,
    /// Distance at which a way-point counts as reached, m.
    pub goal_tolerance: f32,
    /// Flight time of a full battery, s.
    pub battery_s: f32,
    /// Flight time kept in reserve to reach home, s: a sortie is planned to
    /// end with at least this much left.
    pub reserve_s: f32,
    /// The LiDAR's offset below the body centre, m (mounted under it).
    pub sensor_drop: f32,
}

impl Default for MultirotorConfig {
    fn default() -> Self {
        Self {
            max_speed: 5.0,
            max_climb: 3.0,
            max_descent: 2.0,
            max_accel: 2.5,
            max_yaw_rate: 1.5,
            radius: 0.6,
            goal_tolerance: 0.5,
            battery_s: 1200.0,
            reserve_s: 120.0,
            sensor_drop: 0.15,
        }
    }
}

impl MultirotorConfig {
    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), ParamError> {
        let c = Checks("multirotor");
        c.positive("max_speed", self.max_speed)?;
        c.positive("max_climb", self.max_climb)?;
        c.positive("max_descent", self.max_descent)?;
        c.positive("max_accel", self.max_accel)?;
        c.positive("max_yaw_rate", self.max_yaw_rate)?;
        c.positive("radius", self.radius)?;
        c.positive("goal_tolerance", self.goal_tolerance)?;
        c.positive("battery_s", self.battery_s)?;
        c.that(
            self.reserve_s >= 0.0 && self.reserve_s < self.battery_s,
            "reserve_s",
            self.reserve_s,
            "must be ≥ 0 and < battery_s",
        )?;
        c.non_negative("sensor_drop", self.sensor_drop)
    }

    /// Flight time a sortie may plan for, s.
    pub fn sortie_s(&self) -> f32 {
        self.battery_s - self.reserve_s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_pass_and_a_reserve_beyond_the_battery_is_refused() {
        MultirotorConfig::default().validate().unwrap();
        let bad = MultirotorConfig {
            reserve_s: 1300.0,
            ..MultirotorConfig::default()
        };
        let e = bad.validate().unwrap_err().to_string();
        assert!(e.contains("reserve_s"), "{e}");
    }
}
