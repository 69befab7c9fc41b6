use super::*;
use crate::geom::fixtures::flat_ground;

fn region_at(x: f64, y: f64) -> Region {
    Region {
        building: 7,
        polygon: vec![
            [x - 2.0, y - 2.0],
            [x + 2.0, y - 2.0],
            [x + 2.0, y + 2.0],
            [x - 2.0, y + 2.0],
        ],
        z: 0.0,
    }
}

fn planner(block_retries: u32) -> Planner {
    Planner::new(PlannerConfig {
        graph: GraphParams::default(),
        route: RouteParams::default(),
        block_retries,
        targets: TargetParams::default(),
        set_downs: 0,
    })
}

/// Feeds `p` the strip, the position (1, 5), no points (stamp 1) and one
/// region at (22, 5) (stamp `regions_stamp`), then ticks.
fn region_only(p: &mut Planner, regions_stamp: u64) -> Vec<PlannerCommand> {
    // Flat open ground, 40 m × 10 m, one ground point every 0.25 m.
    let (xyz, labels) = flat_ground(160, 40, 0.25);
    p.handle(PlannerEvent::Cloud { xyz, labels });
    p.handle(PlannerEvent::Position([1.0, 5.0, 0.0]));
    p.handle(PlannerEvent::Points {
        points: vec![],
        stamp: 1,
    });
    p.handle(PlannerEvent::Regions {
        regions: vec![region_at(22.0, 5.0)],
        stamp: regions_stamp,
    });
    p.handle(PlannerEvent::Tick)
}

/// Feeds `p` a target set of `points` and no regions, then ticks.
fn points_only(p: &mut Planner, points: Vec<TargetPoint>, stamp: u64) -> Vec<PlannerCommand> {
    p.handle(PlannerEvent::Points { points, stamp });
    p.handle(PlannerEvent::Regions {
        regions: vec![],
        stamp,
    });
    p.handle(PlannerEvent::Tick)
}

/// Targets at (10, 5) on building 1 and (35, 5) on building 2.
fn two_points() -> Vec<TargetPoint> {
    [(10.0, 1), (35.0, 2)]
        .map(|(x, building)| TargetPoint {
            xyz: [x, 5.0, 0.0],
            building,
        })
        .to_vec()
}

/// A planner fed with the strip, two points and one region, at (1, 5).
fn ready(block_retries: u32, stamp: u64) -> (Planner, Vec<PlannerCommand>) {
    let mut p = planner(block_retries);
    // Flat open ground, 40 m × 10 m, one ground point every 0.25 m.
    let (xyz, labels) = flat_ground(160, 40, 0.25);
    p.handle(PlannerEvent::Cloud { xyz, labels });
    p.handle(PlannerEvent::Position([1.0, 5.0, 0.0]));
    let points = two_points();
    p.handle(PlannerEvent::Points { points, stamp });
    p.handle(PlannerEvent::Regions {
        regions: vec![region_at(22.0, 5.0)],
        stamp,
    });
    let out = p.handle(PlannerEvent::Tick);
    (p, out)
}

/// A planner with two tries per blocked stop and `set_downs` a round.
fn with_set_downs(set_downs: usize) -> Planner {
    Planner::new(PlannerConfig {
        graph: GraphParams::default(),
        route: RouteParams::default(),
        block_retries: 2,
        targets: TargetParams::default(),
        set_downs,
    })
}

/// Where `out` asks for the robot to be set down, if it does.
fn set_down_of(out: &[PlannerCommand]) -> Option<[f32; 3]> {
    out.iter().find_map(|c| match c {
        PlannerCommand::SetDown(at) => Some(*at),
        _ => None,
    })
}

fn legs(out: &[PlannerCommand]) -> Vec<Vec<[f32; 3]>> {
    out.iter()
        .filter_map(|c| match c {
            PlannerCommand::Leg(l) => Some(l.clone()),
            _ => None,
        })
        .collect()
}

fn arrived(at: [f32; 3]) -> PlannerEvent {
    PlannerEvent::Vehicle(VehicleStatus {
        name: "vehicle_sim".into(),
        event: VehicleEvent::Arrived,
        goal: [at[0], at[1]],
        at: [at[0], at[1]],
        odometer_m: 0.0,
    })
}

