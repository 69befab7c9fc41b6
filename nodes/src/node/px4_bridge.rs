//! px4_bridge: field mode's link to a PX4 drone over PX4's ROS 2 interface
//! (uXRCE-DDS, v1.15 topics). /uav/global_path → offboard setpoints one
//! way-point at a time (the sequence is `core::px4::Offboard`);
//! /fmu/out/vehicle_odometry (NED) → /uav/state_estimation and /tf (map ENU);
//! /uav/vehicle_status says arrived or blocked as robot_bridge does.

use std::time::Duration;

use futures::StreamExt;
use serde::Deserialize;
use skyground_core::follow::{FollowConfig, FollowEvent};
use skyground_core::mission::{VehicleEvent, VehicleStatus};
use skyground_core::px4::frames::yaw_of;
use skyground_core::px4::{Offboard, OffboardConfig, Out, check_path};
use skyground_msgs::diagnostic_msgs::DiagnosticArray;
use skyground_msgs::geometry_msgs::PointStamped;
use skyground_msgs::nav_msgs::Odometry;
use skyground_msgs::px4_msgs::{self as px4, topics};
use skyground_msgs::tf2_msgs::TFMessage;

use crate::convert::diagnostics::array;
use crate::convert::path::point_stamped;
use crate::convert::px4 as conv;
use crate::convert::tf::tf_message;
use crate::runtime::{NodeRuntime, RuntimeError, forward, qos};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    frame_id: String,
    child_frame_id: String,
    rate_hz: f64,
    offboard: OffboardConfig,
    follow: FollowConfig,
}

pub use crate::runtime::specs::PX4_BRIDGE as SPEC;

/// The name /uav/vehicle_status is signed with (worded as robot_bridge's).
const NAME: &str = "px4_bridge";
/// A refused odometry is logged once, then once every this many.
const LOG_EVERY: u64 = 100;

