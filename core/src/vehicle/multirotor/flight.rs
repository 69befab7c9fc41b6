//! The multirotor's state and one integration step: a point mass whose
//! velocity follows the goal within speed, climb, descent and acceleration
//! limits, a yaw that turns towards the way it flies within the yaw-rate
//! limit, a body sphere that never enters the scene, and a battery that
//! counts the flight time.

use std::collections::VecDeque;
use std::f32::consts::PI;

use nalgebra::Vector3;

use super::body::SceneBody;
use super::config::MultirotorConfig;
use crate::lidar::Pose;

/// Height of the body centre above the pad when landed, beyond the body
/// radius (the landing legs), m.
const LEGS_M: f32 = 0.1;
/// Below this speed the multirotor counts as hovering, m/s.
const HOVER_SPEED: f32 = 0.3;

/// Where the multirotor is and how it moves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MultirotorState {
    /// Body centre, m (scene frame).
    pub position: [f32; 3],
    /// Velocity, m/s.
    pub velocity: [f32; 3],
    /// Heading, rad (0 = +x, counter-clockwise).
    pub yaw: f32,
    /// Seconds flown on the current battery.
    pub flight_s: f32,
    /// Metres flown so far (every sortie).
    pub odometer: f32,
    /// Whether it is in the air (not on a pad).
    pub airborne: bool,
}

/// What one step did.
#[derive(Debug, Clone, PartialEq)]
pub enum FlightStep {
    /// No goal: hovering, or on the pad.
    Idle,
    /// On the way.
    Moving,
    /// Reached a way-point (the next one, if any, is now the goal).
    Arrived([f32; 3]),
    /// The next step would bring the body into the scene: stopped, and the
    /// goal dropped.
    Blocked {
        /// The goal given up.
        goal: [f32; 3],
        /// Why, for a log line.
        reason: String,
    },
    /// The battery is empty: it lands where it is.
    BatteryEmpty,
}

/// A kinematic multirotor that flies to 3D way-points and never passes
/// into the scene.
#[derive(Debug, Clone)]
pub struct Multirotor {
    /// Limits, body and battery.
    pub config: MultirotorConfig,
    /// Current state.
    pub state: MultirotorState,
    /// Where it takes off and lands: the body centre standing on the pad.
    pub home: [f32; 3],
    /// Sorties begun (a sortie begins when it leaves the pad).
    pub sorties: u32,
    goals: VecDeque<[f32; 3]>,
}

impl Multirotor {
    /// A multirotor standing on the pad at `pad` (the ground under it), facing `yaw`.
    pub fn new(config: MultirotorConfig, pad: [f32; 3], yaw: f32) -> Self {
        let home = [pad[0], pad[1], pad[2] + config.radius + LEGS_M];
        Self {
            config,
            state: MultirotorState {
                position: home,
                velocity: [0.0; 3],
                yaw,
                flight_s: 0.0,
                odometer: 0.0,
                airborne: false,
            },
            home,
            sorties: 0,
            goals: VecDeque::new(),
        }
    }

    /// Replaces the goals by a path, followed in order.
    pub fn set_path(&mut self, path: impl IntoIterator<Item = [f32; 3]>) {
        self.goals = path.into_iter().collect();
    }

    /// The current goal.
    pub fn goal(&self) -> Option<[f32; 3]> {
        self.goals.front().copied()
    }

    /// Flight time left on the battery, s.
    pub fn remaining_s(&self) -> f32 {
        self.config.battery_s - self.state.flight_s
    }

    /// Whether it stands on its home pad.
    pub fn on_pad(&self) -> bool {
        !self.state.airborne
            && (v3(self.state.position) - v3(self.home)).norm() <= self.config.goal_tolerance
    }

    /// A fresh battery, on the home pad only (`false` elsewhere).
    pub fn swap_battery(&mut self) -> bool {
        let ok = self.on_pad();
        if ok {
            self.state.flight_s = 0.0;
        }
        ok
    }

    /// The LiDAR's pose: under the body, upside down, so its field of view
    /// (−7…52° above its own horizon) looks from 7° above the horizon to
    /// 52° below it: facades beside it and roofs beneath it.
    pub fn sensor_pose(&self) -> Pose {
        let p = self.state.position;
        Pose {
            position: [p[0], p[1], p[2] - self.config.sensor_drop],
            yaw: self.state.yaw,
            pitch: 0.0,
            roll: PI,
        }
    }

