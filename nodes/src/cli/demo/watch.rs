//! Watching: the mission's topics as they come, the progress they show, the
//! time limit that follows the work, and the stop rule
//! ([`skyground_core::mission::progress`]).

use std::collections::BTreeMap;
use std::path::Path;
use std::time::{Duration, Instant};

use futures::StreamExt;
use skyground_core::cloud::Cloud;
use skyground_core::metrics::MeasureSoFar;
use skyground_core::mission::progress::{Progress, StopRule, most_gain};
use skyground_core::mission::uav::{UavPlan, UavState, UavStatus};
use skyground_core::mission::{
    BuildingStatus, Phase, PlannerStatus, ProtocolError, VehicleStatus, Wire,
};
use skyground_core::route::{BudgetParams, PlannedWork, WorkLimit};
use skyground_core::targets::{TargetPoint, TargetSet};
use skyground_msgs::diagnostic_msgs::DiagnosticArray;
use skyground_msgs::nav_msgs::{Odometry, Path as RosPath};
use skyground_msgs::visualization_msgs::{Marker, MarkerArray};

use super::DemoArgs;
use super::console::Console;
use super::launch::{Proc, respawn};
use super::resume::Carried;
use super::stall::Guard;
use crate::cli::aerial::Survey;
use crate::cli::detections::Detections;
use crate::cli::profile::Profile;
use crate::convert::diagnostics::from_status;
use crate::convert::markers::markers_to_regions;
use crate::convert::path::odom_position;
use crate::runtime::{NodeRuntime, RuntimeError, qos, work_beat};
use crate::transport::{CloudSubscription, Received};

/// What the demo learns from the topics as the mission runs.
#[derive(Default)]
pub(super) struct Watch {
    /// Rounds, targets and the loop's verdict (`skyground_core::mission::progress`).
    pub progress: Progress,
    pub resampled: Option<Cloud>,
    pub route: Vec<[f32; 3]>,
    pub odometer: f64,
    pub sim_s: f64,
    /// The first /state_estimation stamp (the robot's clock when the mission started).
    first_stamp: Option<f64>,
    pub targets: TargetSet,
    /// Every detection round and the targets made from it.
    pub detections: Detections,
    /// The drone's plan and its last status (`--platforms ground,uav`).
    pub uav_plan: Option<UavPlan>,
    pub uav: Option<UavStatus>,
    /// The drone's positions, one every metre flown (for the overview).
    pub flight: Vec<[f32; 3]>,
    /// The last detection's round and each analysed building's missing share (0–1).
    missing: (u32, BTreeMap<u32, f64>),
}

impl Watch {
    /// A watch for a run that finishes a round an earlier run was driving:
    /// the detection it was planned from (`planned_from`) stands as this
    /// run's round 0, so the round's gain is measured from it, not from
    /// the merge so far, which already holds part of the round.
    fn going_on_from(planned_from: Option<f64>) -> Watch {
        let mut w = Watch::default();
        w.progress.detected.extend(planned_from.map(|m| (0, m)));
        w
    }

