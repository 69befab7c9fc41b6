//! Targets from a detection (docs/design.md step 4): point targets on rays from
//! the skeleton through each missing point, region targets around clusters
//! of missing boundary.

use std::collections::HashSet;

use geo::{ConvexHull, MultiPoint, Orient, Point, orient::Direction};
use serde::{Deserialize, Serialize};

use super::params::TargetParams;
use super::site::Site;
use super::types::{Region, TargetPoint, TargetSet};
use crate::missing::{Detection, MissingPoint, Strategy};
use crate::params::ParamError;

/// Candidate targets dropped, by reason.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Dropped {
    /// Inside (or within clearance of) a building.
    pub inside_building: usize,
    /// Inside (or within clearance of) vegetation.
    pub inside_vegetation: usize,
    /// Off the known ground (outside the site or no ground height).
    pub off_ground: usize,
    /// A building stands between the candidate and its wall.
    pub occluded: usize,
    /// Merged into a nearby target by downsampling.
    pub merged: usize,
    /// Missing points for which no standoff was usable.
    pub unserved: usize,
}

/// Missing points closer to their skeleton point than this are rayed along
/// the stored normal only (no usable skeleton direction).
const STEP: f32 = 0.5;
/// Beyond the clearance and a cell's diagonal, this much more of the
/// building's own (grown) cells may lie at the start of a ray: walls are
/// not exactly on cell edges and the missing point may sit behind its wall.
const OWN_WALL_MARGIN: f32 = 1.0;

/// Targets for every analysed building of `detection` on `site`.
/// Point-based buildings get point targets, region-based ones regions
/// (clusters too small for a hull fall back to point targets).
pub fn generate(
    detection: &Detection,
    site: &Site,
    params: &TargetParams,
) -> Result<(TargetSet, Dropped), ParamError> {
    params.validate()?;
    let mut set = TargetSet::default();
    let mut dropped = Dropped::default();
    for b in detection.buildings.iter().filter(|b| b.skipped.is_none()) {
        let for_points: Vec<MissingPoint> = match b.strategy {
            Strategy::PointBased => b.missing.clone(),
            Strategy::RegionBased => {
                let (regions, rest) = regions(&b.missing, site, b.ground_z, params);
                set.regions.extend(regions);
                rest
            }
        };
        let mut seen: HashSet<(i64, i64)> = HashSet::new();
        for m in &for_points {
            let mut served = false;
            let candidates = standoff_candidates(m, site, params, &mut dropped);
            for p in candidates {
                let key = (
                    (p[0] / params.downsample).floor() as i64,
                    (p[1] / params.downsample).floor() as i64,
                );
                served = true;
                if seen.insert(key) {
                    set.points.push(TargetPoint {
                        xyz: p,
                        building: b.building,
                    });
                } else {
                    dropped.merged += 1;
                }
            }
            if !served {
                dropped.unserved += 1;
            }
        }
    }
    Ok((set, dropped))
}

/// The open-ground position on the ray from the skeleton through `m` at the
/// nearest standoff from which the sensor's vertical field of view reaches
/// `m`'s height (the farthest open one when none does).
fn standoff_candidates(
    m: &MissingPoint,
    site: &Site,
    params: &TargetParams,
    dropped: &mut Dropped,
) -> Vec<[f32; 3]> {
    let n = m.normal;
    let len = n[0].hypot(n[1]);
    if !(len.is_finite() && len > 0.0) {
        return Vec::new();
    }
    let dir = [n[0] / len, n[1] / len];
    let tan_fov = params.half_fov_deg.to_radians().tan();
    let mut standoffs = params.standoffs.clone();
    standoffs.sort_by(f32::total_cmp);
    let mut open = Vec::new();
    for &d in &standoffs {
        let p = [m.xyz[0] + dir[0] * d, m.xyz[1] + dir[1] * d];
        let Some(k) = site.index(p[0], p[1]) else {
            dropped.off_ground += 1;
            continue;
        };
        if site.building[k] {
            dropped.inside_building += 1;
            continue;
        }
        if site.vegetation[k] {
            dropped.inside_vegetation += 1;
            continue;
        }
        let g = site.ground.heights[k];
        if !g.is_finite() {
            dropped.off_ground += 1;
            continue;
        }
        if occluded(site, m.xyz, dir, d, own_wall(site, params)) {
            dropped.occluded += 1;
            continue;
        }
        let sees = (m.xyz[2] - (g + params.sensor_height)).abs() <= d * tan_fov;
        open.push(([p[0], p[1], g], sees));
    }
    // The nearest standoff that sees the point: nearer means denser returns
    // and fewer things in between; farther ones only for higher walls.
    open.iter()
        .find(|(_, sees)| *sees)
        .or(open.last())
        .map(|(p, _)| *p)
        .or_else(|| alley_stop(m, dir, site, params))
        .into_iter()
        .collect()
}

