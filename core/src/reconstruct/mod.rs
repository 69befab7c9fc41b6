//! Step 10 of the method: a watertight LoD2 model per building, from the
//! cloud before and after the ground scans, and its accuracy against the
//! ground-truth mesh.
//!
//! Per building (footprint given, or derived from its points):
//! - roof planes by region growing on PCA normals ([`crate::geom`]'s
//!   `normals` and `planes`, which classification's roof check shares);
//! - `partition`: a raster over the footprint labelled with the best plane
//!   per cell (roofer's idea of labelling an arrangement), traced into
//!   chains shared by neighbouring regions;
//! - `walls`: boundary segments between parts of different height move
//!   onto the wall points along them; without wall points they keep the
//!   footprint's line, so a wall the cloud missed stays approximate;
//! - `untangle`: a snapped vertex that would make two boundaries cross
//!   or touch goes back to its traced position;
//! - `exterior`: a given footprint's outline replaces the traced one
//!   exactly, so the models of footprints sharing a wall share it;
//! - `prism`: the LoD 1.2 fallback where no roof plane is found;
//! - [`party`]: how neighbours' models meet along the boundary their
//!   footprints share (gaps, overlaps);
//! - `saddle`: a node where the parts around alternate in height (two
//!   high parts touching at one corner) is split in two, so the solid
//!   stays a 2-manifold there;
//! - `solid`: roof faces, vertical faces and the base as one closed shell
//!   ([`Shell::check`] counts edge uses);
//! - the models are written by [`crate::io`] (CityJSON, OBJ);
//!   [`evaluate`]: distances to the truth;
//!   [`compare`]: before against after.

mod building;
mod compare;
mod error;
pub mod evaluate;
mod exterior;
mod params;
mod partition;
pub mod party;
mod prism;
pub mod quality;
mod saddle;
mod solid;
mod untangle;
mod walls;

#[cfg(test)]
mod tests;

pub use crate::geom::planes::RoofPlane;
pub use building::{Lod, Model, on_roof_planes};
pub use compare::{BeforeAfter, PRIOR_OFF_M, compare};
pub use error::{ReconstructError, Skip};
pub use evaluate::{DistanceStats, ModelEvaluation, ModelScore, evaluate_models};
pub use params::ReconstructParams;
pub use quality::ModelQuality;
pub use solid::{ModelFace, Shell, SolidCheck, SurfaceType};
pub use walls::WallFit;

use rayon::prelude::*;
use rustc_hash::FxHashMap;

use crate::cloud::{Cloud, class};
use crate::footprint::{Footprint, derive, split};
use crate::missing::GroundGrid;

/// Terrain grid cell (m) and hole fill (cells): fills under the widest
/// reference buildings from both sides.
const TERRAIN_CELL: f32 = 1.0;
const TERRAIN_FILL: usize = 60;

/// Every building's model from one cloud.
#[derive(Debug, Clone, PartialEq)]
pub struct Reconstruction {
    /// The cloud's origin: model vertices are relative to it.
    pub origin: [f64; 3],
    /// The cloud's CRS: the writers put the models in its coordinates and unit.
    pub crs: Option<crate::crs::Crs>,
    /// Models, by building id.
    pub models: Vec<Model>,
    /// Buildings without a model, and why.
    pub skipped: Vec<(u32, Skip)>,
    /// Footprints came from the caller (else derived from the points).
    pub footprints_given: bool,
    /// Models of BuildingParts: the own id of the Building each belongs to,
    /// by model id (the footprints' `Loaded::part_of`); written as parts.
    pub part_of: std::collections::BTreeMap<u32, String>,
}

impl Reconstruction {
    /// The frame the models' vertices go back to the cloud's CRS and unit by.
    pub fn frame(&self) -> crate::crs::SourceFrame {
        crate::crs::SourceFrame::new(self.origin, self.crs.clone())
    }
}

