//! Cutting one cluster of buildings out of a large scene (a city-wide model
//! whose ground graph or airborne survey would be too large as a whole).
//!
//! - A building (all objects sharing its id) is kept whole when the centre
//!   of its xy bounding box lies in the window; it is never cut.
//! - Vegetation objects are kept whole the same way.
//! - Ground triangles are clipped to the window grown to hold the kept
//!   buildings' boxes ([`Cropped::extent`]), so every kept wall stands on
//!   ground even where it reaches over the window's edge. Where the source
//!   ground leaves holes in the extent (a CityJSON scene's ground is a patch
//!   per building), the ground is one grid over the extent instead
//!   ([`fill`]): the vehicle can drive between all kept buildings.
//! - The local frame and origin stay those of the source scene; building ids
//!   go 1.. in the order of the source ids.
//!
//! [`busiest_window`] chooses a window of a given size automatically.

mod busiest;
mod clip;
mod error;
mod fill;
mod window;

use std::collections::{BTreeMap, HashMap};

pub use busiest::busiest_window;
pub use error::CropError;
pub use window::Window;

use super::{MeshPart, ObjectKind, Scene, SceneObject};

/// One building of a scene: its xy box and surface area.
#[derive(Debug, Clone, PartialEq)]
pub struct BuildingBox {
    /// Building id in the scene.
    pub id: u32,
    /// Name of its first object.
    pub name: String,
    /// The xy bounding box of its triangles.
    pub xy: Window,
    /// Its lowest z.
    pub base: f64,
    /// Its surface area (walls, roofs, floors), m².
    pub area: f64,
}

/// Every building's xy box and surface area, by ascending id.
pub fn building_boxes(scene: &Scene) -> Vec<BuildingBox> {
    let mut out: BTreeMap<u32, BuildingBox> = BTreeMap::new();
    for t in 0..scene.triangles.len() {
        let (Some(o), Some(corners)) = (scene.triangle_kind(t), scene.triangle_corners(t)) else {
            continue;
        };
        if o.kind != ObjectKind::Building {
            continue;
        }
        let area = scene.triangle_area(t);
        let b = out.entry(o.building).or_insert_with(|| BuildingBox {
            id: o.building,
            name: o.name.clone(),
            xy: NO_BOX,
            base: f64::INFINITY,
            area: 0.0,
        });
        b.area += area;
        for p in corners {
            grow(&mut b.xy, f64::from(p[0]), f64::from(p[1]));
            b.base = b.base.min(f64::from(p[2]));
        }
    }
    out.into_values().collect()
}

/// The box nothing has grown yet (min +∞, max −∞): [`grow`] starts from it.
const NO_BOX: Window = Window {
    min: [f64::INFINITY; 2],
    max: [f64::NEG_INFINITY; 2],
};

/// Grows box `w` to hold `(x, y)`.
fn grow(w: &mut Window, x: f64, y: f64) {
    w.min = [w.min[0].min(x), w.min[1].min(y)];
    w.max = [w.max[0].max(x), w.max[1].max(y)];
}

/// A building kept by a crop.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct KeptBuilding {
    /// Its id in the source scene.
    pub source_id: u32,
    /// Its id in the cropped scene.
    pub id: u32,
    /// Name of its first object.
    pub name: String,
}

/// A cropped scene and what it kept.
#[derive(Debug, Clone, PartialEq)]
pub struct Cropped {
    /// The scene: same frame and origin as the source.
    pub scene: Scene,
    /// The window asked for.
    pub window: Window,
    /// The window grown to hold the kept buildings whole: ground is clipped to it.
    pub extent: Window,
    /// The buildings kept, by new id.
    pub buildings: Vec<KeptBuilding>,
    /// The ground was rebuilt as one grid over the extent (the source's had holes there).
    pub ground_filled: bool,
    /// Buildings in the source scene.
    pub buildings_total: usize,
}

