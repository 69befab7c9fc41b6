//! One building: planes → roof raster → partition → walls → closed solid.

use geo::{Contains, Coord, MultiPolygon};

use super::error::Skip;
use super::exterior::follow_footprint;
use super::params::ReconstructParams;
use super::partition::{Partition, regions, trace};
use super::saddle::split_saddles;
use super::solid::{Shell, build_shell, outline, split_crossings};
use super::untangle::undo_crossing_moves;
use super::walls::{Support, WallFit, snap_ridges, snap_walls};
use crate::geom::grid::GridFrame;
use crate::geom::normals::{Neighbourhoods, neighbourhoods};
use crate::geom::planes::{NO_PLANE, RoofPlane, grow_planes};
use crate::missing::GroundGrid;

/// One building's LoD2 model (local frame of the cloud it came from).
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    /// Building id (the footprint's).
    pub id: u32,
    /// Name (the footprint's).
    pub name: String,
    /// The closed solid.
    pub shell: Shell,
    /// The model's footprint.
    pub outline: MultiPolygon<f64>,
    /// Height of the base, m (local frame).
    pub base: f64,
    /// The base was raised to an underside seen in the points (open ground floor).
    pub open_base: bool,
    /// Roof planes found.
    pub planes: usize,
    /// Points used (after thinning).
    pub points: usize,
    /// Roof points per m² where the roof was seen, which sized its smallest
    /// part (`ReconstructParams::region_m2`); `None` without roof planes.
    pub roof_density: Option<f64>,
    /// Boundary segments fitted to wall points or to the outline.
    pub walls: WallFit,
    /// The model's level of detail.
    pub lod: Lod,
    /// Why the model fell back to LoD 1.2 (`None` for LoD 2.2).
    pub fallback: Option<Skip>,
    /// Its fit to its points and footprint, and its validity.
    pub quality: super::quality::ModelQuality,
}

/// The level of detail a model was made at (CityJSON `lod`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Lod {
    /// Roof planes, walls where the parts' heights differ (3DBAG's LoD 2.2).
    #[serde(rename = "2.2")]
    Lod22,
    /// The footprint extruded to one roof height (3DBAG's LoD 1.2).
    #[serde(rename = "1.2")]
    Lod12,
}

impl Lod {
    /// The CityJSON `lod` string.
    pub fn as_str(self) -> &'static str {
        match self {
            Lod::Lod22 => "2.2",
            Lod::Lod12 => "1.2",
        }
    }
}

/// What one building's reconstruction is given besides its points.
pub(crate) struct Inputs<'a> {
    /// Id and name of the building.
    pub id: u32,
    /// Name.
    pub name: &'a str,
    /// Its footprint.
    pub footprint: &'a MultiPolygon<f64>,
    /// The footprint was given (not derived from the points).
    pub given: bool,
    /// Terrain from the cloud's ground points, when it has any.
    pub ground: Option<&'a GroundGrid>,
}

/// A building's points' neighbourhoods and the roof planes grown on them
/// (each point's plane index or [`NO_PLANE`]); the model and its quality
/// measure both use them.
pub(crate) struct Grown {
    pub nb: Neighbourhoods,
    pub planes: Vec<RoofPlane>,
    pub label: Vec<u32>,
}

/// Grows the roof planes of a building's points `xyz`.
pub(crate) fn grow(xyz: &[[f32; 3]], params: &ReconstructParams) -> Grown {
    let nb = neighbourhoods(xyz, params.k);
    let (planes, label) = grow_planes(xyz, &nb, &params.plane_growth());
    Grown { nb, planes, label }
}

/// Per point of `xyz`: it lies on a roof plane grown as the
/// reconstruction grows them (roofer's points per roof plane).
pub fn on_roof_planes(xyz: &[[f32; 3]], params: &ReconstructParams) -> Vec<bool> {
    on_planes(&grow(xyz, params).label)
}

/// Per point: its plane label is a plane's.
pub(crate) fn on_planes(label: &[u32]) -> Vec<bool> {
    label.iter().map(|&l| l != NO_PLANE).collect()
}