fn blocked(goal: [f32; 3], at: [f32; 2]) -> PlannerEvent {
    PlannerEvent::Vehicle(VehicleStatus {
        name: "vehicle_sim".into(),
        event: VehicleEvent::Blocked("obstacle ahead".into()),
        goal: [goal[0], goal[1]],
        at,
        odometer_m: 0.0,
    })
}

fn done(region: usize, round: u32) -> PlannerEvent {
    PlannerEvent::Explorer(ExplorerStatus {
        state: ExplorerState::Done {
            region,
            round,
            coverage: 0.9,
        },
        resampled_points: 0,
    })
}

/// Drives the mission to its end; returns the stops reached in order.
fn drive(p: &mut Planner, mut out: Vec<PlannerCommand>) -> Vec<String> {
    let mut log = Vec::new();
    for _ in 0..20 {
        let Some(leg) = legs(&out).pop() else { break };
        let goal = *leg.last().expect("a leg has a pose");
        out = p.handle(arrived(goal));
        if let Phase::Exploring(_) = p.phase() {
            let Some((i, b)) = p.status().active_region else {
                panic!("no active region")
            };
            assert!(
                out.iter()
                    .any(|c| matches!(c, PlannerCommand::ActiveRegion(Some(r)) if r.building == b))
            );
            log.push(format!("region {i}"));
            // A stale "done" of another round is not ours.
            assert!(p.handle(done(i, p.round() + 1)).is_empty());
            out = p.handle(done(i, p.round()));
            assert!(out.contains(&PlannerCommand::ActiveRegion(None)));
        } else {
            log.push(format!("point at {:.0}", goal[0]));
        }
    }
    log
}

#[test]
fn a_mission_runs_every_stop_once_and_ends_done() {
    let (mut p, out) = ready(2, 1);
    assert_eq!(p.round(), 1);
    assert!(
        out.iter()
            .any(|c| matches!(c, PlannerCommand::GlobalPath(w) if w.len() > 10))
    );
    assert_eq!(p.phase(), Phase::Driving(0));
    let log = drive(&mut p, out);
    assert_eq!(log.len(), 3, "{log:?}");
    assert!(log.contains(&"region 0".to_string()), "{log:?}");
    assert_eq!(p.phase(), Phase::Done);
    let s = p.status();
    assert_eq!((s.visited.points.len(), s.visited.regions.len()), (2, 1));
    assert_eq!(s.phase, "done");
    // The same targets again: no new round.
    p.handle(PlannerEvent::Regions {
        regions: vec![region_at(22.0, 5.0)],
        stamp: 1,
    });
    p.handle(PlannerEvent::Tick);
    assert_eq!(p.round(), 1);
}

#[test]
fn halves_of_different_target_sets_are_not_planned() {
    let mut p = planner(2);
    let out = region_only(&mut p, 2);
    assert!(legs(&out).is_empty());
    assert_eq!((p.round(), p.phase()), (0, Phase::Waiting));
}

#[test]
fn a_waiting_planner_names_what_it_lacks() {
    let mut p = planner(2);
    assert_eq!(
        p.waiting_for().as_deref(),
        Some("/classified_cloud, /target_points, /target_regions, /state_estimation")
    );
    let (xyz, labels) = flat_ground(160, 40, 0.25);
    p.handle(PlannerEvent::Cloud { xyz, labels });
    p.handle(PlannerEvent::Position([1.0, 5.0, 0.0]));
    p.handle(PlannerEvent::Regions {
        regions: vec![],
        stamp: 3,
    });
    assert_eq!(p.waiting_for().as_deref(), Some("/target_points"));
    // A points half of another set: both halves are there but never pair.
    p.handle(PlannerEvent::Points {
        points: two_points(),
        stamp: 4,
    });
    p.handle(PlannerEvent::Tick);
    let said = p.waiting_for().unwrap_or_default();
    assert!(
        said.contains("stamped 4") && said.contains("/target_regions 3"),
        "{said}"
    );
    // Once planned, nothing is lacking, also after the round is driven.
    let (mut p, out) = ready(2, 1);
    assert_eq!(p.waiting_for(), None);
    drive(&mut p, out);
    assert_eq!(p.waiting_for(), None);
}

