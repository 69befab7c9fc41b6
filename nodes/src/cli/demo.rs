//! `skyground demo`: the default mission, as far as the pipeline exists. Every
//! node is a process of its own on one DDS domain, and the bag records it.
//!
//! Today: the airborne prior of the scene is simulated and published
//! (cloud_publisher → cloud_inspector); vehicle_sim drives a ring of
//! way-points around the scene's middle while this process collects its
//! scans; the merged cloud is measured against ground truth before/after.
//! Detection, targets and planning (issues 5–7) will replace the ring.

use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::process::Stdio;
use std::time::{Duration, Instant};

use futures::StreamExt;
use serde_json::json;
use skyground_core::cloud::write_cloud;
use skyground_core::lidar::Caster;
use skyground_core::metrics::completeness_of_cloud;
use skyground_core::vehicle::free_spot;
use skyground_msgs::diagnostic_msgs::DiagnosticArray;
use skyground_msgs::geometry_msgs::PointStamped;
use skyground_msgs::nav_msgs::Odometry;
use skyground_msgs::pointcloud2::decode;
use skyground_msgs::sensor_msgs::PointCloud2;
use tokio::process::{Child, Command};

use super::aerial::survey;
use crate::bag::read_messages;
use crate::runtime::{NodeRuntime, RuntimeError, qos};

/// Demo options.
#[derive(Debug, Clone, clap::Args)]
pub struct DemoArgs {
    /// reference, reference:SEED, or a scene file (.obj, .ply, CityJSON .json).
    #[arg(long, default_value = "reference")]
    pub scene: String,
    /// Output directory (aerial.las, mission.mcap, report.json, logs).
    #[arg(long, default_value = "out/demo")]
    pub out: PathBuf,
    /// Run here even if other network interfaces exist (default: re-run inside
    /// a loopback-only network namespace).
    #[arg(long)]
    pub no_netns: bool,
    /// Wall seconds before giving up on the mission.
    #[arg(long, default_value_t = 300.0)]
    pub timeout: f64,
    /// Simulated seconds per wall second.
    #[arg(long, default_value_t = 10.0)]
    pub time_factor: f64,
    /// Way-points on the ring the vehicle drives to (and back from).
    #[arg(long, default_value_t = 10)]
    pub way_points: usize,
    /// Radius of the ring, m.
    #[arg(long, default_value_t = 45.0)]
    pub radius: f32,
}

struct Proc {
    name: &'static str,
    child: Child,
}

fn start(
    name: &'static str,
    exe: &Path,
    args: &[String],
    out: &Path,
) -> Result<Proc, RuntimeError> {
    let log = std::fs::File::create(out.join(format!("{name}.log")))
        .map_err(|e| RuntimeError::Node(format!("cannot write {}: {e}", out.display())))?;
    let child = Command::new(exe)
        .args(args)
        .stdout(Stdio::null())
        .stderr(log)
        .kill_on_drop(true)
        .spawn()
        .map_err(|e| RuntimeError::Node(format!("cannot start {name}: {e}")))?;
    eprintln!("  started {name}");
    Ok(Proc { name, child })
}

async fn stop(p: &mut Proc) {
    if let Some(pid) = p.child.id() {
        // SIGINT, as ros2 launch does, so nodes shut down in order.
        let _ = std::process::Command::new("kill")
            .args(["-INT", &pid.to_string()])
            .status();
    }
    if tokio::time::timeout(Duration::from_secs(10), p.child.wait())
        .await
        .is_err()
    {
        let _ = p.child.kill().await;
    }
}

fn node_args(name: &str, params: &[String]) -> Vec<String> {
    let mut v = vec![
        "node".to_string(),
        name.to_string(),
        "--ros-args".to_string(),
    ];
    for p in params {
        v.push("-p".into());
        v.push(p.clone());
    }
    v
}

/// Keeps one point per 5 cm voxel.
#[derive(Default)]
struct Voxels {
    seen: HashSet<[i32; 3]>,
    xyz: Vec<[f32; 3]>,
}

impl Voxels {
    fn add(&mut self, p: [f32; 3]) {
        let key = p.map(|v| (v / 0.05).floor() as i32);
        if self.seen.insert(key) {
            self.xyz.push(p);
        }
    }
}

