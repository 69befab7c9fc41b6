//! Missing-region detection of one building (docs/design.md step 3).

use geo::{Area, CoordsIter, MultiPolygon};
use rayon::prelude::*;

use super::band::BandIndex;
use super::boundary::sample_contour;
use super::coverage::{Strip, strip_coverage};
use super::detection::{
    BoundaryPoint, BuildingDetection, MissingPoint, SkipReason, SliceReport, Strategy,
    StructureReport,
};
use super::ground::GroundGrid;
use super::params::DetectParams;
use super::wall::{face_below, open_below, wall_normal};
use crate::geom::grid::GridFrame;
use crate::params::ParamError;
use crate::skeleton::{Skeleton, medial_axis};
use crate::slice::{Sliced, cluster_structures, slice_building};

/// Cell of the band index, metres (strips are ~1–2 m across).
const INDEX_CELL: f64 = 1.0;
/// Below this skeleton–contour distance the segment has no usable direction.
const MIN_SEGMENT: f64 = 0.5;
/// A tested wall part shorter than this (in z) is not tested.
const MIN_WALL_Z: f32 = 0.1;
/// Wall parts this close above the terrain are not tested (the ground hides them).
const GROUND_CLEARANCE: f32 = 0.1;
/// How far out from an outline the survey's edge is looked for, metres: a
/// tile cut leaves the building's points within a point spacing or two of it.
const EDGE_PROBE: f64 = 1.5;

/// Finds the missing boundary points of building `id` from its `points`.
/// `footprint` (local frame), when given, is C_building and replaces the
/// derived outline of the lowest structure; `ground_z` defaults to the
/// lowest point. Too few points or a degenerate footprint give a building
/// marked `skipped`, not an error.
pub fn detect_building(
    id: u32,
    points: &[[f32; 3]],
    footprint: Option<&MultiPolygon<f64>>,
    ground_z: Option<f32>,
    params: &DetectParams,
) -> Result<BuildingDetection, ParamError> {
    detect_building_on(id, points, footprint, ground_z, None, params)
}

/// [`detect_building`] with the terrain around the building: walls are
/// tested only above the local ground outside them.
pub fn detect_building_on(
    id: u32,
    points: &[[f32; 3]],
    footprint: Option<&MultiPolygon<f64>>,
    ground_z: Option<f32>,
    terrain: Option<&GroundGrid>,
    params: &DetectParams,
) -> Result<BuildingDetection, ParamError> {
    params.validate()?;
    let params = &params.resolved_for(points);
    let n = points
        .iter()
        .filter(|p| p.iter().all(|v| v.is_finite()))
        .count();
    if n < params.min_points.max(1) {
        let reason = SkipReason::TooFewPoints {
            points: n,
            min: params.min_points.max(1),
        };
        return Ok(BuildingDetection::skipped(id, n, reason));
    }
    if let Some(fp) = footprint {
        let area = fp.unsigned_area();
        let finite = fp.coords_iter().all(|c| c.x.is_finite() && c.y.is_finite());
        if !finite || area.is_nan() || area < params.slice.min_area {
            let reason = SkipReason::DegenerateFootprint { area };
            return Ok(BuildingDetection::skipped(id, n, reason));
        }
    }
    let Some(sliced) = slice_building(points, ground_z, &params.slice) else {
        let reason = SkipReason::TooFewPoints {
            points: 0,
            min: params.min_points,
        };
        return Ok(BuildingDetection::skipped(id, n, reason));
    };
    let global = footprint.cloned().unwrap_or_else(|| sliced.global.clone());
    if sliced.levels.iter().all(|l| l.parts.is_empty()) || global.0.is_empty() {
        let reason = SkipReason::NoContour {
            height: sliced.top_z - sliced.ground_z,
            area: sliced.global.unsigned_area(),
        };
        return Ok(BuildingDetection::skipped(id, n, reason));
    }
    let input = Input {
        id,
        n,
        points,
        footprint,
        terrain,
    };
    Ok(analyse(&input, &sliced, global, params))
}

/// One building's inputs, passed on together.
struct Input<'a> {
    id: u32,
    n: usize,
    points: &'a [[f32; 3]],
    footprint: Option<&'a MultiPolygon<f64>>,
    terrain: Option<&'a GroundGrid>,
}

