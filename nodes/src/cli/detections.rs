//! The demo's record of each detection round (its per-building figures on
//! /completeness, its contours on /detection_markers, the targets made from
//! it) and their mapping onto the scene's true buildings: detection numbers
//! buildings its own way, so the per-building tables match by overlap.

use std::collections::BTreeMap;

use skyground_core::field::DetectedFigures;
use skyground_core::footprint::{Footprint, match_footprints};
use skyground_core::mission::protocol::BuildingStatus;
use skyground_core::targets::{Region, TargetPoint};
use skyground_msgs::builtin_interfaces::Time;
use skyground_msgs::visualization_msgs::MarkerArray;

use crate::convert::detection::detection_contours;

/// One detection round as the demo saw it.
#[derive(Debug, Default)]
struct Round {
    stamp: Option<Time>,
    statuses: Vec<BuildingStatus>,
    contours: Vec<Footprint>,
}

/// Every detection round, by round number, and every target set, by stamp
/// (a set belongs to the latest round stamped no later than it: latched
/// topics arrive in any order when the demo subscribes).
#[derive(Debug, Default)]
pub struct Detections {
    rounds: BTreeMap<u32, Round>,
    /// Contours whose /completeness has not come yet, by stamp.
    pending: Vec<(Time, Vec<Footprint>)>,
    points: BTreeMap<(i32, u32), Vec<TargetPoint>>,
    regions: BTreeMap<(i32, u32), Vec<Region>>,
}

fn key(t: Time) -> (i32, u32) {
    (t.sec, t.nanosec)
}

/// What one true building gets in the mission's per-building table.
#[derive(Debug, Clone, PartialEq)]
pub struct TrueBuildingRow {
    /// The first detection's figures (on the prior) of the detected building
    /// overlapping it most; `None` when none overlaps.
    pub detection: Option<DetectedFigures>,
    /// Point targets made for it, over all rounds.
    pub target_points: usize,
    /// Regions made for it, over all rounds.
    pub target_regions: usize,
}

impl Detections {
    /// A round's /completeness (all statuses share its round) with its stamp.
    pub fn completeness(&mut self, stamp: Time, statuses: Vec<BuildingStatus>) {
        let Some(round) = statuses.first().map(|s| s.round) else {
            return;
        };
        let r = self.rounds.entry(round).or_default();
        r.stamp = Some(stamp);
        r.statuses = statuses;
        if let Some(k) = self.pending.iter().position(|(t, _)| *t == stamp) {
            r.contours = self.pending.swap_remove(k).1;
        }
    }

    /// /detection_markers: each detected building's outer contour (the
    /// detector stamps them as its /completeness of the same round).
    pub fn markers(&mut self, stamp: Time, array: &MarkerArray) {
        let contours = detection_contours(array);
        match self.rounds.values_mut().find(|r| r.stamp == Some(stamp)) {
            Some(r) => r.contours = contours,
            None => self.pending.push((stamp, contours)),
        }
    }

    /// A point target set (/target_points) and its stamp.
    pub fn target_points(&mut self, stamp: Time, points: Vec<TargetPoint>) {
        self.points.insert(key(stamp), points);
    }

    /// A region set (/target_regions) and its stamp.
    pub fn target_regions(&mut self, stamp: Time, regions: Vec<Region>) {
        self.regions.insert(key(stamp), regions);
    }

    /// The round a set stamped `t` was made from: the latest stamped no later.
    fn round_of(&self, t: (i32, u32)) -> Option<u32> {
        self.rounds
            .iter()
            .filter_map(|(r, d)| d.stamp.map(|s| (key(s), *r)))
            .filter(|(s, _)| *s <= t)
            .max()
            .map(|(_, r)| r)
    }

    /// Per round, its last set of `sets` (a round's set may be sent again).
    fn last_sets<'a, T>(
        &self,
        sets: &'a BTreeMap<(i32, u32), Vec<T>>,
    ) -> BTreeMap<u32, &'a Vec<T>> {
        let mut out = BTreeMap::new();
        for (t, set) in sets {
            if let Some(r) = self.round_of(*t) {
                out.insert(r, set);
            }
        }
        out
    }

    /// One row per true building, in the order of `truth`.
    pub fn rows(&self, truth: &[Footprint]) -> Vec<TrueBuildingRow> {
        let mut rows: Vec<TrueBuildingRow> = truth
            .iter()
            .map(|_| TrueBuildingRow {
                detection: None,
                target_points: 0,
                target_regions: 0,
            })
            .collect();
        let (points, regions) = (self.last_sets(&self.points), self.last_sets(&self.regions));
        for (k, (r, round)) in self.rounds.iter().enumerate() {
            let to_truth = truth_of(&round.contours, truth);
            if k == 0 {
                for s in &round.statuses {
                    if let Some(&t) = to_truth.get(&s.building)
                        && rows[t].detection.is_none()
                    {
                        rows[t].detection = Some(figures(s));
                    }
                }
            }
            for p in points.get(r).into_iter().flat_map(|s| s.iter()) {
                if let Some(&t) = to_truth.get(&p.building) {
                    rows[t].target_points += 1;
                }
            }
            for g in regions.get(r).into_iter().flat_map(|s| s.iter()) {
                if let Some(&t) = to_truth.get(&g.building) {
                    rows[t].target_regions += 1;
                }
            }
        }
        rows
    }
}

