//! local_explorer: TARE-style exploration of the region the global planner
//! hands over on /active_region (docs/design.md step 7): viewpoints on the ground
//! graph inside it, scored by the missing wall they would see, visited in a
//! short tour on /local_path until the gain per metre runs out; then "done"
//! on /explorer_status. Every building point the vehicle scans is merged
//! (voxel de-duplicated) into /resampled_cloud.

use std::sync::Arc;
use std::time::Duration;

use futures::StreamExt;
use serde::Deserialize;
use skyground_core::cloud::{Cloud, class};
use skyground_core::explore::{ExploreParams, Explorer, VoxelMerge};
use skyground_core::graph::{GraphParams, GroundGraph};
use skyground_core::targets::Region;
use skyground_msgs::diagnostic_msgs::{DiagnosticArray, DiagnosticStatus};
use skyground_msgs::nav_msgs::{Odometry, Path};
use skyground_msgs::pointcloud2::{EncodeOptions, decode, encode};
use skyground_msgs::sensor_msgs::PointCloud2;
use skyground_msgs::std_msgs::Header;
use skyground_msgs::visualization_msgs::MarkerArray;

use crate::convert::diagnostics::{kv, status, value};
use crate::convert::markers::markers_to_regions;
use crate::convert::path::{odom_position, path};
use crate::runtime::{NodeRuntime, NodeSpec, RuntimeError, qos};
use crate::transport::{CloudPublisher, CloudSubscription, Received, TransportConfig};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    #[serde(default)]
    graph: GraphParams,
    #[serde(default)]
    explore: ExploreParams,
    /// Missing points of the region's building within this distance of the
    /// region are the surface to cover, m.
    surface_margin_m: f64,
    /// Also publish /resampled_cloud when each region is done (for viewers).
    publish_each_region: bool,
    /// Edge of the de-duplication voxels of /resampled_cloud, m.
    resample_voxel_m: f32,
    /// Viewpoints the vehicle is blocked on this many times end the region.
    block_retries: u32,
    transport: TransportConfig,
}

/// Name and default params.
pub const SPEC: NodeSpec = NodeSpec {
    name: "local_explorer",
    default_params: include_str!("../../../config/local_explorer.yaml"),
    live: &[],
};

struct Active {
    region: Region,
    index: usize,
    round: u32,
    explorer: Explorer,
    goal: Option<[f32; 3]>,
    pending: Vec<[f32; 3]>,
    blocked: u32,
    stops: u32,
}

fn header(rt: &NodeRuntime) -> Header {
    Header {
        stamp: rt.now(),
        frame_id: "map".into(),
    }
}

