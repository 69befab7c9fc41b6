//! Unit tests of the ground graph on small synthetic clouds.

use super::*;

/// Ground points on a 0.25 m grid, x 0..40 and rows `rows` (×0.25 m), where `keep` holds.
fn ground_grid(
    rows: std::ops::Range<i32>,
    keep: impl Fn(f32, f32) -> bool,
) -> (Vec<[f32; 3]>, Vec<u8>) {
    let mut xyz = Vec::new();
    for i in 0..160 {
        for j in rows.clone() {
            let (x, y) = (i as f32 * 0.25, j as f32 * 0.25);
            if keep(x, y) {
                xyz.push([x, y, 0.0]);
            }
        }
    }
    let lab = vec![2; xyz.len()];
    (xyz, lab)
}

/// Flat ground 0..40 × 0..20 at 0.25 m, a 3 m wall along x = 20 for
/// y < 14 (open above), and a closed 6 m square pen around (8, 10).
fn cloud() -> (Vec<[f32; 3]>, Vec<u8>) {
    let (mut xyz, mut lab) = ground_grid(0..80, |x, y| !((19.8..20.2).contains(&x) && y < 14.0));
    let mut wall = |x0: f32, y0: f32, x1: f32, y1: f32| {
        let n = (((x1 - x0).abs() + (y1 - y0).abs()) / 0.1) as usize;
        for s in 0..=n {
            let t = s as f32 / n.max(1) as f32;
            for h in 0..30 {
                xyz.push([x0 + t * (x1 - x0), y0 + t * (y1 - y0), h as f32 * 0.1]);
                lab.push(6);
            }
        }
    };
    wall(20.0, 0.0, 20.0, 14.0);
    wall(5.0, 7.0, 11.0, 7.0);
    wall(11.0, 7.0, 11.0, 13.0);
    wall(11.0, 13.0, 5.0, 13.0);
    wall(5.0, 13.0, 5.0, 7.0);
    (xyz, lab)
}

#[test]
fn edges_avoid_walls_and_the_pen_is_cut_off() {
    let (xyz, lab) = cloud();
    let p = GraphParams::default();
    let g = GroundGraph::build(&xyz, &lab, [2.0, 2.0, 0.0], &p).unwrap();
    let r = g.report();
    assert!(r.nodes > 300, "{r:?}");
    assert!(
        r.unreachable_components >= 1 && r.unreachable_nodes > 4,
        "{r:?}"
    );
    // No kept node inside the pen.
    assert!(
        g.nodes_in_polygon(&[[5.0, 7.0], [11.0, 7.0], [11.0, 13.0], [5.0, 13.0]])
            .is_empty()
    );
    // No edge crosses the wall at x = 20 below y = 14, nor the pen.
    for (a, b, w) in g.edges() {
        let (p, q) = (g.positions()[a], g.positions()[b]);
        assert!(w < GraphParams::default().d_threshold());
        let crosses = (p[0] - 20.0) * (q[0] - 20.0) < 0.0 && p[1].max(q[1]) < 14.0;
        assert!(!crosses, "edge {p:?} → {q:?} crosses the wall");
        assert!(g.segment_free([p[0], p[1]], [q[0], q[1]]));
    }
    // The far side is reached through the gap: the path is longer than the straight line.
    let a = g.nearest_node([15.0, 3.0]).unwrap().0;
    let b = g.nearest_node([25.0, 3.0]).unwrap().0;
    let (d, path) = g.shortest_path(a, b).unwrap();
    assert!(d > 2.0 * 11.0 + 10.0 - 3.0, "{d}");
    assert_eq!(path.first(), Some(&a));
    assert_eq!(path.last(), Some(&b));
}

#[test]
fn bad_input_gives_errors() {
    let (xyz, lab) = cloud();
    let p = GraphParams::default();
    assert!(matches!(
        GroundGraph::build(&xyz, &lab[1..], [2.0, 2.0, 0.0], &p),
        Err(GraphError::LabelLength(_))
    ));
    let none = vec![6u8; xyz.len()];
    assert_eq!(
        GroundGraph::build(&xyz, &none, [2.0, 2.0, 0.0], &p).unwrap_err(),
        GraphError::NoGround
    );
    assert!(matches!(
        GroundGraph::build(&xyz, &lab, [200.0, 2.0, 0.0], &p),
        Err(GraphError::StartOffGraph { .. })
    ));
    let bad = GraphParams {
        d_threshold_m: crate::density::Auto::Value(0.5),
        ..p.clone()
    };
    assert!(matches!(
        bad.validate(),
        Err(crate::params::ParamError {
            field: "d_threshold_m",
            ..
        })
    ));
    let trunk = GraphParams {
        canopy_trunk_radius_m: -1.0,
        ..p.clone()
    };
    assert!(matches!(
        trunk.validate(),
        Err(crate::params::ParamError {
            field: "canopy_trunk_radius_m",
            ..
        })
    ));
    assert!(GroundGraph::build(&[], &[], [0.0; 3], &p).is_err());
}

