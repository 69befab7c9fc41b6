//! vehicle_sim: /way_point, paths (/local_path by default) and /set_down (the
//! robot carried to a spot, as a field team does) → a simulated ground
//! vehicle with a spinning LiDAR → /state_estimation, /registered_scan (and one
//! scan in `throttle_every` on /registered_scan_throttle), /clock,
//! /vehicle_status, /tf (map → base_link) and /tf_static (base_link → sensor).
//! Simulated time is robot time: `time_factor` times faster than wall time
//! while the vehicle drives or turns, wall speed while it waits for orders.

use std::time::{Duration, Instant};

use crate::convert::pointcloud2::{EncodeOptions, encode};
use serde::Deserialize;
use skyground_core::io::load_scene;
use skyground_core::lidar::{Caster, LidarConfig, Pose, scan};
use skyground_core::mission::VehicleStatus;
use skyground_core::vehicle::{
    Every, RobotClock, ScanSchedule, Step, Vehicle, VehicleConfig, start_spot,
};
use skyground_msgs::builtin_interfaces::Time;
use skyground_msgs::diagnostic_msgs::DiagnosticArray;
use skyground_msgs::nav_msgs::Odometry;
use skyground_msgs::rosgraph_msgs::Clock;
use skyground_msgs::sensor_msgs::PointCloud2;
use skyground_msgs::std_msgs::Header;
use skyground_msgs::tf2_msgs::TFMessage;
use tokio::sync::mpsc;

use crate::convert::path::{odometry, read_paths, read_spots};
use crate::convert::tf::{sensor_mount, tf_message, transform};
use crate::convert::{diagnostics::array, scans::ScanWriter};
use crate::runtime::{NodeRuntime, RuntimeError, publish_logged, qos};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    scene: String,
    start: Vec<f64>,
    start_yaw: f64,
    time_factor: f64,
    step_s: f64,
    odom_rate_hz: f64,
    clock_rate_hz: f64,
    frame_id: String,
    child_frame_id: String,
    sensor_frame_id: String,
    path_topics: Vec<String>,
    /// A scan is cast at the LiDAR's rate once the sensor has moved this far
    /// since the last one, else every `stationary_scan_period_s`.
    scan_min_move_m: f64,
    stationary_scan_period_s: f64,
    /// Every this many scans one also goes to /registered_scan_throttle (0: none).
    throttle_every: u64,
    scan_log: String,
    vehicle: VehicleConfig,
    lidar: LidarConfig,
}

pub use crate::runtime::specs::VEHICLE_SIM as SPEC;