    /// Keeps the drone's position `p` when it is a metre from the last kept.
    fn flown(&mut self, p: [f32; 3]) {
        let far = |q: &[f32; 3]| (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f32>() > 1.0;
        if self.flight.last().is_none_or(far) {
            self.flight.push(p);
        }
    }

    /// Whether the drone has flown all it was given.
    fn uav_done(&self) -> bool {
        self.uav.as_ref().is_some_and(|s| s.state == UavState::Done)
    }
}

/// How the watch ended.
pub(super) struct Outcome {
    pub watch: Watch,
    /// The prior and every ground point that arrived, measured.
    pub after: MeasureSoFar,
    /// The stop rule ended the mission (not a limit, a signal or a fault).
    pub finished: bool,
    pub why: String,
    /// The mission over all its runs (this one and any it resumed).
    pub total: Carried,
}

/// The mission as the topics show it, and what is printed of it.
struct Follower<'a> {
    a: &'a DemoArgs,
    prior: &'a Survey,
    before: &'a MeasureSoFar,
    after: MeasureSoFar,
    coverage_now: f64,
    limit: TimeLimit,
    w: Watch,
    console: Console,
    t0: Instant,
    /// What earlier runs of a resumed mission did.
    carried: Carried,
    /// Each node's progress watched (a silent one is restarted).
    guard: Guard,
    /// What the planner had reached when its status was last kept for a restart.
    planner_kept: Option<(u32, usize, usize, usize)>,
    /// The last /state_estimation stamp.
    last_stamp: f64,
    /// vehicle_sim's starts so far (a new one is handed its leg).
    sim_starts: u32,
    /// The leg the vehicle drives (as the planner or explorer sent it), and
    /// when to hand it to a restarted vehicle_sim.
    leg: Option<RosPath>,
    /// The leg a restarted vehicle_sim is being handed, until a newer one goes out.
    handed: Option<RosPath>,
    resend_at: Vec<Instant>,
    uav_waiting_said: bool,
}

