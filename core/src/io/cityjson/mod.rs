//! CityJSON 1.0 / 1.1 / 2.0 and CityJSONSeq city models as scenes:
//! buildings, the file's ground surfaces, and ground built around them.
//!
//! - Files: one CityJSON file, a CityJSONSeq stream (`.city.jsonl`: header
//!   line, one `CityJSONFeature` per line), or several of either (tiles) in
//!   one frame ([`read_city_files`]; they must name the same CRS).
//! - `Building` and `BuildingPart` objects with `Solid`, `MultiSurface`,
//!   `CompositeSurface` (or `MultiSolid` / `CompositeSolid`) geometry of any
//!   LoD (0–2.2); per object the geometry with the highest LoD is used.
//! - Each such object is one scene object named by its CityJSON id; a
//!   `BuildingPart` takes its root `Building`'s id (following `parents`), so
//!   [`Scene::building_count`] counts whole buildings. Ids go 1.. in the
//!   sorted order of the root buildings' CityJSON ids
//!   ([`CityModel::building_roots`]).
//! - `TINRelief`, `LandUse`, `Road`, `TransportSquare` and `PlantCover`
//!   surfaces are Ground objects named by their ids; other object types
//!   and geometry templates are ignored.
//! - Surfaces (with holes) are triangulated on their best-fit plane by ear
//!   clipping (robust to non-planar rings); triangles under 1 mm² are dropped.
//! - Vertices are decompressed with `transform`, scaled to metres when the
//!   model's CRS (`metadata.referenceSystem`) is in feet, and moved to a
//!   local frame whose origin (kept in [`Scene::origin`], metres as a cloud's
//!   origin) is the buildings' bounding-box minimum floored to whole metres.
//! - A Ground object `terrain` is added around the buildings
//!   ([`TerrainOptions`], [`terrain_around`]): a grid over each footprint box
//!   grown by 30 m, through the buildings' base vertices (their `GroundSurface`, or
//!   the lowest vertex under each wall) and the file's ground surfaces,
//!   smoothed away from the buildings. Most city models (3DBAG, municipal
//!   LoD2) ship buildings only: this is the ground the vehicle drives on.
//!   Clusters whose patches do not meet are joined by 10 m streets along a
//!   minimum spanning tree (`streets`), so buildings hundreds of metres
//!   apart stand on one piece of ground.
//! - A file's ground surfaces that lie at another height than the
//!   buildings' bases (by a median of more than [`MISMATCH_M`]: another
//!   vertical datum) are moved to meet them ([`ground_shift`]).

pub(crate) mod boundaries;
mod error;
pub mod footprints;
mod ground_level;
pub(crate) mod model;
pub mod models;
mod source;
mod write;

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

pub use error::CityJsonError;
pub use ground_level::{MISMATCH_M, ground_shift};
pub use model::{CityObject, Document, Geometry, Transform};
pub use source::{
    BUILDING_TYPES, CityModel, GROUND_TYPES, city_files, crs_key, is_city_file, parse_city_model,
    read_city_model,
};
pub use write::{Attributes, annotated_model, crs_url, scene_model};

use super::SceneError;
use crate::scene::indexed::localize;
use crate::scene::polygon::triangulate_3d;
use crate::scene::terrain::{Footprint, TerrainOptions, terrain_around};
use crate::scene::vec3::{area_vector, norm};
use crate::scene::{MeshPart, ObjectKind, Scene, SceneBuilder};

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

/// Reads a CityJSON or CityJSONSeq file.
pub fn read_cityjson(path: &Path, options: &CityJsonOptions) -> Result<Scene, SceneError> {
    read_city_files(&[path.to_path_buf()], options)
}

/// Reads several city model files (tiles) as one scene in one frame.
pub fn read_city_files(paths: &[PathBuf], options: &CityJsonOptions) -> Result<Scene, SceneError> {
    read_city_files_and_crs(paths, options).map(|(scene, _)| scene)
}

/// [`read_city_files`] with the model's CRS ([`CityModel::crs`]), from one read.
pub fn read_city_files_and_crs(
    paths: &[PathBuf],
    options: &CityJsonOptions,
) -> Result<(Scene, Option<crate::crs::Crs>), SceneError> {
    let model = read_city_model(paths)?;
    let scene = scene_of_model(&model, options).map_err(|source| SceneError::CityJson {
        path: paths.first().cloned().unwrap_or_default(),
        source,
    })?;
    Ok((scene, model.crs()))
}

/// Decodes CityJSON (or CityJSONSeq) bytes into a scene.
pub fn parse_cityjson(data: &[u8], options: &CityJsonOptions) -> Result<Scene, CityJsonError> {
    scene_of_model(&parse_city_model(data)?, options)
}