#[test]
fn new_targets_start_a_new_round() {
    let (mut p, out) = ready(2, 1);
    drive(&mut p, out);
    let points = vec![TargetPoint {
        xyz: [30.0, 8.0, 0.0],
        building: 3,
    }];
    let out = points_only(&mut p, points, 2);
    assert_eq!(p.round(), 2);
    assert_eq!(legs(&out).len(), 1);
    assert!(p.status().visited.points.is_empty());
}

#[test]
fn a_blocked_stop_is_replanned_around_then_given_up() {
    let (mut p, out) = ready(1, 1);
    let goal = *legs(&out)[0].last().expect("pose");
    assert!((goal[0] - 10.0).abs() < 1.0, "first stop {goal:?}");
    // Blocked at x = 6 on the way to x = 10: the spot ahead is taken out.
    let out = p.handle(blocked(goal, [6.0, 5.0]));
    assert!(legs(&out).is_empty());
    assert_eq!(p.phase(), Phase::Waiting);
    let spots = p.status().blocked;
    assert_eq!(spots.len(), 1);
    let d = (spots[0].at[0] - 6.0).hypot(spots[0].at[1] - 5.0);
    assert!(
        (d - spots[0].radius).abs() < 1e-4 && spots[0].at[0] > 6.0,
        "{spots:?}"
    );
    let out = p.handle(PlannerEvent::Tick);
    let leg = &legs(&out)[0];
    for q in leg {
        let d = (q[0] - spots[0].at[0]).hypot(q[1] - spots[0].at[1]);
        assert!(
            d > spots[0].radius,
            "replanned leg passes the blocked spot at {q:?}"
        );
    }
    assert!(p.status().given_up.points.is_empty());
    // Once more blocked: more than block_retries = 1 tries, the stop is given up.
    p.handle(blocked(goal, [7.0, 3.0]));
    assert_eq!(p.status().visited.points, vec![0]);
    assert_eq!(
        p.status().given_up.points,
        vec![0],
        "a given-up stop is dealt with, not reached"
    );
    let out = p.handle(PlannerEvent::Tick);
    let next = *legs(&out)[0].last().expect("pose");
    assert!(
        (next[0] - 10.0).abs() > 3.0,
        "still going to the given-up stop: {next:?}"
    );
}

#[test]
fn a_restarted_planner_goes_on_where_it_was() {
    let (mut before, out) = ready(2, 1);
    let goal = *legs(&out)[0].last().expect("pose");
    before.handle(arrived(goal));
    before.handle(blocked([30.0, 5.0, 0.0], [14.0, 5.0]));
    let saved = before.status();
    assert_eq!(saved.visited.points, vec![0]);
    assert!(saved.given_up.points.is_empty(), "stop 0 was reached");

    // Restarted: the latched status arrives before the route.
    let mut p = planner(2);
    let mut restored = saved.clone();
    restored.round = 4;
    p.handle(PlannerEvent::Restore(restored));
    // Flat open ground, 40 m × 10 m, one ground point every 0.25 m.
    let (xyz, labels) = flat_ground(160, 40, 0.25);
    p.handle(PlannerEvent::Cloud { xyz, labels });
    p.handle(PlannerEvent::Position(goal));
    let points = two_points();
    p.handle(PlannerEvent::Points { points, stamp: 1 });
    p.handle(PlannerEvent::Regions {
        regions: vec![region_at(22.0, 5.0)],
        stamp: 1,
    });
    p.handle(PlannerEvent::Tick);
    let s = p.status();
    assert_eq!(s.round, 4);
    assert_eq!(s.visited.points, vec![0]);
    assert_eq!(s.stops, 2, "the visited point is not planned again");
    assert_eq!(s.blocked, saved.blocked);
    // A restore that does not match the target set is a new round.
    let mut q = planner(2);
    let mut other = saved;
    other.target_points = 9;
    q.handle(PlannerEvent::Restore(other));
    region_only(&mut q, 1);
    assert_eq!((q.round(), q.status().visited.points.len()), (1, 0));
}