/// Follows the mission until the stop rule, the time limit, a signal or (in
/// field mode) a robot that never shows; nodes that exit are started again.
pub(super) async fn follow(
    rt: &mut NodeRuntime,
    (a, prior, before, carried): (&DemoArgs, &Survey, &MeasureSoFar, Carried),
    (procs, exe): (&mut [Proc], &Path),
    prof: &mut Profile,
    t0: Instant,
) -> Result<Outcome, RuntimeError> {
    let mut resampled_sub =
        CloudSubscription::new(rt, "/resampled_cloud", qos::latched(256), 65536)?;
    let mut targets_sub = CloudSubscription::new(rt, "/target_points", qos::latched(64), 65536)?;
    let completeness = rt.subscription::<DiagnosticArray>("/completeness", qos::latched(1))?;
    let planner = rt.subscription::<DiagnosticArray>("/planner_status", qos::latched(1))?;
    let vstatus = rt.subscription::<DiagnosticArray>("/vehicle_status", qos::reliable(50))?;
    let regions = rt.subscription::<MarkerArray>("/target_regions", qos::latched(1))?;
    let contours = rt.subscription::<MarkerArray>("/detection_markers", qos::latched(1))?;
    let odom = rt.subscription::<Odometry>("/state_estimation", qos::odometry())?;
    let uav_status = rt.subscription::<DiagnosticArray>("/uav/flight_status", qos::latched(1))?;
    let uav_plan = rt.subscription::<DiagnosticArray>("/uav/planner_status", qos::latched(1))?;
    let uav_odom = rt.subscription::<Odometry>("/uav/state_estimation", qos::odometry())?;
    let (us_s, up_s, uo_s) = (
        uav_status.async_stream(),
        uav_plan.async_stream(),
        uav_odom.async_stream(),
    );
    futures::pin_mut!(us_s, up_s, uo_s);
    // The leg being driven, kept to hand to a restarted vehicle_sim.
    let legs = rt.subscription::<RosPath>("/local_path", qos::reliable(10))?;
    let leg_pub = rt.publisher::<RosPath>("/local_path", qos::reliable(10))?;
    // Each node's work count: a long computation's progress, to the watchdog.
    let work = rt.subscription::<DiagnosticArray>(work_beat::TOPIC, qos::sensor(16))?;
    let (l_s, w_s) = (legs.async_stream(), work.async_stream());
    futures::pin_mut!(l_s, w_s);
    let (c_s, p_s, v_s, r_s, o_s, m_s) = (
        completeness.async_stream(),
        planner.async_stream(),
        vstatus.async_stream(),
        regions.async_stream(),
        odom.async_stream(),
        contours.async_stream(),
    );
    futures::pin_mut!(c_s, p_s, v_s, r_s, o_s, m_s);
    let mut f = Follower::new(a, prior, before, t0, carried);
    let mut tick = tokio::time::interval(Duration::from_secs(5));
    let mut respawn_tick = tokio::time::interval(Duration::from_millis(500));
    let rule = stop_rule(a, &carried);
    let robot_deadline =
        tokio::time::Instant::now() + Duration::from_secs_f64(a.field.robot_timeout);
    let mut why = String::from("interrupted");
    let finished = loop {
        tokio::select! {
            _ = tokio::time::sleep_until(f.limit.deadline()) => { why = f.limit.why(t0); break false }
            _ = tokio::time::sleep_until(robot_deadline), if a.field.field && f.w.first_stamp.is_none() => {
                why = format!("no /state_estimation from a robot within {} s (is it on ROS_DOMAIN_ID {}, and publishing nav_msgs/Odometry there?)", a.field.robot_timeout, rt.domain.domain_id);
                break false
            }
            _ = rt.shutdown.wait() => break false,
            r = resampled_sub.next() => if let Some(Received::Cloud { decoded, .. }) = r {
                f.resampled(decoded.cloud).await;
            },
            r = targets_sub.next() => if let Some(Received::Cloud { decoded, msg }) = r {
                f.targets(&decoded.cloud, msg.header.stamp);
            },
            Some(Ok((arr, _))) = r_s.next() => f.regions(&arr),
            Some(Ok((arr, _))) = m_s.next() => f.markers(&arr),
            Some(Ok((arr, _))) = c_s.next() => f.completeness(&arr),
            Some(Ok((arr, _))) = p_s.next() => f.planner(&arr, prof),
            Some(Ok((arr, _))) = v_s.next() => if let Some(s) = first_status(&arr, VehicleStatus::from_wire) {
                f.w.odometer = s.odometer_m;
            },
            Some(Ok((o, _))) = o_s.next() => f.odometry(&o),
            Some(Ok((arr, _))) = us_s.next() => f.w.uav = first_status(&arr, UavStatus::from_wire),
            Some(Ok((o, _))) = uo_s.next() => if let Some(p) = odom_position(&o) {
                f.w.flown(p);
            },
            Some(Ok((arr, _))) = up_s.next() => if let Some(p) = first_status(&arr, UavPlan::from_wire) {
                f.uav_plan(p);
            },
            Some(Ok((leg, _))) = l_s.next() => f.leg_seen(leg),
            Some(Ok((arr, _))) = w_s.next() => if let Some((node, steps)) = work_beat::read(&arr) {
                f.guard.work(node, steps);
            },
            _ = respawn_tick.tick() => if !rt.shutdown.requested() { f.respawn(procs, exe, &leg_pub).await? },
            _ = tick.tick() => if let Some(stalled) = f.tick(procs, prof) {
                why = stalled;
                break false;
            }
        }
        // The closed loop: detection after each driven round says whether
        // another is worth it.
        if let Some(v) = f.w.progress.verdict(&rule) {
            if !a.uav() || f.w.uav_done() {
                why = v;
                break true;
            }
            f.waiting_for_uav(&v);
        }
    };
    Ok(f.outcome(finished, why))
}

/// The loop's stop rule; a resumed mission drives the rounds its earlier runs left.
fn stop_rule(a: &DemoArgs, carried: &Carried) -> StopRule {
    StopRule {
        min_round_gain: a.min_round_gain,
        max_rounds: a.max_rounds.saturating_sub(carried.rounds).max(1),
    }
}

/// Every process's resources, the demo's own too, for the profile.
fn sample(procs: &[Proc], prof: &mut Profile) {
    for p in procs {
        prof.sample(p.name, p.child.id());
    }
    prof.sample("demo", Some(std::process::id()));
}

