//! A triangle soup (three unshared vertices per triangle) as parry3d's
//! `TriMesh`, for the ray-cast backend and the point-to-mesh distance.

use parry3d::math::Vector;
use parry3d::shape::TriMesh;

/// The mesh of `vertices` taken three by three; `None` when parry refuses it
/// (no triangles).
pub fn soup_mesh(vertices: Vec<Vector>) -> Option<TriMesh> {
    // Unshared vertices: triangle k's corners are vertices 3k, 3k + 1, 3k + 2.
    let indices: Vec<[u32; 3]> = (0..(vertices.len() / 3) as u32)
        .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
        .collect();
    TriMesh::new(vertices, indices).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangles_are_taken_three_by_three() {
        let v = |x: f32, y: f32| Vector::new(x, y, 0.0);
        let mesh = soup_mesh(vec![
            v(0.0, 0.0),
            v(1.0, 0.0),
            v(0.0, 1.0),
            v(2.0, 0.0),
            v(3.0, 0.0),
            v(2.0, 1.0),
        ])
        .expect("a mesh");
        assert_eq!(mesh.num_triangles(), 2);
        assert_eq!(mesh.indices()[1], [3, 4, 5]);
        assert!(soup_mesh(Vec::new()).is_none());
    }
}
