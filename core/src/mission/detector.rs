//! When completeness_detector runs (docs/design.md steps 2–3 and 8): once on
//! the aerial cloud, then once per finished route on the explorer's merged
//! cloud. The route's end (on /planner_status) and the merged cloud (on
//! /resampled_cloud) come from two publishers, so either can arrive first;
//! the gate runs detection when it holds both, in whichever order.
//! [`Detector`] holds the newest of each cloud for the detection it lets run.

use crate::cloud::Cloud;

/// What the detector has just received.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DetectorEvent {
    /// A (new) classified aerial cloud.
    Aerial,
    /// A merged cloud from the explorer.
    Resampled,
    /// The planner's status names this round's route as done.
    RouteDone(u32),
}

/// Decides, event by event, whether detection runs now.
#[derive(Debug, Clone, Default)]
pub struct DetectorGate {
    /// Without a planner every merged cloud re-runs detection.
    follows_planner: bool,
    has_aerial: bool,
    /// A merged cloud arrived that no detection has used yet.
    unused_cloud: bool,
    /// The newest round whose route is done.
    route_done: Option<u32>,
    /// The round the last merged-cloud detection ran for.
    detected_after: Option<u32>,
    /// A resumed mission: the first detection waits for the merge so far.
    wait_merge: bool,
    merge_seen: bool,
    detected_once: bool,
}

impl DetectorGate {
    /// A gate; `follows_planner` when /planner_status is subscribed.
    pub fn new(follows_planner: bool) -> Self {
        Self {
            follows_planner,
            ..Self::default()
        }
    }

    /// A gate for a resumed mission: the first detection runs on the aerial
    /// cloud and the merged cloud the explorer kept, whichever comes last.
    pub fn resuming(mut self) -> Self {
        self.wait_merge = true;
        self
    }

    /// Takes one event; true when detection should run now.
    pub fn handle(&mut self, e: DetectorEvent) -> bool {
        match e {
            DetectorEvent::Aerial => self.has_aerial = true,
            DetectorEvent::Resampled => {
                self.unused_cloud = true;
                self.merge_seen = true;
            }
            DetectorEvent::RouteDone(r) => {
                // A restarted planner may report an older round: keep the newest.
                if self.route_done.is_none_or(|d| r > d) {
                    self.route_done = Some(r);
                }
            }
        }
        if !self.has_aerial || (self.wait_merge && !self.merge_seen) {
            return false;
        }
        if self.wait_merge && !self.detected_once {
            // The merge so far is part of the first detection.
            self.detected_once = true;
            self.unused_cloud = false;
            return true;
        }
        let cloud_due = if self.follows_planner {
            self.unused_cloud && self.route_done.is_some() && self.route_done != self.detected_after
        } else {
            e == DetectorEvent::Resampled
        };
        if cloud_due {
            // A detection for any reason uses the newest merged cloud too.
            self.unused_cloud = false;
            self.detected_after = self.route_done;
        }
        cloud_due || e == DetectorEvent::Aerial
    }
}

/// The detector's inputs between detections: the newest aerial cloud (with
/// what came with it: the node keeps its message header) and the newest
/// merged cloud, the gate over them, and the round of the next detection.
#[derive(Debug, Clone)]
pub struct Detector<H> {
    gate: DetectorGate,
    aerial: Option<(Cloud, H)>,
    merged: Option<Cloud>,
    round: u32,
}

impl<H> Detector<H> {
    /// A detector holding nothing; `follows_planner` as [`DetectorGate::new`].
    pub fn new(follows_planner: bool) -> Self {
        Self {
            gate: DetectorGate::new(follows_planner),
            aerial: None,
            merged: None,
            round: 0,
        }
    }

    /// A detector for a resumed mission (see [`DetectorGate::resuming`]).
    pub fn resuming(mut self) -> Self {
        self.gate = self.gate.resuming();
        self
    }

    /// A classified aerial cloud and what came with it; true when detection runs now.
    pub fn aerial(&mut self, cloud: Cloud, with: H) -> bool {
        self.aerial = Some((cloud, with));
        self.gate.handle(DetectorEvent::Aerial)
    }

    /// A merged cloud from the explorer; true when detection runs now.
    pub fn merged(&mut self, cloud: Cloud) -> bool {
        self.merged = Some(cloud);
        self.gate.handle(DetectorEvent::Resampled)
    }

    /// The planner's route of `round` is done; true when detection runs now.
    pub fn route_done(&mut self, round: u32) -> bool {
        self.gate.handle(DetectorEvent::RouteDone(round))
    }

