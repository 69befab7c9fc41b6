//! Quality per model, as 3DBAG publishes it: the RMSE of the building's
//! points inside its footprint to its model (`b3_rmse_lod22`'s meaning;
//! roofs and walls alike), the footprint IoU of the model's
//! outline against the footprint it was made for, and the val3dity codes
//! its solid fails.

use geo::{Contains, Coord, MultiPolygon};
use serde::Serialize;

use super::evaluate::FAR;
use super::solid::Shell;
use crate::footprint::iou;
use crate::metrics::{MeshBackend, MeshDistance};

/// What [`assess`] finds of one model.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct ModelQuality {
    /// RMSE of the building's points to its model, m (`None` without points).
    pub rmse_m: Option<f64>,
    /// IoU of the model's outline and the footprint it was made for.
    pub footprint_iou: Option<f64>,
    /// val3dity error codes of the solid (empty: valid).
    pub val3dity: Vec<u16>,
    /// The codes of the LoD 2.2 solid this model replaced, when it is a
    /// fallback for [`Skip::InvalidSolid`](super::Skip::InvalidSolid).
    pub rejected_val3dity: Vec<u16>,
}

/// Measures a model (its closed `shell` and its `outline`) against its
/// points `xyz` and the `footprint` it was made for.
pub fn assess(
    shell: &Shell,
    outline: &MultiPolygon<f64>,
    xyz: &[[f32; 3]],
    footprint: &MultiPolygon<f64>,
) -> ModelQuality {
    let tris: Vec<[[f64; 3]; 3]> = shell.triangles().into_iter().map(|(t, _)| t).collect();
    // Points the split gave the building from just outside its footprint
    // (eaves over the wall line) are not the footprint's points.
    let inside: Vec<[f64; 3]> = xyz
        .iter()
        .map(|p| p.map(f64::from))
        .filter(|p| footprint.contains(&Coord { x: p[0], y: p[1] }))
        .collect();
    let rmse_m = (!inside.is_empty() && !tris.is_empty()).then(|| {
        let mesh = MeshDistance::new(tris, MeshBackend::default());
        let sq: f64 = inside
            .iter()
            .map(|p| mesh.distance(*p, FAR).unwrap_or(FAR).powi(2))
            .sum();
        (sq / inside.len() as f64).sqrt()
    });
    ModelQuality {
        rmse_m,
        footprint_iou: Some(iou(outline, footprint)),
        val3dity: super::validity_codes(shell),
        rejected_val3dity: Vec::new(),
    }
}