impl<'a> Follower<'a> {
    fn new(
        a: &'a DemoArgs,
        prior: &'a Survey,
        before: &'a MeasureSoFar,
        t0: Instant,
        carried: Carried,
    ) -> Self {
        Self {
            a,
            prior,
            before,
            after: before.clone(),
            coverage_now: before
                .measured(&prior.gt)
                .completeness
                .overall
                .ratio
                .unwrap_or(0.0),
            limit: TimeLimit::new(a),
            w: Watch::going_on_from(carried.planned_from),
            console: Console::new(),
            t0,
            carried,
            guard: Guard::new(t0, &a.merge_store()),
            planner_kept: None,
            last_stamp: 0.0,
            sim_starts: 0,
            leg: None,
            handed: None,
            resend_at: Vec::new(),
            uav_waiting_said: false,
        }
    }

    /// Every 500 ms: nodes that exited started again (vehicle_sim where the
    /// vehicle was), and a restarted vehicle_sim handed its leg.
    async fn respawn(
        &mut self,
        procs: &mut [Proc],
        exe: &Path,
        leg_pub: &ros2_client::Publisher<RosPath>,
    ) -> Result<(), RuntimeError> {
        respawn(procs, exe, &self.a.out, self.w.route.last().copied())?;
        let starts = procs.iter().find(|p| p.name == "vehicle_sim");
        if let Some(n) = starts.map(|p| p.restarts).filter(|n| *n > self.sim_starts) {
            // A restarted vehicle_sim gets the leg it was driving once its reader has matched.
            self.sim_starts = n;
            let now = Instant::now();
            self.resend_at = [2, 5, 10].map(|s| now + Duration::from_secs(s)).to_vec();
            self.handed = self.leg.clone();
        }
        if let Some(leg) = self.leg_due() {
            self.console
                .say("  handing the leg it was driving to the restarted vehicle_sim");
            let _ = leg_pub.async_publish(leg).await;
        }
        Ok(())
    }

    /// Every 5 s: the profile, the progress line and file, the watchdog
    /// (`Some(why)` ends the mission).
    fn tick(&mut self, procs: &mut [Proc], prof: &mut Profile) -> Option<String> {
        sample(procs, prof);
        self.state();
        self.keep_progress();
        if self.a.field.field {
            // A real robot is not ours to restart; the time limit follows it.
            return None;
        }
        let console = &mut self.console;
        self.guard.check(procs, &mut |line| console.say(line))
    }

    /// How the watch ended.
    fn outcome(mut self, finished: bool, why: String) -> Outcome {
        self.console.finish();
        self.keep_progress();
        Outcome {
            total: self.total(),
            watch: self.w,
            after: self.after,
            finished,
            why,
        }
    }

    /// The drone's plan: said, and its flight budgeted into the time limit
    /// (its sorties run beside the ground robot's rounds).
    fn uav_plan(&mut self, p: UavPlan) {
        let wall = 3.0 * p.flight_s / self.a.time_factor + 120.0;
        if self.limit.fixed.is_none() {
            let now = self.limit.start.elapsed().as_secs_f64();
            self.limit.limit.at_least(now + wall);
        }
        let line = if p.refused.is_empty() {
            format!(
                "  drone: {} of {} gaps no ground stop sees; {} viewpoints see {} of them; {} sortie(s), {:.0} s of flight",
                p.drone_gaps, p.gaps, p.viewpoints, p.seen, p.sorties, p.flight_s
            )
        } else {
            format!("  drone: no plan ({})", p.refused)
        };
        self.console.say(&line);
        self.w.uav_plan = Some(p);
    }

    /// Said once: the ground robot is done, the drone is not.
    fn waiting_for_uav(&mut self, verdict: &str) {
        if !self.uav_waiting_said {
            self.uav_waiting_said = true;
            self.console.say(&format!(
                "  ground mission done ({verdict}); waiting for the drone to land"
            ));
        }
    }

    /// The leg to send again now to a vehicle_sim that started again.
    fn leg_due(&mut self) -> Option<RosPath> {
        let now = Instant::now();
        let due = self.resend_at.iter().any(|t| *t <= now);
        self.resend_at.retain(|t| *t > now);
        due.then(|| self.handed.clone()).flatten()
    }

