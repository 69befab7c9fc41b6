//! The vehicle's state and one integration step.

use std::collections::VecDeque;
use std::f32::consts::PI;

use super::config::VehicleConfig;
use super::incline::{INCLINE_BASE_M, incline_deg};
use super::probe::{Terrain, goal_inside_building};
use crate::lidar::Caster;

/// Where the vehicle is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VehicleState {
    /// Position on the ground, m (z = ground height).
    pub position: [f32; 3],
    /// Heading, rad (0 = +x, counter-clockwise).
    pub yaw: f32,
    /// Forward speed, m/s.
    pub speed: f32,
    /// Yaw rate, rad/s.
    pub yaw_rate: f32,
    /// Metres driven so far.
    pub odometer: f32,
}

/// What one step did.
#[derive(Debug, Clone, PartialEq)]
pub enum Step {
    /// No goal.
    Idle,
    /// On the way.
    Moving,
    /// Reached a way-point (the next one, if any, is now the goal).
    Arrived([f32; 2]),
    /// Cannot go on towards the goal; the goal is dropped.
    Blocked {
        /// The goal given up.
        goal: [f32; 2],
        /// Why, for a log line.
        reason: String,
    },
}

/// A kinematic ground vehicle (unicycle with speed and yaw-rate limits) that
/// follows the terrain and never drives through an obstacle.
#[derive(Debug, Clone)]
pub struct Vehicle {
    /// Limits and shape.
    pub config: VehicleConfig,
    /// Current state.
    pub state: VehicleState,
    goals: VecDeque<[f32; 2]>,
    // Whether the front goal passed the terrain/inside-building check, so the
    // ray casts run once per goal rather than once per step.
    goal_checked: bool,
}

impl Vehicle {
    /// A vehicle standing at `(x, y)` on the ground, facing `yaw`; `None` off the terrain.
    pub fn new(config: VehicleConfig, caster: &Caster, x: f32, y: f32, yaw: f32) -> Option<Self> {
        let z = Terrain::new(caster).ground_height(x, y)?;
        Some(Self {
            config,
            state: VehicleState {
                position: [x, y, z],
                yaw,
                speed: 0.0,
                yaw_rate: 0.0,
                odometer: 0.0,
            },
            goals: VecDeque::new(),
            goal_checked: false,
        })
    }

    /// The vehicle carried to `to` (plan) and set down there, as a field
    /// team does: facing as it did, its odometer as it was (carried: no
    /// driving), no goal. Off the terrain it stays where it is, and the
    /// error is the step to report, as a blocked goal (the planner waits
    /// for the robot there).
    pub fn set_down(&self, caster: &Caster, to: [f32; 2]) -> Result<Self, Step> {
        let Some(mut v) = Self::new(self.config, caster, to[0], to[1], self.state.yaw) else {
            return Err(Step::Blocked {
                goal: to,
                reason: "cannot set down here: off the terrain".into(),
            });
        };
        v.state.odometer = self.state.odometer;
        Ok(v)
    }

    /// Replaces the goals by one way-point.
    pub fn set_goal(&mut self, goal: [f32; 2]) {
        self.goals.clear();
        self.goals.push_back(goal);
        self.goal_checked = false;
    }

    /// Replaces the goals by a path, followed in order.
    pub fn set_path(&mut self, path: impl IntoIterator<Item = [f32; 2]>) {
        self.goals = path.into_iter().collect();
        self.goal_checked = false;
    }

    /// The current goal.
    pub fn goal(&self) -> Option<[f32; 2]> {
        self.goals.front().copied()
    }

    /// The sensor's position (on the vehicle, `sensor_height` above ground).
    pub fn sensor_position(&self) -> [f32; 3] {
        let p = self.state.position;
        [p[0], p[1], p[2] + self.config.sensor_height]
    }

