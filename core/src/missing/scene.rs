//! Steps 2–3 on a whole classified cloud: buildings by footprints (given or
//! derived), then where each one's walls are missing.

use std::borrow::Cow;

use super::all::{DetectError, detect_all_on};
use super::detection::{Detection, MissingPoint};
use super::ground::GroundGrid;
use super::params::DetectParams;
use crate::cloud::{Cloud, class};
use crate::footprint::{DeriveParams, Footprint, SplitParams, derive, split};
use crate::params::ParamError;

/// What [`detect_scene`] runs with: the completeness detector's params
/// sections `detect`, `split` and `derive`, as the node and `skyground
/// detect` read them (a section left out keeps its defaults).
#[derive(Debug, Clone, Default, serde::Deserialize)]
#[serde(default)]
pub struct SceneParams {
    /// Where walls are missing (step 3).
    pub detect: DetectParams,
    /// Building points by footprint (step 2).
    pub split: SplitParams,
    /// Footprints from the points where none are given (step 2).
    pub derive: DeriveParams,
}

/// Why a scene could not be analysed.
#[derive(Debug, thiserror::Error)]
pub enum SceneDetectError {
    /// The cloud has no `label` column.
    #[error("the cloud has no classification: classify it first (label 6 = building)")]
    Unclassified,
    /// Footprint parameters are out of range.
    #[error(transparent)]
    Footprint(#[from] ParamError),
    /// Detection failed.
    #[error(transparent)]
    Detect(#[from] DetectError),
}

fn building_xyz(
    cloud: &Cloud,
    origin: [f64; 3],
    require_labels: bool,
) -> Result<Vec<[f32; 3]>, SceneDetectError> {
    let labels = match (&cloud.label, require_labels) {
        (Some(l), _) => Some(l),
        (None, true) => return Err(SceneDetectError::Unclassified),
        (None, false) => None,
    };
    let shift = [0, 1, 2].map(|k| cloud.origin[k] - origin[k]);
    Ok(cloud
        .xyz
        .iter()
        .enumerate()
        .filter(|(i, _)| labels.is_none_or(|l| l.get(*i) == Some(&class::BUILDING)))
        .map(|(_, p)| [0, 1, 2].map(|k| (f64::from(p[k]) + shift[k]) as f32))
        .collect())
}

/// Terrain cell and hole-filling reach of the ground grid, as the tests use.
const TERRAIN_CELL: f32 = 2.0;
const TERRAIN_FILL: usize = 40;

/// Detects on the building points of `aerial` (label 6) plus those of
/// `extra` (ground scans merged so far; unlabelled means all building),
/// split by `footprints`, or by footprints derived from the aerial building
/// points (so ids stay the same from round to round); either is each
/// building's C_building, the outline its walls are tested along. The terrain comes
/// from `aerial`'s ground points (label 2): walls are tested above their
/// foot, and open ground floors are told from missing walls. Returns the
/// detection (frame of `aerial`) and the footprints used.
pub fn detect_scene(
    aerial: &Cloud,
    extra: Option<&Cloud>,
    footprints: Option<&[Footprint]>,
    params: &SceneParams,
) -> Result<(Detection, Vec<Footprint>), SceneDetectError> {
    let mut pts = building_xyz(aerial, aerial.origin, true)?;
    // The prior's density sets the `auto` lengths: ground scans merged in
    // later rounds are far denser on their walls and would change them
    // from round to round.
    let detect = &params.detect.resolved_for(&pts);
    let ground = aerial.xyz_of_class(class::GROUND);
    let terrain = GroundGrid::from_points(&ground, TERRAIN_CELL, TERRAIN_FILL);
    let used: Vec<Footprint> = match footprints {
        Some(f) => f.to_vec(),
        None => derived(&pts, terrain.as_ref(), &params.derive)?,
    };
    if let Some(e) = extra {
        pts.extend(building_xyz(e, aerial.origin, false)?);
    }
    let ids = split(&pts, &used, &params.split)?;
    // A derived footprint is C_building as a given one is: walls are tested
    // along the outline of what stands, not round the bushes at its foot.
    let outlines: Vec<(u32, geo::MultiPolygon<f64>)> =
        used.iter().map(|f| (f.id, f.polygon.clone())).collect();
    let mut detection = detect_all_on(&pts, &ids, Some(&outlines), terrain.as_ref(), detect)?;
    name_buildings(&mut detection, &used);
    Ok((detection, used))
}

/// Each detected building takes its footprint's own id.
fn name_buildings(detection: &mut Detection, footprints: &[Footprint]) {
    let names: std::collections::HashMap<u32, &str> =
        footprints.iter().map(|f| (f.id, f.name.as_str())).collect();
    for b in &mut detection.buildings {
        if let Some(n) = names.get(&b.building) {
            b.footprint_id = (*n).to_string();
        }
    }
}

/// The footprints [`detect_scene`] derives when none are given: from the
/// building points (label 6) of `aerial` standing `min_height_m` over its
/// terrain (label 2), in its frame.
pub fn derive_footprints(
    aerial: &Cloud,
    params: &DeriveParams,
) -> Result<Vec<Footprint>, SceneDetectError> {
    let pts = building_xyz(aerial, aerial.origin, true)?;
    let ground = aerial.xyz_of_class(class::GROUND);
    let terrain = GroundGrid::from_points(&ground, TERRAIN_CELL, TERRAIN_FILL);
    Ok(derived(&pts, terrain.as_ref(), params)?)
}

/// Footprints derived from the building points `pts` standing over
/// `terrain`, without the holes that show no ground (roofs the survey did
/// not reach, not courtyards).
fn derived(
    pts: &[[f32; 3]],
    terrain: Option<&GroundGrid>,
    params: &DeriveParams,
) -> Result<Vec<Footprint>, ParamError> {
    let mut footprints = derive(&standing(pts, terrain, params.min_height_m), params)?;
    if let Some(t) = terrain {
        for f in &mut footprints {
            f.polygon = t.fill_blind_holes(&f.polygon);
        }
    }
    Ok(footprints)
}

/// The building points standing at least `min_height_m` over the terrain,
/// the ones footprints are derived from: lower ones are hedges, bushes,
/// cars and pergolas, whether alone or touching a house, where they would
/// widen its outline into the garden. All of them without terrain or at 0.
fn standing<'a>(
    pts: &'a [[f32; 3]],
    terrain: Option<&GroundGrid>,
    min_height_m: f64,
) -> Cow<'a, [[f32; 3]]> {
    let Some(terrain) = terrain.filter(|_| min_height_m > 0.0) else {
        return Cow::Borrowed(pts);
    };
    pts.iter()
        .filter(|p| {
            terrain
                .at(f64::from(p[0]), f64::from(p[1]))
                .is_none_or(|g| f64::from(p[2] - g) >= min_height_m)
        })
        .copied()
        .collect()
}

