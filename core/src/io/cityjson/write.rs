//! Writing buildings back as a CityJSON 2.0 document with attributes of our
//! own per building (3DBAG publishes quality attributes per building; these
//! are skyground's).
//!
//! - From a [`CityModel`]: its buildings as read (every surface geometry and
//!   LoD, semantics kept; textures and materials left out), in its CRS and
//!   compressed with its `transform`, so a 2.0 file comes back with the
//!   same integers.
//! - From any [`Scene`] (the reference scene, OBJ, PLY): one `Building` per
//!   building id, its triangles as a LoD 2 `MultiSurface`.
//!
//! Attributes go on each root `Building`, next to those it already had.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use serde_json::{Map, Value, json};

use super::boundaries::map_indices;
use super::model::Transform;
use super::source::{BUILDING_TYPES, CityModel, crs_key};
use crate::scene::{ObjectKind, Scene};

/// Attributes to add, per building.
pub type Attributes = Map<String, Value>;

/// The CityJSON 2.0 form of a CRS name: an OGC URL for an EPSG code,
/// otherwise the name as given.
pub fn crs_url(crs: &str) -> String {
    match crs_key(crs).strip_prefix("EPSG:") {
        Some(code) => format!("https://www.opengis.net/def/crs/EPSG/0/{code}"),
        None => crs.to_string(),
    }
}

/// The buildings of `model` whose root id is a key of `attributes` (all of
/// them when `only_listed` is false), each root with its attributes added,
/// as a CityJSON 2.0 document.
pub fn annotated_model(
    model: &CityModel,
    attributes: &BTreeMap<String, Attributes>,
    only_listed: bool,
) -> Value {
    let parents = super::parent_map(model);
    let written: BTreeSet<&str> = model
        .objects
        .iter()
        .filter(|(_, o)| BUILDING_TYPES.contains(&o.kind.as_str()))
        .map(|(id, _)| id.as_str())
        .filter(|id| !only_listed || attributes.contains_key(super::root_of(model, &parents, id)))
        .collect();
    let mut out = Vertices::new(model.transform, &model.vertices);
    let mut objects = Map::new();
    for &id in &written {
        let Some(o) = model.objects.get(id) else {
            continue;
        };
        let mut attrs = match &o.attributes {
            Some(Value::Object(m)) => m.clone(),
            _ => Map::new(),
        };
        if let Some(extra) = attributes.get(id) {
            attrs.extend(extra.clone());
        }
        let geometry: Vec<Value> = o
            .geometry
            .iter()
            .filter(|g| g.surface_depth().is_some())
            .filter_map(|g| {
                let boundaries = map_indices(&g.boundaries, &mut |i| {
                    usize::try_from(i)
                        .ok()
                        .and_then(|i| out.index(i))
                        .map(|k| k as u64)
                })?;
                let mut v = json!({
                    "type": g.kind,
                    "lod": super::source::lod_string(g.lod.as_ref()).unwrap_or_else(|| "1".into()),
                    "boundaries": boundaries,
                });
                if let Some(s) = &g.semantics {
                    v["semantics"] = s.clone();
                }
                Some(v)
            })
            .collect();
        let keep = |ids: &[String]| -> Vec<String> {
            ids.iter()
                .filter(|c| written.contains(c.as_str()))
                .cloned()
                .collect()
        };
        let (kids, ups) = (keep(&o.children), keep(&o.parents));
        // A part whose Building is not written would break the schema's
        // parent rule: it stands as a Building of its own.
        let kind = if o.kind == "BuildingPart" && ups.is_empty() {
            "Building"
        } else {
            o.kind.as_str()
        };
        let mut v = json!({"type": kind, "geometry": geometry});
        if !attrs.is_empty() {
            v["attributes"] = Value::Object(attrs);
        }
        if !kids.is_empty() {
            v["children"] = json!(kids);
        }
        if !ups.is_empty() {
            v["parents"] = json!(ups);
        }
        objects.insert(id.to_string(), v);
    }
    out.document(objects, model.reference_system.as_deref())
}

