//! CityJSON (1.0, 1.1, 2.0) footprints: one per Building, its BuildingParts
//! included.
//!
//! Per object the geometry with the highest LoD is used; its footprint is the
//! xy outline of its `GroundSurface` surfaces when it has any, else the union
//! of the xy projections of all its surfaces. A Building's footprint is the
//! union over itself and its parts. Ids follow the scene reader
//! ([`crate::scene::cityjson`]): 1.. in the sorted order of the root
//! buildings' CityJSON ids, so they match a scene loaded from the same file.

use std::collections::{BTreeMap, HashMap};

use geo::Polygon;
use serde::Deserialize;
use serde_json::Value;

use super::error::{ParseError, Skipped, shape};
use super::polygon::{ring, union_valid};
use super::types::{Footprint, Loaded};
use crate::scene::cityjson::boundaries::{self, Surface};
use crate::scene::cityjson::model::Geometry;

/// Parent links followed at most this deep (guards against cycles).
const MAX_DEPTH: usize = 32;

/// Decodes CityJSON bytes; coordinates have `origin` subtracted.
pub fn parse_cityjson_footprints(data: &[u8], origin: [f64; 3]) -> Result<Loaded, ParseError> {
    let doc = super::json::parse(data)?;
    if doc.get("type").and_then(Value::as_str) != Some("CityJSON") {
        return Err(shape(
            "not a CityJSON document (top-level `type` is not `CityJSON`)",
        ));
    }
    let vertices = real_vertices(&doc)?;
    let objects = doc
        .get("CityObjects")
        .and_then(Value::as_object)
        .ok_or_else(|| shape("CityJSON without a `CityObjects` object"))?;
    let is_building = |o: &Value| {
        matches!(
            o.get("type").and_then(Value::as_str),
            Some("Building" | "BuildingPart")
        )
    };
    let parents = parent_map(objects);
    let mut skipped = Vec::new();
    let mut per_root: BTreeMap<&str, Vec<Polygon<f64>>> = BTreeMap::new();
    for (id, object) in objects {
        if !is_building(object) {
            continue;
        }
        let polys = object_footprint(id, object, &vertices, origin, &mut skipped)?;
        if polys.is_empty() {
            continue;
        }
        let root = root_of(objects, &parents, id, &is_building);
        per_root.entry(root).or_default().extend(polys);
    }
    let mut footprints = Vec::with_capacity(per_root.len());
    for (root, polys) in per_root {
        match union_valid(&polys) {
            Ok(polygon) => footprints.push(Footprint {
                id: u32::try_from(footprints.len() + 1).unwrap_or(u32::MAX),
                polygon,
                name: root.to_string(),
            }),
            Err(problem) => skipped.push(Skipped {
                source: format!("building `{root}`"),
                problem,
            }),
        }
    }
    Loaded::new(footprints, skipped)
}

/// Decompressed vertices (source CRS).
fn real_vertices(doc: &Value) -> Result<Vec<[f64; 3]>, ParseError> {
    let triple = |v: Option<&Value>, default: f64| -> Option<[f64; 3]> {
        match v {
            None => Some([default; 3]),
            Some(v) => {
                let a = v.as_array().filter(|a| a.len() == 3)?;
                let out = [0, 1, 2].map(|k| a[k].as_f64().unwrap_or(f64::NAN));
                out.iter().all(|c| c.is_finite()).then_some(out)
            }
        }
    };
    let t = doc.get("transform");
    let scale = triple(t.and_then(|t| t.get("scale")), 1.0)
        .ok_or_else(|| shape("`transform.scale` must be three finite numbers"))?;
    let translate = triple(t.and_then(|t| t.get("translate")), 0.0)
        .ok_or_else(|| shape("`transform.translate` must be three finite numbers"))?;
    let vs = doc
        .get("vertices")
        .and_then(Value::as_array)
        .ok_or_else(|| shape("CityJSON without a `vertices` array"))?;
    vs.iter()
        .enumerate()
        .map(|(k, v)| {
            let p = triple(Some(v), 0.0)
                .ok_or_else(|| shape(&format!("vertex {k} is not three finite numbers")))?;
            Ok([0, 1, 2].map(|a| p[a] * scale[a] + translate[a]))
        })
        .collect()
}

