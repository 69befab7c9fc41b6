use super::*;
use crate::geom::fixtures::flat_ground;
use crate::mission::protocol::PlannerStatus;

/// A 4 m square region of building 7 centred at (31, 5).
fn region() -> Region {
    Region {
        building: 7,
        polygon: vec![[29.0, 3.0], [33.0, 3.0], [33.0, 7.0], [29.0, 7.0]],
        z: 0.0,
    }
}

/// The missing wall of building 7 just east of the region, and a wall of
/// building 8 (not the region's) next to it.
fn missing() -> Vec<([f32; 3], u32)> {
    let mut m = Vec::new();
    for j in 0..16 {
        for k in 0..8 {
            let (y, z) = (3.0 + j as f32 * 0.25, 0.5 + k as f32 * 0.25);
            m.push(([33.5, y, z], 7));
            m.push(([38.0, y, z], 8));
        }
    }
    m
}

fn config(block_retries: u32) -> ExplorerConfig {
    ExplorerConfig {
        graph: GraphParams::default(),
        explore: ExploreParams::default(),
        surface_margin_m: 1.0,
        publish_each_region: false,
        resample_voxel_m: 0.1,
        block_retries,
    }
}

fn planner_status(
    round: u32,
    active: Option<(usize, u32)>,
    blocked: Vec<BlockedSpot>,
) -> PlannerStatus {
    PlannerStatus {
        phase: if active.is_some() {
            "exploring"
        } else {
            "driving"
        }
        .into(),
        round,
        active_region: active,
        blocked,
        ..PlannerStatus::default()
    }
}

/// An explorer with the cloud, the missing points and the vehicle at (2, 5).
fn ready(block_retries: u32) -> ExplorerMachine {
    let mut e = ExplorerMachine::new(config(block_retries)).expect("valid config");
    // Flat open ground, 40 m × 10 m, one ground point every 0.25 m.
    let (xyz, labels) = flat_ground(160, 40, 0.25);
    e.handle(ExplorerEvent::Cloud { xyz, labels });
    e.handle(ExplorerEvent::Missing(missing()));
    e.handle(ExplorerEvent::Position([2.0, 5.0, 0.0]));
    e
}

fn legs(out: &[ExplorerCommand]) -> Vec<Vec<[f32; 3]>> {
    out.iter()
        .filter_map(|c| match c {
            ExplorerCommand::Leg(l) => Some(l.clone()),
            _ => None,
        })
        .collect()
}

fn states(out: &[ExplorerCommand]) -> Vec<ExplorerState> {
    out.iter()
        .filter_map(|c| match c {
            ExplorerCommand::Status(s) => Some(s.state.clone()),
            _ => None,
        })
        .collect()
}

fn vehicle(goal: [f32; 3], event: VehicleEvent) -> ExplorerEvent {
    ExplorerEvent::Vehicle(VehicleStatus {
        name: "vehicle_sim".into(),
        event,
        goal: [goal[0], goal[1]],
        at: [goal[0], goal[1]],
        odometer_m: 0.0,
    })
}

