//! The global planner's executive: waits for the classified cloud, the
//! target set and a position, plans a route (a new target set is a new
//! round), drives it leg by leg, hands regions to the explorer, takes
//! blocked spots out of the ground graph and replans, gives a stop up after
//! `block_retries` blocked tries, asks for the robot to be set down on
//! another piece of ground when targets remain that this piece does not
//! reach (up to `set_downs` a round), and goes on after a restart from its
//! own latched status.

use crate::graph::{GraphParams, GroundGraph};
use crate::missing::MissingPoint;
use crate::route::{
    Ground, Route, RouteError, RouteParams, Stop, Visited, drop_seen_on_the_way, next_set_down,
    replan, way_out,
};
use crate::targets::{Region, Site, TargetParams, TargetPoint, TargetSet};

use super::ground;
use super::kept_round::KeptRound;
use super::protocol::{
    BlockedSpot, ExplorerState, ExplorerStatus, Phase, PlannerStatus, VehicleEvent, VehicleStatus,
};

/// How far beyond the vehicle's radius the obstacle that blocked it is
/// looked for: the vehicle stops when its body is within one step of it.
pub const BLOCK_AHEAD_M: f32 = 0.4;

/// How near (in plan, metres) the robot must be to the set-down asked for
/// before the planner takes it as set down: a field team puts it down by eye.
pub const SET_DOWN_TOLERANCE_M: f32 = 3.0;

/// What the planner needs to know.
#[derive(Debug, Clone)]
pub struct PlannerConfig {
    /// Ground graph settings.
    pub graph: GraphParams,
    /// Route settings.
    pub route: RouteParams,
    /// Tries per stop before a blocked stop is given up.
    pub block_retries: u32,
    /// What a sensor on the ground sees (range, facing, field of view), for
    /// `route.skip_seen`: the target generator's settings.
    pub targets: TargetParams,
    /// Set-downs a round may ask for once the route is done and targets
    /// remain on other pieces of ground (0: never).
    pub set_downs: usize,
}

/// What happens to the planner.
#[derive(Debug, Clone)]
pub enum PlannerEvent {
    /// The classified cloud (new or again): the graph is rebuilt.
    Cloud {
        /// Points.
        xyz: Vec<[f32; 3]>,
        /// Their classes.
        labels: Vec<u8>,
    },
    /// The point half of a target set; `stamp` joins it with its regions.
    Points {
        /// Targets.
        points: Vec<TargetPoint>,
        /// The set's stamp.
        stamp: u64,
    },
    /// The region half of a target set.
    Regions {
        /// Regions.
        regions: Vec<Region>,
        /// The set's stamp.
        stamp: u64,
    },
    /// The round's missing points (for `route.skip_seen`).
    Missing(Vec<MissingPoint>),
    /// Where the vehicle is.
    Position([f32; 3]),
    /// The planner's own latched status, as a restarted planner finds it.
    Restore(PlannerStatus),
    /// The targets of the round that status was driving, as the planner
    /// kept them: with a matching status the planner finishes that round,
    /// whatever target set comes first (a resumed mission's new detection).
    RestoreRound(KeptRound),
    /// The vehicle arrived or is blocked.
    Vehicle(VehicleStatus),
    /// The explorer's state.
    Explorer(ExplorerStatus),
    /// Time passes: plan if needed, say where the mission is.
    Tick,
}

/// What the planner asks its node to do.
#[derive(Debug, Clone, PartialEq)]
pub enum PlannerCommand {
    /// Log at info level.
    Info(String),
    /// Log a warning.
    Warn(String),
    /// Log an error.
    Error(String),
    /// Publish the whole route.
    GlobalPath(Vec<[f32; 3]>),
    /// Send a leg to the vehicle.
    Leg(Vec<[f32; 3]>),
    /// Hand a region to the explorer (`None`: take it back).
    ActiveRegion(Option<Region>),
    /// Publish the status.
    Status(Box<PlannerStatus>),
    /// Ask for the robot to be carried to this spot (a node of another
    /// piece of ground); the plan goes on once it is there.
    SetDown([f32; 3]),
    /// Keep the new round's targets (for a resumed mission).
    KeepRound(Box<KeptRound>),
}