/// Each object's parent: its first `parents` entry, else the object listing it as a child.
fn parent_map(objects: &serde_json::Map<String, Value>) -> HashMap<&str, &str> {
    let mut map: HashMap<&str, &str> = HashMap::new();
    for (id, o) in objects {
        for child in o
            .get("children")
            .and_then(Value::as_array)
            .into_iter()
            .flatten()
        {
            if let Some(c) = child.as_str() {
                map.entry(c).or_insert(id.as_str());
            }
        }
    }
    for (id, o) in objects {
        if let Some(p) = o
            .get("parents")
            .and_then(Value::as_array)
            .and_then(|a| a.first())
            .and_then(Value::as_str)
        {
            map.insert(id.as_str(), p);
        }
    }
    map
}

/// The id of the Building at the top of `id`'s parent chain.
fn root_of<'a>(
    objects: &'a serde_json::Map<String, Value>,
    parents: &HashMap<&'a str, &'a str>,
    id: &'a str,
    is_building: &dyn Fn(&Value) -> bool,
) -> &'a str {
    let mut cur = id;
    for _ in 0..MAX_DEPTH {
        let Some(obj) = objects.get(cur) else { break };
        if obj.get("type").and_then(Value::as_str) == Some("Building") {
            break;
        }
        match parents.get(cur) {
            Some(&p) if objects.get(p).is_some_and(is_building) => cur = p,
            _ => break,
        }
    }
    objects.get_key_value(cur).map_or(id, |(k, _)| k.as_str())
}

/// The footprint polygons of one object (empty when it has no surface geometry).
fn object_footprint(
    id: &str,
    object: &Value,
    vertices: &[[f64; 3]],
    origin: [f64; 3],
    skipped: &mut Vec<Skipped>,
) -> Result<Vec<Polygon<f64>>, ParseError> {
    // The highest-LoD surface geometry, read as the scene's CityJSON reader reads it.
    let geoms: Vec<Geometry> = object
        .get("geometry")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
        .filter_map(|g| Geometry::deserialize(g).ok())
        .filter(|g| g.surface_depth().is_some())
        .collect();
    let Some(g) = geoms
        .iter()
        .max_by(|a, b| a.lod_value().total_cmp(&b.lod_value()))
    else {
        return Ok(Vec::new());
    };
    let values = g.semantics.as_ref().and_then(|s| s.get("values"));
    let depth = g.surface_depth().unwrap_or(0);
    let surfaces = boundaries::surfaces(&g.boundaries, values, depth)
        .map_err(|reason| shape(&format!("city object `{id}`: {reason}")))?;
    let semantic = |s: &Surface| s.semantic.and_then(|i| g.semantic_type(i));
    let grounds = surfaces
        .iter()
        .any(|s| semantic(s) == Some("GroundSurface"));
    let mut out = Vec::new();
    for (k, s) in surfaces.iter().enumerate() {
        if grounds && semantic(s) != Some("GroundSurface") {
            continue;
        }
        let mut rings = Vec::with_capacity(s.rings.len());
        for r in &s.rings {
            let mut pts = Vec::with_capacity(r.len());
            for i in r {
                let p = usize::try_from(*i)
                    .ok()
                    .and_then(|i| vertices.get(i))
                    .ok_or_else(|| {
                        shape(&format!(
                            "city object `{id}`: vertex index {i} is not one of the {} vertices",
                            vertices.len()
                        ))
                    })?;
                pts.push([p[0] - origin[0], p[1] - origin[1]]);
            }
            rings.push(ring(&pts, false));
        }
        let mut it = rings.into_iter();
        match it.next() {
            Some(Ok(outer)) => out.push(Polygon::new(outer, it.filter_map(Result::ok).collect())),
            // Vertical faces project to lines: expected without GroundSurface.
            Some(Err(problem)) if grounds => skipped.push(Skipped {
                source: format!("city object `{id}`, surface {k}"),
                problem,
            }),
            _ => {}
        }
    }
    Ok(out)
}
