//! uav_sim: /uav/global_path (sorties, home to home) → a simulated
//! multirotor with a Mid-360-like LiDAR under it → /uav/state_estimation,
//! /uav/registered_scan (ids marked as the drone's), one scan in
//! `throttle_every` on /uav/registered_scan_throttle, /uav/flight_status,
//! /tf (map → uav/base_link) and /tf_static (uav/base_link → uav/sensor).
//! Its robot time runs as vehicle_sim's: `time_factor` times wall time
//! while it flies, wall speed while it waits on the pad.

use std::time::{Duration, Instant};

use serde::Deserialize;
use skyground_core::io::load_scene;
use skyground_core::lidar::{Caster, LidarConfig, scan};
use skyground_core::mission::uav::{UavState, UavStatus};
use skyground_core::vehicle::multirotor::{
    FlightStep, Multirotor, MultirotorConfig, SceneBody, SortieQueue,
};
use skyground_core::vehicle::{Every, RobotClock, ScanSchedule, Terrain};
use skyground_msgs::builtin_interfaces::Time;
use skyground_msgs::diagnostic_msgs::DiagnosticArray;
use skyground_msgs::nav_msgs::Odometry;
use skyground_msgs::sensor_msgs::PointCloud2;
use skyground_msgs::std_msgs::Header;
use skyground_msgs::tf2_msgs::TFMessage;
use tokio::sync::mpsc;

use crate::convert::path::read_paths;
use crate::convert::pointcloud2::{EncodeOptions, encode};
use crate::convert::tf::{sensor_mount, tf_message, transform, yaw_quaternion};
use crate::convert::{diagnostics::array, scans::ScanWriter};
use crate::runtime::{NodeRuntime, RuntimeError, publish_logged, qos};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    scene: String,
    /// The home pad, [x, y] in the scene's local frame (on its ground).
    pad: Vec<f64>,
    time_factor: f64,
    step_s: f64,
    odom_rate_hz: f64,
    status_period_s: f64,
    frame_id: String,
    child_frame_id: String,
    sensor_frame_id: String,
    path_topic: String,
    scan_topic: String,
    scan_min_move_m: f64,
    stationary_scan_period_s: f64,
    throttle_every: u64,
    scan_log: String,
    multirotor: MultirotorConfig,
    lidar: LidarConfig,
}

pub use crate::runtime::specs::UAV_SIM as SPEC;

/// The drone's platform index in scan ids.
const PLATFORM: u8 = 1;

