//! global_planner: /classified_cloud + /target_points + /target_regions +
//! /state_estimation → a ground graph, one route over every reachable
//! target (docs/design.md steps 5–6) → /global_path, then the route leg by leg on
//! /local_path; regions are handed to local_explorer on /active_region and
//! taken back when /explorer_status says it is done. Progress (and what was
//! visited, so a restarted planner goes on) is on /planner_status.

use std::time::Duration;

use futures::StreamExt;
use serde::Deserialize;
use skyground_core::graph::{GraphParams, GroundGraph};
use skyground_core::route::{Route, RouteParams, Stop, Visited, replan};
use skyground_core::targets::{TargetPoint, TargetSet};
use skyground_msgs::builtin_interfaces::Time;
use skyground_msgs::diagnostic_msgs::{DiagnosticArray, DiagnosticStatus};
use skyground_msgs::nav_msgs::{Odometry, Path};
use skyground_msgs::std_msgs::Header;
use skyground_msgs::visualization_msgs::MarkerArray;

use crate::convert::diagnostics::{kv, status, value};
use crate::convert::markers::{markers_to_regions, regions_to_markers};
use crate::convert::path::{odom_position, path};
use crate::runtime::{NodeRuntime, NodeSpec, RuntimeError, qos};
use crate::transport::{CloudSubscription, Received, TransportConfig};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    #[serde(default)]
    graph: GraphParams,
    #[serde(default)]
    route: RouteParams,
    /// Tries per stop before a blocked stop is given up.
    block_retries: u32,
    transport: TransportConfig,
}

/// How far beyond the vehicle's radius the obstacle that blocked it is
/// looked for: the vehicle stops when its body is within one step of it.
const BLOCK_AHEAD_M: f32 = 0.4;

/// Name and default params.
pub const SPEC: NodeSpec = NodeSpec {
    name: "global_planner",
    default_params: include_str!("../../../config/global_planner.yaml"),
    live: &[],
};

/// Where the mission is.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Phase {
    /// Waiting for inputs or a route.
    Waiting,
    /// Driving leg `k` of the route.
    Driving(usize),
    /// The explorer works on the region of stop `k`.
    Exploring(usize),
    /// Every stop done.
    Done,
}

fn phase_name(p: Phase) -> &'static str {
    match p {
        Phase::Waiting => "waiting",
        Phase::Driving(_) => "driving",
        Phase::Exploring(_) => "exploring",
        Phase::Done => "done",
    }
}

fn list(v: &[usize]) -> String {
    v.iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(",")
}

fn parse_list(s: Option<String>) -> Vec<usize> {
    s.map(|s| s.split(',').filter_map(|x| x.trim().parse().ok()).collect())
        .unwrap_or_default()
}

struct State {
    labels_xyz: Option<(Vec<[f32; 3]>, Vec<u8>)>,
    points: Option<(Vec<TargetPoint>, Time)>,
    regions: Option<(Vec<skyground_core::targets::Region>, Time)>,
    /// Targets as of the last route, and their generation (new targets → new round).
    targets: TargetSet,
    round: u32,
    position: Option<[f32; 3]>,
    graph: Option<GroundGraph>,
    route: Option<Route>,
    visited: Visited,
    unreachable: (Vec<usize>, Vec<usize>),
    phase: Phase,
    need_plan: bool,
    retries: u32,
    restored: Option<(u32, Visited, usize, usize)>,
    driven_legs: usize,
}