/// Where every standoff is blocked, the middle of the open stretch right in
/// front of the wall, if it is at least a cell long: in an alley narrower
/// than the least standoff every standoff lands in the building opposite,
/// yet a robot driving down the alley sees its lower walls best.
fn alley_stop(
    m: &MissingPoint,
    dir: [f32; 2],
    site: &Site,
    params: &TargetParams,
) -> Option<[f32; 3]> {
    let at = |t: f32| [m.xyz[0] + dir[0] * t, m.xyz[1] + dir[1] * t];
    let cell_at = |t: f32| {
        let p = at(t);
        site.index(p[0], p[1])
    };
    // The ground height where a robot may stand at `t`.
    let open = |t: f32| {
        cell_at(t)
            .filter(|&k| !site.building[k] && !site.vegetation[k])
            .map(|k| site.ground.heights[k])
            .filter(|g| g.is_finite())
    };
    let own = own_wall(site, params);
    let reach = params.standoffs.iter().copied().fold(0.0, f32::max);
    let mut t = 0.0;
    while cell_at(t).is_some_and(|k| site.building[k]) {
        t += STEP;
        if t > own {
            return None;
        }
    }
    let start = t;
    while t <= reach && open(t).is_some() {
        t += STEP;
    }
    let end = t - STEP;
    if end - start < site.cell() {
        return None;
    }
    let mid = 0.5 * (start + end);
    let [x, y] = at(mid);
    Some([x, y, open(mid)?])
}

/// How far a ray may run through its own building's grown cells.
pub(super) fn own_wall(site: &Site, params: &TargetParams) -> f32 {
    params.clearance + site.cell() * std::f32::consts::SQRT_2 + OWN_WALL_MARGIN
}

/// Whether building cells lie on the ray once it has left the building it
/// starts on: the first run of building cells (at most `own` metres) is the
/// building's own wall, any building cell after a free one blocks the view.
pub(super) fn occluded(site: &Site, from: [f32; 3], dir: [f32; 2], d: f32, own: f32) -> bool {
    let mut t = 0.0;
    let mut leaving = true;
    while t < d {
        let k = site.index(from[0] + dir[0] * t, from[1] + dir[1] * t);
        let inside = k.is_some_and(|k| site.building[k]);
        if leaving {
            if !inside {
                leaving = false;
            } else if t > own {
                return true;
            }
        } else if inside {
            return true;
        }
        t += STEP;
    }
    false
}

/// Missing points pushed out by the buffer, linked into clusters; each
/// cluster of ≥ 3 distinct points becomes a convex region, the rest go back
/// as point targets.
fn regions(
    missing: &[MissingPoint],
    site: &Site,
    ground_z: f32,
    params: &TargetParams,
) -> (Vec<Region>, Vec<MissingPoint>) {
    let pushed: Vec<[f64; 2]> = missing
        .iter()
        .map(|m| {
            [
                (m.xyz[0] + m.normal[0] * params.region_buffer) as f64,
                (m.xyz[1] + m.normal[1] * params.region_buffer) as f64,
            ]
        })
        .collect();
    let clusters = link_clusters(&pushed, params.region_link as f64);
    let mut regions = Vec::new();
    let mut rest = Vec::new();
    for members in clusters {
        let hull = MultiPoint(
            members
                .iter()
                .map(|&k| Point::new(pushed[k][0], pushed[k][1]))
                .collect(),
        )
        .convex_hull()
        .orient(Direction::Default);
        let mut ring: Vec<[f64; 2]> = hull.exterior().0.iter().map(|c| [c.x, c.y]).collect();
        if ring.len() > 1 && ring.first() == ring.last() {
            ring.pop();
        }
        if ring.len() < 3 {
            rest.extend(members.iter().map(|&k| missing[k]));
            continue;
        }
        let (cx, cy) = ring
            .iter()
            .fold((0.0, 0.0), |(x, y), p| (x + p[0], y + p[1]));
        let c = [
            (cx / ring.len() as f64) as f32,
            (cy / ring.len() as f64) as f32,
        ];
        regions.push(Region {
            building: missing[members[0]].building,
            polygon: ring,
            z: site.ground_at(c[0], c[1]).unwrap_or(ground_z),
        });
    }
    (regions, rest)
}

