//! Poses ↔ the tf tree (`tf2_msgs/TFMessage` on `/tf` and `/tf_static`).

use skyground_msgs::builtin_interfaces::Time;
use skyground_msgs::geometry_msgs::{Quaternion, Transform, TransformStamped, Vector3};
use skyground_msgs::std_msgs::Header;
use skyground_msgs::tf2_msgs::TFMessage;

/// The rotation by `yaw` radians about z.
pub fn yaw_quaternion(yaw: f32) -> Quaternion {
    let h = f64::from(yaw) / 2.0;
    Quaternion {
        x: 0.0,
        y: 0.0,
        z: h.sin(),
        w: h.cos(),
    }
}

/// The yaw (rotation about z) of a quaternion, radians.
pub fn quaternion_yaw(q: &Quaternion) -> f32 {
    (2.0 * (q.w * q.z + q.x * q.y)).atan2(1.0 - 2.0 * (q.y * q.y + q.z * q.z)) as f32
}

/// One edge of the tree: `child` at `xyz`, turned by `yaw`, in `header`'s frame.
pub fn transform(header: &Header, child: &str, xyz: [f64; 3], yaw: f32) -> TransformStamped {
    TransformStamped {
        header: header.clone(),
        child_frame_id: child.to_string(),
        transform: Transform {
            translation: Vector3 {
                x: xyz[0],
                y: xyz[1],
                z: xyz[2],
            },
            rotation: yaw_quaternion(yaw),
        },
    }
}

/// A `/tf` or `/tf_static` message of one transform.
pub fn tf_message(t: TransformStamped) -> TFMessage {
    TFMessage {
        transforms: vec![t],
    }
}

/// The static edge `body` → `sensor`, `height` metres above the body
/// frame's origin (stamped 0), as a `/tf_static` message.
pub fn sensor_mount(body: &str, sensor: &str, height: f32) -> TFMessage {
    let header = Header {
        stamp: Time::from_secs(0.0),
        frame_id: body.to_string(),
    };
    let above = [0.0, 0.0, f64::from(height)];
    tf_message(transform(&header, sensor, above, 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn yaw_survives_the_quaternion() {
        for yaw in [-3.0f32, -1.2, 0.0, 0.7, 2.9] {
            let q = yaw_quaternion(yaw);
            assert!((quaternion_yaw(&q) - yaw).abs() < 1e-5, "{yaw}");
            let norm = q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w;
            assert!((norm - 1.0).abs() < 1e-9);
        }
    }

    #[test]
    fn transform_names_parent_and_child() {
        let h = Header {
            frame_id: "map".into(),
            ..Header::default()
        };
        let t = transform(&h, "base_link", [1.0, 2.0, 3.0], 0.5);
        assert_eq!(t.header.frame_id, "map");
        assert_eq!(t.child_frame_id, "base_link");
        assert_eq!(t.transform.translation.y, 2.0);
        assert!((quaternion_yaw(&t.transform.rotation) - 0.5).abs() < 1e-6);
    }

    #[test]
    fn the_sensor_mount_is_one_static_edge_above_the_body() {
        let m = sensor_mount("base_link", "sensor", 0.75);
        let [t] = m.transforms.as_slice() else {
            panic!("one transform: {m:?}");
        };
        assert_eq!(
            (t.header.frame_id.as_str(), t.child_frame_id.as_str()),
            ("base_link", "sensor")
        );
        assert_eq!((t.header.stamp.sec, t.header.stamp.nanosec), (0, 0));
        assert_eq!(t.transform.translation.z, 0.75);
        assert_eq!(t.transform.rotation.w, 1.0);
    }
}
