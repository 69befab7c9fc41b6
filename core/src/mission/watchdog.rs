//! Progress watched per node, not only time. Each node the launcher
//! restarts owes progress while it should be working, and a node that owes
//! it for `stall_s` wall seconds is named and restarted:
//!
//! - vehicle_sim: its clock (odometry stamps) advances, always (while it
//!   drives and while it waits for orders);
//! - global_planner: its status comes (every tick, in every phase);
//! - local_explorer: the scans it merged grow after the vehicle moved;
//! - completeness_detector: a detection comes after a merged cloud arrived.
//!
//! A node that works without showing it (a long replan or detection on a
//! large scene) shows its work count ([`crate::work`]) advancing instead:
//! the launcher calls that [`Watchdog::working`]. CPU time is not progress:
//! a node spinning in a busy loop, as one stopped or blocked in its event
//! loop, shows none and is restarted. After `max_restarts` restarts of one
//! node in a row without its progress, the mission stops.

/// A node whose progress is watched.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Watched {
    /// The simulated vehicle.
    VehicleSim,
    /// The route's executive.
    GlobalPlanner,
    /// The region explorer, which merges the scans.
    LocalExplorer,
    /// Detection on the merged cloud.
    CompletenessDetector,
}

impl Watched {
    /// Every watched node, in the order they are checked.
    pub const ALL: [Watched; 4] = [
        Watched::VehicleSim,
        Watched::GlobalPlanner,
        Watched::LocalExplorer,
        Watched::CompletenessDetector,
    ];

    /// The node's name, as the launcher starts it.
    pub fn name(self) -> &'static str {
        match self {
            Watched::VehicleSim => "vehicle_sim",
            Watched::GlobalPlanner => "global_planner",
            Watched::LocalExplorer => "local_explorer",
            Watched::CompletenessDetector => "completeness_detector",
        }
    }

    /// The progress it owes, in words.
    pub fn progress(self) -> &'static str {
        match self {
            Watched::VehicleSim => "its clock (robot time) stood",
            Watched::GlobalPlanner => "no /planner_status came",
            Watched::LocalExplorer => "no scan was merged while the vehicle moved",
            Watched::CompletenessDetector => "no detection came after a merged cloud arrived",
        }
    }

    fn index(self) -> usize {
        self as usize
    }
}

/// What the watchdog asks for now.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Verdict {
    /// Every node shows its progress (or owes none).
    Fine,
    /// Restart `node`: it owed progress for `for_s` wall seconds.
    Restart {
        /// The silent node.
        node: Watched,
        /// Wall seconds it has owed progress.
        for_s: f64,
    },
    /// Stop the mission: `restarts` restarts of `node` in a row did not bring its progress.
    GiveUp {
        /// The node that stays silent.
        node: Watched,
        /// Restarts made since its last progress.
        restarts: u32,
    },
}

/// One node's account.
#[derive(Debug, Clone, Copy, Default)]
struct Account {
    /// Wall time since which it owes progress (`None`: it owes none).
    owed_since: Option<f64>,
    /// Restarts since its last progress.
    restarts: u32,
}

/// Follows every watched node's progress against the wall clock.
#[derive(Debug, Clone)]
pub struct Watchdog {
    stall_s: f64,
    max_restarts: u32,
    nodes: [Account; 4],
}

impl Watchdog {
    /// A node owing progress `stall_s` wall seconds is stalled;
    /// `max_restarts` restarts of one node in a row without progress end the mission.
    pub fn new(stall_s: f64, max_restarts: u32) -> Self {
        Watchdog {
            stall_s,
            max_restarts,
            nodes: [Account::default(); 4],
        }
    }

    /// `node` should show progress from wall time `wall_s` on (when it
    /// already owes some, from when it began to).
    pub fn expect(&mut self, node: Watched, wall_s: f64) {
        let a = &mut self.nodes[node.index()];
        a.owed_since.get_or_insert(wall_s);
    }

    /// `node` need not show progress now (its work is over).
    pub fn release(&mut self, node: Watched) {
        self.nodes[node.index()].owed_since = None;
    }

    /// `node` showed progress: it owes none and its restarts in a row end.
    pub fn progress(&mut self, node: Watched) {
        self.nodes[node.index()] = Account::default();
    }

    /// `node` showed progress at `wall_s` and owes more from then on (a
    /// node that should always be working, as the vehicle's clock).
    pub fn beat(&mut self, node: Watched, wall_s: f64) {
        self.progress(node);
        self.expect(node, wall_s);
    }

    /// `node` works without showing it (its work count advances, as in a
    /// long replan): when it owes progress, it owes it from `wall_s`, and
    /// its restarts in a row end.
    pub fn working(&mut self, node: Watched, wall_s: f64) {
        let a = &mut self.nodes[node.index()];
        if a.owed_since.is_some() {
            *a = Account {
                owed_since: Some(wall_s),
                restarts: 0,
            };
        }
    }

    /// Restarts of `node` since its last progress.
    pub fn restarts(&self, node: Watched) -> u32 {
        self.nodes[node.index()].restarts
    }