    /// Advances the multirotor by `dt` seconds towards its goal, `body`
    /// being the true scene it must not touch.
    pub fn step(&mut self, dt: f32, body: &SceneBody) -> FlightStep {
        if self.state.airborne && self.remaining_s() <= 0.0 {
            self.goals.clear();
            self.state.velocity = [0.0; 3];
            self.state.airborne = false;
            return FlightStep::BatteryEmpty;
        }
        let Some(goal) = self.goal() else {
            return self.hover(dt);
        };
        let to_goal = v3(goal) - v3(self.state.position);
        let last = self.goals.len() == 1;
        let speed = v3(self.state.velocity).norm();
        // The last way-point is reached at a stop: slow enough to halt within one step.
        let halted = speed <= self.config.max_accel * dt;
        if to_goal.norm() <= self.config.goal_tolerance && (!last || halted) {
            self.goals.pop_front();
            if last {
                self.state.velocity = [0.0; 3];
            }
            if self.goals.is_empty()
                && (v3(goal) - v3(self.home)).norm() <= self.config.goal_tolerance
            {
                self.state.airborne = false;
            }
            return FlightStep::Arrived(goal);
        }
        // It slows for every way-point, not only the last: a plan is a
        // polyline the airspace checked, and cutting or overshooting its
        // corners at speed (v²/2a = 5 m at 5 m/s) took the body within 0.6 m
        // of a facade in the reference mission.
        let velocity = self.next_velocity(to_goal, dt);
        let next: [f32; 3] = (v3(self.state.position) + velocity * dt).into();
        let clearance = body.clearance(next);
        if clearance < self.config.radius {
            self.goals.pop_front();
            self.state.velocity = [0.0; 3];
            let reason = format!(
                "the body (radius {:.2} m) would come within {clearance:.2} m of the scene at ({:.1}, {:.1}, {:.1})",
                self.config.radius, next[0], next[1], next[2]
            );
            return FlightStep::Blocked { goal, reason };
        }
        if !self.state.airborne {
            self.state.airborne = true;
            self.sorties += 1;
        }
        self.turn(velocity, dt);
        self.state.odometer += (v3(next) - v3(self.state.position)).norm();
        self.state.position = next;
        self.state.velocity = velocity.into();
        self.state.flight_s += dt;
        FlightStep::Moving
    }

    /// Slows to a hover (in the air) or stays put (on a pad).
    fn hover(&mut self, dt: f32) -> FlightStep {
        if self.state.airborne {
            let v = v3(self.state.velocity);
            let slower = v - (v).cap_magnitude(self.config.max_accel * dt);
            self.state.velocity = slower.into();
            self.state.position = (v3(self.state.position) + slower * dt).into();
            self.state.flight_s += dt;
        }
        FlightStep::Idle
    }

    /// The velocity after `dt`: towards the goal, slowing to stop on it,
    /// within every limit.
    fn next_velocity(&self, to_goal: Vector3<f32>, dt: f32) -> Vector3<f32> {
        let c = &self.config;
        let d = to_goal.norm();
        // The speed from which it stops within the distance left.
        let cruise = (2.0 * c.max_accel * d).sqrt() * 0.9;
        let mut want = to_goal * (cruise.min(c.max_speed.max(c.max_climb)) / d.max(1e-6));
        let horizontal = want[0].hypot(want[1]);
        let vertical_limit = if want[2] > 0.0 {
            c.max_climb
        } else {
            c.max_descent
        };
        let mut f = 1.0f32;
        if horizontal > c.max_speed {
            f = f.min(c.max_speed / horizontal);
        }
        if want[2].abs() > vertical_limit {
            f = f.min(vertical_limit / want[2].abs());
        }
        want *= f;
        let now = v3(self.state.velocity);
        now + (want - now).cap_magnitude(c.max_accel * dt)
    }

    /// Turns the heading towards the horizontal velocity within the yaw-rate limit.
    fn turn(&mut self, velocity: Vector3<f32>, dt: f32) {
        if velocity[0].hypot(velocity[1]) < HOVER_SPEED {
            return;
        }
        let want = velocity[1].atan2(velocity[0]);
        let mut diff = want - self.state.yaw;
        while diff > PI {
            diff -= 2.0 * PI;
        }
        while diff < -PI {
            diff += 2.0 * PI;
        }
        let max = self.config.max_yaw_rate * dt;
        self.state.yaw += diff.clamp(-max, max);
    }
}

/// `p` as a nalgebra vector.
fn v3(p: [f32; 3]) -> Vector3<f32> {
    Vector3::from(p)
}
