//! The accuracy term: distance from observed building points to the
//! building mesh.

use rayon::prelude::*;

use super::triangle_grid::TriangleGrid;
use crate::scene::vec3::wide;
use crate::scene::{ObjectKind, Scene};

/// Distance from each point to the nearest building triangle of `scene`
/// (`f32::INFINITY` when the scene has no buildings or the point is not finite).
///
/// Uses a uniform grid over the building triangles (exact nearest triangle),
/// in parallel.
pub fn cloud_to_mesh_distances(scene: &Scene, points: &[[f32; 3]]) -> Vec<f32> {
    let tris: Vec<[[f64; 3]; 3]> = (0..scene.triangles.len())
        .filter(|&t| {
            scene
                .triangle_kind(t)
                .is_some_and(|o| o.kind == ObjectKind::Building)
        })
        .filter_map(|t| scene.triangle_corners(t).map(|c| c.map(wide)))
        .collect();
    let n = tris.len();
    let grid = TriangleGrid::new(tris, vec![0; n]);
    points
        .par_iter()
        .map(|p| {
            grid.nearest(wide(*p), f64::INFINITY, |_| true)
                .map_or(f32::INFINITY, |(d2, _)| d2.sqrt() as f32)
        })
        .collect()
}

/// The accuracy term: mean over `points` (observed building points, same
/// frame as the scene) of the distance to the nearest building triangle;
/// `None` without points or buildings.
pub fn mean_cloud_to_mesh(scene: &Scene, points: &[[f32; 3]]) -> Option<f64> {
    let d = cloud_to_mesh_distances(scene, points);
    let finite: Vec<f64> = d
        .iter()
        .filter(|v| v.is_finite())
        .map(|&v| f64::from(v))
        .collect();
    if finite.is_empty() {
        return None;
    }
    Some(finite.iter().sum::<f64>() / finite.len() as f64)
}