/// The global planner's state machine.
#[derive(Debug)]
pub struct Planner {
    config: PlannerConfig,
    cloud: Option<(Vec<[f32; 3]>, Vec<u8>)>,
    points: Option<(Vec<TargetPoint>, u64)>,
    regions: Option<(Vec<Region>, u64)>,
    /// Targets as of the last route; a new set is a new round.
    targets: TargetSet,
    round: u32,
    position: Option<[f32; 3]>,
    graph: Option<GroundGraph>,
    route: Option<Route>,
    visited: Visited,
    /// The part of `visited` given up after blocked tries.
    given_up: Visited,
    unreachable: (usize, usize),
    phase: Phase,
    need_plan: bool,
    retries: u32,
    restored: Option<PlannerStatus>,
    /// The restored round's targets, until a target set comes.
    kept: Option<KeptRound>,
    /// The stamp of the incoming set the kept round stood in for.
    stood_in_for: Option<u64>,
    blocked: Vec<BlockedSpot>,
    /// The site and the latest missing points (with `route.skip_seen`).
    site: Option<Site>,
    missing: Vec<MissingPoint>,
    /// Point stops of this round left off because the route sees their gaps anyway.
    seen_on_the_way: Vec<usize>,
    /// A node of each piece of ground this round's set-downs left or went
    /// to, and the set-downs asked for this round.
    pieces: Vec<[f32; 3]>,
    set_downs: usize,
    /// Where the robot is being carried to.
    carry_to: Option<[f32; 3]>,
    out: Vec<PlannerCommand>,
}

impl Planner {
    /// A planner waiting for its inputs.
    pub fn new(config: PlannerConfig) -> Self {
        Planner {
            config,
            cloud: None,
            points: None,
            regions: None,
            targets: TargetSet::default(),
            round: 0,
            position: None,
            graph: None,
            route: None,
            visited: Visited::default(),
            given_up: Visited::default(),
            unreachable: (0, 0),
            phase: Phase::Waiting,
            need_plan: false,
            retries: 0,
            restored: None,
            kept: None,
            stood_in_for: None,
            blocked: Vec::new(),
            site: None,
            missing: Vec::new(),
            seen_on_the_way: Vec::new(),
            pieces: Vec::new(),
            set_downs: 0,
            carry_to: None,
            out: Vec::new(),
        }
    }

    /// The mission round (1 for the first target set); counted here only.
    pub fn round(&self) -> u32 {
        self.round
    }

    /// Where the mission is.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// Takes in one event; returns what to do, in order.
    pub fn handle(&mut self, event: PlannerEvent) -> Vec<PlannerCommand> {
        match event {
            PlannerEvent::Cloud { xyz, labels } => {
                if self.config.route.skip_seen {
                    let t = &self.config.targets;
                    self.site = Site::from_cloud(&xyz, &labels, t.cell, t.clearance)
                        .map_err(|e| {
                            self.out
                                .push(PlannerCommand::Warn(format!("no site for skip_seen: {e}")))
                        })
                        .ok();
                }
                self.cloud = Some((xyz, labels));
                self.graph = None;
                self.need_plan = true;
            }
            PlannerEvent::Points { points, stamp } => {
                self.points = Some((points, stamp));
                self.need_plan = true;
            }
            PlannerEvent::Regions { regions, stamp } => {
                self.regions = Some((regions, stamp));
                self.need_plan = true;
            }
            PlannerEvent::Position(p) => self.on_position(p),
            PlannerEvent::Missing(m) => self.missing = m,
            PlannerEvent::Restore(s) => self.restore(s),
            PlannerEvent::RestoreRound(k) => {
                if self.route.is_none() {
                    self.kept = Some(k);
                }
            }
            PlannerEvent::Vehicle(v) => self.on_vehicle(&v),
            PlannerEvent::Explorer(e) => self.on_explorer(&e),
            PlannerEvent::Tick => {
                if self.need_plan {
                    self.plan();
                }
                self.out
                    .push(PlannerCommand::Status(Box::new(self.status())));
            }
        }
        std::mem::take(&mut self.out)
    }