/// Reconstructs every building of `cloud`: its building points (class 6;
/// all points when unlabelled, or labelled only 0/1) split by `footprints` (same frame as the
/// cloud), or by footprints derived from the points when `None`.
pub fn reconstruct_cloud(
    cloud: &Cloud,
    footprints: Option<&[Footprint]>,
    params: &ReconstructParams,
) -> Result<Reconstruction, ReconstructError> {
    params.validate()?;
    // Labels that are all 0 (never classified) or 1 (unclassified), as a
    // LAS file straight from the scanner has, say nothing about which points
    // are buildings: as with no labels, every point is used.
    let labels = cloud
        .label
        .as_ref()
        .filter(|l| l.iter().any(|&c| c > class::UNCLASSIFIED));
    let is = |i: usize, c: u8| labels.is_none_or(|l| l.get(i) == Some(&c));
    let building: Vec<[f32; 3]> = (0..cloud.len())
        .filter(|&i| is(i, class::BUILDING))
        .map(|i| cloud.xyz[i])
        .filter(|p| p.iter().all(|v| v.is_finite()))
        .collect();
    let building = thin(&building, params.voxel_m);
    let mut out = Reconstruction {
        origin: cloud.origin,
        crs: cloud.crs.clone(),
        models: Vec::new(),
        skipped: Vec::new(),
        footprints_given: footprints.is_some(),
        part_of: Default::default(),
    };
    if building.is_empty() {
        // A classified tile without buildings has no models; an empty or
        // unclassified cloud has nothing to say which points are buildings.
        return match labels {
            Some(_) if !cloud.is_empty() => Ok(out),
            _ => Err(ReconstructError::NoBuildingPoints),
        };
    }
    let ground = cloud.xyz_of_class(class::GROUND);
    let terrain = GroundGrid::from_points(&ground, TERRAIN_CELL, TERRAIN_FILL);
    let derived;
    let fps: &[Footprint] = match footprints {
        Some(f) => f,
        None => {
            derived = derive(&building, &params.derive)?;
            &derived
        }
    };
    let ids = split(&building, fps, &params.split)?;
    let mut per: FxHashMap<u32, Vec<[f32; 3]>> = FxHashMap::default();
    for (p, id) in building.iter().zip(ids) {
        if id != 0 {
            per.entry(id).or_default().push(*p);
        }
    }
    // A footprint that others cover entirely (two cadastral records of one
    // house) wins no point in `split`; it takes the points inside it instead.
    if footprints.is_some() {
        let empty: Vec<&Footprint> = fps.iter().filter(|f| !per.contains_key(&f.id)).collect();
        for f in empty {
            let inside = points_inside(&building, f);
            if !inside.is_empty() {
                per.insert(f.id, inside);
            }
        }
    }
    let results: Vec<Result<Model, (u32, Skip)>> = fps
        .par_iter()
        .map(|f| {
            let pts = per.get(&f.id).map_or(&[][..], |v| v.as_slice());
            let inp = building::Inputs {
                id: f.id,
                name: &f.name,
                footprint: &f.polygon,
                given: footprints.is_some(),
                ground: terrain.as_ref(),
            };
            let grown = building::grow(pts, params);
            let mut m = building::reconstruct_building(pts, &grown, &inp, params)
                .or_else(|why| building::fallback_building(pts, &inp, why))
                .map_err(|s| (f.id, s))?;
            let on_plane = building::on_planes(&grown.label);
            let measured = (pts, &on_plane[..]);
            m.quality = quality::assess(&m.shell, &m.outline, measured, &f.polygon);
            // A named building gets a valid model: its LoD 1.2 prism, saying
            // why, rather than a LoD 2.2 solid that fails the checks.
            if !m.quality.val3dity.is_empty()
                && m.lod == Lod::Lod22
                && let Ok(mut p) = building::fallback_building(pts, &inp, Skip::InvalidSolid)
            {
                p.quality = quality::assess(&p.shell, &p.outline, measured, &f.polygon);
                if p.quality.val3dity.is_empty() {
                    p.quality.rejected_val3dity = std::mem::take(&mut m.quality.val3dity);
                    m = p;
                }
            }
            Ok(m)
        })
        .collect();
    for r in results {
        match r {
            Ok(m) => out.models.push(m),
            Err(s) => out.skipped.push(s),
        }
    }
    Ok(out)
}

