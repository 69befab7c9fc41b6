//! Read-only summaries of a [`Scene`]: bounds, counts, per-object triangles.

use std::collections::BTreeSet;

use super::vec3::{area_vector, norm, wide};
use super::{ObjectKind, Scene};

impl Scene {
    /// The three corners of triangle `t`, or `None` when `t` or one of its
    /// vertex indices is out of range.
    pub fn triangle_corners(&self, t: usize) -> Option<[[f32; 3]; 3]> {
        let tri = self.triangles.get(t)?;
        Some([
            *self.vertices.get(tri[0] as usize)?,
            *self.vertices.get(tri[1] as usize)?,
            *self.vertices.get(tri[2] as usize)?,
        ])
    }

    /// The object triangle `t` belongs to, when both exist.
    pub fn triangle_kind(&self, t: usize) -> Option<&super::SceneObject> {
        self.objects.get(*self.triangle_object.get(t)? as usize)
    }

    /// Indices of the triangles of object `object`.
    pub fn object_triangles(&self, object: u32) -> impl Iterator<Item = usize> + '_ {
        self.triangle_object
            .iter()
            .enumerate()
            .filter(move |(_, o)| **o == object)
            .map(|(t, _)| t)
    }

    /// The distinct building ids of building objects, ascending.
    pub fn building_ids(&self) -> Vec<u32> {
        let ids: BTreeSet<u32> = self
            .objects
            .iter()
            .filter(|o| o.kind == ObjectKind::Building)
            .map(|o| o.building)
            .collect();
        ids.into_iter().collect()
    }

    /// Number of distinct buildings (parts of one building count once).
    pub fn building_count(&self) -> usize {
        self.building_ids().len()
    }

    /// Number of objects of `kind`.
    pub fn object_count(&self, kind: ObjectKind) -> usize {
        self.objects.iter().filter(|o| o.kind == kind).count()
    }

    /// Axis-aligned bounds `(min, max)` of the vertices used by triangles of
    /// objects whose kind passes `keep`, or `None` when there are none.
    pub fn bounds_of(&self, keep: impl Fn(ObjectKind) -> bool) -> Option<([f32; 3], [f32; 3])> {
        let mut out: Option<([f32; 3], [f32; 3])> = None;
        for t in 0..self.triangles.len() {
            if !self.triangle_kind(t).is_some_and(|o| keep(o.kind)) {
                continue;
            }
            for p in self.triangle_corners(t).into_iter().flatten() {
                let (lo, hi) = out.get_or_insert((p, p));
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
        }
        out
    }

    /// Axis-aligned bounds of all triangles, or `None` for an empty scene.
    pub fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        self.bounds_of(|_| true)
    }

    /// Area of triangle `t` in m² (0 when it does not exist).
    pub fn triangle_area(&self, t: usize) -> f64 {
        self.triangle_corners(t).map_or(0.0, |[a, b, c]| {
            norm(area_vector(wide(a), wide(b), wide(c))) / 2.0
        })
    }
}
