//! The offboard state machine: PX4 enters offboard only once it has heard a
//! setpoint stream (≥ 2 Hz) for a while, and leaves it when the stream stops.
//! So: wait for odometry → stream a hold setpoint → with a path waiting and
//! N setpoints sent, ask for offboard (176) and arming (400), again until PX4
//! says both → fly the path one way-point at a time (`follow`, in 3D) → at its
//! end hold there or land (21). If PX4 leaves offboard or disarms (a pilot
//! took over, a failsafe), the leg is reported blocked and the bridge does not
//! take control back until a new path comes.

use serde::{Deserialize, Serialize};

use super::frames::{enu_to_ned_yaw, map_to_ned};
use crate::follow::{FollowConfig, FollowEvent, Follower};

/// What to do at the end of a path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum AtEnd {
    /// Hover on the last way-point (still in offboard).
    #[default]
    Hold,
    /// Land where it is (NAV_LAND): PX4 leaves offboard.
    Land,
}

/// The bridge's thresholds and choices.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OffboardConfig {
    /// Where PX4's NED origin (its home) lies in the map (m, ENU).
    pub home_map: [f64; 3],
    /// Setpoints streamed before asking for offboard (PX4 wants a stream first).
    pub setpoints_before_engage: u32,
    /// Ask again for offboard and arming after this long without both (s).
    pub retry_s: f64,
    /// Hold or land at a path's end.
    pub at_end: AtEnd,
}

impl Default for OffboardConfig {
    fn default() -> Self {
        Self {
            home_map: [0.0; 3],
            setpoints_before_engage: 10,
            retry_s: 1.0,
            at_end: AtEnd::Hold,
        }
    }
}

/// Where the bridge is in the sequence.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// No odometry yet: nothing is sent.
    WaitOdometry,
    /// Streaming a hold setpoint; engages once a path waits.
    Ready,
    /// Offboard and arming asked for, not yet confirmed.
    Engaging,
    /// In offboard, armed, following the path.
    Flying,
    /// NAV_LAND sent: PX4 lands by itself.
    Landing,
}

/// A command for PX4 (`VehicleCommand`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Command {
    /// DO_SET_MODE, custom mode, main mode offboard.
    SetOffboard,
    /// COMPONENT_ARM_DISARM, arm.
    Arm,
    /// NAV_LAND.
    Land,
}

impl Command {
    /// MAVLink command id, param1, param2.
    pub fn mavlink(self) -> (u32, f32, f32) {
        match self {
            Command::SetOffboard => (176, 1.0, 6.0),
            Command::Arm => (400, 1.0, 0.0),
            Command::Land => (21, 0.0, 0.0),
        }
    }
}

/// A position setpoint in PX4's local NED.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setpoint {
    /// m, NED.
    pub ned: [f32; 3],
    /// rad, NED yaw.
    pub yaw: f32,
}

/// What the bridge must send or say.
#[derive(Debug, Clone, PartialEq)]
pub enum Out {
    /// OffboardControlMode (position) and this TrajectorySetpoint.
    Heartbeat(Setpoint),
    /// A VehicleCommand.
    Command(Command),
    /// A way-point (for /uav/way_point) or arrived / blocked (/uav/vehicle_status).
    Follow(FollowEvent),
}

/// The state machine (see the module doc).
#[derive(Debug, Clone)]
pub struct Offboard {
    config: OffboardConfig,
    phase: Phase,
    follower: Follower,
    /// The path waiting for offboard, or the one flown: map position, ENU yaw.
    leg: Vec<([f32; 3], f32)>,
    /// Where to hover when there is no way-point (map, ENU yaw).
    hold: ([f32; 3], f32),
    pose: Option<([f32; 3], f32)>,
    streamed: u32,
    asked_at: f64,
    armed: bool,
    offboard: bool,
}

impl Offboard {
    /// A bridge that has heard nothing yet.
    pub fn new(config: OffboardConfig, follow: FollowConfig) -> Self {
        Self {
            config,
            phase: Phase::WaitOdometry,
            follower: Follower::new_3d(follow),
            leg: Vec::new(),
            hold: ([0.0; 3], 0.0),
            pose: None,
            streamed: 0,
            asked_at: f64::NEG_INFINITY,
            armed: false,
            offboard: false,
        }
    }