/// Reconstructs one building from its points `xyz` (local frame) and the
/// roof planes grown on them ([`grow`]).
pub(crate) fn reconstruct_building(
    xyz: &[[f32; 3]],
    grown: &Grown,
    inp: &Inputs,
    params: &ReconstructParams,
) -> Result<Model, Skip> {
    if xyz.len() < params.min_plane_points.max(params.k + 1) {
        return Err(Skip::TooFewPoints);
    }
    let Grown { nb, planes, label } = grown;
    if planes.is_empty() {
        return Err(Skip::NoRoofPlane);
    }
    let bounds = bounds(inp.footprint).ok_or(Skip::EmptyFootprint)?;
    let cell = params.cell_m;
    let pad = 2.0 * cell;
    let grid = GridFrame {
        origin: [bounds[0] - pad, bounds[1] - pad],
        cell,
        nx: ((bounds[2] - bounds[0] + 2.0 * pad) / cell).ceil() as usize,
        ny: ((bounds[3] - bounds[1] + 2.0 * pad) / cell).ceil() as usize,
    };
    let ncell = grid.nx * grid.ny;
    let mask: Vec<bool> = (0..ncell)
        .map(|c| {
            let q = grid.centre(c);
            inp.footprint.contains(&Coord { x: q[0], y: q[1] })
        })
        .collect();
    if !mask.iter().any(|m| *m) {
        return Err(Skip::EmptyFootprint);
    }
    let code = roof_labels(xyz, label, planes, &grid, &mask);
    let mut codes = code;
    // Small parts keep real dormers at airborne densities; on dense clouds
    // they are mostly clutter planes of a few points (`region_m2`).
    let density = roof_density(xyz, label, &grid, &mask);
    let min_cells = (params.region_m2(density) / (cell * cell)).ceil() as usize;
    let (region, region_code) = regions(&grid, &mut codes, min_cells.max(1));
    let mut part = trace(&grid, &region, region_code.len() as u32, params.simplify_m);
    let region_plane: Vec<RoofPlane> = region_code
        .iter()
        .map(|&c| planes[c as usize - 1])
        .collect();
    let (base, open_base) = base_height(
        xyz,
        &nb.normal,
        inp,
        Cells {
            grid: &grid,
            mask: &mask,
            region: &region,
        },
        &region_plane,
        params.open_base_share,
    );
    let top = xyz.iter().map(|p| f64::from(p[2])).fold(f64::MIN, f64::max);
    let height = |r: u32, q: [f64; 2]| -> f64 {
        if r == 0 {
            return base;
        }
        region_plane.get(r as usize - 1).map_or(base, |pl| {
            pl.z_at(q[0], q[1])
                .clamp(base + 0.5, top.max(base + 0.5) + 1.0)
        })
    };
    let wall: Vec<usize> = (0..xyz.len())
        .filter(|&i| nb.normal[i][2].abs() <= params.wall_max_nz && label[i] == NO_PLANE)
        .collect();
    let wall_xyz: Vec<[f64; 3]> = wall.iter().map(|&i| xyz[i].map(f64::from)).collect();
    let wall_normal: Vec<[f64; 3]> = wall.iter().map(|&i| nb.normal[i]).collect();
    let outline_samples = outline_samples(inp.footprint, 0.25);
    // The boundaries as traced: they do not cross, where snapping can move
    // a vertex across a neighbouring boundary.
    let traced = part.clone();
    let fit = snap_walls(
        &mut part,
        &height,
        &Support {
            wall: &wall_xyz,
            wall_normal: &wall_normal,
            outline: &outline_samples,
            outline_first: inp.given,
        },
        params,
    );
    let plane_of = |r: u32| -> Option<[f64; 3]> {
        let pl = region_plane.get((r as usize).checked_sub(1)?)?;
        let n = pl.normal;
        Some([-n[0] / n[2], -n[1] / n[2], -pl.d / n[2]])
    };
    snap_ridges(&mut part, &plane_of, 1.5 * cell);
    let (shell, part, fit) =
        first_valid(part, traced, fit, inp, &height).ok_or(Skip::InvalidSolid)?;
    Ok(Model {
        id: inp.id,
        name: inp.name.to_string(),
        shell,
        outline: outline(&part),
        base,
        open_base,
        planes: region_plane.len(),
        points: xyz.len(),
        roof_density: density.is_finite().then_some(density),
        walls: fit,
        lod: Lod::Lod22,
        fallback: None,
        quality: Default::default(),
    })
}

