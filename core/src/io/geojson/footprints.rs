//! GeoJSON footprints: a FeatureCollection, a Feature or a bare geometry;
//! Polygon, MultiPolygon and GeometryCollections of them, with holes.
//!
//! Each footprint's own id (its `name`) is the property the user names, else
//! the first of [`ID_FIELDS`](crate::footprint::ID_FIELDS) present, else the
//! Feature's `id`, else its `name`. Numeric ids come from the property `id`
//! or `building` or the Feature's `id` (a positive integer or a string of
//! one); the others get the next free ids in file order. Features sharing a
//! numeric id, or without one sharing their own id (a building drawn in
//! several features), are merged.

use std::collections::BTreeMap;

use geo::{MultiPolygon, Polygon};
use serde_json::Value;

use crate::footprint::error::{ParseError, RingProblem, Skipped, shape};
use crate::footprint::ids::{ReadOptions, check_named_field, id_text, own_id};
use crate::footprint::polygon::{ring, union_valid};
use crate::footprint::{Footprint, Loaded};

/// One feature's polygons with its ids.
struct Part {
    id: Option<u32>,
    name: Option<String>,
    polygons: MultiPolygon<f64>,
}

/// Decodes GeoJSON bytes; coordinates have `origin` (x, y) subtracted.
pub fn parse_geojson(data: &[u8], origin: [f64; 3]) -> Result<Loaded, ParseError> {
    parse_geojson_with(data, origin, &ReadOptions::default())
}

/// [`parse_geojson`] with the own ids read as `options` say.
pub fn parse_geojson_with(
    data: &[u8],
    origin: [f64; 3],
    options: &ReadOptions,
) -> Result<Loaded, ParseError> {
    let v = super::json::parse(data)?;
    let features = features_of(&v)?;
    let mut skipped = Vec::new();
    let mut parts: Vec<Part> = Vec::new();
    let mut named = 0usize;
    let mut first_props = None;
    for (k, f) in features.iter().enumerate() {
        let (geometry, props) = if f.get("type").and_then(Value::as_str) == Some("Feature") {
            (
                f.get("geometry").unwrap_or(&Value::Null),
                f.get("properties").and_then(Value::as_object),
            )
        } else {
            (*f, None)
        };
        first_props = first_props.or(props);
        let own = own_id(props, options);
        named += usize::from(own.is_some());
        let label = format!("feature {k}");
        let mut polys = Vec::new();
        collect_polygons(geometry, origin, &label, &mut polys, &mut skipped);
        if polys.is_empty() {
            continue;
        }
        match union_valid(&polys) {
            Ok(polygons) => parts.push(Part {
                id: feature_id(f, props),
                name: own
                    .or_else(|| f.get("id").and_then(id_text))
                    .or_else(|| props.and_then(|p| p.get("name")).and_then(id_text)),
                polygons,
            }),
            Err(problem) => skipped.push(Skipped {
                source: label,
                problem,
            }),
        }
    }
    check_named_field(options, named, first_props)?;
    Loaded::new(merged(parts), skipped)
}

/// The features of a document (a bare geometry is one).
fn features_of(v: &Value) -> Result<Vec<&Value>, ParseError> {
    match v.get("type").and_then(Value::as_str).unwrap_or("") {
        "FeatureCollection" => Ok(v
            .get("features")
            .and_then(Value::as_array)
            .ok_or_else(|| shape("a FeatureCollection needs a `features` array"))?
            .iter()
            .collect()),
        "Feature" | "Polygon" | "MultiPolygon" | "GeometryCollection" => Ok(vec![v]),
        "" => Err(shape("not GeoJSON: no `type` member at the top level")),
        other => Err(shape(&format!(
            "GeoJSON type `{other}` holds no polygons (FeatureCollection, Feature, Polygon or MultiPolygon expected)"
        ))),
    }
}

