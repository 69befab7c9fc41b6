//! CityJSON 1.0 / 1.1 / 2.0 city models as scenes: buildings plus a ground
//! patch under them.
//!
//! - `Building` and `BuildingPart` objects with `Solid`, `MultiSurface`,
//!   `CompositeSurface` (or `MultiSolid` / `CompositeSolid`) geometry; per
//!   object the geometry with the highest LoD is used. Other object types
//!   (roads, vegetation, ...) and geometry templates are ignored.
//! - Each such object is one scene object named by its CityJSON id; a
//!   `BuildingPart` takes its root `Building`'s id (following `parents`), so
//!   [`Scene::building_count`] counts whole buildings. Ids go 1.. in the
//!   sorted order of the root buildings' CityJSON ids.
//! - Surfaces (with holes) are triangulated on their best-fit plane by ear
//!   clipping (robust to non-planar rings); triangles under 1 mm² are dropped.
//! - Vertices are decompressed with `transform` and moved to a local frame
//!   whose origin (kept in [`Scene::origin`]) is the buildings' bounding-box
//!   minimum floored to whole metres.
//! - A Ground object `terrain` is added under the buildings
//!   ([`TerrainOptions`]): a grid over each footprint box + 30 m at the
//!   buildings' base heights.

mod boundaries;
mod error;
mod model;
mod terrain;

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

pub use error::CityJsonError;
pub(crate) use terrain::blend_bases;
pub use terrain::{Footprint, TerrainOptions, terrain_around};

use super::builder::{MeshPart, SceneBuilder};
use super::indexed::localize;
use super::polygon::triangulate_3d;
use super::vec3::{area_vector, norm};
use super::{ObjectKind, Scene, SceneError};
use model::{CityObject, Document};

/// Triangles smaller than this (m²) are dropped as degenerate.
const MIN_AREA: f64 = 1e-6;
/// Parent links followed at most this deep (guards against cycles).
const MAX_DEPTH: usize = 32;

/// Options for reading CityJSON.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CityJsonOptions {
    /// The ground added under the buildings; `None` adds none.
    pub terrain: Option<TerrainOptions>,
}

impl Default for CityJsonOptions {
    fn default() -> Self {
        Self {
            terrain: Some(TerrainOptions::default()),
        }
    }
}

/// Reads a CityJSON file.
pub fn read_cityjson(path: &Path, options: &CityJsonOptions) -> Result<Scene, SceneError> {
    let data = std::fs::read(path).map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_cityjson(&data, options).map_err(|source| SceneError::CityJson {
        path: path.to_path_buf(),
        source,
    })
}

/// One building object's triangles over the document's (real) vertices.
struct Loaded<'a> {
    id: &'a str,
    root: &'a str,
    triangles: Vec<[usize; 3]>,
}

/// Decodes CityJSON bytes into a scene.
pub fn parse_cityjson(data: &[u8], options: &CityJsonOptions) -> Result<Scene, CityJsonError> {
    let doc: Document = serde_json::from_slice(data).map_err(|e| CityJsonError::Json {
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })?;
    if doc.kind != "CityJSON" {
        return Err(CityJsonError::NotCityJson { found: doc.kind });
    }
    if let Some(v) = &doc.version
        && !(v.starts_with("1.") || v.starts_with("2."))
    {
        return Err(CityJsonError::Version { version: v.clone() });
    }
    let vertices = real_vertices(&doc)?;
    let parents = parent_map(&doc);
    let mut loaded: Vec<Loaded<'_>> = Vec::new();
    for (id, object) in &doc.city_objects {
        if !is_building(object) {
            continue;
        }
        let triangles = object_triangles(id, object, &vertices)?;
        if !triangles.is_empty() {
            loaded.push(Loaded {
                id,
                root: root_of(&doc, &parents, id),
                triangles,
            });
        }
    }
    if loaded.is_empty() {
        return Err(CityJsonError::NoBuildings);
    }
    // Roots first, then their parts, in id order.
    loaded.sort_by(|a, b| (a.root, a.id != a.root, a.id).cmp(&(b.root, b.id != b.root, b.id)));
    let origin = origin_of(&loaded, &vertices);
    let local =
        |i: usize| localize(vertices[i], origin).ok_or(CityJsonError::NonFinite { vertex: i });
    let mut b = SceneBuilder::new(origin);
    let mut footprints: BTreeMap<&str, Footprint> = BTreeMap::new();
    let mut ids: BTreeMap<&str, u32> = BTreeMap::new();
    for l in &loaded {
        let next = u32::try_from(ids.len() + 1).unwrap_or(u32::MAX);
        let building = *ids.entry(l.root).or_insert(next);
        let mut part = MeshPart::default();
        let mut map: HashMap<usize, u32> = HashMap::new();
        for t in &l.triangles {
            let mut out = [0u32; 3];
            for (slot, &i) in out.iter_mut().zip(t) {
                *slot = match map.get(&i) {
                    Some(&v) => v,
                    None => {
                        let v = part.vertex(local(i)?);
                        map.insert(i, v);
                        v
                    }
                };
            }
            part.triangles.push(out);
        }
        let f = footprints.entry(l.root).or_insert(Footprint {
            min: [f64::INFINITY; 2],
            max: [f64::NEG_INFINITY; 2],
            base: f64::INFINITY,
        });
        for p in &part.vertices {
            f.min = [f.min[0].min(p[0]), f.min[1].min(p[1])];
            f.max = [f.max[0].max(p[0]), f.max[1].max(p[1])];
            f.base = f.base.min(p[2]);
        }
        b.add(l.id, ObjectKind::Building, building, &part);
    }
    if let Some(t) = &options.terrain {
        let fps: Vec<Footprint> = footprints.into_values().collect();
        let ground = terrain_around(&fps, t);
        if !ground.triangles.is_empty() {
            b.add("terrain", ObjectKind::Ground, 0, &ground);
        }
    }
    Ok(b.finish())
}

