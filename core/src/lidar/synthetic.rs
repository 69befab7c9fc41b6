//! Synthetic scenes for tests and benchmarks: boxes on a plane, and a dense
//! city-like scene of any size.

use crate::rng::Rng;
use crate::scene::{ObjectKind, Scene, SceneObject};

/// Builds a [`Scene`] object by object.
#[derive(Debug, Clone, Default)]
pub struct SyntheticBuilder {
    scene: Scene,
}

impl SyntheticBuilder {
    /// An empty scene with origin zero.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds an object; returns its index (for the `add_*` calls). Buildings
    /// are numbered 1, 2, … in the order they are added.
    pub fn object(&mut self, name: &str, kind: ObjectKind) -> u32 {
        let building = match kind {
            ObjectKind::Building => {
                1 + self
                    .scene
                    .objects
                    .iter()
                    .filter(|o| o.kind == ObjectKind::Building)
                    .count() as u32
            }
            _ => 0,
        };
        self.scene.objects.push(SceneObject {
            name: name.to_owned(),
            kind,
            building,
        });
        (self.scene.objects.len() - 1) as u32
    }

    /// Adds one triangle to `object`.
    pub fn triangle(&mut self, object: u32, v: [[f32; 3]; 3]) {
        let base = self.scene.vertices.len() as u32;
        self.scene.vertices.extend_from_slice(&v);
        self.scene.triangles.push([base, base + 1, base + 2]);
        self.scene.triangle_object.push(object);
    }

    /// Adds a closed axis-aligned box from `lo` to `hi` to `object`, faces
    /// split into cells of at most `cell` metres (`f32::INFINITY`: 12
    /// triangles), wound outward.
    pub fn add_box(&mut self, object: u32, lo: [f32; 3], hi: [f32; 3], cell: f32) {
        let coords: [Vec<f32>; 3] = std::array::from_fn(|k| ticks(lo[k], hi[k], cell));
        for axis in 0..3 {
            let (au, av) = ((axis + 1) % 3, (axis + 2) % 3);
            for (value, outward) in [(lo[axis], -1.0f32), (hi[axis], 1.0)] {
                let mut n = [0.0; 3];
                n[axis] = outward;
                self.add_face(object, axis, value, (au, &coords[au]), (av, &coords[av]), n);
            }
        }
    }

    /// Adds a height-field grid over `[lo, hi]` in x and y with `cells`
    /// cells per side, z from `height(x, y)`, wound upward.
    pub fn add_terrain(
        &mut self,
        object: u32,
        lo: [f32; 2],
        hi: [f32; 2],
        cells: usize,
        height: impl Fn(f32, f32) -> f32,
    ) {
        let cells = cells.max(1);
        let xs = ticks_n(lo[0], hi[0], cells);
        let ys = ticks_n(lo[1], hi[1], cells);
        let base = self.scene.vertices.len() as u32;
        for &y in &ys {
            for &x in &xs {
                self.scene.vertices.push([x, y, height(x, y)]);
            }
        }
        let w = (cells + 1) as u32;
        for j in 0..cells as u32 {
            for i in 0..cells as u32 {
                let a = base + j * w + i;
                for t in [[a, a + 1, a + w + 1], [a, a + w + 1, a + w]] {
                    self.scene.triangles.push(t);
                    self.scene.triangle_object.push(object);
                }
            }
        }
    }

    /// Adds an ellipsoid (a tree crown) with `segments` around and
    /// `segments / 2` rings, wound outward.
    pub fn add_ellipsoid(
        &mut self,
        object: u32,
        center: [f32; 3],
        radii: [f32; 3],
        segments: usize,
    ) {
        let seg = segments.max(3);
        let rings = (seg / 2).max(2);
        let point = |ring: usize, s: usize| {
            let theta = std::f32::consts::PI * ring as f32 / rings as f32;
            let phi = std::f32::consts::TAU * (s % seg) as f32 / seg as f32;
            let (st, ct) = theta.sin_cos();
            let (sp, cp) = phi.sin_cos();
            [
                center[0] + radii[0] * st * cp,
                center[1] + radii[1] * st * sp,
                center[2] + radii[2] * ct,
            ]
        };
        for ring in 0..rings {
            for s in 0..seg {
                let (a, b) = (point(ring, s), point(ring, s + 1));
                let (c, d) = (point(ring + 1, s), point(ring + 1, s + 1));
                if ring > 0 {
                    self.triangle(object, [a, c, b]);
                }
                if ring + 1 < rings {
                    self.triangle(object, [b, c, d]);
                }
            }
        }
    }