fn dist_to_polygon(poly: &[[f64; 2]], p: [f64; 2]) -> f64 {
    if skyground_core::graph::polygon_contains(poly, p) {
        return 0.0;
    }
    let mut best = f64::INFINITY;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let l2 = dx * dx + dy * dy;
        let t = if l2 > 0.0 {
            (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (x, y) = (a[0] + t * dx - p[0], a[1] + t * dy - p[1]);
        best = best.min((x * x + y * y).sqrt());
    }
    best
}

/// Runs the node until asked to stop.
pub async fn run(rt: &mut NodeRuntime) -> Result<(), RuntimeError> {
    let p: Params = rt.params()?;
    p.graph
        .validate()
        .map_err(|e| RuntimeError::Node(format!("graph params: {e}")))?;
    p.explore
        .validate()
        .map_err(|e| RuntimeError::Node(format!("explore params: {e}")))?;
    let mut merged =
        VoxelMerge::new(p.resample_voxel_m).map_err(|e| RuntimeError::Node(e.to_string()))?;
    let mut cloud_sub = CloudSubscription::new(
        rt,
        "/classified_cloud",
        qos::latched(256),
        p.transport.tile_points,
    )?;
    let mut missing_sub = CloudSubscription::new(
        rt,
        "/missing_points",
        qos::latched(64),
        p.transport.tile_points,
    )?;
    let region_sub = rt.subscription::<MarkerArray>("/active_region", qos::latched(1))?;
    let scan_sub = rt.subscription::<PointCloud2>("/registered_scan", qos::sensor(50))?;
    let odom_sub = rt.subscription::<Odometry>("/state_estimation", qos::reliable(10))?;
    let vstatus_sub = rt.subscription::<DiagnosticArray>("/vehicle_status", qos::reliable(50))?;
    let pstatus_sub = rt.subscription::<DiagnosticArray>("/planner_status", qos::latched(1))?;
    let leg_pub = rt.publisher::<Path>("/local_path", qos::reliable(10))?;
    let status_pub = rt.publisher::<DiagnosticArray>("/explorer_status", qos::latched(1))?;
    let resampled_pub = CloudPublisher::new(rt, "/resampled_cloud", qos::latched(1), p.transport)?;
    let region_s = region_sub.async_stream();
    let scan_s = scan_sub.async_stream();
    let odom_s = odom_sub.async_stream();
    let vstatus_s = vstatus_sub.async_stream();
    let pstatus_s = pstatus_sub.async_stream();
    futures::pin_mut!(region_s, scan_s, odom_s, vstatus_s, pstatus_s);
    let mut tick = tokio::time::interval(Duration::from_millis(500));

    let mut classified: Option<Cloud> = None;
    let mut graph: Option<Arc<GroundGraph>> = None;
    let mut missing: Vec<([f32; 3], u32)> = Vec::new();
    let mut position: Option<[f32; 3]> = None;
    let mut active: Option<Active> = None;
    let mut requested: Option<(Region, usize, u32)> = None;
    let mut last_done: Option<(usize, u32, f64)> = None;
    let mut published_rounds: Vec<u32> = Vec::new();
    rt.log.info("waiting for /active_region");
    loop {
        let mut arrived_at: Option<bool> = None;
        tokio::select! {
            _ = rt.shutdown.wait() => break,
            r = cloud_sub.next() => match r {
                Some(Received::Cloud { decoded, .. }) if decoded.cloud.label.is_some() => {
                    classified = Some(decoded.cloud);
                    graph = None;
                }
                Some(Received::Cloud { .. }) => rt.log.error("/classified_cloud has no `label` field"),
                Some(Received::Bad(reason)) => rt.log.error(&format!("rejected /classified_cloud: {reason}")),
                None => break,
            },
            r = missing_sub.next() => match r {
                Some(Received::Cloud { decoded, .. }) => {
                    let c = decoded.cloud;
                    let ids = c.building.clone().unwrap_or_else(|| vec![0; c.len()]);
                    missing = c.xyz.iter().copied().zip(ids).collect();
                }
                Some(Received::Bad(reason)) => rt.log.error(&format!("rejected /missing_points: {reason}")),
                None => break,
            },
            Some(m) = region_s.next() => if let Ok((arr, _)) = m {
                let (regions, errors) = markers_to_regions(&arr);
                for e in errors {
                    rt.log.warn(&format!("/active_region: {e}"));
                }
                let marker = arr.markers.iter().find(|m| m.r#type == skyground_msgs::visualization_msgs::Marker::LINE_STRIP);
                let round = marker.and_then(|m| m.text.strip_prefix("round ")).and_then(|r| r.parse().ok()).unwrap_or(0);
                let index = marker.map_or(0, |m| m.id.max(0) as usize);
                requested = regions.into_iter().next().map(|r| (r, index, round));
                if requested.is_none() {
                    active = None;
                }
            },
            Some(m) = scan_s.next() => if let Ok((msg, _)) = m {
                match decode(&msg) {
                    Ok(d) => {
                        let c = d.cloud;
                        let labels = c.label.as_deref();
                        for (i, q) in c.xyz.iter().enumerate() {
                            if labels.is_none_or(|l| l.get(i) == Some(&class::BUILDING)) {
                                merged.add(*q);
                            }
                        }
                        if let Some(a) = active.as_mut() {
                            a.pending.extend_from_slice(&c.xyz);
                        }
                    }
                    Err(e) => rt.log.warn(&format!("rejected /registered_scan: {e}")),
                }
            },
            Some(m) = odom_s.next() => if let Ok((o, _)) = m {
                position = odom_position(&o).or(position);
            },
            Some(m) = vstatus_s.next() => if let Ok((s, _)) = m {
                for v in &s.status {
                    let (Some(a), Some(gx), Some(gy)) = (active.as_ref(), value::<f32>(v, "goal_x"), value::<f32>(v, "goal_y")) else { continue };
                    let Some(g) = a.goal else { continue };
                    if (gx - g[0]).abs() < 1e-3 && (gy - g[1]).abs() < 1e-3 {
                        arrived_at = Some(v.message == "arrived" || v.level == DiagnosticStatus::OK);
                    }
                }
            },
            Some(m) = pstatus_s.next() => if let Ok((s, _)) = m {
                for v in &s.status {
                    let round = value::<u32>(v, "round").unwrap_or(0);
                    if v.message == "done" && !published_rounds.contains(&round) {
                        published_rounds.push(round);
                        publish_resampled(rt, &merged, &resampled_pub).await?;
                    }
                }
            },
            _ = tick.tick() => publish_status(rt, &status_pub, active.as_ref(), last_done, merged.len()).await,
        }
        // A new region to explore.
        if let (Some((region, index, round)), Some(pos), Some(cloud)) =
            (requested.as_ref(), position, classified.as_ref())
            && active
                .as_ref()
                .is_none_or(|a| a.index != *index || a.round != *round)
            && last_done.is_none_or(|(i, r, _)| i != *index || r != *round)
        {
            if graph.is_none() {
                let labels = cloud.label.as_deref().unwrap_or_default();
                match GroundGraph::build(&cloud.xyz, labels, pos, &p.graph) {
                    Ok(g) => graph = Some(Arc::new(g)),
                    Err(e) => {
                        rt.log.error(&format!("cannot build the ground graph: {e}"));
                        requested = None;
                        continue;
                    }
                }
            }
            let Some(g) = graph.clone() else { continue };
            let surface: Vec<[f32; 3]> = missing
                .iter()
                .filter(|(q, b)| {
                    *b == region.building
                        && dist_to_polygon(&region.polygon, [f64::from(q[0]), f64::from(q[1])])
                            <= p.surface_margin_m
                })
                .map(|(q, _)| *q)
                .collect();
            let known: Vec<[f32; 3]> = cloud
                .xyz
                .iter()
                .zip(cloud.label.as_deref().unwrap_or_default())
                .filter(|(_, l)| **l != class::GROUND)
                .map(|(q, _)| *q)
                .collect();
            match Explorer::new(region, surface.clone(), &known, g, &p.explore) {
                Ok(explorer) => {
                    rt.log.info(&format!(
                        "exploring region {index} of round {round} (building {}): {} surface samples, {} candidate viewpoints",
                        region.building,
                        surface.len(),
                        explorer.candidates()
                    ));
                    active = Some(Active {
                        region: region.clone(),
                        index: *index,
                        round: *round,
                        explorer,
                        goal: None,
                        pending: Vec::new(),
                        blocked: 0,
                        stops: 0,
                    });
                    arrived_at = Some(true);
                    // Every change of state goes out at once: a region can
                    // start and end between two ticks.
                    publish_status(rt, &status_pub, active.as_ref(), last_done, merged.len()).await;
                }
                Err(e) => {
                    rt.log.error(&format!(
                        "cannot explore region {index}: {e}; handing it back"
                    ));
                    last_done = Some((*index, *round, 0.0));
                    requested = None;
                    publish_status(rt, &status_pub, None, last_done, merged.len()).await;
                    continue;
                }
            }
        }
        // At a viewpoint (or blocked on the way): take the scans, go on or finish.
        if let (Some(ok), Some(a), Some(pos)) = (arrived_at, active.as_mut(), position) {
            let pending = std::mem::take(&mut a.pending);
            a.explorer.update(pos, &pending);
            if !ok {
                a.blocked += 1;
            }
            let next = a.explorer.next_waypoints(pos);
            let finished = a.explorer.done() || next.is_empty() || a.blocked > p.block_retries;
            if finished {
                rt.log.info(&format!(
                    "region {} of round {} done: coverage {:.1} % after {} viewpoints",
                    a.index,
                    a.round,
                    a.explorer.coverage() * 100.0,
                    a.stops
                ));
                last_done = Some((a.index, a.round, a.explorer.coverage()));
                active = None;
                requested = None;
                publish_status(rt, &status_pub, None, last_done, merged.len()).await;
                // What the region added, for viewers; the detector re-runs
                // only on the cloud that follows the route's end.
                if p.publish_each_region {
                    publish_resampled(rt, &merged, &resampled_pub).await?;
                }
            } else if let Some(target) = next.first().copied() {
                let leg = a.explorer.path_to(pos, target);
                a.goal = leg.last().copied();
                a.stops += 1;
                let _ = leg_pub.async_publish(path(&header(rt), &leg)).await;
            }
        }
    }
    Ok(())
}

/// /explorer_status: exploring (region, round, building, coverage,
/// viewpoints), done (the last region handed back) or idle.
async fn publish_status(
    rt: &NodeRuntime,
    publisher: &ros2_client::Publisher<DiagnosticArray>,
    active: Option<&Active>,
    last_done: Option<(usize, u32, f64)>,
    resampled_points: usize,
) {
    let (state, mut values) = match (active, last_done) {
        (Some(a), _) => (
            "exploring",
            vec![
                kv("region", a.index),
                kv("round", a.round),
                kv("building", a.region.building),
                kv("coverage", a.explorer.coverage()),
                kv("viewpoints", a.stops),
            ],
        ),
        (None, Some((i, r, c))) => (
            "done",
            vec![kv("region", i), kv("round", r), kv("coverage", c)],
        ),
        (None, None) => ("idle", vec![]),
    };
    values.push(kv("resampled_points", resampled_points));
    let _ = publisher
        .async_publish(DiagnosticArray {
            header: header(rt),
            status: vec![status(
                "local_explorer",
                DiagnosticStatus::OK,
                state,
                values,
            )],
        })
        .await;
}

async fn publish_resampled(
    rt: &NodeRuntime,
    merged: &VoxelMerge,
    publisher: &CloudPublisher,
) -> Result<(), RuntimeError> {
    let mut c = Cloud::from_xyz(merged.points().to_vec());
    c.label = Some(vec![class::BUILDING; c.len()]);
    rt.log.info(&format!(
        "publishing /resampled_cloud: {} building points",
        c.len()
    ));
    publisher
        .publish(encode(&c, header(rt), &EncodeOptions { double: false }))
        .await?;
    Ok(())
}
