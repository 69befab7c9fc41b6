//! Terrain height around buildings, from ground points: on sloped ground a
//! building's lowest point is not the foot of every wall, and slices below
//! the local terrain must not be tested. It also keeps where ground was
//! actually observed: ground seen under a building's outline means the
//! outline is not a wall down to the ground there (a slab on pillars).

use crate::geom::grid::GridFrame;
use crate::ground::Dtm;

/// Cell of the observed-ground bitmap, metres (fine enough to tell the
/// ground under a slab from the ground at its wall's foot).
pub const SEEN_CELL: f32 = 0.5;

/// The terrain model (mean ground height per cell, holes under buildings
/// filled from their neighbours) and where ground was observed.
#[derive(Debug, Clone)]
pub struct GroundGrid {
    terrain: Dtm,
    /// The far corner of the ground points' extent (the terrain's origin is the near one).
    far: [f64; 2],
    seen_frame: GridFrame,
    seen: Vec<bool>,
}

impl GroundGrid {
    /// Terrain of cell `cell` metres over `ground` points (finite ones); cells
    /// without points take the mean of filled neighbours, up to `fill`
    /// cells away. None without finite points or with a bad cell size.
    pub fn from_points(ground: &[[f32; 3]], cell: f32, fill: usize) -> Option<Self> {
        let terrain = Dtm::from_ground_points(ground.iter(), cell, fill)?;
        let finite = || ground.iter().filter(|p| p.iter().all(|v| v.is_finite()));
        let (lo, far) = crate::ground::xy_extent(finite())?;
        let seen_frame = GridFrame::covering(lo, far, f64::from(SEEN_CELL), 0);
        let mut seen = vec![false; seen_frame.len()];
        for p in finite() {
            seen[seen_frame.clamped_index(f64::from(p[0]), f64::from(p[1]))] = true;
        }
        Some(GroundGrid {
            terrain,
            far,
            seen_frame,
            seen,
        })
    }

    /// Ground height at (x, y), None off the grid or where unknown.
    pub fn at(&self, x: f64, y: f64) -> Option<f32> {
        self.terrain.cell_height(x, y)
    }

    /// Whether (x, y) lies outside the ground points' extent: beyond the
    /// survey's edge, where a tile cut a building rather than a wall ending it.
    pub fn beyond_data(&self, x: f64, y: f64) -> bool {
        let lo = self.seen_frame.origin;
        x < lo[0] || y < lo[1] || x > self.far[0] || y > self.far[1]
    }

    /// Whether a ground point was observed within the [`SEEN_CELL`] cell of (x, y).
    pub fn seen(&self, x: f64, y: f64) -> bool {
        self.seen_frame.index_of(x, y).is_some_and(|k| self.seen[k])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_is_kept_and_holes_filled() {
        let mut pts = Vec::new();
        for i in 0..50 {
            for j in 0..50 {
                let (x, y) = (i as f32 + 0.5, j as f32 + 0.5);
                if !((20.0..30.0).contains(&x) && (20.0..30.0).contains(&y)) {
                    pts.push([x, y, 0.1 * x]);
                }
            }
        }
        let g = GroundGrid::from_points(&pts, 2.0, 10).unwrap();
        assert!((g.at(5.0, 5.0).unwrap() - 0.5).abs() < 0.2);
        assert!((g.at(25.0, 25.0).unwrap() - 2.5).abs() < 0.5);
        assert!(g.at(-5.0, 5.0).is_none());
        assert!(g.seen(5.6, 5.6) && !g.seen(25.6, 25.6) && !g.seen(-5.0, 5.0));
        assert!(g.beyond_data(0.4, 5.0) && !g.beyond_data(0.6, 5.0) && g.beyond_data(5.0, 49.6));
        assert!(GroundGrid::from_points(&[], 2.0, 10).is_none());
    }
}
