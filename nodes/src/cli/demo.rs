//! `skyground demo`: the whole sky–ground mission over DDS (docs/design.md steps
//! 1–9). Every node is a process of its own on one domain; this process
//! starts them, watches the mission's topics, closes the loop round by
//! round, stops everything in order and proves the gain against ground
//! truth (report.json, report.md, overview.png; the bag is mission.mcap).

use std::path::{Path, PathBuf};
use std::process::Stdio;
use std::time::{Duration, Instant};

use futures::StreamExt;
use serde_json::json;
use skyground_core::cloud::{Cloud, write_cloud};
use skyground_core::crs::{Crs, LinearUnit, SourceFrame};
use skyground_core::footprint::{Footprint, footprints_of_scene};
use skyground_core::lidar::Caster;
use skyground_core::metrics::{Evaluation, MeasureSoFar, Measured, Mission, compare};
use skyground_core::mission::progress::{Progress, StopRule};
use skyground_core::mission::{BuildingStatus, PlannerStatus, ProtocolError, VehicleStatus, Wire};
use skyground_core::plot::{BuildingGain, mission_picture};
use skyground_core::prior::unlabelled;
use skyground_core::route::{BudgetParams, PlannedWork, WorkLimit};
use skyground_core::scene::{Cropped, Scene, load_scene, load_scene_and_crs, write_obj};
use skyground_core::targets::{TargetPoint, TargetSet};
use skyground_core::vehicle::free_spot;
use skyground_msgs::diagnostic_msgs::DiagnosticArray;
use skyground_msgs::nav_msgs::Odometry;
use skyground_msgs::visualization_msgs::{Marker, MarkerArray};
use tokio::process::{Child, Command};

use super::aerial::survey_of;
use super::city_model::write_completeness;
use super::eval::{markdown, write_json};
use super::merged::{after, merged_cloud};
use super::profile::Profile;
use crate::convert::diagnostics::from_status;
use crate::convert::markers::markers_to_regions;
use crate::convert::path::odom_position;
use crate::runtime::{NodeRuntime, RuntimeError, qos};
use crate::transport::{CloudSubscription, Received};

/// Demo options.
#[derive(Debug, Clone, clap::Args)]
pub struct DemoArgs {
    /// reference, reference:SEED, or a scene file (.obj, .ply, CityJSON .json,
    /// CityJSONSeq .jsonl); city model tiles load as one scene: repeat
    /// --scene, or give a directory or a comma-separated list.
    #[arg(long = "scene", default_value = "reference")]
    pub scenes: Vec<String>,
    /// One cluster of buildings of a large scene (written to OUT/scene.obj,
    /// which every node then loads).
    #[command(flatten)]
    pub crop: super::crop::CropArgs,
    /// A real aerial survey as the prior (`--prior`, `--prior-margin`).
    #[command(flatten)]
    pub prior: super::prior::PriorArgs,
    /// Output directory (aerial.las, resampled.las, mission.mcap, report.*, overview.png, logs).
    #[arg(long, default_value = "out/demo")]
    pub out: PathBuf,
    /// Run here even if other network interfaces exist (default: re-run inside
    /// a loopback-only network namespace).
    #[arg(long)]
    pub no_netns: bool,
    /// Wall seconds before giving up on the mission; default: the limit
    /// follows the work (600 s until the first route is known, then each
    /// round's budget from its length and stops, printed).
    #[arg(long)]
    pub timeout: Option<f64>,
    /// Simulated seconds per wall second while the vehicle drives or turns
    /// (a ceiling: on 2 cores the reference mission's casting holds it near
    /// 20×; waiting for orders always runs at wall speed).
    #[arg(long, default_value_t = 40.0)]
    pub time_factor: f64,
    /// Rounds of detect → plan → drive at most (the paper drives two).
    #[arg(long, default_value_t = 2)]
    pub max_rounds: u32,
    /// A round whose detected completeness gain is below this ends the loop.
    #[arg(long, default_value_t = 0.01)]
    pub min_round_gain: f64,
    /// Set-downs a round may ask for when targets remain on another piece
    /// of ground (vehicle_sim carries the vehicle there; a field team by
    /// hand); default: global_planner's `set_downs` (3); 0: never.
    #[arg(long)]
    pub set_downs: Option<usize>,
    /// Give footprints to the detector: for a CityJSON scene, its own buildings.
    #[arg(long)]
    pub footprints: Option<PathBuf>,
    /// Field mode: a real robot instead of vehicle_sim.
    #[command(flatten)]
    pub field: FieldArgs,
}

/// Field mode: every node but vehicle_sim, and a robot of the CMU
/// exploration environment's interface on the network.
#[derive(Debug, Clone, clap::Args)]
pub struct FieldArgs {
    /// Drive a real robot instead of vehicle_sim: way-points go out on
    /// /way_point (geometry_msgs/PointStamped, one at a time) and the route on
    /// /global_path (nav_msgs/Path); the robot publishes /state_estimation
    /// (nav_msgs/Odometry), /registered_scan (PointCloud2 in the map frame)
    /// and /tf. Runs on the current network (no namespace), with
    /// ROS_DOMAIN_ID and ROS_AUTOMATIC_DISCOVERY_RANGE as set.
    #[arg(long)]
    pub field: bool,
    /// Field mode: seconds to wait for the robot's first /state_estimation.
    #[arg(long, default_value_t = 60.0)]
    pub robot_timeout: f64,
}

impl DemoArgs {
    /// The scene spec every process loads (tiles joined by commas).
    pub fn scene(&self) -> String {
        self.scenes.join(",")
    }
}

struct Proc {
    name: &'static str,
    args: Vec<String>,
    child: Child,
    restarts: u32,
}

fn spawn(name: &str, exe: &Path, args: &[String], out: &Path) -> Result<Child, RuntimeError> {
    // Appended: a respawned node's log follows its predecessor's.
    let log = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(out.join(format!("{name}.log")))
        .map_err(|e| RuntimeError::Node(format!("cannot write {}: {e}", out.display())))?;
    Command::new(exe)
        .args(args)
        .stdout(Stdio::null())
        .stderr(log)
        .kill_on_drop(true)
        .spawn()
        .map_err(|e| RuntimeError::Node(format!("cannot start {name}: {e}")))
}