/// The part of `scene` in `window` (see the module's rules).
pub fn crop_scene(scene: &Scene, window: &Window) -> Result<Cropped, CropError> {
    let boxes = building_boxes(scene);
    let centres =
        box_of(boxes.iter().map(|b| b.xy.centre())).ok_or(CropError::NoBuildingsInScene)?;
    let kept: Vec<&BuildingBox> = boxes
        .iter()
        .filter(|b| {
            let c = b.xy.centre();
            window.contains(c[0], c[1])
        })
        .collect();
    if kept.is_empty() {
        return Err(CropError::EmptyWindow {
            window: *window,
            buildings: centres,
        });
    }
    let extent = kept.iter().fold(*window, |w, b| w.union(&b.xy));
    let new_id: HashMap<u32, u32> = kept.iter().zip(1u32..).map(|(b, id)| (b.id, id)).collect();
    let object_centre = object_centres(scene);

    let mut out = Scene {
        origin: scene.origin,
        ..Scene::default()
    };
    // Old object index → new one, for objects that kept any triangle.
    let mut objects: HashMap<u32, u32> = HashMap::new();
    let mut whole: HashMap<u32, u32> = HashMap::new();
    // Clipped ground pieces, by source object, added once the fill is decided.
    let mut ground: Vec<(u32, Vec<[f64; 3]>)> = Vec::new();
    for t in 0..scene.triangles.len() {
        let (Some(o), Some(corners)) = (scene.triangle_kind(t), scene.triangle_corners(t)) else {
            continue;
        };
        let object = scene.triangle_object[t];
        let keep_whole = match o.kind {
            ObjectKind::Building => new_id.contains_key(&o.building),
            ObjectKind::Vegetation => object_centre
                .get(&object)
                .is_some_and(|c| window.contains(c[0], c[1])),
            ObjectKind::Ground => false,
        };
        if !keep_whole {
            if o.kind == ObjectKind::Ground {
                let polygon = clip::clip_triangle(corners.map(super::vec3::wide), &extent);
                if !polygon.is_empty() {
                    ground.push((object, polygon));
                }
            }
            continue;
        }
        let tri = scene.triangles[t];
        let ids = [0, 1, 2].map(|k| {
            *whole
                .entry(tri[k])
                .or_insert_with(|| push(&mut out, corners[k]))
        });
        let index = object_index(&mut out, &mut objects, scene, object, &new_id);
        out.triangles.push(ids);
        out.triangle_object.push(index);
    }
    let pieces: Vec<[[f64; 3]; 3]> = ground
        .iter()
        .flat_map(|(_, poly)| clip::fan(poly).into_iter().map(|f| f.map(|k| poly[k])))
        .collect();
    let bases: Vec<fill::Base> = kept
        .iter()
        .map(|b| fill::Base {
            xy: b.xy,
            z: b.base,
        })
        .collect();
    let filled = fill::fill_ground(&pieces, &bases, &extent);
    let ground_filled = filled.is_some();
    if let Some(MeshPart {
        vertices,
        triangles,
    }) = filled
    {
        let index = u32::try_from(out.objects.len()).unwrap_or(u32::MAX);
        out.objects.push(SceneObject {
            name: "terrain".into(),
            kind: ObjectKind::Ground,
            building: 0,
        });
        let base = u32::try_from(out.vertices.len()).unwrap_or(u32::MAX);
        out.vertices
            .extend(vertices.iter().map(|p| super::vec3::narrow(*p)));
        for t in triangles {
            out.triangles.push(t.map(|v| v + base));
            out.triangle_object.push(index);
        }
    } else {
        let mut shared: HashMap<[u32; 3], u32> = HashMap::new();
        for (object, poly) in &ground {
            let ids: Vec<u32> = poly
                .iter()
                .map(|p| {
                    let q = super::vec3::narrow(*p);
                    *shared
                        .entry(q.map(f32::to_bits))
                        .or_insert_with(|| push(&mut out, q))
                })
                .collect();
            let index = object_index(&mut out, &mut objects, scene, *object, &new_id);
            for f in clip::fan(poly) {
                out.triangles.push(f.map(|k| ids[k]));
                out.triangle_object.push(index);
            }
        }
    }
    Ok(Cropped {
        scene: out,
        window: *window,
        extent,
        buildings: kept
            .iter()
            .map(|b| KeptBuilding {
                source_id: b.id,
                id: new_id.get(&b.id).copied().unwrap_or(0),
                name: b.name.clone(),
            })
            .collect(),
        ground_filled,
        buildings_total: boxes.len(),
    })
}

/// The cropped scene's index of source object `object`, added on first use.
fn object_index(
    out: &mut Scene,
    objects: &mut HashMap<u32, u32>,
    scene: &Scene,
    object: u32,
    new_id: &HashMap<u32, u32>,
) -> u32 {
    *objects.entry(object).or_insert_with(|| {
        let o = scene
            .objects
            .get(object as usize)
            .cloned()
            .unwrap_or(SceneObject {
                name: String::new(),
                kind: ObjectKind::Ground,
                building: 0,
            });
        out.objects.push(SceneObject {
            building: new_id.get(&o.building).copied().unwrap_or(0),
            ..o
        });
        u32::try_from(out.objects.len() - 1).unwrap_or(u32::MAX)
    })
}

fn push(scene: &mut Scene, p: [f32; 3]) -> u32 {
    scene.vertices.push(p);
    u32::try_from(scene.vertices.len() - 1).unwrap_or(u32::MAX)
}

/// The xy box of `points`; `None` without any.
fn box_of(points: impl IntoIterator<Item = [f64; 2]>) -> Option<Window> {
    let mut w = NO_BOX;
    for c in points {
        grow(&mut w, c[0], c[1]);
    }
    (w.min[0] <= w.max[0]).then_some(w)
}

/// The centre of every object's xy bounding box, by object index.
fn object_centres(scene: &Scene) -> HashMap<u32, [f64; 2]> {
    let mut boxes: HashMap<u32, Window> = HashMap::new();
    for (t, &object) in scene.triangle_object.iter().enumerate() {
        for p in scene.triangle_corners(t).into_iter().flatten() {
            let w = boxes.entry(object).or_insert(NO_BOX);
            grow(w, f64::from(p[0]), f64::from(p[1]));
        }
    }
    boxes.into_iter().map(|(o, w)| (o, w.centre())).collect()
}

#[cfg(test)]
mod tests;
