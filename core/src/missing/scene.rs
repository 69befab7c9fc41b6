//! Steps 2–3 on a whole classified cloud: buildings by footprints (given or
//! derived), then where each one's walls are missing.

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
/// points (so ids stay the same from round to round). The terrain comes
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
    let used: Vec<Footprint> = match footprints {
        Some(f) => f.to_vec(),
        None => derive(&pts, &params.derive)?,
    };
    if let Some(e) = extra {
        pts.extend(building_xyz(e, aerial.origin, false)?);
    }
    let ids = split(&pts, &used, &params.split)?;
    let given: Option<Vec<(u32, geo::MultiPolygon<f64>)>> =
        footprints.map(|f| f.iter().map(|f| (f.id, f.polygon.clone())).collect());
    let ground = aerial.xyz_of_class(class::GROUND);
    let terrain = GroundGrid::from_points(&ground, TERRAIN_CELL, TERRAIN_FILL);
    let detection = detect_all_on(&pts, &ids, given.as_deref(), terrain.as_ref(), detect)?;
    Ok((detection, used))
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
