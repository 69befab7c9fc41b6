//! Stops the rest of the route makes needless: a point stop whose every gap
//! is in view from somewhere the route drives anyway (without the stop) is
//! taken out before the vehicle sets off, and the legs either side of it
//! are joined by the shortest way. Checked at plan time on the whole route,
//! so nothing turns back: dropping a stop on the way (once the trail had
//! seen its gaps) came too late to save metres (docs/profile.md).

use super::params::RouteParams;
use super::plan::Route;
use super::stops::Stop;
use crate::graph::GroundGraph;
use crate::missing::MissingPoint;
use crate::targets::consolidate::sees;
use crate::targets::{Site, TargetParams, TargetSet};

/// Route positions are looked from this far apart at most (m): the LiDAR
/// scans ten times a second at 2 m/s.
const LOOK_STEP_M: f32 = 0.5;

/// The route without its needless stops, and which target points they were.
#[derive(Debug, Clone, PartialEq)]
pub struct DriveBy {
    /// The route left.
    pub route: Route,
    /// Target points dropped (indices into the target set), in route order.
    pub dropped: Vec<usize>,
}

/// Takes out, in route order, every point stop that sees at least one gap
/// and whose every gap is seen (the targets' `sees` test, about as well as
/// from the stop: `route_params`' `seen_*` slack) from the positions of the
/// route as it would be without it; each drop joins the legs either side by
/// the graph's shortest way. Regions stay.
pub fn drop_seen_on_the_way(
    graph: &GroundGraph,
    route: &Route,
    targets: &TargetSet,
    (missing, site): (&[MissingPoint], &Site),
    params: &TargetParams,
    route_params: &RouteParams,
) -> DriveBy {
    let unchanged = || DriveBy {
        route: route.clone(),
        dropped: Vec::new(),
    };
    // A route not made on this graph (or by hand) has no nodes to re-join.
    if route.nodes.len() != route.waypoints.len() {
        return unchanged();
    }
    let mut nodes = route.nodes.clone();
    let mut order = route.order.clone();
    let mut arrivals = route.arrivals.clone();
    let mut dropped = Vec::new();
    let mut k = 0;
    while k < order.len() {
        let Stop::Point(i) = order[k] else {
            k += 1;
            continue;
        };
        let (Some(target), Some((joined, joined_arrivals))) = (
            targets.points.get(i),
            without_stop(graph, &nodes, &arrivals, k),
        ) else {
            k += 1;
            continue;
        };
        let positions: Vec<[f32; 2]> = joined.iter().map(|&n| xy(graph, n)).collect();
        if seen_without(site, missing, target.xyz, &positions, params, route_params) {
            (nodes, arrivals) = (joined, joined_arrivals);
            order.remove(k);
            dropped.push(i);
        } else {
            k += 1;
        }
    }
    if dropped.is_empty() {
        return unchanged();
    }
    let waypoints: Vec<[f32; 3]> = nodes.iter().map(|&n| graph.positions()[n]).collect();
    DriveBy {
        route: Route {
            // An edge weighs its 3D length, so the path's length is the route's.
            length_m: length_3d(&waypoints),
            waypoints,
            nodes,
            arrivals,
            order,
            ..route.clone()
        },
        dropped,
    }
}

/// The node path and arrivals with stop `k` left out: the way from the
/// stop before it goes straight on to the stop after it (or ends there).
fn without_stop(
    graph: &GroundGraph,
    nodes: &[usize],
    arrivals: &[usize],
    k: usize,
) -> Option<(Vec<usize>, Vec<usize>)> {
    let from = if k == 0 { 0 } else { *arrivals.get(k - 1)? };
    let Some(&to) = arrivals.get(k + 1) else {
        // The last stop: the route ends at the one before.
        let mut a = arrivals.to_vec();
        a.pop();
        return Some((nodes.get(..=from)?.to_vec(), a));
    };
    let (_, way) = graph.shortest_path(*nodes.get(from)?, *nodes.get(to)?)?;
    let mut out: Vec<usize> = nodes.get(..from)?.to_vec();
    out.extend_from_slice(&way);
    let shift = out.len() as isize - 1 - to as isize;
    out.extend_from_slice(nodes.get(to + 1..)?);
    let mut a: Vec<usize> = arrivals[..k].to_vec();
    a.extend(
        arrivals[k + 1..]
            .iter()
            .map(|&x| (x as isize + shift) as usize),
    );
    Some((out, a))
}

