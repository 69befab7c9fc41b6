//! px4_bridge: field mode's link to a PX4 drone over PX4's ROS 2 interface
//! (uXRCE-DDS, v1.15 topics). /uav/global_path → offboard setpoints one
//! way-point at a time (the sequence is `core::px4::Offboard`);
//! /fmu/out/vehicle_odometry (NED) → /uav/state_estimation and /tf (map ENU);
//! /uav/vehicle_status says arrived or blocked as robot_bridge does.

use std::time::Duration;

use futures::StreamExt;
use serde::Deserialize;
use skyground_core::follow::FollowConfig;
use skyground_core::px4::frames::yaw_of;
use skyground_core::px4::{Offboard, OffboardConfig, check_path};
use skyground_msgs::px4_msgs::{self as px4, topics};

use crate::convert::px4 as conv;
use crate::runtime::{NodeRuntime, RuntimeError, forward, qos};

mod publish;

use publish::Pubs;

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

/// A refused odometry is logged once, then once every this many.
const LOG_EVERY: u64 = 100;

/// PX4 leaves offboard when the stream drops under 2 Hz.
fn check_rate(hz: f64) -> Result<(), RuntimeError> {
    (2.0..=100.0).contains(&hz).then_some(()).ok_or_else(|| {
        RuntimeError::Node(format!(
            "rate_hz {hz} is outside 2..100: PX4 leaves offboard below 2 Hz"
        ))
    })
}

/// /uav/global_path (latched, as global_planner writes it), as poses.
fn path_channel(rt: &mut NodeRuntime) -> Result<PathRx, RuntimeError> {
    let (tx, rx) = tokio::sync::mpsc::channel(16);
    forward(
        rt,
        "/uav/global_path",
        qos::latched(1),
        tx,
        conv::path_poses,
    )?;
    Ok(rx)
}

type PathRx = tokio::sync::mpsc::Receiver<Vec<([f64; 3], f64)>>;

/// Runs the node until it is asked to stop.
pub async fn run(rt: &mut NodeRuntime) -> Result<(), RuntimeError> {
    let p: Params = rt.params()?;
    check_rate(p.rate_hz)?;
    let pubs = Pubs::new(rt)?;
    // PX4 publishes best effort: a best-effort reader matches it.
    let odom_in =
        rt.subscription::<px4::VehicleOdometry>(topics::VEHICLE_ODOMETRY, qos::sensor(10))?;
    let status_in =
        rt.subscription::<px4::VehicleStatus>(topics::VEHICLE_STATUS, qos::sensor(10))?;
    let mut paths = path_channel(rt)?;
    let (odom_s, status_s) = (odom_in.async_stream(), status_in.async_stream());
    futures::pin_mut!(odom_s, status_s);
    let mut b = Offboard::new(p.offboard, p.follow);
    let mut tick = tokio::time::interval(Duration::from_secs_f64(1.0 / p.rate_hz));
    let (mut refused, mut seen) = (0u64, false);
    let [hx, hy, hz] = p.offboard.home_map;
    rt.log.info(&format!(
        "waiting for PX4 and a path; home at map ({hx:.1}, {hy:.1}, {hz:.1})"
    ));
    loop {
        let now = rt.now().secs();
        let us = (now.max(0.0) * 1e6) as u64;
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
                    b.on_status(armed, offboard, now)
                }
                Err(e) => { rt.log.error(&format!("{}: unreadable: {e}", topics::VEHICLE_STATUS)); continue }
            },
            Some(m) = odom_s.next() => {
                let pose = match m.map_err(|e| e.to_string()).and_then(|(o, _)| {
                    conv::ned_odometry(&o).to_map(p.offboard.home_map).map_err(|e| e.to_string())
                }) {
                    Ok(pose) => pose,
                    Err(e) => {
                        refused += 1;
                        if refused % LOG_EVERY == 1 {
                            rt.log.warn(&format!("{}: skipped ({refused} so far): {e}", topics::VEHICLE_ODOMETRY));
                        }
                        continue;
                    }
                };
                if !std::mem::replace(&mut seen, true) {
                    let [x, y, z] = pose.position;
                    rt.log.info(&format!("PX4 found: drone at map ({x:.1}, {y:.1}, {z:.1})"));
                }
                pubs.pose(rt, &p, &pose).await;
                // follow.* are live: a `ros2 param set` counts from this pose on.
                if let Ok(c) = rt.current_params::<Params>() {
                    b.set_follow(c.follow);
                }
                b.on_pose(pose.position.map(|v| v as f32), yaw_of(pose.q) as f32, now)
            }
            _ = tick.tick() => b.tick(now),
        };
        for out in outs {
            pubs.send(rt, &p, &b, out, us).await;
        }
    }
    rt.log.info(&format!(
        "stopped; the drone flew {:.1} m",
        b.follower().odometer
    ));
    Ok(())
}