/// One object's triangles over the model's (real) vertices, and the
/// vertices its base stands on.
struct Loaded<'a> {
    id: &'a str,
    root: &'a str,
    triangles: Vec<[usize; 3]>,
    base: Vec<usize>,
}

/// The scene of a city model: its buildings, its ground surfaces, and
/// ground built from the buildings' bases around them.
pub fn scene_of_model(
    model: &CityModel,
    options: &CityJsonOptions,
) -> Result<Scene, CityJsonError> {
    // Inside, a scene is in metres: a model in feet is scaled on the way in
    // (its origin too), and outputs divide by the CRS's unit on the way out.
    let f = model.to_metre();
    let vertices: std::borrow::Cow<'_, [[f64; 3]]> = if f == [1.0; 3] {
        std::borrow::Cow::Borrowed(&model.vertices)
    } else {
        model
            .vertices
            .iter()
            .map(|p| [0, 1, 2].map(|k| p[k] * f[k]))
            .collect()
    };
    let vertices = &*vertices;
    let parents = parent_map(model);
    let mut loaded: Vec<Loaded<'_>> = Vec::new();
    let mut grounds: Vec<Loaded<'_>> = Vec::new();
    for (id, object) in &model.objects {
        let building = BUILDING_TYPES.contains(&object.kind.as_str());
        let (triangles, base) = object_triangles(id, object, vertices)?;
        if triangles.is_empty() {
            continue;
        }
        let root = if building {
            root_of(model, &parents, id)
        } else {
            id
        };
        let l = Loaded {
            id,
            root,
            triangles,
            base,
        };
        if building {
            loaded.push(l);
        } else {
            grounds.push(l);
        }
    }
    if loaded.is_empty() {
        return Err(CityJsonError::NoBuildings {
            ground_objects: grounds.len(),
        });
    }
    // Roots first, then their parts, in id order.
    loaded.sort_by(|a, b| (a.root, a.id != a.root, a.id).cmp(&(b.root, b.id != b.root, b.id)));
    let origin = origin_of(&loaded, vertices);
    let local =
        |i: usize| localize(vertices[i], origin).ok_or(CityJsonError::NonFinite { vertex: i });
    let mut b = SceneBuilder::new(origin);
    let mut footprints: BTreeMap<&str, Footprint> = BTreeMap::new();
    let mut samples: Vec<[f64; 3]> = Vec::new();
    let mut ids: BTreeMap<&str, u32> = BTreeMap::new();
    for l in &loaded {
        let next = u32::try_from(ids.len() + 1).unwrap_or(u32::MAX);
        let building = *ids.entry(l.root).or_insert(next);
        let part = mesh_of(l, &local)?;
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
        for &i in &l.base {
            samples.push(local(i)?);
        }
        b.add(l.id, ObjectKind::Building, building, &part);
    }
    let mut parts: Vec<MeshPart> = grounds
        .iter()
        .map(|g| mesh_of(g, &local))
        .collect::<Result<_, _>>()?;
    let all: Vec<[f64; 3]> = parts.iter().flat_map(|p| p.vertices.clone()).collect();
    let shift = ground_shift(&samples, &all);
    for (g, part) in grounds.iter().zip(&mut parts) {
        for p in &mut part.vertices {
            p[2] += shift;
        }
        samples.extend(part.vertices.iter().copied());
        b.add(g.id, ObjectKind::Ground, 0, part);
    }
    if let Some(t) = &options.terrain {
        let fps: Vec<Footprint> = footprints.into_values().collect();
        let mut t = *t;
        if !grounds.is_empty() {
            // Under the file's own ground, so the vehicle drives on that where it exists.
            t.drop = t.drop.max(GROUND_GAP);
        }
        let ground = terrain_around(&fps, &samples, &t);
        if !ground.triangles.is_empty() {
            b.add("terrain", ObjectKind::Ground, 0, &ground);
        }
    }
    Ok(b.finish())
}

/// How far the built ground sits under a file's own ground surfaces, m.
const GROUND_GAP: f64 = 0.05;

/// One loaded object's triangles as a mesh in the local frame (vertices shared).
fn mesh_of(
    l: &Loaded<'_>,
    local: &impl Fn(usize) -> Result<[f64; 3], CityJsonError>,
) -> Result<MeshPart, CityJsonError> {
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
    Ok(part)
}