    /// The scene built so far.
    pub fn finish(self) -> Scene {
        self.scene
    }

    /// One box face at `coord[axis] = value`, gridded by the `u` and `v` ticks.
    fn add_face(
        &mut self,
        object: u32,
        axis: usize,
        value: f32,
        (au, us): (usize, &[f32]),
        (av, vs): (usize, &[f32]),
        outward: [f32; 3],
    ) {
        let p = |i: usize, j: usize| {
            let mut q = [0.0; 3];
            q[axis] = value;
            q[au] = us[i];
            q[av] = vs[j];
            q
        };
        // (u × v) is +axis for the cyclic (axis, au, av); flip for -axis faces.
        let flip = outward[axis] < 0.0;
        for i in 0..us.len().saturating_sub(1) {
            for j in 0..vs.len().saturating_sub(1) {
                let (a, b, c, d) = (p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
                for t in [[a, b, c], [a, c, d]] {
                    let t = if flip { [t[0], t[2], t[1]] } else { t };
                    self.triangle(object, t);
                }
            }
        }
    }
}

/// Ticks from `a` to `b` (both exact) at most `cell` apart.
fn ticks(a: f32, b: f32, cell: f32) -> Vec<f32> {
    let n = if cell.is_finite() && cell > 0.0 {
        (((b - a) / cell).ceil() as usize).clamp(1, 1 << 16)
    } else {
        1
    };
    ticks_n(a, b, n)
}

/// `n + 1` evenly spaced ticks from `a` to `b`, both exact.
fn ticks_n(a: f32, b: f32, n: usize) -> Vec<f32> {
    (0..=n)
        .map(|i| {
            if i == n {
                b
            } else {
                a + (b - a) * (i as f32 / n as f32)
            }
        })
        .collect()
}

/// A square ground plane of half-size `half` at z = 0 (two triangles, object
/// 0) with one closed box building per `(lo, hi)` (objects 1.., building ids 1..).
pub fn boxes_on_plane(half: f32, boxes: &[([f32; 3], [f32; 3])]) -> Scene {
    let mut b = SyntheticBuilder::new();
    let ground = b.object("ground", ObjectKind::Ground);
    b.add_terrain(ground, [-half, -half], [half, half], 1, |_, _| 0.0);
    for (i, &(lo, hi)) in boxes.iter().enumerate() {
        let o = b.object(&format!("box{}", i + 1), ObjectKind::Building);
        b.add_box(o, lo, hi, f32::INFINITY);
    }
    b.finish()
}

/// Gentle terrain of the dense scene.
fn dense_height(x: f32, y: f32) -> f32 {
    0.02 * x + 0.01 * y + 0.6 * (x / 23.0).sin() * (y / 31.0).cos()
}

/// A 200 m × 200 m city-like scene (x, y in 0..200) of about `triangles`
/// triangles: finely tessellated terrain (half the budget), 16 box
/// buildings with tessellated walls on a 4 × 4 block grid (a third) and
/// trees with ellipsoid crowns along the streets (the rest). The same
/// `(triangles, seed)` always gives the same scene.
pub fn dense_scene(triangles: usize, seed: u64) -> Scene {
    let mut rng = Rng::keyed(seed, 0);
    let mut b = SyntheticBuilder::new();
    let ground = b.object("terrain", ObjectKind::Ground);
    let cells = ((triangles as f64 / 4.0).sqrt().ceil() as usize).max(1);
    b.add_terrain(ground, [0.0, 0.0], [200.0, 200.0], cells, dense_height);

    // Buildings: one per 50 m block, footprint 15–35 m, height 6–40 m.
    let mut footprints = Vec::new();
    for bj in 0..4 {
        for bi in 0..4 {
            let sx = 15.0 + 20.0 * rng.unit() as f32;
            let sy = 15.0 + 20.0 * rng.unit() as f32;
            let h = 6.0 + 34.0 * rng.unit() as f32;
            let cx = 25.0 + 50.0 * bi as f32;
            let cy = 25.0 + 50.0 * bj as f32;
            footprints.push((
                [cx - sx / 2.0, cy - sy / 2.0],
                [cx + sx / 2.0, cy + sy / 2.0],
                h,
            ));
        }
    }
    let surface: f32 = footprints
        .iter()
        .map(|(lo, hi, h)| {
            let (dx, dy) = (hi[0] - lo[0], hi[1] - lo[1]);
            2.0 * dx * dy + 2.0 * (dx + dy) * h
        })
        .sum();
    let cell = (2.0 * surface / (triangles as f32 / 3.0).max(1.0))
        .sqrt()
        .max(0.05);
    for (k, (lo, hi, h)) in footprints.iter().enumerate() {
        let o = b.object(&format!("building{}", k + 1), ObjectKind::Building);
        let z0 = dense_height(lo[0], lo[1]).min(dense_height(hi[0], hi[1])) - 1.0;
        let top = dense_height(hi[0], hi[1]).max(dense_height(lo[0], lo[1])) + h;
        b.add_box(o, [lo[0], lo[1], z0], [hi[0], hi[1], top], cell);
    }

    // Trees along the streets (x or y on a multiple of 50 m, offset 5 m).
    let per_tree = 2 * 16 * 8 + 12;
    let trees = (triangles / 6 / per_tree).max(1);
    for t in 0..trees {
        let o = b.object(&format!("tree{}", t + 1), ObjectKind::Vegetation);
        let along = 200.0 * rng.unit() as f32;
        let street = 50.0 * (1 + (rng.unit() * 3.0) as usize).min(3) as f32;
        let side = if rng.unit() < 0.5 { -5.0 } else { 5.0 };
        let (x, y) = if rng.unit() < 0.5 {
            (street + side, along)
        } else {
            (along, street + side)
        };
        let z = dense_height(x, y);
        let r = 2.0 + 2.0 * rng.unit() as f32;
        b.add_box(
            o,
            [x - 0.2, y - 0.2, z - 0.5],
            [x + 0.2, y + 0.2, z + 3.0],
            f32::INFINITY,
        );
        b.add_ellipsoid(o, [x, y, z + 3.0 + r], [r, r, 1.2 * r], 16);
    }
    b.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dense_scene_has_about_the_requested_size() {
        for n in [10_000, 200_000] {
            let s = dense_scene(n, 1);
            let got = s.triangles.len() as f64;
            assert!((0.7..1.3).contains(&(got / n as f64)), "{n}: {got}");
            assert_eq!(s.triangle_object.len(), s.triangles.len());
        }
        assert_eq!(dense_scene(5000, 3), dense_scene(5000, 3));
    }

    #[test]
    fn box_faces_point_outward() {
        let s = boxes_on_plane(10.0, &[([0.0, 0.0, 0.0], [1.0, 2.0, 3.0])]);
        let center = [0.5, 1.0, 1.5];
        for (t, &o) in s.triangles.iter().zip(&s.triangle_object) {
            if o != 1 {
                continue;
            }
            let v = t.map(|i| s.vertices[i as usize]);
            let n = crate::lidar::ray::cross(
                crate::lidar::ray::sub(v[1], v[0]),
                crate::lidar::ray::sub(v[2], v[0]),
            );
            let out = crate::lidar::ray::sub(v[0], center);
            assert!(crate::lidar::ray::dot(n, out) > 0.0);
        }
    }
}
