//! Field mode's leg follower: a real robot takes one way-point at a time (the
//! CMU exploration environment's `/way_point`) and reports neither arrival nor
//! failure, so both are read from its pose. Legs (the planners' paths) go out
//! pose by pose; arrival is the last pose within tolerance; a robot that gets
//! no closer to its way-point for a while is blocked (unreachable or stuck).
//! [`Readers`] says when nothing listens for the way-points.

use serde::{Deserialize, Serialize};

/// When a way-point counts as reached and when the robot counts as stuck.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FollowConfig {
    /// An intermediate way-point is passed within this distance (m, in xy).
    pub waypoint_radius_m: f32,
    /// The leg's last pose is reached within this distance (m, in xy).
    pub goal_tolerance_m: f32,
    /// Getting this much closer to the way-point counts as progress (m).
    pub progress_m: f32,
    /// No progress for this long (s of the pose stamps) makes the leg blocked.
    pub stall_timeout_s: f64,
}

impl Default for FollowConfig {
    fn default() -> Self {
        Self {
            waypoint_radius_m: 1.5,
            goal_tolerance_m: 1.0,
            progress_m: 0.5,
            stall_timeout_s: 30.0,
        }
    }
}

/// What the follower asks its node to say.
#[derive(Debug, Clone, PartialEq)]
pub enum FollowEvent {
    /// Send the robot here next (`/way_point`).
    WayPoint([f32; 3]),
    /// The leg's last pose is reached.
    Arrived {
        /// The leg's last pose.
        goal: [f32; 3],
    },
    /// The robot stopped getting closer: the leg is given up.
    Blocked {
        /// The leg's last pose.
        goal: [f32; 3],
        /// For the log and `/vehicle_status`.
        reason: String,
    },
}

/// The follower's state: the current leg, the way-point in it, progress and
/// the odometer.
#[derive(Debug, Clone, Default)]
pub struct Follower {
    config: FollowConfig,
    leg: Vec<[f32; 3]>,
    next: usize,
    /// Closest distance to the current way-point so far, and when it was last
    /// bettered by `progress_m`.
    best: Option<(f32, f64)>,
    last: Option<[f32; 3]>,
    now: f64,
    /// Distances in 3D (a drone) rather than in xy (a ground robot).
    spatial: bool,
    /// Metres the robot has moved (xy; 3D for a drone) since the follower started.
    pub odometer: f64,
}

fn xy_dist(a: [f32; 3], b: [f32; 3]) -> f32 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

impl Follower {
    /// A follower with no leg.
    pub fn new(config: FollowConfig) -> Self {
        Self {
            config,
            ..Self::default()
        }
    }

    /// A follower for a drone: radii, progress and odometer count in 3D, as
    /// a way-point above or below the vehicle is not reached by standing under it.
    pub fn new_3d(config: FollowConfig) -> Self {
        Self {
            config,
            spatial: true,
            ..Self::default()
        }
    }

    fn dist(&self, a: [f32; 3], b: [f32; 3]) -> f32 {
        if self.spatial {
            (a[0] - b[0]).hypot(a[1] - b[1]).hypot(a[2] - b[2])
        } else {
            xy_dist(a, b)
        }
    }

    /// New thresholds, from the next pose on (a parameter set at run time).
    pub fn set_config(&mut self, config: FollowConfig) {
        self.config = config;
    }

    /// The way-point the robot is driving to, if any.
    pub fn waypoint(&self) -> Option<[f32; 3]> {
        self.leg.get(self.next).copied()
    }

    /// The robot's last known position.
    pub fn position(&self) -> Option<[f32; 3]> {
        self.last
    }

    /// A new leg replaces the current one; an empty leg stops the robot where
    /// it is (no event). Poses the robot already stands on are skipped.
    pub fn set_leg(&mut self, leg: Vec<[f32; 3]>) -> Vec<FollowEvent> {
        self.leg = leg;
        self.next = 0;
        self.best = None;
        match self.last {
            Some(p) => self.advance(p),
            None => self
                .waypoint()
                .map(FollowEvent::WayPoint)
                .into_iter()
                .collect(),
        }
    }

