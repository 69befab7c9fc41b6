//! Ground truth: uniform samples on the visible building surfaces.
//!
//! Per building triangle, points of a square lattice (spacing `s`) laid in
//! the triangle's plane with a deterministic pseudo-random offset (a hash of
//! the triangle index) are kept when inside the triangle. The expected count
//! is exactly area / s² for any triangle shape, so the total is ≈ area / s².
//!
//! Left out:
//! - bottom faces: facing down (n_z ≤ −0.5) with their centroid within
//!   `bottom_tolerance` of the ground (the highest Ground triangle below, or
//!   the object's lowest point where no ground covers it);
//! - samples below the ground (+ `ground_clearance`), e.g. walls sunk into
//!   sloped terrain;
//! - samples on or inside another building object (within
//!   `contact_tolerance` of its surface, or winding number > ½): shared party
//!   walls, a tower's foot on a podium, overlapping BuildingParts.
//!
//! Kinds by the face normal: n_z ≥ 0.5 roof, otherwise wall (undersides of
//! raised floors and overhangs, n_z ≤ −0.5 away from the ground, count as walls:
//! like facades, they are seen from the side or below, not from the air).

use std::io::Write;

use rayon::prelude::*;

use super::ground_height::GroundHeight;
use super::triangle_grid::TriangleGrid;
use super::winding::winding_number;
use crate::cloud::{Cloud, PlyError, write_ply};
use crate::rng::mix;
use crate::scene::vec3::{add, area_vector, cross, dot, narrow, norm, scale, sub, wide};
use crate::scene::{ObjectKind, Scene};

/// Default sample spacing, metres.
pub const DEFAULT_SPACING: f32 = 0.25;

/// What part of a building a sample lies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum SurfaceKind {
    /// Facades (|n_z| < 0.5) and undersides (n_z ≤ −0.5).
    Wall,
    /// Roofs (n_z ≥ 0.5).
    Roof,
}

impl SurfaceKind {
    /// The kind of a face with unit normal z component `nz`.
    pub fn from_normal_z(nz: f64) -> Self {
        if nz >= 0.5 { Self::Roof } else { Self::Wall }
    }

    /// The code written to files: 0 wall, 1 roof.
    pub fn code(self) -> u8 {
        match self {
            Self::Wall => 0,
            Self::Roof => 1,
        }
    }
}

/// How ground truth is sampled (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GtOptions {
    /// Lattice spacing, metres (values below 1 mm are raised to 1 mm).
    pub spacing: f32,
    /// Downward faces this close to the ground are bottoms, metres.
    pub bottom_tolerance: f32,
    /// Samples less than this above the ground are dropped, metres.
    pub ground_clearance: f32,
    /// Samples this close to another building object are dropped, metres.
    pub contact_tolerance: f32,
}

impl Default for GtOptions {
    fn default() -> Self {
        Self {
            spacing: DEFAULT_SPACING,
            bottom_tolerance: 0.5,
            ground_clearance: 0.05,
            contact_tolerance: 0.05,
        }
    }
}

/// Ground-truth samples, structure-of-arrays (one entry per sample in each).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GtSamples {
    /// Positions in the scene's local frame.
    pub xyz: Vec<[f32; 3]>,
    /// Unit outward normal of the face sampled.
    pub normal: Vec<[f32; 3]>,
    /// Building id.
    pub building: Vec<u32>,
    /// Wall or roof.
    pub kind: Vec<SurfaceKind>,
    /// The lattice spacing used, metres.
    pub spacing: f32,
    /// The scene's origin (source coordinates of the local frame).
    pub origin: [f64; 3],
}

impl GtSamples {
    /// Positions of building `id`'s samples.
    pub fn of_building(&self, id: u32) -> Vec<[f32; 3]> {
        crate::cloud::positions_where(&self.xyz, &self.building, id)
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.xyz.len()
    }

    /// True when there are no samples.
    pub fn is_empty(&self) -> bool {
        self.xyz.is_empty()
    }

    /// The samples as a cloud: `building` = building id, `label` = kind code
    /// (0 wall, 1 roof), origin kept.
    pub fn to_cloud(&self) -> Cloud {
        Cloud {
            xyz: self.xyz.clone(),
            intensity: None,
            label: Some(self.kind.iter().map(|k| k.code()).collect()),
            building: Some(self.building.clone()),
            return_number: None,
            number_of_returns: None,
            origin: self.origin,
            crs: None,
        }
    }

