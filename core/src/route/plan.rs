//! The global route: distance matrix of graph distances between targets,
//! the two tours, and the node path of the shorter one.

use rayon::prelude::*;

use super::error::RouteError;
use super::params::{RouteParams, TourChoice};
use super::stops::{Snapped, Stop, snap};
use super::tour::{Costs, greedy_alternating, street_tour, tsp};
use crate::graph::{GroundGraph, ShortestPaths};
use crate::targets::TargetSet;

/// A planned tour over the targets.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Route {
    /// Targets in the order visited.
    pub order: Vec<Stop>,
    /// The node path through the graph, start first (node positions, ground height).
    pub waypoints: Vec<[f32; 3]>,
    /// The graph node of each way-point (the route's own graph; not written out).
    #[serde(skip)]
    pub nodes: Vec<usize>,
    /// For each stop in `order`, the index in `waypoints` where it is reached.
    pub arrivals: Vec<usize>,
    /// Length of `waypoints`, metres.
    pub length_m: f32,
    /// Target points that cannot be reached (indices into the target set).
    pub unreachable_points: Vec<usize>,
    /// Regions with no reachable ground inside (indices into the target set).
    pub unreachable_regions: Vec<usize>,
    /// Driven length of the greedy (paper) tour, metres.
    pub greedy_length_m: f32,
    /// Driven length of the 2-opt/Or-opt tour, metres.
    pub tsp_length_m: f32,
    /// Driven length of the street-by-street tour, metres.
    pub streets_length_m: f32,
}

/// Plans a route from `start` over every reachable target of `targets`.
pub fn plan(
    graph: &GroundGraph,
    targets: &TargetSet,
    start: [f32; 3],
    params: &RouteParams,
) -> Result<Route, RouteError> {
    let (start_node, snapped) = tie(graph, targets, start, params)?;
    // One search per stop, from its nodes: the distance of any node to the stop.
    let trees: Vec<ShortestPaths> = snapped
        .stops
        .par_iter()
        .map(|(_, nodes)| graph.shortest_paths(nodes))
        .collect();
    let mut unreachable_points = snapped.unreachable_points;
    let mut unreachable_regions = snapped.unreachable_regions;
    let mut stops = Vec::new();
    let mut kept_trees = Vec::new();
    for ((stop, nodes), tree) in snapped.stops.into_iter().zip(trees) {
        crate::work::step();
        if tree.dist[start_node].is_finite() {
            stops.push((stop, nodes));
            kept_trees.push(tree);
        } else {
            match stop {
                Stop::Point(i) => unreachable_points.push(i),
                Stop::Region(i) => unreachable_regions.push(i),
            }
        }
    }
    let costs = matrix(&stops, &kept_trees, start_node);
    let is_region: Vec<bool> = stops
        .iter()
        .map(|(s, _)| matches!(s, Stop::Region(_)))
        .collect();
    let greedy = greedy_alternating(&costs, &is_region);
    let tsp_order = tsp(&costs, params.max_passes);
    let xy: Vec<[f32; 2]> = stops
        .iter()
        .map(|(_, nodes)| {
            let p = graph.positions()[nodes[0]];
            [p[0], p[1]]
        })
        .collect();
    let streets = street_tour(&costs, &xy, params.max_passes);
    let greedy_len = drive(&kept_trees, start_node, &greedy).0;
    let tsp_len = drive(&kept_trees, start_node, &tsp_order).0;
    let streets_len = drive(&kept_trees, start_node, &streets).0;
    let chosen = match params.tour {
        TourChoice::Greedy => &greedy,
        TourChoice::Tsp => &tsp_order,
        TourChoice::Streets => &streets,
        // Ties go to the TSP, then to the streets (the order they were added in).
        TourChoice::Shortest => {
            [
                (&tsp_order, tsp_len),
                (&streets, streets_len),
                (&greedy, greedy_len),
            ]
            .into_iter()
            .fold((&tsp_order, f32::INFINITY), |best, c| {
                if c.1 < best.1 { c } else { best }
            })
            .0
        }
    };
    let (length_m, nodes, arrivals) = drive(&kept_trees, start_node, chosen);
    unreachable_points.sort_unstable();
    unreachable_regions.sort_unstable();
    Ok(Route {
        order: chosen.iter().map(|&k| stops[k].0).collect(),
        waypoints: nodes.iter().map(|&n| graph.positions()[n]).collect(),
        nodes,
        arrivals,
        length_m,
        unreachable_points,
        unreachable_regions,
        greedy_length_m: greedy_len,
        tsp_length_m: tsp_len,
        streets_length_m: streets_len,
    })
}

