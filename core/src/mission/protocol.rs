//! The mission's wire contract: one typed struct per status topic
//! (/planner_status, /explorer_status, /vehicle_status) and its conversion
//! to and from [`Wire`], a ROS-free mirror of `diagnostic_msgs/DiagnosticStatus`
//! (the node layer maps `Wire` to the message one to one). Keys are written
//! and read only here.

use std::str::FromStr;

use crate::follow::Follower;
use crate::missing::Strategy;
use crate::route::Visited;
use crate::vehicle::{Step, VehicleState};

/// `DiagnosticStatus.level` OK.
pub const OK: u8 = 0;
/// `DiagnosticStatus.level` WARN.
pub const WARN: u8 = 1;
/// `DiagnosticStatus.level` ERROR.
pub const ERROR: u8 = 2;

/// A status as it travels: level, name, message and key–value pairs (as
/// JSON too: a launcher keeps the planner's last one for a restarted planner).
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct Wire {
    /// 0 OK, 1 WARN, 2 ERROR, 3 STALE.
    pub level: u8,
    /// The node that speaks.
    pub name: String,
    /// Its state in one word (or a short sentence).
    pub message: String,
    /// Everything else, as key → text.
    pub values: Vec<(String, String)>,
}

/// A status that cannot be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProtocolError {
    /// A key the status needs is absent.
    #[error(
        "status `{name}` has no `{key}` value: is the publisher from another skyground version?"
    )]
    Missing {
        /// Status name.
        name: String,
        /// The absent key.
        key: &'static str,
    },
    /// A value does not parse.
    #[error("status `{name}`: `{key}` = {value:?} is not a valid {expected}")]
    Bad {
        /// Status name.
        name: String,
        /// The key.
        key: &'static str,
        /// Its text.
        value: String,
        /// What it should have been.
        expected: &'static str,
    },
    /// The message word is not one this status knows.
    #[error("status `{name}`: unknown state {message:?} (expected one of {expected})")]
    State {
        /// Status name.
        name: String,
        /// The message received.
        message: String,
        /// The states known.
        expected: &'static str,
    },
}

impl Wire {
    pub(crate) fn new(level: u8, name: &str, message: impl Into<String>) -> Self {
        Wire {
            level,
            name: name.into(),
            message: message.into(),
            values: Vec::new(),
        }
    }

    pub(crate) fn put(&mut self, key: &str, value: impl ToString) {
        self.values.push((key.into(), value.to_string()));
    }

    fn text(&self, key: &'static str) -> Option<&str> {
        self.values
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// The value of `key`, parsed; `None` when absent.
    pub(crate) fn opt<T: FromStr>(&self, key: &'static str) -> Result<Option<T>, ProtocolError> {
        self.text(key)
            .map(|v| {
                v.trim().parse().map_err(|_| ProtocolError::Bad {
                    name: self.name.clone(),
                    key,
                    value: v.into(),
                    expected: std::any::type_name::<T>(),
                })
            })
            .transpose()
    }

    /// The value of `key`, parsed; an error when absent.
    pub(crate) fn get<T: FromStr>(&self, key: &'static str) -> Result<T, ProtocolError> {
        self.opt(key)?.ok_or_else(|| ProtocolError::Missing {
            name: self.name.clone(),
            key,
        })
    }

    pub(crate) fn list<T: FromStr>(
        &self,
        key: &'static str,
        sep: char,
    ) -> Result<Vec<T>, ProtocolError> {
        let Some(v) = self.text(key) else {
            return Ok(Vec::new());
        };
        v.split(sep)
            .filter(|s| !s.trim().is_empty())
            .map(|s| {
                s.trim().parse().map_err(|_| ProtocolError::Bad {
                    name: self.name.clone(),
                    key,
                    value: v.into(),
                    expected: "list",
                })
            })
            .collect()
    }
}

pub(crate) fn join<T: ToString>(v: &[T], sep: &str) -> String {
    v.iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(sep)
}

/// A spot the vehicle found blocked: the ground graph drops what lies within
/// `radius` of `at` (xy, map frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlockedSpot {
    /// Centre, m.
    pub at: [f32; 2],
    /// Radius, m.
    pub radius: f32,
}