    /// Advances the vehicle by `dt` seconds towards its goal.
    pub fn step(&mut self, caster: &Caster, dt: f32) -> Step {
        let Some(goal) = self.goal() else {
            self.state.speed = 0.0;
            self.state.yaw_rate = 0.0;
            return Step::Idle;
        };
        let terrain = Terrain::new(caster);
        let p = self.state.position;
        let (dx, dy) = (goal[0] - p[0], goal[1] - p[1]);
        let dist = (dx * dx + dy * dy).sqrt();
        if dist <= self.config.goal_tolerance {
            self.goals.pop_front();
            self.goal_checked = false;
            self.state.speed = 0.0;
            return Step::Arrived(goal);
        }
        let block = |s: &mut Self, reason: String| {
            s.goals.pop_front();
            s.goal_checked = false;
            s.state.speed = 0.0;
            s.state.yaw_rate = 0.0;
            Step::Blocked { goal, reason }
        };
        if !self.goal_checked {
            match terrain.ground_height(goal[0], goal[1]) {
                None => return block(self, "the way-point is off the terrain".into()),
                Some(gz) if goal_inside_building(caster, [goal[0], goal[1], gz + 0.5]) => {
                    return block(self, "the way-point is inside a building".into());
                }
                Some(_) => self.goal_checked = true,
            }
        }
        let heading = dy.atan2(dx);
        let err = wrap(heading - self.state.yaw);
        let max_turn = self.config.max_yaw_rate * dt;
        let turn = err.clamp(-max_turn, max_turn);
        self.state.yaw = wrap(self.state.yaw + turn);
        self.state.yaw_rate = turn / dt.max(1e-6);
        // Turn in place when facing away; slow down on the approach to the
        // path's last way-point only: a path follower drives through the
        // ones before it (slowing at each made the reference mission's
        // average speed half the top speed).
        let last = self.goals.len() == 1;
        let speed = if err.abs() > PI / 3.0 {
            0.0
        } else if last {
            self.config
                .max_speed
                .min(dist / dt.max(1e-6))
                .min(dist.max(0.2))
        } else {
            self.config.max_speed.min(dist / dt.max(1e-6))
        };
        let step = speed * dt;
        if step <= 0.0 {
            self.state.speed = 0.0;
            return Step::Moving;
        }
        let (c, s) = (self.state.yaw.cos(), self.state.yaw.sin());
        let (nx, ny) = (p[0] + c * step, p[1] + s * step);
        let Some(nz) = terrain.ground_height(nx, ny) else {
            return block(self, "the terrain ends ahead".into());
        };
        // Over a wheelbase, not over one time step: a 4 cm step made a 5 cm
        // curb (or a city model's road surface 5 cm above the built ground)
        // a 51° wall; a quay wall is still one over 1 m.
        let base = INCLINE_BASE_M.max(step);
        let incline = terrain
            .ground_height(p[0] + c * base, p[1] + s * base)
            .map_or(incline_deg(nz - p[2], step), |az| {
                incline_deg(az - p[2], base)
            });
        if incline > self.config.max_incline_deg {
            return block(self, format!("slope of {incline:.0}° ahead"));
        }
        if let Some(at) =
            terrain.obstacle(p, [nx, ny, nz], self.config.radius, self.config.body_height)
            && at < step + 1e-3
        {
            // A follower still turning towards its way-point turns on the
            // spot first: swinging round beside a wall is not a blocked way.
            if (err - turn).abs() > ALIGNED_RAD {
                self.state.speed = 0.0;
                return Step::Moving;
            }
            return block(
                self,
                format!("obstacle {at:.2} m ahead at ({:.1}, {:.1})", p[0], p[1]),
            );
        }
        self.state.position = [nx, ny, nz];
        self.state.speed = speed;
        self.state.odometer += step;
        Step::Moving
    }
}

/// Heading error (radians) under which an obstacle ahead blocks the way
/// rather than the vehicle turning on the spot first.
const ALIGNED_RAD: f32 = 0.05;

