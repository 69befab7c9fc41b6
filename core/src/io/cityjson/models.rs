//! CityJSON 2.0 output: one Building per model (a BuildingPart of its
//! Building when the model's footprint was a part), its LoD 2.2 Solid with
//! RoofSurface / WallSurface / GroundSurface semantics, integer vertices
//! under a transform of a thousandth of the unit, in the source coordinates
//! and unit of the cloud, its CRS in `metadata.referenceSystem`.

use std::path::Path;

use serde_json::{Value, json};

use super::crs_url;
use crate::reconstruct::{Model, ReconstructError, Reconstruction};

/// Vertex precision: a thousandth of the source unit (1 mm, or 0.001 ft).
const SCALE: f64 = 0.001;

/// The reconstruction as a CityJSON 2.0 document in the cloud's coordinates
/// and unit; its CRS goes to `metadata.referenceSystem` when it has an EPSG
/// code (CityJSON names a CRS by URL only).
pub fn to_cityjson(rec: &Reconstruction) -> Value {
    let frame = rec.frame();
    let world = |p: [f64; 3]| frame.to_source(p);
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for m in &rec.models {
        for v in &m.shell.vertices {
            let w = world(*v);
            for k in 0..3 {
                lo[k] = lo[k].min(w[k]);
                hi[k] = hi[k].max(w[k]);
            }
        }
    }
    let any = lo[0].is_finite();
    if !any {
        lo = [0.0; 3];
        hi = [0.0; 3];
    }
    let translate = lo.map(|v| (v / SCALE).floor() * SCALE);
    // Vertices merged by their integer position (two corners snapped onto
    // one spot become one vertex; zero-length edges they leave are dropped).
    let mut vertices: Vec<[i64; 3]> = Vec::new();
    let mut index: std::collections::HashMap<[i64; 3], usize> = Default::default();
    let mut objects = serde_json::Map::new();
    // BuildingParts' models by the Building they belong to.
    let mut parts: std::collections::BTreeMap<&str, Vec<(String, &Model)>> = Default::default();
    for m in &rec.models {
        let ids: Vec<usize> = m
            .shell
            .vertices
            .iter()
            .map(|v| {
                let w = world(*v);
                let q = [0, 1, 2].map(|k| ((w[k] - translate[k]) / SCALE).round() as i64);
                *index.entry(q).or_insert_with(|| {
                    vertices.push(q);
                    vertices.len() - 1
                })
            })
            .collect();
        let mut kinds = Vec::new();
        let surfaces: Vec<Value> = m
            .shell
            .faces
            .iter()
            .filter_map(|f| {
                let rings: Vec<Vec<usize>> = f
                    .rings
                    .iter()
                    .map(|r| {
                        let mut out: Vec<usize> = r.iter().map(|&v| ids[v as usize]).collect();
                        out.dedup();
                        while out.len() > 1 && out.first() == out.last() {
                            out.pop();
                        }
                        out
                    })
                    .filter(|r| r.len() >= 3)
                    .collect();
                let outer_ok = f.rings.first().is_some_and(|r| {
                    let mut o: Vec<usize> = r.iter().map(|&v| ids[v as usize]).collect();
                    o.dedup();
                    o.len() >= 3
                });
                (outer_ok && !rings.is_empty()).then(|| {
                    kinds.push(f.kind);
                    Value::from(rings)
                })
            })
            .collect();
        let values: Vec<usize> = kinds
            .iter()
            .map(|k| match k {
                crate::reconstruct::SurfaceType::RoofSurface => 0,
                crate::reconstruct::SurfaceType::WallSurface => 1,
                crate::reconstruct::SurfaceType::GroundSurface => 2,
            })
            .collect();
        let key = match rec.part_of.get(&m.id) {
            Some(b) => {
                let children = parts.entry(b.as_str()).or_default();
                // The input's own BuildingPart id, else one made from its Building's.
                let own = &m.name;
                // Each model goes into `objects` as it is keyed: a key taken
                // there (by a sibling too) is not free.
                let key = if !own.is_empty() && own != b && !objects.contains_key(own) {
                    own.clone()
                } else {
                    format!("{b}-{}", children.len())
                };
                children.push((key.clone(), m));
                key
            }
            None => format!("building_{}", m.id),
        };
        let kind = if rec.part_of.contains_key(&m.id) {
            "BuildingPart"
        } else {
            "Building"
        };
        objects.insert(
            key,
            json!({
                "type": kind,
                "attributes": {
                    "name": m.name,
                    "roof_planes": m.planes,
                    "walls_on_points": m.walls.on_wall_points,
                    "walls_on_outline": m.walls.on_outline,
                    "open_ground_floor": m.open_base,
                    "skyground_lod": m.lod.as_str(),
                    "skyground_fallback_reason": m.fallback,
                    "skyground_rmse_m": m.quality.rmse_m,
                    "skyground_rmse_roof_points_m": m.quality.rmse_roof_points_m,
                    "skyground_footprint_iou": m.quality.footprint_iou,
                    "skyground_val3dity_codes": m.quality.val3dity,
                    "skyground_rejected_lod22_val3dity_codes": m.quality.rejected_val3dity,
                    "skyground_points": m.points,
                    "skyground_roof_density": m.roof_density,
                },
                "geometry": [{
                    "type": "Solid",
                    "lod": m.lod.as_str(),
                    "boundaries": [surfaces],
                    "semantics": {
                        "surfaces": [
                            {"type": "RoofSurface"},
                            {"type": "WallSurface"},
                            {"type": "GroundSurface"}
                        ],
                        "values": [values]
                    }
                }]
            }),
        );
    }
    for (b, children) in &parts {
        let (keys, models): (Vec<String>, Vec<&Model>) = children.iter().cloned().unzip();
        for k in &keys {
            if let Some(o) = objects.get_mut(k) {
                o["parents"] = json!([b]);
            }
        }
        objects.insert(b.to_string(), building_of_parts(b, &models, keys));
    }
    let mut metadata = json!({"title": "skyground LoD2 reconstruction"});
    // No models, no extent (not a point at the origin).
    if any {
        metadata["geographicalExtent"] = json!([lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]]);
    }
    if let Some(code) = rec.crs.as_ref().and_then(|c| c.epsg) {
        metadata["referenceSystem"] = Value::from(crs_url(&format!("EPSG:{code}")));
    }
    json!({
        "type": "CityJSON",
        "version": "2.0",
        "transform": {"scale": [SCALE, SCALE, SCALE], "translate": translate},
        "metadata": metadata,
        "CityObjects": objects,
        "vertices": vertices,
    })
}

/// The Building that holds BuildingParts' models: its own id, the parts,
/// the lowest LoD among them and whether every one is valid.
fn building_of_parts(name: &str, parts: &[&Model], children: Vec<String>) -> Value {
    let lod = parts.iter().map(|m| m.lod.as_str()).min().unwrap_or("1.2");
    json!({
        "type": "Building",
        "attributes": {
            "name": name,
            "skyground_parts": parts.len(),
            "skyground_lod": lod,
            "skyground_all_parts_valid": parts.iter().all(|m| m.quality.val3dity.is_empty()),
            "skyground_points": parts.iter().map(|m| m.points).sum::<usize>(),
        },
        "children": children,
    })
}

/// Writes [`to_cityjson`] to `path`.
pub fn write_cityjson(path: &Path, rec: &Reconstruction) -> Result<(), ReconstructError> {
    crate::file::write(path, to_cityjson(rec).to_string()).map_err(|e| ReconstructError::Write {
        what: path.display().to_string(),
        source: e.source,
    })
}
