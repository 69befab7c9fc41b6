//! The drone's part of a simulated mission (`--platforms ground,uav`): its
//! pad beside the ground robot's start, uav_planner and uav_sim with their
//! parameters, the topics the recorder keeps.

use std::path::Path;

use skyground_core::airspace::AirspaceRules;
use skyground_core::crs::SourceFrame;
use skyground_core::io::load_footprints_in;
use skyground_core::lidar::Caster;
use skyground_core::scene::Scene;
use skyground_core::vehicle::Terrain;
use skyground_core::vehicle::multirotor::{MultirotorConfig, SceneBody};

use crate::cli::aerial::Survey;
use crate::runtime::RuntimeError;

/// The drone's topics in the bag (its scans one in 50, as the robot's).
pub(super) const TOPICS: &[&str] = &[
    "/uav/state_estimation:nav_msgs/msg/Odometry",
    "/uav/global_path:nav_msgs/msg/Path",
    "/uav/planner_status:diagnostic_msgs/msg/DiagnosticArray",
    "/uav/flight_status:diagnostic_msgs/msg/DiagnosticArray",
    "/uav/registered_scan_throttle:sensor_msgs/msg/PointCloud2",
];

/// The pad is sought on rings round the robot's start this far apart, m,
/// from 3 m out to [`PAD_MAX_M`], 16 bearings each.
const PAD_RING_M: f32 = 2.0;
/// The farthest from the robot's start the pad is sought, m.
const PAD_MAX_M: f32 = 30.0;

/// The first spot nearest `start` on the ground where the drone may take
/// off under the airspace's rules: nothing within the distance kept from
/// facades (the rules' `facade_min_m`, and the body plus its margin from
/// anything else) around the column it climbs.
fn pad_near(terrain: &Terrain, body: &SceneBody, start: [f32; 2]) -> Option<[f32; 2]> {
    let (cfg, rules) = (MultirotorConfig::default(), AirspaceRules::default());
    let kept = rules.facade_min_m.max(cfg.radius + rules.margin_m) + rules.cell_m;
    let rings = ((PAD_MAX_M - 1.0) / PAD_RING_M) as u32;
    (1..=rings)
        .flat_map(|r| {
            (0..16).map(move |k| {
                let (s, c) = (k as f32 * std::f32::consts::TAU / 16.0).sin_cos();
                // From 3 m: the robot stands at its start.
                let d = 1.0 + r as f32 * PAD_RING_M;
                [start[0] + d * c, start[1] + d * s]
            })
        })
        .find(|p| {
            // Measured above the ground by more than `kept`, the terrain
            // itself is not what is too near.
            terrain.ground_height(p[0], p[1]).is_some_and(|z| {
                [1.0, 2.0, 4.0]
                    .iter()
                    .all(|&up| body.clearance([p[0], p[1], z + kept + up]) >= kept)
            })
        })
}

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
    let pad = pad_near(&terrain, &body, start).ok_or_else(|| {
        err(format!(
            "no room for the drone's pad within {PAD_MAX_M:.0} m of the robot's start ({:.1}, {:.1}): \
             the airspace keeps {:.1} m from facades",
            start[0],
            start[1],
            AirspaceRules::default().facade_min_m
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

/// uav_planner's `geofence:=`, `crs:=`, `origin:=` for `--geofence FILE`
/// (none without one), after reading FILE in the prior's frame so that a
/// file that cannot be used, or one in another CRS, stops the demo here.
pub(super) fn fence_params(
    file: Option<&Path>,
    prior: &Survey,
) -> Result<Vec<String>, RuntimeError> {
    let Some(file) = file else {
        return Ok(Vec::new());
    };
    let origin = prior.scene.origin;
    let frame = SourceFrame::new(origin, prior.cloud.crs.clone());
    let loaded = load_footprints_in(file, &frame)
        .map_err(|e| RuntimeError::Node(format!("--geofence {}: {e}", file.display())))?;
    for s in &loaded.skipped {
        eprintln!("--geofence {}: {s}", file.display());
    }
    let mut params = vec![
        format!("geofence:={}", file.display()),
        format!("origin:=[{}, {}, {}]", origin[0], origin[1], origin[2]),
    ];
    if let Some(code) = prior.cloud.crs.as_ref().and_then(|c| c.epsg) {
        params.push(format!("crs:=EPSG:{code}"));
    }
    Ok(params)
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
