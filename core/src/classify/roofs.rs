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
use crate::features::Echoes;
use crate::geom::normals::{Neighbourhoods, neighbourhoods};
use crate::geom::planes::{NO_PLANE, PlaneGrowth, ROOF_MIN_NZ, RoofPlane, grow_planes_with};

/// The widest growing angle (°) [`RoofCheck::for_spacing`] gives a sparse
/// cloud: the widest measured on thinned copies of real tiles, at 1 pts/m².
pub const MAX_GROW_ANGLE_DEG: f64 = 40.0;

/// The largest share of multiple-return points a roof plane may hold where
/// [`RoofCheck::for_spacing`] widened the growing angle. On thinned copies
/// at 1 pts/m², 0.3 kept St Barth's and Montpellier's crowns out of the
/// roofs (building precision 0.87 → 0.91, 0.92 → 0.97) where 0.5 hardly
/// did.
pub const SPARSE_MAX_MULTIPLE: f32 = 0.3;

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
    /// Each roof then grows over neighbours whose normal lies within this
    /// angle (°) of the roof plane's, and within `grow_dist_m` of it: the
    /// faces' edges, which the growing angle leaves off. Default 20°,
    /// chosen on Montpellier; held out, building F1 St Barth 0.873 → 0.880,
    /// Delft 0.940 / 0.968 → 0.952 / 0.973 (docs/classification.md, "The roof-plane check").
    /// 0: off.
    pub extend_angle_deg: f64,
    /// Building points within this distance (m) form one object, which
    /// keeps its label only when it holds a roof.
    pub link_m: f32,
    /// Non-ground points under a roof or beside it within this distance
    /// (m), and not more than `above_roof_m` over it, are building (walls,
    /// eaves, balconies), at any height above the ground. Negative: off.
    pub under_roof_m: f32,
    /// The roofs' 2D outline is closed by this radius (m) before it is
    /// grown by `under_roof_m`: gaps between a building's roof planes and
    /// courtyards narrower than twice it join the building's footprint, as
    /// a producer's footprint polygon would have them. 0 (default): the
    /// roof cells as found; on the training file Montpellier 0.5–2 m
    /// changed building F1 by −0.002 to −0.0002.
    pub close_m: f32,
    /// "Not above it": a point in the footprint is building up to this
    /// height (m) over the highest roof near it: chimneys, dormers, roof
    /// terraces' parapets and railings the planes miss, which producers
    /// label building. Chosen on Montpellier (0.2 / 1 / 2 / 3 m: building
    /// F1 0.935 / 0.941 / 0.949 / 0.948). It holds over the roof cells
    /// themselves; beside them, `beside_above_m` does.
    pub above_roof_m: f32,
    /// In the band beside the roof cells (within `under_roof_m`), a point
    /// of a pulse that gave several returns is building only up to this
    /// height (m) over the roof: a parapet or gutter stops the beam, a
    /// crown leaning over the edge lets it through, and calling the crown
    /// building hides the wall gap beneath it from detection.
    pub beside_above_m: f32,
    /// Beside the roof cells, a point is building only within this plan
    /// distance (m) of a roof point, not anywhere in the grown cells (up to
    /// 1.4 m out): a hedge or a bush before the facade stays vegetation and
    /// out of the footprint detection draws. ≤ 0: off. Chosen on one AHN3
    /// Delft tile's detection (missing points within 0.5 m of a producer
    /// building point in plan ≥ 0.95) and checked on the other.
    pub beside_dist_m: f32,
    /// Plan cell (m) in which a roof's area is counted and its footprint
    /// drawn. [`RoofCheck::for_spacing`] raises it to the point spacing.
    pub cell_m: f32,
    /// A plane is a roof only when at most this share of its points come
    /// from pulses that gave several returns: a roof stops the beam, a
    /// crown's top lets part of it through. 1 (default): any share.
    /// [`RoofCheck::for_spacing`] lowers it to [`SPARSE_MAX_MULTIPLE`]
    /// where it widens the growing angle.
    pub max_multiple_share: f32,
}

impl RoofCheck {
    /// The plan cell's edge (m), kept away from 0.
    fn cell(&self) -> f32 {
        self.cell_m.max(0.05)
    }

