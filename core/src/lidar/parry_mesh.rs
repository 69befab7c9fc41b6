//! The second ray-cast backend: parry3d's `TriMesh` (its own BVH), for
//! checking and benchmarking the hand-written [`Bvh`](super::bvh) against the
//! field's collision library.

use parry3d::math::Vector;
use parry3d::query::Ray;
use parry3d::shape::{CompositeShapeRef, TriMesh};

use crate::geom::soup::soup_mesh;

/// A parry triangle mesh over the caster's triangles, in input order.
#[derive(Debug, Clone)]
pub(crate) struct ParryMesh {
    /// `None` for a scene without triangles (parry refuses empty meshes).
    mesh: Option<TriMesh>,
    /// Triangle vertices, in the order parry numbers them.
    pub tris: Vec<[[f32; 3]; 3]>,
    /// For each triangle, its index in the scene.
    pub ids: Vec<u32>,
}

impl ParryMesh {
    /// Indexes `tris` (non-degenerate, finite), `ids[k]` naming `tris[k]`'s scene triangle.
    pub fn new(tris: Vec<[[f32; 3]; 3]>, ids: Vec<u32>) -> Self {
        let vertices: Vec<Vector> = tris
            .iter()
            .flat_map(|t| t.map(|v| Vector::new(v[0], v[1], v[2])))
            .collect();
        Self {
            mesh: soup_mesh(vertices),
            tris,
            ids,
        }
    }

    /// The closest hit `(t, triangle in this mesh's order)` of the ray from
    /// `origin` along unit `dir` within `max_t`.
    pub fn closest(&self, origin: [f32; 3], dir: [f32; 3], max_t: f32) -> Option<(f32, usize)> {
        let mesh = self.mesh.as_ref()?;
        let ray = Ray::new(
            Vector::new(origin[0], origin[1], origin[2]),
            Vector::new(dir[0], dir[1], dir[2]),
        );
        let (id, t) = CompositeShapeRef(mesh).cast_local_ray(&ray, max_t, true)?;
        Some((t, id as usize))
    }
}