/// The start's node and the targets tied to the graph, after checking `params`.
fn tie(
    graph: &GroundGraph,
    targets: &TargetSet,
    start: [f32; 3],
    params: &RouteParams,
) -> Result<(usize, Snapped), RouteError> {
    params.validate()?;
    let (node, _) = graph
        .start_node_from([start[0], start[1]], params.max_snap_m)
        .ok_or(RouteError::StartOffGraph {
            x: start[0],
            y: start[1],
            max: params.max_snap_m,
        })?;
    Ok((node, snap(graph, targets, params.max_snap_m)))
}

/// Targets already dealt with, by their indices in the full target set.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Visited {
    /// Points reached.
    pub points: Vec<usize>,
    /// Regions explored.
    pub regions: Vec<usize>,
}

/// Replans from `position` over the targets not in `visited`; the route's
/// indices refer to the full `targets`.
pub fn replan(
    graph: &GroundGraph,
    targets: &TargetSet,
    visited: &Visited,
    position: [f32; 3],
    params: &RouteParams,
) -> Result<Route, RouteError> {
    let (rest, point_ids, region_ids) = remaining(targets, visited);
    let mut route = plan(graph, &rest, position, params)?;
    for s in &mut route.order {
        *s = match *s {
            Stop::Point(i) => Stop::Point(point_ids[i]),
            Stop::Region(i) => Stop::Region(region_ids[i]),
        };
    }
    route
        .unreachable_points
        .iter_mut()
        .for_each(|i| *i = point_ids[*i]);
    route
        .unreachable_regions
        .iter_mut()
        .for_each(|i| *i = region_ids[*i]);
    Ok(route)
}

/// The targets not in `visited`, with each one's index in `targets`
/// (points, then regions).
pub(crate) fn remaining(
    targets: &TargetSet,
    visited: &Visited,
) -> (TargetSet, Vec<usize>, Vec<usize>) {
    let point_ids: Vec<usize> = (0..targets.points.len())
        .filter(|i| !visited.points.contains(i))
        .collect();
    let region_ids: Vec<usize> = (0..targets.regions.len())
        .filter(|i| !visited.regions.contains(i))
        .collect();
    let rest = TargetSet {
        points: point_ids.iter().map(|&i| targets.points[i]).collect(),
        regions: region_ids
            .iter()
            .map(|&i| targets.regions[i].clone())
            .collect(),
    };
    (rest, point_ids, region_ids)
}

/// The paper's Table 1: graph distances start–stop and stop–stop, a region's
/// distance being the smallest over its nodes.
fn matrix(stops: &[(Stop, Vec<usize>)], trees: &[ShortestPaths], start: usize) -> Costs {
    let n = stops.len();
    let start_row = trees.iter().map(|t| t.dist[start]).collect();
    let between = (0..n * n)
        .into_par_iter()
        .map(|k| {
            let (a, b) = (k / n, k % n);
            if a == b {
                return 0.0;
            }
            stops[a]
                .1
                .iter()
                .map(|&v| trees[b].dist[v])
                .fold(f32::INFINITY, f32::min)
        })
        .collect();
    Costs {
        start: start_row,
        between,
    }
}

/// Drives `order` from `start`: each leg follows the stop's search tree to
/// its nearest node (a region is entered at the node nearest to where the
/// vehicle is). Returns the length, the node path and the arrival indices.
fn drive(trees: &[ShortestPaths], start: usize, order: &[usize]) -> (f32, Vec<usize>, Vec<usize>) {
    let mut at = start;
    let mut len = 0.0;
    let mut path = vec![start];
    let mut arrivals = Vec::with_capacity(order.len());
    for &k in order {
        let leg = trees[k].path_to_source(at);
        if leg.is_empty() {
            arrivals.push(path.len() - 1);
            continue;
        }
        len += trees[k].dist[at];
        path.extend_from_slice(&leg[1..]);
        at = *leg.last().unwrap_or(&at);
        arrivals.push(path.len() - 1);
    }
    (len, path, arrivals)
}
