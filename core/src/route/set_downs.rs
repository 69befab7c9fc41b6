//! Set-downs: where a field team puts the robot down when one piece of
//! ground does not reach every target (a canal without a drivable bridge,
//! a courtyard behind a gate), and the route it drives from each.

use super::error::RouteError;
use super::params::RouteParams;
use super::plan::{Route, Visited, plan, remaining, replan};
use super::stops::{Stop, snap};
use crate::graph::{GraphError, GraphParams, GroundGraph};
use crate::targets::TargetSet;

/// Pieces of ground tried for a set-down after the first, largest first:
/// beyond these the pieces are yards and gardens a team rarely enters.
pub const PIECES_TRIED: usize = 12;

/// How far (m, in plan) [`way_out`] looks for ground that reaches a target:
/// a field team carries a stuck robot a few metres, not across the site.
pub const WAY_OUT_MAX_M: f32 = 25.0;

/// Where to carry a robot that spots it found blocked have cut off from
/// every target not in `done` (a dead end whose one way out it reported
/// blocked): the node nearest `position`, within [`WAY_OUT_MAX_M`], from
/// which one of them is still reached in `graph`. `None` when the robot is
/// not cut off, or no such node is near. A robot whose spots took out every
/// node within the snap distance is cut off too.
pub fn way_out(
    graph: &GroundGraph,
    targets: &TargetSet,
    done: &Visited,
    position: [f32; 3],
    params: &RouteParams,
) -> Option<[f32; 3]> {
    let (rest, _, _) = remaining(targets, done);
    let sources: Vec<usize> = snap(graph, &rest, params.max_snap_m)
        .stops
        .into_iter()
        .flat_map(|(_, nodes)| nodes)
        .collect();
    if sources.is_empty() {
        return None;
    }
    let to_a_target = graph.shortest_paths(&sources);
    let xy = [position[0], position[1]];
    let start = graph.start_node_from(xy, params.max_snap_m);
    if start.is_some_and(|(s, _)| to_a_target.dist[s].is_finite()) {
        return None;
    }
    graph
        .nodes_near(xy, WAY_OUT_MAX_M, usize::MAX)
        .into_iter()
        .find(|&(n, _)| to_a_target.dist[n].is_finite())
        .map(|(n, _)| graph.positions()[n])
}

/// One place the robot is set down and the route it drives from there.
#[derive(Debug, Clone)]
pub struct SetDown {
    /// Where the robot is set down (a node of `graph`, or the caller's start for the first).
    pub start: [f32; 3],
    /// The piece of ground it can drive from there.
    pub graph: GroundGraph,
    /// The route over the targets this piece reaches that no earlier set-down did.
    pub route: Route,
}

/// Every set-down of a plan, and the targets none of them reaches.
#[derive(Debug, Clone)]
pub struct SetDowns {
    /// The first is the caller's; the others in the order they were found.
    pub set_downs: Vec<SetDown>,
    /// Target points no set-down reaches (indices into the target set).
    pub unreachable_points: Vec<usize>,
    /// Regions no set-down reaches (indices into the target set).
    pub unreachable_regions: Vec<usize>,
}

impl SetDowns {
    /// Total route length over all set-downs, metres.
    pub fn length_m(&self) -> f32 {
        self.set_downs.iter().map(|s| s.route.length_m).sum()
    }
}

/// The cloud the pieces are cut from.
pub struct Ground<'a> {
    /// Points, local metres.
    pub xyz: &'a [[f32; 3]],
    /// Their LAS classes.
    pub labels: &'a [u8],
    /// How the graph is built.
    pub params: &'a GraphParams,
}