/// Every building of `scene` as a CityJSON 2.0 `Building` (id
/// `building-K`, or the scene object's name when unique) with a LoD 2
/// MultiSurface of its triangles in source coordinates (local + origin),
/// with `attributes` by building id.
pub fn scene_model(
    scene: &Scene,
    attributes: &BTreeMap<u32, Attributes>,
    reference_system: Option<&str>,
) -> Value {
    let mut per_building: BTreeMap<u32, Vec<usize>> = BTreeMap::new();
    for t in 0..scene.triangles.len() {
        if let Some(o) = scene.triangle_kind(t)
            && o.kind == ObjectKind::Building
        {
            per_building.entry(o.building).or_default().push(t);
        }
    }
    let source: Vec<[f64; 3]> = scene
        .vertices
        .iter()
        .map(|p| [0, 1, 2].map(|k| f64::from(p[k]) + scene.origin[k]))
        .collect();
    let transform = Transform {
        scale: [0.001; 3],
        translate: scene.origin,
    };
    let mut out = Vertices::new(Some(transform), &source);
    let mut objects = Map::new();
    for (building, tris) in per_building {
        let surfaces: Vec<Value> = tris
            .iter()
            .filter_map(|&t| {
                let ring: Option<Vec<usize>> = scene.triangles[t]
                    .iter()
                    .map(|&i| out.index(i as usize))
                    .collect();
                let ring = ring?;
                // Triangles that collapse at millimetre precision are left out.
                (ring[0] != ring[1] && ring[1] != ring[2] && ring[0] != ring[2])
                    .then(|| json!([ring]))
            })
            .collect();
        let mut v = json!({
            "type": "Building",
            "geometry": [{"type": "MultiSurface", "lod": "2", "boundaries": surfaces}],
        });
        if let Some(a) = attributes.get(&building).filter(|a| !a.is_empty()) {
            v["attributes"] = Value::Object(a.clone());
        }
        objects.insert(format!("building-{building}"), v);
    }
    out.document(objects, reference_system)
}

/// The vertices a written document uses, compressed with one transform and
/// deduplicated (the schema forbids duplicate vertices).
struct Vertices<'a> {
    transform: Transform,
    source: &'a [[f64; 3]],
    /// Source index → written index.
    map: HashMap<usize, usize>,
    /// Compressed position → written index.
    seen: HashMap<[i64; 3], usize>,
    out: Vec<[i64; 3]>,
}

impl<'a> Vertices<'a> {
    fn new(transform: Option<Transform>, source: &'a [[f64; 3]]) -> Self {
        let usable = transform.filter(|t| {
            t.scale.iter().all(|s| s.is_finite() && *s > 0.0)
                && t.translate.iter().all(|v| v.is_finite())
        });
        let transform = usable.unwrap_or_else(|| {
            let mut lo = [f64::INFINITY; 3];
            for p in source {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                }
            }
            Transform {
                scale: [0.001; 3],
                translate: lo.map(|v| if v.is_finite() { v.floor() } else { 0.0 }),
            }
        });
        Self {
            transform,
            source,
            map: HashMap::new(),
            seen: HashMap::new(),
            out: Vec::new(),
        }
    }

    /// The written index of source vertex `i` (`None` when out of range or
    /// not representable).
    fn index(&mut self, i: usize) -> Option<usize> {
        if let Some(&k) = self.map.get(&i) {
            return Some(k);
        }
        let p = self.source.get(i)?;
        let q = [0, 1, 2]
            .map(|k| ((p[k] - self.transform.translate[k]) / self.transform.scale[k]).round());
        if !q.iter().all(|v| v.is_finite() && v.abs() < 9.0e15) {
            return None;
        }
        let q = q.map(|v| v as i64);
        let k = *self.seen.entry(q).or_insert_with(|| {
            self.out.push(q);
            self.out.len() - 1
        });
        self.map.insert(i, k);
        Some(k)
    }

    fn document(self, objects: Map<String, Value>, crs: Option<&str>) -> Value {
        let mut metadata = Map::new();
        if let Some(extent) = self.extent() {
            metadata.insert("geographicalExtent".into(), json!(extent));
        }
        if let Some(c) = crs {
            metadata.insert("referenceSystem".into(), json!(crs_url(c)));
        }
        json!({
            "type": "CityJSON",
            "version": "2.0",
            "transform": {"scale": self.transform.scale, "translate": self.transform.translate},
            "metadata": metadata,
            "CityObjects": objects,
            "vertices": self.out,
        })
    }

    /// Min x, y, z then max x, y, z of the written vertices.
    fn extent(&self) -> Option<[f64; 6]> {
        let t = &self.transform;
        let mut e = [
            f64::INFINITY,
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ];
        for q in &self.out {
            for k in 0..3 {
                let v = q[k] as f64 * t.scale[k] + t.translate[k];
                e[k] = e[k].min(v);
                e[k + 3] = e[k + 3].max(v);
            }
        }
        e[0].is_finite().then_some(e)
    }
}
