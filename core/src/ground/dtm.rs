//! The digital terrain model the cloth leaves behind: a plain height grid.

use serde::{Deserialize, Serialize};

use super::grid::Lattice;

/// Terrain heights on a regular grid (same frame as the cloud), row-major
/// with x fastest: `heights[j * nx + i]` is the terrain at
/// `(origin_x + i × cell, origin_y + j × cell)`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Dtm {
    /// x of grid node (0, 0).
    pub origin_x: f32,
    /// y of grid node (0, 0).
    pub origin_y: f32,
    /// Node spacing, metres.
    pub cell: f32,
    /// Nodes along x.
    pub nx: usize,
    /// Nodes along y.
    pub ny: usize,
    /// Terrain height of each node.
    pub heights: Vec<f32>,
}

impl Dtm {
    pub(crate) fn from_lattice(lattice: &Lattice, heights: Vec<f32>) -> Self {
        Self {
            origin_x: lattice.origin[0],
            origin_y: lattice.origin[1],
            cell: lattice.cell,
            nx: lattice.nx,
            ny: lattice.ny,
            heights,
        }
    }

    /// Terrain height at `(x, y)`: bilinear between the four nearest nodes,
    /// the edge value outside the grid; NaN only for an empty or
    /// inconsistent grid or a NaN coordinate.
    pub fn height_at(&self, x: f32, y: f32) -> f32 {
        let consistent = self.nx > 0
            && self.ny > 0
            && self.heights.len() == self.nx * self.ny
            && self.cell > 0.0;
        if !consistent || !x.is_finite() || !y.is_finite() {
            return f32::NAN;
        }
        let lattice = Lattice {
            origin: [self.origin_x, self.origin_y],
            cell: self.cell,
            nx: self.nx,
            ny: self.ny,
        };
        lattice.bilinear(&self.heights, x, y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bilinear_inside_clamped_outside() {
        let dtm = Dtm {
            origin_x: 10.0,
            origin_y: 20.0,
            cell: 2.0,
            nx: 2,
            ny: 2,
            heights: vec![0.0, 2.0, 4.0, 6.0],
        };
        assert!((dtm.height_at(11.0, 21.0) - 3.0).abs() < 1e-6);
        assert_eq!(dtm.height_at(0.0, 0.0), 0.0);
        assert_eq!(dtm.height_at(100.0, 100.0), 6.0);
        assert!(dtm.height_at(f32::NAN, 0.0).is_nan());
        let empty = Dtm {
            nx: 0,
            heights: vec![],
            ..dtm
        };
        assert!(empty.height_at(11.0, 21.0).is_nan());
    }
}
