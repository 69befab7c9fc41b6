//! The roof-plane check after the forest: a building has a roof, a plane of
//! some extent; a crown has none. Per point the forest sees a few metres;
//! sparse conifers then look like roof edges and small pitched roofs like
//! crowns. Planes grown over the whole non-ground cloud settle both:
//! points on a large plane are building, and building points with no large
//! plane in reach are vegetation.

use std::collections::{HashMap, HashSet};
use std::num::NonZeroUsize;

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use petgraph::unionfind::UnionFind;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::cloud::class::{BUILDING, VEGETATION};
use crate::reconstruct::ReconstructParams;
use crate::reconstruct::normals::neighbourhoods;
use crate::reconstruct::planes::{NO_PLANE, grow_planes_with};

/// Settings of the roof-plane check (part of the model file).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RoofCheck {
    /// Off: the forest's labels stand. Models written before the check
    /// existed get it on, with these defaults.
    pub enabled: bool,
    /// Points are thinned to one per voxel of this size (m) first, so the
    /// check costs the same at any density.
    pub voxel_m: f32,
    /// Only points this high above the ground (m) take part: below it,
    /// hedges, cars and walls' feet, where planes say little.
    pub min_hag_m: f32,
    /// A plane covering at least this much ground (m², in 0.5 m cells) is a
    /// roof: a crown is never flat over this area.
    pub min_roof_m2: f64,
    /// Neighbours per point for normals and growing.
    pub k: usize,
    /// Growing angle (°) and distance (m), as in reconstruction.
    pub grow_angle_deg: f64,
    /// Growing distance (m).
    pub grow_dist_m: f64,
    /// Building points within this distance (m) form one object, which
    /// keeps its label only when it holds a roof.
    pub link_m: f32,
    /// Non-ground points under a roof or beside it within this distance
    /// (m), and not above it, are building (walls, eaves, balconies), at
    /// any height above the ground. Negative: off.
    pub under_roof_m: f32,
}

impl Default for RoofCheck {
    fn default() -> Self {
        Self {
            enabled: true,
            voxel_m: 0.35,
            min_hag_m: 2.0,
            min_roof_m2: 8.0,
            k: 12,
            grow_angle_deg: 12.0,
            grow_dist_m: 0.15,
            link_m: 1.0,
            under_roof_m: 0.5,
        }
    }
}

/// What the check changed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct RoofCheckCounts {
    /// Roof planes found.
    pub roofs: usize,
    /// Points turned from vegetation to building (on a roof).
    pub to_building: usize,
    /// Points turned from building to vegetation (no roof in reach).
    pub to_vegetation: usize,
    /// Points turned from vegetation to building (under or beside a roof).
    pub under_roof: usize,
}

/// Applies the check to `labels` (LAS codes from the forest) in place.
pub fn check_roofs(
    xyz: &[[f32; 3]],
    hag: &[f32],
    labels: &mut [u8],
    check: &RoofCheck,
) -> RoofCheckCounts {
    let mut counts = RoofCheckCounts::default();
    if !check.enabled || xyz.len() != hag.len() || xyz.len() != labels.len() {
        return counts;
    }
    let cand: Vec<usize> = (0..xyz.len())
        .filter(|&i| {
            (labels[i] == BUILDING || labels[i] == VEGETATION)
                && hag[i] >= check.min_hag_m
                && xyz[i].iter().all(|v| v.is_finite())
        })
        .collect();
    // One representative per voxel, its first point; every candidate knows
    // its voxel. (`features::voxel::thin` gives centroids, which move the
    // held-out figures the shipped settings were reported with.)
    let inv = 1.0 / check.voxel_m.max(1e-3);
    let mut voxel_of: HashMap<[i32; 3], u32> = HashMap::new();
    let mut reps: Vec<[f32; 3]> = Vec::new();
    let mut vox: Vec<u32> = Vec::with_capacity(cand.len());
    for &i in &cand {
        let key = xyz[i].map(|v| (v * inv).floor() as i32);
        let v = *voxel_of.entry(key).or_insert_with(|| {
            reps.push(xyz[i]);
            (reps.len() - 1) as u32
        });
        vox.push(v);
    }
    if reps.len() <= check.k {
        return counts;
    }
    let (roof, roofs) = roof_voxels(&reps, check);
    counts.roofs = roofs;
    // Building voxels: those holding a building point after the forest.
    let mut building = vec![false; reps.len()];
    for (n, &i) in cand.iter().enumerate() {
        if labels[i] == BUILDING {
            building[vox[n] as usize] = true;
        }
    }
    let keep = objects_with_roof(&reps, &building, &roof, check.link_m);
    for (n, &i) in cand.iter().enumerate() {
        let v = vox[n] as usize;
        if roof[v] {
            if labels[i] != BUILDING {
                labels[i] = BUILDING;
                counts.to_building += 1;
            }
        } else if labels[i] == BUILDING && !keep[v] {
            labels[i] = VEGETATION;
            counts.to_vegetation += 1;
        }
    }
    counts.under_roof = walls_under_roofs(xyz, labels, &reps, &roof, check.under_roof_m);
    counts
}

