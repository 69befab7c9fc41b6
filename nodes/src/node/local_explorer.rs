//! local_explorer: TARE-style exploration of the region the global planner
//! hands over on /active_region (docs/design.md step 7): viewpoints on the
//! ground graph inside it, scored by the missing wall they would see, visited
//! in a short tour on /local_path until the gain per metre runs out; then
//! "done" on /explorer_status. Every building point scanned is merged (voxel
//! de-duplicated) into /resampled_cloud and kept on disk as it grows
//! (`merge_store`). The region's index and round, and the spots the planner
//! found blocked, come on /planner_status. Executive:
//! `skyground_core::mission::explorer`; work count on /work_progress.
use std::time::Duration;

use crate::convert::pointcloud2::{EncodeOptions, encode};
use crate::convert::scan_store::ScanStore;
use crate::convert::scans::{late_scans, scan_feed, scan_qos};
use futures::StreamExt;
use serde::Deserialize;
use skyground_core::cloud::{Cloud, class};
use skyground_core::explore::ExploreParams;
use skyground_core::graph::GraphParams;
use skyground_core::mission::explorer::{
    ExplorerCommand, ExplorerConfig, ExplorerEvent, ExplorerMachine,
};
use skyground_core::mission::{PlannerStatus, VehicleStatus};
use skyground_msgs::diagnostic_msgs::DiagnosticArray;
use skyground_msgs::nav_msgs::{Odometry, Path};
use skyground_msgs::sensor_msgs::PointCloud2;
use skyground_msgs::visualization_msgs::MarkerArray;

use crate::convert::diagnostics::{array, statuses};
use crate::convert::markers::received_regions;
use crate::convert::path::{odom_position, path};
use crate::runtime::{NodeRuntime, RuntimeError, qos, work_beat};
use crate::transport::{CloudPublisher, CloudSubscription, TransportConfig, with_buildings};

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
    /// Folder the merged cloud is kept in as it grows ("" = memory only).
    merge_store: String,
    /// Seconds between two batches written to `merge_store`.
    merge_flush_s: f64,
    /// QoS of /registered_scan: `sensor` or `reliable` ([`scan_qos`]).
    scan_qos: String,
    /// The drone's scans, merged with the ground robot's ("": no drone).
    uav_scan_topic: String,
    transport: TransportConfig,
}

pub use crate::runtime::specs::LOCAL_EXPLORER as SPEC;

