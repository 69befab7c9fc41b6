//! The parts of a CityJSON document the scene reader uses (serde).

use std::collections::BTreeMap;

use serde::Deserialize;
use serde_json::Value;

/// A CityJSON document or one CityJSONSeq line (unknown members are ignored).
#[derive(Debug, Default, Deserialize)]
pub struct Document {
    /// `CityJSON` (a file, or a CityJSONSeq header) or `CityJSONFeature`.
    #[serde(rename = "type")]
    pub kind: String,
    /// `1.0`, `1.1`, `2.0`.
    #[serde(default)]
    pub version: Option<String>,
    /// City objects by id (sorted by id).
    #[serde(rename = "CityObjects", default)]
    pub city_objects: BTreeMap<String, CityObject>,
    /// Vertices (integers with a transform, or plain coordinates).
    #[serde(default)]
    pub vertices: Vec<[f64; 3]>,
    /// Vertex decompression.
    #[serde(default)]
    pub transform: Option<Transform>,
    /// `metadata` as written (`referenceSystem` names the CRS).
    #[serde(default)]
    pub metadata: Option<Value>,
}

impl Document {
    /// The CRS the file names (`metadata.referenceSystem`), if any.
    pub fn reference_system(&self) -> Option<&str> {
        self.metadata
            .as_ref()?
            .get("referenceSystem")?
            .as_str()
            .map(str::trim)
            .filter(|s| !s.is_empty())
    }
}

/// `transform`: real = stored × scale + translate.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, serde::Serialize)]
pub struct Transform {
    /// Per-axis scale.
    pub scale: [f64; 3],
    /// Per-axis translation.
    pub translate: [f64; 3],
}

/// One city object.
#[derive(Debug, Clone, Deserialize)]
pub struct CityObject {
    /// `Building`, `BuildingPart`, `Road`, ...
    #[serde(rename = "type")]
    pub kind: String,
    /// Geometries (any LoD).
    #[serde(default)]
    pub geometry: Vec<Geometry>,
    /// Parent ids (a BuildingPart's Building).
    #[serde(default)]
    pub parents: Vec<String>,
    /// Child ids (a Building's parts).
    #[serde(default)]
    pub children: Vec<String>,
    /// Attributes as written.
    #[serde(default)]
    pub attributes: Option<Value>,
}

/// One geometry of a city object.
#[derive(Debug, Clone, Deserialize)]
pub struct Geometry {
    /// `Solid`, `MultiSurface`, ...
    #[serde(rename = "type")]
    pub kind: String,
    /// Level of detail, a string (`"2.2"`) or a number (CityJSON 1.0).
    #[serde(default)]
    pub lod: Option<Value>,
    /// Nested arrays of vertex indices.
    #[serde(default)]
    pub boundaries: Value,
    /// Semantic surfaces (`surfaces` and `values`) as written.
    #[serde(default)]
    pub semantics: Option<Value>,
}

impl Geometry {
    /// The LoD as a number (0 when absent or unreadable).
    pub fn lod_value(&self) -> f64 {
        match &self.lod {
            Some(Value::Number(n)) => n.as_f64().unwrap_or(0.0),
            Some(Value::String(s)) => s.trim().parse().unwrap_or(0.0),
            _ => 0.0,
        }
    }

    /// The semantic type (`RoofSurface`, `GroundSurface`, ...) of semantic
    /// surface `index`, if any.
    pub fn semantic_type(&self, index: u64) -> Option<&str> {
        self.semantics
            .as_ref()?
            .get("surfaces")?
            .get(usize::try_from(index).ok()?)?
            .get("type")?
            .as_str()
    }

    /// How many array levels sit above the surfaces, for the surface types
    /// this reader triangulates; `None` for other types.
    pub fn surface_depth(&self) -> Option<usize> {
        match self.kind.as_str() {
            "MultiSurface" | "CompositeSurface" => Some(0),
            "Solid" => Some(1),
            "MultiSolid" | "CompositeSolid" => Some(2),
            _ => None,
        }
    }
}
