//! The ray caster: a BVH over a scene's triangles, built once, queried by
//! single rays or by batches in parallel.

use rayon::prelude::*;

use super::bvh::{Bvh, PACKET};
use super::parry_mesh::ParryMesh;
use super::patches::{Patch, patches};
use super::ray::{Hit, Ray, cross, normalize, sub};
use super::triangle::PreparedRay;
use crate::scene::{ObjectKind, Scene, SceneCheckError, SceneObject};

/// Why a scene cannot be indexed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CasterError {
    /// The scene's arrays do not fit together (lengths, vertex or object indices).
    #[error("scene: {0}")]
    Scene(#[from] SceneCheckError),
    /// More triangles than 32-bit ids can name.
    #[error("scene has {0} triangles; at most 2^32 - 1 are supported")]
    TooManyTriangles(usize),
}

/// Which acceleration structure a [`Caster`] casts through.
///
/// Both give the same closest hits; the default is the faster on the
/// reference scene (`cargo bench -p skyground-core --bench lidar -- backend`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CastBackend {
    /// The hand-written 4-wide SAH BVH (`lidar::bvh`).
    #[default]
    Bvh,
    /// parry3d's `TriMesh` and its BVH.
    Parry,
}

/// The built index of one backend.
#[derive(Debug, Clone)]
enum Index {
    Bvh(Bvh),
    /// Boxed: parry's mesh carries a large inline header.
    Parry(Box<ParryMesh>),
}

impl Index {
    /// Triangle vertices and their scene ids, in the index's own order.
    fn triangles(&self) -> (&[[[f32; 3]; 3]], &[u32]) {
        match self {
            Index::Bvh(b) => (&b.tris, &b.ids),
            Index::Parry(p) => (&p.tris, &p.ids),
        }
    }
}

/// Casts rays against one scene.
///
/// Built once per scene ([`Caster::new`]); every query is read-only, so one
/// caster serves any number of threads. Triangles with zero area or
/// non-finite vertices are left out (no ray can hit them).
#[derive(Debug, Clone)]
pub struct Caster {
    index: Index,
    /// Unit normal of every indexed triangle, in the index's order.
    normals: Vec<[f32; 3]>,
    /// Object index of every input triangle.
    triangle_object: Vec<u32>,
    /// The scene's objects.
    objects: Vec<SceneObject>,
    /// Scene bounds of the indexed triangles.
    bounds: Option<([f32; 3], [f32; 3])>,
    /// Highest vertex of a ground triangle.
    ground_top: Option<f32>,
    /// The scene's origin.
    origin: [f64; 3],
}

impl Caster {
    /// Validates `scene` and builds the default backend's acceleration structure over it.
    pub fn new(scene: &Scene) -> Result<Self, CasterError> {
        Self::with_backend(scene, CastBackend::default())
    }