#[test]
fn a_resumed_planner_finishes_the_kept_round_before_a_new_set() {
    let (mut before, out) = ready(2, 5);
    let kept = out
        .iter()
        .find_map(|c| match c {
            PlannerCommand::KeepRound(k) => Some(k.as_ref().clone()),
            _ => None,
        })
        .expect("a new round keeps its targets");
    assert_eq!(
        (kept.round, kept.stamp, kept.targets.points.len()),
        (1, 5, 2)
    );
    let goal = *legs(&out)[0].last().expect("pose");
    before.handle(arrived(goal));
    let saved = before.status();
    assert_eq!(saved.visited.points, vec![0]);

    // Resumed: the status and the round come back; the run's first
    // detection brings another set (one point, stamp 9).
    let mut p = planner(2);
    p.handle(PlannerEvent::Restore(saved.clone()));
    p.handle(PlannerEvent::RestoreRound(kept.clone()));
    let (xyz, labels) = flat_ground(160, 40, 0.25);
    p.handle(PlannerEvent::Cloud { xyz, labels });
    p.handle(PlannerEvent::Position(goal));
    let later = vec![TargetPoint {
        xyz: [30.0, 8.0, 0.0],
        building: 3,
    }];
    let out = points_only(&mut p, later.clone(), 9);
    let s = p.status();
    assert_eq!((s.round, s.target_points, s.target_regions), (1, 2, 1));
    assert_eq!(s.visited.points, vec![0], "what was reached stays reached");
    assert_eq!(
        s.stops, 2,
        "the kept round's remaining stops: a point and a region"
    );
    let next = *legs(&out)[0].last().expect("a leg");
    assert!(
        (next[0] - 10.0).abs() > 3.0,
        "the reached stop again: {next:?}"
    );
    // The set it stood in for does not end the round on the next tick.
    p.handle(PlannerEvent::Tick);
    assert_eq!((p.round(), p.status().target_points), (1, 2));
    // A newer set is the next round.
    points_only(&mut p, later, 10);
    assert_eq!((p.round(), p.status().target_points), (2, 1));

    // A kept round that is not the status's (another count) is not taken.
    let mut q = planner(2);
    q.handle(PlannerEvent::Restore(saved.clone()));
    let mut other = kept.clone();
    other.targets.points.pop();
    q.handle(PlannerEvent::RestoreRound(other));
    region_only(&mut q, 1);
    assert_eq!((q.round(), q.status().visited.points.len()), (1, 0));
    // Nor one whose status says its route was done.
    let mut r = planner(2);
    r.handle(PlannerEvent::Restore(PlannerStatus {
        phase: "done".into(),
        ..saved
    }));
    r.handle(PlannerEvent::RestoreRound(kept));
    let out = points_only(&mut r, vec![], 9);
    assert!(legs(&out).is_empty() && r.status().target_points == 0);
}

