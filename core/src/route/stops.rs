//! Tying targets to the graph: points to their nearest reachable node,
//! regions to the nodes inside them.

use crate::graph::GroundGraph;
use crate::targets::TargetSet;

/// A place on the tour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Stop {
    /// Target point `i` of the target set.
    Point(usize),
    /// Region `i` of the target set.
    Region(usize),
}

/// Targets tied to graph nodes.
pub struct Snapped {
    /// The stops that can be reached, each with its nodes (one for a point).
    pub stops: Vec<(Stop, Vec<usize>)>,
    /// Points with no reachable node within the snap distance.
    pub unreachable_points: Vec<usize>,
    /// Regions with no reachable node inside.
    pub unreachable_regions: Vec<usize>,
}

/// Snaps every target: a point to the nearest node within `max_snap` (xy)
/// that the vehicle can drive to in a straight line (or that shares its cell).
pub fn snap(graph: &GroundGraph, targets: &TargetSet, max_snap: f32) -> Snapped {
    let cell = graph.params().node_spacing();
    let mut out = Snapped {
        stops: Vec::new(),
        unreachable_points: Vec::new(),
        unreachable_regions: Vec::new(),
    };
    for (i, t) in targets.points.iter().enumerate() {
        let xy = [t.xyz[0], t.xyz[1]];
        let node = graph
            .nodes_near(xy, max_snap, 16)
            .into_iter()
            .find(|&(n, d)| {
                let p = graph.positions()[n];
                d <= 0.75 * cell || graph.segment_free(xy, [p[0], p[1]])
            });
        match node {
            Some((n, _)) => out.stops.push((Stop::Point(i), vec![n])),
            None => out.unreachable_points.push(i),
        }
    }
    for (i, r) in targets.regions.iter().enumerate() {
        let nodes = graph.nodes_in_polygon(&r.polygon);
        if nodes.is_empty() {
            out.unreachable_regions.push(i);
        } else {
            out.stops.push((Stop::Region(i), nodes));
        }
    }
    out
}