impl std::fmt::Display for BlockedSpot {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {} {}", self.at[0], self.at[1], self.radius)
    }
}

impl FromStr for BlockedSpot {
    type Err = ();
    fn from_str(s: &str) -> Result<Self, ()> {
        let v: Vec<f32> = s
            .split_whitespace()
            .map(|x| x.parse().map_err(|_| ()))
            .collect::<Result<_, _>>()?;
        match v[..] {
            [x, y, radius] => Ok(BlockedSpot { at: [x, y], radius }),
            _ => Err(()),
        }
    }
}

/// Where the planner's mission is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Waiting for inputs or a route.
    Waiting,
    /// Driving leg `k` of the route.
    Driving(usize),
    /// The explorer works on the region of stop `k`.
    Exploring(usize),
    /// The route is done; the robot is being set down on another piece of
    /// ground for the targets this one does not reach.
    Carrying,
    /// Every stop done.
    Done,
}

impl Phase {
    /// The word on the wire.
    pub fn word(self) -> &'static str {
        match self {
            Phase::Waiting => "waiting",
            Phase::Driving(_) => "driving",
            Phase::Exploring(_) => "exploring",
            Phase::Carrying => "carrying",
            Phase::Done => "done",
        }
    }
}

/// /planner_status: the round, the targets, what was visited (so a
/// restarted planner goes on), the route's figures, the region handed to the
/// explorer and the spots found blocked (so the explorer's graph drops them too).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PlannerStatus {
    /// Phase word: waiting, driving, exploring, carrying or done.
    pub phase: String,
    /// Mission round, from 1 (0 before the first route).
    pub round: u32,
    /// Target points this round.
    pub target_points: usize,
    /// Target regions this round.
    pub target_regions: usize,
    /// Targets dealt with (indices into this round's set): reached or given up.
    pub visited: Visited,
    /// The part of `visited` given up after blocked tries, not reached.
    pub given_up: Visited,
    /// Target points left off the route because the rest of it sees their
    /// gaps anyway (`route.skip_seen`; indices into this round's set).
    pub seen_on_the_way: Vec<usize>,
    /// Targets the route cannot reach.
    pub unreachable_points: usize,
    /// Regions the route cannot reach.
    pub unreachable_regions: usize,
    /// Stops on the route.
    pub stops: usize,
    /// Route length, m.
    pub route_m: f32,
    /// The greedy tour's length, m.
    pub greedy_m: f32,
    /// The TSP tour's length, m.
    pub tsp_m: f32,
    /// The region (index into this round's set) on /active_region, and its building.
    pub active_region: Option<(usize, u32)>,
    /// Spots found blocked so far.
    pub blocked: Vec<BlockedSpot>,
    /// Set-downs asked for this round.
    pub set_downs: usize,
}

/// Name of the planner's status.
pub const PLANNER: &str = "global_planner";
/// Name of the explorer's status.
pub const EXPLORER: &str = "local_explorer";