    /// A pose from the robot at time `t` (seconds, any epoch, increasing).
    pub fn on_pose(&mut self, p: [f32; 3], t: f64) -> Vec<FollowEvent> {
        if let Some(q) = self.last {
            self.odometer += f64::from(self.dist(p, q));
        }
        self.last = Some(p);
        self.now = t;
        let Some(w) = self.waypoint() else {
            return vec![];
        };
        let before = self.next;
        let mut events = self.advance(p);
        if self.next != before
            || events
                .iter()
                .any(|e| !matches!(e, FollowEvent::WayPoint(_)))
        {
            return events;
        }
        let d = self.dist(p, w);
        match self.best {
            Some((best, _)) if d <= best - self.config.progress_m => self.best = Some((d, t)),
            Some((best, since)) if t - since > self.config.stall_timeout_s => {
                let goal = *self.leg.last().unwrap_or(&w);
                events.push(FollowEvent::Blocked {
                    goal,
                    reason: format!(
                        "no progress towards way-point ({:.1}, {:.1}) for {:.0} s (closest {best:.1} m, now {d:.1} m)",
                        w[0], w[1], self.config.stall_timeout_s
                    ),
                });
                self.leg.clear();
                self.next = 0;
                self.best = None;
            }
            Some(_) => {}
            None => self.best = Some((d, t)),
        }
        events
    }

    /// Moves past every way-point within reach of `p`; the next way-point or
    /// the arrival.
    fn advance(&mut self, p: [f32; 3]) -> Vec<FollowEvent> {
        let start = self.next;
        while let Some(w) = self.waypoint() {
            let last = self.next + 1 == self.leg.len();
            let reach = if last {
                self.config.goal_tolerance_m
            } else {
                self.config.waypoint_radius_m
            };
            if self.dist(p, w) > reach {
                break;
            }
            if last {
                let goal = w;
                self.leg.clear();
                self.next = 0;
                self.best = None;
                return vec![FollowEvent::Arrived { goal }];
            }
            self.next += 1;
        }
        match self.waypoint() {
            Some(w) if self.next != start || self.best.is_none() => {
                self.best = Some((self.dist(p, w), self.now));
                vec![FollowEvent::WayPoint(w)]
            }
            _ => vec![],
        }
    }
}

/// A line for robot_bridge's log, and how loud.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Note {
    /// Worth knowing.
    Info(String),
    /// Something is wrong.
    Warn(String),
}

/// Who listens on /way_point: a robot whose driver never subscribes gets no
/// orders and stalls, which the log should say rather than leave to guess.
#[derive(Debug, Clone, Default)]
pub struct Readers {
    matched: usize,
    /// Ticks in a row with a way-point waiting and no reader.
    unheard: u32,
}

impl Readers {
    /// Resend ticks between repeated warnings (20 s at the shipped 2 s).
    pub const WARN_EVERY: u32 = 10;

