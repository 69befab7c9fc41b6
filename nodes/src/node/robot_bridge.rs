//! robot_bridge: field mode's link to a real robot. /local_path legs →
//! /way_point one pose at a time; /state_estimation → /vehicle_status
//! (arrived, blocked: no progress) with the odometer, as vehicle_sim reports.

use std::time::Duration;

use futures::StreamExt;
use serde::Deserialize;
use skyground_core::follow::{FollowConfig, FollowEvent, Follower, Note, Readers};
use skyground_core::mission::{VehicleEvent, VehicleStatus};
use skyground_msgs::diagnostic_msgs::DiagnosticArray;
use skyground_msgs::geometry_msgs::PointStamped;
use skyground_msgs::nav_msgs::Odometry;

use crate::convert::diagnostics::array;
use crate::convert::path::{odom_position, point_stamped, read_paths};
use crate::runtime::{NodeRuntime, RuntimeError, qos};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    frame_id: String,
    path_topics: Vec<String>,
    follow: FollowConfig,
    resend_period_s: f64,
}

pub use crate::runtime::specs::ROBOT_BRIDGE as SPEC;

/// The name robot_bridge signs /vehicle_status with; the status is worded
/// as vehicle_sim's, so the planners need not know which of the two drives.
const NAME: &str = "robot_bridge";

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
            match readers.on_tick(n, f.waypoint().is_some()) {
                Some(Note::Info(line)) => rt.log.info(&line),
                Some(Note::Warn(line)) => rt.log.warn(&line),
                None => {}
            }
        }
        let header = rt.header(&p.frame_id);
        for e in events {
            match e {
                FollowEvent::WayPoint(w) => {
                    let msg = point_stamped(header.clone(), w);
                    rt.log.sent("/way_point", way_pub.async_publish(msg).await);
                }
                FollowEvent::Arrived { goal } => {
                    rt.log
                        .info(&format!("arrived at ({:.1}, {:.1})", goal[0], goal[1]));
                    let s = VehicleStatus::from_follower(NAME, VehicleEvent::Arrived, goal, &f);
                    let s = array(header.clone(), s.to_wire());
                    rt.log
                        .sent("/vehicle_status", status_pub.async_publish(s).await);
                }
                FollowEvent::Blocked { goal, reason } => {
                    rt.log.warn(&format!(
                        "blocked going to ({:.1}, {:.1}): {reason}",
                        goal[0], goal[1]
                    ));
                    let event = VehicleEvent::Blocked(reason);
                    let s = VehicleStatus::from_follower(NAME, event, goal, &f);
                    let s = array(header.clone(), s.to_wire());
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
