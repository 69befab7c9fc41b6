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

mod body;
mod error;
mod header;

use std::collections::BTreeMap;
use std::path::Path;

use body::Body;
pub use error::{PlyMeshError, PlyPlace};
use header::{Element, Property, parse_header};

use super::indexed::{IndexedObject, scene_from_indexed};
use super::{ObjectKind, Scene, SceneError};

const SPLIT_NAMES: [&str; 5] = ["object", "object_id", "label", "building", "building_id"];
const CLASS_NAMES: [&str; 2] = ["class", "classification"];

/// Reads a PLY mesh file.
pub fn read_ply_mesh(path: &Path) -> Result<Scene, SceneError> {
    let data = std::fs::read(path).map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })?;
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
    let header = parse_header(data)?;
    let mut body = Body::new(
        data.get(header.body_offset..).unwrap_or_default(),
        header.format,
        header.lines + 1,
    );
    let mut vertices: Vec<[f64; 3]> = Vec::new();
    let mut faces: Vec<Face> = Vec::new();
    for element in &header.elements {
        match element.name.as_str() {
            "vertex" => read_vertices(&mut body, element, &mut vertices)?,
            "face" => read_faces(&mut body, element, &mut faces)?,
            _ => {
                for row in 0..element.count {
                    body.at_row(&element.name, row);
                    read_row(&mut body, element, |_, _| Ok(()))?;
                }
            }
        }
    }
    if faces.is_empty() {
        return Err(PlyMeshError::NoFaces);
    }
    let objects = group_faces(&faces, vertices.len())?;
    scene_from_indexed(&vertices, &objects)
        .ok_or(PlyMeshError::NoFaces)?
        .map_err(|vertex| PlyMeshError::NonFinite { vertex })
}

/// Reads one row, handing `(property index, values)` to `take`.
fn read_row(
    body: &mut Body<'_>,
    element: &Element,
    mut take: impl FnMut(usize, &[f64]) -> Result<(), PlyMeshError>,
) -> Result<(), PlyMeshError> {
    let mut values = Vec::new();
    for (k, p) in element.properties.iter().enumerate() {
        values.clear();
        match p {
            Property::Scalar { ty, .. } => values.push(body.value(*ty)?),
            Property::List { count, item, .. } => {
                let n = body.value(*count)?;
                if n < 0.0 {
                    return Err(PlyMeshError::BadValue {
                        at: body.place(),
                        token: n.to_string(),
                        ty: "list count",
                    });
                }
                for _ in 0..n as usize {
                    values.push(body.value(*item)?);
                }
            }
        }
        take(k, &values)?;
    }
    Ok(())
}

fn find(element: &Element, names: &[&str], list: bool) -> Option<usize> {
    names.iter().find_map(|n| {
        element
            .properties
            .iter()
            .position(|p| p.name() == *n && matches!(p, Property::List { .. }) == list)
    })
}

fn read_vertices(
    body: &mut Body<'_>,
    element: &Element,
    out: &mut Vec<[f64; 3]>,
) -> Result<(), PlyMeshError> {
    let axes = ["x", "y", "z"].map(|a| find(element, &[a], false));
    let [Some(x), Some(y), Some(z)] = axes else {
        return Err(PlyMeshError::MissingProperty {
            element: "vertex",
            property: "x, y, z",
        });
    };
    for row in 0..element.count {
        body.at_row(&element.name, row);
        let mut p = [f64::NAN; 3];
        read_row(body, element, |k, v| {
            for (axis, &at) in [x, y, z].iter().enumerate() {
                if k == at {
                    p[axis] = v.first().copied().unwrap_or(f64::NAN);
                }
            }
            Ok(())
        })?;
        if !p.iter().all(|v| v.is_finite()) {
            return Err(PlyMeshError::NonFinite { vertex: row });
        }
        out.push(p);
    }
    Ok(())
}

fn read_faces(
    body: &mut Body<'_>,
    element: &Element,
    out: &mut Vec<Face>,
) -> Result<(), PlyMeshError> {
    let Some(list) = find(element, &["vertex_indices", "vertex_index"], true) else {
        return Err(PlyMeshError::MissingProperty {
            element: "face",
            property: "vertex_indices",
        });
    };
    let split = find(element, &SPLIT_NAMES, false);
    let class = find(element, &CLASS_NAMES, false);
    for row in 0..element.count {
        body.at_row(&element.name, row);
        let mut face = Face {
            corners: Vec::new(),
            key: None,
            class: None,
        };
        let place = body.place();
        read_row(body, element, |k, v| {
            let whole = |x: f64| {
                (x.fract() == 0.0 && x.abs() < 9.0e15)
                    .then_some(x as i64)
                    .ok_or_else(|| PlyMeshError::BadValue {
                        at: place.clone(),
                        token: x.to_string(),
                        ty: "whole number",
                    })
            };
            if k == list {
                for &i in v {
                    face.corners.push(whole(i)?);
                }
            } else if Some(k) == split {
                face.key = v.first().copied().map(whole).transpose()?;
            } else if Some(k) == class {
                face.class = v.first().copied().map(whole).transpose()?;
            }
            Ok(())
        })?;
        if face.corners.len() < 3 {
            return Err(PlyMeshError::ShortFace {
                face: row,
                got: face.corners.len(),
            });
        }
        out.push(face);
    }
    Ok(())
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
        .map(|(key, (class, triangles))| IndexedObject {
            name: key.map_or_else(|| "building".to_string(), |k| format!("object_{k}")),
            kind: match class {
                Some(2) => ObjectKind::Ground,
                Some(3..=5) => ObjectKind::Vegetation,
                _ => ObjectKind::Building,
            },
            triangles,
        })
        .collect())
}

#[cfg(test)]
mod tests;
