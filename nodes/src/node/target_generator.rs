//! target_generator: /missing_points (+ the strategy per building on
//! /completeness, the skeletons on /detection_markers, the site from
//! /classified_cloud) → ground targets (docs/design.md step 4): /target_points
//! for point-based buildings, /target_regions (one LINE_STRIP polygon per
//! region, ns = building id) for region-based ones. Both latched. Point
//! targets are consolidated first: one stop for every gap it sees, shared
//! between buildings.

use std::collections::BTreeMap;

use futures::StreamExt;
use serde::Deserialize;
use skyground_core::cloud::Cloud;
use skyground_core::missing::{MissingPoint, Strategy};
use skyground_core::targets::{
    BuildingPlan, Site, TargetParams, consolidate, generate_from_missing,
};
use skyground_msgs::diagnostic_msgs::DiagnosticArray;
use skyground_msgs::pointcloud2::{EncodeOptions, encode};
use skyground_msgs::std_msgs::Header;
use skyground_msgs::visualization_msgs::MarkerArray;

use crate::convert::detection::skeletons_from_markers;
use crate::convert::diagnostics::value;
use crate::convert::markers::regions_to_markers;
use crate::runtime::{NodeRuntime, NodeSpec, RuntimeError, qos};
use crate::transport::{CloudPublisher, CloudSubscription, Received, TransportConfig};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    #[serde(default)]
    targets: TargetParams,
    transport: TransportConfig,
}

/// Per-building plans, detection round and the stamp they came with.
type Strategies = (BTreeMap<u32, BuildingPlan>, u32, Header);

/// Skeleton segments (x, y pairs) per building id.
type Skeletons = BTreeMap<u32, Vec<[[f64; 2]; 2]>>;

/// Name and default params.
pub const SPEC: NodeSpec = NodeSpec {
    name: "target_generator",
    default_params: include_str!("../../../config/target_generator.yaml"),
    live: &[],
};

