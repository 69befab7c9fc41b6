//! CityJSON (1.0, 1.1, 2.0) and CityJSONSeq footprints: one per Building,
//! its BuildingParts joined to it, or with `ReadOptions::parts` one per
//! BuildingPart (the Building's own id kept in `Loaded::part_of`).
//!
//! A building whose objects carry a LoD 0 surface geometry (the cadastral
//! footprint 3DBAG ships) takes the union of those; otherwise each object's
//! highest-LoD geometry gives the xy outline of its `GroundSurface`
//! surfaces when it has any, else the union of the xy projections of all
//! its surfaces. Numeric ids follow the scene reader
//! ([`super`]): 1.. in the sorted order of the root
//! buildings' CityJSON ids, so they match a scene loaded from the same
//! file(s). The own id (`name`) is the root Building's attribute the user
//! names, else the first of [`ID_FIELDS`](crate::footprint::ID_FIELDS) it has,
//! else its CityObject id.

use std::collections::BTreeMap;

use geo::Polygon;

use super::boundaries::{self, Surface};
use super::{CityModel, CityObject, Geometry, parse_city_model};
use crate::footprint::error::{ParseError, Skipped, shape};
use crate::footprint::ids::{ReadOptions, check_named_field, own_id};
use crate::footprint::polygon::{ring, union_valid};
use crate::footprint::{Footprint, Loaded};

/// Decodes CityJSON (or CityJSONSeq) bytes; coordinates have `origin` subtracted.
pub fn parse_cityjson_footprints(data: &[u8], origin: [f64; 3]) -> Result<Loaded, ParseError> {
    let model = parse_city_model(data).map_err(|e| shape(&e.to_string()))?;
    cityjson_footprints(&model, origin, &ReadOptions::default())
}

/// The footprints of a city model (one or more files read as one, source
/// CRS and unit), `origin` subtracted.
pub fn cityjson_footprints(
    model: &CityModel,
    origin: [f64; 3],
    options: &ReadOptions,
) -> Result<Loaded, ParseError> {
    let mut groups: BTreeMap<&str, Vec<(&str, &CityObject)>> = BTreeMap::new();
    for (id, root) in model.roots() {
        if let Some(o) = model.objects.get(id) {
            groups.entry(root).or_default().push((id, o));
        }
    }
    if groups.is_empty() {
        return Err(shape("the city model has no Building or BuildingPart"));
    }
    let mut skipped = Vec::new();
    let mut footprints = Vec::with_capacity(groups.len());
    let mut named = 0usize;
    // Every building with an outline takes an id, as in the scene, even
    // one whose outline then turns out unusable.
    let mut next = 0u32;
    let first_attrs = groups
        .keys()
        .next()
        .and_then(|r| model.objects.get(*r))
        .and_then(|o| o.attributes.as_ref())
        .and_then(|a| a.as_object());
    let mut part_of = BTreeMap::new();
    for (root, objects) in &groups {
        let attrs = model
            .objects
            .get(*root)
            .and_then(|o| o.attributes.as_ref())
            .and_then(|a| a.as_object());
        let own = own_id(attrs, options);
        let building = own.clone().unwrap_or_else(|| (*root).to_string());
        // Per part: each BuildingPart alone; the Building's own geometry
        // (3DBAG's LoD 0 outline of the whole) is then left out.
        let parts: Vec<&[(&str, &CityObject)]> = objects
            .chunks(1)
            .filter(|u| u[0].1.kind == "BuildingPart")
            .collect();
        let units = if options.parts && !parts.is_empty() {
            parts
        } else {
            vec![&objects[..]]
        };
        let mut any = false;
        for unit in units {
            let polys = group_footprint(unit, model, origin, &mut skipped)?;
            if polys.is_empty() {
                continue;
            }
            any = true;
            next = next.saturating_add(1);
            let id = next;
            let (object, o) = unit[0];
            let part = options.parts && o.kind == "BuildingPart";
            let name = if part {
                part_of.insert(id, building.clone());
                object.to_string()
            } else {
                building.clone()
            };
            match union_valid(&polys) {
                Ok(polygon) => footprints.push(Footprint { id, polygon, name }),
                Err(problem) => skipped.push(Skipped {
                    source: format!("building `{root}`"),
                    problem,
                }),
            }
        }
        named += usize::from(any && own.is_some());
    }
    check_named_field(options, named, first_attrs)?;
    let mut loaded = Loaded::new(footprints, skipped)?;
    loaded.part_of = part_of;
    Ok(loaded)
}

/// The footprint polygons of one building (its objects): LoD 0 where any
/// object has it, else each object's highest LoD.
fn group_footprint(
    objects: &[(&str, &CityObject)],
    model: &CityModel,
    origin: [f64; 3],
    skipped: &mut Vec<Skipped>,
) -> Result<Vec<Polygon<f64>>, ParseError> {
    let surface = |g: &&Geometry| g.surface_depth().is_some();
    let lod0 = objects.iter().any(|(_, o)| {
        o.geometry
            .iter()
            .filter(surface)
            .any(|g| g.lod_value() < 1.0)
    });
    let mut out = Vec::new();
    for (id, o) in objects {
        let usable = o.geometry.iter().filter(surface);
        let chosen: Vec<&Geometry> = if lod0 {
            usable.filter(|g| g.lod_value() < 1.0).collect()
        } else {
            usable
                .max_by(|a, b| a.lod_value().total_cmp(&b.lod_value()))
                .into_iter()
                .collect()
        };
        for g in chosen {
            geometry_footprint(id, g, &model.vertices, origin, skipped, &mut out)?;
        }
    }
    Ok(out)
}

/// Appends the xy outline of one geometry: its ground surfaces when it has
/// any, else every surface's projection.
fn geometry_footprint(
    id: &str,
    g: &Geometry,
    vertices: &[[f64; 3]],
    origin: [f64; 3],
    skipped: &mut Vec<Skipped>,
    out: &mut Vec<Polygon<f64>>,
) -> Result<(), ParseError> {
    let values = g.semantics.as_ref().and_then(|s| s.get("values"));
    let depth = g.surface_depth().unwrap_or(0);
    let surfaces = boundaries::surfaces(&g.boundaries, values, depth)
        .map_err(|reason| shape(&format!("city object `{id}`: {reason}")))?;
    let semantic = |s: &Surface| s.semantic.and_then(|i| g.semantic_type(i));
    let grounds = surfaces
        .iter()
        .any(|s| semantic(s) == Some("GroundSurface"));
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
    Ok(())
}