#[test]
fn nearest_node_and_polygon_queries() {
    let (xyz, lab) = cloud();
    let g = GroundGraph::build(&xyz, &lab, [2.0, 2.0, 0.0], &GraphParams::default()).unwrap();
    let (n, d) = g.nearest_node([30.3, 4.1]).unwrap();
    assert!(d < 1.0, "{d}");
    let brute = g
        .positions()
        .iter()
        .map(|p| ((p[0] - 30.3).powi(2) + (p[1] - 4.1).powi(2)).sqrt())
        .fold(f32::INFINITY, f32::min);
    assert!((d - brute).abs() < 1e-5 && g.positions()[n][0] > 29.0);
    let far = g.nearest_node([-50.0, -50.0]).unwrap();
    assert!(far.1 > 60.0);
    let inside = g.nodes_in_polygon(&[[25.0, 2.0], [35.0, 2.0], [35.0, 8.0], [25.0, 8.0]]);
    assert!(inside.len() > 20);
    assert!(
        inside
            .iter()
            .all(|&i| (25.0..35.0).contains(&g.positions()[i][0]))
    );
}

/// Two banks 0..20 × 0..10 and 0..20 × 18..28 at 0.25 m, a canal between
/// them with a few water returns 2 m down, and a 4 m wide bridge deck
/// across it (class 17, or AHN's 26): only the bridge joins the banks.
#[test]
fn bridges_join_what_water_cuts_apart() {
    for bridge in [17u8, 26, 1] {
        let mut xyz = Vec::new();
        let mut lab = Vec::new();
        for i in 0..80 {
            for j in 0..112 {
                let (x, y) = (i as f32 * 0.25, j as f32 * 0.25);
                if !(10.0..18.0).contains(&y) {
                    xyz.push([x, y, 0.0]);
                    lab.push(2);
                } else if (8.0..12.0).contains(&x) {
                    xyz.push([x, y, 0.0]);
                    lab.push(bridge);
                } else if i % 8 == 0 && j % 8 == 0 {
                    xyz.push([x, y, -2.0]);
                    lab.push(9);
                }
            }
        }
        let g = GroundGraph::build(&xyz, &lab, [2.0, 2.0, 0.0], &GraphParams::default()).unwrap();
        let far_bank = g.nearest_node([2.0, 26.0]).is_some_and(|(_, d)| d < 1.0);
        assert_eq!(
            far_bank,
            bridge != 1,
            "bridge class {bridge}: {:?}",
            g.report()
        );
    }
}

/// Two 40 m patches of ground 600 m apart, each with a 3 m wall along x = x0 + 20.
fn two_patches() -> (Vec<[f32; 3]>, Vec<u8>, Vec<[f32; 2]>) {
    let (mut xyz, mut lab, mut wall) = (Vec::new(), Vec::new(), Vec::new());
    for o in [0.0f32, 600.0] {
        for i in 0..80 {
            for j in 0..80 {
                xyz.push([o + i as f32 * 0.5, o + j as f32 * 0.5, 0.0]);
                lab.push(2);
            }
        }
        for s in 0..300 {
            let p = [o + 20.0, o + s as f32 * 0.1];
            wall.push(p);
            for h in 0..30 {
                xyz.push([p[0], p[1], h as f32 * 0.1]);
                lab.push(6);
            }
        }
    }
    (xyz, lab, wall)
}

#[test]
fn the_node_grid_and_obstacle_map_are_stored_near_ground_only_and_measure_as_dense_ones() {
    let (xyz, lab, wall) = two_patches();
    let g = GroundGraph::build(&xyz, &lab, [2.0, 2.0, 0.0], &GraphParams::default()).unwrap();
    let r = g.report();
    // The bounding box is 640 m square (6.6e6 cells at 0.25 m); two 40 m patches and their tile rings are not.
    assert!(r.obstacle_cells_bbox > 6_000_000, "{r:?}");
    assert!(
        r.obstacle_cells_stored * 20 < r.obstacle_cells_bbox,
        "{r:?}"
    );
    // So is the node grid: 512² cells over the box, two patches of 32² and their tile rings.
    assert!(r.node_grid_cells_bbox > 250_000, "{r:?}");
    assert!(r.node_grid_cells * 20 < r.node_grid_cells_bbox, "{r:?}");
    let mut checked = 0;
    for (i, p) in g.positions().iter().enumerate() {
        let d = wall
            .iter()
            .map(|w| (w[0] - p[0]).hypot(w[1] - p[1]))
            .fold(f32::INFINITY, f32::min);
        if d < 3.0 {
            // Chamfer distance on a 0.25 m grid: within half a cell and a few per cent.
            assert!(
                (g.clearance(i) - d).abs() < 0.4,
                "node {p:?}: {} vs {d}",
                g.clearance(i)
            );
            checked += 1;
        }
    }
    assert!(checked > 20, "{checked}");
}