    /// Writes the samples as binary PLY via [`write_ply`]: the kind code
    /// (0 wall, 1 roof) in the label column (PLY property `classification`),
    /// the building id in `building`.
    pub fn write_ply<W: Write>(&self, writer: W) -> Result<(), PlyError> {
        write_ply(writer, &self.to_cloud())
    }
}

/// Samples building walls and roofs of `scene` at `spacing` (default
/// options otherwise).
pub fn sample_building_surfaces(scene: &Scene, spacing: f32) -> GtSamples {
    sample_building_surfaces_with(
        scene,
        &GtOptions {
            spacing,
            ..GtOptions::default()
        },
    )
}

/// One building triangle to sample.
struct Face {
    index: usize,
    object: u32,
    building: u32,
    corners: [[f64; 3]; 3],
}

/// One building object as a solid: its bounds and triangles.
#[derive(Clone)]
struct Solid {
    lo: [f64; 3],
    hi: [f64; 3],
    tris: Vec<[[f64; 3]; 3]>,
}

/// One sample: position, normal, building id, kind.
type Sample = ([f32; 3], [f32; 3], u32, SurfaceKind);

/// Everything the per-triangle sampler looks things up in.
struct Context {
    ground: GroundHeight,
    grid: TriangleGrid,
    /// Per object (`None` for non-buildings).
    solids: Vec<Option<Solid>>,
    spacing: f64,
    options: GtOptions,
}

/// Samples building walls and roofs of `scene` with `options`.
pub fn sample_building_surfaces_with(scene: &Scene, options: &GtOptions) -> GtSamples {
    let spacing = if options.spacing.is_finite() {
        options.spacing.max(1e-3)
    } else {
        DEFAULT_SPACING
    };
    let faces: Vec<Face> = (0..scene.triangles.len())
        .filter_map(|t| {
            let object = *scene.triangle_object.get(t)?;
            let o = scene.objects.get(object as usize)?;
            (o.kind == ObjectKind::Building).then_some(())?;
            let corners = scene.triangle_corners(t)?.map(wide);
            corners
                .iter()
                .flatten()
                .all(|v| v.is_finite())
                .then_some(Face {
                    index: t,
                    object,
                    building: o.building,
                    corners,
                })
        })
        .collect();
    let mut solids: Vec<Option<Solid>> = vec![None; scene.objects.len()];
    for f in &faces {
        let solid = solids[f.object as usize].get_or_insert_with(|| Solid {
            lo: [f64::INFINITY; 3],
            hi: [f64::NEG_INFINITY; 3],
            tris: Vec::new(),
        });
        for p in &f.corners {
            for (k, v) in p.iter().enumerate() {
                solid.lo[k] = solid.lo[k].min(*v);
                solid.hi[k] = solid.hi[k].max(*v);
            }
        }
        solid.tris.push(f.corners);
    }
    let ctx = Context {
        ground: GroundHeight::new(scene),
        grid: TriangleGrid::new(
            faces.iter().map(|f| f.corners).collect(),
            faces.iter().map(|f| f.object).collect(),
        ),
        solids,
        spacing: f64::from(spacing),
        options: *options,
    };
    let per_face: Vec<Vec<Sample>> = faces.par_iter().map(|f| sample_face(&ctx, f)).collect();
    let total = per_face.iter().map(Vec::len).sum();
    let mut out = GtSamples {
        xyz: Vec::with_capacity(total),
        normal: Vec::with_capacity(total),
        building: Vec::with_capacity(total),
        kind: Vec::with_capacity(total),
        spacing,
        origin: scene.origin,
    };
    for (p, n, b, k) in per_face.into_iter().flatten() {
        out.xyz.push(p);
        out.normal.push(n);
        out.building.push(b);
        out.kind.push(k);
    }
    out
}