/// Runs the node until asked to stop.
pub async fn run(rt: &mut NodeRuntime) -> Result<(), RuntimeError> {
    let p: Params = rt.params()?;
    p.graph
        .validate()
        .map_err(|e| RuntimeError::Node(format!("graph params: {e}")))?;
    p.route
        .validate()
        .map_err(|e| RuntimeError::Node(format!("route params: {e}")))?;
    let mut cloud_sub = CloudSubscription::new(
        rt,
        "/classified_cloud",
        qos::latched(256),
        p.transport.tile_points,
    )?;
    let mut target_sub = CloudSubscription::new(
        rt,
        "/target_points",
        qos::latched(64),
        p.transport.tile_points,
    )?;
    let regions_sub = rt.subscription::<MarkerArray>("/target_regions", qos::latched(1))?;
    let odom_sub = rt.subscription::<Odometry>("/state_estimation", qos::reliable(10))?;
    let vstatus_sub = rt.subscription::<DiagnosticArray>("/vehicle_status", qos::reliable(50))?;
    let estatus_sub = rt.subscription::<DiagnosticArray>("/explorer_status", qos::latched(1))?;
    let own_status_sub = rt.subscription::<DiagnosticArray>("/planner_status", qos::latched(1))?;
    let global_pub = rt.publisher::<Path>("/global_path", qos::latched(1))?;
    let leg_pub = rt.publisher::<Path>("/local_path", qos::reliable(10))?;
    let region_pub = rt.publisher::<MarkerArray>("/active_region", qos::latched(1))?;
    let status_pub = rt.publisher::<DiagnosticArray>("/planner_status", qos::latched(1))?;
    let regions_s = regions_sub.async_stream();
    let odom_s = odom_sub.async_stream();
    let vstatus_s = vstatus_sub.async_stream();
    let estatus_s = estatus_sub.async_stream();
    let own_s = own_status_sub.async_stream();
    futures::pin_mut!(regions_s, odom_s, vstatus_s, estatus_s, own_s);
    let mut tick = tokio::time::interval(Duration::from_millis(500));
    let mut st = State {
        labels_xyz: None,
        points: None,
        regions: None,
        targets: TargetSet::default(),
        round: 0,
        position: None,
        graph: None,
        route: None,
        visited: Visited::default(),
        unreachable: (vec![], vec![]),
        phase: Phase::Waiting,
        need_plan: false,
        retries: 0,
        restored: None,
        driven_legs: 0,
    };
    rt.log.info(
        "waiting for /classified_cloud, /target_points, /target_regions and /state_estimation",
    );
    loop {
        tokio::select! {
            _ = rt.shutdown.wait() => break,
            r = cloud_sub.next() => match r {
                Some(Received::Cloud { decoded, .. }) => match decoded.cloud.label.clone() {
                    Some(l) => {
                        st.labels_xyz = Some((decoded.cloud.xyz, l));
                        st.graph = None;
                        st.need_plan = true;
                    }
                    None => rt.log.error("/classified_cloud has no `label` field"),
                },
                Some(Received::Bad(reason)) => rt.log.error(&format!("rejected /classified_cloud: {reason}")),
                None => break,
            },
            r = target_sub.next() => match r {
                Some(Received::Cloud { msg, decoded }) => {
                    let c = decoded.cloud;
                    let ids = c.building.clone().unwrap_or_else(|| vec![0; c.len()]);
                    st.points = Some((c.xyz.iter().zip(ids).map(|(p, b)| TargetPoint { xyz: *p, building: b }).collect(), msg.header.stamp));
                    st.need_plan = true;
                }
                Some(Received::Bad(reason)) => rt.log.error(&format!("rejected /target_points: {reason}")),
                None => break,
            },
            Some(m) = regions_s.next() => match m {
                Ok((arr, _)) => {
                    let (regions, errors) = markers_to_regions(&arr);
                    for e in errors {
                        rt.log.warn(&format!("/target_regions: {e}"));
                    }
                    // The DELETEALL marker first carries the set's stamp.
                    let stamp = arr.markers.first().map(|m| m.header.stamp).unwrap_or_default();
                    st.regions = Some((regions, stamp));
                    st.need_plan = true;
                }
                Err(e) => rt.log.error(&format!("/target_regions: unreadable message: {e}")),
            },
            Some(m) = odom_s.next() => if let Ok((o, _)) = m {
                st.position = odom_position(&o).or(st.position);
            },
            Some(m) = own_s.next() => if let Ok((s, _)) = m {
                // Our own latched status: a restarted planner goes on where it was.
                if st.route.is_none() && st.restored.is_none()
                    && let Some(s) = s.status.first()
                {
                    let visited = Visited {
                        points: parse_list(value(s, "visited_points")),
                        regions: parse_list(value(s, "visited_regions")),
                    };
                    let n_points = value(s, "target_points").unwrap_or(0);
                    let n_regions = value(s, "target_regions").unwrap_or(0);
                    let round = value(s, "round").unwrap_or(0);
                    rt.log.info(&format!("restored round {round}: {} points and {} regions visited", visited.points.len(), visited.regions.len()));
                    st.restored = Some((round, visited, n_points, n_regions));
                }
            },
            Some(m) = vstatus_s.next() => if let Ok((s, _)) = m {
                for v in &s.status {
                    if let Some(next) = on_vehicle_status(rt, &mut st, &p, v, &region_pub).await {
                        start_leg(rt, &mut st, next, &leg_pub).await;
                    }
                }
            },
            Some(m) = estatus_s.next() => if let Ok((s, _)) = m {
                for v in &s.status {
                    if let Phase::Exploring(k) = st.phase
                        && let Some(Stop::Region(i)) = st.route.as_ref().and_then(|r| r.order.get(k)).copied()
                        && v.message == "done"
                        && value::<usize>(v, "region") == Some(i)
                        && value::<u32>(v, "round") == Some(st.round)
                    {
                        rt.log.info(&format!("region {i} explored (coverage {})", value::<f64>(v, "coverage").unwrap_or(f64::NAN)));
                        st.visited.regions.push(i);
                        let empty = regions_to_markers(&header(rt), &[]);
                        let _ = region_pub.async_publish(empty).await;
                        start_leg(rt, &mut st, k + 1, &leg_pub).await;
                    }
                }
            },
            _ = tick.tick() => {
                if st.need_plan {
                    plan(rt, &mut st, &p, &global_pub, &leg_pub, &region_pub).await;
                }
                publish_status(rt, &st, &status_pub).await;
            }
        }
    }
    Ok(())
}

