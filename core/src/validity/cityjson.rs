//! A CityJSON Solid's `boundaries` (shells → surfaces → rings → indices) as a
//! [`Solid`], so the checks run on real files.

use super::{Solid, Surface};
use serde_json::Value;
use std::collections::HashMap;

/// The Solid `geometry` (a CityJSON geometry object of type `Solid`) over the
/// file's real `vertices` (transform applied); `None` for another type, a
/// malformed `boundaries` or an index out of range. Only the vertices the solid
/// uses are kept, renumbered.
pub fn from_cityjson_geometry(geometry: &Value, vertices: &[[f64; 3]]) -> Option<Solid> {
    if geometry.get("type")?.as_str()? != "Solid" {
        return None;
    }
    solid(geometry.get("boundaries")?, vertices)
}

/// Each member of a `Solid`, `MultiSolid` or `CompositeSolid` geometry, in
/// order; empty for another type or a malformed `boundaries`.
pub fn solids_from_cityjson_geometry(geometry: &Value, vertices: &[[f64; 3]]) -> Vec<Solid> {
    let kind = geometry.get("type").and_then(Value::as_str);
    let Some(boundaries) = geometry.get("boundaries") else {
        return Vec::new();
    };
    match kind {
        Some("Solid") => solid(boundaries, vertices).into_iter().collect(),
        Some("MultiSolid" | "CompositeSolid") => boundaries
            .as_array()
            .map(|members| {
                members
                    .iter()
                    .map(|m| solid(m, vertices))
                    .collect::<Option<Vec<_>>>()
                    .unwrap_or_default()
            })
            .unwrap_or_default(),
        _ => Vec::new(),
    }
}

/// One solid's boundaries: an array of shells.
fn solid(boundaries: &Value, vertices: &[[f64; 3]]) -> Option<Solid> {
    let mut renumber: HashMap<usize, usize> = HashMap::new();
    let mut kept = Vec::new();
    let mut index = |i: &Value| -> Option<usize> {
        let i = usize::try_from(i.as_u64()?).ok()?;
        let p = *vertices.get(i)?;
        Some(*renumber.entry(i).or_insert_with(|| {
            kept.push(p);
            kept.len() - 1
        }))
    };
    let mut shells = Vec::new();
    for shell in boundaries.as_array()? {
        let mut surfaces = Vec::new();
        for surface in shell.as_array()? {
            let mut rings: Surface = Vec::new();
            for ring in surface.as_array()? {
                let r: Option<Vec<usize>> = ring.as_array()?.iter().map(&mut index).collect();
                rings.push(r?);
            }
            surfaces.push(rings);
        }
        shells.push(surfaces);
    }
    Some(Solid {
        vertices: kept,
        shells,
    })
}