/// Missing points moved from the frame of `from` to that of `to`.
pub fn shift_missing(points: &[MissingPoint], from: [f64; 3], to: [f64; 3]) -> Vec<MissingPoint> {
    let d = [0, 1, 2].map(|k| from[k] - to[k]);
    points
        .iter()
        .map(|m| {
            let mut m = *m;
            m.xyz = [0, 1, 2].map(|k| (f64::from(m.xyz[k]) + d[k]) as f32);
            m.skeleton = [0, 1].map(|k| (f64::from(m.skeleton[k]) + d[k]) as f32);
            m
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Flat ground (class 2) with a 10 × 10 m roof 6 m up, a 3 × 3 m bush
    /// 1.5 m up against its east wall and a 6 × 6 m hedge top 1.5 m up on
    /// its own, all labelled building.
    fn street() -> Cloud {
        let mut xyz = crate::geom::fixtures::lattice(120, 120, 0.5, |_, _| 0.0);
        let mut label = vec![class::GROUND; xyz.len()];
        let mut add = |x0: f32, y0: f32, side: f32, z: f32| {
            let n = (side / 0.25) as usize;
            for i in 0..n {
                for j in 0..n {
                    xyz.push([x0 + i as f32 * 0.25, y0 + j as f32 * 0.25, z]);
                    label.push(class::BUILDING);
                }
            }
        };
        add(10.0, 10.0, 10.0, 6.0);
        add(20.0, 13.0, 3.0, 1.5);
        add(40.0, 40.0, 6.0, 1.5);
        let mut c = Cloud::from_xyz(xyz);
        c.label = Some(label);
        c
    }

    #[test]
    fn what_stands_too_low_draws_no_outline_alone_or_against_a_house() {
        let cloud = street();
        let (_, kept) = detect_scene(&cloud, None, None, &SceneParams::default())
            .unwrap_or_else(|e| panic!("{e}"));
        let off = SceneParams {
            derive: DeriveParams {
                min_height_m: 0.0,
                ..DeriveParams::default()
            },
            ..SceneParams::default()
        };
        let (_, all) = detect_scene(&cloud, None, None, &off).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(all.len(), 2);
        let house = all[0].bounds().unwrap_or_default();
        assert!(house[2] > 22.0, "the bush widens the house: {house:?}");
        assert_eq!(kept.len(), 1);
        let b = kept[0].bounds().unwrap_or_default();
        assert!(b[0] < 11.0 && b[2] > 19.0 && b[2] < 21.0, "{b:?}");
    }
}
