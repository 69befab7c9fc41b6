//! Target consolidation: one stop serves every gap its sensor sees from
//! there. A greedy set cover of the missing points by the candidate stops
//! (every building's point targets together, so adjacent buildings share
//! stops), with range, facing, field-of-view and line-of-sight checks on
//! the site grid.

use std::collections::HashMap;

use serde::{Deserialize, Serialize};

use super::generate::{occluded, own_wall};
use super::params::TargetParams;
use super::site::Site;
use super::types::TargetPoint;
use crate::missing::MissingPoint;

/// What consolidation kept and what the kept stops still see.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Consolidation {
    /// Candidate stops given.
    pub stops_before: usize,
    /// Stops kept.
    pub stops_after: usize,
    /// Missing points some candidate sees.
    pub seen_before: usize,
    /// Missing points some kept stop sees.
    pub seen_after: usize,
    /// Missing points considered.
    pub missing: usize,
}

/// Whether a sensor at `stop` (on the ground, `params.sensor_height` up)
/// sees the missing point `m`: within `params.stop_range`, in front of its
/// wall (at most `params.max_incidence_deg` off the wall's normal), inside
/// the vertical field of view, and no other building in between.
pub fn sees(site: &Site, stop: [f32; 3], m: &MissingPoint, params: &TargetParams) -> bool {
    let v = [stop[0] - m.xyz[0], stop[1] - m.xyz[1]];
    let d = v[0].hypot(v[1]);
    if !(d > 0.5 && d <= params.stop_range) {
        return false;
    }
    let dir = [v[0] / d, v[1] / d];
    let facing = dir[0] * m.normal[0] + dir[1] * m.normal[1];
    if facing < params.max_incidence_deg.to_radians().cos() {
        return false;
    }
    let dz = m.xyz[2] - (stop[2] + params.sensor_height);
    if dz.abs() > d * params.half_fov_deg.to_radians().tan() {
        return false;
    }
    !occluded(site, m.xyz, dir, d, own_wall(site, params))
}

/// The fewest stops (greedily) that still see every missing point the
/// candidates see. Kept stops come in the order they were chosen (most
/// gaps first); each keeps the building whose gaps it sees most.
/// `params.stop_range` ≤ 0 turns consolidation off (all candidates kept).
pub fn consolidate(
    candidates: &[TargetPoint],
    missing: &[MissingPoint],
    site: &Site,
    params: &TargetParams,
) -> (Vec<TargetPoint>, Consolidation) {
    let cover = coverage(candidates, missing, site, params);
    let seen_before = {
        let mut s = vec![false; missing.len()];
        cover.iter().flatten().for_each(|&k| s[k] = true);
        s.iter().filter(|&&b| b).count()
    };
    if params.stop_range <= 0.0 {
        let c = Consolidation {
            stops_before: candidates.len(),
            stops_after: candidates.len(),
            seen_before,
            seen_after: seen_before,
            missing: missing.len(),
        };
        return (candidates.to_vec(), c);
    }
    let mut seen = vec![false; missing.len()];
    let mut gain: Vec<usize> = cover.iter().map(Vec::len).collect();
    let mut kept = Vec::new();
    // Lazy greedy would be faster; a few thousand candidates need no more.
    // The candidate seeing most unseen gaps (the earliest on ties) is kept next.
    while let Some((best, _)) = gain
        .iter()
        .enumerate()
        .filter(|(_, g)| **g > 0)
        .max_by(|(i, a), (j, b)| a.cmp(b).then(j.cmp(i)))
    {
        let mut by_building: HashMap<u32, usize> = HashMap::new();
        for &k in &cover[best] {
            if !seen[k] {
                seen[k] = true;
                *by_building.entry(missing[k].building).or_default() += 1;
            }
        }
        let building = by_building
            .into_iter()
            .max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(&a.0)))
            .map_or(candidates[best].building, |(b, _)| b);
        kept.push(TargetPoint {
            xyz: candidates[best].xyz,
            building,
        });
        for (c, g) in cover.iter().zip(gain.iter_mut()) {
            *g = c.iter().filter(|&&k| !seen[k]).count();
        }
    }
    let c = Consolidation {
        stops_before: candidates.len(),
        stops_after: kept.len(),
        seen_before,
        seen_after: seen.iter().filter(|&&b| b).count(),
        missing: missing.len(),
    };
    (kept, c)
}