fn start(
    name: &'static str,
    exe: &Path,
    args: &[String],
    out: &Path,
) -> Result<Proc, RuntimeError> {
    let _ = std::fs::remove_file(out.join(format!("{name}.log")));
    Ok(Proc {
        name,
        args: args.to_vec(),
        child: spawn(name, exe, args, out)?,
        restarts: 0,
    })
}

/// Starts again every node that exited while the mission runs, as ros2
/// launch's `respawn=True` does: nodes take their state from latched topics.
/// A node whose DDS start-up deadlocked exits with
/// [`EXIT_STUCK`](crate::runtime::creation_watch::EXIT_STUCK) for this.
fn respawn(procs: &mut [Proc], exe: &Path, out: &Path) -> Result<(), RuntimeError> {
    for p in procs.iter_mut() {
        if let Ok(Some(status)) = p.child.try_wait() {
            eprintln!("  {} exited ({status}); starting it again", p.name);
            p.restarts += 1;
            p.child = spawn(p.name, exe, &args_for_start(&p.args, p.restarts), out)?;
        }
    }
    Ok(())
}

/// `args` for start `n` (0: the first): a respawned recorder writes split
/// `n` (`mission_1.mcap`, as rosbag2 numbers its splits) rather than
/// truncate what its predecessor wrote.
fn args_for_start(args: &[String], n: u32) -> Vec<String> {
    let mut args = args.to_vec();
    if n > 0
        && let Some(i) = args.iter().position(|a| a == "-o")
        && let Some(path) = args.get_mut(i + 1)
    {
        *path = bag_split(Path::new(path), n).display().to_string();
    }
    args
}

/// Split `n` of the bag at `first` (0: `first` itself).
fn bag_split(first: &Path, n: u32) -> PathBuf {
    if n == 0 {
        return first.to_path_buf();
    }
    let stem = first
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    first.with_file_name(format!("{stem}_{n}.mcap"))
}

