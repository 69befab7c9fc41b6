//! What a launcher follows of a mission: the planner's rounds and what each
//! reached, detection's rounds, and when the closed loop ends (docs/design.md,
//! step 9: stop when a round gains too little or after the last round).

use std::collections::{BTreeMap, BTreeSet};

use super::protocol::{Phase, PlannerStatus};
use crate::targets::TargetSet;

/// When the closed loop ends: a round that raised the mean detected
/// completeness by less than `min_round_gain` (0–1), or `max_rounds` driven.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StopRule {
    /// The least gain of a round worth another, 0–1.
    pub min_round_gain: f64,
    /// Rounds driven at most.
    pub max_rounds: u32,
}

/// Targets summed over rounds (kept in a resumable mission's progress).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Totals {
    /// Reached (dealt with and not given up).
    pub reached: usize,
    /// Given up after blocked tries.
    pub given_up: usize,
    /// Left off the route: the rest of it sees their gaps.
    pub seen: usize,
    /// Out of the route's reach.
    pub unreachable: usize,
    /// Set-downs the planner asked for.
    pub set_downs: usize,
}

impl Totals {
    /// Both counts added.
    pub fn plus(&self, o: &Totals) -> Totals {
        Totals {
            reached: self.reached + o.reached,
            given_up: self.given_up + o.given_up,
            seen: self.seen + o.seen,
            unreachable: self.unreachable + o.unreachable,
            set_downs: self.set_downs + o.set_downs,
        }
    }
    /// `o` taken off (never below zero).
    pub fn minus(&self, o: &Totals) -> Totals {
        Totals {
            reached: self.reached.saturating_sub(o.reached),
            given_up: self.given_up.saturating_sub(o.given_up),
            seen: self.seen.saturating_sub(o.seen),
            unreachable: self.unreachable.saturating_sub(o.unreachable),
            set_downs: self.set_downs.saturating_sub(o.set_downs),
        }
    }
}

/// A round whose route was driven to its end, as the planner reported it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FinishedRound {
    /// The round, from 1.
    pub round: u32,
    /// Points and regions dealt with (reached or given up).
    pub done: (usize, usize),
    /// Of `done`, given up after blocked tries.
    pub given_up: usize,
    /// Points left off as seen on the way.
    pub seen: usize,
    /// Targets out of reach.
    pub unreachable: usize,
    /// Set-downs.
    pub set_downs: usize,
}

/// The mission's progress from the planner's and the detector's statuses.
#[derive(Debug, Clone, Default)]
pub struct Progress {
    /// Detection rounds: (round, mean completeness over analysed buildings).
    pub detected: Vec<(u32, f64)>,
    /// The planner's last status (its round, phase, targets, tours).
    pub last: PlannerStatus,
    /// Summed over the finished rounds.
    pub totals: Totals,
    /// Routes driven to the end: (round, targets dealt with).
    pub rounds_finished: Vec<(u32, usize)>,
    /// The round being driven: what it reached and gave up so far (zero between rounds).
    pub round_so_far: Totals,
    /// A round planned after the first and the most it can gain ([`most_gain`]).
    pub prospect: Option<(u32, f64)>,
}

/// The most a round aiming at `targets` can raise the mean detected
/// completeness: the missing shares (0–1, per analysed building, from the
/// detection it was planned from) of the buildings its targets aim at,
/// over every analysed building; as if each of them became complete.
pub fn most_gain(targets: &TargetSet, missing: &BTreeMap<u32, f64>) -> f64 {
    if missing.is_empty() {
        return 0.0;
    }
    let aimed: BTreeSet<u32> = targets
        .points
        .iter()
        .map(|t| t.building)
        .chain(targets.regions.iter().map(|r| r.building))
        .collect();
    let sum: f64 = aimed.iter().filter_map(|b| missing.get(b)).sum();
    sum / missing.len() as f64
}

impl Progress {
    /// Detection's mean completeness for `round`; true when the round is new
    /// (a latched status comes again after a restart).
    pub fn detection(&mut self, round: u32, mean: f64) -> bool {
        if self.detected.last().is_some_and(|(r, _)| *r == round) {
            return false;
        }
        self.detected.push((round, mean));
        true
    }

    /// Points and regions of the planner's round dealt with (reached or given up).
    pub fn done(&self) -> (usize, usize) {
        let v = &self.last.visited;
        (v.points.len(), v.regions.len())
    }

    /// Targets of the planner's round.
    pub fn stops(&self) -> usize {
        self.last.target_points + self.last.target_regions
    }