#[test]
fn without_a_start_the_largest_component_is_kept() {
    let (xyz, lab) = cloud();
    let p = GraphParams::default();
    // Started inside the pen, the graph is the pen.
    let pen = GroundGraph::build(&xyz, &lab, [8.0, 10.0, 0.0], &p).unwrap();
    let largest = GroundGraph::build_largest(&xyz, &lab, &p).unwrap();
    let outside = GroundGraph::build(&xyz, &lab, [2.0, 2.0, 0.0], &p).unwrap();
    assert!(pen.len() < 30, "pen: {} nodes", pen.len());
    assert_eq!(largest.len(), outside.len());
    assert_eq!(largest.report(), outside.report());
    // Its start is a node of its own, near the open ground's middle.
    let s = largest.positions()[largest.start_node()];
    assert!(
        (s[0] - 20.0).abs() < 8.0 && (s[1] - 10.0).abs() < 8.0,
        "{s:?}"
    );
    // No ground, no graph.
    assert!(matches!(
        GroundGraph::build_largest(&xyz[..0], &lab[..0], &p),
        Err(GraphError::NoGround)
    ));
}

/// A street 8 m wide between walls at y = 1 and y = 9, x 0..40, and a
/// tree over it whose crown (a dome 3.5 m in radius, 4.2–6 m up, top over
/// (20, 5)) spans the street; as from the air, no trunk points, but ground
/// returns beneath the crown.
fn street_under_a_crown() -> (Vec<[f32; 3]>, Vec<u8>) {
    let (mut xyz, mut lab) = ground_grid(4..36, |_, _| true);
    for i in 0..400 {
        for y in [1.0f32, 9.0] {
            for h in 0..30 {
                xyz.push([i as f32 * 0.1, y, h as f32 * 0.1]);
                lab.push(6);
            }
        }
    }
    for i in 0..70 {
        for j in 0..70 {
            let (x, y) = (16.5 + i as f32 * 0.1, 1.5 + j as f32 * 0.1);
            let d = (x - 20.0).hypot(y - 5.0);
            if d < 3.5 {
                xyz.push([x, y, 6.0 - 0.15 * d * d]);
                lab.push(5);
            }
        }
    }
    (xyz, lab)
}

#[test]
fn a_crown_over_measured_ground_blocks_only_its_trunk() {
    let start = [2.0, 5.0, 0.0];
    let far = |g: &GroundGraph| g.positions().iter().any(|p| p[0] > 35.0);
    let column = GraphParams::default();
    let trunks = GraphParams {
        canopy_trunk_radius_m: 0.5,
        ..GraphParams::default()
    };
    let (xyz, lab) = street_under_a_crown();
    let g = GroundGraph::build(&xyz, &lab, start, &column).unwrap();
    assert!(!far(&g), "the whole crown cuts the street");
    let g = GroundGraph::build(&xyz, &lab, start, &trunks).unwrap();
    assert!(far(&g), "under the crown the street stays open");
    let near_trunk = g
        .positions()
        .iter()
        .map(|p| (p[0] - 20.0).hypot(p[1] - 5.0))
        .fold(f32::INFINITY, f32::min);
    assert!(near_trunk > 0.9, "a node {near_trunk} m from the trunk");
    for (a, b, _) in g.edges() {
        let (p, q) = (g.positions()[a], g.positions()[b]);
        assert!(g.segment_free([p[0], p[1]], [q[0], q[1]]));
    }
}