/// For each candidate, the missing points (indices) it sees; missing
/// points are bucketed by `stop_range` cells so each candidate looks at
/// its 3 × 3 neighbourhood only.
fn coverage(
    candidates: &[TargetPoint],
    missing: &[MissingPoint],
    site: &Site,
    params: &TargetParams,
) -> Vec<Vec<usize>> {
    let r = params.stop_range.max(params.downsample).max(1.0);
    let key = |p: [f32; 3]| ((p[0] / r).floor() as i64, (p[1] / r).floor() as i64);
    let mut buckets: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (k, m) in missing.iter().enumerate() {
        buckets.entry(key(m.xyz)).or_default().push(k);
    }
    candidates
        .iter()
        .map(|c| {
            let (i, j) = key(c.xyz);
            let mut out = Vec::new();
            for di in -1..=1 {
                for dj in -1..=1 {
                    for &k in buckets.get(&(i + di, j + dj)).into_iter().flatten() {
                        if sees(site, c.xyz, &missing[k], params) {
                            out.push(k);
                        }
                    }
                }
            }
            out
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Flat ground 0..w × 0..h with building boxes (x0, y0, x1, y1) of
    /// height 6 m, on a 1 m grid.
    fn site(w: usize, h: usize, boxes: &[[f32; 4]], params: &TargetParams) -> Site {
        let (mut xyz, mut labels) = (Vec::new(), Vec::new());
        for i in 0..w {
            for j in 0..h {
                let (x, y) = (i as f32 + 0.5, j as f32 + 0.5);
                let inside = boxes
                    .iter()
                    .any(|b| x >= b[0] && x <= b[2] && y >= b[1] && y <= b[3]);
                xyz.push([x, y, if inside { 6.0 } else { 0.0 }]);
                labels.push(if inside { 6 } else { 2 });
            }
        }
        Site::from_cloud(&xyz, &labels, params.cell, params.clearance).unwrap()
    }

    /// Missing points along the south wall (y = y0) of a box, every metre, 2 m up.
    fn south_wall(b: [f32; 4], building: u32) -> Vec<MissingPoint> {
        let mut v = Vec::new();
        let mut x = b[0] + 0.5;
        while x < b[2] {
            v.push(MissingPoint {
                xyz: [x, b[1], 2.0],
                building,
                normal: [0.0, -1.0],
                skeleton: [x, (b[1] + b[3]) / 2.0],
            });
            x += 1.0;
        }
        v
    }

    #[test]
    fn adjacent_buildings_share_stops_and_nothing_seen_is_lost() {
        let p = TargetParams::default();
        // Two 12 m houses side by side with a 4 m gap, both missing their south wall.
        let (a, b) = ([10.0, 30.0, 22.0, 40.0], [26.0, 30.0, 38.0, 40.0]);
        let s = site(60, 60, &[a, b], &p);
        let mut missing = south_wall(a, 1);
        missing.extend(south_wall(b, 2));
        // One candidate per 2 m of wall at the 10 m standoff, as generation does before merging.
        let candidates: Vec<TargetPoint> = missing
            .iter()
            .step_by(2)
            .map(|m| TargetPoint {
                xyz: [m.xyz[0], m.xyz[1] - 10.0, 0.0],
                building: m.building,
            })
            .collect();
        let (kept, c) = consolidate(&candidates, &missing, &s, &p);
        assert_eq!(c.stops_before, 12);
        assert_eq!(c.seen_before, missing.len(), "{c:?}");
        assert_eq!(c.seen_after, c.seen_before, "{c:?}");
        // 28 m of wall seen from 10 m at up to 70° off the normal: ~55 m
        // wide at the wall, so two or three stops do, not twelve.
        assert!(c.stops_after <= 3, "{c:?}");
        assert_eq!(kept.len(), c.stops_after);
        assert!(
            kept.iter()
                .all(|k| candidates.iter().any(|c| c.xyz == k.xyz))
        );
    }

    #[test]
    fn a_building_in_between_or_the_back_of_a_wall_is_not_seen() {
        let p = TargetParams::default();
        let (a, blocker) = ([10.0, 30.0, 22.0, 40.0], [10.0, 22.0, 18.0, 25.0]);
        let s = site(60, 60, &[a, blocker], &p);
        let m = south_wall(a, 1)[6];
        // Straight in front, 12 m out, behind the low block: hidden.
        assert!(!sees(&s, [m.xyz[0], 18.0, 0.0], &m, &p));
        // Beside the block, in front of the wall: seen.
        assert!(sees(&s, [28.0, 22.0, 0.0], &m, &p));
        // Behind the wall (north of the house): never.
        assert!(!sees(&s, [m.xyz[0], 45.0, 0.0], &m, &p));
        // Out of range.
        assert!(!sees(
            &s,
            [m.xyz[0], 30.0 - p.stop_range - 1.0, 0.0],
            &m,
            &p
        ));
        let off = TargetParams {
            stop_range: 0.0,
            ..p.clone()
        };
        let cands = vec![
            TargetPoint {
                xyz: [28.0, 22.0, 0.0],
                building: 1,
            };
            3
        ];
        assert_eq!(consolidate(&cands, &[m], &s, &off).0.len(), 3);
        assert_eq!(consolidate(&cands, &[m], &s, &p).0.len(), 1);
    }
}