    /// Takes the planner's status; the round it finishes, once per round.
    pub fn planner(&mut self, s: &PlannerStatus) -> Option<FinishedRound> {
        self.last.clone_from(s);
        let finished = self.rounds_finished.iter().any(|(r, _)| *r == s.round);
        let done = self.done();
        let given_up = s.given_up.points.len() + s.given_up.regions.len();
        if s.phase != Phase::Done.word() || finished {
            // A restarted planner's first statuses (round 0) are not the round's.
            if s.round > 0 && !finished {
                self.round_so_far = Totals {
                    reached: (done.0 + done.1).saturating_sub(given_up),
                    given_up,
                    ..Totals::default()
                };
            }
            return None;
        }
        self.round_so_far = Totals::default();
        let unreachable = s.unreachable_points + s.unreachable_regions;
        let f = FinishedRound {
            round: s.round,
            done,
            given_up,
            seen: s.seen_on_the_way.len(),
            unreachable,
            set_downs: s.set_downs,
        };
        self.rounds_finished.push((s.round, done.0 + done.1));
        self.totals.reached += (done.0 + done.1).saturating_sub(given_up);
        self.totals.given_up += given_up;
        self.totals.seen += f.seen;
        self.totals.unreachable += unreachable;
        self.totals.set_downs += f.set_downs;
        Some(f)
    }

    /// Targets over the finished rounds and the one being driven.
    pub fn totals_so_far(&self) -> Totals {
        self.totals.plus(&self.round_so_far)
    }

    /// Routes driven to the end that had somewhere to go.
    pub fn rounds_driven(&self) -> usize {
        self.rounds_finished.iter().filter(|(_, s)| *s > 0).count()
    }

    /// Round `round` (planned from the detection before it) can gain at
    /// most `most` (0–1, [`most_gain`]).
    pub fn prospect(&mut self, round: u32, most: f64) {
        self.prospect = Some((round, most));
    }

    /// Why the loop ends now, or `None` while it goes on. Round r is planned
    /// from detection r − 1; once it is driven, detection r says what it
    /// gained. A further round that cannot gain the least worth driving
    /// even if it completed every building it aims at is not driven.
    pub fn verdict(&self, rule: &StopRule) -> Option<String> {
        self.verdict_after(rule).or_else(|| {
            let &(r, _) = self.rounds_finished.last()?;
            let (next, most) = self.prospect.filter(|(n, _)| *n == r + 1)?;
            (most < rule.min_round_gain).then(|| {
                format!(
                    "round {next} could gain at most {:.2} % detected completeness, what the buildings it aims at miss (stop under {:.2} %): not driven",
                    most * 100.0,
                    rule.min_round_gain * 100.0
                )
            })
        })
    }