fn wrap(a: f32) -> f32 {
    let mut a = a % (2.0 * PI);
    if a > PI {
        a -= 2.0 * PI;
    } else if a < -PI {
        a += 2.0 * PI;
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lidar::synthetic::boxes_on_plane;
    use crate::scene::{ObjectKind, Scene, SceneObject};

    /// A ground plane (x, y in ±40 m) with a closed 10 m box building at
    /// x 20..30, y 0..10.
    fn scene() -> Scene {
        boxes_on_plane(40.0, &[([20.0, 0.0, 0.0], [30.0, 10.0, 10.0])])
    }

    fn run(v: &mut Vehicle, c: &Caster, secs: f32) -> Vec<Step> {
        let mut out = Vec::new();
        for _ in 0..(secs / 0.05) as usize {
            let s = v.step(c, 0.05);
            if s != Step::Moving && s != Step::Idle {
                out.push(s);
            }
        }
        out
    }

    /// A vehicle set down in `scene` at `from` (facing +x) and sent to `to`:
    /// where it ends and what it reported within `secs`.
    fn drive(scene: &Scene, from: [f32; 2], to: [f32; 2], secs: f32) -> (Vehicle, Vec<Step>) {
        let c = Caster::new(scene).unwrap();
        let mut v = Vehicle::new(VehicleConfig::default(), &c, from[0], from[1], 0.0).unwrap();
        v.set_goal(to);
        let steps = run(&mut v, &c, secs);
        (v, steps)
    }

    /// Whether the one step reported is a block whose reason says `why`.
    fn blocked(steps: &[Step], why: &str) -> bool {
        matches!(steps, [Step::Blocked { reason, .. }] if reason.contains(why))
    }

    #[test]
    fn set_down_keeps_heading_and_odometer_and_refuses_off_the_terrain() {
        let (v, _) = drive(&scene(), [0.0, 0.0], [5.0, 0.0], 20.0);
        let c = Caster::new(&scene()).unwrap();
        let moved = v.set_down(&c, [-10.0, -10.0]).expect("on the terrain");
        assert_eq!(moved.state.position[..2], [-10.0, -10.0]);
        assert_eq!(moved.state.yaw, v.state.yaw);
        assert_eq!(moved.state.odometer, v.state.odometer);
        assert!(v.state.odometer > 4.0 && moved.goal().is_none());
        let refused = v.set_down(&c, [500.0, 0.0]).expect_err("off the terrain");
        assert!(blocked(&[refused], "cannot set down here: off the terrain"));
    }

    #[test]
    fn drives_to_a_way_point_and_stops() {
        let (v, steps) = drive(&scene(), [0.0, 0.0], [5.0, 12.0], 30.0);
        assert_eq!(steps, vec![Step::Arrived([5.0, 12.0])]);
        let p = v.state.position;
        assert!(((p[0] - 5.0).powi(2) + (p[1] - 12.0).powi(2)).sqrt() <= 0.5);
        assert!(v.state.odometer >= 12.0);
    }

    #[test]
    fn drives_through_a_path_at_speed_and_slows_for_its_end_only() {
        let c = Caster::new(&scene()).unwrap();
        let cfg = VehicleConfig::default();
        let mut v = Vehicle::new(cfg, &c, -10.0, 15.0, 0.0).unwrap();
        // 24 way-points 1.25 m apart, as a graph path gives them: 30 m east.
        v.set_path((1..=24).map(|k| [-10.0 + 1.25 * k as f32, 15.0]));
        let (mut t, dt) = (0.0f32, 0.05f32);
        while !v.goals.is_empty() && t < 60.0 {
            v.step(&c, dt);
            t += dt;
        }
        assert!(v.goals.is_empty(), "path not done after {t} s");
        // At top speed 29.5 m take 14.75 s; the last metre's slow-down adds ~1 s.
        let full_speed = 29.5 / cfg.max_speed;
        assert!(
            t < full_speed + 2.0,
            "{t:.2} s for 29.5 m (top speed: {full_speed:.2} s)"
        );
        assert!(v.state.speed < 0.6, "arrives slowly: {} m/s", v.state.speed);
    }

    #[test]
    fn refuses_a_way_point_inside_a_building() {
        let (v, steps) = drive(&scene(), [0.0, 5.0], [25.0, 5.0], 30.0);
        assert!(blocked(&steps, "inside"), "{steps:?}");
        assert!(v.state.position[0] < 20.0);
    }

    /// The test scene with a raised ground slab of height `h` over x 5..15.
    fn with_step(h: f32) -> Scene {
        let mut s = scene();
        s.objects.push(SceneObject {
            name: "kerb".into(),
            kind: ObjectKind::Ground,
            building: 0,
        });
        let b = s.vertices.len() as u32;
        s.vertices.extend([
            [5.0, -20.0, h],
            [15.0, -20.0, h],
            [15.0, 40.0, h],
            [5.0, 40.0, h],
        ]);
        s.triangles.extend([[b, b + 1, b + 2], [b, b + 2, b + 3]]);
        s.triangle_object.extend([2, 2]);
        s
    }

    #[test]
    fn climbs_kerbs_but_not_a_quay_wall() {
        for (h, passes) in [(0.05, true), (0.3, true), (0.6, false), (1.5, false)] {
            let (v, steps) = drive(&with_step(h), [0.0, 12.0], [10.0, 12.0], 30.0);
            if passes {
                assert_eq!(steps, vec![Step::Arrived([10.0, 12.0])], "kerb of {h} m");
            } else {
                assert!(blocked(&steps, "slope"), "step of {h} m: {steps:?}");
                assert!(v.state.position[0] < 5.0);
            }
        }
    }

    #[test]
    fn turns_on_the_spot_beside_a_wall_rather_than_give_up() {
        // 0.7 m north of the wall at y = 10, facing 35° into it, sent east
        // along it: moving while turning would graze the wall.
        let c = Caster::new(&scene()).unwrap();
        let mut v = Vehicle::new(VehicleConfig::default(), &c, 24.0, 10.7, -0.6).unwrap();
        v.set_goal([29.0, 10.7]);
        assert_eq!(run(&mut v, &c, 30.0), vec![Step::Arrived([29.0, 10.7])]);
        assert!(v.state.position[1] > 10.5, "{:?}", v.state.position);
    }

    #[test]
    fn never_drives_through_a_wall() {
        let (v, steps) = drive(&scene(), [10.0, 5.0], [38.0, 5.0], 40.0);
        assert!(blocked(&steps, "obstacle"), "{steps:?}");
        let x = v.state.position[0];
        assert!(x < 20.0 - 0.4 && x > 15.0, "stopped at x = {x}");
    }
}