    /// The current phase.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// The follower (its odometer, for /uav/vehicle_status).
    pub fn follower(&self) -> &Follower {
        &self.follower
    }

    /// New follow thresholds, from the next pose on.
    pub fn set_follow(&mut self, follow: FollowConfig) {
        self.follower.set_config(follow);
    }

    /// A pose from PX4 (map, ENU yaw) at time `t` (s).
    pub fn on_pose(&mut self, p: [f32; 3], yaw: f32, t: f64) -> Vec<Out> {
        self.pose = Some((p, yaw));
        match self.phase {
            Phase::WaitOdometry => {
                self.hold = (p, yaw);
                self.phase = Phase::Ready;
                vec![]
            }
            Phase::Flying => {
                let events = self.follower.on_pose(p, t);
                self.after(events)
            }
            _ => vec![],
        }
    }

    /// PX4's arming and mode (from VehicleStatus) at time `t` (s).
    pub fn on_status(&mut self, armed: bool, offboard: bool, t: f64) -> Vec<Out> {
        (self.armed, self.offboard) = (armed, offboard);
        match self.phase {
            Phase::Engaging if armed && offboard => {
                self.phase = Phase::Flying;
                let mut out = self
                    .pose
                    .map_or(vec![], |(p, _)| self.follower.on_pose(p, t));
                let leg = self.leg.iter().map(|(p, _)| *p).collect();
                out.extend(self.follower.set_leg(leg));
                self.after(out)
            }
            Phase::Flying if !(armed && offboard) => {
                let goal = self.leg.last().map_or(self.hold.0, |(p, _)| *p);
                self.stop_here();
                self.phase = Phase::Ready;
                vec![Out::Follow(FollowEvent::Blocked {
                    goal,
                    reason: format!(
                        "PX4 left offboard control (armed {armed}, offboard {offboard}): a pilot or a failsafe has it; waiting for a new path"
                    ),
                })]
            }
            _ => vec![],
        }
    }

    /// A new path (checked: see `check_path`) replaces the current one; an
    /// empty one hovers where the drone is.
    pub fn set_path(&mut self, leg: Vec<([f32; 3], f32)>) -> Vec<Out> {
        self.leg = leg;
        match self.phase {
            Phase::Flying => {
                let events = self
                    .follower
                    .set_leg(self.leg.iter().map(|(p, _)| *p).collect());
                if self.leg.is_empty() {
                    self.stop_here();
                }
                self.after(events)
            }
            Phase::Landing => {
                // PX4 has left offboard to land: stream again before asking back.
                self.phase = Phase::Ready;
                self.streamed = 0;
                vec![]
            }
            _ => vec![],
        }
    }

    /// The stream's tick at time `t` (s): the heartbeat and, when due, commands.
    pub fn tick(&mut self, t: f64) -> Vec<Out> {
        let mut out = match self.phase {
            Phase::WaitOdometry | Phase::Landing => return vec![],
            _ => vec![Out::Heartbeat(self.setpoint())],
        };
        self.streamed = self.streamed.saturating_add(1);
        let due = match self.phase {
            Phase::Ready => {
                !self.leg.is_empty() && self.streamed >= self.config.setpoints_before_engage
            }
            Phase::Engaging => t - self.asked_at >= self.config.retry_s,
            _ => false,
        };
        if due {
            self.phase = Phase::Engaging;
            self.asked_at = t;
            out.extend([
                Out::Command(Command::SetOffboard),
                Out::Command(Command::Arm),
            ]);
        }
        out
    }

    /// The setpoint: the way-point flown to, else the hold.
    fn setpoint(&self) -> Setpoint {
        let (p, yaw) = match (self.phase, self.follower.waypoint()) {
            (Phase::Flying, Some(w)) => self
                .leg
                .iter()
                .find(|(q, _)| *q == w)
                .copied()
                .unwrap_or((w, self.hold.1)),
            _ => self.hold,
        };
        let ned = map_to_ned(p.map(f64::from), self.config.home_map);
        Setpoint {
            ned: ned.map(|v| v as f32),
            yaw: enu_to_ned_yaw(f64::from(yaw)) as f32,
        }
    }