    /// A leg on /local_path (the planner's, the explorer's or our own
    /// hand-over). Once another than the one handed over goes out, the
    /// planner drives the restarted vehicle_sim again: handing the old leg
    /// after it would send the vehicle back and leave the new leg undriven.
    fn leg_seen(&mut self, leg: RosPath) {
        if self.handed.as_ref().is_some_and(|h| *h != leg) {
            self.resend_at.clear();
            self.handed = None;
        }
        self.leg = Some(leg);
    }

    /// The mission over all its runs so far.
    fn total(&self) -> Carried {
        let rounds = u32::try_from(self.w.progress.rounds_driven()).unwrap_or(u32::MAX);
        let at = self.w.route.last().copied();
        let targets = self.w.progress.totals_so_far();
        let open = self.w.progress.round_so_far;
        let mut c = self.carried.plus(
            (self.w.odometer, self.w.sim_s),
            rounds,
            at,
            (&targets, &open),
        );
        if let Some(&(_, mean)) = self.w.progress.detected.last() {
            c.planned_from = Some(mean);
        }
        c
    }

    /// progress.json, for `--resume` (a failed write is said, the mission goes on).
    fn keep_progress(&mut self) {
        if let Err(e) = super::resume::write(&self.a.out, &self.total()) {
            self.console.say(&format!("  progress.json: {e}"));
        }
    }

    /// The planner's status kept for a restarted planner when what it
    /// reached changed (a restarted one's round 0 is not its state), and
    /// the progress with it.
    fn keep_planner(&mut self, s: &PlannerStatus) {
        let reached = (
            s.round,
            s.visited.points.len() + s.visited.regions.len(),
            s.given_up.points.len() + s.given_up.regions.len(),
            s.blocked.len(),
        );
        if s.round == 0 || self.planner_kept == Some(reached) {
            return;
        }
        match s.keep(&self.a.out.join(super::resume::PLANNER_FILE)) {
            Ok(()) => {
                self.planner_kept = Some(reached);
                // The vehicle's place as each stop is dealt with: a resumed
                // run starts it there, not where the last 5 s tick saw it.
                self.keep_progress();
            }
            Err(e) => self
                .console
                .say(&format!("  keeping the planner's status: {e}")),
        }
    }

    /// The merged ground cloud so far: only its new points are measured.
    /// After a round's end it asks the detector for a detection.
    async fn resampled(&mut self, cloud: Cloud) {
        let last = &self.w.progress.last;
        if last.phase == "done"
            && self
                .w
                .progress
                .detected
                .last()
                .is_none_or(|(r, _)| *r < last.round)
        {
            self.guard.merged_cloud();
        }
        let new = arrived_points(self.w.resampled.as_ref(), &cloud, self.prior.cloud.origin);
        if new.len() == cloud.len() {
            self.after = self.before.clone();
        }
        let (scene, gt, mut so_far) = (
            self.prior.scene.clone(),
            self.prior.gt.clone(),
            self.after.clone(),
        );
        let measured = tokio::task::spawn_blocking(move || {
            so_far.add(&scene, &gt, &new);
            so_far
        })
        .await;
        match measured {
            Ok(m) => {
                self.after = m;
                let now = self.after.measured(&self.prior.gt);
                self.coverage_now = now.completeness.overall.ratio.unwrap_or(0.0);
                self.w.resampled = Some(cloud);
            }
            Err(e) => self
                .console
                .say(&format!("  measuring /resampled_cloud failed: {e}")),
        }
    }

    fn targets(&mut self, cloud: &Cloud, stamp: skyground_msgs::builtin_interfaces::Time) {
        let ids = cloud.building.clone().unwrap_or_default();
        self.w.targets.points = cloud
            .xyz
            .iter()
            .enumerate()
            .map(|(i, p)| TargetPoint {
                xyz: *p,
                building: ids.get(i).copied().unwrap_or(0),
            })
            .collect();
        self.w
            .detections
            .target_points(stamp, self.w.targets.points.clone());
    }

