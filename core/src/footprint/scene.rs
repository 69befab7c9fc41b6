//! The true footprints of a scene: per building id, the union of the xy
//! projections of its triangles (walls project to lines and add nothing;
//! roofs, overhangs and slabs on pillars all count).

use std::collections::BTreeMap;

use geo::{Coord, LineString, Polygon};
use rayon::prelude::*;

use super::types::Footprint;
use crate::scene::{ObjectKind, Scene};

/// Projected triangles with a smaller area (m²) are vertical or degenerate.
const MIN_PROJECTED_AREA: f64 = 1e-6;

/// One footprint per building id of `scene` (sorted by id), in the scene's
/// local frame; named after the building's first object.
pub fn footprints_of_scene(scene: &Scene) -> Vec<Footprint> {
    let mut tris: BTreeMap<u32, (String, Vec<Polygon<f64>>)> = BTreeMap::new();
    for (t, &o) in scene.triangles.iter().zip(&scene.triangle_object) {
        let Some(obj) = scene.objects.get(o as usize) else {
            continue;
        };
        if obj.kind != ObjectKind::Building || obj.building == 0 {
            continue;
        }
        let Some(p) = projected(scene, t) else {
            continue;
        };
        tris.entry(obj.building)
            .or_insert_with(|| (obj.name.clone(), Vec::new()))
            .1
            .push(p);
    }
    tris.into_iter()
        .collect::<Vec<_>>()
        .into_par_iter()
        .filter_map(|(id, (name, polys))| Footprint::from_parts(id, name, &polys))
        .collect()
}

/// The triangle's xy projection, `None` when (nearly) vertical or out of range.
fn projected(scene: &Scene, t: &[u32; 3]) -> Option<Polygon<f64>> {
    let mut c = [Coord { x: 0.0, y: 0.0 }; 3];
    for (slot, &i) in c.iter_mut().zip(t) {
        let v = scene.vertices.get(i as usize)?;
        *slot = Coord {
            x: f64::from(v[0]),
            y: f64::from(v[1]),
        };
    }
    let cross = (c[1].x - c[0].x) * (c[2].y - c[0].y) - (c[2].x - c[0].x) * (c[1].y - c[0].y);
    // NaN fails this test too.
    if cross.abs() / 2.0 <= MIN_PROJECTED_AREA || cross.is_nan() {
        return None;
    }
    Some(Polygon::new(LineString::new(c.to_vec()), vec![]))
}