/// Plans the route from `first` (a graph and its start), then, while targets
/// remain and fewer than `more` set-downs were added, adds the
/// [`next_set_down`] after the last.
pub fn plan_set_downs(
    ground: &Ground<'_>,
    targets: &TargetSet,
    first: (GroundGraph, [f32; 3]),
    params: &RouteParams,
    more: usize,
) -> Result<SetDowns, RouteError> {
    let (graph, start) = first;
    let route = plan(&graph, targets, start, params)?;
    let mut visited = Visited::default();
    mark(&mut visited, &route);
    let mut pieces: Vec<[f32; 3]> = graph
        .positions()
        .get(graph.start_node())
        .copied()
        .into_iter()
        .collect();
    let mut set_downs = vec![SetDown {
        start,
        graph,
        route,
    }];
    let mut from = 0;
    while set_downs.len() <= more {
        let Some((rank, next)) = next_set_down(ground, targets, &visited, (&pieces, from), params)?
        else {
            break;
        };
        // Smaller pieces than this one reached nothing new and reach less now.
        from = rank + 1;
        mark(&mut visited, &next.route);
        pieces.push(next.start);
        set_downs.push(next);
    }
    let unreachable_points = (0..targets.points.len())
        .filter(|i| !visited.points.contains(i))
        .collect();
    let unreachable_regions = (0..targets.regions.len())
        .filter(|i| !visited.regions.contains(i))
        .collect();
    Ok(SetDowns {
        set_downs,
        unreachable_points,
        unreachable_regions,
    })
}

/// The largest piece of ground, of rank `from` on among the
/// [`PIECES_TRIED`] largest, that holds none of the nodes in `used` (where
/// earlier set-downs stood) and whose route reaches a target not in `done`,
/// with its rank; `None` when no piece does or every target is done. Its
/// start is the piece's middle node.
pub fn next_set_down(
    ground: &Ground<'_>,
    targets: &TargetSet,
    done: &Visited,
    (used, from): (&[[f32; 3]], usize),
    params: &RouteParams,
) -> Result<Option<(usize, SetDown)>, RouteError> {
    let remaining = (0..targets.points.len()).any(|i| !done.points.contains(&i))
        || (0..targets.regions.len()).any(|i| !done.regions.contains(&i));
    if !remaining {
        return Ok(None);
    }
    for rank in from..PIECES_TRIED {
        let graph = match GroundGraph::build_piece(ground.xyz, ground.labels, ground.params, rank) {
            Ok(g) => g,
            Err(GraphError::NoSuchPiece { .. }) => break,
            Err(e) => return Err(e.into()),
        };
        let Some(&start) = graph.positions().get(graph.start_node()) else {
            continue;
        };
        // A piece that was driven already (by any rank) adds nothing: it holds that start node.
        let holds = |p: &[f32; 3]| {
            graph
                .nearest_node([p[0], p[1]])
                .is_some_and(|(_, d)| d == 0.0)
        };
        if used.iter().any(holds) {
            continue;
        }
        let route = replan(&graph, targets, done, start, params)?;
        if !route.order.is_empty() {
            return Ok(Some((
                rank,
                SetDown {
                    start,
                    graph,
                    route,
                },
            )));
        }
    }
    Ok(None)
}