    fn regions(&mut self, arr: &MarkerArray) {
        self.w.targets.regions = markers_to_regions(arr).0;
        if let Some(m) = arr.markers.iter().find(|m| m.action == Marker::ADD) {
            self.w
                .detections
                .target_regions(m.header.stamp, self.w.targets.regions.clone());
        }
    }

    fn markers(&mut self, arr: &MarkerArray) {
        let contour = crate::convert::detection::CONTOUR_NS;
        if let Some(m) = arr.markers.iter().find(|m| m.ns.starts_with(contour)) {
            self.w.detections.markers(m.header.stamp, arr);
        }
    }

    fn completeness(&mut self, arr: &DiagnosticArray) {
        self.w
            .detections
            .completeness(arr.header.stamp, building_statuses(arr));
        self.guard.detected();
        let statuses = building_statuses(arr);
        if let Some(first) = statuses.first() {
            let missing = statuses
                .iter()
                .filter(|b| b.skipped.is_none())
                .map(|b| (b.building, f64::from(b.r_missing)))
                .collect();
            self.w.missing = (first.round, missing);
        }
        if let Some((round, mean, n)) = mean_completeness(arr)
            && self.w.progress.detection(round, mean)
        {
            let skipped = arr.status.len() - n;
            self.console.say(&format!(
                "  detection round {round}: mean detected completeness {:.1} % over {n} buildings{}",
                mean * 100.0,
                if skipped > 0 { format!(" ({skipped} skipped: no points or too few)") } else { String::new() }
            ));
        }
    }

    fn planner(&mut self, arr: &DiagnosticArray, prof: &mut Profile) {
        let Some(s) = first_status(arr, PlannerStatus::from_wire) else {
            return;
        };
        let finished_round = self.w.progress.planner(&s);
        self.aim(&s);
        self.guard.planner();
        self.keep_planner(&s);
        if s.round > 0 {
            prof.stage(&match s.phase.as_str() {
                "driving" | "exploring" | "carrying" => format!("round {} driving", s.round),
                _ => format!(
                    "round {} done: merge, classification, detection, next route",
                    s.round
                ),
            });
        }
        if matches!(s.phase.as_str(), "driving" | "exploring")
            && let Some(line) =
                self.limit
                    .follow(&self.w, f64::from(s.route_m), s.stops, s.target_regions)
        {
            self.console.say(&line);
        }
        if let Some(f) = finished_round {
            self.console.say(&format!(
                "  route of round {} done: {} points, {} regions (of them {} given up, blocked); {} left off (seen on the way); {} unreachable; {} set-downs",
                f.round, f.done.0, f.done.1, f.given_up, f.seen, f.unreachable, f.set_downs
            ));
            // A round's end is in progress.json before anything can kill the mission.
            self.keep_progress();
        }
        self.state();
    }

    /// The most the planner's round can gain, once its targets are the
    /// ones this watch holds and the detection it was planned from is known.
    fn aim(&mut self, s: &PlannerStatus) {
        let w = &mut self.w;
        let (detected, missing) = &w.missing;
        let same = s.target_points == w.targets.points.len()
            && s.target_regions == w.targets.regions.len();
        if s.round > 1 && *detected + 1 == s.round && same && s.phase != Phase::Done.word() {
            let most = most_gain(&w.targets, missing);
            w.progress.prospect(s.round, most);
        }
    }