    /// The status as it goes on /planner_status.
    pub fn status(&self) -> PlannerStatus {
        let route = self.route.as_ref();
        let active_region = match self.phase {
            Phase::Exploring(k) => match self.stop(k) {
                Some(Stop::Region(i)) => self.targets.regions.get(i).map(|r| (i, r.building)),
                _ => None,
            },
            _ => None,
        };
        PlannerStatus {
            phase: self.phase.word().into(),
            round: self.round,
            target_points: self.targets.points.len(),
            target_regions: self.targets.regions.len(),
            visited: self.visited.clone(),
            given_up: self.given_up.clone(),
            seen_on_the_way: self.seen_on_the_way.clone(),
            unreachable_points: self.unreachable.0,
            unreachable_regions: self.unreachable.1,
            stops: route.map_or(0, |r| r.order.len()),
            route_m: route.map_or(0.0, |r| r.length_m),
            greedy_m: route.map_or(0.0, |r| r.greedy_length_m),
            tsp_m: route.map_or(0.0, |r| r.tsp_length_m),
            active_region,
            blocked: self.blocked.clone(),
            set_downs: self.set_downs,
        }
    }

    fn stop(&self, k: usize) -> Option<Stop> {
        self.route.as_ref().and_then(|r| r.order.get(k)).copied()
    }

    fn restore(&mut self, s: PlannerStatus) {
        if self.route.is_some() || self.restored.is_some() {
            return;
        }
        self.out.push(PlannerCommand::Info(format!(
            "restored round {}: {} points and {} regions visited, {} blocked spots",
            s.round,
            s.visited.points.len(),
            s.visited.regions.len(),
            s.blocked.len()
        )));
        if let Some(g) = self.graph.as_mut() {
            ground::apply(g, &s.blocked);
        }
        self.blocked = s.blocked.clone();
        self.seen_on_the_way = s.seen_on_the_way.clone();
        self.restored = Some(s);
    }

    /// What the planner still lacks before it can plan, as the topics a
    /// user would check (`None` when it is not waiting or lacks nothing: a
    /// finished round waits for a new target set, which is no fault).
    pub fn waiting_for(&self) -> Option<String> {
        if self.phase != Phase::Waiting {
            return None;
        }
        let mut lacks: Vec<String> = [
            (self.cloud.is_none(), "/classified_cloud"),
            (self.points.is_none(), "/target_points"),
            (self.regions.is_none(), "/target_regions"),
            (self.position.is_none(), "/state_estimation"),
        ]
        .into_iter()
        .filter(|(lacking, _)| *lacking)
        .map(|(_, topic)| topic.to_owned())
        .collect();
        if let (Some((_, p)), Some((_, r))) = (&self.points, &self.regions)
            && p != r
        {
            // One half of a target set was missed: the pair never matches.
            lacks.push(format!(
                "the other half of a target set (/target_points stamped {p}, /target_regions {r})"
            ));
        }
        (!lacks.is_empty()).then(|| lacks.join(", "))
    }

    /// (Re)plans when every input is there.
    fn plan(&mut self) {
        let (
            Some((xyz, labels)),
            Some((points, t_points)),
            Some((regions, t_regions)),
            Some(position),
        ) = (
            self.cloud.as_ref(),
            self.points.as_ref(),
            self.regions.as_ref(),
            self.position,
        )
        else {
            return;
        };
        // The generator stamps both halves of a target set alike: wait for the pair;
        // while the explorer has the vehicle, plan when it hands back; while
        // the robot is carried, when it is set down.
        if t_points != t_regions || matches!(self.phase, Phase::Exploring(_) | Phase::Carrying) {
            return;
        }
        self.need_plan = false;
        if self.graph.is_none() {
            match ground::build(xyz, labels, position, &self.config.graph, &self.blocked) {
                Ok(g) => {
                    self.out.push(PlannerCommand::Info(format!(
                        "ground graph: {:?}",
                        g.report()
                    )));
                    self.graph = Some(g);
                }
                Err(e) => {
                    self.out.push(PlannerCommand::Error(format!(
                        "cannot build the ground graph: {e}"
                    )));
                    return;
                }
            }
        }
        let stamp = *t_points;
        let targets = TargetSet {
            points: points.clone(),
            regions: regions.clone(),
        };
        if self.stood_in_for != Some(stamp) && targets != self.targets {
            match self.kept_round() {
                Some(k) => {
                    self.out.push(PlannerCommand::Info(format!(
                        "round {}: going on with the kept round ({} points, {} regions, {} dealt with) in place of the target set stamped {stamp}",
                        k.round,
                        k.targets.points.len(),
                        k.targets.regions.len(),
                        self.restored.as_ref().map_or(0, |s| s.visited.points.len() + s.visited.regions.len()),
                    )));
                    self.stood_in_for = Some(stamp);
                    self.new_round(k.targets, k.stamp);
                }
                None => self.new_round(targets, stamp),
            }
        }
        let Some(graph) = self.graph.as_ref() else {
            return;
        };
        // Stops left off stay off when the route is made again (after a block).
        match replan(
            graph,
            &self.targets,
            &self.dealt_with(),
            position,
            &self.config.route,
        ) {
            Ok(route) => {
                let route = self.drop_seen(route);
                self.out.push(PlannerCommand::Info(format!(
                    "round {}: route over {} stops, {:.0} m (greedy {:.0} m, TSP {:.0} m, streets {:.0} m), {} points and {} regions unreachable",
                    self.round,
                    route.order.len(),
                    route.length_m,
                    route.greedy_length_m,
                    route.tsp_length_m,
                    route.streets_length_m,
                    route.unreachable_points.len(),
                    route.unreachable_regions.len(),
                )));
                self.unreachable = (
                    route.unreachable_points.len(),
                    route.unreachable_regions.len(),
                );
                self.out
                    .push(PlannerCommand::GlobalPath(route.waypoints.clone()));
                self.route = Some(route);
                self.out.push(PlannerCommand::ActiveRegion(None));
                self.start_leg(0);
            }
            // Spots the robot found blocked took out the ground around it.
            Err(RouteError::StartOffGraph { .. }) if self.carry_out() => {}
            Err(e) => self
                .out
                .push(PlannerCommand::Error(format!("cannot plan: {e}"))),
        }
    }

