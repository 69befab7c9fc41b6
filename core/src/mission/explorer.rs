//! The local explorer's executive: joins the region on /active_region with
//! the planner's status (which names its index, building and round), starts
//! a [`crate::explore::Explorer`] on the one ground graph (the planner's
//! blocked spots taken out), feeds it the scans made at each viewpoint,
//! drives on until the gain runs out or it is blocked too often, hands the
//! region back, and merges every building point scanned into the resampled
//! cloud.

use std::sync::Arc;

use geo::{Distance, Euclidean, LineString, Point, Polygon};

use crate::cloud::class;
use crate::explore::{
    ExploreError, ExploreParams, Explorer, KeptMerge, StoreError, Stored, VoxelMerge,
};
use crate::graph::{GraphParams, GroundGraph};
use crate::targets::Region;

use super::ground;
use super::protocol::{
    BlockedSpot, ExplorerState, ExplorerStatus, Phase, PlannerStatus, VehicleEvent, VehicleStatus,
};

/// What the explorer needs to know.
#[derive(Debug, Clone)]
pub struct ExplorerConfig {
    /// Ground graph settings (the planner's).
    pub graph: GraphParams,
    /// Viewpoint selection settings.
    pub explore: ExploreParams,
    /// Missing points of the region's building within this distance of the
    /// region are the surface to cover, m.
    pub surface_margin_m: f64,
    /// Also publish the resampled cloud when each region is done.
    pub publish_each_region: bool,
    /// Edge of the de-duplication voxels of the resampled cloud, m.
    pub resample_voxel_m: f32,
    /// Viewpoints the vehicle is blocked on this many times end the region.
    pub block_retries: u32,
}

/// What happens to the explorer.
#[derive(Debug, Clone)]
pub enum ExplorerEvent {
    /// The classified cloud: the graph is built anew at the next region.
    Cloud {
        /// Points.
        xyz: Vec<[f32; 3]>,
        /// Their classes.
        labels: Vec<u8>,
    },
    /// The missing points and their buildings.
    Missing(Vec<([f32; 3], u32)>),
    /// The region handed over (`None`: taken back).
    ActiveRegion(Option<Region>),
    /// The planner's status: which region, which round, which spots are blocked.
    Planner(PlannerStatus),
    /// A registered scan (labels when it carries them).
    Scan {
        /// Its id (its header stamp, see [`super::scan_ids`]); a second scan
        /// with an id already merged is left out.
        id: u64,
        /// Points.
        xyz: Vec<[f32; 3]>,
        /// Their classes.
        labels: Option<Vec<u8>>,
    },
    /// Where the vehicle is.
    Position([f32; 3]),
    /// The vehicle arrived or is blocked.
    Vehicle(VehicleStatus),
    /// Time passes: say what the explorer does.
    Tick,
}

/// The points of a scan the merge takes: its building points (all of them
/// when it carries no labels).
pub fn merged_points(xyz: &[[f32; 3]], labels: Option<&[u8]>) -> Vec<[f32; 3]> {
    xyz.iter()
        .enumerate()
        .filter(|(i, _)| labels.is_none_or(|l| l.get(*i) == Some(&class::BUILDING)))
        .map(|(_, q)| *q)
        .collect()
}

/// What the explorer asks its node to do.
#[derive(Debug, Clone, PartialEq)]
pub enum ExplorerCommand {
    /// Log at info level.
    Info(String),
    /// Log an error.
    Error(String),
    /// Send a leg to the vehicle.
    Leg(Vec<[f32; 3]>),
    /// Publish the status.
    Status(ExplorerStatus),
    /// Publish the resampled cloud ([`ExplorerMachine::resampled`]).
    Resampled,
}

/// A region being explored.
#[derive(Debug)]
struct Active {
    index: usize,
    round: u32,
    building: u32,
    explorer: Explorer,
    goal: Option<[f32; 3]>,
    pending: Vec<[f32; 3]>,
    blocked: u32,
    stops: u32,
}