/// Runs the node until it is asked to stop.
pub async fn run(rt: &mut NodeRuntime) -> Result<(), RuntimeError> {
    let p: Params = rt.params()?;
    let err = |e: String| RuntimeError::Node(e);
    if !(p.time_factor > 0.0 && p.step_s > 0.0) {
        return Err(err("time_factor and step_s must be positive".into()));
    }
    let t_load = Instant::now();
    let scene = load_scene(&p.scene).map_err(|e| err(format!("scene {}: {e}", p.scene)))?;
    let caster = Caster::new(&scene).map_err(|e| err(format!("scene {}: {e}", p.scene)))?;
    let start = start_spot(&caster, &p.start).map_err(|e| err(e.to_string()))?;
    let mut vehicle = Vehicle::new(p.vehicle, &caster, start[0], start[1], p.start_yaw as f32)
        .ok_or_else(|| err(format!("start {start:?} is off the terrain")))?;
    let [x, y, z] = vehicle.state.position;
    rt.log.info(&format!(
        "scene {}: {} triangles, loaded in {:.2} s; vehicle at ({x:.1}, {y:.1}, {z:.1}); time factor {}",
        p.scene,
        caster.triangle_count(),
        t_load.elapsed().as_secs_f64(),
        p.time_factor
    ));

    let odom_pub = rt.publisher::<Odometry>("/state_estimation", qos::odometry())?;
    let mut scan_pub = ScanWriter::new(rt, Duration::from_secs(10), &p.scan_log)?;
    // A reader keeping one scan in N (the recorder) is still sent all N by
    // DDS; this topic, named as topic_tools' throttle does, carries the one.
    let throttle_pub = rt.publisher::<PointCloud2>("/registered_scan_throttle", qos::sensor(5))?;
    let clock_pub = rt.publisher::<Clock>("/clock", qos::sensor(1))?;
    let status_pub = rt.publisher::<DiagnosticArray>("/vehicle_status", qos::reliable(10))?;
    // As tf2's broadcasters: /tf reliable and volatile, /tf_static latched.
    let tf_pub = rt.publisher::<TFMessage>("/tf", qos::tf())?;
    let tf_static_pub = rt.publisher::<TFMessage>("/tf_static", qos::latched(1))?;
    let height = p.vehicle.sensor_height;
    let mount = sensor_mount(&p.child_frame_id, &p.sensor_frame_id, height);
    let sent = tf_static_pub.async_publish(mount);
    publish_logged(&rt.log, "/tf_static", sent).await;
    let (tx, mut paths) = mpsc::channel::<Vec<[f32; 3]>>(16);
    read_paths(rt, &p.path_topics, &tx)?;
    let mut goals = read_spots(rt, "/way_point", qos::reliable(10), 16)?;
    let mut carries = read_spots(rt, "/set_down", qos::latched(1), 4)?;
    let mut odom_due = Every::new(p.odom_rate_hz);
    let mut clock_due = Every::new(p.clock_rate_hz);
    let rate = f64::from(p.lidar.rate_hz);
    let mut scan_due = ScanSchedule::new(rate, p.scan_min_move_m, p.stationary_scan_period_s);
    let mut clock = scan_pub.go_on(RobotClock::new(p.step_s, p.time_factor), p.step_s, &rt.log);
    let (mut scans, mut sent_scans) = (0u64, 0u64);
    let burst = crate::runtime::faults::LargeScans::from_env();
    let wall0 = Instant::now();
    while !rt.shutdown.requested() {
        while let Ok(g) = goals.try_recv() {
            rt.log
                .info(&format!("way-point ({:.1}, {:.1})", g[0], g[1]));
            vehicle.set_goal(g);
        }
        let mut refused = Vec::new();
        while let Ok(to) = carries.try_recv() {
            // Carried: no driving, so the odometer and the clock do not move.
            match vehicle.set_down(&caster, to) {
                Ok(v) => {
                    vehicle = v;
                    odom_due = Every::new(p.odom_rate_hz);
                    rt.log
                        .info(&format!("set down at ({:.1}, {:.1})", to[0], to[1]));
                }
                Err(blocked) => {
                    let at = format!("({:.1}, {:.1})", to[0], to[1]);
                    rt.log
                        .warn(&format!("cannot set down at {at}: off the terrain"));
                    // The planner waits for the robot there: tell it, as a blocked goal.
                    refused.push(blocked);
                }
            }
        }
        while let Ok(pts) = paths.try_recv() {
            rt.log.info(&format!("path of {} pose(s)", pts.len()));
            vehicle.set_path(pts.iter().map(|q| [q[0], q[1]]));
        }
        let step = vehicle.step(&caster, p.step_s as f32);
        let pause = clock.tick(step != Step::Idle, wall0.elapsed().as_secs_f64());
        let sim = clock.now();
        let h = Header {
            stamp: Time::from_secs(sim),
            frame_id: p.frame_id.clone(),
        };
        if let Step::Blocked { goal, reason } = &step {
            let at = format!("({:.1}, {:.1})", goal[0], goal[1]);
            rt.log.warn(&format!("blocked going to {at}: {reason}"));
        }
        for done in refused.iter().chain([&step]) {
            if let Some(s) = VehicleStatus::from_step("vehicle_sim", done, &vehicle.state) {
                let sent = status_pub.async_publish(array(h.clone(), s.to_wire()));
                publish_logged(&rt.log, "/vehicle_status", sent).await;
            }
        }
        if clock_due.due(sim) {
            let sent = clock_pub.async_publish(Clock {
                clock: Time::from_secs(sim),
            });
            publish_logged(&rt.log, "/clock", sent).await;
        }
        if odom_due.due(sim) {
            let at = vehicle.state.position.map(f64::from);
            let pose = transform(&h, &p.child_frame_id, at, vehicle.state.yaw);
            let o = odometry(h.clone(), &p.child_frame_id, &vehicle.state);
            publish_logged(&rt.log, "/state_estimation", odom_pub.async_publish(o)).await;
            publish_logged(&rt.log, "/tf", tf_pub.async_publish(tf_message(pose))).await;
        }
        let sensor = vehicle.sensor_position();
        if scan_pub.ready(&rt.log) && scan_due.due(sim, sensor) {
            let pose = Pose::new(sensor, vehicle.state.yaw);
            let points =
                scan(&caster, &p.lidar, &pose, scans).map_err(|e| err(format!("lidar: {e}")))?;
            let mut cloud = points.to_cloud(caster.origin());
            burst.inspect(|b| b.apply(scans, &mut cloud));
            let msg = encode(&cloud, h, &EncodeOptions::default());
            if p.throttle_every > 0 && scans.is_multiple_of(p.throttle_every) {
                let sent = throttle_pub.async_publish(msg.clone());
                publish_logged(&rt.log, "/registered_scan_throttle", sent).await;
            }
            // Counted (and its id logged) only when DDS took it: the demo compares them with the scans merged.
            let sent = scan_pub.write(msg);
            sent_scans += u64::from(publish_logged(&rt.log, "/registered_scan", sent).await);
            scans += 1;
        }
        if pause > 0.0 {
            tokio::time::sleep(Duration::from_secs_f64(pause)).await;
        } else {
            tokio::task::yield_now().await;
        }
    }
    let (working, waiting) = clock.split();
    let acked = ["not all", "all"][usize::from(scan_pub.wait_acks().await)];
    rt.log.info(&format!(
        "stopped after {:.1} simulated s ({working:.1} s driving or turning, {waiting:.1} s waiting for orders) in {:.1} wall s, {sent_scans} scans, {:.1} m driven ({} not taken by DDS; {acked} acknowledged)",
        clock.now(),
        wall0.elapsed().as_secs_f64(),
        vehicle.state.odometer,
        scans - sent_scans
    ));
    Ok(())
}