/// The bag's size: all its splits.
fn bag_bytes(first: &Path) -> u64 {
    (0..)
        .map_while(|n| std::fs::metadata(bag_split(first, n)).ok())
        .map(|m| m.len())
        .sum()
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

/// Ground-graph parameters for the planner and the explorer. On a real
/// prior or with a real robot a crown blocks only where points stand in the
/// vehicle's height band, not its whole column: a multi-return survey
/// measures the ground under crowns (AHN3 Delft: 43–52 % of points from
/// pulses with several returns; on Delft 1 that joins 1,091 → 3,709
/// reachable nodes) and a real robot steers round the trunks it meets.
/// vehicle_sim on a simulated prior keeps the node's whole-column default:
/// it does not steer round trunks, and the simulated prior cannot show them.
fn graph_params(a: &DemoArgs) -> Vec<String> {
    if a.field.field || !a.prior.files.is_empty() {
        vec!["graph.canopy_is_obstacle:=false".into()]
    } else {
        Vec::new()
    }
}

/// global_planner's parameters from the demo's arguments.
fn planner_params(a: &DemoArgs) -> Vec<String> {
    let mut v = graph_params(a);
    v.extend(a.set_downs.map(|n| format!("set_downs:={n}")));
    v
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

/// Every topic of the mission, as the recorder takes them.
const TOPICS: &[&str] = &[
    "/aerial_cloud:sensor_msgs/msg/PointCloud2",
    "/georeference:diagnostic_msgs/msg/DiagnosticArray",
    "/classified_cloud:sensor_msgs/msg/PointCloud2",
    "/missing_points:sensor_msgs/msg/PointCloud2",
    "/completeness:diagnostic_msgs/msg/DiagnosticArray",
    "/detection_markers:visualization_msgs/msg/MarkerArray",
    "/target_points:sensor_msgs/msg/PointCloud2",
    "/target_regions:visualization_msgs/msg/MarkerArray",
    "/global_path:nav_msgs/msg/Path",
    "/local_path:nav_msgs/msg/Path",
    "/active_region:visualization_msgs/msg/MarkerArray",
    "/planner_status:diagnostic_msgs/msg/DiagnosticArray",
    "/set_down:geometry_msgs/msg/PointStamped",
    "/explorer_status:diagnostic_msgs/msg/DiagnosticArray",
    "/state_estimation:nav_msgs/msg/Odometry",
    "/vehicle_status:diagnostic_msgs/msg/DiagnosticArray",
    "/registered_scan:sensor_msgs/msg/PointCloud2",
    "/resampled_cloud:sensor_msgs/msg/PointCloud2",
    "/clock:rosgraph_msgs/msg/Clock",
    "/tf:tf2_msgs/msg/TFMessage",
    "/tf_static:tf2_msgs/msg/TFMessage",
];

/// vehicle_sim's one scan in 50 (its `throttle_every`), recorded instead of
/// /registered_scan in simulated missions.
const SCANS_THROTTLED: &str = "/registered_scan_throttle:sensor_msgs/msg/PointCloud2";

/// What the demo learns from the topics as the mission runs.
#[derive(Default)]
struct Watch {
    /// Rounds, targets and the loop's verdict (`skyground_core::mission::progress`).
    progress: Progress,
    resampled: Option<Cloud>,
    route: Vec<[f32; 3]>,
    odometer: f64,
    sim_s: f64,
    /// The first /state_estimation stamp (the robot's clock when the mission started).
    first_stamp: Option<f64>,
    targets: TargetSet,
    /// Every detection round and the targets made from it.
    detections: super::detections::Detections,
    /// Nodes started again after they exited, and how often.
    restarts: std::collections::BTreeMap<String, u32>,
}

/// The buildings' statuses on /completeness (unreadable ones said on stderr).
fn building_statuses(arr: &DiagnosticArray) -> Vec<BuildingStatus> {
    arr.status
        .iter()
        .filter_map(|s| readable(BuildingStatus::from_wire(&from_status(s))))
        .collect()
}

/// The detection round and its mean completeness over the buildings detected.
fn mean_completeness(arr: &DiagnosticArray) -> Option<(u32, f64)> {
    let all = building_statuses(arr);
    let vals: Vec<f64> = all
        .iter()
        .filter(|b| b.skipped.is_none())
        .map(|b| 1.0 - f64::from(b.r_missing))
        .collect();
    let round = all.first()?.round;
    (!vals.is_empty()).then(|| (round, vals.iter().sum::<f64>() / vals.len() as f64))
}

/// The array's first status read as a mission status; `None` when it is
/// absent or unreadable (said on stderr).
fn first_status<T>(
    arr: &DiagnosticArray,
    read: fn(&Wire) -> Result<T, ProtocolError>,
) -> Option<T> {
    readable(read(&from_status(arr.status.first()?)))
}

fn readable<T>(r: Result<T, ProtocolError>) -> Option<T> {
    r.map_err(|e| eprintln!("  unreadable status: {e}")).ok()
}

/// Runs the demo mission.
pub async fn run(rt: &mut NodeRuntime, a: DemoArgs) -> Result<(), RuntimeError> {
    let err = |e: String| RuntimeError::Node(e);
    let t0 = Instant::now();
    let mut prof = Profile::new("prior");
    std::fs::create_dir_all(&a.out).map_err(|e| err(format!("{}: {e}", a.out.display())))?;
    let exe = std::env::current_exe().map_err(|e| err(e.to_string()))?;
    let bag = a.out.join("mission.mcap");
    // A former run's bag and its splits (their sizes are summed at the end).
    for n in 0.. {
        if std::fs::remove_file(bag_split(&bag, n)).is_err() {
            break;
        }
    }
    eprintln!(
        "skyground demo: scene {}, output {}",
        a.scene(),
        a.out.display()
    );
    // The model is read once: its CRS is kept, the scene moves into the
    // mission's (or its crop is taken and the whole dropped).
    let (full, model_crs) =
        load_scene_and_crs(&a.scene()).map_err(|e| err(format!("scene {}: {e}", a.scene())))?;
    let (scene_spec, prior, crop) = mission_prior(&a, full, model_crs.as_ref())?;
    // The prior's measurement and models are ready before the mission ends;
    // the merged cloud is measured as its points arrive (report: only the
    // last round's points are left to measure).
    let mut before_so_far = MeasureSoFar::new(&prior.gt, prior.tau);
    before_so_far.add(&prior.scene, &prior.gt, &prior.cloud);
    let before = before_so_far.measured(&prior.gt);
    let mut after_so_far = before_so_far.clone();
    let models_before = {
        let (dir, scene, cloud, spacing) = (
            a.out.clone(),
            prior.scene.clone(),
            prior.cloud.clone(),
            prior.gt.spacing,
        );
        std::thread::spawn(move || {
            super::reconstruct::models_of(&dir, "models_before", &scene, &cloud, spacing)
        })
    };
    let aerial_path = a.out.join("aerial.las");
    // The classifier labels the prior itself: publish it without the simulator's labels.
    write_cloud(&aerial_path, &unlabelled(&prior.cloud)).map_err(|e| err(e.to_string()))?;
    eprintln!(
        "  {}: {} points, building completeness {:.2} % ({:.1} s)",
        if a.prior.files.is_empty() {
            "airborne prior (simulated)"
        } else {
            "real prior"
        },
        prior.cloud.len(),
        before.completeness.overall.ratio.unwrap_or(0.0) * 100.0,
        t0.elapsed().as_secs_f64()
    );
    let driver = if a.field.field {
        field_driver()
    } else {
        sim_driver(
            &prior.scene,
            &scene_spec,
            a.time_factor,
            (!a.prior.files.is_empty()).then_some(&prior.cloud),
        )?
    };

    let mut record_args = vec![
        "record".to_string(),
        "-o".to_string(),
        bag.display().to_string(),
    ];
    // Every topic is in the bag; the LiDAR's at one scan in 50 (one per 5
    // simulated seconds): all of them made a 16 GB bag of the reference run.
    // vehicle_sim sends those on their own topic, so the recorder is not
    // sent the other 49; a real robot's scans are thinned by the recorder.
    record_args.extend(TOPICS.iter().map(|t| (*t).to_string()));
    if a.field.field {
        record_args.extend(["--every".to_string(), "/registered_scan=50".to_string()]);
    } else {
        record_args.retain(|t| !t.starts_with("/registered_scan:"));
        record_args.push(SCANS_THROTTLED.to_string());
    }
    let mut detector_params = vec![];
    if let Some(f) = &a.footprints {
        detector_params.push(format!("footprints:={}", f.display()));
        detector_params.push(format!(
            "origin:=[{}, {}, {}]",
            prior.scene.origin[0], prior.scene.origin[1], prior.scene.origin[2]
        ));
    }
    let mut procs = vec![start("recorder", &exe, &record_args, &a.out)?];
    for (name, params) in [
        ("scene_classifier", vec![]),
        ("completeness_detector", detector_params),
        ("target_generator", vec![]),
        ("global_planner", planner_params(&a)),
        ("local_explorer", graph_params(&a)),
        driver,
        (
            "cloud_publisher",
            vec![format!("file:={}", aerial_path.display())],
        ),
    ] {
        procs.push(start(name, &exe, &node_args(name, &params), &a.out)?);
    }
    prof.stage("start-up, classification, detection, first route");
    eprintln!(
        "  started {} processes: {}",
        procs.len(),
        procs.iter().map(|p| p.name).collect::<Vec<_>>().join(", ")
    );

    let mut resampled_sub =
        CloudSubscription::new(rt, "/resampled_cloud", qos::latched(256), 65536)?;
    let mut targets_sub = CloudSubscription::new(rt, "/target_points", qos::latched(64), 65536)?;
    let completeness = rt.subscription::<DiagnosticArray>("/completeness", qos::latched(1))?;
    let planner = rt.subscription::<DiagnosticArray>("/planner_status", qos::latched(1))?;
    let vstatus = rt.subscription::<DiagnosticArray>("/vehicle_status", qos::reliable(50))?;
    let regions = rt.subscription::<MarkerArray>("/target_regions", qos::latched(1))?;
    let contours = rt.subscription::<MarkerArray>("/detection_markers", qos::latched(1))?;
    let odom = rt.subscription::<Odometry>("/state_estimation", qos::reliable(10))?;
    let (c_s, p_s, v_s, r_s, o_s, m_s) = (
        completeness.async_stream(),
        planner.async_stream(),
        vstatus.async_stream(),
        regions.async_stream(),
        odom.async_stream(),
        contours.async_stream(),
    );
    futures::pin_mut!(c_s, p_s, v_s, r_s, o_s, m_s);
    let mut limit = TimeLimit::new(&a);
    let mut progress = tokio::time::interval(Duration::from_secs(5));
    let mut respawn_tick = tokio::time::interval(Duration::from_millis(500));
    let mut w = Watch::default();
    let rule = StopRule {
        min_round_gain: a.min_round_gain,
        max_rounds: a.max_rounds,
    };
    let robot_deadline =
        tokio::time::Instant::now() + Duration::from_secs_f64(a.field.robot_timeout);
    let mut coverage_now = before.completeness.overall.ratio.unwrap_or(0.0);
    let mut finished = false;
    let mut why = String::from("interrupted");
    loop {
        tokio::select! {
            _ = tokio::time::sleep_until(limit.deadline()) => { why = limit.why(t0); break }
            _ = tokio::time::sleep_until(robot_deadline), if a.field.field && w.first_stamp.is_none() => {
                why = format!("no /state_estimation from a robot within {} s (is it on ROS_DOMAIN_ID {}, and publishing nav_msgs/Odometry there?)", a.field.robot_timeout, rt.domain.domain_id);
                break
            }
            _ = rt.shutdown.wait() => break,
            r = resampled_sub.next() => if let Some(Received::Cloud { decoded, .. }) = r {
                let new = arrived_points(w.resampled.as_ref(), &decoded.cloud, prior.cloud.origin);
                if new.len() == decoded.cloud.len() {
                    after_so_far = before_so_far.clone();
                }
                let (scene, gt, mut so_far) = (prior.scene.clone(), prior.gt.clone(), after_so_far.clone());
                let measured = tokio::task::spawn_blocking(move || {
                    so_far.add(&scene, &gt, &new);
                    so_far
                })
                .await;
                match measured {
                    Ok(m) => {
                        after_so_far = m;
                        coverage_now = after_so_far.measured(&prior.gt).completeness.overall.ratio.unwrap_or(0.0);
                        w.resampled = Some(decoded.cloud);
                    }
                    Err(e) => eprintln!("  measuring /resampled_cloud failed: {e}"),
                }
            },
            r = targets_sub.next() => if let Some(Received::Cloud { decoded, msg }) = r {
                let ids = decoded.cloud.building.clone().unwrap_or_default();
                w.targets.points = decoded.cloud.xyz.iter().enumerate().map(|(i, p)| TargetPoint { xyz: *p, building: ids.get(i).copied().unwrap_or(0) }).collect();
                w.detections.target_points(msg.header.stamp, w.targets.points.clone());
            },
            Some(Ok((arr, _))) = r_s.next() => {
                w.targets.regions = markers_to_regions(&arr).0;
                if let Some(m) = arr.markers.iter().find(|m| m.action == Marker::ADD) {
                    w.detections.target_regions(m.header.stamp, w.targets.regions.clone());
                }
            }
            Some(Ok((arr, _))) = m_s.next() => if let Some(m) = arr.markers.iter().find(|m| m.ns.starts_with(crate::convert::detection::CONTOUR_NS)) {
                w.detections.markers(m.header.stamp, &arr);
            },
            Some(Ok((arr, _))) = c_s.next() => {
                w.detections.completeness(arr.header.stamp, building_statuses(&arr));
                if let Some((round, mean)) = mean_completeness(&arr)
                    && w.progress.detection(round, mean)
                {
                    eprintln!("  detection round {round}: mean detected completeness {:.1} % over {} buildings", mean * 100.0, arr.status.len());
                }
            },
            Some(Ok((arr, _))) = p_s.next() => if let Some(s) = first_status(&arr, PlannerStatus::from_wire) {
                let finished_round = w.progress.planner(&s);
                if s.round > 0 {
                    prof.stage(&match s.phase.as_str() {
                        "driving" | "exploring" | "carrying" => format!("round {} driving", s.round),
                        _ => format!("round {} done: merge, classification, detection, next route", s.round),
                    });
                }
                if matches!(s.phase.as_str(), "driving" | "exploring") {
                    limit.follow(&w, f64::from(s.route_m), s.stops, s.target_regions);
                }
                if let Some(f) = finished_round {
                    eprintln!("  route of round {} done: {} points, {} regions (of them {} given up, blocked); {} left off (seen on the way); {} unreachable; {} set-downs", f.round, f.done.0, f.done.1, f.given_up, f.seen, f.unreachable, f.set_downs);
                }
            },
            Some(Ok((arr, _))) = v_s.next() => if let Some(s) = first_status(&arr, VehicleStatus::from_wire) {
                w.odometer = s.odometer_m;
            },
            Some(Ok((o, h))) = o_s.next() => {
                let _ = h;
                let t = o.header.stamp.secs();
                if w.first_stamp.is_none() && a.field.field {
                    eprintln!("  robot found on /state_estimation after {:.1} s", t0.elapsed().as_secs_f64());
                }
                // A real robot stamps with its clock; the mission's time starts
                // at its first pose (vehicle_sim's clock starts at 0 itself).
                let first = *w.first_stamp.get_or_insert(t);
                w.sim_s = if a.field.field { t - first } else { t };
                if let Some(p) = odom_position(&o)
                    && w.route.last().is_none_or(|q| (q[0] - p[0]).hypot(q[1] - p[1]) > 1.0)
                {
                    w.route.push(p);
                }
            },
            _ = respawn_tick.tick() => if !rt.shutdown.requested() { respawn(&mut procs, &exe, &a.out)? },
            _ = progress.tick() => {
                for p in &procs {
                    prof.sample(p.name, p.child.id());
                }
                prof.sample("demo", Some(std::process::id()));
                eprintln!(
                    "  [{:>5.0} s] round {} {}: targets {}/{} | coverage {:.2} % | {:.0} m driven, {:.0} sim s",
                    t0.elapsed().as_secs_f64(), w.progress.last.round, if w.progress.last.phase.is_empty() { "starting" } else { &w.progress.last.phase },
                    w.progress.done().0 + w.progress.done().1, w.progress.stops(), coverage_now * 100.0, w.odometer, w.sim_s
                );
            }
        }
        // The closed loop: detection after each driven round says whether
        // another is worth it.
        if let Some(v) = w.progress.verdict(&rule) {
            why = v;
            finished = true;
            break;
        }
    }
    eprintln!("  {why}; stopping the nodes");
    prof.stage("stopping the nodes");
    for p in procs.iter_mut().rev() {
        prof.sample(p.name, p.child.id());
        stop(p).await;
    }
    w.restarts = procs
        .iter()
        .map(|p| (p.name.to_string(), p.restarts))
        .filter(|(_, n)| *n > 0)
        .collect();
    let measured = (before, after_so_far.measured(&prior.gt), models_before);
    report(
        &a,
        &prior,
        // The city model's CRS, also when the mission ran on a crop of it.
        (crop.as_ref(), model_crs),
        &w,
        (finished, &why),
        measured,
        (t0, &mut prof),
    )
    .map(|_| ())?;
    if finished {
        Ok(())
    } else {
        Err(err(format!(
            "the mission did not finish ({why}): see the logs in {}",
            a.out.display()
        )))
    }
}

/// The demo's time limit: `--timeout`, or one that follows the work
/// ([`WorkLimit`]): a first allowance until a route is known, then every
/// route the planner makes (each round's, and each new one after the
/// vehicle was blocked) gets the budget of the work it leaves from the
/// moment it is known.
struct TimeLimit {
    start: tokio::time::Instant,
    fixed: Option<f64>,
    limit: WorkLimit,
    params: BudgetParams,
    /// The last round whose budget was printed; routes budgeted so far.
    printed_round: u32,
    routes: usize,
}

/// Wall seconds until the first route is known (prior, classification,
/// detection, targets, graph).
const FIRST_ROUTE_S: f64 = 600.0;

impl TimeLimit {
    fn new(a: &DemoArgs) -> Self {
        Self {
            start: tokio::time::Instant::now(),
            fixed: a.timeout,
            limit: WorkLimit::new(a.timeout.unwrap_or(FIRST_ROUTE_S)),
            params: BudgetParams {
                time_factor: a.time_factor,
                ..BudgetParams::default()
            },
            printed_round: 0,
            routes: 0,
        }
    }

    fn deadline(&self) -> tokio::time::Instant {
        self.start + Duration::from_secs_f64(self.limit.deadline_s())
    }

    /// Budgets the planner's route (`route_m` over `stops` stops) when it is a new one.
    fn follow(&mut self, w: &Watch, route_m: f64, stops: usize, regions: usize) {
        if self.fixed.is_some() || !route_m.is_finite() {
            return;
        }
        // The route's regions: the round's not yet explored nor unreachable.
        let regions_left = regions
            .saturating_sub(w.progress.done().1 + w.progress.last.unreachable_regions)
            .min(stops);
        let perimeters: Vec<f64> = w
            .targets
            .regions
            .iter()
            .map(|r| perimeter(&r.polygon))
            .collect();
        let mean = perimeters.iter().sum::<f64>() / perimeters.len().max(1) as f64;
        let work = PlannedWork {
            round: w.progress.last.round,
            route_m,
            points: stops - regions_left,
            region_perimeters_m: &vec![mean; regions_left],
        };
        let now = self.start.elapsed().as_secs_f64();
        let Some(b) = self.limit.follow(now, &work, &self.params) else {
            return;
        };
        self.routes += 1;
        if w.progress.last.round > self.printed_round {
            self.printed_round = w.progress.last.round;
            eprintln!(
                "  round {}: {route_m:.0} m over {} points and {regions_left} regions ≈ {:.0} simulated s; time limit {:.0} wall s from now, extended by each new route (--timeout fixes one)",
                w.progress.last.round,
                work.points,
                b.sim_s,
                self.limit.deadline_s() - now
            );
        }
    }

    fn why(&self, t0: Instant) -> String {
        match self.fixed {
            Some(s) => format!("timed out after {s} s (--timeout)"),
            None if self.routes == 0 => format!(
                "no route within {FIRST_ROUTE_S:.0} s (global_planner.log names the inputs it waited for)"
            ),
            None => format!(
                "timed out after {:.0} s: the work of round {} took longer than its budget ({} routes budgeted)",
                t0.elapsed().as_secs_f64(),
                self.printed_round,
                self.routes
            ),
        }
    }
}

/// Length of a closed polygon's outline, metres.
fn perimeter(ring: &[[f64; 2]]) -> f64 {
    ring.iter()
        .zip(ring.iter().cycle().skip(1))
        .map(|(a, b)| (b[0] - a[0]).hypot(b[1] - a[1]))
        .sum()
}

/// The mission's scene and prior: the simulated airborne survey of
/// [`mission_scene`], or the real survey of `--prior` over the city model.
fn mission_prior(
    a: &DemoArgs,
    full: Scene,
    model_crs: Option<&Crs>,
) -> Result<(String, super::aerial::Survey, Option<Cropped>), RuntimeError> {
    if !a.prior.files.is_empty() {
        return super::prior::real_prior(a, full, model_crs);
    }
    let (scene_spec, scene, crop) = mission_scene(a, full, model_crs)?;
    let mut prior = survey_of(scene, &scene_spec, None)?;
    // The city model's CRS, also when the mission runs on a crop of it
    // (written as OBJ, which names none).
    prior.cloud.crs = model_crs.cloned();
    Ok((scene_spec, prior, crop))
}

/// vehicle_sim and its parameters: the simulated robot, started at the free
/// spot nearest the scene's middle, or on a real prior's largest ground.
fn sim_driver(
    scene: &Scene,
    scene_spec: &str,
    time_factor: f64,
    real_prior: Option<&Cloud>,
) -> Result<(&'static str, Vec<String>), RuntimeError> {
    let err = |e: String| RuntimeError::Node(e);
    let caster = Caster::new(scene).map_err(|e| err(e.to_string()))?;
    let start_xy = match real_prior {
        Some(cloud) => super::prior::start_on_prior(&caster, cloud)?,
        None => {
            let (lo, hi) = caster.bounds().ok_or_else(|| err("empty scene".into()))?;
            let centre = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
            free_spot(&caster, centre[0], centre[1], 2.0, 100.0)
                .ok_or_else(|| err("no free spot to start the vehicle".into()))?
        }
    };
    Ok((
        "vehicle_sim",
        vec![
            format!("scene:={scene_spec}"),
            format!("start:=[{}, {}]", start_xy[0], start_xy[1]),
            format!("time_factor:={time_factor}"),
        ],
    ))
}

/// Field mode's robot_bridge in vehicle_sim's place: the robot is wherever
/// it is, and the planners start from its first pose.
fn field_driver() -> (&'static str, Vec<String>) {
    eprintln!(
        "  field mode: no vehicle_sim; way-points on /way_point and /global_path, waiting for the robot on /state_estimation, /registered_scan, /tf"
    );
    eprintln!(
        "  ground graph: tree crowns block only where points stand in the vehicle's height band (the robot steers round trunks itself)"
    );
    ("robot_bridge", vec![])
}

/// The scene every process of the mission loads (its spec and the scene as
/// they will read it): `--scene` itself, or its crop written to
/// OUT/scene.obj (`--crop`; automatic when the scene is too large for the
/// ground graph).
pub(super) fn mission_scene(
    a: &DemoArgs,
    full: Scene,
    model_crs: Option<&Crs>,
) -> Result<(String, Scene, Option<Cropped>), RuntimeError> {
    let err = |e: String| RuntimeError::Node(e);
    let Some(c) = super::crop::apply(&full, &a.scene(), &a.crop)? else {
        // Uncropped yet too large: only `--crop none` gets here.
        if let Some(why) = super::crop::too_large(&full) {
            return Err(err(format!(
                "scene {}: {why}; run on one cluster of buildings: --crop auto (the {} m window with the most building surface, --crop-size) or --crop x0,y0,x1,y1",
                a.scene(),
                a.crop.crop_size
            )));
        }
        return Ok((a.scene(), full, None));
    };
    let path = a.out.join("scene.obj");
    write_obj(&c.scene, &path).map_err(|e| err(e.to_string()))?;
    eprintln!(
        "  {}; written to {}",
        super::crop::describe(&c, model_crs),
        path.display()
    );
    let spec = path.display().to_string();
    // Read back, not c.scene: the file picks its own local frame, and the
    // survey must be in the frame vehicle_sim will load.
    let scene = load_scene(&spec).map_err(|e| err(format!("scene {spec}: {e}")))?;
    Ok((spec, scene, Some(c)))
}

/// The prior's models, made in the background while the mission runs.
type ModelsBefore =
    std::thread::JoinHandle<Result<skyground_core::reconstruct::ModelEvaluation, RuntimeError>>;

/// The points of `now` (the whole resampled cloud so far) that `before` did
/// not have: the explorer only appends, so `before` is a prefix unless the
/// explorer started again (then all of `now`). The nodes work in the
/// prior's frame (`origin`); a decoded message does not carry it.
fn arrived_points(before: Option<&Cloud>, now: &Cloud, origin: [f64; 3]) -> Cloud {
    let kept = before
        .filter(|b| now.xyz.get(..b.len()) == Some(&b.xyz[..]))
        .map_or(0, Cloud::len);
    // Positions only, copied once (not the whole 15 M-point cloud then
    // drained): every resampled point is a building point, and
    // building_points keeps all of an unlabelled cloud.
    let mut c = Cloud::from_xyz(now.xyz[kept..].to_vec());
    c.origin = origin;
    c
}

/// Measures, writes report.json / report.md / overview.png and resampled.las.
fn report(
    a: &DemoArgs,
    prior: &super::aerial::Survey,
    (crop, model_crs): (Option<&Cropped>, Option<Crs>),
    w: &Watch,
    (finished, why): (bool, &str),
    (before, after_m, models_before): (Measured, Measured, ModelsBefore),
    (t0, prof): (Instant, &mut Profile),
) -> Result<Evaluation, RuntimeError> {
    let err = |e: String| RuntimeError::Node(e);
    let scans = w.resampled.as_ref().map_or(0, Cloud::len);
    let e = compare(prior.tau, prior.gt.len(), before, after_m);
    let mission = Mission {
        targets: &w.targets,
        rounds: w.progress.rounds_driven(),
    };
    let city = write_completeness(
        &a.out,
        &a.scene(),
        &prior.scene,
        crop,
        &e,
        prior.gt.spacing,
        Some(mission),
    )?;
    // Step 10: LoD2 models from the prior and from the merged cloud. (Made
    // beside the last round's detection instead, the two took longer
    // together than one after the other on 2 cores: 24.9 s against 21.)
    prof.stage("report: resampled.las beside the LoD2 models after");
    let merged = merged_cloud(&prior.cloud, w.resampled.as_ref());
    let (written, ma) = after(&a.out, &prior.scene, &merged, prior.gt.spacing);
    written.map_err(err)?;
    let ma = ma?;
    prof.stage("report: LoD2 models before (made during the mission)");
    let mb = models_before
        .join()
        .map_err(|_| err("the prior's models panicked".into()))??;
    let pictured =
        super::reconstruct::write_picture(&a.out.join("models.png"), &prior.scene, &mb, &ma, 3)?;
    let verdict =
        skyground_core::reconstruct::compare(&mb, &ma, skyground_core::reconstruct::PRIOR_OFF_M);
    prof.stage("report: tables, pictures, GeoJSON");
    let bag_bytes = bag_bytes(&a.out.join("mission.mcap"));
    let wall = t0.elapsed().as_secs_f64();
    let mut value = json!({
        "scene": a.scene(),
        "mode": if a.field.field { "field" } else { "simulated" },
        // The figures count ground points against this scene's buildings: in
        // field mode they mean something only if the robot drove in this scene.
        "ground_truth": format!("building surfaces of the scene {}", a.scene()),
        "prior": a.prior.describe(),
        "crop": crop.map(|c| super::crop::to_json(c, model_crs.as_ref())),
        "finished": finished,
        "ended_because": why,
        "coverage_before": e.before.completeness.overall.ratio,
        "coverage_after": e.after.completeness.overall.ratio,
        "walls_before": e.before.completeness.walls.ratio,
        "walls_after": e.after.completeness.walls.ratio,
        "roofs_before": e.before.completeness.roofs.ratio,
        "roofs_after": e.after.completeness.roofs.ratio,
        "mean_gt_dist_before": e.before.completeness.mean_gt_distance,
        "mean_gt_dist_after": e.after.completeness.mean_gt_distance,
        "mean_cloud_to_mesh_before": e.before.mean_cloud_to_mesh,
        "mean_cloud_to_mesh_after": e.after.mean_cloud_to_mesh,
        "path_length_m": w.odometer,
        "sim_time_s": w.sim_s,
        "wall_time_s": wall,
        "rounds": w.progress.rounds_driven(),
        "detected_completeness_by_round": w.progress.detected,
        "targets_reached": w.progress.totals.reached,
        "targets_given_up": w.progress.totals.given_up,
        "targets_seen_on_the_way": w.progress.totals.seen,
        "targets_unreachable": w.progress.totals.unreachable,
        "set_downs": w.progress.totals.set_downs,
        "last_route": {"greedy_m": f64::from(w.progress.last.greedy_m), "tsp_m": f64::from(w.progress.last.tsp_m)},
        "ground_points_added": scans,
        "bag_bytes": bag_bytes,
        "restarts": w.restarts,
        "buildings": e.buildings,
        "model_dist_before": mb.distance.mean,
        "model_dist_after": ma.distance.mean,
        "models_before": mb,
        "models_after": ma,
        "models_pictured": pictured,
        "models_compared": verdict,
    });
    let title = match crop {
        Some(c) => format!(
            "skyground demo: {}, crop {} ({} of {} buildings)",
            a.scene(),
            c.window,
            c.buildings.len(),
            c.buildings_total
        ),
        None => format!("skyground demo: {}", a.scene()),
    };
    let mut md = markdown(&e, &title);
    md.push_str(&format!(
        "\n## Mission\n\n| | |\n|---|---|\n| prior | {} |\n| finished | {finished} ({why}) |\n| rounds | {} |\n| targets reached / given up (blocked) / left off (seen on the way) / unreachable | {} / {} / {} / {} |\n| set-downs (the robot carried to another piece of ground) | {} |\n| metres driven | {:.0} |\n| {} seconds | {:.0} |\n| wall seconds | {wall:.1} |\n| ground points added | {scans} |\n",
        a.prior.describe(), w.progress.rounds_driven(), w.progress.totals.reached, w.progress.totals.given_up, w.progress.totals.seen, w.progress.totals.unreachable, w.progress.totals.set_downs, w.odometer,
        if a.field.field { "robot (odometry stamps)" } else { "simulated" }, w.sim_s
    ));
    if a.field.field {
        md.push_str(&format!(
            "\nField mode: a robot, not vehicle_sim, drove. Coverage counts its scans against the building surfaces of {}; the figures hold only where the robot drove in that scene.\n",
            a.scene()
        ));
    }
    md.push_str(&format!(
        "\n## Building models (LoD2) before and after\n\nMean symmetric surface distance to the true buildings (m), RMSE, 95th percentile, roof error (true roof → model roof), footprint IoU; `models_before.city.json`, `models_after.city.json`. `models.png`: buildings {pictured:?} (rows), before left, after right, model surface coloured by distance to the truth, 0 m blue → 0.5 m red (colour bar ticks 0, 0.25, 0.5 m); scale bar 10 m; north up.\n\n{}",
        super::reconstruct::table(&mb, Some(&ma))
    ));
    md.push_str(&format!("\n{}", super::reconstruct::verdict_md(&verdict)));
    if let Some(c) = crop {
        md.push_str(&super::crop::markdown(c));
    }
    let outlines = footprints_of_scene(&prior.scene);
    write_overview(&a.out.join("overview.png"), prior, &outlines, &e, w)?;
    write_field_outputs(&a.out, prior, model_crs, &outlines, &e, w)?;
    // Where the time went, up to here (the process figures were read as
    // each node was asked to stop).
    prof.sample("demo", Some(std::process::id()));
    value["profile"] = prof.to_json();
    md.push_str(&format!(
        "\n## Profile\n\nWall seconds per stage; CPU seconds and peak resident memory per process (read from /proc every 5 s and when the node was asked to stop).\n\n{}",
        prof.to_markdown()
    ));
    write_json(&a.out.join("report.json"), &value)?;
    std::fs::write(a.out.join("report.md"), md).map_err(|e| err(e.to_string()))?;
    let pct = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{:.2} %", v * 100.0));
    eprintln!(
        "\nskyground demo: {} in {wall:.1} s — coverage {} → {}, mean GT distance {:.3} → {:.3} m, {} rounds, {:.0} m driven; report {}",
        if finished {
            "mission finished"
        } else {
            "mission NOT finished"
        },
        pct(e.before.completeness.overall.ratio),
        pct(e.after.completeness.overall.ratio),
        e.before.completeness.mean_gt_distance.unwrap_or(f64::NAN),
        e.after.completeness.mean_gt_distance.unwrap_or(f64::NAN),
        w.progress.rounds_driven(),
        w.odometer,
        a.out.join("report.json").display()
    );
    eprintln!(
        "  per-building figures in the city model: {}",
        city.display()
    );
    Ok(e)
}

/// Each building's coverage gain, for the overview picture.
fn building_gains(outlines: &[Footprint], e: &Evaluation) -> Vec<BuildingGain> {
    outlines
        .iter()
        .map(|f| {
            let row = e.buildings.iter().find(|r| r.building == f.id);
            let gain = row.map_or(0.0, |r| {
                r.coverage_after.unwrap_or(0.0) - r.coverage_before.unwrap_or(0.0)
            });
            BuildingGain {
                outline: f.polygon.clone(),
                gain,
            }
        })
        .collect()
}

/// overview.png: the buildings coloured by their gain, the route driven and
/// the targets (legend, scale bar, north).
fn write_overview(
    path: &Path,
    prior: &super::aerial::Survey,
    outlines: &[Footprint],
    e: &Evaluation,
    w: &Watch,
) -> Result<(), RuntimeError> {
    let Some((lo, hi)) = prior.cloud.bounds() else {
        return Ok(());
    };
    let bounds = (
        [f64::from(lo[0]), f64::from(lo[1])],
        [f64::from(hi[0]), f64::from(hi[1])],
    );
    mission_picture(
        bounds,
        &building_gains(outlines, e),
        0.25,
        &w.route,
        &w.targets,
        2000,
        &LinearUnit::Metre,
    )
    .and_then(|c| c.save(path))
    .map_err(|e| RuntimeError::Node(e.to_string()))
}

/// What a field team takes away, in the model's CRS: the route driven and
/// each building's detection and completeness before and after
/// ([`super::field::write_mission`]).
fn write_field_outputs(
    out: &Path,
    prior: &super::aerial::Survey,
    model_crs: Option<Crs>,
    outlines: &[Footprint],
    e: &Evaluation,
    w: &Watch,
) -> Result<(), RuntimeError> {
    let frame = SourceFrame::new(prior.cloud.origin, model_crs);
    let detected = w.detections.rows(outlines);
    let rows: Vec<super::field::MissionBuilding> = outlines
        .iter()
        .zip(detected)
        .map(|(f, detected)| {
            let row = e.buildings.iter().find(|r| r.building == f.id);
            super::field::MissionBuilding {
                building: f.id,
                outline: &f.polygon,
                detected,
                before_after: (
                    row.and_then(|r| r.coverage_before),
                    row.and_then(|r| r.coverage_after),
                ),
            }
        })
        .collect();
    super::field::write_mission(out, &frame, &rows, &w.route, w.odometer)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use skyground_core::cloud::class;

    fn cloud(n: usize) -> Cloud {
        let mut c = Cloud::from_xyz((0..n).map(|i| [i as f32, 0.0, 0.0]).collect());
        c.label = Some(vec![class::BUILDING; n]);
        c
    }

    #[test]
    fn a_respawned_recorder_writes_the_next_split_and_the_size_counts_them_all() {
        let args: Vec<String> = ["record", "-o", "/m/mission.mcap", "/tf"]
            .iter()
            .map(|s| (*s).to_string())
            .collect();
        assert_eq!(args_for_start(&args, 0), args);
        assert_eq!(args_for_start(&args, 2)[2], "/m/mission_2.mcap");
        let other = vec!["vehicle_sim".to_string()];
        assert_eq!(args_for_start(&other, 3), other);
        let dir = std::env::temp_dir().join(format!("skyground-splits-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let first = dir.join("mission.mcap");
        assert_eq!(bag_bytes(&first), 0);
        std::fs::write(&first, [0u8; 5]).unwrap();
        std::fs::write(bag_split(&first, 1), [0u8; 7]).unwrap();
        assert_eq!(bag_bytes(&first), 12);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn only_the_appended_points_are_new() {
        let (old, now) = (cloud(3), cloud(5));
        let new = arrived_points(Some(&old), &now, [7.0, 8.0, 9.0]);
        assert_eq!(new.xyz, vec![[3.0, 0.0, 0.0], [4.0, 0.0, 0.0]]);
        assert_eq!(new.label, None);
        // In the prior's frame, whatever the decoded message said.
        assert_eq!(new.origin, [7.0, 8.0, 9.0]);
        assert_eq!(arrived_points(None, &now, [0.0; 3]).len(), 5);
    }

    fn demo_args(args: &[&str]) -> DemoArgs {
        #[derive(clap::Parser)]
        struct Cli {
            #[command(flatten)]
            demo: DemoArgs,
        }
        let argv = std::iter::once("demo").chain(args.iter().copied());
        <Cli as clap::Parser>::try_parse_from(argv)
            .expect("demo arguments")
            .demo
    }

    #[test]
    fn crowns_block_their_whole_column_only_for_vehicle_sim_on_a_simulated_prior() {
        let band = vec!["graph.canopy_is_obstacle:=false".to_string()];
        assert!(graph_params(&demo_args(&[])).is_empty());
        assert_eq!(graph_params(&demo_args(&["--field"])), band);
        assert_eq!(graph_params(&demo_args(&["--prior", "a.laz"])), band);
        let planner = planner_params(&demo_args(&["--field", "--set-downs", "0"]));
        assert_eq!(planner, [band[0].clone(), "set_downs:=0".to_string()]);
    }

    #[test]
    fn a_restarted_explorer_sends_all_points_again() {
        let mut now = cloud(5);
        now.xyz[1][2] = 9.0;
        assert_eq!(arrived_points(Some(&cloud(3)), &now, [0.0; 3]).len(), 5);
        assert_eq!(
            arrived_points(Some(&cloud(6)), &cloud(5), [0.0; 3]).len(),
            5
        );
    }
}
