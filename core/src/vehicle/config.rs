//! Vehicle limits and shape.

use serde::Deserialize;

/// Limits and shape of the ground vehicle (the `vehicle.*` params of vehicle_sim).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct VehicleConfig {
    /// Top speed, m/s.
    pub max_speed: f32,
    /// Top yaw rate, rad/s.
    pub max_yaw_rate: f32,
    /// Steepest slope it drives up or down, degrees.
    pub max_incline_deg: f32,
    /// Body radius, m: obstacles closer than this to its path block it.
    pub radius: f32,
    /// Body height, m: obstacles above it (tree crowns, raised floors) do not block.
    pub body_height: f32,
    /// LiDAR height above the ground, m.
    pub sensor_height: f32,
    /// Distance at which a way-point counts as reached, m.
    pub goal_tolerance: f32,
}

impl Default for VehicleConfig {
    fn default() -> Self {
        Self {
            max_speed: 2.0,
            max_yaw_rate: 1.2,
            max_incline_deg: 20.0,
            radius: 0.5,
            body_height: 1.6,
            sensor_height: 1.8,
            goal_tolerance: 0.5,
        }
    }
}
