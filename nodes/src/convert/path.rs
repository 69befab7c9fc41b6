//! nav_msgs/Path, odometry and geometry_msgs/PointStamped helpers.

use skyground_core::vehicle::VehicleState;
use skyground_msgs::geometry_msgs::{Point, PointStamped, PoseStamped};
use skyground_msgs::nav_msgs::{Odometry, Path};
use skyground_msgs::std_msgs::Header;
use tokio::sync::mpsc;

use crate::convert::tf::yaw_quaternion;
use crate::runtime::{NodeRuntime, RuntimeError, forward, qos};

/// A Path through `pts` (orientation identity), every pose with `header`.
pub fn path(header: &Header, pts: &[[f32; 3]]) -> Path {
    Path {
        header: header.clone(),
        poses: pts
            .iter()
            .map(|p| {
                let mut ps = PoseStamped {
                    header: header.clone(),
                    ..PoseStamped::default()
                };
                ps.pose.position.x = f64::from(p[0]);
                ps.pose.position.y = f64::from(p[1]);
                ps.pose.position.z = f64::from(p[2]);
                ps.pose.orientation.w = 1.0;
                ps
            })
            .collect(),
    }
}

/// The positions of a Path.
pub fn path_points(p: &Path) -> Vec<[f32; 3]> {
    p.poses
        .iter()
        .map(|ps| {
            let q = &ps.pose.position;
            [q.x as f32, q.y as f32, q.z as f32]
        })
        .collect()
}

/// The position of an odometry message, when finite.
pub fn odom_position(o: &Odometry) -> Option<[f32; 3]> {
    let q = &o.pose.pose.position;
    let p = [q.x as f32, q.y as f32, q.z as f32];
    p.iter().all(|v| v.is_finite()).then_some(p)
}

/// Odometry of a vehicle state in `header.frame_id`, body frame `child`.
pub fn odometry(header: Header, child: &str, s: &VehicleState) -> Odometry {
    let mut o = Odometry {
        header,
        child_frame_id: child.into(),
        ..Odometry::default()
    };
    o.pose.pose.position.x = f64::from(s.position[0]);
    o.pose.pose.position.y = f64::from(s.position[1]);
    o.pose.pose.position.z = f64::from(s.position[2]);
    o.pose.pose.orientation = yaw_quaternion(s.yaw);
    o.twist.twist.linear.x = f64::from(s.speed);
    o.twist.twist.angular.z = f64::from(s.yaw_rate);
    o
}

/// Reads Paths from every topic of `topics` into `tx` (as their points); a
/// latched route (/global_path, /uav/global_path) is read as latched, legs
/// as they come.
pub fn read_paths(
    rt: &mut NodeRuntime,
    topics: &[String],
    tx: &mpsc::Sender<Vec<[f32; 3]>>,
) -> Result<(), RuntimeError> {
    for topic in topics {
        let q = if topic.ends_with("/global_path") {
            qos::latched(1)
        } else {
            qos::reliable(10)
        };
        forward(rt, topic, q, tx.clone(), path_points)?;
    }
    Ok(())
}

/// A PointStamped at `at` (a way-point, a set-down spot).
pub fn point_stamped(header: Header, at: [f32; 3]) -> PointStamped {
    let [x, y, z] = at.map(f64::from);
    PointStamped {
        header,
        point: Point { x, y, z },
    }
}

/// Reads PointStamped messages on `topic` into a channel of `depth`, as
/// their plan positions, in order.
pub fn read_spots(
    rt: &mut NodeRuntime,
    topic: &str,
    qos: ros2_client::QosProfile,
    depth: usize,
) -> Result<mpsc::Receiver<[f32; 2]>, RuntimeError> {
    let (tx, rx) = mpsc::channel(depth);
    forward(rt, topic, qos, tx, |m: &PointStamped| {
        [m.point.x as f32, m.point.y as f32]
    })?;
    Ok(rx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_round_trip() {
        let pts = vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]];
        let p = path(&Header::default(), &pts);
        assert_eq!(p.poses[1].pose.orientation.w, 1.0);
        assert_eq!(path_points(&p), pts);
    }

    #[test]
    fn a_point_stamped_keeps_its_header() {
        let h = Header {
            frame_id: "map".into(),
            ..Header::default()
        };
        let m = point_stamped(h, [1.5, -2.0, 3.25]);
        assert_eq!(m.header.frame_id, "map");
        assert_eq!([m.point.x, m.point.y, m.point.z], [1.5, -2.0, 3.25]);
    }
}