/// One footprint per numeric id, or per own id where there is none; the
/// rest get the next free numeric ids in file order.
fn merged(parts: Vec<Part>) -> Vec<Footprint> {
    let mut next = parts.iter().filter_map(|p| p.id).max().unwrap_or(0);
    let mut by_name: BTreeMap<String, u32> = BTreeMap::new();
    let mut by_id: BTreeMap<u32, (String, Vec<Polygon<f64>>)> = BTreeMap::new();
    for (k, part) in parts.into_iter().enumerate() {
        let mut fresh = || {
            next = next.saturating_add(1);
            next
        };
        let id = match (part.id, &part.name) {
            (Some(id), _) => id,
            (None, Some(name)) => *by_name.entry(name.clone()).or_insert_with(&mut fresh),
            (None, None) => fresh(),
        };
        let name = part.name.unwrap_or_else(|| format!("feature_{k}"));
        by_id
            .entry(id)
            .or_insert_with(|| (name, Vec::new()))
            .1
            .extend(part.polygons);
    }
    by_id
        .into_iter()
        .filter_map(|(id, (name, polys))| Footprint::from_parts(id, name, &polys))
        .collect()
}

/// A positive id from the feature's `id` or its properties `id` / `building`.
fn feature_id(feature: &Value, props: Option<&serde_json::Map<String, Value>>) -> Option<u32> {
    let as_id = |v: &Value| -> Option<u32> {
        let n = match v {
            Value::Number(n) => n.as_u64()?,
            Value::String(s) => s.trim().parse::<u64>().ok()?,
            _ => return None,
        };
        u32::try_from(n).ok().filter(|&n| n > 0)
    };
    let p = |key: &str| props.and_then(|p| p.get(key)).and_then(as_id);
    p("id")
        .or_else(|| p("building"))
        .or_else(|| feature.get("id").and_then(as_id))
}

/// Appends the polygons of a geometry (non-polygon geometries are skipped and counted).
fn collect_polygons(
    g: &Value,
    origin: [f64; 3],
    label: &str,
    out: &mut Vec<Polygon<f64>>,
    skipped: &mut Vec<Skipped>,
) {
    let coords = g.get("coordinates");
    match g.get("type").and_then(Value::as_str) {
        Some("Polygon") => {
            if let Some(p) = polygon(coords, origin, label, skipped) {
                out.push(p);
            }
        }
        Some("MultiPolygon") => match coords.and_then(Value::as_array) {
            Some(ps) => {
                for (k, p) in ps.iter().enumerate() {
                    let l = format!("{label}, polygon {k}");
                    if let Some(p) = polygon(Some(p), origin, &l, skipped) {
                        out.push(p);
                    }
                }
            }
            None => skipped.push(Skipped {
                source: label.to_string(),
                problem: RingProblem::BadPosition,
            }),
        },
        Some("GeometryCollection") => {
            for sub in g
                .get("geometries")
                .and_then(Value::as_array)
                .into_iter()
                .flatten()
            {
                collect_polygons(sub, origin, label, out, skipped);
            }
        }
        other => skipped.push(Skipped {
            source: label.to_string(),
            problem: RingProblem::NotPolygon(other.unwrap_or("null").to_string()),
        }),
    }
}

/// One Polygon's `coordinates`: a bad exterior skips the polygon, a bad hole only the hole.
fn polygon(
    coords: Option<&Value>,
    origin: [f64; 3],
    label: &str,
    skipped: &mut Vec<Skipped>,
) -> Option<Polygon<f64>> {
    let mut skip = |problem| {
        skipped.push(Skipped {
            source: label.to_string(),
            problem,
        })
    };
    let Some(rings) = coords.and_then(Value::as_array) else {
        skip(RingProblem::BadPosition);
        return None;
    };
    let mut out = Vec::with_capacity(rings.len());
    for (k, r) in rings.iter().enumerate() {
        let parsed = positions(r, origin).and_then(|p| ring(&p, true));
        match parsed {
            Ok(l) => out.push(l),
            Err(problem) if k == 0 => {
                skip(problem);
                return None;
            }
            Err(problem) => skip(problem),
        }
    }
    let mut it = out.into_iter();
    let outer = it.next()?;
    Some(Polygon::new(outer, it.collect()))
}

fn positions(ring: &Value, origin: [f64; 3]) -> Result<Vec<[f64; 2]>, RingProblem> {
    ring.as_array()
        .ok_or(RingProblem::BadPosition)?
        .iter()
        .map(|p| {
            let a = p.as_array().filter(|a| a.len() >= 2);
            let x = a.and_then(|a| a[0].as_f64());
            let y = a.and_then(|a| a[1].as_f64());
            match (x, y) {
                (Some(x), Some(y)) => Ok([x - origin[0], y - origin[1]]),
                _ => Err(RingProblem::BadPosition),
            }
        })
        .collect()
}
