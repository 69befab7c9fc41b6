//! The one terrain model: ground heights on a regular grid. The cloth
//! filter leaves one behind ([`super::csf`]); the steps that only see a
//! classified cloud (detection, targets, reconstruction, the classifier's
//! training clouds) build one from its ground points, the same way.

use crate::geom::grid::{self, GridFrame, Neighbours};

/// Terrain heights, one per cell of `frame`, taken at the cell centres.
#[derive(Debug, Clone, PartialEq)]
pub struct Dtm {
    /// The grid (same frame as the cloud).
    pub frame: GridFrame,
    /// Terrain height of each cell, row-major; NaN where unknown.
    pub heights: Vec<f32>,
}

impl Dtm {
    /// The terrain under `ground` points (non-finite ones skipped): the
    /// mean height per `cell`-wide cell over the points' extent, cells
    /// without points filled from their neighbours up to `fill` cells away
    /// (NaN beyond). `None` without a finite point or with a cell that is
    /// not a positive number.
    pub fn from_ground_points<'a>(
        ground: impl Iterator<Item = &'a [f32; 3]> + Clone,
        cell: f32,
        fill: usize,
    ) -> Option<Self> {
        if !(cell.is_finite() && cell > 0.0) {
            return None;
        }
        let finite = ground.filter(|p| p.iter().all(|v| v.is_finite()));
        let (lo, hi) = xy_extent(finite.clone())?;
        let frame = GridFrame::covering(lo, hi, f64::from(cell), 0);
        let at = |p: &[f32; 3]| ([f64::from(p[0]), f64::from(p[1])], p[2]);
        let mut heights = grid::cell_means(&frame, finite.map(at));
        grid::fill_holes(&mut heights, frame.nx, frame.ny, fill, Neighbours::Four);
        Some(Dtm { frame, heights })
    }

    /// Terrain height at `(x, y)`: bilinear between the four nearest cell
    /// centres, the edge value outside the grid; NaN for an empty or
    /// inconsistent grid, a NaN coordinate or where the terrain is unknown.
    pub fn height_at(&self, x: f32, y: f32) -> f32 {
        self.frame
            .bilinear(&self.heights, f64::from(x), f64::from(y))
    }

    /// Terrain height of the cell holding `(x, y)`; `None` off the grid or
    /// where unknown.
    pub fn cell_height(&self, x: f64, y: f64) -> Option<f32> {
        let k = self.frame.index_of(x, y)?;
        self.heights.get(k).copied().filter(|z| z.is_finite())
    }
}

/// The xy bounding box of `points`, `None` when there are none.
pub(crate) fn xy_extent<'a>(
    points: impl Iterator<Item = &'a [f32; 3]>,
) -> Option<([f64; 2], [f64; 2])> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
        for k in 0..2 {
            lo[k] = lo[k].min(f64::from(p[k]));
            hi[k] = hi[k].max(f64::from(p[k]));
        }
    }
    (lo[0] <= hi[0]).then_some((lo, hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bilinear_inside_clamped_outside() {
        // Cell centres at x 10, 12 and y 20, 22.
        let dtm = Dtm {
            frame: GridFrame {
                origin: [9.0, 19.0],
                cell: 2.0,
                nx: 2,
                ny: 2,
            },
            heights: vec![0.0, 2.0, 4.0, 6.0],
        };
        assert!((dtm.height_at(11.0, 21.0) - 3.0).abs() < 1e-6);
        assert_eq!(dtm.height_at(0.0, 0.0), 0.0);
        assert_eq!(dtm.height_at(100.0, 100.0), 6.0);
        assert!(dtm.height_at(f32::NAN, 0.0).is_nan());
        assert_eq!(dtm.cell_height(12.9, 19.1), Some(2.0));
        assert_eq!(dtm.cell_height(8.9, 20.0), None);
        let empty = Dtm {
            heights: vec![],
            ..dtm
        };
        assert!(empty.height_at(11.0, 21.0).is_nan());
        assert_eq!(empty.cell_height(11.0, 21.0), None);
    }

    #[test]
    fn ground_points_keep_the_slope_and_fill_holes() {
        // z = 0.1 x with a 10 m × 10 m hole (a building) in the middle.
        let pts: Vec<[f32; 3]> = crate::geom::fixtures::lattice(50, 50, 1.0, |x, _| 0.1 * x)
            .into_iter()
            .filter(|p| !((20.0..30.0).contains(&p[0]) && (20.0..30.0).contains(&p[1])))
            .collect();
        let dtm = Dtm::from_ground_points(pts.iter(), 2.0, 10).unwrap();
        assert!((dtm.cell_height(5.0, 5.0).unwrap() - 0.45).abs() < 1e-5);
        assert!((dtm.cell_height(25.0, 25.0).unwrap() - 2.5).abs() < 0.5);
        assert!((dtm.height_at(7.3, 40.0) - 0.68).abs() < 1e-4);
        assert_eq!(dtm.cell_height(-5.0, 5.0), None);
        let few = Dtm::from_ground_points(pts.iter(), 2.0, 0).unwrap();
        assert_eq!(few.cell_height(25.0, 25.0), None);
        assert!(Dtm::from_ground_points([].iter(), 2.0, 10).is_none());
        assert!(Dtm::from_ground_points(pts.iter(), 0.0, 10).is_none());
    }
}
