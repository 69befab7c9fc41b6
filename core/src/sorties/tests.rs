//! The drone's plan for the walls of a 10 m cube, flown in the simulation.

use super::*;
use crate::airspace::AirspaceRules;
use crate::geom::fixtures::cube_prior;
use crate::lidar::synthetic::boxes_on_plane;
use crate::lidar::{Caster, scan};
use crate::vehicle::multirotor::{FlightStep, Multirotor, SceneBody, mid360_like};

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
