//! The cloth's lattice as a grid frame: particle `k` sits at the centre of
//! cell `k`, so the terrain the cloth leaves is a [`super::Dtm`] as it is.

use super::error::CsfError;
use crate::geom::grid::GridFrame;

/// Largest number of cloth particles (about 0.5 GB of working memory).
pub(crate) const MAX_PARTICLES: usize = 40_000_000;

/// Cells beyond the points' bounds on every side, so edge points have
/// cloth around them.
const MARGIN_CELLS: usize = 2;

/// The lattice of particles `cell` apart covering `lo..hi` (xy) with a
/// margin; too many particles is an error.
pub(crate) fn covering(lo: [f32; 2], hi: [f32; 2], cell: f32) -> Result<GridFrame, CsfError> {
    let count = |k: usize| ((hi[k] - lo[k]) / cell).ceil() as usize + 1 + 2 * MARGIN_CELLS;
    let (nx, ny) = (count(0), count(1));
    if nx.saturating_mul(ny) > MAX_PARTICLES {
        return Err(CsfError::ClothTooLarge {
            nx,
            ny,
            max: MAX_PARTICLES,
        });
    }
    // The first particle is MARGIN_CELLS before `lo`; its cell starts half a cell before it.
    let first = |k: usize| f64::from(lo[k] - MARGIN_CELLS as f32 * cell) - 0.5 * f64::from(cell);
    Ok(GridFrame {
        origin: [first(0), first(1)],
        cell: f64::from(cell),
        nx,
        ny,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn covers_bounds_with_margin_and_interpolates_planes_exactly() {
        let l = covering([0.0, 0.0], [10.0, 5.0], 1.0).unwrap();
        assert_eq!((l.nx, l.ny), (15, 10));
        assert_eq!(l.centre(0), [-2.0, -2.0]);
        assert_eq!(l.clamped_index(0.0, 0.0), 2 * 15 + 2);
        assert_eq!(l.clamped_index(0.49, -0.49), 2 * 15 + 2);
        let v: Vec<f32> = (0..l.len())
            .map(|k| {
                let p = l.centre(k);
                (2.0 * p[0] - p[1]) as f32
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
            covering([0.0, 0.0], [1e6, 1e6], 0.1),
            Err(CsfError::ClothTooLarge { .. })
        ));
    }
}
