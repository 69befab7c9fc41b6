//! Turning loaded vertices (source coordinates, `f64`) and named groups of
//! indexed triangles into a [`Scene`] in a local frame.

use std::collections::HashMap;

use super::builder::{MeshPart, SceneBuilder};
use super::{ObjectKind, Scene};
use crate::cloud::origin::{local_origin, to_local};

/// One loaded object: triangles index the file's vertex list.
#[derive(Debug, Clone, PartialEq)]
pub struct IndexedObject {
    /// Object name.
    pub name: String,
    /// Its kind.
    pub kind: ObjectKind,
    /// Triangles (indices into the file's vertices, already range-checked).
    pub triangles: Vec<[u32; 3]>,
    /// Building objects with the same group are parts of one building (one id).
    pub group: usize,
}

/// Builds a scene: objects without triangles are dropped, each object gets
/// its own copy of the vertices it uses, buildings get ids 1.. in order of
/// their group's first object with triangles (parts share their group's), and
/// the origin follows [`crate::cloud::origin`] for the lowest used vertex.
///
/// `None` when no object has triangles; `Some(Err(v))` when used vertex `v`
/// does not fit the local frame.
pub fn scene_from_indexed(
    vertices: &[[f64; 3]],
    objects: &[IndexedObject],
) -> Option<Result<Scene, usize>> {
    let used: Vec<&IndexedObject> = objects.iter().filter(|o| !o.triangles.is_empty()).collect();
    if used.is_empty() {
        return None;
    }
    let mut parts: Vec<(MeshPart, Vec<usize>)> = Vec::with_capacity(used.len());
    let mut lo = [f64::INFINITY; 3];
    for o in &used {
        let mut part = MeshPart::default();
        let mut source = Vec::new();
        let mut local: HashMap<u32, u32> = HashMap::new();
        for t in &o.triangles {
            let t = t.map(|i| {
                *local.entry(i).or_insert_with(|| {
                    let p = vertices.get(i as usize).copied().unwrap_or([f64::NAN; 3]);
                    for k in 0..3 {
                        lo[k] = lo[k].min(p[k]);
                    }
                    part.vertices.push(p);
                    source.push(i as usize);
                    u32::try_from(part.vertices.len() - 1).unwrap_or(u32::MAX)
                })
            });
            part.triangles.push(t);
        }
        parts.push((part, source));
    }
    let origin = local_origin(lo);
    let mut b = SceneBuilder::new(origin);
    let mut ids: HashMap<usize, u32> = HashMap::new();
    for (o, (mut part, source)) in used.iter().zip(parts) {
        for (p, &src) in part.vertices.iter_mut().zip(&source) {
            match localize(*p, origin) {
                Some(q) => *p = q,
                None => return Some(Err(src)),
            }
        }
        let id = if o.kind == ObjectKind::Building {
            let next = u32::try_from(ids.len() + 1).unwrap_or(u32::MAX);
            *ids.entry(o.group).or_insert(next)
        } else {
            0
        };
        b.add(o.name.clone(), o.kind, id, &part);
    }
    Some(Ok(b.finish()))
}

/// `p - origin`, or `None` when a coordinate is not finite or does not fit `f32`.
pub fn localize(p: [f64; 3], origin: [f64; 3]) -> Option<[f64; 3]> {
    let mut out = [0.0; 3];
    for k in 0..3 {
        to_local(p[k], origin[k])?;
        out[k] = p[k] - origin[k];
    }
    Some(out)
}
