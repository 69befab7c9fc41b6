//! px4_msgs ↔ the library's PX4 values ([`skyground_core::px4`]) and the ROS
//! messages the drone is seen by (map ENU).

use skyground_core::px4::{Command, MapPose, NedOdometry, Setpoint};
use skyground_msgs::geometry_msgs::{Quaternion, Transform, TransformStamped, Vector3};
use skyground_msgs::nav_msgs::{Odometry, Path};
use skyground_msgs::px4_msgs::{
    OffboardControlMode, TrajectorySetpoint, VehicleCommand, VehicleOdometry, VehicleStatus,
};
use skyground_msgs::std_msgs::Header;

/// A path's poses: map position and ENU heading (from each orientation),
/// unchecked (NaN passes through, for `check_path` to refuse).
pub fn path_poses(p: &Path) -> Vec<([f64; 3], f64)> {
    p.poses
        .iter()
        .map(|ps| {
            let (q, o) = (&ps.pose.position, &ps.pose.orientation);
            let yaw = (2.0 * (o.w * o.z + o.x * o.y)).atan2(1.0 - 2.0 * (o.y * o.y + o.z * o.z));
            ([q.x, q.y, q.z], yaw)
        })
        .collect()
}

/// The fields of PX4's odometry the bridge reads.
pub fn ned_odometry(o: &VehicleOdometry) -> NedOdometry {
    NedOdometry {
        pose_frame: o.pose_frame,
        position: o.position,
        q: o.q,
        velocity_frame: o.velocity_frame,
        velocity: o.velocity,
        angular_velocity: o.angular_velocity,
    }
}

/// Armed, and in offboard, as PX4's status says.
pub fn armed_offboard(s: &VehicleStatus) -> (bool, bool) {
    (
        s.arming_state == VehicleStatus::ARMING_STATE_ARMED,
        s.nav_state == VehicleStatus::NAVIGATION_STATE_OFFBOARD,
    )
}

fn quaternion(q: [f64; 4]) -> Quaternion {
    Quaternion {
        w: q[0],
        x: q[1],
        y: q[2],
        z: q[3],
    }
}

fn vector(v: [f64; 3]) -> Vector3 {
    Vector3 {
        x: v[0],
        y: v[1],
        z: v[2],
    }
}

/// nav_msgs/Odometry of the drone in `header.frame_id` (twist in `child`).
pub fn odometry(header: Header, child: &str, m: &MapPose) -> Odometry {
    let mut o = Odometry {
        header,
        child_frame_id: child.into(),
        ..Odometry::default()
    };
    let p = &mut o.pose.pose.position;
    (p.x, p.y, p.z) = (m.position[0], m.position[1], m.position[2]);
    o.pose.pose.orientation = quaternion(m.q);
    o.twist.twist.linear = vector(m.linear_body);
    o.twist.twist.angular = vector(m.angular_body);
    o
}

/// The /tf edge map → `child` of the drone (full attitude, not only yaw).
pub fn transform(header: Header, child: &str, m: &MapPose) -> TransformStamped {
    TransformStamped {
        header,
        child_frame_id: child.into(),
        transform: Transform {
            translation: vector(m.position),
            rotation: quaternion(m.q),
        },
    }
}

/// The heartbeat (position control) and its setpoint, stamped `us` (µs).
pub fn heartbeat(s: &Setpoint, us: u64) -> (OffboardControlMode, TrajectorySetpoint) {
    let mode = OffboardControlMode {
        timestamp: us,
        position: true,
        ..OffboardControlMode::default()
    };
    let sp = TrajectorySetpoint {
        timestamp: us,
        position: s.ned,
        // NaN: not controlled, PX4's position controller makes them.
        velocity: [f32::NAN; 3],
        acceleration: [f32::NAN; 3],
        jerk: [f32::NAN; 3],
        yaw: s.yaw,
        yawspeed: f32::NAN,
    };
    (mode, sp)
}

/// A VehicleCommand for PX4's system and component 1, from an external source.
pub fn command(c: Command, us: u64) -> VehicleCommand {
    let (command, param1, param2) = c.mavlink();
    VehicleCommand {
        timestamp: us,
        param1,
        param2,
        command,
        target_system: 1,
        target_component: 1,
        source_system: 1,
        source_component: 1,
        from_external: true,
        ..VehicleCommand::default()
    }
}