#[test]
fn a_region_starts_when_the_planner_names_it_and_ends_after_its_blocked_tries() {
    let mut e = ready(1);
    // The markers alone say neither index nor round: wait for the status.
    assert!(
        e.handle(ExplorerEvent::ActiveRegion(Some(region())))
            .is_empty()
    );
    // A status naming another building's region is not this one.
    assert!(
        legs(&e.handle(ExplorerEvent::Planner(planner_status(
            2,
            Some((4, 9)),
            vec![]
        ))))
        .is_empty()
    );
    let out = e.handle(ExplorerEvent::Planner(planner_status(
        2,
        Some((4, 7)),
        vec![],
    )));
    assert!(matches!(
        states(&out)[..],
        [ExplorerState::Exploring {
            region: 4,
            round: 2,
            building: 7,
            viewpoints: 0,
            ..
        }]
    ));
    let leg = legs(&out).pop().expect("a first viewpoint");
    let goal = *leg.last().expect("a leg has a pose");
    assert!(
        (29.0..=33.0).contains(&goal[0]) && (3.0..=7.0).contains(&goal[1]),
        "{goal:?}"
    );
    // Another goal's news is not ours.
    assert!(
        e.handle(vehicle([0.0, 0.0, 0.0], VehicleEvent::Arrived))
            .is_empty()
    );
    // Blocked twice with one retry allowed: the region is handed back.
    let blocked = || VehicleEvent::Blocked("obstacle ahead".into());
    e.handle(ExplorerEvent::Position(goal));
    let out = e.handle(vehicle(goal, blocked()));
    let goal = legs(&out)
        .pop()
        .map_or(goal, |l| *l.last().expect("a pose"));
    let out = e.handle(vehicle(goal, blocked()));
    assert!(
        matches!(
            states(&out)[..],
            [ExplorerState::Done {
                region: 4,
                round: 2,
                ..
            }]
        ),
        "{out:?}"
    );
    assert!(legs(&out).is_empty());
    // The same region again (a stale message) does not start it anew.
    e.handle(ExplorerEvent::ActiveRegion(Some(region())));
    let out = e.handle(ExplorerEvent::Planner(planner_status(
        2,
        Some((4, 7)),
        vec![],
    )));
    assert!(states(&out).is_empty() && legs(&out).is_empty(), "{out:?}");
    // The next round's region 4 is a new one.
    let out = e.handle(ExplorerEvent::Planner(planner_status(
        3,
        Some((4, 7)),
        vec![],
    )));
    assert!(matches!(
        states(&out)[..],
        [ExplorerState::Exploring { round: 3, .. }]
    ));
}

#[test]
fn scans_count_for_the_region_and_building_points_join_the_resampled_cloud() {
    let mut e = ready(2);
    e.handle(ExplorerEvent::ActiveRegion(Some(region())));
    let out = e.handle(ExplorerEvent::Planner(planner_status(
        1,
        Some((0, 7)),
        vec![],
    )));
    let goal = *legs(&out).pop().expect("a leg").last().expect("a pose");
    // The scan sees the whole missing wall of building 7 (and some ground).
    let wall: Vec<[f32; 3]> = missing()
        .iter()
        .filter(|(_, b)| *b == 7)
        .map(|(q, _)| *q)
        .collect();
    let mut labels = vec![class::BUILDING; wall.len()];
    let mut xyz = wall.clone();
    xyz.push([goal[0], goal[1], 0.0]);
    labels.push(class::GROUND);
    let scan = ExplorerEvent::Scan {
        id: 42,
        xyz,
        labels: Some(labels),
    };
    e.handle(scan.clone());
    let merged = e.resampled().len();
    // The same scan again (by id): left out, said, not counted.
    let again = e.handle(scan);
    assert!(
        matches!(&again[..], [ExplorerCommand::Error(s)] if s.contains("0.000000042 came again")),
        "{again:?}"
    );
    assert_eq!(
        (e.scans(), e.ids(), e.resampled().len()),
        (1, &[42][..], merged)
    );
    e.handle(ExplorerEvent::Position(goal));
    let out = e.handle(vehicle(goal, VehicleEvent::Arrived));
    match states(&out)[..] {
        [
            ExplorerState::Done {
                region: 0,
                round: 1,
                coverage,
            },
        ] => assert!(coverage > 0.99, "{coverage}"),
        _ => panic!("not done: {out:?}"),
    }
    assert_eq!(
        e.resampled().len(),
        wall.len(),
        "ground points are not resampled"
    );
    // The resampled cloud goes out once per round, when the route is done.
    let done = |round| PlannerStatus {
        phase: "done".into(),
        round,
        ..PlannerStatus::default()
    };
    assert_eq!(
        e.handle(ExplorerEvent::Planner(done(1))),
        vec![ExplorerCommand::Resampled]
    );
    assert!(e.handle(ExplorerEvent::Planner(done(1))).is_empty());
}

