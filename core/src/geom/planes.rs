//! Roof planes by region growing on normals: seeds in order of flatness,
//! neighbours join while their normal and offset agree with the plane,
//! which is refitted as the region grows; coplanar fragments are merged.

use super::normals::Neighbourhoods;
use super::shape::Moments;

/// A roof plane n·p + d = 0 (unit n, n_z > 0) and its support.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoofPlane {
    /// Unit normal, pointing up.
    pub normal: [f64; 3],
    /// Offset: n·p + d = 0 on the plane.
    pub d: f64,
    /// Points assigned to it.
    pub points: usize,
}

impl RoofPlane {
    /// Height of the plane above (x, y).
    pub fn z_at(&self, x: f64, y: f64) -> f64 {
        -(self.normal[0] * x + self.normal[1] * y + self.d) / self.normal[2]
    }

    /// Signed distance of `p` from the plane (positive above).
    pub fn distance(&self, p: [f64; 3]) -> f64 {
        self.normal[0] * p[0] + self.normal[1] * p[1] + self.normal[2] * p[2] + self.d
    }

    fn from_moments(m: &Moments, anchor: [f64; 3]) -> Option<Self> {
        let s = m.shape();
        // A row of points (a ridge line, an edge) has no plane. Linearity
        // alone would also reject a long narrow roof (a 27 m × 7 m slope
        // reaches 0.93, a 40 m one 0.97): the row is told by its width.
        let width = s.spread * (1.0 - s.linearity).max(0.0).sqrt();
        if s.linearity > 0.95 && width < ROW_WIDTH_M {
            return None;
        }
        let mut n = s.normal;
        if n[2] < 0.0 {
            n = n.map(|v| -v);
        }
        if n[2] < 1e-3 || !n.iter().all(|v| v.is_finite()) {
            return None;
        }
        let c = [0, 1, 2].map(|k| anchor[k] + s.mean[k]);
        Some(Self {
            normal: n,
            d: -(n[0] * c[0] + n[1] * c[1] + n[2] * c[2]),
            points: m.count() as usize,
        })
    }
}

/// How planes grow: which points may join one, how far a neighbour's normal
/// and offset may stray from it, and the smallest plane kept.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneGrowth {
    /// Points whose normal has at least this |z| may belong to a plane.
    pub min_nz: f64,
    /// A neighbour joins a growing plane when its normal is within this angle (°).
    pub angle_deg: f64,
    /// ... and it lies within this distance (m) of the plane.
    pub dist_m: f64,
    /// Planes with fewer points are dropped.
    pub min_points: usize,
}

/// Normals at least this upright may be roof: 60° slopes and flatter.
pub const ROOF_MIN_NZ: f64 = 0.5;

/// Across-spread (m, one standard deviation) under which a long region is a
/// row of points rather than a plane: a real roof 0.35 m wide has 0.1 m.
const ROW_WIDTH_M: f64 = 0.1;

/// Marks a point no plane took.
pub(crate) const NO_PLANE: u32 = u32::MAX;

fn wide(p: [f32; 3]) -> [f64; 3] {
    p.map(f64::from)
}

/// Grows roof planes over `xyz` (normals and neighbours in `nb`); returns
/// the planes (largest first) and each point's plane index or [`NO_PLANE`].
pub(crate) fn grow_planes(
    xyz: &[[f32; 3]],
    nb: &Neighbourhoods,
    growth: &PlaneGrowth,
) -> (Vec<RoofPlane>, Vec<u32>) {
    grow_planes_with(xyz, nb, growth, true)
}

/// [`grow_planes`], merging planes grown from two seeds only when `merge`:
/// the merge compares every pair of like planes, which over a whole survey
/// tile costs more than the growing.
pub(crate) fn grow_planes_with(
    xyz: &[[f32; 3]],
    nb: &Neighbourhoods,
    growth: &PlaneGrowth,
    merge: bool,
) -> (Vec<RoofPlane>, Vec<u32>) {
    let n = xyz.len();
    let mut label = vec![NO_PLANE; n];
    if nb.k == 0 {
        return (Vec::new(), label);
    }
    let candidate: Vec<bool> = nb.normal.iter().map(|v| v[2] >= growth.min_nz).collect();
    let mut order: Vec<usize> = (0..n).filter(|&i| candidate[i]).collect();
    order.sort_by(|&a, &b| nb.curvature[a].total_cmp(&nb.curvature[b]));
    let cos_max = growth.angle_deg.to_radians().cos();
    let mut visited = vec![false; n];
    let mut planes: Vec<RoofPlane> = Vec::new();
    let mut members: Vec<Vec<usize>> = Vec::new();
    for &seed in &order {
        if visited[seed] {
            continue;
        }
        let anchor = wide(xyz[seed]);
        let n0 = nb.normal[seed];
        let mut plane = RoofPlane {
            normal: n0,
            d: -(n0[0] * anchor[0] + n0[1] * anchor[1] + n0[2] * anchor[2]),
            points: 1,
        };
        let mut m = Moments::default();
        m.add([0.0; 3]);
        let mut region = vec![seed];
        visited[seed] = true;
        let mut refit_at = 8usize;
        let mut head = 0;
        while head < region.len() {
            let i = region[head];
            head += 1;
            for &j in nb.of(i) {
                let j = j as usize;
                if visited[j] || !candidate[j] {
                    continue;
                }
                let nj = nb.normal[j];
                let cos =
                    nj[0] * plane.normal[0] + nj[1] * plane.normal[1] + nj[2] * plane.normal[2];
                let p = wide(xyz[j]);
                if cos < cos_max || plane.distance(p).abs() > growth.dist_m {
                    continue;
                }
                visited[j] = true;
                region.push(j);
                m.add([0, 1, 2].map(|k| p[k] - anchor[k]));
                if region.len() >= refit_at {
                    if let Some(pl) = RoofPlane::from_moments(&m, anchor) {
                        plane = pl;
                    }
                    refit_at = region.len() * 3 / 2;
                }
            }
        }
        if region.len() < growth.min_points {
            // Small regions free their points for later, larger ones. (A
            // row keeps its points: freed, each of them would seed the
            // same row again.)
            for &i in &region[1..] {
                visited[i] = false;
            }
            continue;
        }
        if let Some(pl) = RoofPlane::from_moments(&m, anchor) {
            planes.push(pl);
            members.push(region);
        }
    }
    if merge {
        merge_coplanar(xyz, &mut planes, &mut members, growth);
    }
    let mut idx: Vec<usize> = (0..planes.len()).collect();
    idx.sort_by_key(|&i| std::cmp::Reverse(members[i].len()));
    let mut out = Vec::with_capacity(idx.len());
    for (new, &old) in idx.iter().enumerate() {
        let mut pl = planes[old];
        pl.points = members[old].len();
        out.push(pl);
        for &i in &members[old] {
            label[i] = new as u32;
        }
    }
    (out, label)
}

