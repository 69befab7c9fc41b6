//! Assembling a [`Scene`] object by object from per-object meshes.

use super::polygon::triangulate_2d;
use super::vec3::narrow;
use super::{ObjectKind, Scene, SceneObject};

/// One object's triangle mesh in `f64`, before it is appended to a scene.
///
/// Vertices are shared between faces (so closed solids are closed meshes);
/// triangles turn counter-clockwise seen from outside.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MeshPart {
    /// Vertex positions, metres, scene-local frame.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
}

impl MeshPart {
    /// Adds a vertex and returns its index.
    pub fn vertex(&mut self, p: [f64; 3]) -> u32 {
        self.vertices.push(p);
        u32::try_from(self.vertices.len() - 1).unwrap_or(u32::MAX)
    }

    /// Adds the vertices of a horizontal ring at height `z`.
    pub fn ring(&mut self, xy: &[[f64; 2]], z: f64) -> Vec<u32> {
        xy.iter().map(|p| self.vertex([p[0], p[1], z])).collect()
    }

    /// Adds the vertices of a ring whose height varies per point.
    pub fn ring_with(&mut self, xy: &[[f64; 2]], z: impl Fn([f64; 2]) -> f64) -> Vec<u32> {
        xy.iter()
            .map(|p| self.vertex([p[0], p[1], z(*p)]))
            .collect()
    }

    /// Adds triangle `abc`.
    pub fn triangle(&mut self, a: u32, b: u32, c: u32) {
        self.triangles.push([a, b, c]);
    }

    /// Adds quad `abcd` (counter-clockwise seen from outside) as two triangles.
    pub fn quad(&mut self, a: u32, b: u32, c: u32, d: u32) {
        self.triangles.push([a, b, c]);
        self.triangles.push([a, c, d]);
    }

    /// Fills the polygon bounded by rings of existing vertices (first outer,
    /// then holes), triangulated in the xy plane; `up` makes it face +z,
    /// otherwise −z.
    pub fn cap(&mut self, rings: &[&[u32]], up: bool) {
        let points: Vec<[f64; 2]> = self.vertices.iter().map(|p| [p[0], p[1]]).collect();
        let index_rings: Vec<Vec<usize>> = rings
            .iter()
            .map(|r| r.iter().map(|&i| i as usize).collect())
            .collect();
        for t in triangulate_2d(&points, &index_rings) {
            let t = t.map(|i| u32::try_from(i).unwrap_or(u32::MAX));
            if up {
                self.triangle(t[0], t[1], t[2]);
            } else {
                self.triangle(t[0], t[2], t[1]);
            }
        }
    }

    /// Joins two rings of equal length (`lower` below `upper`) with quads.
    ///
    /// A counter-clockwise ring (seen from above) gives outward walls of the
    /// solid it bounds; a clockwise ring (a hole) gives walls facing into the hole.
    pub fn walls(&mut self, lower: &[u32], upper: &[u32]) {
        let n = lower.len().min(upper.len());
        for k in 0..n {
            let j = (k + 1) % n;
            self.quad(lower[k], lower[j], upper[j], upper[k]);
        }
    }

    /// Appends `other`, keeping its vertices separate.
    pub fn append(&mut self, other: &MeshPart) {
        let base = u32::try_from(self.vertices.len()).unwrap_or(u32::MAX);
        self.vertices.extend_from_slice(&other.vertices);
        self.triangles
            .extend(other.triangles.iter().map(|t| t.map(|i| i + base)));
    }
}

/// Builds a [`Scene`] by adding objects and their meshes.
#[derive(Debug, Default)]
pub struct SceneBuilder {
    scene: Scene,
}

impl SceneBuilder {
    /// An empty scene whose local frame has `origin` in the source coordinates.
    pub fn new(origin: [f64; 3]) -> Self {
        Self {
            scene: Scene {
                origin,
                ..Scene::default()
            },
        }
    }

    /// Adds an object and returns its index.
    pub fn add_object(&mut self, name: impl Into<String>, kind: ObjectKind, building: u32) -> u32 {
        self.scene.objects.push(SceneObject {
            name: name.into(),
            kind,
            building,
        });
        u32::try_from(self.scene.objects.len() - 1).unwrap_or(u32::MAX)
    }

    /// Appends `mesh` to object `object` (vertices narrowed to `f32`).
    pub fn add_mesh(&mut self, object: u32, mesh: &MeshPart) {
        let base = u32::try_from(self.scene.vertices.len()).unwrap_or(u32::MAX);
        self.scene
            .vertices
            .extend(mesh.vertices.iter().map(|p| narrow(*p)));
        for t in &mesh.triangles {
            self.scene.triangles.push(t.map(|i| i + base));
            self.scene.triangle_object.push(object);
        }
    }

    /// Adds an object with one mesh; returns the object's index.
    pub fn add(
        &mut self,
        name: impl Into<String>,
        kind: ObjectKind,
        building: u32,
        mesh: &MeshPart,
    ) -> u32 {
        let object = self.add_object(name, kind, building);
        self.add_mesh(object, mesh);
        object
    }

    /// Number of objects so far.
    pub fn object_count(&self) -> usize {
        self.scene.objects.len()
    }

    /// The finished scene.
    pub fn finish(self) -> Scene {
        self.scene
    }
}
