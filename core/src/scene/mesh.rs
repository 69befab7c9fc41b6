//! A scene as one labelled triangle soup: what every ray cast and every
//! ground-truth sample is taken from.

/// What an object is, as the classifier and the metrics see it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum ObjectKind {
    /// Terrain, streets, open ground (LAS class 2).
    Ground,
    /// Trees and bushes (LAS class 5).
    Vegetation,
    /// A building (LAS class 6); its id is in [`SceneObject::building`].
    Building,
}

impl ObjectKind {
    /// The ASPRS LAS class code of this kind.
    pub fn las_class(self) -> u8 {
        match self {
            Self::Ground => 2,
            Self::Vegetation => 5,
            Self::Building => 6,
        }
    }
}

/// One named object of a scene.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SceneObject {
    /// Name as in the source (OBJ object/group, CityJSON id, generator name).
    pub name: String,
    /// What it is.
    pub kind: ObjectKind,
    /// Building id (1-based) for buildings, 0 otherwise.
    pub building: u32,
}

/// A triangle mesh in a local metric frame (z up), every triangle tagged with
/// the object it belongs to.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Scene {
    /// Vertex positions, metres, local frame.
    pub vertices: Vec<[f32; 3]>,
    /// Triangles as indices into `vertices` (counter-clockwise seen from outside).
    pub triangles: Vec<[u32; 3]>,
    /// For each triangle, the index into `objects`.
    pub triangle_object: Vec<u32>,
    /// The objects.
    pub objects: Vec<SceneObject>,
    /// The local frame's origin in the source coordinate system (e.g. EPSG:2056),
    /// in metres (a source in feet: its coordinates times the foot's length).
    pub origin: [f64; 3],
}