    /// At a resend tick, with `matched` subscribers on /way_point and a
    /// way-point `waiting` or none: what the log should say, if anything (a
    /// change of match once, no reader again every [`Self::WARN_EVERY`] ticks).
    pub fn on_tick(&mut self, matched: usize, waiting: bool) -> Option<Note> {
        let was = std::mem::replace(&mut self.matched, matched);
        if matched > 0 {
            self.unheard = 0;
            return (matched != was)
                .then(|| Note::Info(format!("/way_point: {matched} subscriber(s) matched")));
        }
        if !waiting {
            return None;
        }
        self.unheard += 1;
        (self.unheard % Self::WARN_EVERY == 1).then(|| {
            Note::Warn(
                "a way-point is waiting but nothing subscribes to /way_point \
                 (geometry_msgs/PointStamped, reliable): is the robot's driver listening there?"
                    .to_owned(),
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn follower() -> Follower {
        Follower::new(FollowConfig {
            waypoint_radius_m: 1.0,
            goal_tolerance_m: 0.5,
            progress_m: 0.5,
            stall_timeout_s: 10.0,
        })
    }

    #[test]
    fn a_leg_goes_out_pose_by_pose_and_arrives_at_its_end() {
        let mut f = follower();
        assert!(f.on_pose([0.0, 0.0, 0.0], 0.0).is_empty());
        let leg = vec![[5.0, 0.0, 0.0], [10.0, 0.0, 0.0], [10.0, 5.0, 0.0]];
        assert_eq!(f.set_leg(leg), vec![FollowEvent::WayPoint([5.0, 0.0, 0.0])]);
        assert!(f.on_pose([3.0, 0.0, 0.0], 1.0).is_empty());
        // Within the way-point radius of the first pose: on to the second.
        assert_eq!(
            f.on_pose([4.2, 0.1, 0.0], 2.0),
            vec![FollowEvent::WayPoint([10.0, 0.0, 0.0])]
        );
        assert_eq!(
            f.on_pose([9.5, 0.2, 0.0], 3.0),
            vec![FollowEvent::WayPoint([10.0, 5.0, 0.0])]
        );
        // The last pose needs the tighter goal tolerance.
        assert!(f.on_pose([10.0, 4.2, 0.0], 4.0).is_empty());
        assert_eq!(
            f.on_pose([10.1, 4.7, 0.0], 5.0),
            vec![FollowEvent::Arrived {
                goal: [10.0, 5.0, 0.0]
            }]
        );
        assert_eq!(f.waypoint(), None);
        let driven = 3.0 + 1.2 + 5.3 + 4.0 + 0.5;
        assert!((f.odometer - driven).abs() < 0.05, "{}", f.odometer);
    }

    #[test]
    fn a_robot_that_gets_no_closer_is_blocked_after_the_timeout() {
        let mut f = follower();
        f.on_pose([0.0, 0.0, 0.0], 100.0);
        f.set_leg(vec![[20.0, 0.0, 0.0]]);
        assert!(f.on_pose([2.0, 0.0, 0.0], 101.0).is_empty());
        // Jitter without progress, short of the timeout: nothing.
        assert!(f.on_pose([2.3, 0.5, 0.0], 105.0).is_empty());
        assert!(f.on_pose([2.1, -0.5, 0.0], 110.9).is_empty());
        let e = f.on_pose([2.2, 0.0, 0.0], 111.5);
        match e.as_slice() {
            [FollowEvent::Blocked { goal, reason }] => {
                assert_eq!(*goal, [20.0, 0.0, 0.0]);
                assert!(
                    reason.contains("no progress") && reason.contains("10 s"),
                    "{reason}"
                );
            }
            other => panic!("{other:?}"),
        }
        // The leg is given up: no more events until a new one.
        assert!(f.on_pose([2.2, 0.0, 0.0], 200.0).is_empty());
    }

    #[test]
    fn progress_resets_the_stall_clock() {
        let mut f = follower();
        f.on_pose([0.0, 0.0, 0.0], 0.0);
        f.set_leg(vec![[100.0, 0.0, 0.0]]);
        for k in 1..50 {
            // Slow but steady: 0.6 m every 8 s never stalls.
            let e = f.on_pose([0.6 * k as f32, 0.0, 0.0], 8.0 * f64::from(k));
            assert!(e.is_empty(), "{k}: {e:?}");
        }
    }

    #[test]
    fn a_leg_starting_under_the_robot_skips_what_it_stands_on() {
        let mut f = follower();
        f.on_pose([0.0, 0.0, 0.0], 0.0);
        let e = f.set_leg(vec![[0.2, 0.0, 0.0], [8.0, 0.0, 0.0]]);
        assert_eq!(e, vec![FollowEvent::WayPoint([8.0, 0.0, 0.0])]);
        // A one-pose leg the robot already stands on arrives at once.
        let e = f.set_leg(vec![[0.1, 0.1, 0.0]]);
        assert_eq!(
            e,
            vec![FollowEvent::Arrived {
                goal: [0.1, 0.1, 0.0]
            }]
        );
        assert!(f.set_leg(vec![]).is_empty());
    }
    #[test]
    fn a_3d_follower_does_not_arrive_under_its_way_point() {
        let mut f = Follower::new_3d(FollowConfig::default());
        f.on_pose([0.0, 0.0, 0.0], 0.0);
        assert_eq!(
            f.set_leg(vec![[0.0, 0.0, 20.0]]),
            vec![FollowEvent::WayPoint([0.0, 0.0, 20.0])]
        );
        // Right under it, 19.5 m short: a ground robot would have arrived.
        assert!(f.on_pose([0.0, 0.0, 0.5], 1.0).is_empty());
        let e = f.on_pose([0.2, 0.0, 19.5], 5.0);
        assert_eq!(
            e,
            vec![FollowEvent::Arrived {
                goal: [0.0, 0.0, 20.0]
            }]
        );
        assert!((f.odometer - (0.5 + 19.0f64.hypot(0.2))).abs() < 1e-3);
    }

    #[test]
    fn a_waypoint_nobody_hears_is_warned_of_and_a_match_is_said_once() {
        let mut r = Readers::default();
        assert!(
            r.on_tick(0, false).is_none(),
            "no way-point: nothing to say"
        );
        let first = r.on_tick(0, true);
        assert!(matches!(first, Some(Note::Warn(ref l)) if l.contains("nothing subscribes")));
        let repeats = (0..Readers::WARN_EVERY)
            .filter(|_| r.on_tick(0, true).is_some())
            .count();
        assert_eq!(
            repeats,
            1,
            "warned again once every {} ticks",
            Readers::WARN_EVERY
        );
        assert!(
            matches!(r.on_tick(1, true), Some(Note::Info(ref l)) if l.contains("1 subscriber"))
        );
        assert!(r.on_tick(1, true).is_none(), "said once");
        assert!(
            matches!(r.on_tick(0, true), Some(Note::Warn(_))),
            "lost again: warned at once"
        );
    }
}