/// Single-linkage clusters of `pts` at distance `link` (grid-bucketed union-find).
fn link_clusters(pts: &[[f64; 2]], link: f64) -> Vec<Vec<usize>> {
    let mut parent: Vec<usize> = (0..pts.len()).collect();
    fn root(parent: &mut [usize], mut k: usize) -> usize {
        while parent[k] != k {
            parent[k] = parent[parent[k]];
            k = parent[k];
        }
        k
    }
    let key = |p: &[f64; 2]| ((p[0] / link).floor() as i64, (p[1] / link).floor() as i64);
    let mut buckets: std::collections::HashMap<(i64, i64), Vec<usize>> =
        std::collections::HashMap::new();
    for (k, p) in pts.iter().enumerate() {
        buckets.entry(key(p)).or_default().push(k);
    }
    for (k, p) in pts.iter().enumerate() {
        let (i, j) = key(p);
        for di in -1..=1 {
            for dj in -1..=1 {
                let Some(others) = buckets.get(&(i + di, j + dj)) else {
                    continue;
                };
                for &o in others {
                    let q = pts[o];
                    if o > k && (p[0] - q[0]).hypot(p[1] - q[1]) <= link {
                        let (a, b) = (root(&mut parent, k), root(&mut parent, o));
                        parent[a] = b;
                    }
                }
            }
        }
    }
    let mut groups: std::collections::BTreeMap<usize, Vec<usize>> =
        std::collections::BTreeMap::new();
    for k in 0..pts.len() {
        let r = root(&mut parent, k);
        groups.entry(r).or_default().push(k);
    }
    groups.into_values().collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 40 m × 40 m of ground (0.5 m lattice) with two 10 m high blocks,
    /// x 5..35, one y 5..15 and the other from y 15 + `gap` on, 10 m deep.
    fn alley(gap: f32) -> Site {
        let (mut xyz, mut labels) = crate::geom::fixtures::flat_ground(80, 80, 0.5);
        for [x, y, _] in xyz.clone() {
            let in_a = (5.0..35.0).contains(&x) && (5.0..15.0).contains(&y);
            let in_b = (5.0..35.0).contains(&x) && (15.0 + gap..25.0 + gap).contains(&y);
            if in_a || in_b {
                xyz.push([x, y, 10.0]);
                labels.push(crate::cloud::class::BUILDING);
            }
        }
        Site::from_cloud(&xyz, &labels, 1.0, 1.0).expect("site")
    }

    fn wall_gap() -> MissingPoint {
        MissingPoint {
            xyz: [20.0, 15.0, 1.0],
            building: 1,
            normal: [0.0, 1.0],
            skeleton: [20.0, 10.0],
        }
    }

    #[test]
    fn a_wall_on_a_narrow_alley_gets_a_stop_in_the_alley() {
        let params = TargetParams::default();
        let mut dropped = Dropped::default();
        let stops = standoff_candidates(&wall_gap(), &alley(4.0), &params, &mut dropped);
        // Every standoff (6–22 m) lands in the block opposite or behind it.
        assert_eq!(dropped.inside_building + dropped.occluded, 4, "{dropped:?}");
        let [stop] = stops[..] else {
            panic!("one stop expected, got {stops:?}");
        };
        assert!((stop[0] - 20.0).abs() < 1e-3, "{stop:?}");
        assert!((16.0..18.0).contains(&stop[1]), "{stop:?}");
        // A 2 m alley leaves no open cell once both walls are grown by the clearance.
        let mut dropped = Dropped::default();
        let none = standoff_candidates(&wall_gap(), &alley(2.0), &params, &mut dropped);
        assert!(none.is_empty(), "{none:?}");
    }

    #[test]
    fn clusters_split_at_the_link_distance() {
        let pts = vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [10.0, 0.0], [11.0, 0.5]];
        let mut c = link_clusters(&pts, 1.5);
        c.sort();
        assert_eq!(c, vec![vec![0, 1, 2], vec![3, 4]]);
    }
}
