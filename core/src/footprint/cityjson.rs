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
use serde_json::Value;

use super::error::{ParseError, Skipped, shape};
use super::polygon::{ring, union_valid};
use super::types::{Footprint, Loaded};

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

/// Array levels above the surface level for surface geometry types.
fn surface_depth(kind: &str) -> Option<usize> {
    match kind {
        "MultiSurface" | "CompositeSurface" => Some(0),
        "Solid" => Some(1),
        "MultiSolid" | "CompositeSolid" => Some(2),
        _ => None,
    }
}

fn lod_value(g: &Value) -> f64 {
    match g.get("lod") {
        Some(Value::Number(n)) => n.as_f64().unwrap_or(0.0),
        Some(Value::String(s)) => s.trim().parse().unwrap_or(0.0),
        _ => 0.0,
    }
}

/// One surface: rings of vertex indices, and its semantic type if any.
struct Surface<'a> {
    rings: &'a [Value],
    semantic: Option<&'a str>,
}

/// The footprint polygons of one object (empty when it has no surface geometry).
fn object_footprint(
    id: &str,
    object: &Value,
    vertices: &[[f64; 3]],
    origin: [f64; 3],
    skipped: &mut Vec<Skipped>,
) -> Result<Vec<Polygon<f64>>, ParseError> {
    let geoms = object.get("geometry").and_then(Value::as_array);
    let best = geoms
        .into_iter()
        .flatten()
        .filter_map(|g| Some((g, surface_depth(g.get("type")?.as_str()?)?)))
        .max_by(|a, b| lod_value(a.0).total_cmp(&lod_value(b.0)));
    let Some((g, depth)) = best else {
        return Ok(Vec::new());
    };
    let types: Vec<Option<&str>> = g
        .pointer("/semantics/surfaces")
        .and_then(Value::as_array)
        .map(|s| {
            s.iter()
                .map(|t| t.get("type").and_then(Value::as_str))
                .collect()
        })
        .unwrap_or_default();
    let mut surfaces = Vec::new();
    walk(
        g.get("boundaries").unwrap_or(&Value::Null),
        g.pointer("/semantics/values"),
        depth,
        &types,
        &mut surfaces,
    )
    .map_err(|reason| shape(&format!("city object `{id}`: {reason}")))?;
    let grounds = surfaces.iter().any(|s| s.semantic == Some("GroundSurface"));
    let mut out = Vec::new();
    for (k, s) in surfaces.iter().enumerate() {
        if grounds && s.semantic != Some("GroundSurface") {
            continue;
        }
        let mut rings = Vec::with_capacity(s.rings.len());
        for r in s.rings {
            let idx = r.as_array().map(Vec::as_slice).unwrap_or_default();
            let mut pts = Vec::with_capacity(idx.len());
            for i in idx {
                let p = i
                    .as_u64()
                    .and_then(|i| usize::try_from(i).ok())
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

/// Walks nested `boundaries` (and the parallel `semantics.values`) down to surfaces.
fn walk<'a>(
    b: &'a Value,
    values: Option<&'a Value>,
    depth: usize,
    types: &[Option<&'a str>],
    out: &mut Vec<Surface<'a>>,
) -> Result<(), &'static str> {
    let items = b
        .as_array()
        .ok_or("`boundaries` do not nest as the geometry type requires")?;
    let vals = values.and_then(Value::as_array);
    for (k, item) in items.iter().enumerate() {
        let v = vals.and_then(|a| a.get(k));
        if depth > 0 {
            walk(item, v, depth - 1, types, out)?;
        } else {
            let rings = item
                .as_array()
                .ok_or("a surface must be an array of rings")?;
            let semantic = v
                .and_then(Value::as_u64)
                .and_then(|i| types.get(usize::try_from(i).ok()?).copied().flatten());
            out.push(Surface { rings, semantic });
        }
    }
    Ok(())
}