/// Detection's figures from its status on /completeness.
fn figures(s: &BuildingStatus) -> DetectedFigures {
    DetectedFigures {
        footprint_id: s.footprint_id.clone(),
        points: s.points,
        skipped: s.skipped.clone(),
        boundary_points: s.boundary,
        missing_points: s.missing,
        r_missing: f64::from(s.r_missing),
        strategy: s.skipped.is_none().then_some(s.strategy),
    }
}

/// Detected id → index in `truth` of the true building it overlaps most.
fn truth_of(detected: &[Footprint], truth: &[Footprint]) -> BTreeMap<u32, usize> {
    let mut best: BTreeMap<u32, (f64, usize)> = BTreeMap::new();
    for (t, m) in match_footprints(detected, truth).iter().enumerate() {
        if m.derived == 0 {
            continue;
        }
        let e = best.entry(m.derived).or_insert((m.iou, t));
        if m.iou > e.0 {
            *e = (m.iou, t);
        }
    }
    best.into_iter().map(|(d, (_, t))| (d, t)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::{LineString, MultiPolygon, Polygon};
    use skyground_core::missing::Strategy;
    use skyground_msgs::geometry_msgs::Point;
    use skyground_msgs::visualization_msgs::Marker;

    fn square(id: u32, x: f64) -> Footprint {
        Footprint {
            id,
            polygon: MultiPolygon(vec![Polygon::new(
                LineString::from(vec![(x, 0.0), (x + 10.0, 0.0), (x + 10.0, 10.0), (x, 10.0)]),
                vec![],
            )]),
            name: String::new(),
        }
    }

    fn contour(id: u32, x: f64) -> Marker {
        let p = |x: f64, y: f64| Point { x, y, z: 0.0 };
        Marker {
            ns: format!("contour/{id}"),
            action: Marker::ADD,
            r#type: Marker::LINE_STRIP,
            points: vec![
                p(x, 0.5),
                p(x + 9.0, 0.5),
                p(x + 9.0, 9.5),
                p(x, 9.5),
                p(x, 0.5),
            ],
            ..Marker::default()
        }
    }

    fn status(building: u32, round: u32) -> BuildingStatus {
        BuildingStatus {
            building,
            footprint_id: format!("NL.IMBAG.Pand.{building}"),
            points: 100 * building as usize,
            round,
            skipped: None,
            r_missing: 0.25,
            missing: 5,
            boundary: 20,
            slices: 3,
            structures: 1,
            strategy: Strategy::PointBased,
            ground_z: 0.0,
        }
    }

    fn stamp(sec: i32) -> Time {
        Time { sec, nanosec: 0 }
    }

    #[test]
    fn detected_ids_map_onto_true_buildings_by_overlap_in_every_round() {
        // Truth: 7 at x 0, 9 at x 50. Round 0 numbers them 2 and 1; round 1
        // numbers them 1 and 2; its markers arrive before its statuses.
        let truth = [square(7, 0.0), square(9, 50.0)];
        let mut d = Detections::default();
        let tp = |building| TargetPoint {
            xyz: [0.0; 3],
            building,
        };
        // Round 0's targets (stamped 2) come before its statuses (stamped 1).
        d.target_points(stamp(2), vec![tp(1), tp(1), tp(2)]);
        d.completeness(stamp(1), vec![status(1, 0), status(2, 0)]);
        let markers = MarkerArray {
            markers: vec![contour(2, 0.0), contour(1, 50.0)],
        };
        d.markers(stamp(1), &markers);
        d.markers(
            stamp(3),
            &MarkerArray {
                markers: vec![contour(1, 0.0), contour(2, 50.0)],
            },
        );
        d.completeness(stamp(3), vec![status(1, 1), status(2, 1)]);
        // Round 1's first set is sent again, smaller: the last one counts.
        d.target_points(stamp(4), vec![tp(1), tp(2)]);
        d.target_points(stamp(5), vec![tp(1)]);
        d.target_regions(
            stamp(5),
            vec![Region {
                building: 2,
                polygon: vec![],
                z: 0.0,
            }],
        );
        let rows = d.rows(&truth);
        // True 7 is round 0's detected 2 (200 points), true 9 its detected 1.
        assert_eq!(rows[0].detection.as_ref().map(|f| f.points), Some(200));
        assert_eq!(rows[1].detection.as_ref().map(|f| f.points), Some(100));
        assert_eq!(
            rows[0]
                .detection
                .as_ref()
                .and_then(DetectedFigures::completeness),
            Some(0.75)
        );
        // Round 0: two targets for detected 1 (true 9), one for 2 (true 7);
        // round 1: one for detected 1 (true 7), a region for 2 (true 9).
        assert_eq!((rows[0].target_points, rows[0].target_regions), (2, 0));
        assert_eq!((rows[1].target_points, rows[1].target_regions), (2, 1));
        // A true building nothing overlaps gets no detection figures.
        let far = [square(3, 500.0)];
        assert_eq!(d.rows(&far)[0].detection, None);
        assert_eq!(d.rows(&far)[0].target_points, 0);
    }
}