fn is_building(o: &CityObject) -> bool {
    matches!(o.kind.as_str(), "Building" | "BuildingPart")
}

/// Each object's parent: its first `parents` entry, else the object that
/// lists it among its `children`.
fn parent_map(doc: &Document) -> HashMap<&str, &str> {
    let mut map: HashMap<&str, &str> = HashMap::new();
    for (id, o) in &doc.city_objects {
        for child in &o.children {
            map.entry(child.as_str()).or_insert(id.as_str());
        }
    }
    for (id, o) in &doc.city_objects {
        if let Some(p) = o.parents.first() {
            map.insert(id.as_str(), p.as_str());
        }
    }
    map
}

/// The id of the Building at the top of `id`'s parent chain.
fn root_of<'a>(doc: &'a Document, parents: &HashMap<&'a str, &'a str>, id: &'a str) -> &'a str {
    let mut cur = id;
    for _ in 0..MAX_DEPTH {
        let Some(obj) = doc.city_objects.get(cur) else {
            break;
        };
        if obj.kind == "Building" {
            break;
        }
        match parents.get(cur) {
            Some(&p) if doc.city_objects.get(p).is_some_and(is_building) => cur = p,
            _ => break,
        }
    }
    // `cur` borrows from either `id` or the document's keys.
    doc.city_objects
        .get_key_value(cur)
        .map_or(id, |(k, _)| k.as_str())
}

/// Decompressed vertices (source CRS).
fn real_vertices(doc: &Document) -> Result<Vec<[f64; 3]>, CityJsonError> {
    let (scale, translate) = match &doc.transform {
        Some(t) => (t.scale, t.translate),
        None => ([1.0; 3], [0.0; 3]),
    };
    if !scale.iter().chain(&translate).all(|v| v.is_finite()) {
        return Err(CityJsonError::Transform);
    }
    doc.vertices
        .iter()
        .enumerate()
        .map(|(k, v)| {
            let p = [0, 1, 2].map(|a| v[a] * scale[a] + translate[a]);
            if p.iter().all(|c| c.is_finite()) {
                Ok(p)
            } else {
                Err(CityJsonError::NonFinite { vertex: k })
            }
        })
        .collect()
}

/// The used vertices' bounding-box minimum, floored to whole metres.
fn origin_of(loaded: &[Loaded<'_>], vertices: &[[f64; 3]]) -> [f64; 3] {
    let mut lo = [f64::INFINITY; 3];
    for i in loaded.iter().flat_map(|l| l.triangles.iter().flatten()) {
        for k in 0..3 {
            lo[k] = lo[k].min(vertices[*i][k]);
        }
    }
    lo.map(f64::floor)
}

/// Triangles of the object's highest-LoD surface geometry.
fn object_triangles(
    id: &str,
    object: &CityObject,
    vertices: &[[f64; 3]],
) -> Result<Vec<[usize; 3]>, CityJsonError> {
    let best = object
        .geometry
        .iter()
        .enumerate()
        .filter(|(_, g)| g.surface_depth().is_some())
        .max_by(|(_, a), (_, b)| a.lod_value().total_cmp(&b.lod_value()));
    let Some((gi, geometry)) = best else {
        return Ok(Vec::new());
    };
    let depth = geometry.surface_depth().unwrap_or(0);
    let surfaces = boundaries::surfaces(&geometry.boundaries, depth).map_err(|reason| {
        CityJsonError::Boundaries {
            object: id.to_string(),
            geometry: gi,
            kind: geometry.kind.clone(),
            reason,
        }
    })?;
    // Rings are triangulated near the first vertex, to keep precision in
    // projected coordinates of millions of metres.
    let mut out = Vec::new();
    for surface in &surfaces {
        let mut rings_idx: Vec<Vec<usize>> = Vec::with_capacity(surface.len());
        for ring in surface {
            let ring = ring
                .iter()
                .map(|&i| {
                    usize::try_from(i)
                        .ok()
                        .filter(|&u| u < vertices.len())
                        .ok_or_else(|| CityJsonError::VertexIndex {
                            object: id.to_string(),
                            index: i,
                            vertices: vertices.len(),
                        })
                })
                .collect::<Result<Vec<usize>, _>>()?;
            rings_idx.push(ring);
        }
        let Some(&anchor) = rings_idx.first().and_then(|r| r.first()) else {
            continue;
        };
        let a = vertices[anchor];
        let rel = |i: usize| {
            let p = vertices[i];
            [p[0] - a[0], p[1] - a[1], p[2] - a[2]]
        };
        let rings_pts: Vec<Vec<[f64; 3]>> = rings_idx
            .iter()
            .map(|r| r.iter().map(|&i| rel(i)).collect())
            .collect();
        let refs: Vec<&[[f64; 3]]> = rings_pts.iter().map(Vec::as_slice).collect();
        let flat: Vec<usize> = rings_idx.iter().flatten().copied().collect();
        for t in triangulate_3d(&refs) {
            let t = t.map(|k| flat[k]);
            let area = norm(area_vector(rel(t[0]), rel(t[1]), rel(t[2]))) / 2.0;
            if area >= MIN_AREA {
                out.push(t);
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests;