    fn odometry(&mut self, o: &Odometry) {
        let t = o.header.stamp.secs();
        let field = self.a.field.field;
        if self.w.first_stamp.is_none() && field {
            self.console.say(&format!(
                "  robot found on /state_estimation after {:.1} s",
                self.t0.elapsed().as_secs_f64()
            ));
        }
        // A real robot stamps with its clock; the mission's time starts at
        // its first pose. vehicle_sim's clock starts at 0 in a new mission
        // and goes on after its last scan when restarted or resumed (its
        // stamps are the scans' ids): this run's time is past the carried.
        let first = *self.w.first_stamp.get_or_insert(t);
        if t != self.last_stamp {
            self.guard.clock();
        }
        self.last_stamp = t;
        self.w.sim_s = if field {
            t - first
        } else {
            self.w.sim_s.max(t - self.carried.sim_s)
        };
        if let Some(p) = odom_position(o) {
            self.guard.pose(p);
            if self
                .w
                .route
                .last()
                .is_none_or(|q| (q[0] - p[0]).hypot(q[1] - p[1]) > 1.0)
            {
                self.w.route.push(p);
            }
        }
    }

    /// The progress bar, or a line when the state changed.
    fn state(&mut self) {
        let last = &self.w.progress.last;
        let phase = if last.phase.is_empty() {
            "starting"
        } else {
            &last.phase
        };
        let stage = format!("round {} {phase}", last.round);
        let done = self.w.progress.done();
        let gain = format!("coverage {:.2} %", self.coverage_now * 100.0);
        let odometer = format!("{:.0} m driven, {:.0} sim s", self.w.odometer, self.w.sim_s);
        self.console.state(
            self.t0.elapsed().as_secs_f64(),
            (&stage, done.0 + done.1, self.w.progress.stops()),
            &gain,
            &odometer,
        );
    }
}

/// The buildings' statuses on /completeness (unreadable ones said on stderr).
fn building_statuses(arr: &DiagnosticArray) -> Vec<BuildingStatus> {
    arr.status
        .iter()
        .filter_map(|s| readable(BuildingStatus::from_wire(&from_status(s))))
        .collect()
}

/// The detection round and its mean completeness over the buildings detected.
fn mean_completeness(arr: &DiagnosticArray) -> Option<(u32, f64, usize)> {
    let all = building_statuses(arr);
    let vals: Vec<f64> = all
        .iter()
        .filter(|b| b.skipped.is_none())
        .map(|b| 1.0 - f64::from(b.r_missing))
        .collect();
    let round = all.first()?.round;
    (!vals.is_empty()).then(|| {
        let n = vals.len();
        (round, vals.iter().sum::<f64>() / n as f64, n)
    })
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

    /// Budgets the planner's route (`route_m` over `stops` stops) when it is
    /// a new one; the line to say when it is a new round's.
    fn follow(&mut self, w: &Watch, route_m: f64, stops: usize, regions: usize) -> Option<String> {
        if self.fixed.is_some() || !route_m.is_finite() {
            return None;
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
        let b = self.limit.follow(now, &work, &self.params)?;
        self.routes += 1;
        if w.progress.last.round <= self.printed_round {
            return None;
        }
        self.printed_round = w.progress.last.round;
        Some(format!(
            "  round {}: {route_m:.0} m over {} points and {regions_left} regions ≈ {:.0} simulated s; time limit {:.0} wall s from now, extended by each new route (--timeout fixes one)",
            w.progress.last.round,
            work.points,
            b.sim_s,
            self.limit.deadline_s() - now
        ))
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
    fn only_the_appended_points_are_new() {
        let (old, now) = (cloud(3), cloud(5));
        let new = arrived_points(Some(&old), &now, [7.0, 8.0, 9.0]);
        assert_eq!(new.xyz, vec![[3.0, 0.0, 0.0], [4.0, 0.0, 0.0]]);
        assert_eq!(new.label, None);
        // In the prior's frame, whatever the decoded message said.
        assert_eq!(new.origin, [7.0, 8.0, 9.0]);
        assert_eq!(arrived_points(None, &now, [0.0; 3]).len(), 5);
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

    #[test]
    fn a_square_outline_is_four_sides_long() {
        let sq = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]];
        assert!((perimeter(&sq) - 40.0).abs() < 1e-9);
    }
}
