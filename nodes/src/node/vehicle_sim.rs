//! vehicle_sim: /way_point and paths (/local_path by default) → a simulated ground
//! vehicle with a spinning LiDAR → /state_estimation, /registered_scan, /clock,
//! /vehicle_status, /tf (map → base_link) and /tf_static (base_link → sensor).
//! Simulated time runs `time_factor` times faster than wall time.

use std::time::{Duration, Instant};

use futures::StreamExt;
use serde::Deserialize;
use skyground_core::lidar::{Caster, LidarConfig, Pose, scan};
use skyground_core::scene::load_scene;
use skyground_core::vehicle::{Step, Vehicle, VehicleConfig, free_spot};
use skyground_msgs::builtin_interfaces::Time;
use skyground_msgs::diagnostic_msgs::{DiagnosticArray, DiagnosticStatus, KeyValue};
use skyground_msgs::geometry_msgs::PointStamped;
use skyground_msgs::nav_msgs::{Odometry, Path};
use skyground_msgs::pointcloud2::{EncodeOptions, encode};
use skyground_msgs::rosgraph_msgs::Clock;
use skyground_msgs::sensor_msgs::PointCloud2;
use skyground_msgs::std_msgs::Header;
use skyground_msgs::tf2_msgs::TFMessage;
use tokio::sync::mpsc;

use crate::convert::tf::{tf_message, transform, yaw_quaternion};
use crate::runtime::{NodeRuntime, NodeSpec, RuntimeError, qos};

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
    vehicle: VehicleConfig,
    lidar: LidarConfig,
}

/// Name and default params.
pub const SPEC: NodeSpec = NodeSpec {
    name: "vehicle_sim",
    default_params: include_str!("../../../config/vehicle_sim.yaml"),
    live: &[],
};

enum Command {
    Goal([f32; 2]),
    Path(Vec<[f32; 2]>),
}

