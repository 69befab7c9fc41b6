//! The drone's plan for the walls of a 10 m cube, flown in the simulation.

use super::*;
use crate::airspace::AirspaceRules;
use crate::geom::fixtures::cube_prior;
use crate::lidar::synthetic::boxes_on_plane;
use crate::lidar::{Caster, scan};
use crate::vehicle::multirotor::{FlightStep, Multirotor, SceneBody, SortieQueue, mid360_like};

const DT: f32 = 0.05;
/// The pad, on the ground south-west of the cube.
const PAD: [f32; 3] = [5.0, 5.0, 0.0];

/// Gaps on all four walls, every metre at 2, 5 and 8 m, normals outward.
fn gaps() -> Vec<MissingPoint> {
    let mut out = Vec::new();
    for s in 0..10 {
        let t = 20.5 + s as f32;
        for z in [2.0, 5.0, 8.0] {
            for (xy, n) in [
                ([t, 20.0], [0.0, -1.0]),
                ([t, 30.0], [0.0, 1.0]),
                ([20.0, t], [-1.0, 0.0]),
                ([30.0, t], [1.0, 0.0]),
            ] {
                out.push(MissingPoint {
                    xyz: [xy[0], xy[1], z],
                    building: 1,
                    normal: n,
                    skeleton: [25.0, 25.0],
                });
            }
        }
    }
    out
}

fn airspace(cfg: &MultirotorConfig) -> Airspace {
    let home = [PAD[0], PAD[1], PAD[2] + cfg.radius + 0.1];
    Airspace::from_prior(&cube_prior(), AirspaceRules::default(), cfg.radius, home).unwrap()
}

#[test]
fn the_plan_sees_every_wall_gap_and_keeps_every_rule() {
    let cfg = MultirotorConfig::default();
    let a = airspace(&cfg);
    let missing = gaps();
    let plan = plan(&missing, &a, &cfg, &SortieParams::default()).unwrap();
    let seen = plan.seen.iter().filter(|&&s| s).count();
    assert_eq!(seen, missing.len(), "every gap seen from a kept viewpoint");
    assert!(
        plan.viewpoints.len() <= 16,
        "a set cover, not one per gap: {}",
        plan.viewpoints.len()
    );
    assert!(plan.unreachable.is_empty());
    assert_eq!(plan.sorties.len(), 1, "one battery is enough");
    for s in &plan.sorties {
        a.check_path(&s.path)
            .expect("every leg inside the airspace");
        assert!(s.flight_s <= cfg.sortie_s());
        assert_eq!((s.path[0], *s.path.last().unwrap()), (a.home(), a.home()));
    }
}

#[test]
fn a_small_battery_splits_the_tour_into_sorties_each_within_it() {
    let cfg = MultirotorConfig {
        battery_s: 60.0,
        reserve_s: 15.0,
        ..MultirotorConfig::default()
    };
    let a = airspace(&cfg);
    let plan = plan(&gaps(), &a, &cfg, &SortieParams::default()).unwrap();
    assert!(plan.sorties.len() >= 2, "{:?}", plan.sorties);
    assert!(plan.unreachable.is_empty(), "{:?}", plan.unreachable);
    let visited: usize = plan.sorties.iter().map(|s| s.viewpoints.len()).sum();
    assert_eq!(visited + plan.unreachable.len(), plan.viewpoints.len());
    for s in &plan.sorties {
        assert!(s.flight_s <= cfg.sortie_s(), "{}", s.flight_s);
    }
}

#[test]
fn flown_in_the_simulation_its_scans_cover_the_gaps_without_touching_anything() {
    let cfg = MultirotorConfig::default();
    let a = airspace(&cfg);
    let missing = gaps();
    let plan = plan(&missing, &a, &cfg, &SortieParams::default()).unwrap();
    let scene = boxes_on_plane(70.0, &[([20.0, 20.0, 0.0], [30.0, 30.0, 10.0])]);
    let (body, caster) = (SceneBody::new(&scene), Caster::new(&scene).unwrap());
    let mut m = Multirotor::new(cfg, PAD, 0.0);
    let mut points = Vec::new();
    let mut closest = f32::INFINITY;
    for s in &plan.sorties {
        m.set_path(s.path[1..].iter().copied());
        for k in 0..20_000 {
            let step = m.step(DT, &body);
            closest = closest.min(body.clearance(m.state.position));
            if matches!(step, FlightStep::Arrived(_)) {
                points.extend(
                    scan(&caster, &mid360_like(), &m.sensor_pose(), k)
                        .unwrap()
                        .xyz,
                );
            }
            assert!(
                !matches!(step, FlightStep::Blocked { .. } | FlightStep::BatteryEmpty),
                "{step:?}"
            );
            if m.goal().is_none() {
                break;
            }
        }
        assert!(m.on_pad(), "home after the sortie");
    }
    assert!(closest >= cfg.radius, "closest approach {closest}");
    let covered = missing
        .iter()
        .filter(|g| {
            points
                .iter()
                .any(|p| (0..3).map(|k| (p[k] - g.xyz[k]).powi(2)).sum::<f32>() < 0.3 * 0.3)
        })
        .count();
    assert!(
        covered as f32 >= 0.95 * missing.len() as f32,
        "{covered} of {}",
        missing.len()
    );
}

