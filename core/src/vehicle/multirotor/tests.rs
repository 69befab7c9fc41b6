//! The multirotor flown over a cube on a plane.

use super::*;
use crate::lidar::synthetic::boxes_on_plane;
use crate::lidar::{Caster, scan};

const DT: f32 = 0.05;

/// A 10 m cube standing on a 100 m plane.
fn cube() -> crate::scene::Scene {
    boxes_on_plane(50.0, &[([0.0, 0.0, 0.0], [10.0, 10.0, 10.0])])
}

/// Flies until the path is done or `max_s` passed; every step's state.
fn fly(
    m: &mut Multirotor,
    body: &SceneBody,
    max_s: f32,
) -> (Vec<FlightStep>, Vec<MultirotorState>) {
    let (mut steps, mut states) = (Vec::new(), Vec::new());
    let mut t = 0.0;
    while t < max_s && (m.goal().is_some() || steps.is_empty()) {
        steps.push(m.step(DT, body));
        states.push(m.state);
        t += DT;
    }
    (steps, states)
}

#[test]
fn it_flies_a_sortie_within_its_limits_and_lands_home() {
    let scene = cube();
    let body = SceneBody::new(&scene);
    let c = MultirotorConfig::default();
    let mut m = Multirotor::new(c, [-20.0, -20.0, 0.0], 0.0);
    let home = m.home;
    m.set_path([
        [-20.0, -20.0, 15.0],
        [25.0, 5.0, 15.0],
        [25.0, 5.0, 6.0],
        home,
    ]);
    let (steps, states) = fly(&mut m, &body, 300.0);
    let arrived = steps
        .iter()
        .filter(|s| matches!(s, FlightStep::Arrived(_)))
        .count();
    assert_eq!(arrived, 4, "{:?}", steps.last());
    assert!(m.on_pad(), "landed at home: {:?}", m.state);
    assert_eq!(m.sorties, 1);
    let mut prev = [0.0f32; 3];
    for s in &states {
        let v = s.velocity;
        assert!(v[0].hypot(v[1]) <= c.max_speed + 1e-3, "speed {v:?}");
        assert!(
            v[2] <= c.max_climb + 1e-3 && -v[2] <= c.max_descent + 1e-3,
            "climb {v:?}"
        );
        let dv =
            ((v[0] - prev[0]).powi(2) + (v[1] - prev[1]).powi(2) + (v[2] - prev[2]).powi(2)).sqrt();
        assert!(dv <= c.max_accel * DT + 1e-3, "acceleration {dv}");
        assert!(
            body.clearance(s.position) >= c.radius,
            "touched at {:?}",
            s.position
        );
        prev = v;
    }
    // Robot time counts the flying: every moving step is flight time.
    let moving = steps.iter().filter(|s| **s == FlightStep::Moving).count() as f32;
    assert!(
        (m.state.flight_s - moving * DT).abs() < 1e-2,
        "{} vs {}",
        m.state.flight_s,
        moving * DT
    );
    assert!(m.state.odometer > 45.0 + 25.0 + 9.0, "{}", m.state.odometer);
    assert!(m.swap_battery() && m.state.flight_s == 0.0);
}

#[test]
fn a_goal_inside_a_building_is_refused_before_the_body_touches_it() {
    let scene = cube();
    let body = SceneBody::new(&scene);
    let mut m = Multirotor::new(MultirotorConfig::default(), [-10.0, 5.0, 0.0], 0.0);
    m.set_path([[-10.0, 5.0, 5.0], [5.0, 5.0, 5.0]]);
    let (steps, states) = fly(&mut m, &body, 120.0);
    let Some(FlightStep::Blocked { goal, reason }) = steps.last() else {
        panic!("not blocked: {:?}", steps.last());
    };
    assert_eq!(*goal, [5.0, 5.0, 5.0]);
    assert!(reason.contains("radius 0.60 m"), "{reason}");
    let closest = states
        .iter()
        .map(|s| body.clearance(s.position))
        .fold(f32::INFINITY, f32::min);
    assert!((0.6..1.5).contains(&closest), "closest approach {closest}");
    assert!(m.goal().is_none());
}

#[test]
fn an_empty_battery_ends_the_flight_and_no_swap_away_from_home() {
    let body = SceneBody::new(&cube());
    let c = MultirotorConfig {
        battery_s: 8.0,
        reserve_s: 1.0,
        ..MultirotorConfig::default()
    };
    let mut m = Multirotor::new(c, [-30.0, -30.0, 0.0], 0.0);
    m.set_path([[-30.0, -30.0, 20.0], [40.0, -30.0, 20.0]]);
    let (steps, _) = fly(&mut m, &body, 60.0);
    assert_eq!(steps.last(), Some(&FlightStep::BatteryEmpty));
    assert!(
        (m.state.flight_s - 8.0).abs() <= DT + 1e-3,
        "{}",
        m.state.flight_s
    );
    assert!(!m.swap_battery(), "a swap away from the pad");
}

#[test]
fn the_yaw_turns_no_faster_than_its_limit() {
    let body = SceneBody::new(&cube());
    let c = MultirotorConfig::default();
    let mut m = Multirotor::new(c, [-20.0, -20.0, 0.0], 0.0);
    // Climb, then fly the opposite way: the heading must turn by π.
    m.set_path([[-20.0, -20.0, 15.0], [-45.0, -20.0, 15.0]]);
    let (_, states) = fly(&mut m, &body, 60.0);
    for w in states.windows(2) {
        let mut d = (w[1].yaw - w[0].yaw).abs();
        if d > std::f32::consts::PI {
            d = 2.0 * std::f32::consts::PI - d;
        }
        assert!(d <= c.max_yaw_rate * DT + 1e-4, "yaw step {d}");
    }
    let heading = m.state.yaw.rem_euclid(2.0 * std::f32::consts::PI);
    assert!((heading - std::f32::consts::PI).abs() < 0.05, "{heading}");
}

#[test]
fn the_lidar_under_it_sees_the_roof_below_and_the_wall_beside() {
    let scene = cube();
    let caster = Caster::new(&scene).unwrap();
    // Hovering 6 m beside the cube's east wall, 3 m above its roof.
    let mut m = Multirotor::new(MultirotorConfig::default(), [16.0, 5.0, 0.0], 0.0);
    m.state.position = [16.0, 5.0, 13.0];
    let pts = scan(&caster, &mid360_like(), &m.sensor_pose(), 1).unwrap();
    let roof = pts
        .xyz
        .iter()
        .filter(|p| (p[2] - 10.0).abs() < 0.1 && p[0] < 9.9)
        .count();
    let wall = pts
        .xyz
        .iter()
        .filter(|p| (p[0] - 10.0).abs() < 0.1 && p[2] < 9.9 && p[2] > 0.1)
        .count();
    let above = pts.xyz.iter().filter(|p| p[2] > 13.0).count();
    assert!(roof > 100 && wall > 100, "roof {roof}, wall {wall}");
    assert_eq!(above, 0, "nothing above the drone to hit");
}
