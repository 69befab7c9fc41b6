//! Point-to-mesh distance behind one interface, on either of two indexes:
//! the hand-written uniform grid ([`TriangleGrid`]) or parry3d's `TriMesh`
//! (its own BVH). `benches/mesh_distance.rs` measures both on the reference
//! scene; the default is the faster.

use parry3d::math::Vector;
use parry3d::shape::{CompositeShapeRef, TriMesh};

use crate::geom::soup::soup_mesh;

use super::triangle_grid::TriangleGrid;
use crate::scene::vec3::{area_vector, dot, point_triangle_dist2, wide};
use crate::scene::{ObjectKind, Scene};

/// Which index answers nearest-triangle queries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MeshBackend {
    /// The uniform 3D grid over the triangles (exact, f64).
    Grid,
    /// parry3d's `TriMesh` finds the triangle (f32, about the mesh's
    /// centre); the distance to it is measured again in f64.
    #[default]
    Parry,
}

/// Triangles indexed for distance queries.
pub struct MeshDistance {
    index: Index,
}

enum Index {
    Grid(TriangleGrid),
    /// Boxed: parry's mesh is a large value beside the grid's vectors.
    Parry(Box<ParryIndex>),
}

struct ParryIndex {
    /// `None` for a mesh without triangles (parry refuses empty meshes).
    mesh: Option<TriMesh>,
    /// Subtracted before the f32 conversion, so far-from-origin frames keep
    /// their precision.
    centre: [f64; 3],
    /// The triangles in parry's order (finite, non-degenerate).
    tris: Vec<[[f64; 3]; 3]>,
}

/// The building triangles of `scene` (its ground truth surfaces), widened to f64.
pub fn building_triangles(scene: &Scene) -> Vec<[[f64; 3]; 3]> {
    (0..scene.triangles.len())
        .filter(|&t| {
            scene
                .triangle_kind(t)
                .is_some_and(|o| o.kind == ObjectKind::Building)
        })
        .filter_map(|t| scene.triangle_corners(t).map(|c| c.map(wide)))
        .collect()
}

impl MeshDistance {
    /// Indexes `tris` with `backend`; non-finite triangles are left out
    /// (and, for parry, degenerate ones: they have no face to project on).
    pub fn new(tris: Vec<[[f64; 3]; 3]>, backend: MeshBackend) -> Self {
        let index = match backend {
            MeshBackend::Grid => {
                let n = tris.len();
                Index::Grid(TriangleGrid::new(tris, vec![0; n]))
            }
            MeshBackend::Parry => Index::Parry(Box::new(ParryIndex::new(tris))),
        };
        MeshDistance { index }
    }

    /// Distance from `p` to the nearest triangle, if one lies within
    /// `max_dist` (and `p` is finite).
    pub fn distance(&self, p: [f64; 3], max_dist: f64) -> Option<f64> {
        let d2 = match &self.index {
            Index::Grid(g) => g.nearest(p, max_dist, |_| true).map(|(d2, _)| d2),
            Index::Parry(m) => m.nearest_dist2(p, max_dist),
        }?;
        Some(d2.sqrt())
    }
}

impl ParryIndex {
    fn new(tris: Vec<[[f64; 3]; 3]>) -> Self {
        let tris: Vec<[[f64; 3]; 3]> = tris
            .into_iter()
            .filter(|t| t.iter().flatten().all(|v| v.is_finite()) && area2(t) > 0.0)
            .collect();
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for p in tris.iter().flatten() {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let centre = if tris.is_empty() {
            [0.0; 3]
        } else {
            [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]))
        };
        let vertices: Vec<Vector> = tris
            .iter()
            .flat_map(|t| t.map(|v| local(v, centre)))
            .collect();
        ParryIndex {
            mesh: soup_mesh(vertices),
            centre,
            tris,
        }
    }

    fn nearest_dist2(&self, p: [f64; 3], max_dist: f64) -> Option<f64> {
        if !p.iter().all(|v| v.is_finite()) {
            return None;
        }
        let mesh = self.mesh.as_ref()?;
        // parry's f32 search may be off by its rounding: search a little
        // farther, then hold the exact distance to `max_dist`.
        let reach = if max_dist.is_finite() {
            (max_dist * (1.0 + 1e-4) + 1e-3) as f32
        } else {
            f32::MAX
        };
        let (id, _) =
            CompositeShapeRef(mesh).project_local_point(local(p, self.centre), reach, false)?;
        let t = self.tris.get(id as usize)?;
        let d2 = point_triangle_dist2(p, t[0], t[1], t[2]);
        (d2 <= max_dist * max_dist).then_some(d2)
    }
}

fn local(p: [f64; 3], centre: [f64; 3]) -> Vector {
    Vector::new(
        (p[0] - centre[0]) as f32,
        (p[1] - centre[1]) as f32,
        (p[2] - centre[2]) as f32,
    )
}

/// Twice the triangle's area, squared.
fn area2(t: &[[f64; 3]; 3]) -> f64 {
    let c = area_vector(t[0], t[1], t[2]);
    dot(c, c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::reference::reference_scene;

    #[test]
    fn both_backends_agree_on_the_reference_scene() {
        let tris = building_triangles(&reference_scene(1));
        let grid = MeshDistance::new(tris.clone(), MeshBackend::Grid);
        let parry = MeshDistance::new(tris.clone(), MeshBackend::Parry);
        // Points about the buildings: off every 97th corner by up to ±3 m.
        let mut worst = 0.0f64;
        for (k, t) in tris.iter().enumerate().step_by(97) {
            let c = t[k % 3];
            let off = [0.0, 1.0, 2.0].map(|s| ((k as f64 * 0.37 + s).sin()) * 3.0);
            let p = [c[0] + off[0], c[1] + off[1], c[2] + off[2]];
            let (a, b) = (
                grid.distance(p, f64::INFINITY),
                parry.distance(p, f64::INFINITY),
            );
            let (a, b) = (a.expect("a grid answer"), b.expect("a parry answer"));
            worst = worst.max((a - b).abs());
            if a > 1e-3 {
                assert_eq!(grid.distance(p, a * 0.5), None);
                assert_eq!(parry.distance(p, a * 0.5), None);
            }
        }
        assert!(worst < 1e-6, "backends differ by {worst} m");
        let empty = MeshDistance::new(Vec::new(), MeshBackend::Parry);
        assert_eq!(empty.distance([0.0; 3], f64::INFINITY), None);
        assert_eq!(parry.distance([f64::NAN, 0.0, 0.0], f64::INFINITY), None);
    }
}