/// Runs the node until it is asked to stop.
pub async fn run(rt: &mut NodeRuntime) -> Result<(), RuntimeError> {
    let p: Params = rt.params()?;
    let err = |e: String| RuntimeError::Node(e);
    p.multirotor.validate()?;
    let scene = load_scene(&p.scene).map_err(|e| err(format!("scene {}: {e}", p.scene)))?;
    let caster = Caster::new(&scene).map_err(|e| err(format!("scene {}: {e}", p.scene)))?;
    let body = SceneBody::new(&scene);
    let &[px, py] = p.pad.as_slice() else {
        return Err(err(format!("pad {:?}: give [x, y]", p.pad)));
    };
    let (px, py) = (px as f32, py as f32);
    let gz = Terrain::new(&caster)
        .ground_height(px, py)
        .ok_or_else(|| err(format!("pad ({px:.1}, {py:.1}) is off the terrain")))?;
    let mut m = Multirotor::new(p.multirotor, [px, py, gz], 0.0);
    rt.log.info(&format!(
        "scene {}: {} triangles; drone on its pad at ({px:.1}, {py:.1}, {gz:.1})",
        p.scene,
        caster.triangle_count()
    ));
    let odom_pub = rt.publisher::<Odometry>("/uav/state_estimation", qos::odometry())?;
    let mut scan_pub = ScanWriter::on(
        rt,
        (&p.scan_topic, PLATFORM),
        Duration::from_secs(10),
        &p.scan_log,
    )?;
    let throttle = format!("{}_throttle", p.scan_topic);
    let throttle_pub = rt.publisher::<PointCloud2>(&throttle, qos::sensor(5))?;
    let status_pub = rt.publisher::<DiagnosticArray>("/uav/flight_status", qos::latched(1))?;
    let tf_pub = rt.publisher::<TFMessage>("/tf", qos::tf())?;
    let tf_static_pub = rt.publisher::<TFMessage>("/tf_static", qos::latched(1))?;
    let drop = -p.multirotor.sensor_drop;
    let mount = sensor_mount(&p.child_frame_id, &p.sensor_frame_id, drop);
    publish_logged(&rt.log, "/tf_static", tf_static_pub.async_publish(mount)).await;
    let (tx, mut paths) = mpsc::channel::<Vec<[f32; 3]>>(16);
    read_paths(rt, std::slice::from_ref(&p.path_topic), &tx)?;
    // Cut short, it comes home 5 m over the scene's top.
    let top = caster.bounds().map_or(gz + 50.0, |(_, hi)| hi[2]);
    let mut queue = SortieQueue::new(top + 5.0);
    let (mut odom_due, mut status_due) = (
        Every::new(p.odom_rate_hz),
        Every::new(1.0 / p.status_period_s),
    );
    let mut scan_due = ScanSchedule::new(
        f64::from(p.lidar.rate_hz),
        p.scan_min_move_m,
        p.stationary_scan_period_s,
    );
    let mut clock = scan_pub.go_on(RobotClock::new(p.step_s, p.time_factor), p.step_s, &rt.log);
    let (mut scans, mut given, mut closest) = (0u64, false, f64::INFINITY);
    let wall0 = Instant::now();
    while !rt.shutdown.requested() {
        while let Ok(path) = paths.try_recv() {
            rt.log.info(&format!("path of {} way-point(s)", path.len()));
            queue.push_path(m.home, &path, m.config.goal_tolerance);
            given = true;
        }
        let step = queue.step(&mut m, p.step_s as f32, &body);
        let flying = m.state.airborne || matches!(step, FlightStep::Moving);
        let pause = clock.tick(flying, wall0.elapsed().as_secs_f64());
        let sim = clock.now();
        closest = closest.min(f64::from(body.clearance(m.state.position)));
        let h = Header {
            stamp: Time::from_secs(sim),
            frame_id: p.frame_id.clone(),
        };
        match &step {
            FlightStep::Blocked { reason, .. } => rt
                .log
                .warn(&format!("sortie cut short, coming home: {reason}")),
            FlightStep::BatteryEmpty => rt.log.error("battery empty: landed where it was"),
            _ => {}
        }
        let state = match (given, queue.done(&m)) {
            (false, _) => UavState::Waiting,
            (true, false) => UavState::Flying,
            (true, true) => UavState::Done,
        };
        if status_due.due(sim) || matches!(step, FlightStep::Arrived(_)) {
            let s = UavStatus {
                name: "uav_sim".into(),
                state,
                sorties: m.sorties,
                waiting: queue.waiting() as u32,
                cut: queue.cut,
                flight_s: clock.split().0,
                time_s: sim,
                odometer_m: f64::from(m.state.odometer),
                closest_m: closest,
            };
            let sent = status_pub.async_publish(array(h.clone(), s.to_wire()));
            publish_logged(&rt.log, "/uav/flight_status", sent).await;
        }
        if odom_due.due(sim) {
            let at = m.state.position.map(f64::from);
            let pose = transform(&h, &p.child_frame_id, at, m.state.yaw);
            let o = odometry(h.clone(), &p.child_frame_id, &m);
            publish_logged(&rt.log, "/uav/state_estimation", odom_pub.async_publish(o)).await;
            publish_logged(&rt.log, "/tf", tf_pub.async_publish(tf_message(pose))).await;
        }
        let pose = m.sensor_pose();
        if m.state.airborne && scan_pub.ready(&rt.log) && scan_due.due(sim, pose.position) {
            let points =
                scan(&caster, &p.lidar, &pose, scans).map_err(|e| err(format!("lidar: {e}")))?;
            let msg = encode(
                &points.to_cloud(caster.origin()),
                h,
                &EncodeOptions::default(),
            );
            if p.throttle_every > 0 && scans.is_multiple_of(p.throttle_every) {
                publish_logged(&rt.log, &throttle, throttle_pub.async_publish(msg.clone())).await;
            }
            publish_logged(&rt.log, &p.scan_topic, scan_pub.write(msg)).await;
            scans += 1;
        }
        if pause > 0.0 {
            tokio::time::sleep(Duration::from_secs_f64(pause)).await;
        } else {
            tokio::task::yield_now().await;
        }
    }
    let acked = ["not all", "all"][usize::from(scan_pub.wait_acks().await)];
    rt.log.info(&format!(
        "stopped after {:.1} simulated s, {} sortie(s), {:.1} m flown, {scans} scans ({acked} acknowledged), closest approach {closest:.2} m",
        clock.now(),
        m.sorties,
        m.state.odometer
    ));
    Ok(())
}

/// The drone's odometry: its pose, yaw and velocity in `map`.
fn odometry(header: Header, child: &str, m: &Multirotor) -> Odometry {
    let mut o = Odometry {
        header,
        child_frame_id: child.into(),
        ..Odometry::default()
    };
    let [x, y, z] = m.state.position.map(f64::from);
    (
        o.pose.pose.position.x,
        o.pose.pose.position.y,
        o.pose.pose.position.z,
    ) = (x, y, z);
    o.pose.pose.orientation = yaw_quaternion(m.state.yaw);
    let [vx, vy, vz] = m.state.velocity.map(f64::from);
    (
        o.twist.twist.linear.x,
        o.twist.twist.linear.y,
        o.twist.twist.linear.z,
    ) = (vx, vy, vz);
    o
}