/// A 20 m square block, 10 m high, round a closed 10 m courtyard.
fn courtyard_prior() -> crate::cloud::Cloud {
    use crate::cloud::class;
    let block = |x: f32, y: f32| (20.0..40.0).contains(&x) && (20.0..40.0).contains(&y);
    let court = |x: f32, y: f32| (25.0..35.0).contains(&x) && (25.0..35.0).contains(&y);
    let mut xyz = Vec::new();
    let mut label = Vec::new();
    for j in 0..120 {
        for i in 0..120 {
            let (x, y) = (i as f32 * 0.5 + 0.25, j as f32 * 0.5 + 0.25);
            let roof = block(x, y) && !court(x, y);
            xyz.push([x, y, if roof { 10.0 } else { 0.0 }]);
            label.push(if roof { class::BUILDING } else { class::GROUND });
        }
    }
    let mut c = crate::cloud::Cloud::from_xyz(xyz);
    c.label = Some(label);
    c
}

fn gap(xyz: [f32; 3], normal: [f32; 2]) -> MissingPoint {
    MissingPoint {
        xyz,
        building: 1,
        normal,
        skeleton: [30.0, 30.0],
    }
}

#[test]
fn the_drone_takes_upper_storeys_and_closed_courtyards_the_ground_robot_the_rest() {
    let cfg = MultirotorConfig::default();
    let home = [5.0, 5.0, cfg.radius + 0.1];
    let a = Airspace::from_prior(
        &courtyard_prior(),
        AirspaceRules::default(),
        cfg.radius,
        home,
    )
    .unwrap();
    let reach = a.ground_reach([5.0, 5.0], 0.3);
    assert!(reach.count() > 10_000, "the open ground round the block");
    assert!(
        !a.can_stand(&reach, 30.0, 30.0),
        "the courtyard is joined to nothing"
    );
    let missing = [
        gap([30.0, 20.0, 3.0], [0.0, -1.0]), // outer wall, low: a ground stop sees it
        gap([30.0, 20.0, 9.5], [0.0, -1.0]), // outer wall, top storey: over the ±15° beams within 20 m
        gap([30.0, 25.0, 3.0], [0.0, 1.0]),  // courtyard wall, low: no ground reaches it
        gap([20.0, 30.0, 6.0], [-1.0, 0.0]), // west wall at 6 m: seen from 16 m out
    ];
    let drone = for_the_drone(&missing, &a, &reach, &GroundView::default());
    assert_eq!(drone, vec![false, true, true, false]);
    // With the whole block open to the robot (no courtyard walls), the court's gap is the ground's.
    let open = a.ground_reach([30.0, 30.0], 0.3);
    let from_court = for_the_drone(&missing[2..3], &a, &open, &GroundView::default());
    assert_eq!(from_court, vec![false]);
}

#[test]
fn a_path_of_sorties_is_flown_one_battery_each_and_ends_home() {
    let cfg = MultirotorConfig {
        battery_s: 60.0,
        reserve_s: 15.0,
        ..MultirotorConfig::default()
    };
    let a = airspace(&cfg);
    let plan = plan(&gaps(), &a, &cfg, &SortieParams::default()).unwrap();
    assert!(plan.sorties.len() >= 2);
    let path: Vec<[f32; 3]> = plan.sorties.iter().flat_map(|s| s.path.clone()).collect();
    let scene = boxes_on_plane(70.0, &[([20.0, 20.0, 0.0], [30.0, 30.0, 10.0])]);
    let body = SceneBody::new(&scene);
    let mut m = Multirotor::new(cfg, PAD, 0.0);
    let mut q = SortieQueue::default();
    q.push_path(a.home(), &path, cfg.goal_tolerance);
    assert_eq!(q.waiting(), plan.sorties.len());
    for _ in 0..200_000 {
        let step = q.step(&mut m, DT, &body);
        assert!(
            !matches!(step, FlightStep::BatteryEmpty | FlightStep::Blocked { .. }),
            "{step:?}"
        );
        if q.done(&m) {
            break;
        }
    }
    assert!(q.done(&m) && m.on_pad());
    assert_eq!(q.begun as usize, plan.sorties.len());
    assert_eq!(
        m.sorties as usize,
        plan.sorties.len(),
        "took off once per sortie"
    );
}

