//! global_planner: /classified_cloud + /target_points + /target_regions +
//! /state_estimation → a ground graph, one route over every reachable target
//! (docs/design.md steps 5–6) → /global_path, then the route leg by leg on
//! /local_path; regions go to local_explorer on /active_region and are taken
//! back when /explorer_status says done. Progress (stops visited, the region
//! handed over, spots found blocked) is on the latched /planner_status, so a
//! restarted planner goes on and the explorer's graph drops the same spots.
//! Targets beyond the robot's piece of ground: the spot to carry it to goes
//! out on the latched /set_down. Executive: `mission::planner`; what it says
//! while it lacks an input: `mission::waiting`; work count on /work_progress.
use std::time::{Duration, Instant};

use futures::StreamExt;
use serde::Deserialize;
use skyground_core::graph::GraphParams;
use skyground_core::mission::kept_round::KeptRound;
use skyground_core::mission::planner::{Planner, PlannerCommand, PlannerConfig, PlannerEvent};
use skyground_core::mission::waiting::{WaitingReminder, publishers_said};
use skyground_core::mission::{ExplorerStatus, PlannerStatus, VehicleStatus};
use skyground_core::route::RouteParams;
use skyground_core::targets::TargetParams;
use skyground_msgs::diagnostic_msgs::DiagnosticArray;
use skyground_msgs::geometry_msgs::PointStamped;
use skyground_msgs::nav_msgs::{Odometry, Path};
use skyground_msgs::visualization_msgs::MarkerArray;

use crate::convert::detection::missing_from_message;
use crate::convert::diagnostics::{array, statuses};
use crate::convert::markers::{received_regions, regions_to_markers};
use crate::convert::path::{odom_position, path, point_stamped};
use crate::convert::targets::{stamp_key, target_points};
use crate::runtime::{NodeRuntime, RuntimeError, faults, qos, work_beat};
use crate::transport::{CloudSubscription, TransportConfig, next_cloud_of};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    #[serde(default)]
    graph: GraphParams,
    #[serde(default)]
    route: RouteParams,
    /// The target generator's view model, for `route.skip_seen`.
    #[serde(default)]
    targets: TargetParams,
    /// Tries per stop before a blocked stop is given up.
    block_retries: u32,
    /// Set-downs on other pieces of ground a round may ask for.
    set_downs: usize,
    transport: TransportConfig,
    /// A status the launcher kept (`PlannerStatus::keep`), this planner's state at start.
    #[serde(default)]
    restore: String,
    /// Where each round's targets are kept (`KeptRound`), and read back at
    /// start: with `restore`, a resumed mission finishes the round it was driving.
    #[serde(default)]
    keep_round: String,
}

pub use crate::runtime::specs::GLOBAL_PLANNER as SPEC;

/// How often a planner that lacks an input says which.
const WAITING_SAID_EVERY: Duration = Duration::from_secs(30);

struct Outputs {
    global: ros2_client::Publisher<Path>,
    leg: ros2_client::Publisher<Path>,
    region: ros2_client::Publisher<MarkerArray>,
    status: ros2_client::Publisher<DiagnosticArray>,
    set_down: ros2_client::Publisher<PointStamped>,
}