#[test]
fn stops_whose_gaps_the_route_sees_anyway_are_left_off_and_stay_off() {
    // Gaps on a west-facing wall at x = 28, 2 m up. The stops at (10, 5) and
    // (20, 6) see them (18 and 8 m off); so does the way from (1, 5) to the
    // stop at (35, 5), behind the wall, which sees none of them.
    let gaps = [4.5, 5.0, 5.5].map(|y| MissingPoint {
        xyz: [28.0, y, 2.0],
        building: 1,
        normal: [-1.0, 0.0],
        skeleton: [30.0, y],
    });
    let run = |skip_seen: bool| {
        let mut p = Planner::new(PlannerConfig {
            graph: GraphParams::default(),
            route: RouteParams {
                skip_seen,
                ..RouteParams::default()
            },
            block_retries: 2,
            targets: TargetParams::default(),
            set_downs: 0,
        });
        let (xyz, labels) = flat_ground(160, 40, 0.25);
        p.handle(PlannerEvent::Cloud { xyz, labels });
        p.handle(PlannerEvent::Position([1.0, 5.0, 0.0]));
        p.handle(PlannerEvent::Missing(gaps.to_vec()));
        let mut points = two_points();
        points.push(TargetPoint {
            xyz: [20.0, 6.0, 0.0],
            building: 1,
        });
        let out = points_only(&mut p, points, 1);
        let goal = *legs(&out)[0].last().expect("pose");
        (p, goal)
    };
    let (p, goal) = run(false);
    assert_eq!((p.status().stops, p.status().seen_on_the_way.len()), (3, 0));
    assert!((goal[0] - 10.0).abs() < 1.0, "first stop {goal:?}");

    let (mut p, goal) = run(true);
    let s = p.status();
    assert_eq!(s.seen_on_the_way, vec![0, 2]);
    assert_eq!(s.stops, 1);
    assert!((goal[0] - 35.0).abs() < 1.0, "the one stop left {goal:?}");
    let back = PlannerStatus::from_wire(&s.to_wire()).expect("status reads back");
    assert_eq!(back.seen_on_the_way, vec![0, 2]);
    // Blocked on the way: the route made again leaves them off too.
    p.handle(blocked(goal, [15.0, 5.0]));
    let out = p.handle(PlannerEvent::Tick);
    let again = *legs(&out)[0].last().expect("a new leg");
    assert!((again[0] - 35.0).abs() < 1.0, "{again:?}");
    assert_eq!(p.status().stops, 1);
    // The mission ends with the two stops counted as seen, not reached.
    p.handle(arrived(again));
    assert_eq!(p.phase(), Phase::Done);
    assert_eq!(p.status().visited.points, vec![1]);
}

/// Targets at (20, 10) on open ground and (30, 10) inside a walled pen:
/// with `set_downs` 1, the planner drives the open one, asks for the robot
/// in the pen, plans there once it stands there, and ends done with both.
#[test]
fn a_target_behind_walls_gets_a_set_down_and_is_driven_after_it() {
    let run = |set_downs: usize| {
        let mut p = with_set_downs(set_downs);
        let (xyz, labels) = crate::geom::fixtures::pens(&[([25.0, 5.0], [35.0, 15.0])]);
        p.handle(PlannerEvent::Cloud { xyz, labels });
        p.handle(PlannerEvent::Position([2.0, 2.0, 0.0]));
        let points = [20.0, 30.0]
            .map(|x| TargetPoint {
                xyz: [x, 10.0, 0.0],
                building: 1,
            })
            .to_vec();
        let out = points_only(&mut p, points, 1);
        (p, out)
    };

    let (mut p, out) = run(0);
    drive(&mut p, out);
    assert_eq!(p.phase(), Phase::Done, "no set-downs allowed: done at once");
    assert_eq!(p.status().unreachable_points, 1);

    // A set-down the robot cannot take (vehicle_sim: off its terrain) is
    // given up: that piece is not asked for again, and the round is done.
    let (mut p, out) = run(3);
    let leg = legs(&out).pop().expect("a leg to the open target");
    p.handle(arrived(*leg.last().expect("a leg has a pose")));
    let to = p.carry_to.expect("a set-down asked for");
    let refused = p.handle(blocked(to, [20.0, 10.0]));
    assert!(
        refused
            .iter()
            .any(|c| matches!(c, PlannerCommand::Warn(w) if w.contains("set-down at") && w.contains("failed"))),
        "{refused:?}"
    );
    assert_eq!(set_down_of(&refused), None);
    assert_eq!(p.phase(), Phase::Done);

    let (mut p, out) = run(1);
    let leg = legs(&out).pop().expect("a leg to the open target");
    let goal = *leg.last().expect("a leg has a pose");
    assert!((goal[0] - 20.0).abs() < 2.0, "{goal:?}");
    let ended = p.handle(arrived(goal));
    assert_eq!(p.phase(), Phase::Carrying);
    assert_eq!(p.status().phase, "carrying");
    let to = set_down_of(&ended).expect("a set-down with the route's end");
    assert!(
        (25.0..35.0).contains(&to[0]) && (5.0..15.0).contains(&to[1]),
        "the set-down is inside the pen: {to:?}"
    );
    // Still outside: nothing is planned.
    assert!(legs(&p.handle(PlannerEvent::Position([2.0, 2.0, 0.0]))).is_empty());
    p.handle(PlannerEvent::Tick);
    assert_eq!(p.phase(), Phase::Carrying);
    // Set down 1 m off the spot asked for: planned there, same round.
    p.handle(PlannerEvent::Position([to[0] + 1.0, to[1], 0.0]));
    let out = p.handle(PlannerEvent::Tick);
    assert_eq!(p.round(), 1);
    let log = drive(&mut p, out);
    assert_eq!(log, vec!["point at 30"]);
    assert_eq!(p.phase(), Phase::Done, "one set-down a round at most");
    let s = p.status();
    assert_eq!(s.visited.points.len(), 2);
    assert_eq!(s.unreachable_points, 0);
}

