//! Launching: the mission's processes, their arguments, respawn and the
//! orderly stop (as ros2 launch does with `respawn=True` and SIGINT).

use std::path::{Path, PathBuf};
use std::process::Stdio;
use std::time::Duration;

use skyground_core::cloud::Cloud;
use skyground_core::lidar::Caster;
use skyground_core::scene::Scene;
use skyground_core::vehicle::find_start;
use tokio::process::{Child, Command};

use super::DemoArgs;
use super::resume::Carried;
use crate::cli::profile::Profile;
use crate::runtime::RuntimeError;

/// One node of the mission, as a child process.
pub(super) struct Proc {
    pub name: &'static str,
    args: Vec<String>,
    pub child: Child,
    pub restarts: u32,
    /// Starts made by earlier runs of a resumed mission (the recorder's bag splits).
    earlier: u32,
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
    fresh: bool,
) -> Result<Proc, RuntimeError> {
    // A resumed mission's logs follow those of its earlier runs.
    if fresh {
        let _ = std::fs::remove_file(out.join(format!("{name}.log")));
    }
    Ok(Proc {
        name,
        args: args.to_vec(),
        child: spawn(name, exe, args, out)?,
        restarts: 0,
        earlier: 0,
    })
}

/// Starts the recorder, then every node of the mission: `detector` holds
/// completeness_detector's parameters, `aerial` is the prior the cloud
/// publisher sends, `driver` the vehicle (sim or bridge). A resumed mission
/// (`carried` from its earlier runs) goes on recording into the next bag
/// split, its vehicle starts where it was, and the first detection waits for
/// the merge the explorer kept.
pub(super) fn start_all(
    a: &DemoArgs,
    exe: &Path,
    (mut detector, aerial, mut driver): (Vec<String>, &Path, (&'static str, Vec<String>)),
    carried: &Carried,
    drone: Vec<(&'static str, Vec<String>)>,
) -> Result<Vec<Proc>, RuntimeError> {
    let fresh = a.resume.is_none();
    // A resumed mission's recorder writes the split after its earlier runs' last.
    let earlier = if fresh {
        0
    } else {
        bag_splits(&a.out.join("mission.mcap")).count() as u32
    };
    let record = record_args(a);
    let mut recorder = start(
        "recorder",
        exe,
        &args_for_start(&record, earlier),
        &a.out,
        fresh,
    )?;
    (recorder.args, recorder.earlier) = (record, earlier);
    let mut procs = vec![recorder];
    if driver.0 == "vehicle_sim" {
        driver
            .1
            .push(format!("scan_log:={}", a.scan_log().display()));
    }
    if !fresh {
        detector.push("wait_resampled:=true".into());
        if let (Some(p), "vehicle_sim") = (carried.position, driver.0) {
            start_at(&mut driver.1, p);
        }
    }
    for (name, params) in [
        ("scene_classifier", vec![]),
        ("completeness_detector", detector),
        ("target_generator", vec![]),
        ("global_planner", planner_params(a)),
        ("local_explorer", explorer_params(a)),
        driver,
        (
            "cloud_publisher",
            vec![format!("file:={}", aerial.display())],
        ),
    ]
    .into_iter()
    .chain(drone)
    {
        procs.push(start(name, exe, &node_args(name, &params), &a.out, fresh)?);
    }
    Ok(procs)
}

/// Starts again every node that exited while the mission runs, as ros2
/// launch's `respawn=True` does: nodes take their state from latched topics.
/// A node whose DDS start-up deadlocked exits with
/// [`EXIT_STUCK`](crate::runtime::creation_watch::EXIT_STUCK) for this.
/// A vehicle_sim started again starts `at` the vehicle's last place.
pub(super) fn respawn(
    procs: &mut [Proc],
    exe: &Path,
    out: &Path,
    at: Option<[f32; 3]>,
) -> Result<(), RuntimeError> {
    for p in procs.iter_mut() {
        if let Ok(Some(status)) = p.child.try_wait() {
            eprintln!("  {} exited ({status}); starting it again", p.name);
            p.restarts += 1;
            if let (Some(q), "vehicle_sim") = (at, p.name) {
                start_at(&mut p.args, q);
            }
            let args = args_for_start(&p.args, p.earlier + p.restarts);
            p.child = spawn(p.name, exe, &args, out)?;
        }
    }
    Ok(())
}

/// Asks every node to stop, the last started first, noting what each used.
pub(super) async fn stop_all(procs: &mut [Proc], prof: &mut Profile) {
    for p in procs.iter_mut().rev() {
        prof.sample(p.name, p.child.id());
        stop(p).await;
    }
}

/// The nodes started again, and how often.
pub(super) fn restarts(procs: &[Proc]) -> std::collections::BTreeMap<String, u32> {
    procs
        .iter()
        .map(|p| (p.name.to_string(), p.restarts))
        .filter(|(_, n)| *n > 0)
        .collect()
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

/// The bag's splits on disk, in order (`first`, `…_1.mcap`, … up to the first missing).
fn bag_splits(first: &Path) -> impl Iterator<Item = PathBuf> + '_ {
    (0..)
        .map(|n| bag_split(first, n))
        .take_while(|p| p.is_file())
}

/// The bag's size: all its splits.
pub(super) fn bag_bytes(first: &Path) -> u64 {
    bag_splits(first)
        .filter_map(|p| std::fs::metadata(p).ok())
        .map(|m| m.len())
        .sum()
}

/// vehicle_sim's `start` parameter (which sim_driver always sets) moved to `q`.
fn start_at(args: &mut [String], q: [f32; 3]) {
    for arg in args.iter_mut().filter(|s| s.starts_with("start:=")) {
        *arg = format!("start:=[{}, {}]", q[0], q[1]);
    }
}

/// Messages and bytes per topic over the bag and its splits (a split that
/// cannot be read is left out and named on the console).
pub(super) fn bag_topics(
    first: &Path,
) -> std::collections::BTreeMap<String, crate::bag::TopicSize> {
    let mut all = std::collections::BTreeMap::<String, crate::bag::TopicSize>::new();
    for split in bag_splits(first) {
        match crate::bag::topic_sizes(&split) {
            Ok(sizes) => {
                for (topic, s) in sizes {
                    let t = all.entry(topic).or_default();
                    t.messages += s.messages;
                    t.bytes += s.bytes;
                }
            }
            Err(e) => eprintln!("  bag sizes: {e}"),
        }
    }
    all
}

/// Removes a former run's merge store.
pub(super) fn remove_merge(dir: &Path) -> Result<(), RuntimeError> {
    match std::fs::remove_dir_all(dir) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(RuntimeError::Node(format!(
            "{}: cannot remove the former merge: {e}",
            dir.display()
        ))),
        _ => Ok(()),
    }
}

/// Removes a former run's bag and its splits (their sizes are summed at the end).
pub(super) fn remove_bag(first: &Path) {
    for n in 0.. {
        if std::fs::remove_file(bag_split(first, n)).is_err() {
            break;
        }
    }
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
    if a.field.field || a.real_prior() {
        vec!["graph.canopy_is_obstacle:=false".into()]
    } else {
        Vec::new()
    }
}

/// local_explorer's parameters: the graph's, the merge's voxel and store.
fn explorer_params(a: &DemoArgs) -> Vec<String> {
    let mut v = graph_params(a);
    v.push(format!("resample_voxel_m:={}", a.merge_voxel));
    v.push(format!("merge_store:={}", a.merge_store().display()));
    if !a.field.field {
        // vehicle_sim's writer is reliable: so is the reader, no scan lost.
        v.push("scan_qos:=reliable".into());
    }
    if a.uav() {
        v.push("uav_scan_topic:=/uav/registered_scan".into());
    }
    v
}

/// global_planner's parameters from the demo's arguments; a planner the
/// watch restarts goes on from the status the watch kept.
fn planner_params(a: &DemoArgs) -> Vec<String> {
    let mut v = graph_params(a);
    v.extend(a.set_downs.map(|n| format!("set_downs:={n}")));
    let kept = a.out.join(super::resume::PLANNER_FILE);
    v.push(format!("restore:={}", kept.display()));
    let round = a.out.join(super::resume::ROUND_FILE);
    v.push(format!("keep_round:={}", round.display()));
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

/// The recorder's arguments: every topic into OUT/mission.mcap; the
/// LiDAR's at one scan in 50 (one per 5 simulated seconds): all of them made
/// a 16 GB bag of the reference run. vehicle_sim sends those on their own
/// topic, so the recorder is not sent the other 49; a real robot's scans are
/// thinned by the recorder.
fn record_args(a: &DemoArgs) -> Vec<String> {
    let mut args = vec![
        "record".to_string(),
        "-o".to_string(),
        a.out.join("mission.mcap").display().to_string(),
    ];
    args.extend(TOPICS.iter().map(|t| (*t).to_string()));
    if a.uav() {
        args.extend(super::uav::TOPICS.iter().map(|t| (*t).to_string()));
    }
    if a.field.field {
        args.extend(["--every".to_string(), "/registered_scan=50".to_string()]);
    } else {
        args.retain(|t| !t.starts_with("/registered_scan:"));
        args.push(SCANS_THROTTLED.to_string());
    }
    args
}

/// vehicle_sim and its parameters: the simulated robot, started at the free
/// spot nearest the scene's middle, or on a real prior's largest ground.
pub(super) fn sim_driver(
    scene: &Scene,
    scene_spec: &str,
    time_factor: f64,
    real_prior: Option<&Cloud>,
) -> Result<(&'static str, Vec<String>), RuntimeError> {
    let err = |e: String| RuntimeError::Node(e);
    let caster = Caster::new(scene).map_err(|e| err(e.to_string()))?;
    let start_xy = match real_prior {
        Some(cloud) => crate::cli::prior::start_on_prior(&caster, cloud)?,
        None => {
            find_start(&caster, None).map_err(|e| err(format!("no start for the vehicle: {e}")))?
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
pub(super) fn field_driver() -> (&'static str, Vec<String>) {
    eprintln!(
        "  field mode: no vehicle_sim; way-points on /way_point and /global_path, waiting for the robot on /state_estimation, /registered_scan, /tf"
    );
    eprintln!(
        "  ground graph: tree crowns block only where points stand in the vehicle's height band (the robot steers round trunks itself)"
    );
    ("robot_bridge", vec![])
}

#[cfg(test)]
mod tests {
    use super::*;

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
        remove_bag(&first);
        assert_eq!(bag_bytes(&first), 0);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn crowns_block_their_whole_column_only_for_vehicle_sim_on_a_simulated_prior() {
        use super::super::args::parse;
        let band = vec!["graph.canopy_is_obstacle:=false".to_string()];
        assert!(graph_params(&parse(&[])).is_empty());
        assert_eq!(graph_params(&parse(&["--field"])), band);
        assert_eq!(graph_params(&parse(&["--prior", "a.laz"])), band);
        let planner = planner_params(&parse(&["--field", "--set-downs", "0", "--out", "/o"]));
        let restore = "restore:=/o/planner.json".to_string();
        let round = "keep_round:=/o/round.json".to_string();
        assert_eq!(
            planner,
            [band[0].clone(), "set_downs:=0".to_string(), restore, round]
        );
    }

    #[test]
    fn the_recorder_takes_the_throttled_scans_in_simulation_and_thins_a_robots() {
        use super::super::args::parse;
        let sim = record_args(&parse(&["--out", "/o"]));
        assert_eq!(sim[..3], ["record", "-o", "/o/mission.mcap"]);
        assert!(sim.contains(&SCANS_THROTTLED.to_string()));
        assert!(!sim.iter().any(|t| t.starts_with("/registered_scan:")));
        let field = record_args(&parse(&["--field"]));
        assert!(field.iter().any(|t| t.starts_with("/registered_scan:")));
        assert!(field.contains(&"/registered_scan=50".to_string()));
    }
}
