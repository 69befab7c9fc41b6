//! PX4's odometry (NED/FRD) into the map (ENU/FLU), and the checks a message
//! must pass first: a bad one is refused with the reason, never used.

use super::frames::{
    body_to_world, flu_to_frd, ned_frd_to_enu_flu, ned_to_enu_vec, ned_to_map, world_to_body,
};

/// Why a message from or for PX4 is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Px4Error {
    /// The odometry is not in PX4's local NED frame (FRD world frames have an
    /// unknown heading; unknown is unknown).
    #[error("odometry pose_frame {0} is not NED (1)")]
    PoseFrame(u8),
    /// A position or attitude component is NaN or infinite.
    #[error("odometry {0} is not finite")]
    NotFinite(&'static str),
    /// The attitude quaternion is far from unit length.
    #[error("odometry attitude quaternion has norm {0:.3}, not 1")]
    NotUnit(f64),
    /// A way-point of a path is NaN or infinite.
    #[error("way-point {index} of {len} is not finite: ({x}, {y}, {z}), yaw {yaw}")]
    WayPoint {
        /// Its place in the path.
        index: usize,
        /// The path's length.
        len: usize,
        /// East (m).
        x: f64,
        /// North (m).
        y: f64,
        /// Up (m).
        z: f64,
        /// Heading (rad).
        yaw: f64,
    },
}

/// The fields of `px4_msgs/VehicleOdometry` the bridge reads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NedOdometry {
    /// `POSE_FRAME_*` (1 = NED).
    pub pose_frame: u8,
    /// m, NED.
    pub position: [f32; 3],
    /// Body FRD → NED, `[w, x, y, z]`.
    pub q: [f32; 4],
    /// `VELOCITY_FRAME_*` (1 = NED, 3 = body FRD).
    pub velocity_frame: u8,
    /// m/s in `velocity_frame`.
    pub velocity: [f32; 3],
    /// rad/s, body FRD.
    pub angular_velocity: [f32; 3],
}

/// The drone in the map: what nav_msgs/Odometry says.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapPose {
    /// m, map ENU.
    pub position: [f64; 3],
    /// Body FLU → map, `[w, x, y, z]`.
    pub q: [f64; 4],
    /// m/s in the body FLU frame (nav_msgs/Odometry's twist is in the child
    /// frame); zero when PX4 gives none.
    pub linear_body: [f64; 3],
    /// rad/s, body FLU; zero when PX4 gives none.
    pub angular_body: [f64; 3],
}

/// NED velocity frame, as PX4 numbers it.
const VELOCITY_NED: u8 = 1;
/// Body FRD velocity frame.
const VELOCITY_BODY_FRD: u8 = 3;

fn f64s<const N: usize>(v: [f32; N]) -> [f64; N] {
    v.map(f64::from)
}

impl NedOdometry {
    /// The pose in the map, PX4's NED origin lying at `origin` (map, m);
    /// an odometry not in NED or not finite is refused.
    pub fn to_map(&self, origin: [f64; 3]) -> Result<MapPose, Px4Error> {
        if self.pose_frame != 1 {
            return Err(Px4Error::PoseFrame(self.pose_frame));
        }
        if !self.position.iter().all(|v| v.is_finite()) {
            return Err(Px4Error::NotFinite("position"));
        }
        if !self.q.iter().all(|v| v.is_finite()) {
            return Err(Px4Error::NotFinite("attitude"));
        }
        let q = f64s(self.q);
        let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
        if (norm - 1.0).abs() > 0.01 {
            return Err(Px4Error::NotUnit(norm));
        }
        let q_enu = ned_frd_to_enu_flu(q);
        let v = f64s(self.velocity);
        let linear_body = if !v.iter().all(|c| c.is_finite()) {
            [0.0; 3]
        } else if self.velocity_frame == VELOCITY_NED {
            world_to_body(q_enu, ned_to_enu_vec(v))
        } else if self.velocity_frame == VELOCITY_BODY_FRD {
            flu_to_frd(v)
        } else {
            // World FRD has an unknown heading: no velocity rather than a wrong one.
            [0.0; 3]
        };
        let w = f64s(self.angular_velocity);
        let angular_body = if w.iter().all(|c| c.is_finite()) {
            flu_to_frd(w)
        } else {
            [0.0; 3]
        };
        Ok(MapPose {
            position: ned_to_map(f64s(self.position), origin),
            q: q_enu,
            linear_body,
            angular_body,
        })
    }
}

impl MapPose {
    /// The velocity in the map frame (m/s, ENU).
    pub fn velocity_map(&self) -> [f64; 3] {
        body_to_world(self.q, self.linear_body)
    }
}

