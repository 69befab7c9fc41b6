//! target_generator: /missing_points (each with its outward normal and
//! skeleton point as extra columns) + the strategy per building on
//! /completeness + the site from /classified_cloud → ground targets (docs/design.md step 4): /target_points
//! for point-based buildings, /target_regions (one LINE_STRIP polygon per
//! region, ns = building id) for region-based ones. Both latched. Point
//! targets are consolidated first: one stop for every gap it sees, shared
//! between buildings. The same `targets::generate` and `consolidate` as
//! `skyground detect`, on the detector's own missing points.

use std::collections::BTreeMap;

use crate::convert::pointcloud2::{EncodeOptions, encode};
use futures::StreamExt;
use serde::Deserialize;
use skyground_core::cloud::Cloud;
use skyground_core::missing::MissingPoint;
use skyground_core::targets::{
    BuildingPlan, Site, TargetParams, consolidate, generate_from_missing,
};
use skyground_msgs::diagnostic_msgs::DiagnosticArray;
use skyground_msgs::std_msgs::Header;
use skyground_msgs::visualization_msgs::MarkerArray;

use crate::convert::detection::{missing_from_message, plans_from_completeness};
use crate::convert::markers::regions_to_markers;
use crate::runtime::{NodeRuntime, RuntimeError, qos};
use crate::transport::{CloudPublisher, CloudSubscription, TransportConfig};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    #[serde(default)]
    targets: TargetParams,
    transport: TransportConfig,
}

/// Per-building plans, detection round and the stamp they came with.
type Strategies = (BTreeMap<u32, BuildingPlan>, u32, Header);

pub use crate::runtime::specs::TARGET_GENERATOR as SPEC;

/// Runs the node until asked to stop.
pub async fn run(rt: &mut NodeRuntime) -> Result<(), RuntimeError> {
    let p: Params = rt.params()?;
    p.targets.validate()?;
    let tile = p.transport.tile_points;
    let mut cloud_sub = CloudSubscription::new(rt, "/classified_cloud", qos::latched(256), tile)?;
    let mut missing_sub = CloudSubscription::new(rt, "/missing_points", qos::latched(64), tile)?;
    let status_sub = rt.subscription::<DiagnosticArray>("/completeness", qos::latched(1))?;
    let points_pub = CloudPublisher::new(rt, "/target_points", qos::latched(1), p.transport)?;
    let regions_pub = rt.publisher::<MarkerArray>("/target_regions", qos::latched(1))?;
    let status_s = status_sub.async_stream();
    futures::pin_mut!(status_s);
    let mut site: Option<Site> = None;
    let mut missing: Option<(Vec<MissingPoint>, [f64; 3], Header)> = None;
    let mut strategy: Option<Strategies> = None;
    let mut done_for: Option<(Header, u32)> = None;
    rt.log
        .info("waiting for /classified_cloud, /missing_points and /completeness");
    loop {
        tokio::select! {
            _ = rt.shutdown.wait() => break,
            r = cloud_sub.next_cloud(&rt.log) => match r {
                Some(Some((_, d))) => match Site::from_classified(&d.cloud, &p.targets) {
                    Ok(s) => site = Some(s),
                    Err(e) => rt.log.error(&format!("/classified_cloud: {e}")),
                },
                Some(None) => {}
                None => break,
            },
            r = missing_sub.next_cloud(&rt.log) => match r {
                Some(Some((msg, d))) => match missing_from_message(&d) {
                    Ok(points) => missing = Some((points, d.cloud.origin, msg.header)),
                    Err(e) => rt.log.error(&e),
                },
                Some(None) => {}
                None => break,
            },
            Some(m) = status_s.next() => if let Ok((arr, _)) = m {
                let (plans, round) = plans_from_completeness(&arr);
                strategy = Some((plans, round, arr.header));
            },
        }
        let (Some(site), Some((points, origin, header)), Some((strategy, round, h1))) =
            (site.as_ref(), missing.as_ref(), strategy.as_ref())
        else {
            continue;
        };
        // The detector stamps its outputs alike: wait until both are of one round.
        if h1.stamp != header.stamp
            || done_for
                .as_ref()
                .is_some_and(|(h, r)| h == header && r == round)
        {
            continue;
        }
        let (mut targets, dropped) = match generate_from_missing(points, strategy, site, &p.targets)
        {
            Ok(v) => v,
            Err(e) => {
                rt.log.error(&format!("cannot generate targets: {e}"));
                continue;
            }
        };
        let (kept, merged) = consolidate(&targets.points, points, site, &p.targets);
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
        tc.origin = *origin;
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