    /// The check for a cloud whose points lie `spacing_m` apart.
    ///
    /// Below 4 pts/m² (spacing over 0.5 m) a 0.5 m cell holds less than one
    /// point, so a roof's cells undercount its area and its points no
    /// longer link within 1 m: the cell follows the spacing and the link
    /// twice it. Where the points lie farther apart than the voxel (below
    /// about 8 pts/m²), each normal comes from a wider patch, which near a
    /// ridge, an eave or a dormer takes in the other side, so a roof face
    /// falls apart into pieces too small to be a roof: the growing angle
    /// widens in proportion to the spacing over the voxel, up to
    /// [`MAX_GROW_ANGLE_DEG`]. The wider angle also grows planes over
    /// crowns' tops, so a plane must then hold at most
    /// [`SPARSE_MAX_MULTIPLE`] of points from multiple-return pulses.
    /// Denser clouds keep the model's settings.
    pub fn for_spacing(&self, spacing_m: f32) -> Self {
        let s = if spacing_m.is_finite() {
            spacing_m
        } else {
            0.0
        };
        let mut check = Self {
            cell_m: self.cell_m.max(s),
            link_m: self.link_m.max(2.0 * s),
            ..self.clone()
        };
        let widen = f64::from(s / self.voxel_m.max(1e-3));
        if widen > 1.0 {
            check.grow_angle_deg =
                (self.grow_angle_deg * widen).min(MAX_GROW_ANGLE_DEG.max(self.grow_angle_deg));
            check.max_multiple_share = self.max_multiple_share.min(SPARSE_MAX_MULTIPLE);
        }
        check
    }
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
            extend_angle_deg: 20.0,
            link_m: 1.0,
            under_roof_m: 0.5,
            close_m: 0.0,
            above_roof_m: 2.0,
            beside_above_m: 0.2,
            beside_dist_m: 0.7,
            cell_m: 0.5,
            max_multiple_share: 1.0,
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
    echoes: Option<Echoes<'_>>,
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
    // Per voxel: its points, and those of pulses that gave several returns;
    // counted only where the check bounds their share.
    let pulses = echoes
        .as_ref()
        .filter(|_| check.max_multiple_share < 1.0)
        .map(|e| {
            let mut pulses = vec![[0u32; 2]; reps.len()];
            for (n, &i) in cand.iter().enumerate() {
                let c = &mut pulses[vox[n] as usize];
                c[0] += 1;
                c[1] += u32::from(e.is_multiple(i));
            }
            pulses
        });
    let (roof, roofs) = roof_voxels(&reps, pulses.as_deref(), check);
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
    counts.under_roof = walls_under_roofs(xyz, labels, echoes, (&reps, &roof), check);
    counts
}

/// Turns vegetation points inside the roofs' footprint (the roof cells
/// closed by `close_m`, grown by `under_roof_m`) and at most
/// `above_roof_m` over the highest roof near them into building; returns
/// how many.
fn walls_under_roofs(
    xyz: &[[f32; 3]],
    labels: &mut [u8],
    echoes: Option<Echoes<'_>>,
    (reps, roof): (&[[f32; 3]], &[bool]),
    check: &RoofCheck,
) -> usize {
    let cell = check.cell();
    let reach = check.under_roof_m;
    if reach.is_nan() || reach < 0.0 {
        return 0;
    }
    let cell_of = |p: &[f32; 3]| plan_cell(p, cell);
    let mut roof_top: HashMap<[i32; 2], f32> = HashMap::new();
    for (p, _) in reps.iter().zip(roof).filter(|(_, r)| **r) {
        let z = roof_top.entry(cell_of(p)).or_insert(f32::MIN);
        *z = z.max(p[2]);
    }
    let rc = cells_of(check.close_m, cell);
    let r = (reach / cell).ceil() as i32;
    // Sparse cells, not a raster: the cloud may span kilometres and its
    // roofs cover a small part of it.
    let closed = close_cells(&roof_top.keys().copied().collect(), rc);
    // Each footprint cell's height is the highest roof within the closing
    // and growing reach: a courtyard takes its surrounding roofs' height.
    let spread = spread_max(&roof_top, rc + r);
    let mut top: HashMap<[i32; 2], f32> = HashMap::new();
    for c in &closed {
        for dx in -r..=r {
            for dy in -r..=r {
                let k = [c[0] + dx, c[1] + dy];
                if let Some(&z) = spread.get(&k) {
                    top.insert(k, z);
                }
            }
        }
    }
    let finite = |v: f32| if v.is_finite() { v } else { 0.0 };
    let (over, beside) = (finite(check.above_roof_m), finite(check.beside_above_m));
    let near = finite(check.beside_dist_m);
    let roof_xy: Vec<[f32; 2]> = reps
        .iter()
        .zip(roof)
        .filter(|(_, r)| **r && near > 0.0)
        .map(|(p, _)| [p[0], p[1]])
        .collect();
    let roof_tree = (!roof_xy.is_empty())
        .then(|| ImmutableKdTree::<f32, 2>::new_from_slice(&roof_xy).ok())
        .flatten();
    let beside_roof = |p: &[f32; 3]| {
        roof_tree.as_ref().is_none_or(|t| {
            t.query(&[p[0], p[1]])
                .nearest_one::<SquaredEuclidean<f32>>()
                .execute()
                .distance
                <= near * near
        })
    };
    let mut n = 0;
    for (i, (p, l)) in xyz.iter().zip(labels.iter_mut()).enumerate() {
        if *l != VEGETATION {
            continue;
        }
        // A crown over a roof stands above it (more than a chimney does);
        // what is under is the house.
        let c = cell_of(p);
        let crown_like = echoes.as_ref().is_some_and(|e| e.is_multiple(i));
        let above = if crown_like && !closed.contains(&c) {
            beside
        } else {
            over
        };
        if top.get(&c).is_some_and(|&z| p[2] <= z + above)
            && (closed.contains(&c) || beside_roof(p))
        {
            *l = BUILDING;
            n += 1;
        }
    }
    n
}

