//! The demo's command-line options.

use std::path::PathBuf;

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
    pub crop: crate::cli::crop::CropArgs,
    /// A real aerial survey as the prior (`--prior`, `--prior-margin`).
    #[command(flatten)]
    pub prior: crate::cli::prior::PriorArgs,
    /// Output directory (aerial.laz, resampled.laz, merge/, mission.mcap, report.*, overview.png, logs).
    #[arg(long, default_value = "out/demo")]
    pub out: PathBuf,
    /// Write the big clouds as uncompressed LAS (aerial.las, resampled.las) instead of LAZ.
    #[arg(long)]
    pub las: bool,
    /// Edge of the voxels the merged ground scans are thinned to (one point
    /// each), m; 0 keeps every point the LiDAR returned (full density).
    #[arg(long, default_value_t = 0.05)]
    pub merge_voxel: f32,
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
    /// Footprints for the detector (`--footprints`, `--footprint-id`); `model`: a CityJSON
    /// scene's own buildings. Read and checked before any node starts.
    #[command(flatten)]
    pub footprints: crate::cli::footprints::FootprintsArg,
    /// With CityJSON footprints: the LoD2 models one per BuildingPart, each written as a
    /// BuildingPart of its Building (the detector node reads its footprints per Building);
    /// default: one per Building.
    #[arg(long, requires = "footprints")]
    pub parts: bool,
    /// The platforms that resample: `ground` (the robot), `uav` (a drone
    /// taking the gaps no ground stop sees), or both: `ground,uav` (field
    /// mode drives the real robot only).
    #[arg(long, value_delimiter = ',', default_value = "ground,uav")]
    pub platforms: Vec<Platform>,
    /// With the drone: a GeoJSON of the area(s) it must stay inside
    /// (Polygon / MultiPolygon, in the scene's CRS); read and checked
    /// before any node starts.
    #[arg(long, value_name = "GEOJSON")]
    pub geofence: Option<PathBuf>,
    /// Field mode: a real robot instead of vehicle_sim.
    #[command(flatten)]
    pub field: FieldArgs,
    /// Go on with the mission in DIR (killed, stalled, a battery run out): its
    /// command line (DIR/command.json), the scans merged (DIR/merge), the
    /// rounds done and the vehicle's last place (DIR/progress.json) are
    /// taken from there; `--timeout` and `--no-netns` given now still apply.
    #[arg(long, value_name = "DIR")]
    pub resume: Option<PathBuf>,
    /// With `--resume`: the folder the mission was started in (its relative paths' base).
    #[arg(skip)]
    pub started_in: Option<PathBuf>,
}

/// A resampling platform.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Platform {
    /// The ground robot (vehicle_sim, or robot_bridge in field mode).
    Ground,
    /// The drone (uav_planner and uav_sim).
    Uav,
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
    /// Whether the drone flies (simulated missions only).
    pub fn uav(&self) -> bool {
        self.platforms.contains(&Platform::Uav) && !self.field.field
    }

    /// The scene spec every process loads (tiles joined by commas).
    pub fn scene(&self) -> String {
        self.scenes.join(",")
    }

    /// `OUT/STEM.laz`, or `OUT/STEM.las` with `--las`.
    pub fn cloud_file(&self, stem: &str) -> PathBuf {
        self.out
            .join(format!("{stem}.{}", if self.las { "las" } else { "laz" }))
    }

    /// Where the merged scans are kept as they arrive (`skyground_core::explore::MergeStore`).
    pub fn merge_store(&self) -> PathBuf {
        self.out.join("merge")
    }

    /// vehicle_sim's log of the scan ids DDS took (`scan_log`), one stamp a line.
    pub fn scan_log(&self) -> PathBuf {
        self.out.join("scans_sent.txt")
    }

    /// These arguments, or with `--resume DIR` the ones DIR's mission was
    /// started with (output DIR), with this `--timeout` and `--no-netns`;
    /// `started_in` is the folder its relative paths were given in.
    pub fn resumed(self) -> Result<DemoArgs, String> {
        let Some(given) = self.resume.clone() else {
            return Ok(self);
        };
        let dir = std::fs::canonicalize(&given)
            .map_err(|e| format!("--resume {}: {e}", given.display()))?;
        let command = super::resume::Command::read(&dir)?;
        #[derive(clap::Parser)]
        struct Cli {
            #[command(flatten)]
            demo: DemoArgs,
        }
        let argv = std::iter::once("demo".to_string()).chain(command.argv);
        let parsed = <Cli as clap::Parser>::try_parse_from(argv)
            .map_err(|e| format!("--resume {}: {e}", dir.display()))?;
        let mut a = parsed.demo;
        a.started_in = command.cwd;
        a.out = dir.clone();
        a.resume = Some(dir);
        a.timeout = self.timeout.or(a.timeout);
        a.no_netns |= self.no_netns;
        Ok(a)
    }

    /// A prior of real survey files rather than the simulated flight.
    pub fn real_prior(&self) -> bool {
        !self.prior.files.is_empty()
    }
}

#[cfg(test)]
pub(super) fn parse(args: &[&str]) -> DemoArgs {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_drone_flies_by_default_in_simulation_only_and_prior_tiles_split_at_commas() {
        assert!(parse(&[]).uav());
        assert!(!parse(&["--platforms", "ground"]).uav());
        assert!(
            !parse(&["--field"]).uav(),
            "field mode drives the real robot only"
        );
        let a = parse(&["--prior", "a.laz,b.laz", "--prior", "c.laz"]);
        let want: Vec<PathBuf> = ["a.laz", "b.laz", "c.laz"].map(PathBuf::from).into();
        assert_eq!(a.prior.files, want);
    }
}