/// Merges planes whose normals agree within half the growing angle and
/// whose offsets agree within the growing distance at each other's points
/// (one roof grown from two seeds).
fn merge_coplanar(
    xyz: &[[f32; 3]],
    planes: &mut Vec<RoofPlane>,
    members: &mut Vec<Vec<usize>>,
    growth: &PlaneGrowth,
) {
    let cos_max = (growth.angle_deg * 0.5).to_radians().cos();
    loop {
        let mut merged = false;
        'outer: for a in 0..planes.len() {
            for b in a + 1..planes.len() {
                let (pa, pb) = (planes[a], planes[b]);
                let cos: f64 = (0..3).map(|k| pa.normal[k] * pb.normal[k]).sum();
                if cos < cos_max {
                    continue;
                }
                let off = |pl: &RoofPlane, ids: &[usize]| {
                    ids.iter()
                        .map(|&i| pl.distance(wide(xyz[i])).abs())
                        .sum::<f64>()
                        / ids.len().max(1) as f64
                };
                if off(&pa, &members[b]) > growth.dist_m * 0.5
                    || off(&pb, &members[a]) > growth.dist_m * 0.5
                {
                    continue;
                }
                let moved = std::mem::take(&mut members[b]);
                members[a].extend(moved);
                let anchor = wide(xyz[members[a][0]]);
                let mut m = Moments::default();
                for &i in &members[a] {
                    let p = wide(xyz[i]);
                    m.add([0, 1, 2].map(|k| p[k] - anchor[k]));
                }
                if let Some(pl) = RoofPlane::from_moments(&m, anchor) {
                    planes[a] = pl;
                }
                planes.remove(b);
                members.remove(b);
                merged = true;
                break 'outer;
            }
        }
        if !merged {
            break;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::normals::neighbourhoods;
    use super::*;

    /// Reconstruction's default growth.
    const GROWTH: PlaneGrowth = PlaneGrowth {
        min_nz: ROOF_MIN_NZ,
        angle_deg: 12.0,
        dist_m: 0.2,
        min_points: 30,
    };

    #[test]
    fn gable_roof_gives_two_planes_and_walls_none() {
        // Ridge along x at y = 3.75, slope 0.6; a wall at y = -0.05 below it.
        let mut pts =
            crate::geom::fixtures::lattice(40, 30, 0.25, |_, y| 8.0 - 0.6 * (y - 3.75).abs());
        let wall = crate::geom::fixtures::lattice(40, 20, 0.25, |_, _| 0.0);
        pts.extend(wall.iter().map(|p| [p[0], -0.05, p[1]]));
        let nb = neighbourhoods(&pts, 12);
        let (planes, label) = grow_planes(&pts, &nb, &GROWTH);
        assert_eq!(planes.len(), 2, "{planes:?}");
        for p in &planes {
            let slope = (p.normal[1] / p.normal[2]).abs();
            assert!((slope - 0.6).abs() < 0.03, "{p:?}");
            assert!((p.z_at(1.0, 3.75) - 8.0).abs() < 0.05, "{p:?}");
        }
        let wall_labelled = pts
            .iter()
            .zip(&label)
            .filter(|(p, l)| p[1] < 0.0 && **l != NO_PLANE)
            .count();
        assert_eq!(wall_labelled, 0);
    }

    #[test]
    fn a_long_narrow_gable_keeps_both_slopes() {
        // 40 m along the ridge, 3 m of slope each side (linearity 0.99):
        // both slopes are planes, not rows of points.
        let pts = crate::geom::fixtures::lattice(160, 24, 0.25, |_, y| 8.0 - 0.9 * (y - 3.0).abs());
        let nb = neighbourhoods(&pts, 12);
        let (planes, label) = grow_planes(&pts, &nb, &GROWTH);
        assert_eq!(planes.len(), 2, "{planes:?}");
        let labelled = label.iter().filter(|&&l| l != NO_PLANE).count();
        assert!(
            labelled * 100 >= pts.len() * 85,
            "{labelled} of {}",
            pts.len()
        );
    }
}