fn stamp(sim_s: f64) -> Time {
    Time {
        sec: sim_s.floor() as i32,
        nanosec: ((sim_s - sim_s.floor()) * 1e9) as u32,
    }
}

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
    let (lo, hi) = caster
        .bounds()
        .ok_or_else(|| err("the scene is empty".into()))?;
    let start = match p.start.as_slice() {
        [x, y] => [*x as f32, *y as f32],
        [] => free_spot(
            &caster,
            (lo[0] + hi[0]) / 2.0,
            (lo[1] + hi[1]) / 2.0,
            2.0,
            100.0,
        )
        .ok_or_else(|| err("no free spot to start from".into()))?,
        other => return Err(err(format!("start must be [x, y] or [], not {other:?}"))),
    };
    let mut vehicle = Vehicle::new(p.vehicle, &caster, start[0], start[1], p.start_yaw as f32)
        .ok_or_else(|| err(format!("start {start:?} is off the terrain")))?;
    rt.log.info(&format!(
        "scene {}: {} triangles, loaded in {:.2} s; vehicle at ({:.1}, {:.1}, {:.1}); time factor {}",
        p.scene,
        caster.triangle_count(),
        t_load.elapsed().as_secs_f64(),
        vehicle.state.position[0],
        vehicle.state.position[1],
        vehicle.state.position[2],
        p.time_factor
    ));

    let odom_pub = rt.publisher::<Odometry>("/state_estimation", qos::reliable(10))?;
    let scan_pub = rt.publisher::<PointCloud2>("/registered_scan", qos::sensor(5))?;
    let clock_pub = rt.publisher::<Clock>("/clock", qos::sensor(1))?;
    let status_pub = rt.publisher::<DiagnosticArray>("/vehicle_status", qos::reliable(10))?;
    // As tf2's broadcasters: /tf reliable and volatile, /tf_static latched.
    let tf_pub = rt.publisher::<TFMessage>("/tf", qos::reliable(100))?;
    let tf_static_pub = rt.publisher::<TFMessage>("/tf_static", qos::latched(1))?;
    let sensor_mount = transform(
        &Header {
            stamp: stamp(0.0),
            frame_id: p.child_frame_id.clone(),
        },
        &p.sensor_frame_id,
        [0.0, 0.0, f64::from(p.vehicle.sensor_height)],
        0.0,
    );
    let _ = tf_static_pub.async_publish(tf_message(sensor_mount)).await;
    let (tx, mut rx) = mpsc::channel::<Command>(16);
    let way = rt.subscription::<PointStamped>("/way_point", qos::reliable(10))?;
    let mut paths = Vec::new();
    for topic in &p.path_topics {
        // A latched route (/global_path) is read as latched; legs as they come.
        let q = if topic == "/global_path" {
            qos::latched(1)
        } else {
            qos::reliable(10)
        };
        paths.push((rt.subscription::<Path>(topic, q)?, topic.clone()));
    }
    let log = rt.log.clone();
    let t = tx.clone();
    let l = log.clone();
    tokio::spawn(async move {
        let s = way.async_stream();
        futures::pin_mut!(s);
        while let Some(m) = s.next().await {
            match m {
                Ok((m, _)) => {
                    let _ = t
                        .send(Command::Goal([m.point.x as f32, m.point.y as f32]))
                        .await;
                }
                Err(e) => l.error(&format!("/way_point: unreadable message: {e}")),
            }
        }
    });
    for (sub, name) in paths {
        let t = tx.clone();
        let l = log.clone();
        tokio::spawn(async move {
            let s = sub.async_stream();
            futures::pin_mut!(s);
            while let Some(m) = s.next().await {
                match m {
                    Ok((m, _)) => {
                        let pts = m
                            .poses
                            .iter()
                            .map(|ps| [ps.pose.position.x as f32, ps.pose.position.y as f32]);
                        let _ = t.send(Command::Path(pts.collect())).await;
                    }
                    Err(e) => l.error(&format!("{name}: unreadable message: {e}")),
                }
            }
        });
    }

    let lidar_period = 1.0 / f64::from(p.lidar.rate_hz).max(1e-3);
    let odom_period = 1.0 / p.odom_rate_hz.max(1e-3);
    let clock_period = 1.0 / p.clock_rate_hz.max(1e-3);
    let (mut next_scan, mut next_odom, mut next_clock) = (0.0f64, 0.0f64, 0.0f64);
    let mut sim = 0.0f64;
    let mut scans = 0u64;
    // Where and when the last scan was cast.
    let mut last_scan_at: Option<([f32; 3], f64)> = None;
    let wall0 = Instant::now();
    while !rt.shutdown.requested() {
        while let Ok(cmd) = rx.try_recv() {
            match cmd {
                Command::Goal(g) => {
                    rt.log
                        .info(&format!("way-point ({:.1}, {:.1})", g[0], g[1]));
                    vehicle.set_goal(g);
                }
                Command::Path(pts) => {
                    rt.log.info(&format!("path of {} pose(s)", pts.len()));
                    vehicle.set_path(pts);
                }
            }
        }
        let step = vehicle.step(&caster, p.step_s as f32);
        sim += p.step_s;
        let status = match &step {
            Step::Blocked { goal, reason } => {
                rt.log.warn(&format!(
                    "blocked going to ({:.1}, {:.1}): {reason}",
                    goal[0], goal[1]
                ));
                Some((DiagnosticStatus::WARN, format!("blocked: {reason}"), *goal))
            }
            Step::Arrived(goal) => Some((DiagnosticStatus::OK, "arrived".to_string(), *goal)),
            _ => None,
        };
        if let Some((level, message, goal)) = status {
            let s = &vehicle.state;
            let report = DiagnosticArray {
                header: Header {
                    stamp: stamp(sim),
                    frame_id: p.frame_id.clone(),
                },
                status: vec![DiagnosticStatus {
                    level,
                    name: "vehicle_sim".into(),
                    message,
                    hardware_id: String::new(),
                    values: vec![
                        KeyValue {
                            key: "goal_x".into(),
                            value: goal[0].to_string(),
                        },
                        KeyValue {
                            key: "goal_y".into(),
                            value: goal[1].to_string(),
                        },
                        KeyValue {
                            key: "x".into(),
                            value: s.position[0].to_string(),
                        },
                        KeyValue {
                            key: "y".into(),
                            value: s.position[1].to_string(),
                        },
                        KeyValue {
                            key: "odometer_m".into(),
                            value: s.odometer.to_string(),
                        },
                    ],
                }],
            };
            let _ = status_pub.async_publish(report).await;
        }
        if sim >= next_clock {
            next_clock += clock_period;
            let _ = clock_pub.async_publish(Clock { clock: stamp(sim) }).await;
        }
        if sim >= next_odom {
            next_odom += odom_period;
            let s = &vehicle.state;
            let mut o = Odometry {
                header: Header {
                    stamp: stamp(sim),
                    frame_id: p.frame_id.clone(),
                },
                child_frame_id: p.child_frame_id.clone(),
                ..Odometry::default()
            };
            o.pose.pose.position.x = f64::from(s.position[0]);
            o.pose.pose.position.y = f64::from(s.position[1]);
            o.pose.pose.position.z = f64::from(s.position[2]);
            o.pose.pose.orientation = yaw_quaternion(s.yaw);
            o.twist.twist.linear.x = f64::from(s.speed);
            o.twist.twist.angular.z = f64::from(s.yaw_rate);
            let pose = transform(
                &o.header,
                &p.child_frame_id,
                [
                    o.pose.pose.position.x,
                    o.pose.pose.position.y,
                    o.pose.pose.position.z,
                ],
                s.yaw,
            );
            let _ = odom_pub.async_publish(o).await;
            let _ = tf_pub.async_publish(tf_message(pose)).await;
        }
        let scan_due = sim >= next_scan;
        if scan_due {
            next_scan += lidar_period;
        }
        let sensor = vehicle.sensor_position();
        // A 360° sensor that has not moved sees what it saw: a vehicle
        // standing or turning on the spot casts a scan only now and then.
        let moved = |(q, t): ([f32; 3], f64)| {
            let d: f32 = (0..3).map(|k| (sensor[k] - q[k]).powi(2)).sum();
            f64::from(d.sqrt()) >= p.scan_min_move_m || sim - t >= p.stationary_scan_period_s
        };
        if scan_due && last_scan_at.is_none_or(moved) {
            last_scan_at = Some((sensor, sim));
            let pose = Pose::new(sensor, vehicle.state.yaw);
            match scan(&caster, &p.lidar, &pose, scans) {
                Ok(points) => {
                    let header = Header {
                        stamp: stamp(sim),
                        frame_id: p.frame_id.clone(),
                    };
                    let msg = encode(
                        &points.to_cloud(caster.origin()),
                        header,
                        &EncodeOptions::default(),
                    );
                    let _ = scan_pub.async_publish(msg).await;
                    scans += 1;
                }
                Err(e) => return Err(err(format!("lidar: {e}"))),
            }
        }
        // Keep simulated time `time_factor` ahead of wall time, never behind.
        let due = Duration::from_secs_f64(sim / p.time_factor);
        let now = wall0.elapsed();
        if due > now {
            tokio::time::sleep(due - now).await;
        } else {
            tokio::task::yield_now().await;
        }
    }
    rt.log.info(&format!(
        "stopped after {sim:.1} simulated s in {:.1} wall s, {scans} scans, {:.1} m driven",
        wall0.elapsed().as_secs_f64(),
        vehicle.state.odometer
    ));
    Ok(())
}
