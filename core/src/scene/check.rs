//! Consistency and topology checks of a [`Scene`].

use std::collections::HashMap;

use super::Scene;
use super::vec3::{cross, dot, wide};

/// What is wrong with a scene's arrays.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SceneCheckError {
    /// `triangle_object` does not have one entry per triangle.
    #[error("{triangles} triangles but {labels} triangle_object entries")]
    TriangleObjectLength {
        /// Number of triangles.
        triangles: usize,
        /// Number of object entries.
        labels: usize,
    },
    /// A triangle refers to a vertex that does not exist.
    #[error("triangle {triangle} uses vertex {vertex} but there are {vertices} vertices")]
    VertexIndex {
        /// Triangle index.
        triangle: usize,
        /// The bad vertex index.
        vertex: u32,
        /// Number of vertices.
        vertices: usize,
    },
    /// A triangle refers to an object that does not exist.
    #[error("triangle {triangle} belongs to object {object} but there are {objects} objects")]
    ObjectIndex {
        /// Triangle index.
        triangle: usize,
        /// The bad object index.
        object: u32,
        /// Number of objects.
        objects: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {vertex} is not finite")]
    NonFiniteVertex {
        /// Vertex index.
        vertex: usize,
    },
}

/// Edge topology of one object's triangles (see [`Scene::edge_defects`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct EdgeDefects {
    /// Distinct undirected edges.
    pub edges: usize,
    /// Edges used by one triangle only (holes in the surface).
    pub boundary: usize,
    /// Edges used by more than two triangles.
    pub non_manifold: usize,
    /// Edges used twice in the same direction (neighbours facing opposite ways).
    pub misoriented: usize,
}

impl EdgeDefects {
    /// True for a closed, consistently oriented 2-manifold.
    pub fn is_closed(&self) -> bool {
        self.boundary == 0 && self.non_manifold == 0 && self.misoriented == 0
    }
}

impl Scene {
    /// Checks array lengths, indices and finiteness.
    pub fn validate(&self) -> Result<(), SceneCheckError> {
        self.check_lengths()?;
        if let Some(vertex) = self
            .vertices
            .iter()
            .position(|p| !p.iter().all(|v| v.is_finite()))
        {
            return Err(SceneCheckError::NonFiniteVertex { vertex });
        }
        self.check_index_range()
    }

    /// Checks array lengths and indices only: what the ray caster needs (it
    /// skips a triangle with a non-finite corner rather than refuse the scene).
    pub fn check_indices(&self) -> Result<(), SceneCheckError> {
        self.check_lengths()?;
        self.check_index_range()
    }

    fn check_lengths(&self) -> Result<(), SceneCheckError> {
        if self.triangle_object.len() != self.triangles.len() {
            return Err(SceneCheckError::TriangleObjectLength {
                triangles: self.triangles.len(),
                labels: self.triangle_object.len(),
            });
        }
        Ok(())
    }

    fn check_index_range(&self) -> Result<(), SceneCheckError> {
        for (triangle, (t, &object)) in self.triangles.iter().zip(&self.triangle_object).enumerate()
        {
            if let Some(&vertex) = t.iter().find(|&&i| i as usize >= self.vertices.len()) {
                return Err(SceneCheckError::VertexIndex {
                    triangle,
                    vertex,
                    vertices: self.vertices.len(),
                });
            }
            if object as usize >= self.objects.len() {
                return Err(SceneCheckError::ObjectIndex {
                    triangle,
                    object,
                    objects: self.objects.len(),
                });
            }
        }
        Ok(())
    }

    /// Counts open, non-manifold and misoriented edges among the triangles of
    /// object `object` (vertices are matched by index, not by position).
    pub fn edge_defects(&self, object: u32) -> EdgeDefects {
        // (low, high) -> (uses low->high, uses high->low)
        let mut uses: HashMap<(u32, u32), (u32, u32)> = HashMap::new();
        for t in self.object_triangles(object) {
            let tri = self.triangles[t];
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                let e = uses.entry((a.min(b), a.max(b))).or_default();
                if a < b {
                    e.0 += 1;
                } else {
                    e.1 += 1;
                }
            }
        }
        let mut d = EdgeDefects {
            edges: uses.len(),
            ..EdgeDefects::default()
        };
        for &(f, r) in uses.values() {
            match f + r {
                1 => d.boundary += 1,
                2 if f != 1 => d.misoriented += 1,
                2 => {}
                _ => d.non_manifold += 1,
            }
        }
        d
    }

    /// Signed volume (m³) enclosed by object `object`'s triangles: positive
    /// for a closed mesh with outward normals.
    pub fn signed_volume(&self, object: u32) -> f64 {
        self.object_triangles(object)
            .filter_map(|t| self.triangle_corners(t))
            .map(|[a, b, c]| dot(wide(a), cross(wide(b), wide(c))) / 6.0)
            .sum()
    }
}