/// Runs the node until it is asked to stop.
pub async fn run(rt: &mut NodeRuntime) -> Result<(), RuntimeError> {
    let p: Params = rt.params()?;
    if !(p.rate_hz >= 2.0 && p.rate_hz <= 100.0) {
        return Err(RuntimeError::Node(format!(
            "rate_hz {} is outside 2..100: PX4 leaves offboard below 2 Hz",
            p.rate_hz
        )));
    }
    let mode_pub =
        rt.publisher::<px4::OffboardControlMode>(topics::OFFBOARD_CONTROL_MODE, qos::reliable(10))?;
    let sp_pub =
        rt.publisher::<px4::TrajectorySetpoint>(topics::TRAJECTORY_SETPOINT, qos::reliable(10))?;
    let cmd_pub =
        rt.publisher::<px4::VehicleCommand>(topics::VEHICLE_COMMAND, qos::reliable(10))?;
    let odom_pub = rt.publisher::<Odometry>("/uav/state_estimation", qos::odometry())?;
    let tf_pub = rt.publisher::<TFMessage>("/tf", qos::tf())?;
    let way_pub = rt.publisher::<PointStamped>("/uav/way_point", qos::reliable(10))?;
    let status_pub = rt.publisher::<DiagnosticArray>("/uav/vehicle_status", qos::reliable(10))?;
    // PX4 publishes best effort: a best-effort reader matches it.
    let odom_in =
        rt.subscription::<px4::VehicleOdometry>(topics::VEHICLE_ODOMETRY, qos::sensor(10))?;
    let status_in =
        rt.subscription::<px4::VehicleStatus>(topics::VEHICLE_STATUS, qos::sensor(10))?;
    let (tx, mut paths) = tokio::sync::mpsc::channel(16);
    forward(
        rt,
        "/uav/global_path",
        qos::latched(1),
        tx,
        conv::path_poses,
    )?;
    let (odom_s, status_s) = (odom_in.async_stream(), status_in.async_stream());
    futures::pin_mut!(odom_s, status_s);
    let mut b = Offboard::new(p.offboard, p.follow);
    let mut tick = tokio::time::interval(Duration::from_secs_f64(1.0 / p.rate_hz));
    let (mut refused, mut seen) = (0u64, false);
    rt.log.info(&format!(
        "waiting for PX4 on {} and a path on /uav/global_path; home at map ({:.1}, {:.1}, {:.1})",
        topics::VEHICLE_ODOMETRY,
        p.offboard.home_map[0],
        p.offboard.home_map[1],
        p.offboard.home_map[2]
    ));
    loop {
        let now = rt.now();
        let (t, us) = (now.secs(), (now.secs().max(0.0) * 1e6) as u64);
        let outs = tokio::select! {
            _ = rt.shutdown.wait() => break,
            Some(poses) = paths.recv() => match check_path(&poses) {
                Ok(leg) => {
                    rt.log.info(&format!("path of {} way-point(s)", leg.len()));
                    b.set_path(leg)
                }
                Err(e) => { rt.log.warn(&format!("/uav/global_path refused: {e}")); continue }
            },
            Some(m) = status_s.next() => match m {
                Ok((s, _)) => {
                    let (armed, offboard) = conv::armed_offboard(&s);
                    b.on_status(armed, offboard, t)
                }
                Err(e) => { rt.log.error(&format!("{}: unreadable: {e}", topics::VEHICLE_STATUS)); continue }
            },
            Some(m) = odom_s.next() => {
                let pose = m.map_err(|e| e.to_string())
                    .and_then(|(o, _)| conv::ned_odometry(&o).to_map(p.offboard.home_map).map_err(|e| e.to_string()));
                let pose = match pose {
                    Ok(pose) => pose,
                    Err(e) => {
                        refused += 1;
                        if refused % LOG_EVERY == 1 {
                            rt.log.warn(&format!("{}: skipped ({refused} so far): {e}", topics::VEHICLE_ODOMETRY));
                        }
                        continue;
                    }
                };
                if !seen {
                    seen = true;
                    let q = pose.position;
                    rt.log.info(&format!("PX4 found: drone at map ({:.1}, {:.1}, {:.1})", q[0], q[1], q[2]));
                }
                let header = rt.header(&p.frame_id);
                let o = conv::odometry(header.clone(), &p.child_frame_id, &pose);
                rt.log.sent("/uav/state_estimation", odom_pub.async_publish(o).await);
                let tf = tf_message(conv::transform(header, &p.child_frame_id, &pose));
                rt.log.sent("/tf", tf_pub.async_publish(tf).await);
                if let Ok(c) = rt.current_params::<Params>() {
                    b.set_follow(c.follow);
                }
                b.on_pose(pose.position.map(|v| v as f32), yaw_of(pose.q) as f32, t)
            }
            _ = tick.tick() => b.tick(t),
        };
        for out in outs {
            match out {
                Out::Heartbeat(s) => {
                    let (mode, sp) = conv::heartbeat(&s, us);
                    rt.log.sent(
                        topics::OFFBOARD_CONTROL_MODE,
                        mode_pub.async_publish(mode).await,
                    );
                    rt.log
                        .sent(topics::TRAJECTORY_SETPOINT, sp_pub.async_publish(sp).await);
                }
                Out::Command(c) => {
                    rt.log
                        .info(&format!("asking PX4: {c:?} (command {})", c.mavlink().0));
                    rt.log.sent(
                        topics::VEHICLE_COMMAND,
                        cmd_pub.async_publish(conv::command(c, us)).await,
                    );
                }
                Out::Follow(FollowEvent::WayPoint(w)) => {
                    let msg = point_stamped(rt.header(&p.frame_id), w);
                    rt.log
                        .sent("/uav/way_point", way_pub.async_publish(msg).await);
                }
                Out::Follow(FollowEvent::Arrived { goal }) => {
                    rt.log.info(&format!(
                        "arrived at ({:.1}, {:.1}, {:.1})",
                        goal[0], goal[1], goal[2]
                    ));
                    let s = VehicleStatus::from_follower(
                        NAME,
                        VehicleEvent::Arrived,
                        goal,
                        b.follower(),
                    );
                    let s = array(rt.header(&p.frame_id), s.to_wire());
                    rt.log
                        .sent("/uav/vehicle_status", status_pub.async_publish(s).await);
                }
                Out::Follow(FollowEvent::Blocked { goal, reason }) => {
                    rt.log.warn(&format!(
                        "blocked going to ({:.1}, {:.1}, {:.1}): {reason}",
                        goal[0], goal[1], goal[2]
                    ));
                    let s = VehicleStatus::from_follower(
                        NAME,
                        VehicleEvent::Blocked(reason),
                        goal,
                        b.follower(),
                    );
                    let s = array(rt.header(&p.frame_id), s.to_wire());
                    rt.log
                        .sent("/uav/vehicle_status", status_pub.async_publish(s).await);
                }
            }
        }
    }
    rt.log.info(&format!(
        "stopped; the drone flew {:.1} m",
        b.follower().odometer
    ));
    Ok(())
}
