//! Quality per model, as 3DBAG publishes it: the RMSE of the building's
//! points on its roof planes inside its footprint to its model's roof
//! surfaces (`b3_rmse_lod22`'s meaning: roofer measures the points its
//! plane detector put on roof planes), the same over every roof point (a
//! stricter figure: dormer sides, chimneys and clutter count too), the
//! footprint IoU of the model's outline against the footprint it was made
//! for, and the val3dity codes its solid fails. Roof points are the ones
//! the air sees: no other point of the building lies over them (within
//! [`COVER_RADIUS_M`] in plan and [`COVER_HEIGHT_M`] above). A facade or a
//! point under the eaves has the roof over it and is left out, as are the
//! model's walls and base: a wall point lies metres below the roof the
//! RMSE is about.

use geo::{Contains, Coord, MultiPolygon};
use rustc_hash::FxHashMap;
use serde::Serialize;

use super::evaluate::FAR;
use super::solid::{Shell, SurfaceType};
use crate::footprint::iou;
use crate::metrics::{MeshBackend, MeshDistance};

/// What [`assess`] finds of one model.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct ModelQuality {
    /// RMSE of the building's points on roof planes to its model's roof
    /// faces, m (`b3_rmse_lod22`'s meaning; `None` without such points).
    pub rmse_m: Option<f64>,
    /// RMSE of every roof point (seen from above) to the roof faces, m.
    pub rmse_roof_points_m: Option<f64>,
    /// IoU of the model's outline and the footprint it was made for.
    pub footprint_iou: Option<f64>,
    /// val3dity error codes of the solid (empty: valid).
    pub val3dity: Vec<u16>,
    /// The codes of the LoD 2.2 solid this model replaced, when it is a
    /// fallback for [`Skip::InvalidSolid`](super::Skip::InvalidSolid).
    pub rejected_val3dity: Vec<u16>,
}

/// A point with another this close in plan ...
pub const COVER_RADIUS_M: f64 = 0.3;
/// ... and this much higher is covered: not a roof point.
pub const COVER_HEIGHT_M: f64 = 0.5;

/// Per point of `xyz`: no other point covers it (see the module docs).
pub fn seen_from_above(xyz: &[[f32; 3]]) -> Vec<bool> {
    let r = COVER_RADIUS_M;
    let key = |p: &[f32; 3]| {
        (
            (f64::from(p[0]) / r).floor() as i64,
            (f64::from(p[1]) / r).floor() as i64,
        )
    };
    // Per cell its points and their highest z: a point with no cell
    // around it reaching COVER_HEIGHT_M over it (most roof points) is
    // seen without looking at single points.
    let mut cells: FxHashMap<(i64, i64), (f32, Vec<u32>)> = FxHashMap::default();
    for (i, p) in xyz.iter().enumerate() {
        let c = cells.entry(key(p)).or_insert((f32::MIN, Vec::new()));
        c.0 = c.0.max(p[2]);
        c.1.push(i as u32);
    }
    xyz.iter()
        .map(|p| {
            let (i, j) = key(p);
            let over = |c: &(f32, Vec<u32>)| f64::from(c.0 - p[2]) > COVER_HEIGHT_M;
            !(i - 1..=i + 1).any(|a| {
                (j - 1..=j + 1).any(|b| {
                    cells
                        .get(&(a, b))
                        .filter(|c| over(c))
                        .is_some_and(|(_, v)| {
                            v.iter().any(|&k| {
                                let q = &xyz[k as usize];
                                let (dx, dy) = (f64::from(q[0] - p[0]), f64::from(q[1] - p[1]));
                                dx * dx + dy * dy <= r * r
                                    && f64::from(q[2] - p[2]) > COVER_HEIGHT_M
                            })
                        })
                })
            })
        })
        .collect()
}

/// Measures a model (its closed `shell` and its `outline`) against its
/// points `xyz` (`on_plane`: which lie on roof planes,
/// [`on_roof_planes`](super::on_roof_planes))
/// and the `footprint` it was made for.
pub fn assess(
    shell: &Shell,
    outline: &MultiPolygon<f64>,
    (xyz, on_plane): (&[[f32; 3]], &[bool]),
    footprint: &MultiPolygon<f64>,
) -> ModelQuality {
    let tris: Vec<[[f64; 3]; 3]> = shell
        .triangles()
        .into_iter()
        .filter(|(_, kind)| *kind == SurfaceType::RoofSurface)
        .map(|(t, _)| t)
        .collect();
    // Points the split gave the building from just outside its footprint
    // (eaves over the wall line) are not the footprint's points.
    let seen = seen_from_above(xyz);
    let inside = |keep: &dyn Fn(usize) -> bool| -> Vec<[f64; 3]> {
        xyz.iter()
            .enumerate()
            .filter(|&(i, _)| keep(i))
            .map(|(_, p)| p.map(f64::from))
            .filter(|p| footprint.contains(&Coord { x: p[0], y: p[1] }))
            .collect()
    };
    let planar = inside(&|i| on_plane.get(i).copied().unwrap_or(false));
    let roof = inside(&|i| seen[i]);
    let mesh = (!tris.is_empty()).then(|| MeshDistance::new(tris, MeshBackend::default()));
    let rmse = |pts: &[[f64; 3]]| -> Option<f64> {
        let mesh = mesh.as_ref().filter(|_| !pts.is_empty())?;
        let sq: f64 = pts
            .iter()
            .map(|p| mesh.distance(*p, FAR).unwrap_or(FAR).powi(2))
            .sum();
        Some((sq / pts.len() as f64).sqrt())
    };
    ModelQuality {
        rmse_m: rmse(&planar),
        rmse_roof_points_m: rmse(&roof),
        footprint_iou: Some(iou(outline, footprint)),
        val3dity: super::validity_codes(shell),
        rejected_val3dity: Vec::new(),
    }
}