/// The local explorer's state machine.
#[derive(Debug)]
pub struct ExplorerMachine {
    config: ExplorerConfig,
    cloud: Option<(Vec<[f32; 3]>, Vec<u8>)>,
    graph: Option<Arc<GroundGraph>>,
    /// How many of `blocked` the graph has taken out.
    applied: usize,
    blocked: Vec<BlockedSpot>,
    missing: Vec<([f32; 3], u32)>,
    position: Option<[f32; 3]>,
    requested: Option<Region>,
    /// (index, building, round) of the planner's active region.
    assigned: Option<(usize, u32, u32)>,
    active: Option<Active>,
    last_done: Option<(usize, u32, f64)>,
    published_rounds: Vec<u32>,
    merged: VoxelMerge,
    scans: usize,
    /// Ids of the scans merged, in order, and as a set (a repeat is left out).
    ids: Vec<u64>,
    seen: std::collections::HashSet<u64>,
    out: Vec<ExplorerCommand>,
}

impl ExplorerMachine {
    /// An explorer waiting for a region; errors on bad settings.
    pub fn new(config: ExplorerConfig) -> Result<Self, ExploreError> {
        config.explore.validate()?;
        let merged = VoxelMerge::new(config.resample_voxel_m)?;
        Ok(ExplorerMachine {
            config,
            cloud: None,
            graph: None,
            applied: 0,
            blocked: Vec::new(),
            missing: Vec::new(),
            position: None,
            requested: None,
            assigned: None,
            active: None,
            last_done: None,
            published_rounds: Vec::new(),
            merged,
            scans: 0,
            ids: Vec::new(),
            seen: std::collections::HashSet::new(),
            out: Vec::new(),
        })
    }

    /// The building points scanned so far, voxel de-duplicated.
    pub fn resampled(&self) -> &[[f32; 3]] {
        self.merged.points()
    }

    /// Scans received so far (what the simulator sent less what DDS dropped).
    pub fn scans(&self) -> usize {
        self.scans
    }

    /// Keeps the merge in the store in `dir` (a batch at most every
    /// `every_s`), going on from what the store holds (a respawned explorer,
    /// a resumed mission): the points and scans read back.
    pub fn keep_merge_in(
        &mut self,
        dir: &std::path::Path,
        every_s: f64,
    ) -> Result<(KeptMerge, Stored), StoreError> {
        let (mut kept, stored) = KeptMerge::open(dir, self.config.resample_voxel_m, every_s)?;
        for p in &stored.points {
            self.merged.add(*p);
        }
        self.take_ids(&stored.ids);
        // A v1 store counted scans without ids.
        self.scans += stored.scans.saturating_sub(stored.ids.len());
        let batches = (self.merged.len(), self.ids.len());
        for p in &stored.journal.points {
            self.merged.add(*p);
        }
        self.take_ids(&stored.journal.ids);
        kept.resumed(batches, (self.merged.len(), self.ids.len()));
        // Scans received but not merged before the kill: merged now, and
        // batched at once so that their inbox segments can go.
        for p in &stored.inbox.points {
            self.merged.add(*p);
        }
        self.take_ids(&stored.inbox.ids);
        if !stored.inbox.ids.is_empty() {
            self.keep(&mut kept, 0.0, true)?;
        }
        if !self.merged.is_empty() {
            // The detector and the demo learn the merge so far as they would at a route's end.
            self.out.push(ExplorerCommand::Resampled);
        }
        Ok((kept, stored))
    }

    /// At shutdown: the last batch written to `kept`, and the line to log
    /// (scans received, points merged, what the store holds).
    pub fn stop(&self, kept: Option<&mut KeptMerge>) -> String {
        let stored = match kept.map(|k| self.keep(k, 0.0, true).map(|_| k.stored())) {
            None => "no store".to_string(),
            Some(Ok((p, s))) => format!("on disk: {p} points of {s} scans"),
            Some(Err(e)) => format!("the last batch could not be written: {e}"),
        };
        format!(
            "stopping: {} scans received, {} points merged; {stored}",
            self.scans,
            self.merged.len()
        )
    }

    /// Journals the scans merged since the last call in `kept`, and writes
    /// a batch when due (see [`KeptMerge::flush`]).
    pub fn keep(&self, kept: &mut KeptMerge, now_s: f64, force: bool) -> Result<usize, StoreError> {
        kept.flush(self.merged.points(), &self.ids, now_s, force)
    }

    /// Ids of the scans merged, in order.
    pub fn ids(&self) -> &[u64] {
        &self.ids
    }