fn analyse(
    input: &Input,
    sliced: &Sliced,
    global: MultiPolygon<f64>,
    params: &DetectParams,
) -> BuildingDetection {
    let Input {
        id,
        n,
        points,
        footprint,
        terrain,
    } = *input;
    let levels = &sliced.levels;
    let (mut structures, assign) = cluster_structures(levels, params.structure_keep);
    if let Some(fp) = footprint {
        for s in structures.iter_mut().filter(|s| s.base_level == 0) {
            s.contour = fp.clone();
        }
    }
    let skeletons: Vec<Skeleton> = structures
        .par_iter()
        .map(|s| medial_axis(&s.contour, &params.skeleton))
        .collect();

    let delta = params.delta_m();
    let grid = &sliced.grid;
    let frame = GridFrame {
        origin: grid.origin,
        cell: INDEX_CELL,
        nx: (grid.nx as f64 * grid.cell / INDEX_CELL).ceil() as usize + 1,
        ny: (grid.ny as f64 * grid.cell / INDEX_CELL).ceil() as usize + 1,
    };
    let base = levels.first().map_or(0.0, |l| l.band[0]);
    let index = BandIndex::new(points, base, params.slice.spacing_m(), levels.len(), frame);

    let per_level: Vec<(SliceReport, Vec<BoundaryPoint>)> = levels
        .par_iter()
        .enumerate()
        .map(|(k, level)| {
            crate::work::step();
            let mut tested: Vec<(MultiPolygon<f64>, usize)> = Vec::new();
            let mut footprint_done = false;
            for (p, (_, contour)) in level.parts.iter().enumerate() {
                let sid = assign[k][p];
                if footprint.is_some() && structures[sid].base_level == 0 {
                    if !footprint_done {
                        tested.push((structures[sid].contour.clone(), sid));
                        footprint_done = true;
                    }
                } else {
                    tested.push((contour.clone(), sid));
                }
            }
            let mut boundary = Vec::new();
            for (contour, sid) in &tested {
                for sample in sample_contour(contour, params.boundary_spacing) {
                    let q = sample.xy;
                    // An outline facing the survey's edge is where the tile
                    // cut the building: there is no wall there to miss.
                    if terrain.is_some_and(|t| {
                        t.beyond_data(
                            q[0] + EDGE_PROBE * sample.normal[0],
                            q[1] + EDGE_PROBE * sample.normal[1],
                        )
                    }) {
                        continue;
                    }
                    let (s, dir) = segment(&skeletons[*sid], q, sample.normal);
                    let top = local_top(sliced, q, params.near);
                    // Terrain just outside the wall: the wall's foot.
                    let foot = terrain
                        .and_then(|t| t.at(q[0] + sample.normal[0], q[1] + sample.normal[1]))
                        .unwrap_or(f32::NEG_INFINITY);
                    let z = [
                        level.band[0].max(foot + GROUND_CLEARANCE),
                        level.band[1].min(top),
                    ];
                    if z[1] - z[0] < MIN_WALL_Z {
                        continue;
                    }
                    // The strip is measured across the wall the points
                    // trace: s→q runs at 45° near corners of the skeleton,
                    // or along the wall at a chamfered contour corner, and a
                    // slanted strip sees a covered wall as partly empty.
                    let wall_dir = wall_normal(&index, k, q, dir, 2.0 * delta).unwrap_or(dir);
                    let mut strip = Strip {
                        q,
                        dir: wall_dir,
                        half_width: delta,
                        near: params.near,
                        outside: params.outside,
                        band: k,
                        z,
                        radius: params.coverage_radius,
                    };
                    let mut cover = strip_coverage(&index, &strip);
                    // Ground seen behind the outline: an open ground floor.
                    // Without points there is no wall to miss; the outline's
                    // own face (a slab's facade) starts at its lowest point,
                    // while points set back (pillars) are tested as they are.
                    // Unless the face is seen in a lower band: then the wall
                    // reaches down past this one, and the ground seen is that
                    // at its foot (probes run along s→q, often oblique to the
                    // wall, in 0.5 m cells) or under a lower floor.
                    let open = cover.share < params.min_coverage
                        && terrain.is_some_and(|t| open_below(t, contour, q, dir, delta))
                        && !face_below(&index, &strip);
                    if open {
                        if cover.wall_offset.is_none() {
                            continue;
                        }
                        if let Some(lo) = cover.face_z_min.filter(|&lo| lo > z[0]) {
                            if z[1] - lo < MIN_WALL_Z {
                                continue;
                            }
                            strip.z = [lo, z[1]];
                            cover = strip_coverage(&index, &strip);
                        }
                    }
                    let coverage = cover.share;
                    // Report the point on the wall: where the strip's points
                    // put it, else half a raster cell in (the outline lies
                    // up to a cell outside the wall).
                    let off = cover.wall_offset.unwrap_or(-0.5 * params.slice.cell_m());
                    let at = [q[0] + wall_dir[0] * off, q[1] + wall_dir[1] * off];
                    boundary.push(BoundaryPoint {
                        xyz: [at[0] as f32, at[1] as f32, 0.5 * (strip.z[0] + strip.z[1])],
                        normal: [dir[0] as f32, dir[1] as f32],
                        skeleton: [s[0] as f32, s[1] as f32],
                        coverage,
                        collected: coverage >= params.min_coverage,
                        slice: k as u32,
                    });
                }
            }
            let missing = boundary.iter().filter(|b| !b.collected).count();
            let report = SliceReport {
                height: level.height,
                points: level.points,
                contour: MultiPolygon(tested.iter().flat_map(|(c, _)| c.0.clone()).collect()),
                structures: tested.iter().map(|(_, s)| *s).collect(),
                boundary: boundary.len(),
                missing,
            };
            (report, boundary)
        })
        .collect();

    let mut slices = Vec::with_capacity(per_level.len());
    let mut boundary = Vec::new();
    for (report, b) in per_level {
        slices.push(report);
        boundary.extend(b);
    }
    let missing: Vec<MissingPoint> = boundary
        .iter()
        .filter(|b| !b.collected)
        .map(|b| MissingPoint {
            xyz: b.xyz,
            building: id,
            normal: b.normal,
            skeleton: b.skeleton,
        })
        .collect();
    let r_missing = if boundary.is_empty() {
        0.0
    } else {
        missing.len() as f32 / boundary.len() as f32
    };
    let height_of = |k: usize| levels.get(k).map_or(0.0, |l| l.height);
    BuildingDetection {
        building: id,
        footprint_id: String::new(),
        points: n,
        skipped: None,
        ground_z: sliced.ground_z,
        top_z: sliced.top_z,
        global_contour: global,
        slices,
        structures: structures
            .into_iter()
            .zip(skeletons)
            .map(|(s, skeleton)| StructureReport {
                heights: [height_of(s.base_level), height_of(s.top_level)],
                contour: s.contour,
                skeleton,
            })
            .collect(),
        boundary,
        missing,
        r_missing,
        strategy: if r_missing < params.theta {
            Strategy::PointBased
        } else {
            Strategy::RegionBased
        },
    }
}

