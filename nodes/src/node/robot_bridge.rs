//! robot_bridge: field mode's link to a real robot. /local_path legs →
//! /way_point one pose at a time; /state_estimation → /vehicle_status
//! (arrived, blocked: no progress) with the odometer, as vehicle_sim reports.

use std::time::Duration;

use futures::StreamExt;
use serde::Deserialize;
use skyground_core::follow::{FollowConfig, FollowEvent, Follower};
use skyground_core::mission::{VehicleEvent, VehicleStatus};
use skyground_msgs::diagnostic_msgs::DiagnosticArray;
use skyground_msgs::geometry_msgs::{Point, PointStamped};
use skyground_msgs::nav_msgs::Odometry;
use skyground_msgs::std_msgs::Header;

use crate::convert::diagnostics::array;
use crate::convert::path::{odom_position, read_paths};
use crate::runtime::{NodeRuntime, RuntimeError, qos};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    frame_id: String,
    path_topics: Vec<String>,
    follow: FollowConfig,
    resend_period_s: f64,
}

crate::node_spec!("robot_bridge", live: ["follow."]);

/// `/vehicle_status` as vehicle_sim words it, so the planners need not know
/// which of the two drives.
fn status(header: Header, event: VehicleEvent, goal: [f32; 3], f: &Follower) -> DiagnosticArray {
    let at = f.position().unwrap_or(goal);
    let s = VehicleStatus {
        name: "robot_bridge".into(),
        event,
        goal: [goal[0], goal[1]],
        at: [at[0], at[1]],
        odometer_m: f.odometer,
    };
    array(header, s.to_wire())
}

enum Level {
    Info,
    Warn,
}

/// Who listens on /way_point: a robot whose driver never subscribes gets no
/// orders and stalls, which the log should say rather than leave to guess.
#[derive(Default)]
struct Readers {
    matched: usize,
    /// Ticks in a row with a way-point waiting and no reader.
    unheard: u32,
}

impl Readers {
    /// Resend ticks between repeated warnings (20 s at the shipped 2 s).
    const WARN_EVERY: u32 = 10;

    fn on_tick(&mut self, matched: usize, waiting: bool) -> Option<(Level, String)> {
        let was = std::mem::replace(&mut self.matched, matched);
        if matched > 0 {
            self.unheard = 0;
            return (matched != was).then(|| {
                (
                    Level::Info,
                    format!("/way_point: {matched} subscriber(s) matched"),
                )
            });
        }
        if !waiting {
            return None;
        }
        self.unheard += 1;
        (self.unheard % Self::WARN_EVERY == 1).then(|| {
            (
                Level::Warn,
                "a way-point is waiting but nothing subscribes to /way_point \
                 (geometry_msgs/PointStamped, reliable): is the robot's driver listening there?"
                    .to_owned(),
            )
        })
    }
}

/// Runs the node until it is asked to stop.
pub async fn run(rt: &mut NodeRuntime) -> Result<(), RuntimeError> {
    let p: Params = rt.params()?;
    let way_pub = rt.publisher::<PointStamped>("/way_point", qos::reliable(10))?;
    let status_pub = rt.publisher::<DiagnosticArray>("/vehicle_status", qos::reliable(10))?;
    let odom = rt.subscription::<Odometry>("/state_estimation", qos::odometry())?;
    let (tx, mut legs) = tokio::sync::mpsc::channel::<Vec<[f32; 3]>>(16);
    read_paths(rt, &p.path_topics, &tx)?;
    let odom_s = odom.async_stream();
    futures::pin_mut!(odom_s);
    let mut f = Follower::new(p.follow);
    let mut resend = tokio::time::interval(Duration::from_secs_f64(p.resend_period_s.max(0.1)));
    rt.log
        .info("waiting for legs on /local_path and the robot on /state_estimation");
    let mut seen_robot = false;
    let mut readers = Readers::default();
    loop {
        let mut ticked = false;
        let events = tokio::select! {
            _ = rt.shutdown.wait() => break,
            Some(leg) = legs.recv() => {
                rt.log.info(&format!("leg of {} pose(s)", leg.len()));
                f.set_leg(leg)
            }
            Some(m) = odom_s.next() => match m {
                Ok((o, _)) => {
                    let Some(pos) = odom_position(&o) else { continue };
                    if !seen_robot {
                        seen_robot = true;
                        rt.log.info(&format!("robot at ({:.1}, {:.1}, {:.1})", pos[0], pos[1], pos[2]));
                    }
                    let t = o.header.stamp.secs();
                    // follow.* are live: a `ros2 param set` counts from this pose on.
                    if let Ok(c) = rt.current_params::<Params>() {
                        f.set_config(c.follow);
                    }
                    f.on_pose(pos, t)
                }
                Err(e) => { rt.log.error(&format!("/state_estimation: unreadable message: {e}")); continue }
            },
            _ = resend.tick() => {
                ticked = true;
                f.waypoint().map(FollowEvent::WayPoint).into_iter().collect()
            }
        };
        if ticked {
            let n = way_pub.get_subscription_count(rt.node());
            if let Some((level, line)) = readers.on_tick(n, f.waypoint().is_some()) {
                match level {
                    Level::Info => rt.log.info(&line),
                    Level::Warn => rt.log.warn(&line),
                }
            }
        }
        let header = rt.header(&p.frame_id);
        for e in events {
            match e {
                FollowEvent::WayPoint(w) => {
                    let msg = PointStamped {
                        header: header.clone(),
                        point: Point {
                            x: f64::from(w[0]),
                            y: f64::from(w[1]),
                            z: f64::from(w[2]),
                        },
                    };
                    rt.log.sent("/way_point", way_pub.async_publish(msg).await);
                }
                FollowEvent::Arrived { goal } => {
                    rt.log
                        .info(&format!("arrived at ({:.1}, {:.1})", goal[0], goal[1]));
                    let s = status(header.clone(), VehicleEvent::Arrived, goal, &f);
                    rt.log
                        .sent("/vehicle_status", status_pub.async_publish(s).await);
                }
                FollowEvent::Blocked { goal, reason } => {
                    rt.log.warn(&format!(
                        "blocked going to ({:.1}, {:.1}): {reason}",
                        goal[0], goal[1]
                    ));
                    let s = status(header.clone(), VehicleEvent::Blocked(reason), goal, &f);
                    rt.log
                        .sent("/vehicle_status", status_pub.async_publish(s).await);
                }
            }
        }
    }
    rt.log
        .info(&format!("stopped; the robot moved {:.1} m", f.odometer));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_waypoint_nobody_hears_is_warned_of_and_a_match_is_said_once() {
        let mut r = Readers::default();
        assert!(
            r.on_tick(0, false).is_none(),
            "no way-point: nothing to say"
        );
        let first = r.on_tick(0, true);
        assert!(matches!(first, Some((Level::Warn, ref l)) if l.contains("nothing subscribes")));
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
            matches!(r.on_tick(1, true), Some((Level::Info, ref l)) if l.contains("1 subscriber"))
        );
        assert!(r.on_tick(1, true).is_none(), "said once");
        assert!(
            matches!(r.on_tick(0, true), Some((Level::Warn, _))),
            "lost again: warned at once"
        );
    }
}