/// Adds the route's stops to `visited`.
fn mark(visited: &mut Visited, route: &Route) {
    for s in &route.order {
        match *s {
            Stop::Point(i) => visited.points.push(i),
            Stop::Region(i) => visited.regions.push(i),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::fixtures::pens;
    use crate::targets::TargetPoint;

    /// A large pen around (30, 10) and a small one around (8, 10).
    fn two_pens() -> (Vec<[f32; 3]>, Vec<u8>) {
        pens(&[([25.0, 5.0], [35.0, 15.0]), ([5.0, 7.0], [11.0, 13.0])])
    }

    fn at(x: f32, y: f32) -> TargetPoint {
        TargetPoint {
            xyz: [x, y, 0.0],
            building: 1,
        }
    }

    #[test]
    fn each_pen_gets_a_set_down_only_when_it_holds_a_target() {
        let (xyz, labels) = two_pens();
        let params = GraphParams::default();
        let ground = Ground {
            xyz: &xyz,
            labels: &labels,
            params: &params,
        };
        let start = [2.0, 2.0, 0.0];
        let first = || GroundGraph::build(&xyz, &labels, start, &params).unwrap();
        // Open ground, the large pen, open ground again.
        let targets = TargetSet {
            points: vec![at(20.0, 10.0), at(30.0, 10.0), at(38.0, 18.0)],
            regions: Vec::new(),
        };
        let rp = RouteParams::default();

        let none = plan_set_downs(&ground, &targets, (first(), start), &rp, 0).unwrap();
        assert_eq!(none.set_downs.len(), 1);
        assert_eq!(none.unreachable_points, vec![1], "the pen's target");

        let s = plan_set_downs(&ground, &targets, (first(), start), &rp, 3).unwrap();
        assert_eq!(
            s.set_downs.len(),
            2,
            "the small pen holds no target: no set-down there"
        );
        assert!(s.unreachable_points.is_empty());
        let pen = &s.set_downs[1];
        assert_eq!(pen.route.order, vec![Stop::Point(1)]);
        let [x, y, _] = pen.start;
        assert!(
            (25.0..35.0).contains(&x) && (5.0..15.0).contains(&y),
            "{:?}",
            pen.start
        );
        assert!(
            pen.graph
                .positions()
                .iter()
                .all(|p| (25.0..35.0).contains(&p[0]) && (5.0..15.0).contains(&p[1])),
            "the second piece is the pen"
        );
        // The first route's stops are not driven again.
        let first_stops = &s.set_downs[0].route.order;
        assert!(first_stops.contains(&Stop::Point(0)) && first_stops.contains(&Stop::Point(2)));
        assert_eq!(
            s.length_m(),
            s.set_downs[0].route.length_m + pen.route.length_m
        );
    }

    #[test]
    fn a_robot_cut_off_by_its_blocked_spots_gets_the_nearest_way_out() {
        // A corridor 40 m × 1.25 m: the robot at x = 1.2, a target at x = 30.
        let (xyz, labels) = crate::geom::fixtures::flat_ground(160, 6, 0.25);
        let params = GraphParams::default();
        let mut g = GroundGraph::build(&xyz, &labels, [1.2, 0.6, 0.0], &params).unwrap();
        let targets = TargetSet {
            points: vec![at(30.0, 0.6)],
            regions: Vec::new(),
        };
        let (rp, done) = (RouteParams::default(), Visited::default());
        let robot = [1.2, 0.6, 0.0];
        assert_eq!(
            way_out(&g, &targets, &done, robot, &rp),
            None,
            "not cut off"
        );
        assert!(g.block_near([2.1, 0.6], 0.9) > 0);
        let to = way_out(&g, &targets, &done, robot, &rp).expect("a way out");
        assert!(
            (3.0..=2.1 + WAY_OUT_MAX_M).contains(&to[0]),
            "past the spot, the nearest node that reaches the target: {to:?}"
        );
        assert!(!plan(&g, &targets, to, &rp).unwrap().order.is_empty());
        // Reached already, or no target left: nothing to carry it to.
        let reached = Visited {
            points: vec![0],
            regions: Vec::new(),
        };
        assert_eq!(way_out(&g, &targets, &reached, robot, &rp), None);
        // Every node within the snap distance taken out: still a way out.
        let mut bare = g.clone();
        assert!(bare.block_near([1.2, 0.6], 3.5) > 0);
        assert!(bare.start_node_from([1.2, 0.6], rp.max_snap_m).is_none());
        let to = way_out(&bare, &targets, &done, robot, &rp).expect("a way out");
        assert!(to[0] > 4.7, "{to:?}");
        // A spot as wide as the reach leaves no way out near.
        assert!(g.block_near([15.0, 0.6], 13.0) > 0);
        assert_eq!(way_out(&g, &targets, &done, robot, &rp), None);
    }

    #[test]
    fn a_missing_piece_is_an_error_naming_how_many_there_are() {
        let (xyz, labels) = two_pens();
        let params = GraphParams::default();
        let err = GroundGraph::build_piece(&xyz, &labels, &params, 50).unwrap_err();
        assert!(
            matches!(
                err,
                GraphError::NoSuchPiece {
                    rank: 50,
                    pieces: 3
                }
            ),
            "{err}"
        );
        let largest = GroundGraph::build_piece(&xyz, &labels, &params, 0).unwrap();
        let third = GroundGraph::build_piece(&xyz, &labels, &params, 2).unwrap();
        assert!(
            largest.len() > 10 * third.len(),
            "{} vs {}",
            largest.len(),
            third.len()
        );
    }
}