fn nearest_on_segments(segs: &[[[f64; 2]; 2]], q: [f64; 2]) -> Option<[f64; 2]> {
    let mut best: Option<([f64; 2], f64)> = None;
    for [a, b] in segs {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let l2 = dx * dx + dy * dy;
        let t = if l2 > 0.0 {
            (((q[0] - a[0]) * dx + (q[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let p = [a[0] + t * dx, a[1] + t * dy];
        let d = (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
        if best.is_none_or(|(_, bd)| d < bd) {
            best = Some((p, d));
        }
    }
    best.map(|(p, _)| p)
}

/// Missing points with their skeleton point and outward normal, as the
/// detector had them (rebuilt from the topics).
fn missing_points(
    cloud: &Cloud,
    skeletons: &BTreeMap<u32, Vec<[[f64; 2]; 2]>>,
) -> Vec<MissingPoint> {
    let ids = cloud
        .building
        .clone()
        .unwrap_or_else(|| vec![0; cloud.len()]);
    cloud
        .xyz
        .iter()
        .zip(ids)
        .filter_map(|(p, b)| {
            let q = [f64::from(p[0]), f64::from(p[1])];
            let s = skeletons
                .get(&b)
                .and_then(|segs| nearest_on_segments(segs, q))?;
            let (dx, dy) = (q[0] - s[0], q[1] - s[1]);
            let len = (dx * dx + dy * dy).sqrt();
            (len > 1e-6).then(|| MissingPoint {
                xyz: *p,
                building: b,
                normal: [(dx / len) as f32, (dy / len) as f32],
                skeleton: [s[0] as f32, s[1] as f32],
            })
        })
        .collect()
}

/// Runs the node until asked to stop.
pub async fn run(rt: &mut NodeRuntime) -> Result<(), RuntimeError> {
    let p: Params = rt.params()?;
    p.targets
        .validate()
        .map_err(|e| RuntimeError::Node(format!("target params: {e}")))?;
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
    let status_sub = rt.subscription::<DiagnosticArray>("/completeness", qos::latched(1))?;
    let marker_sub = rt.subscription::<MarkerArray>("/detection_markers", qos::latched(1))?;
    let points_pub = CloudPublisher::new(rt, "/target_points", qos::latched(1), p.transport)?;
    let regions_pub = rt.publisher::<MarkerArray>("/target_regions", qos::latched(1))?;
    let status_s = status_sub.async_stream();
    let marker_s = marker_sub.async_stream();
    futures::pin_mut!(status_s, marker_s);
    let mut site: Option<Site> = None;
    let mut missing: Option<(Cloud, Header)> = None;
    let mut strategy: Option<Strategies> = None;
    let mut skeletons: Option<(Skeletons, Header)> = None;
    let mut done_for: Option<(Header, u32)> = None;
    rt.log.info(
        "waiting for /classified_cloud, /missing_points, /completeness and /detection_markers",
    );
    loop {
        tokio::select! {
            _ = rt.shutdown.wait() => break,
            r = cloud_sub.next() => match r {
                Some(Received::Cloud { decoded, .. }) => match Site::from_classified(&decoded.cloud, &p.targets) {
                    Ok(s) => site = Some(s),
                    Err(e) => rt.log.error(&format!("/classified_cloud: {e}")),
                },
                Some(Received::Bad(reason)) => rt.log.error(&format!("rejected /classified_cloud: {reason}")),
                None => break,
            },
            r = missing_sub.next() => match r {
                Some(Received::Cloud { msg, decoded }) => missing = Some((decoded.cloud, msg.header)),
                Some(Received::Bad(reason)) => rt.log.error(&format!("rejected /missing_points: {reason}")),
                None => break,
            },
            Some(m) = status_s.next() => if let Ok((arr, _)) = m {
                let mut map = BTreeMap::new();
                let mut round = 0;
                for s in &arr.status {
                    round = value(s, "round").unwrap_or(round);
                    let (Some(b), Some(k), Some(ground_z)) = (value::<u32>(s, "building"), value::<String>(s, "strategy"), value::<f32>(s, "ground_z")) else { continue };
                    let strategy = if k == "region" { Strategy::RegionBased } else { Strategy::PointBased };
                    map.insert(b, BuildingPlan { strategy, ground_z });
                }
                strategy = Some((map, round, arr.header));
            },
            Some(m) = marker_s.next() => if let Ok((arr, _)) = m {
                let h = arr.markers.first().map(|m| m.header.clone()).unwrap_or_default();
                skeletons = Some((skeletons_from_markers(&arr), h));
            },
        }
        let (Some(site), Some((cloud, header)), Some((strategy, round, h1)), Some((skeletons, h2))) = (
            site.as_ref(),
            missing.as_ref(),
            strategy.as_ref(),
            skeletons.as_ref(),
        ) else {
            continue;
        };
        // The detector stamps its three outputs alike: wait until all are of one round.
        if h1.stamp != header.stamp || h2.stamp != header.stamp {
            continue;
        }
        if done_for
            .as_ref()
            .is_some_and(|(h, r)| h == header && r == round)
        {
            continue;
        }
        let points = missing_points(cloud, skeletons);
        let (mut targets, dropped) =
            match generate_from_missing(&points, strategy, site, &p.targets) {
                Ok(v) => v,
                Err(e) => {
                    rt.log.error(&format!("cannot generate targets: {e}"));
                    continue;
                }
            };
        let (kept, merged) = consolidate(&targets.points, &points, site, &p.targets);
        targets.points = kept;
        rt.log.info(&format!(
            "round {round}: consolidated {} target points into {} stops; they see {} of {} missing points ({} before)",
            merged.stops_before, merged.stops_after, merged.seen_after, merged.missing, merged.seen_before
        ));
        rt.log.info(&format!(
            "round {round}: {} missing points → {} target points, {} regions; dropped {dropped:?}",
            points.len(),
            targets.points.len(),
            targets.regions.len()
        ));
        let mut tc = Cloud::from_xyz(targets.points.iter().map(|t| t.xyz).collect());
        tc.building = Some(targets.points.iter().map(|t| t.building).collect());
        tc.origin = cloud.origin;
        let mut h = header.clone();
        h.stamp = rt.now();
        // Regions first: the planner replans on either, and a point cloud is slower to arrive.
        if let Err(e) = regions_pub
            .async_publish(regions_to_markers(&h, &targets.regions))
            .await
        {
            rt.log.warn(&format!("cannot publish /target_regions: {e}"));
        }
        points_pub
            .publish(encode(&tc, h, &EncodeOptions { double: false }))
            .await?;
        done_for = Some((header.clone(), *round));
    }
    Ok(())
}