/// The first valid solid of: the snapped partition `snapped`; the same
/// with the moves that make boundaries cross or touch undone; the
/// partition as `traced`. A given footprint's outline must be kept too
/// (else none); of a derived one, else the first valid one, else the
/// snapped solid (the caller then falls back to LoD 1.2, saying why).
fn first_valid(
    snapped: Partition,
    traced: Partition,
    fit: WallFit,
    inp: &Inputs,
    height: &dyn Fn(u32, [f64; 2]) -> f64,
) -> Option<(Shell, Partition, WallFit)> {
    let first = close(snapped.clone(), inp, height);
    if first.2 && first.3 {
        return Some((first.0, first.1, fit));
    }
    // A snapped vertex moved across another boundary, or onto it, crosses
    // a roof ring (104), or keeps the outline from following the
    // footprint: those moves go back, the others stay.
    let mut untangled = snapped;
    let mut tries = Vec::new();
    if undo_crossing_moves(&mut untangled, &traced) > 0 {
        tries.push((close(untangled, inp, height), fit));
    }
    // The traced boundaries, with walls on the raster's lines: still far
    // closer than the LoD 1.2 prism.
    tries.push((close(traced, inp, height), WallFit::default()));
    let mut best = (first.2, (first.0, first.1, fit));
    for ((s, p, valid, kept), f) in tries {
        if valid && kept {
            return Some((s, p, f));
        }
        if valid && !best.0 {
            best = (true, (s, p, f));
        }
    }
    // A given footprint's model that cannot keep its outline would leave
    // a gap or an overlap at its party walls: the LoD 1.2 prism keeps it.
    (!inp.given).then_some(best.1)
}

/// The closed solid on partition `part` (and the partition it was built
/// on), whether it is valid, and whether a given footprint's outline was
/// kept exactly; crossings and saddles split, warped roofs triangulated,
/// corners within 1 mm welded.
fn close(
    mut part: Partition,
    inp: &Inputs,
    height: &dyn Fn(u32, [f64; 2]) -> f64,
) -> (Shell, Partition, bool, bool) {
    // A given footprint is where the building stands: its outline is kept
    // exactly, so neighbours sharing a wall share it in their models too.
    let kept = !inp.given || follow_footprint(&mut part, inp.footprint).kept == 0;
    split_crossings(&mut part, height);
    // The new boundaries a split adds can have crossings of their own.
    if split_saddles(&mut part, height) > 0 {
        split_crossings(&mut part, height);
    }
    let mut shell = build_shell(&part, height);
    shell.split_warped_roofs(WARP_TOL_M);
    shell.weld(WELD_TOL_M);
    let valid = super::validity_codes(&shell).is_empty();
    (shell, part, valid, kept)
}

/// A roof face farther than this from planar is split into triangles
/// (half val3dity's 1 cm planarity tolerance, leaving room for the writers' 1 mm rounding).
const WARP_TOL_M: f64 = 0.005;

/// Corners closer than this are one vertex: val3dity's snapping tolerance.
const WELD_TOL_M: f64 = 0.001;

/// Fewest points a LoD 1.2 fallback takes its roof height from.
const FALLBACK_MIN_POINTS: usize = 3;