/// Turns vegetation points lying under a roof (or beside it within
/// `reach` m) and not above it into building; returns how many.
fn walls_under_roofs(
    xyz: &[[f32; 3]],
    labels: &mut [u8],
    reps: &[[f32; 3]],
    roof: &[bool],
    reach: f32,
) -> usize {
    const CELL: f32 = 0.5;
    if reach.is_nan() || reach < 0.0 {
        return 0;
    }
    // Roof height per 0.5 m cell, spread over the reach around it.
    let r = (reach / CELL).ceil() as i32;
    let mut top: HashMap<[i32; 2], f32> = HashMap::new();
    for (p, _) in reps.iter().zip(roof).filter(|(_, r)| **r) {
        let c = [(p[0] / CELL).floor() as i32, (p[1] / CELL).floor() as i32];
        for dx in -r..=r {
            for dy in -r..=r {
                let z = top.entry([c[0] + dx, c[1] + dy]).or_insert(f32::MIN);
                *z = z.max(p[2]);
            }
        }
    }
    let mut n = 0;
    for (p, l) in xyz.iter().zip(labels.iter_mut()) {
        if *l != VEGETATION {
            continue;
        }
        let c = [(p[0] / CELL).floor() as i32, (p[1] / CELL).floor() as i32];
        // A crown over a roof stands above it; what is under is the house.
        if top.get(&c).is_some_and(|&z| p[2] <= z + 0.2) {
            *l = BUILDING;
            n += 1;
        }
    }
    n
}

/// Voxels on a plane covering at least `min_roof_m2`, and how many such planes.
fn roof_voxels(reps: &[[f32; 3]], check: &RoofCheck) -> (Vec<bool>, usize) {
    let params = ReconstructParams {
        k: check.k,
        grow_angle_deg: check.grow_angle_deg,
        grow_dist_m: check.grow_dist_m,
        min_plane_points: 12,
        ..ReconstructParams::default()
    };
    let nb = neighbourhoods(reps, check.k);
    let (planes, label) = grow_planes_with(reps, &nb, &params, false);
    let mut cells: Vec<HashSet<[i32; 2]>> = vec![HashSet::new(); planes.len()];
    for (p, &l) in reps.iter().zip(&label) {
        if l != NO_PLANE {
            cells[l as usize].insert([(p[0] * 2.0).floor() as i32, (p[1] * 2.0).floor() as i32]);
        }
    }
    let is_roof: Vec<bool> = cells
        .iter()
        .map(|c| c.len() as f64 * 0.25 >= check.min_roof_m2)
        .collect();
    let roof = label
        .iter()
        .map(|&l| l != NO_PLANE && is_roof[l as usize])
        .collect();
    (roof, is_roof.iter().filter(|r| **r).count())
}

/// Per voxel: it is a building voxel whose object (building voxels linked
/// within `link_m`, roof voxels included) holds a roof voxel.
fn objects_with_roof(
    reps: &[[f32; 3]],
    building: &[bool],
    roof: &[bool],
    link_m: f32,
) -> Vec<bool> {
    let members: Vec<usize> = (0..reps.len())
        .filter(|&v| building[v] || roof[v])
        .collect();
    let mut keep = vec![false; reps.len()];
    if members.is_empty() {
        return keep;
    }
    let pts: Vec<[f32; 3]> = members.iter().map(|&v| reps[v]).collect();
    let Ok(tree) = ImmutableKdTree::<f32, 3>::new_from_slice(&pts) else {
        return keep;
    };
    let mut uf = UnionFind::<usize>::new(pts.len());
    let r2 = link_m * link_m;
    // Sixteen nearest within reach link an object as well as all of them
    // would: a chain needs one link per point.
    let n = NonZeroUsize::new(16.min(pts.len())).unwrap_or(NonZeroUsize::MIN);
    let links: Vec<Vec<u32>> = pts
        .par_iter()
        .map(|p| {
            tree.query(p)
                .nearest_n::<SquaredEuclidean<f32>>(n)
                .execute()
                .iter()
                .filter(|nn| nn.distance <= r2)
                .map(|nn| nn.item)
                .collect()
        })
        .collect();
    for (a, near) in links.iter().enumerate() {
        for &b in near {
            uf.union(a, b as usize);
        }
    }
    let with_roof: HashSet<usize> = members
        .iter()
        .enumerate()
        .filter(|(_, v)| roof[**v])
        .map(|(a, _)| uf.find(a))
        .collect();
    for (a, &v) in members.iter().enumerate() {
        keep[v] = with_roof.contains(&uf.find(a));
    }
    keep
}

