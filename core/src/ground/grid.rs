//! The cloth's lattice: particle (i, j) sits at `origin + (i, j) × cell`.

use super::error::CsfError;

/// Largest number of cloth particles (about 0.5 GB of working memory).
pub(crate) const MAX_PARTICLES: usize = 40_000_000;

/// Cells beyond the points' bounds on every side, so edge points have
/// cloth around them.
const MARGIN_CELLS: usize = 2;

/// A regular lattice of particles in row-major order (x fastest).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Lattice {
    pub origin: [f32; 2],
    pub cell: f32,
    pub nx: usize,
    pub ny: usize,
}

impl Lattice {
    /// The lattice covering `lo..hi` (xy) with a margin.
    pub fn covering(lo: [f32; 2], hi: [f32; 2], cell: f32) -> Result<Self, CsfError> {
        let count = |k: usize| ((hi[k] - lo[k]) / cell).ceil() as usize + 1 + 2 * MARGIN_CELLS;
        let (nx, ny) = (count(0), count(1));
        if nx.saturating_mul(ny) > MAX_PARTICLES {
            return Err(CsfError::ClothTooLarge {
                nx,
                ny,
                max: MAX_PARTICLES,
            });
        }
        let m = MARGIN_CELLS as f32 * cell;
        Ok(Self {
            origin: [lo[0] - m, lo[1] - m],
            cell,
            nx,
            ny,
        })
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.nx * self.ny
    }

    /// Index of the particle nearest to `(x, y)`, clamped to the lattice.
    pub fn nearest(&self, x: f32, y: f32) -> usize {
        let i = clamp_index((x - self.origin[0]) / self.cell, self.nx);
        let j = clamp_index((y - self.origin[1]) / self.cell, self.ny);
        j * self.nx + i
    }

    /// Position of particle `(i, j)`.
    pub fn position(&self, i: usize, j: usize) -> [f32; 2] {
        [
            self.origin[0] + i as f32 * self.cell,
            self.origin[1] + j as f32 * self.cell,
        ]
    }

    /// Bilinear interpolation of `values` (one per particle) at `(x, y)`,
    /// clamped at the edges.
    pub fn bilinear(&self, values: &[f32], x: f32, y: f32) -> f32 {
        let (i0, fx) = split(((x - self.origin[0]) / self.cell).clamp(0.0, (self.nx - 1) as f32));
        let (j0, fy) = split(((y - self.origin[1]) / self.cell).clamp(0.0, (self.ny - 1) as f32));
        let i1 = (i0 + 1).min(self.nx - 1);
        let j1 = (j0 + 1).min(self.ny - 1);
        let at = |i: usize, j: usize| values[j * self.nx + i];
        let bottom = at(i0, j0) + fx * (at(i1, j0) - at(i0, j0));
        let top = at(i0, j1) + fx * (at(i1, j1) - at(i0, j1));
        bottom + fy * (top - bottom)
    }

    /// The 4-neighbours of particle `k`.
    pub fn neighbours(&self, k: usize) -> impl Iterator<Item = usize> + use<> {
        let (nx, ny) = (self.nx, self.ny);
        let (i, j) = (k % nx, k / nx);
        [
            (i > 0).then(|| k - 1),
            (i + 1 < nx).then(|| k + 1),
            (j > 0).then(|| k - nx),
            (j + 1 < ny).then(|| k + nx),
        ]
        .into_iter()
        .flatten()
    }
}

fn clamp_index(t: f32, n: usize) -> usize {
    // NaN casts to 0, which the caller never passes (points are finite).
    (t.round().max(0.0) as usize).min(n - 1)
}

fn split(t: f32) -> (usize, f32) {
    let i = t.floor();
    (i as usize, t - i)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn covers_bounds_with_margin_and_interpolates_planes_exactly() {
        let l = Lattice::covering([0.0, 0.0], [10.0, 5.0], 1.0).unwrap();
        assert_eq!((l.nx, l.ny), (15, 10));
        assert_eq!(l.nearest(0.0, 0.0), 2 * 15 + 2);
        let v: Vec<f32> = (0..l.len())
            .map(|k| {
                let p = l.position(k % l.nx, k / l.nx);
                2.0 * p[0] - p[1]
            })
            .collect();
        let z = l.bilinear(&v, 3.3, 1.7);
        assert!((z - (6.6 - 1.7)).abs() < 1e-4, "{z}");
        assert_eq!(l.neighbours(0).count(), 2);
        assert_eq!(l.neighbours(16).count(), 4);
    }

    #[test]
    fn huge_extent_is_an_error() {
        assert!(matches!(
            Lattice::covering([0.0, 0.0], [1e6, 1e6], 0.1),
            Err(CsfError::ClothTooLarge { .. })
        ));
    }
}
