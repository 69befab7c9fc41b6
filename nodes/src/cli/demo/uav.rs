//! The drone's part of a simulated mission (`--platforms ground,uav`): its
//! pad beside the ground robot's start, uav_planner and uav_sim with their
//! parameters, the topics the recorder keeps.

use std::path::Path;

use skyground_core::lidar::Caster;
use skyground_core::scene::Scene;
use skyground_core::vehicle::Terrain;
use skyground_core::vehicle::multirotor::{MultirotorConfig, SceneBody};

use crate::runtime::RuntimeError;

/// The drone's topics in the bag (its scans one in 50, as the robot's).
pub(super) const TOPICS: &[&str] = &[
    "/uav/state_estimation:nav_msgs/msg/Odometry",
    "/uav/global_path:nav_msgs/msg/Path",
    "/uav/planner_status:diagnostic_msgs/msg/DiagnosticArray",
    "/uav/flight_status:diagnostic_msgs/msg/DiagnosticArray",
    "/uav/registered_scan_throttle:sensor_msgs/msg/PointCloud2",
];

/// How far from the robot's start the pad is sought, m, in this order.
const PAD_OFFSETS: [[f32; 2]; 8] = [
    [3.0, 0.0],
    [0.0, 3.0],
    [-3.0, 0.0],
    [0.0, -3.0],
    [5.0, 5.0],
    [-5.0, 5.0],
    [-5.0, -5.0],
    [5.0, -5.0],
];

/// uav_planner's and uav_sim's parameters: the pad the first spot beside
/// `start` on the ground with room for the body, the ground robot's start
/// for the planner's choice of gaps; the sent scans' ids into `scan_log`.
pub(super) fn nodes(
    scene: &Scene,
    scene_spec: &str,
    start: [f32; 2],
    time_factor: f64,
    scan_log: &Path,
) -> Result<Vec<(&'static str, Vec<String>)>, RuntimeError> {
    let err = |e: String| RuntimeError::Node(e);
    let caster = Caster::new(scene).map_err(|e| err(e.to_string()))?;
    let terrain = Terrain::new(&caster);
    let body = SceneBody::new(scene);
    let room = 2.0 * MultirotorConfig::default().radius;
    let pad = PAD_OFFSETS
        .iter()
        .map(|o| [start[0] + o[0], start[1] + o[1]])
        .find(|p| {
            terrain
                .ground_height(p[0], p[1])
                .is_some_and(|z| body.clearance([p[0], p[1], z + 2.0 * room]) >= room)
        })
        .ok_or_else(|| {
            err(format!(
                "no room for the drone's pad within 7 m of the robot's start ({:.1}, {:.1})",
                start[0], start[1]
            ))
        })?;
    Ok(vec![
        (
            "uav_planner",
            vec![format!("ground_start:=[{}, {}]", start[0], start[1])],
        ),
        (
            "uav_sim",
            vec![
                format!("scene:={scene_spec}"),
                format!("pad:=[{}, {}]", pad[0], pad[1]),
                format!("time_factor:={time_factor}"),
                format!("scan_log:={}", scan_log.display()),
            ],
        ),
    ])
}

/// The ground robot's start from vehicle_sim's `start:=[x, y]` argument.
pub(super) fn start_of(driver_args: &[String]) -> Option<[f32; 2]> {
    let v = driver_args.iter().find_map(|a| a.strip_prefix("start:="))?;
    let xy: Vec<f32> = v
        .trim_matches(|c| c == '[' || c == ']')
        .split(',')
        .map(|t| t.trim().parse().ok())
        .collect::<Option<_>>()?;
    (xy.len() == 2).then(|| [xy[0], xy[1]])
}