    /// What a detection runs on: the aerial cloud, what came with it and the
    /// merged cloud, if any; `None` before the aerial cloud.
    pub fn inputs(&self) -> Option<(&Cloud, &H, Option<&Cloud>)> {
        let (cloud, with) = self.aerial.as_ref()?;
        Some((cloud, with, self.merged.as_ref()))
    }

    /// The round of the next detection (0: the aerial cloud's).
    pub fn round(&self) -> u32 {
        self.round
    }

    /// A detection was published: the next one is of the next round.
    pub fn detected(&mut self) {
        self.round += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::DetectorEvent::{Aerial, Resampled, RouteDone};
    use super::*;

    /// What a fresh gate answers to each of `events`.
    fn gate(follows_planner: bool, events: &[DetectorEvent]) -> Vec<bool> {
        let mut g = DetectorGate::new(follows_planner);
        events.iter().map(|&e| g.handle(e)).collect()
    }

    #[test]
    fn a_resumed_gate_waits_for_the_kept_merge_in_either_order() {
        for events in [[Aerial, Resampled], [Resampled, Aerial]] {
            let mut g = DetectorGate::new(true).resuming();
            assert_eq!(events.map(|e| g.handle(e)), [false, true], "{events:?}");
            // The kept merge was used: the next detection waits for round 1.
            assert!(!g.handle(RouteDone(1)));
            assert!(g.handle(Resampled));
        }
    }

    #[test]
    fn the_aerial_cloud_runs_detection_at_once() {
        assert_eq!(gate(true, &[Aerial]), [true]);
    }

    #[test]
    fn route_end_before_cloud_runs_on_the_cloud() {
        let got = gate(true, &[Aerial, RouteDone(0), RouteDone(0), Resampled]);
        assert_eq!(got, [true, false, false, true]);
    }

    #[test]
    fn cloud_before_route_end_runs_on_the_route_end() {
        // The race the field test met: the explorer answers the planner's
        // "done" with its cloud before the detector has read that "done".
        assert_eq!(
            gate(true, &[Aerial, Resampled, RouteDone(0)]),
            [true, false, true]
        );
    }

    #[test]
    fn each_round_runs_once() {
        let events = [
            Aerial,
            RouteDone(0),
            Resampled,
            Resampled,
            RouteDone(0),
            Resampled,
            RouteDone(1),
        ];
        assert_eq!(
            gate(true, &events),
            [true, false, true, false, false, false, true]
        );
    }

    #[test]
    fn a_route_end_without_a_new_cloud_waits_for_one() {
        let events = [Aerial, RouteDone(0), Resampled, RouteDone(1), Resampled];
        assert_eq!(gate(true, &events), [true, false, true, false, true]);
    }

    #[test]
    fn nothing_runs_before_the_aerial_cloud() {
        // The aerial cloud's detection already uses round 0's merged cloud,
        // so round 0 is not detected twice.
        let events = [Resampled, RouteDone(0), Aerial, Resampled, RouteDone(1)];
        assert_eq!(gate(true, &events), [false, false, true, false, true]);
    }

    #[test]
    fn an_older_round_from_a_restarted_planner_is_ignored() {
        let events = [Aerial, RouteDone(1), Resampled, RouteDone(0), Resampled];
        assert_eq!(gate(true, &events), [true, false, true, false, false]);
    }

    #[test]
    fn the_detector_holds_the_newest_clouds_and_counts_rounds() {
        let cloud = |x: f32| Cloud::from_xyz(vec![[x, 0.0, 0.0]]);
        let mut d = Detector::new(true);
        assert!(
            !d.route_done(0) && d.inputs().is_none(),
            "nothing before the aerial cloud"
        );
        assert!(d.aerial(cloud(0.0), "aerial header"));
        let (aerial, with, merged) = d.inputs().expect("held");
        assert_eq!((aerial.xyz[0][0], *with), (0.0, "aerial header"));
        assert!(merged.is_none());
        d.detected();
        assert!(d.merged(cloud(1.0)), "route 0 done and its cloud in");
        d.detected();
        assert!(!d.route_done(1), "route 1 done, its cloud not yet in");
        assert!(d.merged(cloud(2.0)));
        assert_eq!(d.inputs().and_then(|i| i.2).map(|m| m.xyz[0][0]), Some(2.0));
        assert_eq!(d.round(), 2);
    }

    #[test]
    fn without_a_planner_every_cloud_runs_detection() {
        let events = [Resampled, Aerial, Resampled, Resampled];
        assert_eq!(gate(false, &events), [false, true, true, true]);
    }
}