    /// [`Caster::new`] with the acceleration structure of `backend`.
    pub fn with_backend(scene: &Scene, backend: CastBackend) -> Result<Self, CasterError> {
        let n = scene.triangles.len();
        if n >= u32::MAX as usize {
            return Err(CasterError::TooManyTriangles(n));
        }
        scene.check_indices()?;
        let mut tris = Vec::with_capacity(n);
        let mut ids = Vec::with_capacity(n);
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        let mut ground_top: Option<f32> = None;
        for (t, (tri, &obj)) in scene
            .triangles
            .iter()
            .zip(&scene.triangle_object)
            .enumerate()
        {
            // Indices are in range: check_indices above.
            let v = tri.map(|i| scene.vertices[i as usize]);
            let finite = v.iter().flatten().all(|x| x.is_finite());
            let area2 = cross(sub(v[1], v[0]), sub(v[2], v[0]));
            if !finite || area2 == [0.0; 3] {
                continue;
            }
            for p in &v {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            if scene.objects[obj as usize].kind == ObjectKind::Ground {
                let top = v[0][2].max(v[1][2]).max(v[2][2]);
                ground_top = Some(ground_top.map_or(top, |g| g.max(top)));
            }
            tris.push(v);
            ids.push(t as u32);
        }
        let bounds = (!tris.is_empty()).then_some((lo, hi));
        let index = match backend {
            CastBackend::Bvh => Index::Bvh(Bvh::new(tris, ids)),
            CastBackend::Parry => Index::Parry(Box::new(ParryMesh::new(tris, ids))),
        };
        let normals = index.triangles().0.iter().map(normal_of).collect();
        Ok(Self {
            index,
            normals,
            triangle_object: scene.triangle_object.clone(),
            objects: scene.objects.clone(),
            bounds,
            ground_top,
            origin: scene.origin,
        })
    }

    /// Number of triangles indexed (the scene's minus degenerate ones).
    pub fn triangle_count(&self) -> usize {
        self.index.triangles().0.len()
    }

    /// The backend this caster was built with.
    pub fn backend(&self) -> CastBackend {
        match self.index {
            Index::Bvh(_) => CastBackend::Bvh,
            Index::Parry(_) => CastBackend::Parry,
        }
    }

    /// Bounds `(min, max)` of the indexed triangles; `None` for an empty scene.
    pub fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        self.bounds
    }

    /// Highest point of the scene's ground objects; `None` without ground.
    pub fn ground_top(&self) -> Option<f32> {
        self.ground_top
    }

    /// The parts of the scene whose buildings lie at least
    /// [`PATCH_GAP_M`](super::patches::PATCH_GAP_M) apart in plan (computed
    /// on each call: only an airborne survey asks).
    pub fn patches(&self) -> Vec<Patch> {
        let (tris, ids) = self.index.triangles();
        let kinds: Vec<ObjectKind> = ids
            .iter()
            .map(|&t| {
                let o = self.triangle_object[t as usize] as usize;
                self.objects[o].kind
            })
            .collect();
        patches(tris, &kinds)
    }

    /// The scene's origin (its local frame in the source coordinates).
    pub fn origin(&self) -> [f64; 3] {
        self.origin
    }

    /// The scene object with index `object` (as in [`Hit::object`]).
    pub fn object(&self, object: u32) -> Option<&SceneObject> {
        self.objects.get(object as usize)
    }

    /// Number of BVH nodes, leaves and the deepest leaf's depth; `None`
    /// for the parry backend (its tree is its own).
    pub fn bvh_shape(&self) -> Option<(usize, usize, usize)> {
        let Index::Bvh(b) = &self.index else {
            return None;
        };
        let s = b.stats();
        Some((s.nodes, s.leaves, s.depth))
    }

    /// The closest hit within `max_range` metres of `origin` along `dir`
    /// (normalized here; zero or non-finite input gives `None`).
    pub fn cast(&self, origin: [f32; 3], dir: [f32; 3], max_range: f32) -> Option<Hit> {
        self.cast_ray(&Ray::new(origin, dir, max_range))
    }

    /// [`Caster::cast`] for a [`Ray`].
    pub fn cast_ray(&self, ray: &Ray) -> Option<Hit> {
        let (t, i) = match &self.index {
            Index::Bvh(b) => b.closest(&prepare(ray)?, ray.max_t)?,
            Index::Parry(p) => {
                let dir = normalize(ray.dir)?;
                let ok = ray.origin.iter().all(|x| x.is_finite()) && ray.max_t > 0.0;
                if !ok {
                    return None;
                }
                p.closest(ray.origin, dir, ray.max_t)?
            }
        };
        Some(self.hit(t, i))
    }

    /// Casts every ray, in parallel on the current rayon pool; result `i`
    /// belongs to `rays[i]`, the same hit as [`Caster::cast_ray`] gives.
    /// Consecutive rays from one origin (a spinning sensor's columns) are
    /// traced together in packets of up to 64, which is several times
    /// faster than ray by ray; pass rays in a coherent order (neighbours in
    /// the slice point in similar directions).
    pub fn cast_many(&self, rays: &[Ray]) -> Vec<Option<Hit>> {
        let mut out = vec![None; rays.len()];
        out.par_chunks_mut(PACKET)
            .zip(rays.par_chunks(PACKET))
            .with_min_len(16)
            .for_each(|(out, rays)| self.cast_packet(rays, out));
        out
    }