    /// With `route.skip_seen`, the route without the point stops whose
    /// gaps the rest of it sees anyway (they are remembered for the round).
    fn drop_seen(&mut self, route: Route) -> Route {
        let (Some(graph), Some(site)) = (self.graph.as_ref(), self.site.as_ref()) else {
            return route;
        };
        if !self.config.route.skip_seen || self.missing.is_empty() {
            return route;
        }
        let before = (route.order.len(), route.length_m);
        let d = drop_seen_on_the_way(
            graph,
            &route,
            &self.targets,
            (&self.missing, site),
            &self.config.targets,
            &self.config.route,
        );
        if !d.dropped.is_empty() {
            self.out.push(PlannerCommand::Info(format!(
                "round {}: {} of {} stops left off, the route sees their gaps anyway ({:.0} → {:.0} m)",
                self.round,
                d.dropped.len(),
                before.0,
                before.1,
                d.route.length_m
            )));
        }
        self.seen_on_the_way.extend(d.dropped);
        d.route
    }

    /// The kept round's targets when the restored status was driving them.
    fn kept_round(&mut self) -> Option<KeptRound> {
        let k = self.kept.take()?;
        let s = self.restored.as_ref()?;
        k.unfinished_in(s).then_some(k)
    }

    /// New targets: a new round, or the restored one if it matches.
    fn new_round(&mut self, targets: TargetSet, stamp: u64) {
        self.visited = Visited::default();
        self.given_up = Visited::default();
        self.seen_on_the_way.clear();
        self.retries = 0;
        self.set_downs = 0;
        self.pieces.clear();
        self.round += 1;
        if let Some(s) = self.restored.take()
            && s.target_points == targets.points.len()
            && s.target_regions == targets.regions.len()
        {
            self.round = s.round;
            self.visited = s.visited;
            self.given_up = s.given_up;
            self.seen_on_the_way = s.seen_on_the_way;
            self.set_downs = s.set_downs;
        }
        self.out.push(PlannerCommand::KeepRound(Box::new(KeptRound {
            round: self.round,
            stamp,
            targets: targets.clone(),
        })));
        self.targets = targets;
    }

    /// Sends leg `k` (the path to stop `k`) to the vehicle, or ends the route.
    fn start_leg(&mut self, k: usize) {
        let Some(route) = self.route.as_ref() else {
            return;
        };
        if k >= route.order.len() {
            self.route_done();
            return;
        }
        self.phase = Phase::Driving(k);
        self.out.push(PlannerCommand::Leg(leg(route, k)));
    }

    /// Asks for a set-down if one helps, else ends the round's driving.
    fn route_done(&mut self) {
        if self.carry_out() || self.ask_set_down() {
            return;
        }
        self.phase = Phase::Done;
        self.out.push(PlannerCommand::Info(format!(
            "round {}: route done",
            self.round
        )));
        self.out
            .push(PlannerCommand::Status(Box::new(self.status())));
    }