    fn stop_here(&mut self) {
        self.leg.clear();
        if let Some(pose) = self.pose {
            self.hold = pose;
        }
    }

    /// Follower events as outputs; an arrival moves the hold to the goal and lands if asked.
    fn after(&mut self, events: Vec<FollowEvent>) -> Vec<Out> {
        let mut out = Vec::new();
        for e in events {
            match &e {
                FollowEvent::Arrived { goal } => {
                    let yaw = self.leg.last().map_or(self.hold.1, |l| l.1);
                    self.hold = (*goal, yaw);
                    self.leg.clear();
                    if self.config.at_end == AtEnd::Land {
                        self.phase = Phase::Landing;
                        out.push(Out::Follow(e));
                        out.push(Out::Command(Command::Land));
                        continue;
                    }
                }
                FollowEvent::Blocked { .. } => self.stop_here(),
                FollowEvent::WayPoint(_) => {}
            }
            out.push(Out::Follow(e));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bridge(at_end: AtEnd) -> Offboard {
        let config = OffboardConfig {
            home_map: [10.0, 20.0, 1.0],
            setpoints_before_engage: 3,
            retry_s: 1.0,
            at_end,
        };
        Offboard::new(config, FollowConfig::default())
    }

    fn commands(out: &[Out]) -> Vec<Command> {
        out.iter()
            .filter_map(|o| match o {
                Out::Command(c) => Some(*c),
                _ => None,
            })
            .collect()
    }

    fn heartbeat(out: &[Out]) -> Setpoint {
        match out.first() {
            Some(Out::Heartbeat(s)) => *s,
            other => panic!("no heartbeat first: {other:?}"),
        }
    }

    /// A bridge that has streamed, engaged and is flying `leg` from home.
    fn flying(at_end: AtEnd, leg: Vec<([f32; 3], f32)>) -> Offboard {
        let mut b = bridge(at_end);
        b.on_pose([10.0, 20.0, 1.0], 0.0, 0.0);
        b.set_path(leg);
        for k in 0..3 {
            b.tick(0.1 * f64::from(k));
        }
        assert_eq!(b.phase(), Phase::Engaging);
        b.on_status(true, true, 0.4);
        assert_eq!(b.phase(), Phase::Flying);
        b
    }

    #[test]
    fn nothing_is_sent_before_odometry_and_no_command_before_a_path_and_the_stream() {
        let mut b = bridge(AtEnd::Hold);
        assert!(b.tick(0.0).is_empty(), "no odometry: silent");
        b.on_pose([12.0, 23.0, 1.0], std::f32::consts::FRAC_PI_2, 0.0);
        // Streams a hold at the drone's own place, in NED (3 north, 2 east, 0 down).
        for k in 0..10 {
            let out = b.tick(0.1 * f64::from(k));
            assert!(commands(&out).is_empty(), "no path: never arms");
            let s = heartbeat(&out);
            assert_eq!(s.ned, [3.0, 2.0, 0.0]);
            assert!(s.yaw.abs() < 1e-6, "facing north");
        }
        b.set_path(vec![([12.0, 23.0, 20.0], 0.0)]);
        // Already 10 setpoints out: the next tick asks for offboard, then arming.
        let out = b.tick(1.1);
        assert_eq!(commands(&out), vec![Command::SetOffboard, Command::Arm]);
        assert_eq!(b.phase(), Phase::Engaging);
        // Not confirmed: asked again after retry_s, not before.
        assert!(commands(&b.tick(1.5)).is_empty());
        assert_eq!(commands(&b.tick(2.1)).len(), 2);
        // Still the hold while not confirmed: no flying on an unconfirmed mode.
        assert_eq!(heartbeat(&b.tick(2.2)).ned, [3.0, 2.0, 0.0]);
        assert_eq!(Command::SetOffboard.mavlink(), (176, 1.0, 6.0));
        assert_eq!(Command::Arm.mavlink(), (400, 1.0, 0.0));
        assert_eq!(Command::Land.mavlink(), (21, 0.0, 0.0));
    }

    #[test]
    fn a_path_is_flown_way_point_by_way_point_and_held_at_its_end() {
        let leg = vec![([10.0, 20.0, 21.0], 0.0), ([30.0, 20.0, 21.0], 1.0)];
        let mut b = flying(AtEnd::Hold, leg);
        // The first way-point, 20 m above home: NED (0, 0, −20), yaw π/2 − 0.
        let s = heartbeat(&b.tick(0.5));
        assert_eq!(s.ned, [0.0, 0.0, -20.0]);
        assert!((s.yaw - std::f32::consts::FRAC_PI_2).abs() < 1e-6);
        let out = b.on_pose([10.0, 20.0, 20.5], 0.0, 5.0);
        assert_eq!(
            out,
            vec![Out::Follow(FollowEvent::WayPoint([30.0, 20.0, 21.0]))]
        );
        assert_eq!(heartbeat(&b.tick(5.1)).ned, [0.0, 20.0, -20.0]);
        let out = b.on_pose([29.6, 20.1, 21.2], 0.0, 9.0);
        assert_eq!(
            out,
            vec![Out::Follow(FollowEvent::Arrived {
                goal: [30.0, 20.0, 21.0]
            })]
        );
        // Holds the goal, with the goal's heading, still streaming.
        let s = heartbeat(&b.tick(9.1));
        assert_eq!(s.ned, [0.0, 20.0, -20.0]);
        assert!((s.yaw - (std::f32::consts::FRAC_PI_2 - 1.0)).abs() < 1e-6);
        // Flown since offboard: 19.5 m up, then 19.6 m east.
        let flown = 19.5 + (19.6f64.hypot(0.1)).hypot(0.7);
        assert!(
            (b.follower().odometer - flown).abs() < 0.01,
            "{}",
            b.follower().odometer
        );
    }

    #[test]
    fn land_at_the_end_sends_nav_land_and_stops_the_stream() {
        let mut b = flying(AtEnd::Land, vec![([10.0, 20.0, 11.0], 0.0)]);
        let out = b.on_pose([10.0, 20.0, 10.8], 0.0, 4.0);
        assert!(matches!(out[0], Out::Follow(FollowEvent::Arrived { .. })));
        assert_eq!(commands(&out), vec![Command::Land]);
        assert_eq!(b.phase(), Phase::Landing);
        assert!(b.tick(4.1).is_empty());
        // A new path after landing streams again before asking for offboard.
        b.set_path(vec![([10.0, 20.0, 11.0], 0.0)]);
        assert_eq!(b.phase(), Phase::Ready);
        assert!(commands(&b.tick(5.0)).is_empty());
    }

    #[test]
    fn a_pilot_taking_over_blocks_the_leg_and_is_not_fought() {
        let mut b = flying(AtEnd::Hold, vec![([50.0, 20.0, 21.0], 0.0)]);
        b.on_pose([20.0, 20.0, 21.0], 0.0, 3.0);
        let out = b.on_status(true, false, 3.5);
        match out.as_slice() {
            [Out::Follow(FollowEvent::Blocked { goal, reason })] => {
                assert_eq!(*goal, [50.0, 20.0, 21.0]);
                assert!(reason.contains("left offboard"), "{reason}");
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(b.phase(), Phase::Ready);
        for k in 0..20 {
            assert!(
                commands(&b.tick(4.0 + f64::from(k))).is_empty(),
                "no re-engaging"
            );
        }
    }

    #[test]
    fn a_stalled_drone_is_blocked_and_hovers_where_it_is() {
        let mut b = flying(AtEnd::Hold, vec![([100.0, 20.0, 21.0], 0.0)]);
        b.on_pose([12.0, 20.0, 5.0], 0.0, 1.0);
        let mut blocked = false;
        for k in 2..40 {
            let out = b.on_pose([12.0, 20.0, 5.0], 0.0, f64::from(k));
            blocked |= out
                .iter()
                .any(|o| matches!(o, Out::Follow(FollowEvent::Blocked { .. })));
        }
        assert!(blocked, "30 s without progress");
        assert_eq!(heartbeat(&b.tick(40.0)).ned, [0.0, 2.0, -4.0]);
    }
}