/// The points of `xyz` inside `f`'s polygon (x, y).
fn points_inside(xyz: &[[f32; 3]], f: &Footprint) -> Vec<[f32; 3]> {
    use geo::{Contains, Coord};
    let Some(b) = f.bounds() else {
        return Vec::new();
    };
    xyz.iter()
        .filter(|p| {
            let (x, y) = (f64::from(p[0]), f64::from(p[1]));
            x >= b[0] && x <= b[2] && y >= b[1] && y <= b[3] && f.polygon.contains(&Coord { x, y })
        })
        .copied()
        .collect()
}

/// The val3dity codes `shell` fails (ISO 19107 checks of [`crate::validity`],
/// val3dity's tolerances), each once, in order.
pub fn validity_codes(shell: &Shell) -> Vec<u16> {
    let solid = crate::validity::Solid {
        vertices: shell.vertices.clone(),
        shells: vec![
            shell
                .faces
                .iter()
                .map(|f| {
                    f.rings
                        .iter()
                        .map(|r| r.iter().map(|&v| v as usize).collect())
                        .collect()
                })
                .collect(),
        ],
    };
    let mut codes: Vec<u16> =
        crate::validity::check_solid(&solid, &crate::validity::Tolerances::default())
            .into_iter()
            .map(|f| f.code)
            .collect();
    codes.sort_unstable();
    codes.dedup();
    codes
}

/// One point per voxel of `edge` m: the one nearest the voxel's centre
/// (ties to the lower coordinates), so the result does not depend on the
/// points' order; `edge` 0 keeps all.
fn thin(xyz: &[[f32; 3]], edge: f64) -> Vec<[f32; 3]> {
    if edge <= 0.0 {
        return xyz.to_vec();
    }
    let mut best: FxHashMap<[i64; 3], (f64, [f32; 3])> = FxHashMap::default();
    for p in xyz {
        let s = p.map(|v| f64::from(v) / edge);
        let key = s.map(|v| v.floor() as i64);
        let d: f64 = s.iter().map(|v| (v - v.floor() - 0.5).powi(2)).sum();
        best.entry(key)
            .and_modify(|b| {
                let nearer = d.total_cmp(&b.0).then_with(|| {
                    p.iter()
                        .zip(&b.1)
                        .map(|(x, y)| x.total_cmp(y))
                        .find(|o| o.is_ne())
                        .unwrap_or(std::cmp::Ordering::Equal)
                });
                if nearer.is_lt() {
                    *b = (d, *p);
                }
            })
            .or_insert((d, *p));
    }
    let mut kept: Vec<([i64; 3], [f32; 3])> = best.into_iter().map(|(k, v)| (k, v.1)).collect();
    // Voxel order, so the rest of the pipeline sees the same sequence too.
    kept.sort_unstable_by_key(|e| e.0);
    kept.into_iter().map(|e| e.1).collect()
}

#[cfg(test)]
mod thin_tests {
    use super::thin;

    #[test]
    fn thinning_keeps_the_point_nearest_each_voxel_centre_whatever_the_order() {
        let pts: Vec<[f32; 3]> = (0..500)
            .map(|k| {
                let t = k as f32;
                [(t * 0.37).sin() * 3.0, (t * 0.11).cos() * 3.0, t * 0.01]
            })
            .collect();
        let a = thin(&pts, 0.5);
        let mut rev = pts.clone();
        rev.reverse();
        assert_eq!(a, thin(&rev, 0.5));
        assert!(a.len() < pts.len() && !a.is_empty());
        let two = [[0.05f32, 0.05, 0.05], [0.24, 0.26, 0.25], [0.4, 0.4, 0.4]];
        assert_eq!(thin(&two, 0.5), vec![[0.24, 0.26, 0.25]]);
        assert_eq!(thin(&two, 0.0).len(), 3);
    }
}