/// The LoD 1.2 model of a given footprint whose LoD 2.2 failed for `why`,
/// when it holds enough points to give it a height.
pub(crate) fn fallback_building(xyz: &[[f32; 3]], inp: &Inputs, why: Skip) -> Result<Model, Skip> {
    if xyz.is_empty() {
        return Err(Skip::NoPoints);
    }
    // A derived footprint without a roof plane is a fragment or clutter, not
    // a building someone named: only given footprints fall back.
    if !inp.given || xyz.len() < FALLBACK_MIN_POINTS || why == Skip::EmptyFootprint {
        return Err(why);
    }
    let (base, top) = super::prism::prism_heights(xyz, inp.footprint, inp.ground).ok_or(why)?;
    let shell = super::prism::prism(inp.footprint, base, top);
    if shell.faces.is_empty() {
        return Err(Skip::EmptyFootprint);
    }
    Ok(Model {
        id: inp.id,
        name: inp.name.to_string(),
        shell,
        outline: inp.footprint.clone(),
        base,
        open_base: false,
        planes: 0,
        points: xyz.len(),
        roof_density: None,
        walls: WallFit::default(),
        lod: Lod::Lod12,
        fallback: Some(why),
        quality: Default::default(),
    })
}

fn bounds(mp: &MultiPolygon<f64>) -> Option<[f64; 4]> {
    use geo::BoundingRect;
    let r = mp.bounding_rect()?;
    let b = [r.min().x, r.min().y, r.max().x, r.max().y];
    b.iter().all(|v| v.is_finite()).then_some(b)
}

/// Roof points per m² where the roof was seen: the points on a plane
/// inside the footprint over the area of the cells they fall in (a roof
/// half seen is as dense as a whole one); NaN without any.
pub(crate) fn roof_density(
    xyz: &[[f32; 3]],
    label: &[u32],
    grid: &GridFrame,
    mask: &[bool],
) -> f64 {
    let mut seen = vec![false; mask.len()];
    let mut n = 0usize;
    for (p, &l) in xyz.iter().zip(label) {
        if l == NO_PLANE {
            continue;
        }
        let Some(c) = grid.index_of(f64::from(p[0]), f64::from(p[1])) else {
            continue;
        };
        if mask[c] {
            seen[c] = true;
            n += 1;
        }
    }
    let cells = seen.iter().filter(|s| **s).count();
    n as f64 / (cells as f64 * grid.cell * grid.cell)
}

/// Per cell: the highest plane (1-based code) holding at least a quarter
/// as many of its points as the best-supported one, cells without points the nearest labelled
/// cell's plane, 0 outside the mask.
fn roof_labels(
    xyz: &[[f32; 3]],
    label: &[u32],
    planes: &[RoofPlane],
    grid: &GridFrame,
    mask: &[bool],
) -> Vec<u32> {
    let mut votes: Vec<(usize, u32)> = xyz
        .iter()
        .zip(label)
        .filter(|(_, l)| **l != NO_PLANE)
        .filter_map(|(p, &l)| {
            let c = grid.index_of(f64::from(p[0]), f64::from(p[1]))?;
            mask[c].then_some((c, l))
        })
        .collect();
    votes.sort_unstable();
    let mut code = vec![0u32; mask.len()];
    let mut k = 0;
    while k < votes.len() {
        let c = votes[k].0;
        let q = grid.centre(c);
        let mut here: Vec<(u32, usize, f64)> = Vec::new();
        while k < votes.len() && votes[k].0 == c {
            let l = votes[k].1;
            let mut n = 0;
            while k < votes.len() && votes[k] == (c, l) {
                n += 1;
                k += 1;
            }
            here.push((l, n, planes[l as usize].z_at(q[0], q[1])));
        }
        // The top surface is the roof: the highest plane with real support
        // wins, not the most points (a slab's underside scanned densely
        // from below must not replace the roof above it). At airborne
        // densities a cell often holds one point: it still labels the cell,
        // or the fill below spreads far planes over most of the roof.
        let most = here.iter().map(|h| h.1).max().unwrap_or(0);
        let best = here
            .iter()
            .filter(|h| (h.1 >= 2 || most < 2) && 4 * h.1 >= most)
            .max_by(|a, b| a.2.total_cmp(&b.2))
            .map_or(0, |h| h.0 + 1);
        code[c] = best;
    }
    // Multi-source breadth-first fill inside the mask.
    let mut queue: std::collections::VecDeque<usize> =
        (0..code.len()).filter(|&c| code[c] != 0).collect();
    while let Some(c) = queue.pop_front() {
        let (i, j) = (c % grid.nx, c / grid.nx);
        let nbs = [
            (i > 0).then(|| c - 1),
            (i + 1 < grid.nx).then(|| c + 1),
            (j > 0).then(|| c - grid.nx),
            (j + 1 < grid.ny).then(|| c + grid.nx),
        ];
        for n in nbs.into_iter().flatten() {
            if mask[n] && code[n] == 0 {
                code[n] = code[c];
                queue.push_back(n);
            }
        }
    }
    code
}