#[test]
fn what_crowns_cost_is_the_graph_with_them_blocking_only_in_the_band() {
    let start = [2.0, 5.0, 0.0];
    let (xyz, lab) = street_under_a_crown();
    let whole = GroundGraph::build(&xyz, &lab, start, &GraphParams::default()).unwrap();
    let open = whole
        .if_crowns_block_only_in_band(&xyz, &lab)
        .unwrap()
        .unwrap();
    let band_only = GraphParams {
        canopy_is_obstacle: false,
        ..GraphParams::default()
    };
    let direct = GroundGraph::build(&xyz, &lab, start, &band_only).unwrap();
    assert_eq!(open, direct.report());
    assert!(
        open.nodes > 2 * whole.len(),
        "{open:?} against {}",
        whole.len()
    );
    // A graph that lets crowns already has nothing to compare.
    assert!(
        direct
            .if_crowns_block_only_in_band(&xyz, &lab)
            .unwrap()
            .is_none()
    );
}

/// Ground of kind Ground: a 50 m × 30 m plain at z = 0, a 3 m high
/// plateau over x 15..25, y −5..12 (a quay), and a ridge 0.3 m wide and
/// 3 m high over x 30..30.3, y −5..15 (the spikes city-model ground
/// carries); both are boxes whose sides are ground too, as a model's are.
fn stepped_scene() -> crate::scene::Scene {
    use crate::lidar::synthetic::SyntheticBuilder;
    use crate::scene::ObjectKind;
    let mut b = SyntheticBuilder::new();
    let ground = b.object("ground", ObjectKind::Ground);
    b.add_terrain(ground, [-5.0, -5.0], [45.0, 25.0], 1, |_, _| 0.0);
    let quay = ([15.0, -5.0, 0.0], [25.0, 12.0, 3.0]);
    let ridge = ([30.0, -5.0, 0.0], [30.3, 15.0, 3.0]);
    for (lo, hi) in [quay, ridge] {
        b.add_box(ground, lo, hi, f32::INFINITY);
    }
    b.finish()
}

/// The graph leaves out every edge the vehicle would refuse: a route
/// planned over a 3 m quay and a 3 m ridge goes round both, and the
/// simulated vehicle drives it to the end without a slope block.
#[test]
fn routes_go_round_drops_and_the_vehicle_drives_them_unblocked() {
    use crate::lidar::Caster;
    use crate::vehicle::{Step, Terrain, Vehicle, VehicleConfig};
    let caster = Caster::new(&stepped_scene()).unwrap();
    let terrain = Terrain::new(&caster);
    // The prior: ground points every 0.25 m, as an aerial survey sees the ground.
    let mut xyz = Vec::new();
    for i in 0..200 {
        for j in 0..120 {
            let (x, y) = (-4.9 + i as f32 * 0.25, -4.9 + j as f32 * 0.25);
            if let Some(z) = terrain.ground_height(x, y) {
                xyz.push([x, y, z]);
            }
        }
    }
    let labels = vec![2u8; xyz.len()];
    let g = GroundGraph::build(&xyz, &labels, [2.0, 0.0, 0.0], &GraphParams::default()).unwrap();
    // No edge joins the plain to the quay's top or climbs onto the ridge.
    for (a, b, _) in g.edges() {
        let (p, q) = (g.positions()[a], g.positions()[b]);
        assert!(
            (p[2] - q[2]).abs() < 0.5,
            "edge {p:?} → {q:?} crosses a 3 m step"
        );
        // Where the edge meets the ridge's midline, if it does.
        let t = (30.15 - p[0]) / (q[0] - p[0]);
        let crosses_ridge = (0.0..=1.0).contains(&t) && p[1] + t * (q[1] - p[1]) <= 15.0;
        assert!(!crosses_ridge, "edge {p:?} → {q:?} crosses the ridge");
    }
    let a = g.nearest_node([2.0, 0.0]).unwrap().0;
    let b = g.nearest_node([40.0, 0.0]).unwrap().0;
    let (len, path) = g
        .shortest_path(a, b)
        .expect("the far side is reached round the ridge's end");
    // Round the quay (y 12) and the ridge (y 15): about 52 m against 38 straight.
    assert!(len > 48.0, "{len} m: the route does not go round");
    let mut v = Vehicle::new(VehicleConfig::default(), &caster, 2.0, 0.0, 0.0).unwrap();
    v.set_path(
        path.iter()
            .map(|&n| [g.positions()[n][0], g.positions()[n][1]]),
    );
    let mut arrived = 0;
    for _ in 0..(400.0 / 0.05) as usize {
        match v.step(&caster, 0.05) {
            Step::Blocked { reason, goal } => panic!("blocked before {goal:?}: {reason}"),
            Step::Arrived(_) => arrived += 1,
            Step::Idle => break,
            Step::Moving => {}
        }
    }
    assert_eq!(arrived, path.len(), "the vehicle did not finish the route");
    let end = v.state.position;
    assert!((end[0] - 40.0).hypot(end[1]) < 1.5, "{end:?}");
}
