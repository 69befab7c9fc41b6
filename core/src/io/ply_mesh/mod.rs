//! PLY triangle meshes (ASCII or binary), optionally split into objects by a
//! per-face property.
//!
//! - `element vertex` needs `x`, `y`, `z` (any numeric type); other vertex
//!   properties are ignored.
//! - `element face` needs a list `vertex_indices` (or `vertex_index`);
//!   polygons are fanned into triangles.
//! - An optional per-face scalar `object`, `object_id`, `label`, `building`
//!   or `building_id` (first found, in that order) splits the mesh: each
//!   distinct value is one object named `object_<value>`. An optional
//!   per-face `class` / `classification` (ASPRS code of the object's first
//!   face: 2 ground, 3–5 vegetation, anything else building) gives its kind;
//!   without it every object is a building. Building ids go 1.. in ascending
//!   value order.
//! - Without a split property the whole mesh is one building named `building`.
//! - Other elements are read and skipped. Coordinates are moved to a local
//!   frame ([`crate::cloud::origin`] rule) kept in [`Scene::origin`].
//!
//! The header, scalar types and ASCII/binary row readers are the point-cloud
//! reader's ([`crate::cloud::ply::reader`]); only the mesh logic lives here.

mod body;
mod error;

use std::collections::BTreeMap;
use std::path::Path;

pub use error::{PlyMeshError, PlyPlace};

use crate::cloud::ply::reader::{AsciiRows, BinaryRows, Header, PlyFormat, Rows, parse_header};

use crate::file;
use crate::io::SceneError;
use crate::scene::indexed::{IndexedObject, scene_from_indexed};
use crate::scene::{ObjectKind, Scene};

const SPLIT_NAMES: [&str; 5] = ["object", "object_id", "label", "building", "building_id"];
const CLASS_NAMES: [&str; 2] = ["class", "classification"];

/// Reads a PLY mesh file.
pub fn read_ply_mesh(path: &Path) -> Result<Scene, SceneError> {
    let data = file::read(path)?;
    parse_ply_mesh(&data).map_err(|source| SceneError::PlyMesh {
        path: path.to_path_buf(),
        source,
    })
}

/// One face as read: its corners, split value and class.
struct Face {
    corners: Vec<i64>,
    key: Option<i64>,
    class: Option<i64>,
}

/// Decodes PLY mesh bytes into a scene.
pub fn parse_ply_mesh(data: &[u8]) -> Result<Scene, PlyMeshError> {
    let header = parse_header(data).map_err(|e| PlyMeshError::from_header(e, data))?;
    if let Some(e) = header
        .elements
        .iter()
        .find(|e| e.count > 0 && e.properties.is_empty())
    {
        return Err(PlyMeshError::Header {
            at: PlyPlace::Line(header.lines),
            text: format!("element {} {}", e.name, e.count),
            reason: "element with rows but no properties".into(),
        });
    }
    let body = data.get(header.body_offset..).unwrap_or_default();
    let (vertices, faces) = match header.format {
        PlyFormat::Ascii => read_body(&header, AsciiRows::new(body, header.lines)),
        PlyFormat::BinaryLittleEndian => read_body(&header, BinaryRows::new(body, false)),
        PlyFormat::BinaryBigEndian => read_body(&header, BinaryRows::new(body, true)),
    }?;
    if faces.is_empty() {
        return Err(PlyMeshError::NoFaces);
    }
    let objects = group_faces(&faces, vertices.len())?;
    scene_from_indexed(&vertices, &objects)
        .ok_or(PlyMeshError::NoFaces)?
        .map_err(|vertex| PlyMeshError::NonFinite { vertex })
}

/// Reads every element: vertices and faces kept, the rest skipped. Bytes
/// after the last element are ignored.
fn read_body<R: Rows>(
    header: &Header,
    mut rows: R,
) -> Result<(Vec<[f64; 3]>, Vec<Face>), PlyMeshError> {
    let mut vertices: Vec<[f64; 3]> = Vec::new();
    let mut faces: Vec<Face> = Vec::new();
    for element in &header.elements {
        match element.name.as_str() {
            "vertex" => body::read_vertices(&mut rows, element, &mut vertices)?,
            "face" => body::read_faces(&mut rows, element, &mut faces)?,
            _ => body::skip_element(&mut rows, element)?,
        }
    }
    Ok((vertices, faces))
}

/// Faces grouped by split value: (class of the first face, triangles).
type Groups = BTreeMap<Option<i64>, (Option<i64>, Vec<[u32; 3]>)>;

fn group_faces(faces: &[Face], vertex_count: usize) -> Result<Vec<IndexedObject>, PlyMeshError> {
    let mut groups: Groups = BTreeMap::new();
    for (row, f) in faces.iter().enumerate() {
        let c = f
            .corners
            .iter()
            .map(|&i| {
                usize::try_from(i)
                    .ok()
                    .filter(|&u| u < vertex_count)
                    .and_then(|u| u32::try_from(u).ok())
                    .ok_or(PlyMeshError::FaceIndex {
                        face: row,
                        index: i,
                        vertices: vertex_count,
                    })
            })
            .collect::<Result<Vec<u32>, _>>()?;
        let (_, tris) = groups.entry(f.key).or_insert((f.class, Vec::new()));
        tris.extend((1..c.len() - 1).map(|i| [c[0], c[i], c[i + 1]]));
    }
    Ok(groups
        .into_iter()
        .enumerate()
        .map(|(group, (key, (class, triangles)))| IndexedObject {
            name: key.map_or_else(|| "building".to_string(), |k| format!("object_{k}")),
            kind: match class {
                Some(2) => ObjectKind::Ground,
                Some(3..=5) => ObjectKind::Vegetation,
                _ => ObjectKind::Building,
            },
            triangles,
            group,
        })
        .collect())
}

#[cfg(test)]
mod tests;