/// s_m and the unit direction s_m → q_n; the contour normal stands in when
/// the skeleton is missing, too close to q_n, or points along the wall.
fn segment(skeleton: &Skeleton, q: [f64; 2], normal: [f64; 2]) -> ([f64; 2], [f64; 2]) {
    if let Some(s) = skeleton.nearest(q) {
        let d = [q[0] - s[0], q[1] - s[1]];
        let len = d[0].hypot(d[1]);
        if len >= MIN_SEGMENT {
            let dir = [d[0] / len, d[1] / len];
            if dir[0] * normal[0] + dir[1] * normal[1] > 0.2 {
                return (s, dir);
            }
        }
    }
    let s = [
        q[0] - normal[0] * MIN_SEGMENT,
        q[1] - normal[1] * MIN_SEGMENT,
    ];
    (s, normal)
}

/// Highest building point within `r` (square) of `q`: where the wall ends.
fn local_top(sliced: &Sliced, q: [f64; 2], r: f64) -> f32 {
    let g = &sliced.grid;
    let lo = |v: f64, o: f64| ((v - r - o) / g.cell).floor().max(0.0) as usize;
    let hi =
        |v: f64, o: f64, n: usize| (((v + r - o) / g.cell).floor().max(0.0) as usize).min(n - 1);
    let mut top = f32::NEG_INFINITY;
    for j in lo(q[1], g.origin[1])..=hi(q[1], g.origin[1], g.ny) {
        for i in lo(q[0], g.origin[0])..=hi(q[0], g.origin[0], g.nx) {
            top = top.max(sliced.top[j * g.nx + i]);
        }
    }
    top
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 12 × 10 m slab on an open ground floor (floor 4 m, roof 12 m; its
    /// pillars unseen). The aerial view sees the roof, every facade from the
    /// floor up except the south one between 6 and 10 m (occluded), and the
    /// ground outside and up to 3 m in under the slab.
    fn slab() -> (Vec<[f32; 3]>, GroundGrid) {
        let grid = |n: usize, m: usize| (0..n).flat_map(move |i| (0..m).map(move |j| (i, j)));
        let mut pts: Vec<[f32; 3]> = grid(49, 41)
            .map(|(i, j)| [i as f32 * 0.25, j as f32 * 0.25, 12.0])
            .collect();
        for (i, k) in grid(49, 33) {
            let (s, z) = (i as f32 * 0.25, 4.0 + k as f32 * 0.25);
            if s <= 10.0 {
                pts.push([0.0, s, z]);
                pts.push([12.0, s, z]);
            }
            pts.push([s, 10.0, z]);
            if !(6.0..10.0).contains(&z) {
                pts.push([s, 0.0, z]);
            }
        }
        let ground: Vec<[f32; 3]> = grid(97, 89)
            .map(|(i, j)| [-6.0 + i as f32 * 0.25, -6.0 + j as f32 * 0.25, 0.0])
            .filter(|p| !((3.0..9.0).contains(&p[0]) && (3.0..7.0).contains(&p[1])))
            .collect();
        let terrain = GroundGrid::from_points(&ground, 2.0, 40).expect("ground points");
        (pts, terrain)
    }

    #[test]
    fn open_floor_is_skipped_but_a_facade_seen_lower_down_is_tested() {
        let (pts, terrain) = slab();
        let params = DetectParams::default();
        let det = detect_building_on(1, &pts, None, Some(0.0), Some(&terrain), &params)
            .expect("valid params");
        assert!(det.skipped.is_none(), "{:?}", det.skipped);
        let south: Vec<&BoundaryPoint> = det
            .boundary
            .iter()
            .filter(|p| p.xyz[1] < 1.0 && (1.0..11.0).contains(&p.xyz[0]))
            .collect();
        // Under the floor: ground behind the outline and no face: not tested.
        assert!(
            south.iter().all(|p| p.xyz[2] > 4.0),
            "tested under the floor"
        );
        // Between 6 and 10 m the facade is missing: it is seen from 4 m up,
        // so the ground seen under the slab does not excuse it.
        let gap: Vec<_> = south
            .iter()
            .filter(|p| (6.0..10.0).contains(&p.xyz[2]))
            .collect();
        assert!(gap.len() >= 20, "gap tested at {} points", gap.len());
        assert!(gap.iter().all(|p| !p.collected));
        // Where it is seen, it is collected.
        assert!(
            south
                .iter()
                .filter(|p| !(5.5..10.5).contains(&p.xyz[2]))
                .all(|p| p.collected)
        );
    }

    /// A 12 × 10 m block cut by the survey's east edge at x = 12: roof and
    /// the other three facades seen, the north one missing above 4 m.
    #[test]
    fn outline_at_the_survey_edge_is_not_a_missing_wall() {
        let grid = |n: usize, m: usize| (0..n).flat_map(move |i| (0..m).map(move |j| (i, j)));
        let mut pts: Vec<[f32; 3]> = grid(49, 41)
            .map(|(i, j)| [i as f32 * 0.25, j as f32 * 0.25, 8.0])
            .collect();
        for (i, k) in grid(49, 33) {
            let (s, z) = (i as f32 * 0.25, k as f32 * 0.25);
            if s <= 10.0 {
                pts.push([0.0, s, z]);
            }
            pts.push([s, 0.0, z]);
            if z < 4.0 {
                pts.push([s, 10.0, z]);
            }
        }
        let ground: Vec<[f32; 3]> = grid(73, 89)
            .map(|(i, j)| [-6.0 + i as f32 * 0.25, -6.0 + j as f32 * 0.25, 0.0])
            .filter(|p| !((0.0..=12.0).contains(&p[0]) && (0.0..=10.0).contains(&p[1])))
            .collect();
        let terrain = GroundGrid::from_points(&ground, 2.0, 40).expect("ground points");
        let det = detect_building_on(
            1,
            &pts,
            None,
            Some(0.0),
            Some(&terrain),
            &DetectParams::default(),
        )
        .expect("valid params");
        let east = det
            .boundary
            .iter()
            .filter(|p| p.xyz[0] > 11.0 && (1.0..9.0).contains(&p.xyz[1]));
        assert_eq!(east.count(), 0, "the cut was tested as a wall");
        let north_gap = det
            .missing
            .iter()
            .filter(|m| m.xyz[1] > 9.0 && m.xyz[2] > 4.0 && m.xyz[0] < 11.0)
            .count();
        assert!(north_gap >= 10, "north gap: {north_gap} missing points");
    }
}
