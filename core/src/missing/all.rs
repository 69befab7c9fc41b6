//! Detection over every building of a cloud, in parallel.

use std::collections::BTreeMap;

use geo::MultiPolygon;
use rayon::prelude::*;
use thiserror::Error;

use super::building::detect_building_on;
use super::detection::{BuildingDetection, Detection, SkipReason};
use super::ground::GroundGrid;
use super::params::DetectParams;
use crate::cloud::ColumnLength;
use crate::density::Density;
use crate::params::ParamError;

/// Why detection over a cloud could not run.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum DetectError {
    /// Parameters are invalid.
    #[error(transparent)]
    Params(#[from] ParamError),
    /// The building-id column does not match the points.
    #[error(transparent)]
    IdLength(#[from] ColumnLength),
}

/// Runs [`detect_building`] on every building id (> 0) in `building` (one id
/// per point of `xyz`). `footprints` (id, polygon in the cloud's local
/// frame) replace derived outlines; a footprint without points is reported
/// as skipped. Buildings come back in ascending id order.
pub fn detect_all(
    xyz: &[[f32; 3]],
    building: &[u32],
    footprints: Option<&[(u32, MultiPolygon<f64>)]>,
    params: &DetectParams,
) -> Result<Detection, DetectError> {
    detect_all_on(xyz, building, footprints, None, params)
}

/// [`detect_all`] with the terrain (e.g. from the cloud's ground points), so
/// walls on sloped ground are tested only above their foot.
pub fn detect_all_on(
    xyz: &[[f32; 3]],
    building: &[u32],
    footprints: Option<&[(u32, MultiPolygon<f64>)]>,
    terrain: Option<&GroundGrid>,
    params: &DetectParams,
) -> Result<Detection, DetectError> {
    params.validate()?;
    ColumnLength::check("building ids", xyz.len(), building.len())?;
    // One density for the whole cloud's buildings, so every building is
    // sliced alike.
    let own: Vec<[f32; 3]> = xyz
        .iter()
        .zip(building)
        .filter(|(_, id)| **id > 0)
        .map(|(p, _)| *p)
        .collect();
    let density = Density::measure(&own);
    let params = &params.resolved_for(&own);
    let mut groups: BTreeMap<u32, Vec<[f32; 3]>> = BTreeMap::new();
    for (p, &id) in xyz.iter().zip(building) {
        if id > 0 {
            groups.entry(id).or_default().push(*p);
        }
    }
    let fp: BTreeMap<u32, &MultiPolygon<f64>> = footprints
        .unwrap_or(&[])
        .iter()
        .map(|(id, m)| (*id, m))
        .collect();
    for id in fp.keys() {
        groups.entry(*id).or_default();
    }
    // Largest first so one big building does not start last on a busy pool.
    let mut jobs: Vec<(u32, Vec<[f32; 3]>)> = groups.into_iter().collect();
    jobs.sort_by_key(|(_, pts)| std::cmp::Reverse(pts.len()));
    let mut buildings =
        jobs.par_iter()
            .map(|(id, pts)| {
                crate::work::step();
                detect_building_on(*id, pts, fp.get(id).copied(), None, terrain, params)
                    .unwrap_or_else(|_| {
                        // validate() passed above, so this is unreachable in practice.
                        BuildingDetection::skipped(
                            *id,
                            pts.len(),
                            SkipReason::TooFewPoints {
                                points: pts.len(),
                                min: params.min_points,
                            },
                        )
                    })
            })
            .collect::<Vec<_>>();
    buildings.sort_by_key(|b| b.building);
    Ok(Detection {
        buildings,
        params: Some(params.clone()),
        density,
    })
}