#[test]
fn a_sortie_blocked_by_what_the_prior_did_not_show_is_cut_short_and_comes_home() {
    let cfg = MultirotorConfig::default();
    let a = airspace(&cfg);
    let plan = plan(&gaps(), &a, &cfg, &SortieParams::default()).unwrap();
    // A mast the survey missed, 14 m high, on the first leg's way.
    let first = plan.viewpoints[plan.sorties[0].viewpoints[0]];
    let mid = [(PAD[0] + first[0]) / 2.0, (PAD[1] + first[1]) / 2.0];
    let mast = (
        [mid[0] - 0.5, mid[1] - 0.5, 0.0],
        [mid[0] + 0.5, mid[1] + 0.5, 14.0],
    );
    let scene = boxes_on_plane(70.0, &[([20.0, 20.0, 0.0], [30.0, 30.0, 10.0]), mast]);
    let body = SceneBody::new(&scene);
    let mut m = Multirotor::new(cfg, PAD, 0.0);
    let mut q = SortieQueue::new(20.0);
    q.push_path(a.home(), &plan.sorties[0].path, cfg.goal_tolerance);
    let mut closest = f32::INFINITY;
    for _ in 0..100_000 {
        q.step(&mut m, DT, &body);
        closest = closest.min(body.clearance(m.state.position));
        if q.done(&m) {
            break;
        }
    }
    assert!(q.cut >= 1, "the mast blocked a leg");
    assert!(m.on_pad(), "home after the cut: {:?}", m.state.position);
    assert!(closest >= cfg.radius, "closest approach {closest}");
}

/// A rectangle [x0, x1] × [y0, y1] as a geofence.
fn fence(x0: f64, x1: f64, y0: f64, y1: f64) -> Geofence {
    use geo::{MultiPolygon, polygon};
    MultiPolygon(vec![polygon![
        (x: x0, y: y0), (x: x1, y: y0), (x: x1, y: y1), (x: x0, y: y1), (x: x0, y: y0)
    ]])
}

#[test]
fn a_geofence_keeps_every_viewpoint_and_leg_inside_it() {
    use geo::{Contains, Coord};
    let cfg = MultirotorConfig::default();
    // The cube's south and west sides only (x, y < 27): the north and east
    // walls are out of reach.
    let f = fence(0.0, 27.0, 0.0, 27.0);
    let a = airspace(&cfg).with_fence(f.clone());
    let missing = gaps();
    let plan = plan(&missing, &a, &cfg, &SortieParams::default()).unwrap();
    let seen = plan.seen.iter().filter(|&&s| s).count();
    assert!(
        seen > 0 && seen < missing.len(),
        "{seen} of {}",
        missing.len()
    );
    for (m, &s) in missing.iter().zip(&plan.seen) {
        let north_or_east = m.normal[0] > 0.5 || m.normal[1] > 0.5;
        assert!(!(s && north_or_east), "{m:?} seen from outside the fence");
    }
    for s in &plan.sorties {
        a.check_path(&s.path).expect("inside the fence");
        for p in &s.path {
            let c = Coord {
                x: f64::from(p[0]),
                y: f64::from(p[1]),
            };
            assert!(f.contains(&c), "{p:?}");
        }
    }
}

#[test]
fn a_home_outside_the_geofence_reaches_nothing_and_says_why() {
    let cfg = MultirotorConfig::default();
    // The fence holds the cube's surroundings but not the pad at (5, 5).
    let a = airspace(&cfg).with_fence(fence(12.0, 40.0, 12.0, 40.0));
    let plan = plan(&gaps(), &a, &cfg, &SortieParams::default()).unwrap();
    assert!(plan.sorties.is_empty());
    assert_eq!(plan.unreachable.len(), plan.viewpoints.len());
    let why = plan.why_unreachable.expect("a reason");
    assert!(
        why.contains("outside the geofence") && why.contains("from home"),
        "{why}"
    );
}

#[test]
fn a_battery_too_small_for_any_viewpoint_is_named_as_the_reason() {
    let cfg = MultirotorConfig {
        battery_s: 10.0,
        reserve_s: 5.0,
        ..MultirotorConfig::default()
    };
    let plan = plan(&gaps(), &airspace(&cfg), &cfg, &SortieParams::default()).unwrap();
    assert!(plan.sorties.is_empty());
    let why = plan.why_unreachable.expect("a reason");
    assert!(why.contains("over a sortie's 5 s"), "{why}");
}

#[test]
fn take_off_is_refused_beside_a_facade_and_allowed_in_the_open() {
    let cfg = MultirotorConfig::default();
    let mut a = airspace(&cfg);
    assert_eq!(take_off(&a), Ok(()), "the pad at (5, 5) is in the open");
    // 2 m from the cube's west wall (x = 20): under the 3 m kept.
    a.set_home([18.0, 25.0, PAD[2] + cfg.radius + 0.1]);
    let r = take_off(&a).expect_err("too near the facade");
    assert!(r.to_string().contains("from a building"), "{r}");
}