    /// What to do at wall time `wall_s`: the first stalled node is restarted
    /// (and owes progress again a whole period from now) or given up on.
    pub fn check(&mut self, wall_s: f64) -> Verdict {
        for node in Watched::ALL {
            let (stall_s, max) = (self.stall_s, self.max_restarts);
            let a = &mut self.nodes[node.index()];
            let Some(since) = a.owed_since else {
                continue;
            };
            let for_s = wall_s - since;
            if for_s < stall_s {
                continue;
            }
            if a.restarts >= max {
                return Verdict::GiveUp {
                    node,
                    restarts: a.restarts,
                };
            }
            a.restarts += 1;
            a.owed_since = Some(wall_s);
            return Verdict::Restart { node, for_s };
        }
        Verdict::Fine
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_moving_clock_is_fine_a_stopped_one_restarts_then_gives_up() {
        let v = Watched::VehicleSim;
        let mut w = Watchdog::new(30.0, 2);
        assert_eq!(w.check(100.0), Verdict::Fine, "no clock yet");
        w.beat(v, 0.0);
        w.beat(v, 20.0);
        assert_eq!(w.check(45.0), Verdict::Fine);
        assert_eq!(
            w.check(51.0),
            Verdict::Restart {
                node: v,
                for_s: 31.0
            }
        );
        assert_eq!(w.check(60.0), Verdict::Fine, "a period for the restart");
        assert!(matches!(w.check(81.0), Verdict::Restart { .. }));
        assert_eq!(w.restarts(v), 2);
        assert_eq!(
            w.check(112.0),
            Verdict::GiveUp {
                node: v,
                restarts: 2
            }
        );
    }

    #[test]
    fn progress_after_a_restart_resets_the_count() {
        let v = Watched::VehicleSim;
        let mut w = Watchdog::new(30.0, 1);
        w.beat(v, 0.0);
        assert!(matches!(w.check(31.0), Verdict::Restart { .. }));
        w.beat(v, 40.0);
        assert_eq!(w.restarts(v), 0);
        assert!(
            matches!(w.check(71.0), Verdict::Restart { .. }),
            "a new stall, not a give-up"
        );
    }

    #[test]
    fn a_planner_is_watched_only_while_a_round_runs() {
        let p = Watched::GlobalPlanner;
        let mut w = Watchdog::new(30.0, 3);
        w.beat(p, 0.0);
        w.release(p);
        assert_eq!(
            w.check(100.0),
            Verdict::Fine,
            "between rounds it owes nothing"
        );
        w.beat(p, 100.0);
        w.beat(p, 110.0);
        assert_eq!(w.check(139.0), Verdict::Fine);
        assert_eq!(
            w.check(141.0),
            Verdict::Restart {
                node: p,
                for_s: 31.0
            }
        );
    }

    #[test]
    fn a_node_at_work_is_not_stalled_but_owes_nothing_more_for_it() {
        let p = Watched::GlobalPlanner;
        let mut w = Watchdog::new(30.0, 3);
        w.working(p, 0.0);
        assert_eq!(
            w.check(100.0),
            Verdict::Fine,
            "working owes nothing by itself"
        );
        w.beat(p, 100.0);
        assert!(matches!(w.check(131.0), Verdict::Restart { .. }));
        w.working(p, 140.0);
        assert_eq!(w.restarts(p), 0);
        assert_eq!(w.check(169.0), Verdict::Fine);
        assert!(matches!(
            w.check(171.0),
            Verdict::Restart { for_s, .. } if for_s == 31.0
        ));
    }

    #[test]
    fn the_explorer_owes_scans_from_the_first_move_it_has_not_answered() {
        let e = Watched::LocalExplorer;
        let mut w = Watchdog::new(30.0, 3);
        w.expect(e, 10.0);
        // Moving on does not push the debt back.
        w.expect(e, 25.0);
        w.expect(e, 39.0);
        assert!(matches!(
            w.check(40.0),
            Verdict::Restart { node: Watched::LocalExplorer, for_s } if for_s == 30.0
        ));
        w.progress(e);
        assert_eq!(
            w.check(200.0),
            Verdict::Fine,
            "merged: owes nothing until the next move"
        );
    }

    #[test]
    fn the_detector_owes_a_detection_after_a_merged_cloud_and_nodes_are_named_in_order() {
        let (d, v) = (Watched::CompletenessDetector, Watched::VehicleSim);
        let mut w = Watchdog::new(30.0, 0);
        w.expect(d, 0.0);
        w.beat(v, 0.0);
        // Both stalled: the vehicle first; with no restarts allowed, it is given up on.
        assert_eq!(
            w.check(31.0),
            Verdict::GiveUp {
                node: v,
                restarts: 0
            }
        );
        w.beat(v, 31.0);
        assert_eq!(
            w.check(32.0),
            Verdict::GiveUp {
                node: d,
                restarts: 0
            }
        );
        w.progress(d);
        assert_eq!(w.check(33.0), Verdict::Fine);
        assert_eq!(
            Watched::CompletenessDetector.name(),
            "completeness_detector"
        );
    }

    #[test]
    fn a_long_replan_that_counts_its_work_is_kept_and_a_spinning_one_restarted() {
        let p = Watched::GlobalPlanner;
        let mut w = Watchdog::new(25.0, 3);
        // A 2-minute replan: no status, its work count moving every 2 s.
        w.beat(p, 0.0);
        for t in (2..120).step_by(2) {
            w.working(p, f64::from(t));
            assert_eq!(w.check(f64::from(t) + 1.0), Verdict::Fine, "at {t} s");
        }
        // Spinning (CPU, no work step) after its last step at 118 s: named 25 s on.
        assert_eq!(w.check(142.0), Verdict::Fine);
        assert!(matches!(w.check(143.5), Verdict::Restart { node, .. } if node == p));
    }
}