/// The footprint's raster: the grid, which cells are inside, and each
/// cell's roof region.
#[derive(Clone, Copy)]
struct Cells<'a> {
    grid: &'a GridFrame,
    mask: &'a [bool],
    region: &'a [u32],
}

/// The base: the lowest terrain under the footprint (the lowest point when
/// the cloud has no ground); raised to the underside when horizontal points
/// between the ground and the roof cover much of the footprint (a slab on
/// pillars, seen from below: only a ground sensor sees it).
fn base_height(
    xyz: &[[f32; 3]],
    normal: &[[f64; 3]],
    inp: &Inputs,
    cells: Cells<'_>,
    planes: &[RoofPlane],
    open_share: f64,
) -> (f64, bool) {
    let Cells { grid, mask, region } = cells;
    let lowest = xyz.iter().map(|p| f64::from(p[2])).fold(f64::MAX, f64::min);
    let Some(ground) = inp.ground else {
        return (lowest, false);
    };
    let mut base = f64::MAX;
    for c in (0..mask.len()).filter(|&c| mask[c]) {
        let q = grid.centre(c);
        if let Some(z) = ground.at(q[0], q[1]) {
            base = base.min(f64::from(z));
        }
    }
    if base == f64::MAX {
        return (lowest, false);
    }
    // Horizontal points at least 1 m above the ground and 1 m below their roof.
    let mut cells = vec![false; mask.len()];
    let mut under: Vec<f64> = xyz
        .iter()
        .zip(normal)
        .filter(|(_, n)| n[2] > 0.9)
        .filter_map(|(p, _)| {
            let (x, y, z) = (f64::from(p[0]), f64::from(p[1]), f64::from(p[2]));
            let c = grid.index_of(x, y)?;
            let r = region[c];
            let roof = planes.get((r as usize).checked_sub(1)?)?.z_at(x, y);
            let g = f64::from(ground.at(x, y)?);
            let hit = z > g + 1.0 && z < roof - 1.0;
            if hit {
                cells[c] = true;
            }
            hit.then_some(z)
        })
        .collect();
    let inside = mask.iter().filter(|m| **m).count();
    let covered = cells.iter().filter(|c| **c).count();
    if (covered as f64) < open_share * inside as f64 {
        return (base, false);
    }
    under.sort_by(f64::total_cmp);
    (under[under.len() / 10].max(base), true)
}

/// Points every `step` m along the footprint's rings with the ring's direction there.
fn outline_samples(mp: &MultiPolygon<f64>, step: f64) -> Vec<([f64; 2], [f64; 2])> {
    let mut out = Vec::new();
    for poly in &mp.0 {
        for ring in std::iter::once(poly.exterior()).chain(poly.interiors()) {
            for l in ring.lines() {
                let d = [l.end.x - l.start.x, l.end.y - l.start.y];
                let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
                if len <= 0.0 {
                    continue;
                }
                let u = [d[0] / len, d[1] / len];
                let n = (len / step).ceil() as usize;
                for k in 0..n {
                    let t = (k as f64 + 0.5) / n as f64;
                    out.push(([l.start.x + t * d[0], l.start.y + t * d[1]], u));
                }
            }
        }
    }
    out
}