/// A corridor 40 m × 1.25 m, the robot at its west end, a target at x = 30.
/// The robot reports the way east blocked: the spot cuts it off. With a
/// set-down left, the planner asks for it to be carried past the spot and
/// drives on from there; without, the round ends with the target out of reach.
#[test]
fn a_robot_its_blocked_spots_cut_off_is_carried_out() {
    let run = |set_downs: usize| {
        let mut p = with_set_downs(set_downs);
        let (xyz, labels) = flat_ground(160, 6, 0.25);
        p.handle(PlannerEvent::Cloud { xyz, labels });
        p.handle(PlannerEvent::Position([1.2, 0.6, 0.0]));
        let target = TargetPoint {
            xyz: [30.0, 0.6, 0.0],
            building: 1,
        };
        let out = points_only(&mut p, vec![target], 1);
        let goal = *legs(&out)[0].last().expect("a leg has a pose");
        p.handle(blocked(goal, [1.2, 0.6]));
        let out = p.handle(PlannerEvent::Tick);
        (p, out)
    };

    let (mut p, out) = run(1);
    assert_eq!(p.phase(), Phase::Carrying, "{out:?}");
    let to = set_down_of(&out).expect("a set-down");
    let spot = p.status().blocked[0];
    assert!(
        to[0] - spot.at[0] > spot.radius && to[0] < 1.2 + crate::route::WAY_OUT_MAX_M,
        "carried just past the spot: {to:?}, {spot:?}"
    );
    assert!(
        out.iter()
            .any(|c| matches!(c, PlannerCommand::Warn(w) if w.contains("cut the robot off"))),
        "{out:?}"
    );
    p.handle(PlannerEvent::Position(to));
    let out = p.handle(PlannerEvent::Tick);
    assert_eq!(drive(&mut p, out), vec!["point at 30"]);
    assert_eq!(p.phase(), Phase::Done);
    assert_eq!(p.status().visited.points, vec![0]);

    let (p, out) = run(0);
    assert_eq!(set_down_of(&out), None, "{out:?}");
    assert_eq!(p.phase(), Phase::Done);
    assert_eq!(p.status().unreachable_points, 1);

    // Set down past the spot, then blocked on both sides until no node is
    // left within the snap distance: no route can start there, and the
    // robot is carried out all the same (the round's second set-down).
    let (mut p, out) = run(2);
    let to = set_down_of(&out).expect("a set-down");
    p.handle(PlannerEvent::Position(to));
    let out = p.handle(PlannerEvent::Tick);
    let goal = *legs(&out)[0].last().expect("a leg has a pose");
    let r = [to[0], to[1]];
    for (gx, ax) in [
        (-9.0, 0.0),
        (-9.0, -1.5),
        (-9.0, -2.4),
        (9.0, -0.9),
        (9.0, 1.5),
        (9.0, 2.4),
    ] {
        p.handle(blocked([r[0] + gx, r[1], 0.0], [r[0] + ax, r[1]]));
    }
    p.handle(blocked(goal, r));
    let out = p.handle(PlannerEvent::Tick);
    assert_eq!(p.phase(), Phase::Carrying, "{out:?}");
    assert!(
        !out.iter().any(|c| matches!(c, PlannerCommand::Error(_))),
        "{out:?}"
    );
}