    /// The route is done: when set-downs are left this round and another
    /// piece of ground reaches a target not yet dealt with, asks for the
    /// robot there. True when it asked.
    fn ask_set_down(&mut self) -> bool {
        if self.set_downs >= self.config.set_downs {
            return false;
        }
        let Some((xyz, labels)) = self.cloud.as_ref() else {
            return false;
        };
        let ground = Ground {
            xyz,
            labels,
            params: &self.config.graph,
        };
        // The piece driven now is not asked for again this round (rebuilt
        // without its blocked spots, it might seem to reach what they cut off).
        if let Some(g) = self.graph.as_ref() {
            self.pieces
                .extend(g.positions().get(g.start_node()).copied());
        }
        let next = next_set_down(
            &ground,
            &self.targets,
            &self.dealt_with(),
            (&self.pieces, 0),
            &self.config.route,
        );
        let (_, set_down) = match next {
            Ok(Some(n)) => n,
            Ok(None) => return false,
            Err(e) => {
                self.out.push(PlannerCommand::Warn(format!(
                    "no set-down: the other pieces of ground cannot be planned: {e}"
                )));
                return false;
            }
        };
        self.pieces.push(set_down.start);
        let why = format!(
            "route done, {} more stops on another piece of ground",
            set_down.route.order.len()
        );
        self.carry(set_down.start, &why);
        true
    }

    /// Spots the robot found blocked have cut it off from every stop left
    /// (a dead end whose way out it reported blocked): when set-downs are
    /// left this round, asks for it to be carried to the nearest ground that
    /// still reaches one. True when it asked.
    fn carry_out(&mut self) -> bool {
        if self.set_downs >= self.config.set_downs || self.blocked.is_empty() {
            return false;
        }
        let (Some(graph), Some(at)) = (self.graph.as_ref(), self.position) else {
            return false;
        };
        let Some(to) = way_out(
            graph,
            &self.targets,
            &self.dealt_with(),
            at,
            &self.config.route,
        ) else {
            return false;
        };
        let why = format!(
            "the spots found blocked cut the robot off at ({:.1}, {:.1}) from every stop left",
            at[0], at[1]
        );
        self.carry(to, &why);
        true
    }

    /// Asks for the robot to be carried to `to` (a set-down of this round).
    fn carry(&mut self, to: [f32; 3], why: &str) {
        self.set_downs += 1;
        self.out.push(PlannerCommand::Warn(format!(
            "round {}: {why}: carry the robot to ({:.1}, {:.1}) (set-down {} of at most {})",
            self.round, to[0], to[1], self.set_downs, self.config.set_downs
        )));
        self.phase = Phase::Carrying;
        self.carry_to = Some(to);
        self.out.push(PlannerCommand::ActiveRegion(None));
        self.out.push(PlannerCommand::SetDown(to));
        self.out
            .push(PlannerCommand::Status(Box::new(self.status())));
    }

    /// Targets reached, given up, or left off as seen on the way this round.
    fn dealt_with(&self) -> Visited {
        Visited {
            points: [&self.visited.points[..], &self.seen_on_the_way[..]].concat(),
            regions: self.visited.regions.clone(),
        }
    }

    /// A new position; while the robot is carried, one near the set-down
    /// asked for ends the carry and the graph is built where it stands.
    fn on_position(&mut self, p: [f32; 3]) {
        self.position = Some(p);
        let (Phase::Carrying, Some(to)) = (self.phase, self.carry_to) else {
            return;
        };
        if (p[0] - to[0]).hypot(p[1] - to[1]) > SET_DOWN_TOLERANCE_M {
            return;
        }
        self.out.push(PlannerCommand::Info(format!(
            "robot set down at ({:.1}, {:.1}): planning on its piece of ground",
            p[0], p[1]
        )));
        self.carry_to = None;
        self.phase = Phase::Waiting;
        self.graph = None;
        self.need_plan = true;
    }

    fn on_explorer(&mut self, e: &ExplorerStatus) {
        let Phase::Exploring(k) = self.phase else {
            return;
        };
        let Some(Stop::Region(i)) = self.stop(k) else {
            return;
        };
        if let ExplorerState::Done {
            region,
            round,
            coverage,
        } = e.state
            && region == i
            && round == self.round
        {
            self.out.push(PlannerCommand::Info(format!(
                "region {i} explored (coverage {coverage})"
            )));
            self.visited.regions.push(i);
            self.out.push(PlannerCommand::ActiveRegion(None));
            self.start_leg(k + 1);
        }
    }