    /// Whether the scan `id` is merged.
    pub fn has(&self, id: u64) -> bool {
        self.seen.contains(&id)
    }

    fn take_ids(&mut self, ids: &[u64]) {
        for &id in ids {
            if self.seen.insert(id) {
                self.ids.push(id);
                self.scans += 1;
            }
        }
    }

    /// The ground graph regions are explored on (once one was requested).
    pub fn graph(&self) -> Option<&GroundGraph> {
        self.graph.as_deref()
    }

    /// Takes in one event; returns what to do, in order.
    pub fn handle(&mut self, event: ExplorerEvent) -> Vec<ExplorerCommand> {
        let mut arrived = None;
        match event {
            ExplorerEvent::Cloud { xyz, labels } => {
                self.cloud = Some((xyz, labels));
                self.graph = None;
                self.applied = 0;
            }
            ExplorerEvent::Missing(m) => self.missing = m,
            ExplorerEvent::ActiveRegion(r) => {
                if r.is_none() {
                    self.active = None;
                }
                self.requested = r;
            }
            ExplorerEvent::Planner(s) => self.on_planner(s),
            ExplorerEvent::Scan { id, xyz, labels } => {
                if !self.seen.insert(id) {
                    self.out.push(ExplorerCommand::Error(format!(
                        "scan {} came again: left out",
                        super::scan_ids::format(id)
                    )));
                    return std::mem::take(&mut self.out);
                }
                self.ids.push(id);
                self.scans += 1;
                for q in merged_points(&xyz, labels.as_deref()) {
                    self.merged.add(q);
                }
                if let Some(a) = self.active.as_mut() {
                    a.pending.extend_from_slice(&xyz);
                }
            }
            ExplorerEvent::Position(p) => self.position = Some(p),
            ExplorerEvent::Vehicle(v) => arrived = self.on_vehicle(&v),
            ExplorerEvent::Tick => self.say(),
        }
        if self.start_region() {
            arrived = Some(true);
        }
        if let Some(ok) = arrived {
            self.at_viewpoint(ok);
        }
        std::mem::take(&mut self.out)
    }

    fn status(&self) -> ExplorerStatus {
        let state = match (&self.active, self.last_done) {
            (Some(a), _) => ExplorerState::Exploring {
                region: a.index,
                round: a.round,
                building: a.building,
                coverage: a.explorer.coverage(),
                viewpoints: a.stops,
            },
            (None, Some((region, round, coverage))) => ExplorerState::Done {
                region,
                round,
                coverage,
            },
            (None, None) => ExplorerState::Idle,
        };
        ExplorerStatus {
            state,
            resampled_points: self.merged.len(),
        }
    }

    fn say(&mut self) {
        self.out.push(ExplorerCommand::Status(self.status()));
    }

    fn on_planner(&mut self, s: PlannerStatus) {
        self.assigned = s.active_region.map(|(i, b)| (i, b, s.round));
        if s.blocked.len() > self.blocked.len() {
            self.blocked = s.blocked;
        }
        // The robot goes to another piece of ground: the graph is built again there.
        if s.phase == Phase::Carrying.word() {
            self.graph = None;
        }
        if s.phase == "done" && !self.published_rounds.contains(&s.round) {
            self.published_rounds.push(s.round);
            self.out.push(ExplorerCommand::Resampled);
        }
    }

    fn on_vehicle(&self, v: &VehicleStatus) -> Option<bool> {
        let goal = self.active.as_ref()?.goal?;
        v.is_for(goal)
            .then_some(matches!(v.event, VehicleEvent::Arrived))
    }

    /// The graph with every blocked spot taken out, built at the first region.
    fn ground(&mut self, at: [f32; 3]) -> Option<Arc<GroundGraph>> {
        if self.graph.is_none() {
            let (xyz, labels) = self.cloud.as_ref()?;
            match ground::build(xyz, labels, at, &self.config.graph, &self.blocked) {
                Ok(g) => {
                    self.graph = Some(Arc::new(g));
                    self.applied = self.blocked.len();
                }
                Err(e) => {
                    let e = format!("cannot build the ground graph: {e}");
                    self.out.push(ExplorerCommand::Error(e));
                    return None;
                }
            }
        }
        let g = self.graph.as_mut()?;
        if self.applied < self.blocked.len() {
            // No explorer holds the graph now, so this does not copy it.
            ground::apply(Arc::make_mut(g), &self.blocked[self.applied..]);
            self.applied = self.blocked.len();
        }
        Some(Arc::clone(g))
    }

