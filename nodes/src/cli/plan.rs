//! `skyground plan`: steps 5–6 offline — the ground graph and the route
//! over the targets `skyground detect` wrote — with both tour builders.

use std::path::PathBuf;
use std::time::Instant;

use serde::Deserialize;
use serde_json::json;
use skyground_core::cloud::read_cloud;
use skyground_core::field::FieldRoute;
use skyground_core::graph::{GraphParams, GroundGraph};
use skyground_core::missing::MissingPoint;
use skyground_core::plot::{PlanView, plan_picture};
use skyground_core::route::{
    Ground, Route, RouteParams, SetDown, Stop, drop_seen_on_the_way, plan_set_downs,
};
use skyground_core::targets::{Site, TargetParams, TargetSet};

use super::err;
use crate::runtime::RuntimeError;
use crate::runtime::params::section_over;

/// `skyground plan`'s own ground-graph default, over the planner node's: a
/// tree crown blocks only where points stand in the vehicle's height band.
/// The plan is for a robot in the field, which steers round the trunks it
/// meets, over a survey whose split pulses measure the ground under the
/// crowns; `demo --prior` drives a real prior the same way. The node's
/// default (the whole column) is for the simulated world, whose vehicle
/// does not steer round trunks the prior cannot show. On AHN3 Delft 1 with
/// our classes the start's ground holds 3,702 nodes instead of 1,109.
const FIELD_GRAPH: &str =
    "global_planner:\n  ros__parameters:\n    graph:\n      canopy_is_obstacle: false\n";

