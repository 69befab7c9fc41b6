//! Stalls: what the watch sees of each node's progress, fed to
//! [`skyground_core::mission::watchdog`], and what is done with its verdict
//! (a silent node killed, so that the respawn starts it again with its
//! state; the mission stopped when restarts do not help).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use skyground_core::mission::watchdog::{Verdict, Watchdog, Watched};

use super::launch::Proc;

/// Wall seconds a node may owe its progress before it is restarted: with
/// the watch's 5-s check, a silent node is named within 30 s (issue 50).
const STALL_S: f64 = 25.0;
/// Restarts of one node in a row without its progress before the mission stops.
const STALL_RESTARTS: u32 = 3;
/// A move from the last pose counted shorter than this is standing, longer
/// a set-down (m).
const MOVE_M: (f32, f32) = (0.5, 5.0);

/// The mission's nodes as the watchdog follows them.
pub(super) struct Guard {
    dog: Watchdog,
    t0: Instant,
    /// The merge store's state file (its scans count is the explorer's progress).
    merge_state: PathBuf,
    scans: Option<u64>,
    last_pose: Option<[f32; 3]>,
    /// Each watched node's last work count (/work_progress) since it started.
    steps: BTreeMap<Watched, u64>,
}

impl Guard {
    pub fn new(t0: Instant, merge_store: &Path) -> Self {
        Guard {
            dog: Watchdog::new(STALL_S, STALL_RESTARTS),
            t0,
            merge_state: merge_store.join(skyground_core::explore::STATE_FILE),
            scans: None,
            last_pose: None,
            steps: BTreeMap::new(),
        }
    }

    fn now(&self) -> f64 {
        self.t0.elapsed().as_secs_f64()
    }

    /// A new robot time: vehicle_sim's progress; it owes the next.
    pub fn clock(&mut self) {
        self.dog.beat(Watched::VehicleSim, self.now());
    }

    /// A pose: a vehicle that drove owes merged scans from the explorer.
    pub fn pose(&mut self, p: [f32; 3]) {
        let q = *self.last_pose.get_or_insert(p);
        let d = (p[0] - q[0]).hypot(p[1] - q[1]);
        if d < MOVE_M.0 {
            return;
        }
        if d < MOVE_M.1 {
            self.dog.expect(Watched::LocalExplorer, self.now());
        }
        self.last_pose = Some(p);
    }

    /// A planner status (one every 0.5 s, in every phase): progress; it
    /// owes the next (a planner stopped between rounds would never plan the next).
    pub fn planner(&mut self) {
        self.dog.beat(Watched::GlobalPlanner, self.now());
    }

    /// A merged cloud arrived: the detector owes a detection.
    pub fn merged_cloud(&mut self) {
        self.dog.expect(Watched::CompletenessDetector, self.now());
    }

    /// A detection came.
    pub fn detected(&mut self) {
        self.dog.progress(Watched::CompletenessDetector);
    }

    /// Every 5 s: the explorer's merged scans read, then the verdict. A stalled node is killed (the respawn starts it
    /// again with its state); `Some(why)` stops the mission.
    pub fn check(&mut self, procs: &mut [Proc], say: &mut dyn FnMut(&str)) -> Option<String> {
        self.merged_scans();
        match self.dog.check(self.now()) {
            Verdict::Fine => None,
            Verdict::Restart { node, for_s } => {
                say(&format!(
                    "  {} stalled: {} for {for_s:.0} wall s; restarting it (restart {} in a row) with its state",
                    node.name(),
                    node.progress(),
                    self.dog.restarts(node)
                ));
                if let Some(p) = procs.iter_mut().find(|p| p.name == node.name()) {
                    let _ = p.child.start_kill();
                }
                // The next process counts from 0: its first count is no progress.
                self.steps.remove(&node);
                None
            }
            Verdict::GiveUp { node, restarts } => Some(format!(
                "{} stalled: {}, and {restarts} restarts in a row did not bring it back",
                node.name(),
                node.progress()
            )),
        }
    }

    /// The scans the explorer's store holds: a change is its progress.
    fn merged_scans(&mut self) {
        let scans = skyground_core::file::read(&self.merge_state)
            .ok()
            .and_then(|b| serde_json::from_slice::<serde_json::Value>(&b).ok())
            .and_then(|v| v.get("scans")?.as_u64());
        if scans.is_some() && scans != self.scans {
            self.scans = scans;
            self.dog.progress(Watched::LocalExplorer);
        }
    }

    /// `node`'s work count (on /work_progress every 2 s, from inside its
    /// long computations): one that moved is a node at work without showing
    /// it otherwise (a long replan or detection), so it owes its progress
    /// from now. CPU time is not progress: a node spinning in a busy loop
    /// uses all of it and does no work step.
    pub fn work(&mut self, node: &str, steps: u64) {
        let Some(w) = Watched::ALL.into_iter().find(|w| w.name() == node) else {
            return;
        };
        if self
            .steps
            .insert(w, steps)
            .is_some_and(|before| steps > before)
        {
            self.dog.working(w, self.now());
        }
    }
}