/// The plan cell of edge `cell` (m) holding `p`.
fn plan_cell(p: &[f32; 3], cell: f32) -> [i32; 2] {
    [(p[0] / cell).floor() as i32, (p[1] / cell).floor() as i32]
}

/// A length in whole cells (≤ 0 or NaN: none).
fn cells_of(m: f32, cell: f32) -> i32 {
    if m.is_finite() && m > 0.0 {
        (m / cell).round() as i32
    } else {
        0
    }
}

/// Morphological closing of a set of cells by a (2r+1)² square (as
/// `geom::grid::close` on a raster): dilation, then erosion.
fn close_cells(cells: &HashSet<[i32; 2]>, r: i32) -> HashSet<[i32; 2]> {
    if r <= 0 {
        return cells.clone();
    }
    let square = || (-r..=r).flat_map(move |dx| (-r..=r).map(move |dy| (dx, dy)));
    let grown: HashSet<[i32; 2]> = cells
        .iter()
        .flat_map(|c| square().map(move |(dx, dy)| [c[0] + dx, c[1] + dy]))
        .collect();
    grown
        .iter()
        .filter(|c| square().all(|(dx, dy)| grown.contains(&[c[0] + dx, c[1] + dy])))
        .copied()
        .collect()
}

/// The largest value within a (2r+1)² square of each cell near a valued one.
fn spread_max(values: &HashMap<[i32; 2], f32>, r: i32) -> HashMap<[i32; 2], f32> {
    let mut out: HashMap<[i32; 2], f32> = HashMap::with_capacity(values.len() * 4);
    for (c, &z) in values {
        for dx in -r..=r {
            for dy in -r..=r {
                let v = out.entry([c[0] + dx, c[1] + dy]).or_insert(f32::MIN);
                *v = v.max(z);
            }
        }
    }
    out
}

