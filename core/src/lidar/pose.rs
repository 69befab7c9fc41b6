//! Sensor poses: position plus yaw, pitch, roll.

use nalgebra::Rotation3;
use serde::{Deserialize, Serialize};

/// Where a sensor is and how it is turned, in the scene's local frame.
///
/// Angles in radians, applied as `R = Rz(yaw) · Ry(pitch) · Rx(roll)` (ROS
/// convention: x forward, y left, z up; yaw counter-clockwise from +x).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Sensor origin, metres.
    pub position: [f32; 3],
    /// Rotation about z, radians.
    pub yaw: f32,
    /// Rotation about y, radians.
    pub pitch: f32,
    /// Rotation about x, radians.
    pub roll: f32,
}

impl Pose {
    /// A level pose at `position` facing `yaw`.
    pub fn new(position: [f32; 3], yaw: f32) -> Self {
        Self {
            position,
            yaw,
            ..Self::default()
        }
    }

    /// The rotation matrix (rows) taking sensor-frame vectors to the map frame.
    pub fn rotation(&self) -> [[f32; 3]; 3] {
        // nalgebra's roll-pitch-yaw is the same `Rz(yaw) · Ry(pitch) · Rx(roll)`.
        let r = Rotation3::from_euler_angles(self.roll, self.pitch, self.yaw);
        std::array::from_fn(|i| std::array::from_fn(|j| r[(i, j)]))
    }
}

/// `m · v`.
pub(crate) fn rotate(m: &[[f32; 3]; 3], v: [f32; 3]) -> [f32; 3] {
    std::array::from_fn(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f32; 3], b: [f32; 3]) -> bool {
        (0..3).all(|k| (a[k] - b[k]).abs() < 1e-6)
    }

    #[test]
    fn yaw_pitch_roll_turn_the_axes_as_ros_does() {
        let yaw = Pose::new([0.0; 3], std::f32::consts::FRAC_PI_2).rotation();
        assert!(close(rotate(&yaw, [1.0, 0.0, 0.0]), [0.0, 1.0, 0.0]));
        let pitch = Pose {
            pitch: std::f32::consts::FRAC_PI_2,
            ..Pose::default()
        }
        .rotation();
        // Positive pitch tips the nose down.
        assert!(close(rotate(&pitch, [1.0, 0.0, 0.0]), [0.0, 0.0, -1.0]));
        let roll = Pose {
            roll: std::f32::consts::FRAC_PI_2,
            ..Pose::default()
        }
        .rotation();
        assert!(close(rotate(&roll, [0.0, 1.0, 0.0]), [0.0, 0.0, 1.0]));
    }
}