/// Options of `skyground plan`.
#[derive(Debug, Clone, clap::Args)]
pub struct PlanArgs {
    /// A `skyground detect` output directory (classified.laz or .las, targets.json).
    #[arg(long = "in")]
    pub input: PathBuf,
    /// Start position x,y in the cloud's local frame (default: the middle of
    /// the largest piece of drivable ground, where a robot reaches most).
    #[arg(long, value_delimiter = ',', num_args = 2)]
    pub start: Option<Vec<f32>>,
    /// A params file (section global_planner: graph, route, targets). Tree
    /// crowns block only in the vehicle's height band here, unlike the
    /// planner node's default; `graph.canopy_is_obstacle: true` blocks
    /// their whole column.
    #[arg(long)]
    pub params_file: Option<PathBuf>,
    /// Where the ground comes in pieces no drivable way joins (a canal, a
    /// courtyard), plan up to this many more set-downs: the field team puts
    /// the robot down on the largest other pieces that reach targets the
    /// earlier set-downs do not; 0: one route from the start.
    #[arg(long, default_value_t = 3)]
    pub set_downs: usize,
    /// Print the summary as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Deserialize, Default)]
struct PlannerParams {
    #[serde(default)]
    graph: GraphParams,
    #[serde(default)]
    route: RouteParams,
    /// The view model `route.skip_seen` judges by, as the planner node reads it.
    #[serde(default)]
    targets: TargetParams,
}

#[derive(Debug, Deserialize)]
struct TargetsFile {
    targets: TargetSet,
    /// The gaps (files from before they were written: none).
    #[serde(default)]
    missing: Vec<MissingPoint>,
}

/// Builds the graph and the route from the start, then more set-downs
/// where targets remain; writes DIR/route.json, route.geojson and plan.png.
pub fn run(a: &PlanArgs) -> Result<serde_json::Value, RuntimeError> {
    let p: PlannerParams = section_over(
        "global_planner",
        (
            crate::runtime::specs::GLOBAL_PLANNER.default_params,
            Some(("skyground plan", FIELD_GRAPH)),
        ),
        a.params_file.as_deref(),
        &["graph", "route", "targets"],
    )?;
    let classified = super::detect::find_classified(&a.input)?;
    let cloud = read_cloud(&classified).map_err(err)?;
    let labels = cloud
        .label
        .clone()
        .ok_or_else(|| err(format!("{} has no classification", classified.display())))?;
    let tpath = a.input.join("targets.json");
    let text =
        std::fs::read_to_string(&tpath).map_err(|e| err(format!("{}: {e}", tpath.display())))?;
    let targets: TargetsFile =
        serde_json::from_str(&text).map_err(|e| err(format!("{}: {e}", tpath.display())))?;
    let (targets, missing) = (targets.targets, targets.missing);
    let t0 = Instant::now();
    let given = a.start.as_ref().map(|s| [s[0], s[1], 0.0]);
    let graph = match given {
        Some(s) => GroundGraph::build(&cloud.xyz, &labels, s, &p.graph),
        None => GroundGraph::build_largest(&cloud.xyz, &labels, &p.graph),
    }
    .map_err(err)?;
    let start = given.unwrap_or_else(|| graph.positions()[graph.start_node()]);
    let graph_s = t0.elapsed().as_secs_f64();
    let t_crowns = Instant::now();
    let crowns_open = graph
        .if_crowns_block_only_in_band(&cloud.xyz, &labels)
        .map_err(err)?;
    let crowns_s = t_crowns.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let ground = Ground {
        xyz: &cloud.xyz,
        labels: &labels,
        params: &p.graph,
    };
    let mut plan =
        plan_set_downs(&ground, &targets, (graph, start), &p.route, a.set_downs).map_err(err)?;
    let toured_length_m = plan.length_m();
    let mut dropped = Vec::new();
    if p.route.skip_seen && !missing.is_empty() {
        let t = &p.targets;
        let site = Site::from_cloud(&cloud.xyz, &labels, t.cell, t.clearance).map_err(err)?;
        for s in &mut plan.set_downs {
            let d =
                drop_seen_on_the_way(&s.graph, &s.route, &targets, (&missing, &site), t, &p.route);
            s.route = d.route;
            dropped.extend(d.dropped);
        }
    }
    let route_s = t1.elapsed().as_secs_f64();
    let first = &plan.set_downs[0];
    let (graph, route) = (&first.graph, &first.route);
    let report = graph.report();
    let set_down_nodes: usize = plan.set_downs.iter().map(|s| s.graph.len()).sum();
    let sum = |f: fn(&Route) -> f32| plan.set_downs.iter().map(|s| f(&s.route)).sum::<f32>();
    let greedy_length_m = sum(|r| r.greedy_length_m);
    let tsp_length_m = sum(|r| r.tsp_length_m);
    let stops: usize = plan.set_downs.iter().map(|s| s.route.order.len()).sum();
    let (points, regions) = (targets.points.len(), targets.regions.len());
    // Targets reached by all set-downs, and by the first alone.
    let (reach_points, reach_regions) = (
        points - plan.unreachable_points.len(),
        regions - plan.unreachable_regions.len(),
    );
    let (first_points, first_regions) = (
        points - route.unreachable_points.len(),
        regions - route.unreachable_regions.len(),
    );
    // Said only where it matters: some target lies beyond the start's ground.
    let cut_off = first_points < points || first_regions < regions;
    if let Some(open) =
        crowns_open.filter(|o| cut_off && o.nodes as f64 > 1.1 * report.nodes as f64)
    {
        eprintln!(
            "tree crowns block their whole column here (graph.canopy_is_obstacle: true in the params file): the start's ground holds {} nodes ({:.3} of candidates); with crowns blocking only in the vehicle's height band it would hold {} ({:.3}). For a robot that avoids trunks on its own: graph.canopy_is_obstacle: false (skyground plan's default)",
            report.nodes,
            report.reachable_share(),
            open.nodes,
            open.reachable_share()
        );
    }
    let out = json!({
        "input": a.input,
        "start": start,
        "graph": report,
        "graph_params": graph.params(),
        "reachable_node_share": report.reachable_share(),
        "if_crowns_block_only_in_band": crowns_open.map(|o| json!({
            "graph": o,
            "reachable_node_share": o.reachable_share(),
        })),
        "set_down_node_share": report.share_of_candidates(set_down_nodes),
        "nodes": graph.len(),
        "edges": report.edges,
        "target_points": points,
        "target_regions": regions,
        "reachable_points": reach_points,
        "reachable_regions": reach_regions,
        "reachable_points_first": first_points,
        "reachable_regions_first": first_regions,
        "unreachable_points": plan.unreachable_points,
        "unreachable_regions": plan.unreachable_regions,
        "greedy_length_m": greedy_length_m,
        "tsp_length_m": tsp_length_m,
        "tsp_over_greedy": tsp_length_m / greedy_length_m.max(1e-6),
        "streets_length_m": sum(|r| r.streets_length_m),
        "route_length_m": plan.length_m(),
        "stops": stops,
        "toured_length_m": toured_length_m,
        "dropped_seen_on_the_way": dropped,
        "set_downs": plan.set_downs.iter().map(set_down_summary).collect::<Vec<_>>(),
        "seconds": {"graph": graph_s, "if_crowns_block_only_in_band": crowns_s, "matrix_and_tours": route_s, "total": graph_s + crowns_s + route_s},
    });
    let routes: Vec<&Route> = plan.set_downs.iter().map(|s| &s.route).collect();
    let file = json!({"summary": out, "route": route, "set_down_routes": &routes[1..]});
    skyground_core::file::write(&a.input.join("route.json"), format!("{file:#}\n")).map_err(err)?;
    super::field::write_route(&a.input, &cloud, &FieldRoute::from(&plan), &targets)?;
    let unit = cloud.frame().unit();
    let view = PlanView {
        xyz: &cloud.xyz,
        labels: &labels,
        set_downs: &plan,
        targets: &targets,
    };
    plan_picture(&view, 2400, &unit)
        .and_then(|c| c.save(&a.input.join("plan.png")))
        .map_err(err)?;
    if !a.json {
        eprintln!(
            "graph: {} nodes, {} edges ({:.2} s; tree crowns block {}); {} set-down(s); targets reachable: {} of {} points, {} of {} regions (from the start: {} and {}); tours: greedy {:.0} m, TSP {:.0} m ({:.2}×), driven {:.0} m ({:.2} s)",
            graph.len(),
            report.edges,
            graph_s,
            if p.graph.canopy_is_obstacle {
                "their whole column"
            } else {
                "only in the vehicle's height band"
            },
            plan.set_downs.len(),
            reach_points,
            points,
            reach_regions,
            regions,
            first_points,
            first_regions,
            greedy_length_m,
            tsp_length_m,
            tsp_length_m / greedy_length_m.max(1e-6),
            plan.length_m(),
            route_s
        );
    }
    Ok(out)
}

/// One set-down in the summary: where, how much ground, what it reaches.
fn set_down_summary(s: &SetDown) -> serde_json::Value {
    let points = s
        .route
        .order
        .iter()
        .filter(|o| matches!(o, Stop::Point(_)))
        .count();
    json!({
        "start": s.start,
        "nodes": s.graph.len(),
        "stops": s.route.order.len(),
        "points": points,
        "regions": s.route.order.len() - points,
        "route_length_m": s.route.length_m,
    })
}