/// Each object's parent: its first `parents` entry, else the object that
/// lists it among its `children`.
pub(crate) fn parent_map(model: &CityModel) -> HashMap<&str, &str> {
    let mut map: HashMap<&str, &str> = HashMap::new();
    for (id, o) in &model.objects {
        for child in &o.children {
            map.entry(child.as_str()).or_insert(id.as_str());
        }
    }
    for (id, o) in &model.objects {
        if let Some(p) = o.parents.first() {
            map.insert(id.as_str(), p.as_str());
        }
    }
    map
}

/// The id of the Building at the top of `id`'s parent chain.
pub(crate) fn root_of<'a>(
    model: &'a CityModel,
    parents: &HashMap<&'a str, &'a str>,
    id: &'a str,
) -> &'a str {
    let is_building = |o: &CityObject| BUILDING_TYPES.contains(&o.kind.as_str());
    let mut cur = id;
    for _ in 0..MAX_DEPTH {
        let Some(obj) = model.objects.get(cur) else {
            break;
        };
        if obj.kind == "Building" {
            break;
        }
        match parents.get(cur) {
            Some(&p) if model.objects.get(p).is_some_and(is_building) => cur = p,
            _ => break,
        }
    }
    // `cur` borrows from either `id` or the model's keys.
    model
        .objects
        .get_key_value(cur)
        .map_or(id, |(k, _)| k.as_str())
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

/// Triangles of the object's highest-LoD surface geometry, and the
/// vertices of its base ([`base_vertices`]).
fn object_triangles(
    id: &str,
    object: &CityObject,
    vertices: &[[f64; 3]],
) -> Result<(Vec<[usize; 3]>, Vec<usize>), CityJsonError> {
    let best = object
        .geometry
        .iter()
        .enumerate()
        .filter(|(_, g)| g.surface_depth().is_some())
        .max_by(|(_, a), (_, b)| a.lod_value().total_cmp(&b.lod_value()));
    let Some((gi, geometry)) = best else {
        return Ok((Vec::new(), Vec::new()));
    };
    let depth = geometry.surface_depth().unwrap_or(0);
    let values = geometry.semantics.as_ref().and_then(|s| s.get("values"));
    let surfaces = boundaries::surfaces(&geometry.boundaries, values, depth).map_err(|reason| {
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
    let mut ground_rings: Vec<usize> = Vec::new();
    let mut used: Vec<usize> = Vec::new();
    for surface in &surfaces {
        let mut rings_idx: Vec<Vec<usize>> = Vec::with_capacity(surface.rings.len());
        for ring in &surface.rings {
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
        let flat: Vec<usize> = rings_idx.iter().flatten().copied().collect();
        let semantic = surface.semantic.and_then(|k| geometry.semantic_type(k));
        if semantic == Some("GroundSurface") {
            ground_rings.extend(&flat);
        }
        // Holes (windows, doors) stand on nothing: only outer rings count.
        used.extend(rings_idx.first().into_iter().flatten());
        let Some(&anchor) = flat.first() else {
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
        for t in triangulate_3d(&refs) {
            let t = t.map(|k| flat[k]);
            let area = norm(area_vector(rel(t[0]), rel(t[1]), rel(t[2]))) / 2.0;
            if area >= MIN_AREA {
                out.push(t);
            }
        }
    }
    let base = if ground_rings.is_empty() {
        base_vertices(&used, vertices)
    } else {
        ground_rings
    };
    Ok((out, base))
}

/// The vertices an object without `GroundSurface` semantics stands on, of
/// the vertices of its surfaces' outer rings (`used`): the lowest vertex at
/// each xy that has a wall above it (another vertex ≥ 1 m higher at the
/// same xy) in the lower quarter of the object's height, and every vertex
/// at its lowest z (a LoD0 footprint has no walls).
fn base_vertices(used: &[usize], vertices: &[[f64; 3]]) -> Vec<usize> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    // Vertices at the same xy, to the centimetre.
    let mut columns: HashMap<(i64, i64), (usize, f64)> = HashMap::new();
    for &i in used {
        let p = vertices[i];
        lo = lo.min(p[2]);
        hi = hi.max(p[2]);
        let key = ((p[0] * 100.0).round() as i64, (p[1] * 100.0).round() as i64);
        let c = columns.entry(key).or_insert((i, p[2]));
        if p[2] < vertices[c.0][2] {
            c.0 = i;
        }
        c.1 = c.1.max(p[2]);
    }
    let reach = lo + 0.25 * (hi - lo);
    let mut out: Vec<usize> = columns
        .into_values()
        .filter(|&(i, top)| {
            let z = vertices[i][2];
            z <= lo + 0.01 || (z <= reach && top - z >= 1.0)
        })
        .map(|(i, _)| i)
        .collect();
    out.sort_unstable();
    out
}

#[cfg(test)]
mod tests;