fn length_3d(p: &[[f32; 3]]) -> f32 {
    p.windows(2)
        .map(|w| {
            let d = [w[1][0] - w[0][0], w[1][1] - w[0][1], w[1][2] - w[0][2]];
            (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
        })
        .sum()
}

/// Whether a stop at `stop` sees a gap and every gap it sees is seen from
/// `positions` (a node path, looked from every `LOOK_STEP_M` along it)
/// about as well as from the stop (`route_params`' `seen_*` slack).
fn seen_without(
    site: &Site,
    missing: &[MissingPoint],
    stop: [f32; 3],
    positions: &[[f32; 2]],
    params: &TargetParams,
    route_params: &RouteParams,
) -> bool {
    let (ratio, extra_deg) = (
        route_params.seen_range_ratio,
        route_params.seen_extra_incidence_deg,
    );
    let gaps: Vec<(&MissingPoint, View)> = missing
        .iter()
        .filter(|m| sees(site, stop, m, params))
        .map(|m| (m, View::of([stop[0], stop[1]], m)))
        .collect();
    if gaps.is_empty() {
        return false;
    }
    let reach = params.stop_range * ratio.max(1.0) + LOOK_STEP_M;
    let near = |p: &[f32; 2]| {
        gaps.iter()
            .any(|(m, _)| (p[0] - m.xyz[0]).hypot(p[1] - m.xyz[1]) <= reach)
    };
    let mut looks: Vec<[f32; 3]> = Vec::new();
    for w in positions.windows(2) {
        let (a, b) = (w[0], w[1]);
        if !near(&a) && !near(&b) {
            continue;
        }
        let steps = ((b[0] - a[0]).hypot(b[1] - a[1]) / LOOK_STEP_M)
            .ceil()
            .max(1.0) as usize;
        for s in 0..=steps {
            let t = s as f32 / steps as f32;
            let q = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
            if let Some(z) = site.ground_at(q[0], q[1]).filter(|z| z.is_finite()) {
                looks.push([q[0], q[1], z]);
            }
        }
    }
    gaps.iter().all(|(m, at_stop)| {
        looks.iter().any(|&p| {
            let v = View::of([p[0], p[1]], m);
            v.distance <= at_stop.distance * ratio
                && v.incidence_deg <= at_stop.incidence_deg + extra_deg
                && sees(site, p, m, params)
                && !through_trees(site, [p[0], p[1]], m)
        })
    })
}

/// Whether the sight line from `from` to the gap crosses vegetation cells:
/// `sees` counts only buildings in the way, and a street tree before the
/// wall hides from a passing vehicle what the stop, placed for that wall,
/// sees.
fn through_trees(site: &Site, from: [f32; 2], m: &MissingPoint) -> bool {
    let (dx, dy) = (m.xyz[0] - from[0], m.xyz[1] - from[1]);
    let d = dx.hypot(dy);
    let steps = (d / TREE_STEP_M).ceil() as usize;
    (1..steps).any(|s| {
        let t = s as f32 / steps as f32;
        site.index(from[0] + t * dx, from[1] + t * dy)
            .is_some_and(|k| site.vegetation.get(k).copied().unwrap_or(false))
    })
}

/// Sight lines are walked in steps this long (m): half a site cell.
const TREE_STEP_M: f32 = 0.25;

/// Distance (xy) and angle off the gap's normal of a view of a gap.
#[derive(Debug, Clone, Copy)]
struct View {
    distance: f32,
    incidence_deg: f32,
}

impl View {
    fn of(from: [f32; 2], m: &MissingPoint) -> Self {
        let v = [from[0] - m.xyz[0], from[1] - m.xyz[1]];
        let distance = v[0].hypot(v[1]);
        let cos = (v[0] * m.normal[0] + v[1] * m.normal[1]) / distance.max(1e-6);
        View {
            distance,
            incidence_deg: cos.clamp(-1.0, 1.0).acos().to_degrees(),
        }
    }
}

fn xy(graph: &GroundGraph, n: usize) -> [f32; 2] {
    let p = graph.positions()[n];
    [p[0], p[1]]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::class;
    use crate::graph::GraphParams;
    use crate::route::{RouteParams, plan};
    use crate::targets::TargetPoint;

    /// Flat ground 0..70 × 0..45 at 0.5 m, a 10 m block at x 20..30,
    /// y 20..30 (walls and roof), gaps on its south face (normal −y) and on
    /// its north face (normal +y), 3 m up.
    fn block_cloud() -> (Vec<[f32; 3]>, Vec<u8>, Vec<MissingPoint>) {
        let (mut xyz, mut labels) = (Vec::new(), Vec::new());
        for j in 0..90 {
            for i in 0..140 {
                let (x, y) = (i as f32 * 0.5, j as f32 * 0.5);
                let inside = (20.0..=30.0).contains(&x) && (20.0..=30.0).contains(&y);
                let z_top = if inside { 8 } else { 0 };
                for h in 0..=z_top {
                    xyz.push([x, y, h as f32]);
                    labels.push(if inside {
                        class::BUILDING
                    } else {
                        class::GROUND
                    });
                }
            }
        }
        let face = |y: f32, ny: f32| {
            (0..5).map(move |k| MissingPoint {
                xyz: [22.0 + 1.5 * k as f32, y, 3.0],
                building: 1,
                normal: [0.0, ny],
                skeleton: [25.0, 25.0],
            })
        };
        let gaps = face(20.0, -1.0).chain(face(30.0, 1.0)).collect();
        (xyz, labels, gaps)
    }

    /// Where the vehicle starts: on the street south of the block.
    const START: [f32; 3] = [2.0, 12.0, 0.0];

    /// The block's ground graph (from [`START`]), its site and its gaps.
    fn block() -> (GroundGraph, Site, Vec<MissingPoint>) {
        let (xyz, labels, gaps) = block_cloud();
        let graph =
            GroundGraph::build(&xyz, &labels, START, &GraphParams::default()).expect("graph");
        let tp = TargetParams::default();
        let site = Site::from_cloud(&xyz, &labels, tp.cell, tp.clearance).expect("site");
        (graph, site, gaps)
    }

    fn point(x: f32, y: f32) -> TargetPoint {
        TargetPoint {
            xyz: [x, y, 0.0],
            building: 1,
        }
    }

    /// The block's world and the route from `START` over point stops at `xy`.
    fn planned(xy: &[(f32, f32)]) -> (GroundGraph, Site, Vec<MissingPoint>, TargetSet, Route) {
        let (graph, site, gaps) = block();
        let targets = TargetSet {
            points: xy.iter().map(|&(x, y)| point(x, y)).collect(),
            regions: Vec::new(),
        };
        let route = plan(&graph, &targets, START, &RouteParams::default()).expect("route");
        (graph, site, gaps, targets, route)
    }

    /// The drop with default target and route params.
    fn drive_by(
        graph: &GroundGraph,
        route: &Route,
        targets: &TargetSet,
        gaps: &[MissingPoint],
        site: &Site,
    ) -> DriveBy {
        let (tp, rp) = (TargetParams::default(), RouteParams::default());
        drop_seen_on_the_way(graph, route, targets, (gaps, site), &tp, &rp)
    }

    #[test]
    fn a_stop_the_route_passes_in_view_of_is_dropped_and_the_rest_stay() {
        // 0: before the south face, on the street the route takes east
        // anyway; 1: far east, sees no gap.
        let (graph, site, gaps, targets, route) = planned(&[(25.0, 12.0), (65.0, 12.0)]);
        assert_eq!(route.order, vec![Stop::Point(0), Stop::Point(1)]);
        let d = drive_by(&graph, &route, &targets, &gaps, &site);
        assert_eq!(d.dropped, vec![0]);
        assert_eq!(d.route.order, vec![Stop::Point(1)]);
        assert!(!d.route.order.contains(&Stop::Point(0)));
        // Arrivals still name each kept stop's node, and the route got no longer.
        for (k, s) in d.route.order.iter().enumerate() {
            let Stop::Point(i) = *s else {
                panic!("no regions here")
            };
            let at = d.route.waypoints[d.route.arrivals[k]];
            let t = targets.points[i].xyz;
            assert!(
                (at[0] - t[0]).hypot(at[1] - t[1]) < 2.0,
                "stop {i} at {at:?}"
            );
        }
        assert!(
            d.route.length_m <= route.length_m + 1e-3,
            "{} > {}",
            d.route.length_m,
            route.length_m
        );
        let driven: f32 = d
            .route
            .waypoints
            .windows(2)
            .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
            .sum();
        assert!(
            (driven - d.route.length_m).abs() < 0.05 * driven,
            "{driven} vs {}",
            d.route.length_m
        );
    }

    #[test]
    fn stops_whose_gaps_the_rest_of_the_route_misses_stay() {
        // 0: before the north face (the way east runs south of the block).
        let (graph, site, gaps, targets, route) = planned(&[(25.0, 38.0), (65.0, 12.0)]);
        let d = drive_by(&graph, &route, &targets, &gaps, &site);
        assert!(d.dropped.is_empty());
        assert_eq!(d.route, route);
        let none = drive_by(&graph, &route, &targets, &[], &site);
        assert_eq!(none.route, route, "a stop that sees no gap is kept");
    }
}
