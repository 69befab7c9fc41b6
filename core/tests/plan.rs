//! Ground graph and global route on the reference scene with its simulated
//! aerial prior (labels are ground truth): every reachable target is on the
//! route, the TSP tour beats the paper's greedy one, no path segment passes
//! through a building or tree (ray casts against the mesh), and a target in
//! the closed courtyard is unreachable.

mod planning_scene;

use planning_scene::{
    building_box, building_named, graph, ground_z, kind_below, start, target_set, world,
};
use skyground_core::graph::GraphParams;
use skyground_core::route::{RouteParams, Stop, TourChoice, Visited, plan, replan};
use skyground_core::scene::ObjectKind;
use skyground_core::targets::{TargetPoint, TargetSet};

#[test]
fn route_reaches_every_reachable_target_and_tsp_beats_greedy() {
    let w = world();
    let g = graph();
    println!("graph: {:?}", g.report());
    let targets = target_set(w);
    assert!(
        targets.points.len() >= 30,
        "only {} point targets",
        targets.points.len()
    );
    let buildings: std::collections::HashSet<u32> =
        targets.points.iter().map(|t| t.building).collect();
    assert!(buildings.len() >= 8);
    let params = RouteParams::default();
    let route = plan(&g, &targets, start(w), &params).unwrap();
    println!(
        "{} points, {} regions: greedy {:.0} m, tsp {:.0} m (ratio {:.3}), unreachable points {:?} regions {:?}",
        targets.points.len(),
        targets.regions.len(),
        route.greedy_length_m,
        route.tsp_length_m,
        route.tsp_length_m / route.greedy_length_m,
        route.unreachable_points,
        route.unreachable_regions
    );
    // Every target is either on the route once or reported unreachable.
    for i in 0..targets.points.len() {
        let on = route.order.iter().filter(|&&s| s == Stop::Point(i)).count();
        let off = route.unreachable_points.contains(&i);
        assert!(
            (on == 1) != off,
            "point {i}: on route {on}×, unreachable {off}"
        );
    }
    for i in 0..targets.regions.len() {
        let on = route
            .order
            .iter()
            .filter(|&&s| s == Stop::Region(i))
            .count();
        assert!((on == 1) != route.unreachable_regions.contains(&i));
    }
    // The targets stand on open ground 8 m from walls: nearly all are reachable.
    assert!(
        route.unreachable_points.len() * 10 <= targets.points.len(),
        "{:?}",
        route.unreachable_points
    );
    assert!(route.unreachable_regions.is_empty());
    // Arrivals are at the targets.
    for (s, &k) in route.order.iter().zip(&route.arrivals) {
        let p = route.waypoints[k];
        match *s {
            Stop::Point(i) => {
                let t = targets.points[i].xyz;
                assert!((p[0] - t[0]).hypot(p[1] - t[1]) <= params.max_snap_m);
            }
            Stop::Region(i) => {
                let poly = &targets.regions[i].polygon;
                assert!(skyground_core::graph::polygon_contains(
                    poly,
                    [f64::from(p[0]), f64::from(p[1])]
                ));
            }
        }
    }
    assert!(route.tsp_length_m <= 0.85 * route.greedy_length_m);
    let shortest = route
        .tsp_length_m
        .min(route.greedy_length_m)
        .min(route.streets_length_m);
    assert!((route.length_m - shortest).abs() < 1e-2);
    let path_len: f32 = route
        .waypoints
        .windows(2)
        .map(|p| {
            (0..3)
                .map(|k| (p[1][k] - p[0][k]).powi(2))
                .sum::<f32>()
                .sqrt()
        })
        .sum();
    assert!(
        (path_len - route.length_m).abs() < 0.5,
        "{path_len} vs {}",
        route.length_m
    );
}