fn sample_face(ctx: &Context, f: &Face) -> Vec<Sample> {
    let [a, b, c] = f.corners;
    let av = area_vector(a, b, c);
    let len = norm(av);
    if len < 1e-12 {
        return Vec::new();
    }
    let n = scale(av, 1.0 / len);
    let centroid = scale(add(add(a, b), c), 1.0 / 3.0);
    let opt = &ctx.options;
    if n[2] <= -0.5 {
        let own_min = ctx.solids[f.object as usize]
            .as_ref()
            .map_or(centroid[2], |s| s.lo[2]);
        let floor = ctx.ground.at(centroid[0], centroid[1]).unwrap_or(own_min);
        if centroid[2] - floor <= f64::from(opt.bottom_tolerance) {
            return Vec::new();
        }
    }
    let kind = SurfaceKind::from_normal_z(n[2]);
    let tol = f64::from(opt.contact_tolerance);
    let (lo, hi) = bounds(&f.corners, tol);
    let others: Vec<u32> = ctx
        .solids
        .iter()
        .enumerate()
        .filter(|(o, s)| {
            *o != f.object as usize
                && s.as_ref()
                    .is_some_and(|s| overlaps(lo, hi, s.lo, s.hi, tol))
        })
        .map(|(o, _)| u32::try_from(o).unwrap_or(u32::MAX))
        .collect();
    let normal = narrow(n);
    let mut out = Vec::new();
    for p in lattice_points(f.index, &f.corners, n, ctx.spacing) {
        if let Some(g) = ctx.ground.at(p[0], p[1])
            && p[2] < g + f64::from(opt.ground_clearance)
        {
            continue;
        }
        if !others.is_empty() && buried(ctx, f.object, &others, p, tol) {
            continue;
        }
        out.push((narrow(p), normal, f.building, kind));
    }
    out
}

/// On or inside another building object.
fn buried(ctx: &Context, own: u32, others: &[u32], p: [f64; 3], tol: f64) -> bool {
    if ctx.grid.nearest(p, tol, |o| o != own).is_some() {
        return true;
    }
    others.iter().any(|&o| {
        ctx.solids[o as usize]
            .as_ref()
            .is_some_and(|s| overlaps(p, p, s.lo, s.hi, tol) && winding_number(p, &s.tris) > 0.5)
    })
}

/// Lattice points inside triangle `t` (unit normal `n`), offset by a hash of `index`.
fn lattice_points(index: usize, t: &[[f64; 3]; 3], n: [f64; 3], s: f64) -> Vec<[f64; 3]> {
    let [a, b, c] = *t;
    let e1 = sub(b, a);
    let l1 = norm(e1);
    if l1 <= 0.0 {
        return Vec::new();
    }
    let u = scale(e1, 1.0 / l1);
    let v = cross(n, u);
    let (cx, cy) = (dot(sub(c, a), u), dot(sub(c, a), v));
    if cy <= 0.0 {
        return Vec::new();
    }
    let h = mix(0x6774_5EED ^ index as u64);
    let sx = s * ((h >> 40) as f64 / (1u64 << 24) as f64);
    let sy = s * (((h >> 16) & 0xFF_FFFF) as f64 / (1u64 << 24) as f64);
    let (x0, x1) = (0.0_f64.min(cx), l1.max(cx));
    let first = |lo: f64, shift: f64| ((lo - shift) / s).ceil() as i64;
    let mut out = Vec::new();
    for j in first(0.0, sy)..=((cy - sy) / s).floor() as i64 {
        let y = sy + j as f64 * s;
        for i in first(x0, sx)..=((x1 - sx) / s).floor() as i64 {
            let x = sx + i as f64 * s;
            // Inside: above AB (y ≥ 0), left of BC and of CA.
            let bc = (cx - l1) * y - cy * (x - l1);
            let ca = -cx * (y - cy) + cy * (x - cx);
            if y >= 0.0 && bc >= 0.0 && ca >= 0.0 {
                out.push(add(a, add(scale(u, x), scale(v, y))));
            }
        }
    }
    out
}

fn bounds(t: &[[f64; 3]; 3], pad: f64) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in t {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k] - pad);
            hi[k] = hi[k].max(p[k] + pad);
        }
    }
    (lo, hi)
}

fn overlaps(alo: [f64; 3], ahi: [f64; 3], blo: [f64; 3], bhi: [f64; 3], pad: f64) -> bool {
    (0..3).all(|k| alo[k] <= bhi[k] + pad && blo[k] - pad <= ahi[k])
}