/// Voxels on a plane covering at least `min_roof_m2`, and how many such planes.
/// `pulses` holds each voxel's point count and how many of its points came
/// from pulses with several returns (`None`: no bound on their share).
fn roof_voxels(
    reps: &[[f32; 3]],
    pulses: Option<&[[u32; 2]]>,
    check: &RoofCheck,
) -> (Vec<bool>, usize) {
    let growth = PlaneGrowth {
        min_nz: ROOF_MIN_NZ,
        angle_deg: check.grow_angle_deg,
        dist_m: check.grow_dist_m,
        min_points: 12,
    };
    let nb = neighbourhoods(reps, check.k);
    let (planes, label) = grow_planes_with(reps, &nb, &growth, false);
    let cell = check.cell();
    let mut cells: Vec<HashSet<[i32; 2]>> = vec![HashSet::new(); planes.len()];
    let mut echo = vec![[0u32; 2]; planes.len()];
    for (v, (p, &l)) in reps.iter().zip(&label).enumerate() {
        if l != NO_PLANE {
            cells[l as usize].insert(plan_cell(p, cell));
            if let Some(e) = pulses.and_then(|c| c.get(v)) {
                echo[l as usize][0] += e[0];
                echo[l as usize][1] += e[1];
            }
        }
    }
    let max_multi = f64::from(check.max_multiple_share);
    let cell_m2 = f64::from(cell) * f64::from(cell);
    let is_roof: Vec<bool> = cells
        .iter()
        .zip(&echo)
        .map(|(c, [points, multiple])| {
            c.len() as f64 * cell_m2 >= check.min_roof_m2
                && f64::from(*multiple) <= max_multi * f64::from(*points)
        })
        .collect();
    let mut roof: Vec<bool> = label
        .iter()
        .map(|&l| l != NO_PLANE && is_roof[l as usize])
        .collect();
    extend_roofs(reps, &nb, (&planes, &label), &mut roof, check);
    (roof, is_roof.iter().filter(|r| **r).count())
}