/// Runs the node until asked to stop.
pub async fn run(rt: &mut NodeRuntime) -> Result<(), RuntimeError> {
    let p: Params = rt.params()?;
    p.graph.validate()?;
    p.route.validate()?;
    work_beat::beat(rt, "global_planner")?;
    let tile = p.transport.tile_points;
    let mut cloud_sub = CloudSubscription::new(rt, "/classified_cloud", qos::latched(256), tile)?;
    let mut target_sub = CloudSubscription::new(rt, "/target_points", qos::latched(64), tile)?;
    // Only skip_seen needs the gaps: otherwise the detector need not send them here.
    let skip_seen = p.route.skip_seen;
    let mut missing_sub = skip_seen
        .then(|| CloudSubscription::new(rt, "/missing_points", qos::latched(64), tile))
        .transpose()?;
    let regions_sub = rt.subscription::<MarkerArray>("/target_regions", qos::latched(1))?;
    let odom_sub = rt.subscription::<Odometry>("/state_estimation", qos::odometry())?;
    let vstatus_sub = rt.subscription::<DiagnosticArray>("/vehicle_status", qos::reliable(50))?;
    let estatus_sub = rt.subscription::<DiagnosticArray>("/explorer_status", qos::latched(1))?;
    let own_status_sub = rt.subscription::<DiagnosticArray>("/planner_status", qos::latched(1))?;
    let out = Outputs {
        global: rt.publisher::<Path>("/global_path", qos::latched(1))?,
        leg: rt.publisher::<Path>("/local_path", qos::reliable(10))?,
        region: rt.publisher::<MarkerArray>("/active_region", qos::latched(1))?,
        status: rt.publisher::<DiagnosticArray>("/planner_status", qos::latched(1))?,
        set_down: rt.publisher::<PointStamped>("/set_down", qos::latched(1))?,
    };
    let regions_s = regions_sub.async_stream();
    let odom_s = odom_sub.async_stream();
    let vstatus_s = vstatus_sub.async_stream();
    let estatus_s = estatus_sub.async_stream();
    let own_s = own_status_sub.async_stream();
    futures::pin_mut!(regions_s, odom_s, vstatus_s, estatus_s, own_s);
    let mut tick = tokio::time::interval(Duration::from_millis(500));
    // A latched input that never arrives would otherwise leave the planner silent for good.
    let mut reminder = WaitingReminder::new(WAITING_SAID_EVERY, Instant::now());
    let mut planner = Planner::new(PlannerConfig {
        graph: p.graph,
        route: p.route,
        block_retries: p.block_retries,
        targets: p.targets,
        set_downs: p.set_downs,
    });
    // Before its own first status: a restarted planner goes on with the round it was driving.
    let kept = PlannerStatus::kept(std::path::Path::new(&p.restore));
    let kept = kept.map_err(|e| rt.log.warn(&format!("restore: {e}")));
    let round = (!p.keep_round.is_empty())
        .then(|| KeptRound::kept(std::path::Path::new(&p.keep_round)))
        .transpose()
        .map_err(|e| rt.log.warn(&format!("keep_round: {e}")));
    let restored = kept.ok().flatten().map(PlannerEvent::Restore);
    let round = round
        .ok()
        .flatten()
        .flatten()
        .map(PlannerEvent::RestoreRound);
    for c in restored
        .into_iter()
        .chain(round)
        .flat_map(|e| planner.handle(e))
    {
        perform(rt, &out, &p.keep_round, c).await;
    }
    rt.log.info(
        "waiting for /classified_cloud, /target_points, /target_regions and /state_estimation",
    );
    loop {
        let events: Vec<PlannerEvent> = tokio::select! {
            _ = rt.shutdown.wait() => break,
            r = cloud_sub.next_labelled(&rt.log) => match r {
                Some(c) => c.map(|(xyz, labels)| PlannerEvent::Cloud { xyz, labels }).into_iter().collect(),
                None => break,
            },
            r = target_sub.next_cloud(&rt.log) => match r {
                Some(c) => c.map(|(msg, d)| PlannerEvent::Points { points: target_points(d.cloud), stamp: stamp_key(msg.header.stamp) })
                    .into_iter().collect(),
                None => break,
            },
            r = next_cloud_of(missing_sub.as_mut(), &rt.log), if skip_seen => match r {
                Some(c) => c.and_then(|(_, d)| missing_from_message(&d).map_err(|e| rt.log.error(&e)).ok())
                    .map(PlannerEvent::Missing).into_iter().collect(),
                None => break,
            },
            Some(m) = regions_s.next() => received_regions(&rt.log, "/target_regions", m)
                .map(|(regions, stamp)| PlannerEvent::Regions { regions, stamp: stamp_key(stamp) }).into_iter().collect(),
            Some(m) = odom_s.next() => m.ok().and_then(|(o, _)| odom_position(&o)).map(PlannerEvent::Position).into_iter().collect(),
            Some(m) = own_s.next() => statuses(&rt.log, m, PlannerStatus::from_wire).into_iter().map(PlannerEvent::Restore).collect(),
            Some(m) = vstatus_s.next() => statuses(&rt.log, m, VehicleStatus::from_wire).into_iter().map(PlannerEvent::Vehicle).collect(),
            Some(m) = estatus_s.next() => statuses(&rt.log, m, ExplorerStatus::from_wire).into_iter().map(PlannerEvent::Explorer).collect(),
            _ = tick.tick() => vec![PlannerEvent::Tick],
        };
        for e in events {
            for c in planner.handle(e) {
                perform(rt, &out, &p.keep_round, c).await;
            }
        }
        let what = planner.waiting_for();
        let due = reminder.check(what.is_some(), Instant::now());
        if let (Some(s), Some(what)) = (due, what) {
            let node = rt.node();
            let matched = [
                ("/classified_cloud", cloud_sub.publisher_count(node)),
                ("/target_points", target_sub.publisher_count(node)),
                ("/target_regions", regions_sub.get_publisher_count(node)),
                ("/state_estimation", odom_sub.get_publisher_count(node)),
            ];
            rt.log.warn(&format!(
                "no route after {s} s: still waiting for {what}{}",
                publishers_said(&what, &matched)
            ));
        }
    }
    Ok(())
}

async fn perform(rt: &NodeRuntime, out: &Outputs, keep_round: &str, c: PlannerCommand) {
    faults::spin_if_asked("global_planner", matches!(c, PlannerCommand::GlobalPath(_)));
    let h = rt.header("map");
    let sent = match c {
        PlannerCommand::Info(s) => return rt.log.info(&s),
        PlannerCommand::Warn(s) => return rt.log.warn(&s),
        PlannerCommand::Error(s) => return rt.log.error(&s),
        PlannerCommand::KeepRound(k) if !keep_round.is_empty() => {
            let kept = k.keep(std::path::Path::new(keep_round));
            return kept.unwrap_or_else(|e| rt.log.warn(&format!("keep_round: {e}")));
        }
        PlannerCommand::KeepRound(_) => return,
        PlannerCommand::GlobalPath(w) => out.global.async_publish(path(&h, &w)).await.is_ok(),
        PlannerCommand::Leg(w) => out.leg.async_publish(path(&h, &w)).await.is_ok(),
        PlannerCommand::ActiveRegion(r) => {
            let markers = regions_to_markers(&h, r.as_slice());
            out.region.async_publish(markers).await.is_ok()
        }
        PlannerCommand::SetDown(at) => out
            .set_down
            .async_publish(point_stamped(h, at))
            .await
            .is_ok(),
        PlannerCommand::Status(s) => out
            .status
            .async_publish(array(h, s.to_wire()))
            .await
            .is_ok(),
    };
    if !sent {
        rt.log
            .warn("a publish failed (DDS write error); the next tick sends the status again");
    }
}
