//! The reference scene's terrain: a tilted plane (2–4 % slope) with gentle
//! value-noise undulation, meshed as a regular grid.

use crate::rng::{Rng, mix};
use crate::scene::builder::MeshPart;

/// Side of the square reference scene, metres (it spans `[0, SIZE]²`).
pub const SIZE: f64 = 200.0;
/// Grid cells per side of the terrain mesh (cell = 1.5625 m).
pub const CELLS: usize = 128;

/// The reference terrain of one seed, usable without building the scene
/// (e.g. to put a vehicle on the ground).
///
/// [`height`](Self::height) is the smooth surface; the scene's ground mesh
/// samples it on a grid of [`CELLS`]² cells and [`mesh_height`](Self::mesh_height)
/// is the height of that mesh (they differ by millimetres). Only IEEE-exact
/// arithmetic is used, so heights are identical on every machine.
#[derive(Debug, Clone, PartialEq)]
pub struct ReferenceTerrain {
    seed: u64,
    grad: [f64; 2],
    octaves: [(f64, f64); 2],
}

impl ReferenceTerrain {
    /// The terrain of `seed`.
    pub fn new(seed: u64) -> Self {
        let mut r = Rng::new(seed, 0x7E44);
        let slope = r.range(0.02, 0.035);
        // Direction from a rational parametrisation of the circle (no trig).
        let t = r.range(-1.0, 1.0);
        let (c, s) = ((1.0 - t * t) / (1.0 + t * t), 2.0 * t / (1.0 + t * t));
        let sign = if r.chance(0.5) { 1.0 } else { -1.0 };
        Self {
            seed,
            grad: [sign * slope * c, sign * slope * s],
            // (lattice spacing m, amplitude m)
            octaves: [(r.range(55.0, 75.0), 0.35), (r.range(22.0, 30.0), 0.12)],
        }
    }

    /// The overall slope (dz/dx, dz/dy).
    pub fn gradient(&self) -> [f64; 2] {
        self.grad
    }

    /// Height of the smooth terrain at `(x, y)`, metres (0 near the centre).
    pub fn height(&self, x: f64, y: f64) -> f64 {
        let mut h = self.grad[0] * (x - SIZE / 2.0) + self.grad[1] * (y - SIZE / 2.0);
        for (k, &(spacing, amplitude)) in self.octaves.iter().enumerate() {
            h += amplitude * self.value_noise(x / spacing, y / spacing, k as u64);
        }
        h
    }

    /// Height of the terrain mesh (the grid triangulation of
    /// [`height`](Self::height)) at `(x, y)`; outside the scene the border
    /// cell is extended.
    pub fn mesh_height(&self, x: f64, y: f64) -> f64 {
        let cell = SIZE / CELLS as f64;
        let fx = (x / cell).clamp(0.0, CELLS as f64);
        let fy = (y / cell).clamp(0.0, CELLS as f64);
        let i = (fx.floor() as usize).min(CELLS - 1);
        let j = (fy.floor() as usize).min(CELLS - 1);
        let (u, v) = (x / cell - i as f64, y / cell - j as f64);
        let corner = |di: usize, dj: usize| self.grid_height(i + di, j + dj);
        let (h00, h10, h01, h11) = (corner(0, 0), corner(1, 0), corner(0, 1), corner(1, 1));
        // Same diagonal as the mesh: (00, 10, 11) and (00, 11, 01).
        if u >= v {
            h00 + u * (h10 - h00) + v * (h11 - h10)
        } else {
            h00 + u * (h11 - h01) + v * (h01 - h00)
        }
    }

    /// Lowest and highest mesh height over the axis-aligned box `[x0,x1]×[y0,y1]`.
    pub fn range_over(&self, x0: f64, y0: f64, x1: f64, y1: f64) -> (f64, f64) {
        let steps = |a: f64, b: f64| ((b - a) / 0.75).ceil().max(1.0) as usize;
        let (nx, ny) = (steps(x0, x1), steps(y0, y1));
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for i in 0..=nx {
            for j in 0..=ny {
                let x = x0 + (x1 - x0) * i as f64 / nx as f64;
                let y = y0 + (y1 - y0) * j as f64 / ny as f64;
                let h = self.mesh_height(x, y);
                lo = lo.min(h);
                hi = hi.max(h);
            }
        }
        (lo, hi)
    }

    /// The ground mesh: `CELLS`² cells over `[0, SIZE]²`, two triangles each.
    pub fn mesh(&self) -> MeshPart {
        let n = CELLS + 1;
        let cell = SIZE / CELLS as f64;
        let mut m = MeshPart::default();
        for j in 0..n {
            for i in 0..n {
                m.vertex([i as f64 * cell, j as f64 * cell, self.grid_height(i, j)]);
            }
        }
        let id = |i: usize, j: usize| u32::try_from(j * n + i).unwrap_or(u32::MAX);
        for j in 0..CELLS {
            for i in 0..CELLS {
                let (v00, v10, v11, v01) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                m.triangle(v00, v10, v11);
                m.triangle(v00, v11, v01);
            }
        }
        m
    }

    fn grid_height(&self, i: usize, j: usize) -> f64 {
        let cell = SIZE / CELLS as f64;
        self.height(i as f64 * cell, j as f64 * cell)
    }

    /// Smooth value noise in `[-1, 1]` on the unit lattice.
    fn value_noise(&self, x: f64, y: f64, octave: u64) -> f64 {
        let (ix, iy) = (x.floor(), y.floor());
        let (u, v) = (smooth(x - ix), smooth(y - iy));
        let at = |dx: f64, dy: f64| self.lattice(ix + dx, iy + dy, octave);
        let a = at(0.0, 0.0) + u * (at(1.0, 0.0) - at(0.0, 0.0));
        let b = at(0.0, 1.0) + u * (at(1.0, 1.0) - at(0.0, 1.0));
        a + v * (b - a)
    }

    fn lattice(&self, x: f64, y: f64, octave: u64) -> f64 {
        let h = mix(self.seed ^ mix((x as i64 as u64) ^ mix((y as i64 as u64) ^ mix(octave))));
        (h >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

fn smooth(t: f64) -> f64 {
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_is_gentle_and_mesh_matches_surface() {
        for seed in [0, 1, 42, 2024] {
            let t = ReferenceTerrain::new(seed);
            let g = t.gradient();
            let slope = (g[0] * g[0] + g[1] * g[1]).sqrt();
            assert!((0.02..=0.035).contains(&slope), "slope {slope}");
            for (x, y) in [(0.0, 0.0), (37.3, 150.1), (199.9, 12.0), (100.0, 100.0)] {
                assert!((t.height(x, y) - t.mesh_height(x, y)).abs() < 0.02);
            }
            // Local slope stays moderate everywhere.
            for k in 0..50 {
                let (x, y) = (4.0 * k as f64, 200.0 - 4.0 * k as f64);
                let dx = (t.height(x + 1.0, y) - t.height(x - 1.0, y)) / 2.0;
                let dy = (t.height(x, y + 1.0) - t.height(x, y - 1.0)) / 2.0;
                assert!((dx * dx + dy * dy).sqrt() < 0.08);
            }
        }
    }

    #[test]
    fn mesh_height_interpolates_grid_vertices() {
        let t = ReferenceTerrain::new(3);
        let m = t.mesh();
        for p in m.vertices.iter().step_by(97) {
            assert!((t.mesh_height(p[0], p[1]) - p[2]).abs() < 1e-9);
        }
    }
}
