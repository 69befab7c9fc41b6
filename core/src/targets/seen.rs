//! Gaps seen on the way: the missing points a ground sensor has already had
//! in view from where the vehicle drove, by the same [`sees`] test that
//! consolidation chose the stops with. A stop whose every gap is seen
//! needs no visit: its LiDAR would see nothing new there.

use std::collections::HashMap;

use super::consolidate::sees;
use super::params::TargetParams;
use super::site::Site;
use crate::missing::MissingPoint;

/// The missing points of a round and which of them a pose has seen.
#[derive(Debug, Clone)]
pub struct SeenGaps {
    missing: Vec<MissingPoint>,
    seen: Vec<bool>,
    /// Missing points by square bucket of `bucket` metres, so a pose tests
    /// only the points within range.
    buckets: HashMap<(i32, i32), Vec<usize>>,
    bucket: f32,
}

impl SeenGaps {
    /// None seen yet; `range` is the farthest a pose sees (`params.stop_range`).
    pub fn new(missing: Vec<MissingPoint>, range: f32) -> Self {
        let bucket = range.max(1.0);
        let mut buckets: HashMap<(i32, i32), Vec<usize>> = HashMap::new();
        for (k, m) in missing.iter().enumerate() {
            buckets
                .entry(key(m.xyz[0], m.xyz[1], bucket))
                .or_default()
                .push(k);
        }
        SeenGaps {
            seen: vec![false; missing.len()],
            missing,
            buckets,
            bucket,
        }
    }

    /// Missing points in all.
    pub fn len(&self) -> usize {
        self.missing.len()
    }

    /// No missing points.
    pub fn is_empty(&self) -> bool {
        self.missing.is_empty()
    }

    /// Missing points seen so far.
    pub fn seen_count(&self) -> usize {
        self.seen.iter().filter(|&&s| s).count()
    }

    /// Marks every missing point a sensor at `xy` (on the ground there) sees.
    /// A pose off the site's ground sees nothing.
    pub fn look_from(&mut self, site: &Site, xy: [f32; 2], params: &TargetParams) {
        let Some(pose) = on_ground(site, xy) else {
            return;
        };
        for k in self.near(xy) {
            if !self.seen[k] && sees(site, pose, &self.missing[k], params) {
                self.seen[k] = true;
            }
        }
    }

    /// Whether a stop at `stop` would see nothing new: it sees at least one
    /// missing point, and every one it sees is seen already. A stop that
    /// sees none is kept (it was chosen for a reason this model misses).
    pub fn nothing_new_from(&self, site: &Site, stop: [f32; 3], params: &TargetParams) -> bool {
        let mut any = false;
        for k in self.near([stop[0], stop[1]]) {
            if sees(site, stop, &self.missing[k], params) {
                if !self.seen[k] {
                    return false;
                }
                any = true;
            }
        }
        any
    }

    fn near(&self, xy: [f32; 2]) -> Vec<usize> {
        let (i, j) = key(xy[0], xy[1], self.bucket);
        let mut out = Vec::new();
        for dj in -1..=1 {
            for di in -1..=1 {
                if let Some(v) = self.buckets.get(&(i + di, j + dj)) {
                    out.extend_from_slice(v);
                }
            }
        }
        out
    }
}

fn key(x: f32, y: f32, bucket: f32) -> (i32, i32) {
    ((x / bucket).floor() as i32, (y / bucket).floor() as i32)
}

fn on_ground(site: &Site, xy: [f32; 2]) -> Option<[f32; 3]> {
    let z = site.ground_at(xy[0], xy[1])?;
    z.is_finite().then_some([xy[0], xy[1], z])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::class;

    /// Flat ground 0..60 × 0..40 with a 10 m building block at x 20..30,
    /// y 20..30, and a wall gap on its south face (normal −y) at z 3.
    fn site_and_gaps() -> (Site, Vec<MissingPoint>) {
        let mut xyz = Vec::new();
        let mut labels = Vec::new();
        for j in 0..40 {
            for i in 0..60 {
                let (x, y) = (i as f32 + 0.5, j as f32 + 0.5);
                let inside = (20.0..30.0).contains(&x) && (20.0..30.0).contains(&y);
                xyz.push([x, y, if inside { 8.0 } else { 0.0 }]);
                labels.push(if inside {
                    class::BUILDING
                } else {
                    class::GROUND
                });
            }
        }
        let site = Site::from_cloud(&xyz, &labels, 1.0, 1.0).unwrap();
        let gaps = (0..5)
            .map(|k| MissingPoint {
                xyz: [22.0 + 1.5 * k as f32, 20.0, 3.0],
                building: 1,
                normal: [0.0, -1.0],
                skeleton: [25.0, 25.0],
            })
            .collect();
        (site, gaps)
    }

    #[test]
    fn a_stop_is_spared_once_the_way_has_seen_its_gaps() {
        let (site, gaps) = site_and_gaps();
        let p = TargetParams::default();
        let stop = [25.0, 12.0, 0.0];
        let mut seen = SeenGaps::new(gaps, p.stop_range);
        assert_eq!(seen.len(), 5);
        assert!(!seen.nothing_new_from(&site, stop, &p));
        // Driving along the building's north side: the south face is out of view.
        for x in 10..40 {
            seen.look_from(&site, [x as f32, 35.0], &p);
        }
        assert_eq!(seen.seen_count(), 0);
        assert!(!seen.nothing_new_from(&site, stop, &p));
        // Along the south street, 8 m out: every gap is in view.
        for x in 10..40 {
            seen.look_from(&site, [x as f32, 12.0], &p);
        }
        assert_eq!(seen.seen_count(), 5);
        assert!(seen.nothing_new_from(&site, stop, &p));
    }

    #[test]
    fn a_stop_that_sees_no_gap_is_kept() {
        let (site, gaps) = site_and_gaps();
        let p = TargetParams::default();
        let mut seen = SeenGaps::new(gaps, p.stop_range);
        for x in 10..40 {
            seen.look_from(&site, [x as f32, 12.0], &p);
        }
        // North of the block: none of the south gaps is in its view.
        assert!(!seen.nothing_new_from(&site, [25.0, 36.0, 0.0], &p));
        // Off the site: no ground to stand on, nothing marked, nothing to spare.
        let mut fresh = SeenGaps::new(site_and_gaps().1, p.stop_range);
        fresh.look_from(&site, [500.0, 500.0], &p);
        assert_eq!(fresh.seen_count(), 0);
    }
}