/// A path's way-points (map position, ENU heading) as f32, or the first one
/// that is not finite.
pub fn check_path(points: &[([f64; 3], f64)]) -> Result<Vec<([f32; 3], f32)>, Px4Error> {
    points
        .iter()
        .enumerate()
        .map(|(index, &(p, yaw))| {
            if p.iter().chain([&yaw]).all(|v| v.is_finite()) {
                Ok((p.map(|v| v as f32), yaw as f32))
            } else {
                Err(Px4Error::WayPoint {
                    index,
                    len: points.len(),
                    x: p[0],
                    y: p[1],
                    z: p[2],
                    yaw,
                })
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::px4::frames::{from_yaw, yaw_of};

    fn odom() -> NedOdometry {
        NedOdometry {
            pose_frame: 1,
            position: [3.0, 4.0, -10.0],
            // Facing east in NED (yaw π/2).
            q: from_yaw(std::f64::consts::FRAC_PI_2).map(|v| v as f32),
            velocity_frame: 1,
            // 2 m/s east, 1 m/s climbing.
            velocity: [0.0, 2.0, -1.0],
            angular_velocity: [0.0, 0.0, 0.5],
        }
    }

    #[test]
    fn odometry_lands_in_the_map_with_body_velocities() {
        let m = odom().to_map([100.0, 200.0, 5.0]).unwrap();
        assert_eq!(m.position, [104.0, 203.0, 15.0]);
        assert!(yaw_of(m.q).abs() < 1e-6, "east is ENU yaw 0: {:?}", m.q);
        // Facing east and flying east: forward 2, up 1 in FLU.
        let v = m.linear_body;
        assert!(
            (v[0] - 2.0).abs() < 1e-6 && v[1].abs() < 1e-6 && (v[2] - 1.0).abs() < 1e-6,
            "{v:?}"
        );
        let w = m.velocity_map();
        assert!(
            (w[0] - 2.0).abs() < 1e-6 && (w[2] - 1.0).abs() < 1e-6,
            "{w:?}"
        );
        // Turning clockwise seen from above (FRD z+) is turning right: FLU z−.
        assert!((m.angular_body[2] + 0.5).abs() < 1e-6);
        // The same motion given in body FRD says the same.
        let body = NedOdometry {
            velocity_frame: 3,
            velocity: [2.0, 0.0, -1.0],
            ..odom()
        };
        let b = body.to_map([100.0, 200.0, 5.0]).unwrap().linear_body;
        assert!(b.iter().zip(&v).all(|(x, y)| (x - y).abs() < 1e-6), "{b:?}");
    }

    #[test]
    fn bad_odometry_is_refused_with_the_reason() {
        let o = [0.0; 3];
        let frame = NedOdometry {
            pose_frame: 2,
            ..odom()
        };
        assert_eq!(frame.to_map(o), Err(Px4Error::PoseFrame(2)));
        let nan = NedOdometry {
            position: [f32::NAN, 0.0, 0.0],
            ..odom()
        };
        assert_eq!(nan.to_map(o), Err(Px4Error::NotFinite("position")));
        let q = NedOdometry {
            q: [f32::NAN, 0.0, 0.0, 0.0],
            ..odom()
        };
        assert_eq!(q.to_map(o), Err(Px4Error::NotFinite("attitude")));
        let zero = NedOdometry {
            q: [0.0; 4],
            ..odom()
        };
        assert!(matches!(zero.to_map(o), Err(Px4Error::NotUnit(_))));
        // Unknown velocity is no velocity, not a refusal.
        let v = NedOdometry {
            velocity: [f32::NAN; 3],
            ..odom()
        };
        assert_eq!(v.to_map(o).unwrap().linear_body, [0.0; 3]);
    }

    #[test]
    fn a_path_with_a_nan_way_point_is_refused_naming_it() {
        let good = [([1.0, 2.0, 30.0], 0.5), ([4.0, 2.0, 30.0], 0.0)];
        assert_eq!(check_path(&good).unwrap()[1], ([4.0, 2.0, 30.0], 0.0));
        let bad = [good[0], ([f64::NAN, 2.0, 30.0], 0.0)];
        let e = check_path(&bad).unwrap_err();
        assert!(
            matches!(
                e,
                Px4Error::WayPoint {
                    index: 1,
                    len: 2,
                    ..
                }
            ),
            "{e}"
        );
        assert!(
            e.to_string().contains("way-point 1 of 2 is not finite"),
            "{e}"
        );
        let yaw = [([0.0; 3], f64::INFINITY)];
        assert!(check_path(&yaw).is_err());
    }
}