#[test]
fn no_path_segment_passes_through_a_building_or_tree() {
    let w = world();
    let g = graph();
    let route = plan(
        &g,
        &target_set(w),
        start(w),
        &RouteParams {
            tour: TourChoice::Tsp,
            ..RouteParams::default()
        },
    )
    .unwrap();
    let mut checked = 0;
    for h in [0.5f32, 1.0, GraphParams::default().vehicle_height_m] {
        for s in route.waypoints.windows(2) {
            let (a, b) = (
                [s[0][0], s[0][1], s[0][2] + h],
                [s[1][0], s[1][1], s[1][2] + h],
            );
            let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            if len < 1e-3 {
                continue;
            }
            checked += 1;
            if let Some(hit) = w.caster.cast(a, d, len) {
                let kind = w.caster.object(hit.object).map(|o| o.kind);
                assert!(
                    !matches!(kind, Some(ObjectKind::Building | ObjectKind::Vegetation)),
                    "segment {a:?} → {b:?} at {h} m hits {kind:?} after {:.2} m",
                    hit.t
                );
            }
        }
    }
    assert!(checked > 300, "{checked}");
    // Also every edge of the graph, at 1 m.
    for (a, b, _) in g.edges() {
        let (p, q) = (g.positions()[a], g.positions()[b]);
        let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if let Some(hit) = w.caster.cast([p[0], p[1], p[2] + 1.0], d, len) {
            let kind = w.caster.object(hit.object).map(|o| o.kind);
            assert!(
                !matches!(kind, Some(ObjectKind::Building | ObjectKind::Vegetation)),
                "edge {p:?} → {q:?}: {kind:?}"
            );
        }
    }
}

#[test]
fn courtyard_target_is_unreachable_and_replanning_keeps_indices() {
    let w = world();
    let g = graph();
    let court = building_named(w, "courtyard");
    let (lo, hi) = building_box(w, court);
    let centre = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
    assert_eq!(
        kind_below(w, centre),
        Some(ObjectKind::Ground),
        "courtyard centre is open ground"
    );
    // The aerial prior sees the courtyard's floor: ground nodes there exist
    // before the reachability cut, and none survive it.
    assert!(g.report().unreachable_nodes > 0 && g.report().unreachable_components > 0);
    assert!(
        g.nodes_in_polygon(&[
            [f64::from(centre[0]) - 3.0, f64::from(centre[1]) - 3.0],
            [f64::from(centre[0]) + 3.0, f64::from(centre[1]) - 3.0],
            [f64::from(centre[0]) + 3.0, f64::from(centre[1]) + 3.0],
            [f64::from(centre[0]) - 3.0, f64::from(centre[1]) + 3.0],
        ])
        .is_empty()
    );
    let mut targets = target_set(w);
    targets.points.insert(
        0,
        TargetPoint {
            xyz: [centre[0], centre[1], ground_z(w, centre)],
            building: court,
        },
    );
    let route = plan(&g, &targets, start(w), &RouteParams::default()).unwrap();
    assert!(route.unreachable_points.contains(&0));
    assert!(!route.order.contains(&Stop::Point(0)));
    // Replan from the first stop's arrival with it done: the rest, original indices.
    let first = route.order[0];
    let at = route.waypoints[route.arrivals[0]];
    let visited = match first {
        Stop::Point(i) => Visited {
            points: vec![i],
            regions: vec![],
        },
        Stop::Region(i) => Visited {
            points: vec![],
            regions: vec![i],
        },
    };
    let again = replan(&g, &targets, &visited, at, &RouteParams::default()).unwrap();
    assert_eq!(again.order.len(), route.order.len() - 1);
    assert!(!again.order.contains(&first));
    assert!(again.unreachable_points.contains(&0));
    assert!((again.waypoints[0][0] - at[0]).hypot(again.waypoints[0][1] - at[1]) < 1.0);
}

#[test]
fn empty_targets_and_bad_start() {
    let w = world();
    let g = graph();
    let r = plan(&g, &TargetSet::default(), start(w), &RouteParams::default()).unwrap();
    assert!(r.order.is_empty() && r.length_m == 0.0 && r.waypoints.len() == 1);
    let inside = {
        let (lo, hi) = building_box(w, 1);
        [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0, 0.0]
    };
    assert!(plan(&g, &TargetSet::default(), inside, &RouteParams::default()).is_err());
    assert!(
        plan(
            &g,
            &TargetSet::default(),
            start(w),
            &RouteParams {
                max_snap_m: -1.0,
                ..RouteParams::default()
            }
        )
        .is_err()
    );
}
