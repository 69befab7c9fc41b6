//! uav_planner: /classified_cloud (the prior) + the first /missing_points +
//! the drone's pose on its pad (/uav/state_estimation) → the gaps no
//! ground stop sees, their viewpoints and the sorties that fly them
//! (`sorties::for_detection`) → /uav/global_path (every sortie, home to
//! home, latched) and /uav/planner_status (counts, latched). It plans once,
//! on the prior's detection; the ground robot's rounds re-detect.

use futures::StreamExt;
use serde::Deserialize;
use skyground_core::airspace::{AirspaceRules, Geofence, geofence};
use skyground_core::cloud::Cloud;
use skyground_core::missing::MissingPoint;
use skyground_core::mission::uav::UavPlan;
use skyground_core::sorties::{GroundView, SortieParams, for_detection};
use skyground_core::vehicle::multirotor::MultirotorConfig;
use skyground_msgs::diagnostic_msgs::DiagnosticArray;
use skyground_msgs::nav_msgs::{Odometry, Path};
use skyground_msgs::std_msgs::Header;

use crate::convert::areas::load_logged;
use crate::convert::detection::missing_from_message;
use crate::convert::diagnostics::array;
use crate::convert::path::{odom_position, path};
use crate::runtime::{NodeRuntime, RuntimeError, publish_logged, qos};
use crate::transport::{CloudSubscription, TransportConfig};

/// The `geofence` param's polygons in the clouds' frame, `None` when blank;
/// a file that cannot be read stops the node with the reason.
fn read_fence(rt: &NodeRuntime, p: &Params) -> Result<Option<Geofence>, RuntimeError> {
    if p.geofence.trim().is_empty() {
        return Ok(None);
    }
    let frame = ("", p.crs.as_str(), p.origin.as_slice());
    let areas = load_logged(&rt.log, "geofence", &p.geofence, frame)?;
    Ok(Some(geofence(&areas)))
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    frame_id: String,
    /// Where the ground robot starts, [x, y]: the ground joined to it is
    /// what its stops can stand on.
    ground_start: Vec<f64>,
    /// A GeoJSON of the area(s) the drone must stay inside, blank: none;
    /// read in `crs` (`EPSG:N`, blank: the file's own) and moved by `origin`
    /// into the clouds' local frame, as the detector reads footprints.
    geofence: String,
    crs: String,
    origin: Vec<f64>,
    multirotor: MultirotorConfig,
    airspace: AirspaceRules,
    sorties: SortieParams,
    ground_view: GroundView,
    transport: TransportConfig,
}

pub use crate::runtime::specs::UAV_PLANNER as SPEC;

/// Runs the node until asked to stop.
pub async fn run(rt: &mut NodeRuntime) -> Result<(), RuntimeError> {
    let p: Params = rt.params()?;
    let &[sx, sy] = p.ground_start.as_slice() else {
        return Err(RuntimeError::Node(format!(
            "ground_start {:?}: give [x, y]",
            p.ground_start
        )));
    };
    let fence = read_fence(rt, &p)?;
    let tile = p.transport.tile_points;
    let mut cloud_sub = CloudSubscription::new(rt, "/classified_cloud", qos::latched(256), tile)?;
    let mut missing_sub = CloudSubscription::new(rt, "/missing_points", qos::latched(64), tile)?;
    let odom_sub = rt.subscription::<Odometry>("/uav/state_estimation", qos::odometry())?;
    let path_pub = rt.publisher::<Path>("/uav/global_path", qos::latched(1))?;
    let status_pub = rt.publisher::<DiagnosticArray>("/uav/planner_status", qos::latched(1))?;
    let odom_s = odom_sub.async_stream();
    futures::pin_mut!(odom_s);
    let mut prior: Option<Cloud> = None;
    let mut missing: Option<Vec<MissingPoint>> = None;
    let mut home: Option<[f32; 3]> = None;
    rt.log.info(
        "waiting for /classified_cloud, /missing_points and the drone on /uav/state_estimation",
    );
    loop {
        tokio::select! {
            _ = rt.shutdown.wait() => break,
            r = cloud_sub.next_cloud(&rt.log) => match r {
                Some(Some((_, d))) => prior = Some(d.cloud),
                Some(None) => {}
                None => break,
            },
            r = missing_sub.next_cloud(&rt.log) => match r {
                Some(Some((_, d))) => match missing_from_message(&d) {
                    Ok(points) => missing = missing.or(Some(points)),
                    Err(e) => rt.log.error(&e),
                },
                Some(None) => {}
                None => break,
            },
            Some(m) = odom_s.next() => if home.is_none() {
                home = m.ok().and_then(|(o, _)| odom_position(&o));
            },
        }
        let (Some(cloud), Some(points), Some(at)) = (&prior, &missing, home) else {
            continue;
        };
        let cloud = cloud.clone();
        let points = points.clone();
        let start = [sx as f32, sy as f32];
        let (cfg, rules, sp, view, fence) = (
            p.multirotor,
            p.airspace,
            p.sorties.clone(),
            p.ground_view.clone(),
            fence.clone(),
        );
        let t0 = std::time::Instant::now();
        let planned = tokio::task::spawn_blocking(move || {
            let rules = (&cfg, &rules, fence.as_ref());
            for_detection(&cloud, &points, (at, start), rules, (&sp, &view))
        })
        .await
        .map_err(|e| RuntimeError::Node(format!("sortie planning: {e}")))?;
        let (way, counts) = match planned {
            Ok((plan, counts)) => {
                if let Some(why) = &plan.why_unreachable {
                    rt.log.warn(&format!(
                        "{} viewpoint(s) no sortie reaches; the first: {why}",
                        plan.unreachable.len()
                    ));
                }
                let way: Vec<[f32; 3]> = plan.sorties.iter().flat_map(|s| s.path.clone()).collect();
                (way, counts)
            }
            Err(e) => (
                Vec::new(),
                UavPlan {
                    refused: e.to_string(),
                    ..UavPlan::default()
                },
            ),
        };
        rt.log.info(&format!(
            "{} of {} gaps are the drone's: {} viewpoints see {}, {} sortie(s), {:.0} s of flight, {} viewpoint(s) unreachable; planned in {:.1} s{}",
            counts.drone_gaps, counts.gaps, counts.viewpoints, counts.seen, counts.sorties,
            counts.flight_s, counts.unreachable, t0.elapsed().as_secs_f64(),
            if counts.refused.is_empty() { String::new() } else { format!("; refused: {}", counts.refused) }
        ));
        let h = Header {
            stamp: rt.now(),
            frame_id: p.frame_id.clone(),
        };
        let sent = status_pub.async_publish(array(h.clone(), counts.to_wire()));
        publish_logged(&rt.log, "/uav/planner_status", sent).await;
        publish_logged(
            &rt.log,
            "/uav/global_path",
            path_pub.async_publish(path(&h, &way)),
        )
        .await;
        // Planned once: the node stays to keep its latched outputs for late readers.
        rt.shutdown.wait().await;
        break;
    }
    Ok(())
}