    /// [`Self::verdict`] on the rounds driven.
    fn verdict_after(&self, rule: &StopRule) -> Option<String> {
        let &(r, stops) = self.rounds_finished.last()?;
        if stops == 0 {
            return Some(format!(
                "round {r} left nothing to visit (no reachable target)"
            ));
        }
        let of = |k: u32| self.detected.iter().find(|(d, _)| *d == k).map(|(_, m)| *m);
        let gain = of(r)? - of(r.saturating_sub(1))?;
        (gain < rule.min_round_gain || self.rounds_driven() >= rule.max_rounds as usize).then(|| {
            format!(
                "round {r} gained {:.2} % detected completeness (stop under {:.2} % or after {} rounds)",
                gain * 100.0,
                rule.min_round_gain * 100.0,
                rule.max_rounds
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::route::Visited;

    const RULE: StopRule = StopRule {
        min_round_gain: 0.01,
        max_rounds: 2,
    };

    fn status(round: u32, phase: &str, points: usize, given_up: usize) -> PlannerStatus {
        PlannerStatus {
            phase: phase.into(),
            round,
            target_points: points + 1,
            target_regions: 1,
            visited: Visited {
                points: (0..points).collect(),
                regions: vec![0],
            },
            given_up: Visited {
                points: (0..given_up).collect(),
                regions: vec![],
            },
            seen_on_the_way: vec![points],
            unreachable_points: 0,
            unreachable_regions: 0,
            set_downs: 1,
            ..PlannerStatus::default()
        }
    }

    #[test]
    fn a_finished_round_is_counted_once_and_its_given_up_targets_apart() {
        let mut p = Progress::default();
        assert_eq!(p.planner(&status(1, "driving", 3, 1)), None);
        let done = p.planner(&status(1, "done", 4, 1)).expect("round 1 ends");
        assert_eq!(
            (done.round, done.done, done.given_up, done.seen),
            (1, (4, 1), 1, 1)
        );
        // The latched status again (a restarted planner): not a second round.
        assert_eq!(p.planner(&status(1, "done", 4, 1)), None);
        assert_eq!(p.rounds_finished, [(1, 5)]);
        assert_eq!(
            p.totals,
            Totals {
                reached: 4,
                given_up: 1,
                seen: 1,
                unreachable: 0,
                set_downs: 1
            }
        );
        assert_eq!(p.rounds_driven(), 1);
    }

    #[test]
    fn the_round_being_driven_counts_until_it_ends_and_a_restarted_planner_does_not_reset_it() {
        let mut p = Progress::default();
        p.planner(&status(1, "done", 4, 1));
        p.planner(&status(2, "driving", 3, 1));
        let so_far = p.totals_so_far();
        assert_eq!((so_far.reached, so_far.given_up), (4 + 3, 1 + 1));
        p.planner(&PlannerStatus::default());
        assert_eq!(
            p.totals_so_far(),
            so_far,
            "round 0: a planner starting again"
        );
        p.planner(&status(2, "done", 5, 1));
        let end = p.totals_so_far();
        assert_eq!((end.reached, end.given_up), (4 + 5, 2));
        assert_eq!(p.round_so_far, Totals::default());
    }

    #[test]
    fn the_loop_goes_on_while_a_round_gains_and_stops_when_it_does_not() {
        let mut p = Progress::default();
        assert!(p.detection(0, 0.80));
        assert!(!p.detection(0, 0.80), "a repeated round is not new");
        p.planner(&status(1, "done", 2, 0));
        // Round 1 driven, its detection not in yet: no verdict.
        assert_eq!(p.verdict(&RULE), None);
        p.detection(1, 0.90);
        assert_eq!(p.verdict(&RULE), None, "gained 10 %, one round of two");
        p.planner(&status(2, "done", 2, 0));
        p.detection(2, 0.905);
        let why = p.verdict(&RULE).expect("gained 0.5 %");
        assert!(why.starts_with("round 2 gained 0.50 %"), "{why}");
    }

    #[test]
    fn the_last_round_ends_the_loop_whatever_it_gained() {
        let rule = StopRule {
            max_rounds: 1,
            ..RULE
        };
        let mut p = Progress::default();
        p.detection(0, 0.5);
        p.planner(&status(1, "done", 2, 0));
        p.detection(1, 0.9);
        assert!(p.verdict(&rule).is_some());
    }

    #[test]
    fn a_further_round_that_cannot_gain_enough_is_not_driven() {
        use crate::targets::{Region, TargetPoint};
        let missing: BTreeMap<u32, f64> = [(1, 0.02), (2, 0.01), (3, 0.0), (4, 0.05)].into();
        let aim = |points: &[u32], regions: &[u32]| TargetSet {
            points: points
                .iter()
                .map(|&building| TargetPoint {
                    xyz: [0.0; 3],
                    building,
                })
                .collect(),
            regions: regions
                .iter()
                .map(|&building| Region {
                    building,
                    polygon: vec![],
                    z: 0.0,
                })
                .collect(),
        };
        // Buildings 1 and 2 (twice) miss 3 % between them, over 4 buildings.
        assert!((most_gain(&aim(&[1, 2, 2], &[]), &missing) - 0.0075).abs() < 1e-12);
        assert!((most_gain(&aim(&[1], &[4]), &missing) - 0.0175).abs() < 1e-12);
        assert_eq!(most_gain(&aim(&[9], &[]), &missing), 0.0, "not analysed");
        assert_eq!(most_gain(&aim(&[1], &[]), &BTreeMap::new()), 0.0);

        let rule = StopRule {
            max_rounds: 3,
            ..RULE
        };
        let mut p = Progress::default();
        p.detection(0, 0.5);
        // The first round is driven whatever it can gain.
        p.prospect(1, 0.001);
        assert_eq!(p.verdict(&rule), None);
        p.planner(&status(1, "done", 2, 0));
        p.detection(1, 0.9);
        assert_eq!(p.verdict(&rule), None, "gained 40 %");
        p.prospect(2, 0.02);
        assert_eq!(p.verdict(&rule), None, "round 2 may gain 2 %");
        p.prospect(2, 0.0075);
        let why = p.verdict(&rule).expect("round 2 can gain 0.75 % at most");
        assert!(
            why.starts_with("round 2 could gain at most 0.75 %"),
            "{why}"
        );
        // A prospect of another round says nothing of this one.
        p.prospect(3, 0.0);
        assert_eq!(p.verdict(&rule), None);
    }

    #[test]
    fn a_round_with_nothing_to_visit_ends_the_loop() {
        let mut p = Progress::default();
        let mut s = status(1, "done", 0, 0);
        s.visited = Visited::default();
        p.planner(&s);
        assert_eq!(
            p.verdict(&RULE).as_deref(),
            Some("round 1 left nothing to visit (no reachable target)")
        );
        assert_eq!(p.rounds_driven(), 0);
    }
}