    /// Starts the requested region once the planner's status names it; true when started.
    fn start_region(&mut self) -> bool {
        let (Some(region), Some((index, building, round)), Some(pos)) =
            (self.requested.clone(), self.assigned, self.position)
        else {
            return false;
        };
        let same = |i: usize, r: u32| i == index && r == round;
        if region.building != building
            || self.cloud.is_none()
            || self.active.as_ref().is_some_and(|a| same(a.index, a.round))
            || self.last_done.is_some_and(|(i, r, _)| same(i, r))
        {
            return false;
        }
        self.active = None;
        let Some(graph) = self.ground(pos) else {
            self.requested = None;
            return false;
        };
        let surface = surface(&region, &self.missing, self.config.surface_margin_m);
        let known: Vec<[f32; 3]> = self.cloud.as_ref().map_or_else(Vec::new, |(xyz, labels)| {
            xyz.iter()
                .zip(labels)
                .filter(|(_, l)| **l != class::GROUND)
                .map(|(q, _)| *q)
                .collect()
        });
        let n_surface = surface.len();
        match Explorer::new(&region, surface, &known, graph, &self.config.explore) {
            Ok(explorer) => {
                self.out.push(ExplorerCommand::Info(format!(
                    "exploring region {index} of round {round} (building {building}): {n_surface} surface samples, {} candidate viewpoints",
                    explorer.candidates()
                )));
                self.active = Some(Active {
                    index,
                    round,
                    building,
                    explorer,
                    goal: None,
                    pending: Vec::new(),
                    blocked: 0,
                    stops: 0,
                });
                // Every change of state goes out at once: a region can start
                // and end between two ticks.
                self.say();
                true
            }
            Err(e) => {
                self.out.push(ExplorerCommand::Error(format!(
                    "cannot explore region {index}: {e}; handing it back"
                )));
                self.last_done = Some((index, round, 0.0));
                self.requested = None;
                self.say();
                false
            }
        }
    }

    /// At a viewpoint (or blocked on the way): take the scans, go on or finish.
    fn at_viewpoint(&mut self, ok: bool) {
        let (Some(a), Some(pos)) = (self.active.as_mut(), self.position) else {
            return;
        };
        let pending = std::mem::take(&mut a.pending);
        a.explorer.update(pos, &pending);
        if !ok {
            a.blocked += 1;
        }
        let next = a.explorer.next_waypoints(pos);
        if a.explorer.done() || next.is_empty() || a.blocked > self.config.block_retries {
            self.out.push(ExplorerCommand::Info(format!(
                "region {} of round {} done: coverage {:.1} % after {} viewpoints",
                a.index,
                a.round,
                a.explorer.coverage() * 100.0,
                a.stops
            )));
            self.last_done = Some((a.index, a.round, a.explorer.coverage()));
            self.active = None;
            self.requested = None;
            self.say();
            // What the region added, for viewers; the detector re-runs only
            // on the cloud that follows the route's end.
            if self.config.publish_each_region {
                self.out.push(ExplorerCommand::Resampled);
            }
        } else if let Some(target) = next.first().copied() {
            let leg = a.explorer.path_to(pos, target);
            a.goal = leg.last().copied();
            a.stops += 1;
            self.out.push(ExplorerCommand::Leg(leg));
        }
    }
}

/// The missing points of the region's building within `margin` m of its polygon.
fn surface(region: &Region, missing: &[([f32; 3], u32)], margin: f64) -> Vec<[f32; 3]> {
    let ring: LineString<f64> = region.polygon.iter().map(|p| (p[0], p[1])).collect();
    let poly = Polygon::new(ring, vec![]);
    missing
        .iter()
        .filter(|(q, b)| {
            let p = Point::new(f64::from(q[0]), f64::from(q[1]));
            *b == region.building && Euclidean.distance(&p, &poly) <= margin
        })
        .map(|(q, _)| *q)
        .collect()
}

#[cfg(test)]
#[path = "explorer_tests.rs"]
mod tests;