/// Grows every roof over its neighbours whose normal lies within
/// `extend_angle_deg` of the roof plane's (at least the growing angle) and
/// which lie within `grow_dist_m` of it: the edge of a roof face, whose
/// normals the eave or the ridge tilts past the growing angle. Only roofs
/// grow, so a crown without a roof-sized plane stays out.
fn extend_roofs(
    reps: &[[f32; 3]],
    nb: &Neighbourhoods,
    (planes, label): (&[RoofPlane], &[u32]),
    roof: &mut [bool],
    check: &RoofCheck,
) {
    let angle = check.extend_angle_deg.max(check.grow_angle_deg);
    if !(check.extend_angle_deg > 0.0 && angle.is_finite()) || nb.k == 0 {
        return;
    }
    let cos_max = angle.to_radians().cos();
    let mut plane_of = label.to_vec();
    let mut queue: Vec<usize> = (0..reps.len()).filter(|&i| roof[i]).collect();
    while let Some(i) = queue.pop() {
        let Some(plane) = planes.get(plane_of[i] as usize) else {
            continue;
        };
        for &j in nb.of(i) {
            let j = j as usize;
            if roof[j] {
                continue;
            }
            let n = nb.normal[j];
            let cos = n[0] * plane.normal[0] + n[1] * plane.normal[1] + n[2] * plane.normal[2];
            if cos < cos_max || plane.distance(reps[j].map(f64::from)).abs() > check.grow_dist_m {
                continue;
            }
            roof[j] = true;
            plane_of[j] = plane_of[i];
            queue.push(j);
        }
    }
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
        let counts = check_roofs(&xyz, &hag, &mut lab, None, &on());
        assert!(counts.roofs >= 2, "{counts:?}");
        let roof_building = lab[..1280].iter().filter(|l| **l == BUILDING).count();
        // Half the roof came in as vegetation; the ridge line, whose normals
        // straddle both slopes, may stay as it was.
        assert!(roof_building >= 1240, "{roof_building} of 1280 roof points");
        let crown_veg = lab[1280..].iter().filter(|l| **l == VEGETATION).count();
        assert!(crown_veg >= 1490, "{crown_veg} of 1500 crown points");
    }

    #[test]
    fn a_small_roof_of_a_sparse_survey_stays_a_roof_at_its_spacing() {
        // 4.2 × 3.5 m (14.7 m²) at 2 pts/m²: 30 points, each alone in its
        // 0.5 m cell, count 7.5 m² there, under the 8 m² of a roof.
        let s = 0.7;
        let (mut xyz, mut hag) = (Vec::new(), Vec::new());
        for i in 0..6 {
            for j in 0..5 {
                let (x, y) = (i as f32 * s, j as f32 * s);
                let z = 6.0 + 0.3 * y;
                xyz.push([x, y, z]);
                hag.push(z);
            }
        }
        let building = |check: &RoofCheck| {
            let mut lab = vec![BUILDING; xyz.len()];
            check_roofs(&xyz, &hag, &mut lab, None, check);
            lab.iter().filter(|l| **l == BUILDING).count()
        };
        assert_eq!(building(&on()), 0, "0.5 m cells: no roof");
        assert_eq!(
            building(&on().for_spacing(s)),
            xyz.len(),
            "cells at the spacing"
        );
        // Points no farther apart than the voxel: the model's settings.
        assert_eq!(on().for_spacing(0.35), on());
        assert_eq!(on().for_spacing(0.2), on());
        assert_eq!(on().for_spacing(f32::NAN), on());
        let sparse = on().for_spacing(s);
        assert_eq!((sparse.cell_m, sparse.link_m), (0.7, 1.4));
    }

    #[test]
    fn a_roof_grows_over_its_tilted_edge_but_not_off_its_plane() {
        // A row along x at 6 m: points 0–3 are a found roof; 4 lies on its
        // plane with its normal tilted 15° (an eave), 5 beyond it tilted
        // 30°, 6 tilted 10° but 0.3 m over the plane.
        let reps: Vec<[f32; 3]> = (0..7)
            .map(|i| [i as f32 * 0.4, 0.0, if i == 6 { 6.3 } else { 6.0 }])
            .collect();
        let tilt = |deg: f64| [deg.to_radians().sin(), 0.0, deg.to_radians().cos()];
        let normal = vec![
            tilt(0.0),
            tilt(0.0),
            tilt(0.0),
            tilt(0.0),
            tilt(15.0),
            tilt(30.0),
            tilt(10.0),
        ];
        // Each point's neighbours: the one before and the one after.
        let knn: Vec<u32> = (0..7u32)
            .flat_map(|i| [i.saturating_sub(1), (i + 1).min(6)])
            .collect();
        let nb = Neighbourhoods {
            normal,
            curvature: vec![0.0; 7],
            knn,
            k: 2,
        };
        let planes = [RoofPlane {
            normal: [0.0, 0.0, 1.0],
            d: -6.0,
            points: 4,
        }];
        let label = [0, 0, 0, 0, NO_PLANE, NO_PLANE, NO_PLANE];
        let grown = |check: &RoofCheck| {
            let mut roof = vec![true, true, true, true, false, false, false];
            extend_roofs(&reps, &nb, (&planes, &label), &mut roof, check);
            roof
        };
        assert_eq!(grown(&on()), [true, true, true, true, true, false, false]);
        let off = RoofCheck {
            extend_angle_deg: 0.0,
            ..on()
        };
        assert_eq!(grown(&off), [true, true, true, true, false, false, false]);
        // Point 6 joins through 5 only if 5 joins: at 35° both are within
        // the angle, and 6 is still off the plane.
        let wide = RoofCheck {
            extend_angle_deg: 35.0,
            ..on()
        };
        assert_eq!(grown(&wide), [true, true, true, true, true, true, false]);
    }

    #[test]
    fn a_sparse_plane_of_multiple_returns_is_no_roof() {
        // A 6 × 5 m flat top at 1 pts/m², 4 m up: a roof when its pulses
        // gave one return each, a crown's top when most gave several.
        let s = 1.0;
        let (mut xyz, mut hag) = (Vec::new(), Vec::new());
        for i in 0..7 {
            for j in 0..6 {
                xyz.push([i as f32 * s, j as f32 * s, 4.0]);
                hag.push(4.0);
            }
        }
        let first = vec![1u8; xyz.len()];
        let building = |returns: &[u8], check: &RoofCheck| {
            let mut lab = vec![VEGETATION; xyz.len()];
            let echoes = Echoes {
                return_number: &first,
                number_of_returns: returns,
            };
            check_roofs(&xyz, &hag, &mut lab, Some(echoes), check);
            lab.iter().filter(|l| **l == BUILDING).count()
        };
        let single = vec![1u8; xyz.len()];
        // Two of every five pulses gave a second return below the top.
        let crown: Vec<u8> = (0..xyz.len()).map(|i| 1 + u8::from(i % 5 < 2)).collect();
        let sparse = on().for_spacing(s);
        assert_eq!(sparse.max_multiple_share, SPARSE_MAX_MULTIPLE);
        assert_eq!(building(&single, &sparse), xyz.len());
        assert_eq!(building(&crown, &sparse), 0);
        // Where the angle is not widened the model's share (any) holds.
        let dense = RoofCheck {
            cell_m: 1.0,
            link_m: 2.0,
            ..on()
        };
        assert_eq!(building(&crown, &dense), xyz.len());
    }

    #[test]
    fn the_growing_angle_widens_with_the_spacing_up_to_its_limit() {
        let at = |s: f32| on().for_spacing(s).grow_angle_deg;
        // 4 pts/m²: the cell and link stay, the angle widens by 0.5 / 0.35.
        let four = on().for_spacing(0.5);
        assert_eq!((four.cell_m, four.link_m), (0.5, 1.0));
        assert!((at(0.5) - 12.0 * 0.5 / 0.35).abs() < 1e-3, "{}", at(0.5));
        assert!((at(0.7) - 24.0).abs() < 1e-3, "{}", at(0.7));
        assert_eq!(at(5.0), MAX_GROW_ANGLE_DEG);
        // A model set wider than the limit keeps its own angle.
        let wide = RoofCheck {
            grow_angle_deg: 50.0,
            ..on()
        };
        assert_eq!(wide.for_spacing(5.0).grow_angle_deg, 50.0);
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
            check_roofs(&xyz, &hag, &mut lab, None, &off),
            RoofCheckCounts::default()
        );
        assert_eq!(lab, lab0);
        assert_eq!(
            check_roofs(&xyz, &hag[1..], &mut lab, None, &on()),
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
        let counts = check_roofs(&xyz, &hag, &mut lab, None, &on());
        let wall = &lab[n0..n0 + 400];
        assert!(wall.iter().all(|l| *l == BUILDING), "{counts:?}");
        assert!(
            lab[n0 + 400..].iter().all(|l| *l == VEGETATION),
            "{counts:?}"
        );
        // The wall, and the ridge points the planes left as they came.
        assert!(counts.under_roof >= 400, "{counts:?}");
    }

    /// Two 6 × 8 m flat roofs at 6 m with a 2 m courtyard between them,
    /// its crown at 5 m called vegetation, and a chimney 1.5 m above the
    /// first roof called vegetation; returns (cloud, hag, labels, courtyard
    /// rows, chimney rows).
    #[allow(clippy::type_complexity)]
    fn courtyard() -> (
        Vec<[f32; 3]>,
        Vec<f32>,
        Vec<u8>,
        std::ops::Range<usize>,
        std::ops::Range<usize>,
    ) {
        let (mut xyz, mut hag, mut lab) = (Vec::new(), Vec::new(), Vec::new());
        for x0 in [0.0f32, 8.0] {
            for i in 0..24 {
                for j in 0..32 {
                    xyz.push([x0 + i as f32 * 0.25, j as f32 * 0.25, 6.0]);
                    hag.push(6.0);
                    lab.push(BUILDING);
                }
            }
        }
        let yard = xyz.len();
        // x 6.6–7.4: more than the 0.5 m reach from either roof's cells.
        for i in 0..5 {
            for j in 0..10 {
                let p = [6.6 + i as f32 * 0.2, 3.0 + j as f32 * 0.2, 5.0];
                xyz.push(p);
                hag.push(p[2]);
                lab.push(VEGETATION);
            }
        }
        let chimney = xyz.len();
        for k in 0..12 {
            let p = [2.0 + (k % 3) as f32 * 0.2, 2.0 + (k / 3) as f32 * 0.2, 7.5];
            xyz.push(p);
            hag.push(p[2]);
            lab.push(VEGETATION);
        }
        let end = xyz.len();
        (xyz, hag, lab, yard..chimney, chimney..end)
    }

    #[test]
    fn the_footprint_takes_what_stands_on_a_roof_and_closes_courtyards_when_asked() {
        let (xyz, hag, lab0, yard, chimney) = courtyard();
        let veg = |lab: &[u8], r: &std::ops::Range<usize>| {
            lab[r.clone()].iter().filter(|l| **l == VEGETATION).count()
        };
        // Defaults: the chimney 1.5 m up is building, the courtyard (2 m
        // from either roof) is not.
        let mut lab = lab0.clone();
        check_roofs(&xyz, &hag, &mut lab, None, &on());
        assert_eq!(veg(&lab, &chimney), 0);
        assert_eq!(veg(&lab, &yard), yard.len());
        // The old tolerance (0.2 m) leaves the chimney as it came.
        let mut lab = lab0.clone();
        let flat = RoofCheck {
            above_roof_m: 0.2,
            ..on()
        };
        check_roofs(&xyz, &hag, &mut lab, None, &flat);
        assert_eq!(veg(&lab, &chimney), chimney.len());
        // Closed by 1.5 m, the 2 m gap between the roofs is footprint.
        let mut lab = lab0;
        let closed = RoofCheck {
            close_m: 1.5,
            ..on()
        };
        check_roofs(&xyz, &hag, &mut lab, None, &closed);
        assert_eq!(veg(&lab, &yard), 0);
    }

    /// One 6 × 8 m flat roof at 6 m and, 0.3 m beyond its east edge, 1 m
    /// over it, a column of points the forest called vegetation; returns
    /// (cloud, hag, labels, the column's rows).
    fn edge_column() -> (Vec<[f32; 3]>, Vec<f32>, Vec<u8>, std::ops::Range<usize>) {
        let (mut xyz, mut hag, mut lab) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..24 {
            for j in 0..32 {
                xyz.push([i as f32 * 0.25, j as f32 * 0.25, 6.0]);
                hag.push(6.0);
                lab.push(BUILDING);
            }
        }
        let column = xyz.len();
        for j in 0..20 {
            xyz.push([6.05, 2.0 + j as f32 * 0.2, 7.0]);
            hag.push(7.0);
            lab.push(VEGETATION);
        }
        let end = xyz.len();
        (xyz, hag, lab, column..end)
    }

    #[test]
    fn beside_a_roof_a_crown_stays_vegetation_and_a_parapet_is_building() {
        let (xyz, hag, lab0, column) = edge_column();
        let run = |returns: u8| {
            let rn = vec![1u8; xyz.len()];
            let nr: Vec<u8> = (0..xyz.len())
                .map(|i| if column.contains(&i) { returns } else { 1 })
                .collect();
            let echoes = Echoes {
                return_number: &rn,
                number_of_returns: &nr,
            };
            let mut lab = lab0.clone();
            check_roofs(&xyz, &hag, &mut lab, Some(echoes), &on());
            lab[column.clone()]
                .iter()
                .filter(|l| **l == BUILDING)
                .count()
        };
        // One return a pulse: the beam stopped on it (a parapet, a gutter).
        assert_eq!(run(1), column.len());
        // Several: the beam went through (a crown leaning over the edge).
        assert_eq!(run(3), 0);
        // Without echoes, as before this rule: building.
        let mut lab = lab0;
        check_roofs(&xyz, &hag, &mut lab, None, &on());
        assert!(lab[column].iter().all(|l| *l == BUILDING));
    }

    #[test]
    fn a_hedge_before_the_facade_stays_vegetation() {
        let (mut xyz, mut hag, mut lab) = scene();
        let n0 = xyz.len();
        // 0.65 m beyond the roof's east edge (x 9.75), 0.9 m from the
        // nearest roof voxel, 1 m up: in the grown cells, out of reach.
        for k in 0..24 {
            for h in 0..3 {
                let p = [10.4, 1.0 + k as f32 * 0.25, 0.5 + h as f32 * 0.25];
                xyz.push(p);
                hag.push(p[2]);
                lab.push(VEGETATION);
            }
        }
        let hedge = |check: &RoofCheck| {
            let mut l = lab.clone();
            check_roofs(&xyz, &hag, &mut l, None, check);
            l[n0..].iter().filter(|l| **l == BUILDING).count()
        };
        assert_eq!(hedge(&on()), 0);
        let cells = RoofCheck {
            beside_dist_m: 0.0,
            ..on()
        };
        assert_eq!(hedge(&cells), 72);
    }

    #[test]
    fn closing_bridges_gaps_and_keeps_outer_edges() {
        let cells: HashSet<[i32; 2]> = (0..10)
            .flat_map(|i| (0..4).map(move |j| [i, j]))
            .filter(|c| c[0] != 4 && c[0] != 5)
            .collect();
        let closed = close_cells(&cells, 2);
        assert!(closed.contains(&[4, 1]) && closed.contains(&[5, 2]));
        assert!(
            closed
                .iter()
                .all(|c| (0..10).contains(&c[0]) && (0..4).contains(&c[1]))
        );
        assert_eq!(close_cells(&cells, 0), cells);
        assert_eq!(cells_of(f32::NAN, 0.5), 0);
        assert_eq!(cells_of(1.0, 0.5), 2);
    }
}
