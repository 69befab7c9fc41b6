//! The drone's part of a simulated mission (`--platforms ground,uav`): its
//! pad beside the ground robot's start, uav_planner and uav_sim with their
//! parameters, the topics the recorder keeps.

use std::path::Path;

use skyground_core::airspace::{Airspace, AirspaceRules};
use skyground_core::cloud::Cloud;
use skyground_core::crs::SourceFrame;
use skyground_core::io::load_footprints_in;
use skyground_core::lidar::Caster;
use skyground_core::scene::Scene;
use skyground_core::sorties::take_off;
use skyground_core::vehicle::Terrain;
use skyground_core::vehicle::multirotor::{Multirotor, MultirotorConfig, SceneBody};

use crate::cli::aerial::Survey;
use crate::cli::footprints::frame_params;
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

/// Kept beyond the airspace's distances when the pad is sought on the
/// prior the demo holds, m: the planner's prior is the classifier's, whose
/// building cells may reach a little farther.
const PAD_SLACK_M: f32 = 0.5;

/// The spot nearest `start` (rings from 3 m out) on the true scene's
/// ground, with room for the body there, from which the airspace over
/// `prior` lets the drone climb straight up to its transit height (the
/// rules' distances grown by [`PAD_SLACK_M`]).
fn pad_near(scene: &Scene, prior: &Cloud, start: [f32; 2]) -> Result<[f32; 2], String> {
    let caster = Caster::new(scene).map_err(|e| e.to_string())?;
    let (terrain, body) = (Terrain::new(&caster), SceneBody::new(scene));
    let cfg = MultirotorConfig::default();
    let rules = AirspaceRules::default();
    let strict = AirspaceRules {
        facade_min_m: rules.facade_min_m + PAD_SLACK_M,
        margin_m: rules.margin_m + PAD_SLACK_M,
        ..rules
    };
    let home = |p: [f32; 2], z: f32| Multirotor::new(cfg, [p[0], p[1], z], 0.0).state.position;
    let first = [start[0], start[1], 0.0];
    let mut airspace =
        Airspace::from_prior(prior, strict, cfg.radius, first).map_err(|e| e.to_string())?;
    let rings = ((PAD_MAX_M - 1.0) / PAD_RING_M) as u32;
    let mut why = String::from("no ground there");
    for p in (1..=rings).flat_map(|r| {
        (0..16).map(move |k| {
            let (s, c) = (k as f32 * std::f32::consts::TAU / 16.0).sin_cos();
            // From 3 m: the robot stands at its start.
            let d = 1.0 + r as f32 * PAD_RING_M;
            [start[0] + d * c, start[1] + d * s]
        })
    }) {
        let Some(z) = terrain.ground_height(p[0], p[1]) else {
            continue;
        };
        if body.clearance([p[0], p[1], z + 4.0 * cfg.radius]) < 2.0 * cfg.radius {
            continue;
        }
        airspace.set_home(home(p, z));
        match take_off(&airspace) {
            Ok(()) => return Ok(p),
            Err(e) => why = e.to_string(),
        }
    }
    Err(why)
}

/// uav_planner's and uav_sim's parameters: the pad the first spot beside
/// `start` on the ground with room for the body, the ground robot's start
/// for the planner's choice of gaps; the sent scans' ids into `scan_log`.
pub(super) fn nodes(
    scene: &Scene,
    prior: &Cloud,
    scene_spec: &str,
    start: [f32; 2],
    time_factor: f64,
    scan_log: &Path,
) -> Result<Vec<(&'static str, Vec<String>)>, RuntimeError> {
    let err = |e: String| RuntimeError::Node(e);
    let pad = pad_near(scene, prior, start).map_err(|why| {
        err(format!(
            "no pad for the drone within {PAD_MAX_M:.0} m of the robot's start ({:.1}, {:.1}) \
             it may climb from under the airspace's rules; the last one tried: {why}",
            start[0], start[1],
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
    let mut params = vec![format!("geofence:={}", file.display())];
    params.extend(frame_params(prior.cloud.crs.as_ref(), origin));
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