#[cfg(test)]
mod tests {
    use super::*;

    fn on() -> RoofCheck {
        RoofCheck {
            enabled: true,
            ..RoofCheck::default()
        }
    }

    /// A 10 × 8 m pitched roof at 6–8 m the forest half called vegetation,
    /// and a 4 m crown of scattered points it called building.
    fn scene() -> (Vec<[f32; 3]>, Vec<f32>, Vec<u8>) {
        let (mut xyz, mut hag, mut lab) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..40 {
            for j in 0..32 {
                let (x, y) = (i as f32 * 0.25, j as f32 * 0.25);
                let z = 6.0 + 0.5 * y.min(8.0 - y);
                xyz.push([x, y, z]);
                hag.push(z);
                lab.push(if i < 20 { VEGETATION } else { BUILDING });
            }
        }
        // Deterministic scatter: a crown is volume, not surface.
        let mut s = 1u32;
        let mut r = || {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (s >> 8) as f32 / (1u32 << 24) as f32
        };
        for _ in 0..1500 {
            let p = [30.0 + 4.0 * r(), 30.0 + 4.0 * r(), 4.0 + 4.0 * r()];
            xyz.push(p);
            hag.push(p[2]);
            lab.push(BUILDING);
        }
        (xyz, hag, lab)
    }

    #[test]
    fn roofs_become_building_and_roofless_objects_vegetation() {
        let (xyz, hag, mut lab) = scene();
        let counts = check_roofs(&xyz, &hag, &mut lab, &on());
        assert!(counts.roofs >= 2, "{counts:?}");
        let roof_building = lab[..1280].iter().filter(|l| **l == BUILDING).count();
        // Half the roof came in as vegetation; the ridge line, whose normals
        // straddle both slopes, may stay as it was.
        assert!(roof_building >= 1240, "{roof_building} of 1280 roof points");
        let crown_veg = lab[1280..].iter().filter(|l| **l == VEGETATION).count();
        assert!(crown_veg >= 1490, "{crown_veg} of 1500 crown points");
    }

    #[test]
    fn disabled_or_mismatched_input_changes_nothing() {
        let (xyz, hag, lab0) = scene();
        let mut lab = lab0.clone();
        let off = RoofCheck {
            enabled: false,
            ..RoofCheck::default()
        };
        assert_eq!(
            check_roofs(&xyz, &hag, &mut lab, &off),
            RoofCheckCounts::default()
        );
        assert_eq!(lab, lab0);
        assert_eq!(
            check_roofs(&xyz, &hag[1..], &mut lab, &on()),
            RoofCheckCounts::default()
        );
        assert_eq!(lab, lab0);
    }

    #[test]
    fn a_wall_under_its_eave_is_building_and_a_crown_above_is_not() {
        let (mut xyz, mut hag, mut lab) = scene();
        let n0 = xyz.len();
        // A facade 0.3 m outside the roof's west edge, 0.5–5 m up, and a
        // crown 2 m above the roof's middle, both called vegetation.
        for k in 0..40 {
            for h in 0..10 {
                xyz.push([-0.3, k as f32 * 0.2, 0.5 + h as f32 * 0.5]);
                hag.push(0.5 + h as f32 * 0.5);
                lab.push(VEGETATION);
            }
        }
        for k in 0..50 {
            xyz.push([4.0 + (k % 5) as f32 * 0.3, 3.0 + (k / 5) as f32 * 0.2, 10.5]);
            hag.push(10.5);
            lab.push(VEGETATION);
        }
        let counts = check_roofs(&xyz, &hag, &mut lab, &on());
        let wall = &lab[n0..n0 + 400];
        assert!(wall.iter().all(|l| *l == BUILDING), "{counts:?}");
        assert!(
            lab[n0 + 400..].iter().all(|l| *l == VEGETATION),
            "{counts:?}"
        );
        // The wall, and the ridge points the planes left as they came.
        assert!(counts.under_roof >= 400, "{counts:?}");
    }
}