/// A planner status kept in a file could not be written or read back.
#[derive(Debug, thiserror::Error)]
pub enum KeptStatusError {
    /// Writing or reading the file failed.
    #[error(transparent)]
    File(#[from] crate::file::FileError),
    /// The file is not a kept status.
    #[error("{}: not a kept planner status ({reason})", path.display())]
    Json {
        /// The file.
        path: std::path::PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// The status it holds cannot be read.
    #[error(transparent)]
    Protocol(#[from] ProtocolError),
    /// The file is not a kept round's targets.
    #[error("{}: not a kept round's targets ({reason})", path.display())]
    Round {
        /// The file.
        path: std::path::PathBuf,
        /// What is wrong with it.
        reason: String,
    },
}

impl PlannerStatus {
    /// Keeps it in `path` (its wire form as JSON), atomically: a launcher
    /// saves the planner's last status for a planner it restarts.
    pub fn keep(&self, path: &std::path::Path) -> Result<(), KeptStatusError> {
        let json = serde_json::to_vec(&self.to_wire()).map_err(|e| KeptStatusError::Json {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
        Ok(crate::file::write(path, json)?)
    }

    /// The status kept in `path`; `None` when there is no such file.
    pub fn kept(path: &std::path::Path) -> Result<Option<PlannerStatus>, KeptStatusError> {
        if !path.is_file() {
            return Ok(None);
        }
        let bytes = crate::file::read(path)?;
        let wire: Wire = serde_json::from_slice(&bytes).map_err(|e| KeptStatusError::Json {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
        Ok(Some(PlannerStatus::from_wire(&wire)?))
    }
}

impl PlannerStatus {
    /// As it goes on the wire.
    pub fn to_wire(&self) -> Wire {
        let mut w = Wire::new(OK, PLANNER, self.phase.clone());
        w.put("round", self.round);
        w.put("target_points", self.target_points);
        w.put("target_regions", self.target_regions);
        w.put("visited_points", join(&self.visited.points, ","));
        w.put("visited_regions", join(&self.visited.regions, ","));
        // Counts for readers that want no list (the demo's watch, scripts).
        w.put("points_done", self.visited.points.len());
        w.put("regions_done", self.visited.regions.len());
        w.put("given_up_points", join(&self.given_up.points, ","));
        w.put("given_up_regions", join(&self.given_up.regions, ","));
        w.put("seen_points", join(&self.seen_on_the_way, ","));
        w.put("points_seen", self.seen_on_the_way.len());
        w.put("unreachable_points", self.unreachable_points);
        w.put("unreachable_regions", self.unreachable_regions);
        w.put("stops", self.stops);
        w.put("route_m", self.route_m);
        w.put("greedy_m", self.greedy_m);
        w.put("tsp_m", self.tsp_m);
        if let Some((i, b)) = self.active_region {
            w.put("active_region", i);
            w.put("active_building", b);
        }
        w.put("blocked_spots", join(&self.blocked, ";"));
        w.put("set_downs", self.set_downs);
        w
    }

    /// Read from the wire.
    pub fn from_wire(w: &Wire) -> Result<Self, ProtocolError> {
        let active = match (w.opt("active_region")?, w.opt("active_building")?) {
            (Some(i), Some(b)) => Some((i, b)),
            _ => None,
        };
        Ok(PlannerStatus {
            phase: w.message.clone(),
            round: w.get("round")?,
            target_points: w.get("target_points")?,
            target_regions: w.get("target_regions")?,
            visited: Visited {
                points: w.list("visited_points", ',')?,
                regions: w.list("visited_regions", ',')?,
            },
            // Absent from a planner older than the field: nothing given up.
            given_up: Visited {
                points: w.list("given_up_points", ',')?,
                regions: w.list("given_up_regions", ',')?,
            },
            seen_on_the_way: w.list("seen_points", ',')?,
            unreachable_points: w.opt("unreachable_points")?.unwrap_or(0),
            unreachable_regions: w.opt("unreachable_regions")?.unwrap_or(0),
            stops: w.opt("stops")?.unwrap_or(0),
            route_m: w.opt("route_m")?.unwrap_or(0.0),
            greedy_m: w.opt("greedy_m")?.unwrap_or(0.0),
            tsp_m: w.opt("tsp_m")?.unwrap_or(0.0),
            active_region: active,
            blocked: w.list("blocked_spots", ';')?,
            set_downs: w.opt("set_downs")?.unwrap_or(0),
        })
    }
}

/// /explorer_status: what the local explorer does.
#[derive(Debug, Clone, PartialEq)]
pub enum ExplorerState {
    /// Nothing handed over yet.
    Idle,
    /// Exploring a region.
    Exploring {
        /// Region index in its round's set.
        region: usize,
        /// Round.
        round: u32,
        /// The region's building.
        building: u32,
        /// Share of the region's surface seen, 0–1.
        coverage: f64,
        /// Viewpoints driven to.
        viewpoints: u32,
    },
    /// The last region handed back.
    Done {
        /// Region index.
        region: usize,
        /// Round.
        round: u32,
        /// Final coverage, 0–1.
        coverage: f64,
    },
}

/// /explorer_status with the merged cloud's size.
#[derive(Debug, Clone, PartialEq)]
pub struct ExplorerStatus {
    /// What it does.
    pub state: ExplorerState,
    /// Points in /resampled_cloud so far.
    pub resampled_points: usize,
}

impl ExplorerStatus {
    /// As it goes on the wire.
    pub fn to_wire(&self) -> Wire {
        let mut w;
        match self.state {
            ExplorerState::Idle => w = Wire::new(OK, EXPLORER, "idle"),
            ExplorerState::Exploring {
                region,
                round,
                building,
                coverage,
                viewpoints,
            } => {
                w = Wire::new(OK, EXPLORER, "exploring");
                w.put("region", region);
                w.put("round", round);
                w.put("building", building);
                w.put("coverage", coverage);
                w.put("viewpoints", viewpoints);
            }
            ExplorerState::Done {
                region,
                round,
                coverage,
            } => {
                w = Wire::new(OK, EXPLORER, "done");
                w.put("region", region);
                w.put("round", round);
                w.put("coverage", coverage);
            }
        }
        w.put("resampled_points", self.resampled_points);
        w
    }

    /// Read from the wire.
    pub fn from_wire(w: &Wire) -> Result<Self, ProtocolError> {
        let state = match w.message.as_str() {
            "idle" => ExplorerState::Idle,
            "exploring" => ExplorerState::Exploring {
                region: w.get("region")?,
                round: w.get("round")?,
                building: w.get("building")?,
                coverage: w.get("coverage")?,
                viewpoints: w.get("viewpoints")?,
            },
            "done" => ExplorerState::Done {
                region: w.get("region")?,
                round: w.get("round")?,
                coverage: w.get("coverage")?,
            },
            other => {
                return Err(ProtocolError::State {
                    name: w.name.clone(),
                    message: other.into(),
                    expected: "idle, exploring, done",
                });
            }
        };
        Ok(ExplorerStatus {
            state,
            resampled_points: w.opt("resampled_points")?.unwrap_or(0),
        })
    }
}

/// What the vehicle reports on /vehicle_status.
#[derive(Debug, Clone, PartialEq)]
pub enum VehicleEvent {
    /// It reached `goal`.
    Arrived,
    /// It cannot go on towards `goal`, and why.
    Blocked(String),
}

/// /vehicle_status (vehicle_sim or robot_bridge): arrived at or blocked on
/// the way to a goal.
#[derive(Debug, Clone, PartialEq)]
pub struct VehicleStatus {
    /// The node speaking.
    pub name: String,
    /// Arrived or blocked.
    pub event: VehicleEvent,
    /// The pose it was going to (xy).
    pub goal: [f32; 2],
    /// Where it is (xy).
    pub at: [f32; 2],
    /// Metres driven so far.
    pub odometer_m: f64,
}

impl VehicleStatus {
    /// As it goes on the wire.
    pub fn to_wire(&self) -> Wire {
        let mut w = match &self.event {
            VehicleEvent::Arrived => Wire::new(OK, &self.name, "arrived"),
            VehicleEvent::Blocked(r) => Wire::new(WARN, &self.name, format!("blocked: {r}")),
        };
        w.put("goal_x", self.goal[0]);
        w.put("goal_y", self.goal[1]);
        w.put("x", self.at[0]);
        w.put("y", self.at[1]);
        w.put("odometer_m", self.odometer_m);
        w
    }

    /// Read from the wire.
    pub fn from_wire(w: &Wire) -> Result<Self, ProtocolError> {
        let event = if w.message == "arrived" {
            VehicleEvent::Arrived
        } else if let Some(r) = w.message.strip_prefix("blocked") {
            VehicleEvent::Blocked(r.trim_start_matches(':').trim_start().into())
        } else {
            return Err(ProtocolError::State {
                name: w.name.clone(),
                message: w.message.clone(),
                expected: "arrived, blocked: REASON",
            });
        };
        Ok(VehicleStatus {
            name: w.name.clone(),
            event,
            goal: [w.get("goal_x")?, w.get("goal_y")?],
            at: [w.get("x")?, w.get("y")?],
            odometer_m: w.opt("odometer_m")?.unwrap_or(0.0),
        })
    }

    /// What a simulated vehicle's step says, if anything (arrived or blocked).
    pub fn from_step(name: &str, step: &Step, state: &VehicleState) -> Option<Self> {
        let (event, goal) = match step {
            Step::Arrived(goal) => (VehicleEvent::Arrived, *goal),
            Step::Blocked { goal, reason } => (VehicleEvent::Blocked(reason.clone()), *goal),
            Step::Idle | Step::Moving => return None,
        };
        Some(VehicleStatus {
            name: name.into(),
            event,
            goal,
            at: [state.position[0], state.position[1]],
            odometer_m: f64::from(state.odometer),
        })
    }

    /// What a followed robot says (field mode's robot_bridge), worded as a
    /// simulated vehicle's: `event` about `goal`, at the robot's last known
    /// position (the goal before any), with the follower's odometer.
    pub fn from_follower(name: &str, event: VehicleEvent, goal: [f32; 3], f: &Follower) -> Self {
        let at = f.position().unwrap_or(goal);
        VehicleStatus {
            name: name.into(),
            event,
            goal: [goal[0], goal[1]],
            at: [at[0], at[1]],
            odometer_m: f.odometer,
        }
    }

    /// Whether it is about the pose `goal` (xy within 1 mm).
    pub fn is_for(&self, goal: [f32; 3]) -> bool {
        (self.goal[0] - goal[0]).abs() < 1e-3 && (self.goal[1] - goal[1]).abs() < 1e-3
    }
}

/// One building's detection on /completeness: skipped (and why) or its
/// missing-wall figures and the strategy its targets follow.
#[derive(Debug, Clone, PartialEq)]
pub struct BuildingStatus {
    /// Building id.
    pub building: u32,
    /// Its footprint's own id (BAG, OSM, CityObject id; `derived_N`), empty
    /// when none named it (key `footprint_id`, absent then).
    pub footprint_id: String,
    /// Its points in the prior.
    pub points: usize,
    /// Detection round (0 on the aerial prior alone).
    pub round: u32,
    /// `None` when detected, else why it was skipped.
    pub skipped: Option<String>,
    /// Share of boundary points missing, 0–1 (completeness is 1 − this).
    pub r_missing: f32,
    /// Missing boundary points.
    pub missing: usize,
    /// Boundary points.
    pub boundary: usize,
    /// Slices.
    pub slices: usize,
    /// Structures (skeletons).
    pub structures: usize,
    /// Point- or region-based targets.
    pub strategy: Strategy,
    /// Ground height, m.
    pub ground_z: f32,
}

fn strategy_word(s: Strategy) -> &'static str {
    match s {
        Strategy::PointBased => "point",
        Strategy::RegionBased => "region",
    }
}

impl BuildingStatus {
    /// As it goes on the wire (name `building ID`).
    pub fn to_wire(&self) -> Wire {
        let name = format!("building {}", self.building);
        let mut w = match &self.skipped {
            Some(r) => Wire::new(WARN, &name, format!("skipped: {r}")),
            None => Wire::new(
                OK,
                &name,
                format!(
                    "R_missing {:.3}, {}",
                    self.r_missing,
                    strategy_word(self.strategy)
                ),
            ),
        };
        w.put("building", self.building);
        if !self.footprint_id.is_empty() {
            w.put("footprint_id", &self.footprint_id);
        }
        w.put("points", self.points);
        w.put("round", self.round);
        if self.skipped.is_none() {
            w.put("completeness", 1.0 - self.r_missing);
            w.put("r_missing", self.r_missing);
            w.put("missing", self.missing);
            w.put("boundary", self.boundary);
            w.put("slices", self.slices);
            w.put("structures", self.structures);
            w.put("strategy", strategy_word(self.strategy));
            w.put("ground_z", self.ground_z);
        }
        w
    }

    /// Read from the wire.
    pub fn from_wire(w: &Wire) -> Result<Self, ProtocolError> {
        let skipped = w
            .message
            .strip_prefix("skipped: ")
            .map(str::to_string)
            .filter(|_| w.level != OK);
        let mut s = BuildingStatus {
            building: w.get("building")?,
            footprint_id: w.get::<String>("footprint_id").unwrap_or_default(),
            points: w.get("points")?,
            round: w.get("round")?,
            skipped,
            r_missing: 0.0,
            missing: 0,
            boundary: 0,
            slices: 0,
            structures: 0,
            strategy: Strategy::PointBased,
            ground_z: 0.0,
        };
        if s.skipped.is_none() {
            s.r_missing = w.get("r_missing")?;
            s.missing = w.get("missing")?;
            s.boundary = w.get("boundary")?;
            s.slices = w.get("slices")?;
            s.structures = w.get("structures")?;
            s.ground_z = w.get("ground_z")?;
            s.strategy = match w.get::<String>("strategy")?.as_str() {
                "point" => Strategy::PointBased,
                "region" => Strategy::RegionBased,
                other => {
                    return Err(ProtocolError::Bad {
                        name: w.name.clone(),
                        key: "strategy",
                        value: other.into(),
                        expected: "point or region",
                    });
                }
            };
        }
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;
    use proptest::strategy::Strategy;

    use super::*;

    fn finite() -> impl Strategy<Value = f32> {
        -1e6f32..1e6
    }

    prop_compose! {
        fn spot()(x in finite(), y in finite(), radius in 0.0f32..10.0) -> BlockedSpot {
            BlockedSpot { at: [x, y], radius }
        }
    }

    prop_compose! {
        fn planner()(
            phase in prop::sample::select(vec!["waiting", "driving", "exploring", "done"]),
            round in 0u32..10,
            tp in 0usize..1000, tr in 0usize..100,
            vp in prop::collection::vec(0usize..1000, 0..20),
            vr in prop::collection::vec(0usize..100, 0..5),
            gp in prop::collection::vec(0usize..1000, 0..5),
            gr in prop::collection::vec(0usize..100, 0..3),
            seen in prop::collection::vec(0usize..1000, 0..20),
            up in 0usize..50, ur in 0usize..50, stops in 0usize..1000,
            lens in (0.0f32..1e5, 0.0f32..1e5, 0.0f32..1e5),
            active in prop::option::of((0usize..100, 0u32..100)),
            blocked in prop::collection::vec(spot(), 0..6),
            set_downs in 0usize..4,
        ) -> PlannerStatus {
            PlannerStatus {
                phase: phase.into(), round, target_points: tp, target_regions: tr,
                visited: Visited { points: vp, regions: vr },
                given_up: Visited { points: gp, regions: gr },
                seen_on_the_way: seen,
                unreachable_points: up, unreachable_regions: ur, stops,
                route_m: lens.0, greedy_m: lens.1, tsp_m: lens.2,
                active_region: active, blocked, set_downs,
            }
        }
    }

    fn explorer_state() -> impl Strategy<Value = ExplorerState> {
        prop_oneof![
            Just(ExplorerState::Idle),
            (0usize..100, 0u32..9, 0u32..500, 0.0f64..1.0, 0u32..99).prop_map(
                |(region, round, building, coverage, viewpoints)| ExplorerState::Exploring {
                    region,
                    round,
                    building,
                    coverage,
                    viewpoints
                }
            ),
            (0usize..100, 0u32..9, 0.0f64..1.0).prop_map(|(region, round, coverage)| {
                ExplorerState::Done {
                    region,
                    round,
                    coverage,
                }
            }),
        ]
    }

    prop_compose! {
        fn building()(
            building in 1u32..1000, points in 0usize..100_000, round in 0u32..5,
            skipped in prop::option::of("[a-z][a-z ]{0,20}[a-z]"),
            footprint_id in "([A-Za-z0-9./_-]{1,30})?",
            r_missing in 0.0f32..1.0, counts in (0usize..1000, 0usize..1000, 0usize..50, 0usize..9),
            region in any::<bool>(), ground_z in -100.0f32..100.0,
        ) -> BuildingStatus {
            let detected = skipped.is_none();
            BuildingStatus {
                building, footprint_id, points, round, skipped,
                r_missing: if detected { r_missing } else { 0.0 },
                missing: if detected { counts.0 } else { 0 },
                boundary: if detected { counts.1 } else { 0 },
                slices: if detected { counts.2 } else { 0 },
                structures: if detected { counts.3 } else { 0 },
                strategy: if detected && region { crate::missing::Strategy::RegionBased } else { crate::missing::Strategy::PointBased },
                ground_z: if detected { ground_z } else { 0.0 },
            }
        }
    }

    proptest! {
        #[test]
        fn building_status_round_trips(s in building()) {
            prop_assert_eq!(BuildingStatus::from_wire(&s.to_wire()), Ok(s));
        }

        #[test]
        fn planner_status_round_trips(s in planner()) {
            prop_assert_eq!(PlannerStatus::from_wire(&s.to_wire()), Ok(s));
        }

        #[test]
        fn explorer_status_round_trips(state in explorer_state(), n in 0usize..10_000_000) {
            let s = ExplorerStatus { state, resampled_points: n };
            prop_assert_eq!(ExplorerStatus::from_wire(&s.to_wire()), Ok(s));
        }

        #[test]
        fn vehicle_status_round_trips(
            blocked in prop::option::of("[a-z ]{1,20}"),
            g in (finite(), finite()), at in (finite(), finite()), odo in 0.0f64..1e5,
        ) {
            let event = match blocked {
                Some(r) => VehicleEvent::Blocked(r.trim().into()),
                None => VehicleEvent::Arrived,
            };
            let s = VehicleStatus { name: "vehicle_sim".into(), event, goal: [g.0, g.1], at: [at.0, at.1], odometer_m: odo };
            prop_assert_eq!(VehicleStatus::from_wire(&s.to_wire()), Ok(s));
        }
    }

    #[test]
    fn a_vehicle_step_says_arrived_or_blocked_and_nothing_else() {
        let state = VehicleState {
            position: [3.0, 4.0, 1.0],
            yaw: 0.0,
            speed: 0.0,
            yaw_rate: 0.0,
            odometer: 12.5,
        };
        let blocked = Step::Blocked {
            goal: [5.0, 6.0],
            reason: "wall".into(),
        };
        let s = VehicleStatus::from_step("vehicle_sim", &blocked, &state).expect("a status");
        assert_eq!(s.event, VehicleEvent::Blocked("wall".into()));
        assert_eq!((s.goal, s.at, s.odometer_m), ([5.0, 6.0], [3.0, 4.0], 12.5));
        assert_eq!(s.to_wire().level, WARN);
        let arrived = VehicleStatus::from_step("vehicle_sim", &Step::Arrived([5.0, 6.0]), &state);
        assert_eq!(arrived.map(|s| s.event), Some(VehicleEvent::Arrived));
        assert_eq!(VehicleStatus::from_step("v", &Step::Moving, &state), None);
    }

    #[test]
    fn a_status_without_its_keys_or_with_bad_values_is_an_error() {
        let w = Wire::new(OK, PLANNER, "driving");
        assert!(matches!(
            PlannerStatus::from_wire(&w),
            Err(ProtocolError::Missing { key: "round", .. })
        ));
        let mut w = PlannerStatus::default().to_wire();
        w.values[0].1 = "two".into();
        assert!(matches!(
            PlannerStatus::from_wire(&w),
            Err(ProtocolError::Bad { key: "round", .. })
        ));
        let w = Wire::new(OK, EXPLORER, "sleeping");
        assert!(matches!(
            ExplorerStatus::from_wire(&w),
            Err(ProtocolError::State { .. })
        ));
    }

    #[test]
    fn a_kept_planner_status_reads_back_and_a_bad_file_is_an_error() {
        let dir = std::env::temp_dir().join(format!("skyground-kept-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("planner.json");
        assert!(
            PlannerStatus::kept(&path).unwrap().is_none(),
            "no file, no status"
        );
        let s = PlannerStatus {
            phase: "driving".into(),
            round: 2,
            target_points: 9,
            visited: Visited {
                points: vec![0, 3],
                regions: vec![1],
            },
            given_up: Visited {
                points: vec![3],
                regions: vec![],
            },
            ..PlannerStatus::default()
        };
        s.keep(&path).unwrap();
        assert_eq!(PlannerStatus::kept(&path).unwrap(), Some(s));
        std::fs::write(&path, b"{\"level\": 0}").unwrap();
        assert!(matches!(
            PlannerStatus::kept(&path),
            Err(KeptStatusError::Json { .. })
        ));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