/// Runs the demo mission.
pub async fn run(rt: &mut NodeRuntime, a: DemoArgs) -> Result<(), RuntimeError> {
    let err = |e: String| RuntimeError::Node(e);
    let t0 = Instant::now();
    std::fs::create_dir_all(&a.out).map_err(|e| err(format!("{}: {e}", a.out.display())))?;
    let exe = std::env::current_exe().map_err(|e| err(e.to_string()))?;
    let bag = a.out.join("mission.mcap");
    let _ = std::fs::remove_file(&bag);

    eprintln!(
        "skyground demo: scene {}, output {}",
        a.scene,
        a.out.display()
    );
    let prior = survey(&a.scene, None)?;
    let before = completeness_of_cloud(&prior.gt, &prior.cloud, prior.tau);
    let aerial_path = a.out.join("aerial.las");
    write_cloud(&aerial_path, &prior.cloud).map_err(|e| err(e.to_string()))?;
    eprintln!(
        "  airborne prior: {} points, building completeness {:.2} % ({:.1} s)",
        prior.cloud.len(),
        before.overall.ratio.unwrap_or(0.0) * 100.0,
        t0.elapsed().as_secs_f64()
    );
    let caster = Caster::new(&prior.scene).map_err(|e| err(e.to_string()))?;
    let (lo, hi) = caster.bounds().ok_or_else(|| err("empty scene".into()))?;
    let centre = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
    let start_xy = free_spot(&caster, centre[0], centre[1], 2.0, 100.0)
        .ok_or_else(|| err("no free spot to start the vehicle".into()))?;
    // Without a planner yet, the vehicle drives straight lines: spokes out to
    // the ring and back to the start, so a blocked spoke costs only itself.
    let ring: Vec<[f32; 2]> = (0..a.way_points)
        .filter_map(|k| {
            let ang = k as f32 * std::f32::consts::TAU / a.way_points.max(1) as f32;
            let (x, y) = (
                centre[0] + a.radius * ang.cos(),
                centre[1] + a.radius * ang.sin(),
            );
            free_spot(&caster, x, y, 1.5, 15.0)
        })
        .flat_map(|p| [p, start_xy])
        .collect();

    let mut procs = [
        start(
            "recorder",
            &exe,
            &[
                "record".into(),
                "-o".into(),
                bag.display().to_string(),
                "/aerial_cloud:sensor_msgs/msg/PointCloud2".into(),
                "/cloud_stats:diagnostic_msgs/msg/DiagnosticArray".into(),
                "/state_estimation:nav_msgs/msg/Odometry".into(),
                "/vehicle_status:diagnostic_msgs/msg/DiagnosticArray".into(),
                "/way_point:geometry_msgs/msg/PointStamped".into(),
            ],
            &a.out,
        )?,
        start(
            "cloud_inspector",
            &exe,
            &node_args("cloud_inspector", &["max_clouds:=1".into()]),
            &a.out,
        )?,
        start(
            "cloud_publisher",
            &exe,
            &node_args(
                "cloud_publisher",
                &[
                    format!("file:={}", aerial_path.display()),
                    "wait_for_subscribers:=2".into(),
                ],
            ),
            &a.out,
        )?,
        start(
            "vehicle_sim",
            &exe,
            &node_args(
                "vehicle_sim",
                &[
                    format!("scene:={}", a.scene),
                    format!("start:=[{}, {}]", start_xy[0], start_xy[1]),
                    format!("time_factor:={}", a.time_factor),
                ],
            ),
            &a.out,
        )?,
    ];

    let scans = rt.subscription::<PointCloud2>("/registered_scan", qos::sensor(50))?;
    let status = rt.subscription::<DiagnosticArray>("/vehicle_status", qos::reliable(10))?;
    let odom = rt.subscription::<Odometry>("/state_estimation", qos::sensor(1))?;
    let way = rt.publisher::<PointStamped>("/way_point", qos::reliable(10))?;
    let scan_stream = scans.async_stream();
    let status_stream = status.async_stream();
    let odom_stream = odom.async_stream();
    futures::pin_mut!(scan_stream, status_stream, odom_stream);
    let deadline = tokio::time::Instant::now() + Duration::from_secs_f64(a.timeout);
    let mut merged = Voxels::default();
    let mut n_scans = 0u64;
    let mut reached = 0usize;
    let mut blocked = 0usize;
    let mut driven = 0.0f64;
    let mut sim_s = 0.0f64;
    let mut vehicle_up = false;
    let mut k = 0usize;
    let mut sent = false;
    let mut resend = tokio::time::interval(Duration::from_secs(2));
    let mut ok = false;
    loop {
        if k >= ring.len() {
            ok = true;
            break;
        }
        tokio::select! {
            _ = tokio::time::sleep_until(deadline) => break,
            _ = rt.shutdown.wait() => break,
            Some(Ok((m, _))) = scan_stream.next() => {
                n_scans += 1;
                sim_s = f64::from(m.header.stamp.sec) + f64::from(m.header.stamp.nanosec) * 1e-9;
                if let Ok(d) = decode(&m)
                    && let Some(labels) = d.cloud.label.as_ref()
                {
                    for (p, l) in d.cloud.xyz.iter().zip(labels) {
                        if *l == 6 {
                            merged.add(*p);
                        }
                    }
                }
            }
            Some(Ok((_, _))) = odom_stream.next() => {
                vehicle_up = true;
            }
            Some(Ok((s, _))) = status_stream.next() => {
                for st in &s.status {
                    let value = |key: &str| st.values.iter().find(|v| v.key == key).and_then(|v| v.value.parse::<f64>().ok());
                    let goal = ring.get(k).copied().unwrap_or_default();
                    let is_ours = matches!((value("goal_x"), value("goal_y")), (Some(x), Some(y))
                        if (x as f32 - goal[0]).abs() < 1e-3 && (y as f32 - goal[1]).abs() < 1e-3);
                    if !is_ours {
                        continue;
                    }
                    driven = value("odometer_m").unwrap_or(driven);
                    if st.message == "arrived" { reached += 1 } else { blocked += 1 }
                    eprintln!(
                        "  way-point {}/{} {} — {:.0} m driven, {:.0} sim s, {} scans, {} new building points",
                        k + 1, ring.len(), st.message, driven, sim_s, n_scans, merged.xyz.len()
                    );
                    k += 1;
                    sent = false;
                }
            }
            _ = resend.tick() => {}
        }
        if vehicle_up
            && !sent
            && let Some(g) = ring.get(k)
        {
            let mut m = PointStamped::default();
            m.header.frame_id = "map".into();
            m.point.x = f64::from(g[0]);
            m.point.y = f64::from(g[1]);
            let _ = way.async_publish(m).await;
            sent = true;
        }
    }
    for p in procs.iter_mut().rev() {
        stop(p).await;
        eprintln!("  stopped {}", p.name);
    }

    let mut after_cloud = prior.cloud.clone();
    let n_ground = merged.xyz.len();
    after_cloud.xyz.extend(merged.xyz.iter().copied());
    if let Some(l) = after_cloud.label.as_mut() {
        l.extend(std::iter::repeat_n(6u8, n_ground));
    }
    if let Some(b) = after_cloud.building.as_mut() {
        b.extend(std::iter::repeat_n(0u32, n_ground));
    }
    if let Some(i) = after_cloud.intensity.as_mut() {
        i.extend(std::iter::repeat_n(0.0f32, n_ground));
    }
    let after = completeness_of_cloud(&prior.gt, &after_cloud, prior.tau);
    write_cloud(&a.out.join("resampled.las"), &after_cloud).map_err(|e| err(e.to_string()))?;
    let messages = read_messages(&bag).map_err(|e| err(e.to_string()))?;
    let count = |t: &str| messages.iter().filter(|m| m.topic == t).count();
    let wall = t0.elapsed().as_secs_f64();
    let report = json!({
        "scene": a.scene,
        "coverage_before": before.overall.ratio,
        "coverage_after": after.overall.ratio,
        "walls_before": before.walls.ratio,
        "walls_after": after.walls.ratio,
        "mean_gt_dist_before": before.mean_gt_distance,
        "mean_gt_dist_after": after.mean_gt_distance,
        "path_length_m": driven,
        "sim_time_s": sim_s,
        "wall_time_s": wall,
        "way_points": ring.len(),
        "reached": reached,
        "blocked": blocked,
        "scans": n_scans,
        "ground_points_added": n_ground,
        "bag_messages": messages.len(),
    });
    std::fs::write(a.out.join("report.json"), format!("{report:#}"))
        .map_err(|e| err(e.to_string()))?;
    let pct = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{:.2} %", v * 100.0));
    let m = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.3} m"));
    eprintln!(
        "\n| building completeness (τ = {} m) | before | after |\n|---|---|---|",
        prior.tau
    );
    eprintln!(
        "| all surfaces | {} | {} |",
        pct(before.overall.ratio),
        pct(after.overall.ratio)
    );
    eprintln!(
        "| walls | {} | {} |",
        pct(before.walls.ratio),
        pct(after.walls.ratio)
    );
    eprintln!(
        "| mean GT→cloud distance | {} | {} |",
        m(before.mean_gt_distance),
        m(after.mean_gt_distance)
    );
    eprintln!(
        "\nskyground demo: {} in {wall:.1} s: {reached} way-points reached, {blocked} blocked, {driven:.0} m in {sim_s:.0} sim s, {n_scans} scans; bag {} ({} messages: /aerial_cloud {}, /state_estimation {}); report {}",
        if ok {
            "mission finished"
        } else {
            "mission NOT finished"
        },
        bag.display(),
        messages.len(),
        count("/aerial_cloud"),
        count("/state_estimation"),
        a.out.join("report.json").display()
    );
    if ok && count("/aerial_cloud") > 0 && n_scans > 0 {
        Ok(())
    } else {
        Err(err(format!(
            "the mission did not finish: see the logs in {}",
            a.out.display()
        )))
    }
}
