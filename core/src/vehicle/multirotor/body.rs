//! The multirotor's body against the true scene: the distance from the body
//! centre to the nearest scene triangle, by parry3d's point query on a
//! triangle mesh (its own BVH), so a sphere of the body's radius never
//! passes into a wall, a roof or a tree.

use parry3d::math::Vector;
use parry3d::query::PointQuery;
use parry3d::shape::TriMesh;

use crate::geom::soup::soup_mesh;
use crate::scene::Scene;

/// The scene's triangles as one parry3d mesh, for clearance queries.
pub struct SceneBody {
    /// `None` for a scene without a usable triangle.
    mesh: Option<TriMesh>,
}

impl SceneBody {
    /// Indexes every finite, non-degenerate triangle of `scene` (indices out
    /// of range are skipped: the caster refuses such scenes before this).
    pub fn new(scene: &Scene) -> Self {
        let mut vertices = Vec::with_capacity(3 * scene.triangles.len());
        for tri in &scene.triangles {
            let Some(v) = corners(scene, tri) else {
                continue;
            };
            let (a, b, c) = (v[0], v[1], v[2]);
            if (b - a).cross(c - a).length_squared() > 0.0 {
                vertices.extend([a, b, c]);
            }
        }
        Self {
            mesh: soup_mesh(vertices),
        }
    }

    /// Distance from `p` to the nearest scene surface, m (`f32::INFINITY`
    /// for an empty scene).
    pub fn clearance(&self, p: [f32; 3]) -> f32 {
        self.mesh.as_ref().map_or(f32::INFINITY, |m| {
            m.distance_to_local_point(Vector::new(p[0], p[1], p[2]), false)
        })
    }
}

/// The three corners of `tri`, `None` when one is out of range or not finite.
fn corners(scene: &Scene, tri: &[u32; 3]) -> Option<[Vector; 3]> {
    let mut out = [Vector::ZERO; 3];
    for (o, &i) in out.iter_mut().zip(tri) {
        let v = scene.vertices.get(i as usize)?;
        if !v.iter().all(|x| x.is_finite()) {
            return None;
        }
        *o = Vector::new(v[0], v[1], v[2]);
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lidar::synthetic::boxes_on_plane;

    #[test]
    fn clearance_is_the_distance_to_the_nearest_surface() {
        // A 10 m cube on a plane.
        let scene = boxes_on_plane(50.0, &[([0.0, 0.0, 0.0], [10.0, 10.0, 10.0])]);
        let body = SceneBody::new(&scene);
        let near = |p: [f32; 3], d: f32| (body.clearance(p) - d).abs() < 1e-3;
        assert!(near([5.0, 5.0, 13.0], 3.0), "above the roof");
        assert!(near([12.5, 5.0, 5.0], 2.5), "beside a wall");
        assert!(near([30.0, 30.0, 4.0], 4.0), "over open ground");
        assert!(body.clearance([5.0, 5.0, 10.0]) < 1e-3, "on the roof");
    }

    #[test]
    fn an_empty_scene_is_clear_everywhere() {
        let body = SceneBody::new(&Scene::default());
        assert_eq!(body.clearance([1.0, 2.0, 3.0]), f32::INFINITY);
    }
}