fn header(rt: &NodeRuntime) -> Header {
    Header {
        stamp: rt.now(),
        frame_id: "map".into(),
    }
}

/// (Re)plans when every input is there.
async fn plan(
    rt: &NodeRuntime,
    st: &mut State,
    p: &Params,
    global_pub: &ros2_client::Publisher<Path>,
    leg_pub: &ros2_client::Publisher<Path>,
    region_pub: &ros2_client::Publisher<MarkerArray>,
) {
    let (Some((xyz, labels)), Some((points, t_points)), Some((regions, t_regions)), Some(position)) = (
        st.labels_xyz.as_ref(),
        st.points.as_ref(),
        st.regions.as_ref(),
        st.position,
    ) else {
        return;
    };
    // The generator stamps both halves of a target set alike: wait for the pair.
    if t_points != t_regions {
        return;
    }
    if matches!(st.phase, Phase::Exploring(_)) {
        // The explorer has the vehicle; plan when it hands back.
        return;
    }
    st.need_plan = false;
    let t0 = std::time::Instant::now();
    if st.graph.is_none() {
        match GroundGraph::build(xyz, labels, position, &p.graph) {
            Ok(g) => {
                let r = g.report();
                rt.log.info(&format!("ground graph: {r:?}"));
                st.graph = Some(g);
            }
            Err(e) => {
                rt.log.error(&format!("cannot build the ground graph: {e}"));
                return;
            }
        }
    }
    let Some(graph) = st.graph.as_ref() else {
        return;
    };
    let targets = TargetSet {
        points: points.clone(),
        regions: regions.clone(),
    };
    if targets != st.targets {
        // New targets: a new round (or the restored one, if it matches).
        st.targets = targets.clone();
        st.visited = Visited::default();
        st.retries = 0;
        st.round += 1;
        if let Some((round, visited, np, nr)) = st.restored.take()
            && np == targets.points.len()
            && nr == targets.regions.len()
        {
            st.round = round;
            st.visited = visited;
        }
    }
    match replan(graph, &st.targets, &st.visited, position, &p.route) {
        Ok(route) => {
            rt.log.info(&format!(
                "round {}: route over {} stops, {:.0} m (greedy {:.0} m, TSP {:.0} m), {} points and {} regions unreachable ({:.2} s)",
                st.round,
                route.order.len(),
                route.length_m,
                route.greedy_length_m,
                route.tsp_length_m,
                route.unreachable_points.len(),
                route.unreachable_regions.len(),
                t0.elapsed().as_secs_f64()
            ));
            st.unreachable = (
                route.unreachable_points.clone(),
                route.unreachable_regions.clone(),
            );
            let _ = global_pub
                .async_publish(path(&header(rt), &route.waypoints))
                .await;
            st.route = Some(route);
            let empty = regions_to_markers(&header(rt), &[]);
            let _ = region_pub.async_publish(empty).await;
            start_leg(rt, st, 0, leg_pub).await;
        }
        Err(e) => rt.log.error(&format!("cannot plan: {e}")),
    }
}

/// Sends leg `k` (the path to stop `k`) to the vehicle, or ends the route.
async fn start_leg(
    rt: &NodeRuntime,
    st: &mut State,
    k: usize,
    leg_pub: &ros2_client::Publisher<Path>,
) {
    let Some(route) = st.route.as_ref() else {
        return;
    };
    if k >= route.order.len() {
        st.phase = Phase::Done;
        rt.log.info(&format!("round {}: route done", st.round));
        return;
    }
    let from = if k == 0 {
        0
    } else {
        route.arrivals.get(k - 1).copied().unwrap_or(0)
    };
    let to = route.arrivals.get(k).copied().unwrap_or(from);
    let mut leg: Vec<[f32; 3]> = route
        .waypoints
        .get(from..=to)
        .map(<[_]>::to_vec)
        .unwrap_or_default();
    if leg.is_empty() {
        leg = route.waypoints.last().copied().into_iter().collect();
    }
    st.phase = Phase::Driving(k);
    st.driven_legs += 1;
    let _ = leg_pub.async_publish(path(&header(rt), &leg)).await;
}