/// Runs the node until asked to stop.
pub async fn run(rt: &mut NodeRuntime) -> Result<(), RuntimeError> {
    let p: Params = rt.params()?;
    work_beat::beat(rt, "local_explorer")?;
    p.graph.validate()?;
    let mut ex = ExplorerMachine::new(ExplorerConfig {
        graph: p.graph,
        explore: p.explore,
        surface_margin_m: p.surface_margin_m,
        publish_each_region: p.publish_each_region,
        resample_voxel_m: p.resample_voxel_m,
        block_retries: p.block_retries,
    })
    .map_err(|e| RuntimeError::Node(format!("explore params: {e}")))?;
    let mut kept = ScanStore::open(&rt.log, (&p.merge_store, p.merge_flush_s), &mut ex)?;
    let t0 = std::time::Instant::now();
    let tile = p.transport.tile_points;
    let mut cloud_sub = CloudSubscription::new(rt, "/classified_cloud", qos::latched(256), tile)?;
    let mut missing_sub = CloudSubscription::new(rt, "/missing_points", qos::latched(64), tile)?;
    let region_sub = rt.subscription::<MarkerArray>("/active_region", qos::latched(1))?;
    let scan_sub = rt.subscription::<PointCloud2>("/registered_scan", scan_qos(&p.scan_qos)?)?;
    let odom_sub = rt.subscription::<Odometry>("/state_estimation", qos::odometry())?;
    let vstatus_sub = rt.subscription::<DiagnosticArray>("/vehicle_status", qos::reliable(50))?;
    let pstatus_sub = rt.subscription::<DiagnosticArray>("/planner_status", qos::latched(1))?;
    let leg_pub = rt.publisher::<Path>("/local_path", qos::reliable(10))?;
    let status_pub = rt.publisher::<DiagnosticArray>("/explorer_status", qos::latched(1))?;
    let resampled_pub = CloudPublisher::new(rt, "/resampled_cloud", qos::latched(1), p.transport)?;
    let region_s = region_sub.async_stream();
    let mut feeds = vec![(scan_sub, 0)];
    if !p.uav_scan_topic.is_empty() {
        let qos = scan_qos(&p.scan_qos)?;
        feeds.push((rt.subscription::<PointCloud2>(&p.uav_scan_topic, qos)?, 1));
    }
    let inbox = kept.as_ref().map(ScanStore::inbox);
    let mut scans = scan_feed(rt.log.clone(), feeds, inbox);
    let odom_s = odom_sub.async_stream();
    let vstatus_s = vstatus_sub.async_stream();
    let pstatus_s = pstatus_sub.async_stream();
    futures::pin_mut!(region_s, odom_s, vstatus_s, pstatus_s);
    let mut tick = tokio::time::interval(Duration::from_millis(500));
    rt.log.info("waiting for /active_region");
    loop {
        let events: Vec<ExplorerEvent> = tokio::select! {
            _ = rt.shutdown.wait() => break,
            r = cloud_sub.next_labelled(&rt.log) => match r {
                Some(c) => c.map(|(xyz, labels)| ExplorerEvent::Cloud { xyz, labels }).into_iter().collect(),
                None => break,
            },
            r = missing_sub.next_cloud(&rt.log) => match r {
                Some(c) => c.map(|(_, d)| {
                    let (xyz, ids) = with_buildings(d.cloud);
                    ExplorerEvent::Missing(xyz.into_iter().zip(ids).collect())
                }).into_iter().collect(),
                None => break,
            },
            Some(m) = region_s.next() => received_regions(&rt.log, "/active_region", m)
                .map(|(regions, _)| ExplorerEvent::ActiveRegion(regions.into_iter().next())).into_iter().collect(),
            Some(e) = scans.recv() => vec![e],
            Some(m) = odom_s.next() => m.ok().and_then(|(o, _)| odom_position(&o)).map(ExplorerEvent::Position).into_iter().collect(),
            Some(m) = vstatus_s.next() => statuses(&rt.log, m, VehicleStatus::from_wire).into_iter().map(ExplorerEvent::Vehicle).collect(),
            Some(m) = pstatus_s.next() => statuses(&rt.log, m, PlannerStatus::from_wire).into_iter().map(ExplorerEvent::Planner).collect(),
            _ = tick.tick() => vec![ExplorerEvent::Tick],
        };
        for e in events {
            let cmds = ex.handle(e);
            // What goes out on /resampled_cloud is on disk first.
            let force = cmds.iter().any(|c| matches!(c, ExplorerCommand::Resampled));
            let now = t0.elapsed().as_secs_f64();
            if let Some(k) = kept.as_mut() {
                k.keep(&rt.log, &ex, now, force);
            }
            for c in cmds {
                perform(rt, &ex, c, &leg_pub, &status_pub, &resampled_pub).await?;
            }
        }
    }
    // Scans still on their way are merged too (issue 50 part 5).
    for e in late_scans(&rt.log, &mut scans, Duration::from_secs(3)).await {
        ex.handle(e);
    }
    rt.log.info(&match kept.as_mut() {
        Some(k) => k.stop(&ex),
        None => ex.stop(None),
    });
    Ok(())
}

async fn perform(
    rt: &NodeRuntime,
    ex: &ExplorerMachine,
    c: ExplorerCommand,
    leg_pub: &ros2_client::Publisher<Path>,
    status_pub: &ros2_client::Publisher<DiagnosticArray>,
    resampled_pub: &CloudPublisher,
) -> Result<(), RuntimeError> {
    let h = rt.header("map");
    let sent = match c {
        ExplorerCommand::Info(s) => {
            rt.log.info(&s);
            true
        }
        ExplorerCommand::Error(s) => {
            rt.log.error(&s);
            true
        }
        ExplorerCommand::Leg(w) => leg_pub.async_publish(path(&h, &w)).await.is_ok(),
        ExplorerCommand::Status(s) => status_pub
            .async_publish(array(h, s.to_wire()))
            .await
            .is_ok(),
        ExplorerCommand::Resampled => {
            let mut c = Cloud::from_xyz(ex.resampled().to_vec());
            c.label = Some(vec![class::BUILDING; c.len()]);
            rt.log.info(&format!(
                "publishing /resampled_cloud: {} building points from {} scans",
                c.len(),
                ex.scans()
            ));
            resampled_pub
                .publish(encode(&c, h, &EncodeOptions { double: false }))
                .await?;
            // A loop stuck after a round's merge (tests): scans pile up in the feed.
            crate::runtime::faults::spin_if_asked("local_explorer", true);
            true
        }
    };
    if !sent {
        rt.log.warn("a publish failed (DDS write error)");
    }
    Ok(())
}