fn min_distance(leg: &[[f32; 3]], at: [f32; 2]) -> f32 {
    leg.iter()
        .map(|p| (p[0] - at[0]).hypot(p[1] - at[1]))
        .fold(f32::INFINITY, f32::min)
}

/// The first leg from (2, 5) to the region, with the planner's status
/// carrying `blocked`.
fn first_leg(blocked: Vec<BlockedSpot>) -> Vec<[f32; 3]> {
    let mut e = ready(2);
    e.handle(ExplorerEvent::ActiveRegion(Some(region())));
    let out = e.handle(ExplorerEvent::Planner(planner_status(
        1,
        Some((0, 7)),
        blocked,
    )));
    legs(&out).pop().expect("a leg")
}

#[test]
fn the_explorer_does_not_route_through_a_spot_the_planner_blocked() {
    let spot = BlockedSpot {
        at: [16.0, 6.5],
        radius: 2.0,
    };
    // Open ground: the way to the region runs straight through the spot.
    let free = first_leg(vec![]);
    assert!(min_distance(&free, spot.at) < 1.0, "{free:?}");
    // Blocked by the planner: around it, every pose clear of it.
    let around = first_leg(vec![spot]);
    assert!(around.len() > 2, "{around:?}");
    let d = min_distance(&around, spot.at);
    assert!(
        d > spot.radius,
        "passes {d:.2} m from the blocked spot: {around:?}"
    );
    let length = |l: &[[f32; 3]]| {
        l.windows(2)
            .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
            .sum::<f32>()
    };
    assert!(length(&around) > length(&free) + 0.5);
}

#[test]
fn spots_blocked_after_the_graph_is_built_count_for_the_next_region() {
    let spot = BlockedSpot {
        at: [16.0, 6.5],
        radius: 2.0,
    };
    let mut e = ready(0);
    e.handle(ExplorerEvent::ActiveRegion(Some(region())));
    e.handle(ExplorerEvent::Planner(planner_status(
        1,
        Some((0, 7)),
        vec![],
    )));
    assert!(e.graph().is_some());
    // The planner takes the region back, then is blocked on its way.
    e.handle(ExplorerEvent::ActiveRegion(None));
    e.handle(ExplorerEvent::Planner(planner_status(1, None, vec![spot])));
    e.handle(ExplorerEvent::ActiveRegion(Some(region())));
    let out = e.handle(ExplorerEvent::Planner(planner_status(
        1,
        Some((1, 7)),
        vec![spot],
    )));
    let leg = legs(&out).pop().expect("a leg");
    assert!(min_distance(&leg, spot.at) > spot.radius, "{leg:?}");
}

/// Hands the explorer region `index` (building 7) of round 1.
fn hand_over(e: &mut ExplorerMachine, index: usize) -> Vec<ExplorerCommand> {
    e.handle(ExplorerEvent::ActiveRegion(Some(region())));
    e.handle(ExplorerEvent::Planner(planner_status(
        1,
        Some((index, 7)),
        vec![],
    )))
}

#[test]
fn a_set_down_drops_the_graph_so_the_next_region_builds_it_where_the_vehicle_stands() {
    let mut e = ready(0);
    hand_over(&mut e, 0);
    assert!(e.graph().is_some());
    e.handle(ExplorerEvent::ActiveRegion(None));
    e.handle(ExplorerEvent::Planner(planner_status(1, None, vec![])));
    assert!(e.graph().is_some(), "driving on: the graph stays");
    let carrying = PlannerStatus {
        phase: Phase::Carrying.word().into(),
        round: 1,
        ..PlannerStatus::default()
    };
    e.handle(ExplorerEvent::Planner(carrying));
    assert!(
        e.graph().is_none(),
        "carried to another piece: built again there"
    );
    hand_over(&mut e, 1);
    assert!(e.graph().is_some());
}