    fn on_vehicle(&mut self, v: &VehicleStatus) {
        // The robot cannot be put down there (vehicle_sim: off its terrain): the next piece, or done.
        if let (Phase::Carrying, Some(to), VehicleEvent::Blocked(why)) =
            (self.phase, self.carry_to, &v.event)
            && v.is_for(to)
        {
            self.out.push(PlannerCommand::Warn(format!(
                "set-down at ({:.1}, {:.1}) failed: {why}",
                to[0], to[1]
            )));
            self.carry_to = None;
            self.route_done();
            return;
        }
        let Phase::Driving(k) = self.phase else {
            return;
        };
        let Some(goal) = self.route.as_ref().and_then(|r| leg_goal(r, k)) else {
            return;
        };
        let ours = v.is_for(goal);
        match &v.event {
            VehicleEvent::Arrived if ours => self.arrived(k),
            VehicleEvent::Arrived => {}
            VehicleEvent::Blocked(_) => self.blocked_at(k, v, ours),
        }
    }

    fn arrived(&mut self, k: usize) {
        match self.stop(k) {
            Some(Stop::Point(i)) => {
                self.visited.points.push(i);
                self.retries = 0;
                self.start_leg(k + 1);
            }
            Some(Stop::Region(i)) => {
                self.phase = Phase::Exploring(k);
                let region = self.targets.regions.get(i).cloned();
                self.out.push(PlannerCommand::ActiveRegion(region));
                // The explorer joins the region with this status: send it at once.
                self.out
                    .push(PlannerCommand::Status(Box::new(self.status())));
            }
            None => {}
        }
    }

    /// Something the prior did not show stands between the vehicle and a
    /// pose of its leg: the graph forgets the ground just ahead of it, so
    /// later routes go around. The vehicle itself skips to the next pose;
    /// only when it gives up the leg's last one is a new route needed.
    fn blocked_at(&mut self, k: usize, v: &VehicleStatus, ours: bool) {
        if let Some(g) = self.graph.as_mut() {
            let (dx, dy) = (v.goal[0] - v.at[0], v.goal[1] - v.at[1]);
            let len = dx.hypot(dy);
            if len > 1e-3 {
                let ahead = g.params().vehicle_radius_m + BLOCK_AHEAD_M;
                let spot = BlockedSpot {
                    at: [v.at[0] + dx / len * ahead, v.at[1] + dy / len * ahead],
                    radius: ahead,
                };
                let cut = ground::apply(g, std::slice::from_ref(&spot));
                self.blocked.push(spot);
                self.out.push(PlannerCommand::Info(format!(
                    "blocked near ({:.1}, {:.1}): {cut} graph edges taken out",
                    spot.at[0], spot.at[1]
                )));
            }
        }
        if !ours {
            return;
        }
        // A per-stop count, kept across replans, gives the stop up when every
        // way round is blocked too.
        self.retries += 1;
        if self.retries > self.config.block_retries {
            let stop = self.stop(k);
            self.out.push(PlannerCommand::Warn(format!(
                "giving up stop {stop:?} after {} blocked tries",
                self.retries
            )));
            for v in [&mut self.visited, &mut self.given_up] {
                match stop {
                    Some(Stop::Point(i)) => v.points.push(i),
                    Some(Stop::Region(i)) => v.regions.push(i),
                    None => {}
                }
            }
            self.retries = 0;
        }
        // New way-points from where the vehicle is.
        self.need_plan = true;
        self.phase = Phase::Waiting;
    }
}

/// The way-points of leg `k`: from the previous stop's arrival to this one's.
fn leg(route: &Route, k: usize) -> Vec<[f32; 3]> {
    let from = if k == 0 {
        0
    } else {
        route.arrivals.get(k - 1).copied().unwrap_or(0)
    };
    let to = route.arrivals.get(k).copied().unwrap_or(from);
    match route.waypoints.get(from..=to) {
        Some(w) if !w.is_empty() => w.to_vec(),
        _ => route.waypoints.last().copied().into_iter().collect(),
    }
}

fn leg_goal(route: &Route, k: usize) -> Option<[f32; 3]> {
    route.waypoints.get(*route.arrivals.get(k)?).copied()
}

#[cfg(test)]
#[path = "planner_tests.rs"]
mod tests;