fn leg_goal(st: &State, k: usize) -> Option<[f32; 3]> {
    let route = st.route.as_ref()?;
    route.waypoints.get(*route.arrivals.get(k)?).copied()
}

async fn on_vehicle_status(
    rt: &NodeRuntime,
    st: &mut State,
    p: &Params,
    v: &DiagnosticStatus,
    region_pub: &ros2_client::Publisher<MarkerArray>,
) -> Option<usize> {
    let Phase::Driving(k) = st.phase else {
        return None;
    };
    let (Some(gx), Some(gy), Some(goal)) = (
        value::<f32>(v, "goal_x"),
        value::<f32>(v, "goal_y"),
        leg_goal(st, k),
    ) else {
        return None;
    };
    let ours = (gx - goal[0]).abs() < 1e-3 && (gy - goal[1]).abs() < 1e-3;
    if v.message == "arrived" && ours {
        let stop = st.route.as_ref().and_then(|r| r.order.get(k)).copied();
        match stop {
            Some(Stop::Point(i)) => {
                st.visited.points.push(i);
                st.retries = 0;
                return Some(k + 1);
            }
            Some(Stop::Region(i)) => {
                if let Some(r) = st.targets.regions.get(i) {
                    let mut arr = regions_to_markers(&header(rt), std::slice::from_ref(r));
                    // The marker id carries the region's index in this round's set.
                    if let Some(m) = arr.markers.get_mut(1) {
                        m.id = i as i32;
                        m.text = format!("round {}", st.round);
                    }
                    let _ = region_pub.async_publish(arr).await;
                }
                st.phase = Phase::Exploring(k);
            }
            None => {}
        }
    } else if v.message.starts_with("blocked") && v.level != DiagnosticStatus::OK {
        // Something the prior did not show stands between the vehicle and a
        // pose of its leg: the graph forgets the ground just ahead of it, so
        // later routes go around. The vehicle itself skips to the next pose;
        // only when it gives up the leg's last one is a new route needed.
        if let (Some(x), Some(y), Some(g)) = (
            value::<f32>(v, "x"),
            value::<f32>(v, "y"),
            st.graph.as_mut(),
        ) {
            let (dx, dy) = (gx - x, gy - y);
            let len = dx.hypot(dy);
            if len > 1e-3 {
                let ahead = g.params().vehicle_radius_m + BLOCK_AHEAD_M;
                let at = [x + dx / len * ahead, y + dy / len * ahead];
                let cut = g.block_near(at, ahead);
                rt.log.info(&format!(
                    "blocked near ({:.1}, {:.1}): {cut} graph edges taken out",
                    at[0], at[1]
                ));
            }
        }
        if !ours {
            return None;
        }
        // A per-stop count, kept across replans, gives the stop up when every
        // way round is blocked too.
        st.retries += 1;
        if st.retries > p.block_retries {
            let stop = st.route.as_ref().and_then(|r| r.order.get(k)).copied();
            rt.log.warn(&format!(
                "giving up stop {stop:?} after {} blocked tries",
                st.retries
            ));
            match stop {
                Some(Stop::Point(i)) => st.visited.points.push(i),
                Some(Stop::Region(i)) => st.visited.regions.push(i),
                None => {}
            }
            st.retries = 0;
        }
        // New way-points from where the vehicle is.
        st.need_plan = true;
        st.phase = Phase::Waiting;
    }
    None
}

async fn publish_status(
    rt: &NodeRuntime,
    st: &State,
    status_pub: &ros2_client::Publisher<DiagnosticArray>,
) {
    let (done_p, done_r) = (st.visited.points.len(), st.visited.regions.len());
    let route = st.route.as_ref();
    let s = status(
        "global_planner",
        DiagnosticStatus::OK,
        phase_name(st.phase),
        vec![
            kv("round", st.round),
            kv("target_points", st.targets.points.len()),
            kv("target_regions", st.targets.regions.len()),
            kv("visited_points", list(&st.visited.points)),
            kv("visited_regions", list(&st.visited.regions)),
            kv("points_done", done_p),
            kv("regions_done", done_r),
            kv("unreachable_points", st.unreachable.0.len()),
            kv("unreachable_regions", st.unreachable.1.len()),
            kv("stops", route.map_or(0, |r| r.order.len())),
            kv("route_m", route.map_or(0.0, |r| r.length_m)),
            kv("greedy_m", route.map_or(0.0, |r| r.greedy_length_m)),
            kv("tsp_m", route.map_or(0.0, |r| r.tsp_length_m)),
        ],
    );
    let _ = status_pub
        .async_publish(DiagnosticArray {
            header: header(rt),
            status: vec![s],
        })
        .await;
}