    /// [`Caster::cast_many`] on the calling thread only.
    pub fn cast_many_serial(&self, rays: &[Ray]) -> Vec<Option<Hit>> {
        let mut out = vec![None; rays.len()];
        for (out, rays) in out.chunks_mut(PACKET).zip(rays.chunks(PACKET)) {
            self.cast_packet(rays, out);
        }
        out
    }

    /// [`Caster::cast_many`] ray by ray (no packets): the reference path
    /// for benchmarks and tests.
    pub fn cast_many_single(&self, rays: &[Ray]) -> Vec<Option<Hit>> {
        rays.par_iter()
            .with_min_len(1024)
            .map(|r| self.cast_ray(r))
            .collect()
    }

    /// Casts at most [`PACKET`] rays into `out` (result `i` for `rays[i]`),
    /// each run of equal origins as one packet.
    pub(crate) fn cast_packet(&self, rays: &[Ray], out: &mut [Option<Hit>]) {
        let Index::Bvh(bvh) = &self.index else {
            for (o, r) in out.iter_mut().zip(rays) {
                *o = self.cast_ray(r);
            }
            return;
        };
        let mut prepared = [PreparedRay::default(); PACKET];
        let mut t_max = [0.0f32; PACKET];
        let mut found = [None; PACKET];
        let mut start = 0;
        while start < rays.len() {
            let org = rays[start].origin;
            let len = rays[start..]
                .iter()
                .take_while(|r| r.origin == org)
                .count()
                .max(1);
            let run = &rays[start..start + len];
            if len < 4 {
                // Too few to share a walk: ray by ray is cheaper.
                for (o, r) in out[start..start + len].iter_mut().zip(run) {
                    *o = self.cast_ray(r);
                }
                start += len;
                continue;
            }
            for (k, r) in run.iter().enumerate() {
                // A ray that cannot hit anything gets range 0: the packet skips it.
                (prepared[k], t_max[k]) = match prepare(r) {
                    Some(p) => (p, r.max_t),
                    None => (PreparedRay::default(), 0.0),
                };
            }
            bvh.closest_packet(org, &prepared[..len], &t_max[..len], &mut found[..len]);
            for (o, f) in out[start..start + len].iter_mut().zip(&found[..len]) {
                *o = f.map(|(t, i)| self.hit(t, i));
            }
            start += len;
        }
    }

    /// The closest hit found by testing every triangle: slow, for checking
    /// [`Caster::cast_ray`].
    pub fn cast_brute_force(&self, ray: &Ray) -> Option<Hit> {
        let r = prepare(ray)?;
        let (tris, _) = self.index.triangles();
        let (t, i) = Bvh::closest_among(tris, &r, ray.max_t)?;
        Some(self.hit(t, i))
    }

    /// Builds the hit record for index-order triangle `i` at distance `t`.
    fn hit(&self, t: f32, i: usize) -> Hit {
        let triangle = self.index.triangles().1[i];
        Hit {
            t,
            triangle,
            object: self.triangle_object[triangle as usize],
            normal: self.normals[i],
        }
    }
}

/// Unit normal of a triangle by its winding (+z for a degenerate one).
fn normal_of(v: &[[f32; 3]; 3]) -> [f32; 3] {
    normalize(cross(sub(v[1], v[0]), sub(v[2], v[0]))).unwrap_or([0.0, 0.0, 1.0])
}

/// Normalizes and prepares a ray; `None` when it cannot hit anything.
fn prepare(ray: &Ray) -> Option<PreparedRay> {
    let dir = normalize(ray.dir)?;
    let ok = ray.origin.iter().all(|x| x.is_finite()) && ray.max_t > 0.0;
    ok.then(|| PreparedRay::new(ray.origin, dir))
}
