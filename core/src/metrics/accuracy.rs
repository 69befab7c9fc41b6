//! The accuracy term: distance from observed building points to the
//! building mesh.

use rayon::prelude::*;

use super::mesh_distance::{MeshBackend, MeshDistance, building_triangles};
use crate::scene::Scene;
use crate::scene::vec3::wide;

/// Distance from each point to the nearest building triangle of `scene`
/// (`f32::INFINITY` when the scene has no buildings or the point is not
/// finite), in parallel, on the default [`MeshBackend`].
pub fn cloud_to_mesh_distances(scene: &Scene, points: &[[f32; 3]]) -> Vec<f32> {
    cloud_to_mesh_distances_with(scene, points, MeshBackend::default())
}

/// [`cloud_to_mesh_distances`] on a chosen index (for benches and checks).
pub fn cloud_to_mesh_distances_with(
    scene: &Scene,
    points: &[[f32; 3]],
    backend: MeshBackend,
) -> Vec<f32> {
    let mesh = MeshDistance::new(building_triangles(scene), backend);
    points
        .par_iter()
        .map(|p| {
            mesh.distance(wide(*p), f64::INFINITY)
                .map_or(f32::INFINITY, |d| d as f32)
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
