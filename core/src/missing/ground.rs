//! Terrain height around buildings, from ground points: on sloped ground a
//! building's lowest point is not the foot of every wall, and slices below
//! the local terrain must not be tested. It also keeps where ground was
//! actually observed: ground seen under a building's outline means the
//! outline is not a wall down to the ground there (a slab on pillars).

use geo::{BoundingRect, Contains, LineString, MultiPolygon, Point, Polygon};

use crate::geom::grid::GridFrame;
use crate::ground::Dtm;

/// Cell of the observed-ground bitmap, metres (fine enough to tell the
/// ground under a slab from the ground at its wall's foot).
pub const SEEN_CELL: f32 = 0.5;
/// Most probes along one side of a hole looked into for ground (a 1 km hole at 0.5 m).
const MAX_PROBES: usize = 2000;

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

    /// `outline` without the holes in which no ground was observed: a
    /// courtyard shows its floor from the air, while a gap in the roof
    /// points that shows nothing is a roof the aerial survey did not reach
    /// (the shadow of a tower on its podium), with no wall round it to miss.
    pub fn fill_blind_holes(&self, outline: &MultiPolygon<f64>) -> MultiPolygon<f64> {
        let polygons = outline.0.iter().map(|p| {
            let holes: Vec<LineString<f64>> = p
                .interiors()
                .iter()
                .filter(|ring| self.seen_inside(ring))
                .cloned()
                .collect();
            Polygon::new(p.exterior().clone(), holes)
        });
        MultiPolygon(polygons.collect())
    }

    /// Whether ground was observed anywhere inside `ring`.
    fn seen_inside(&self, ring: &LineString<f64>) -> bool {
        let area = Polygon::new(ring.clone(), vec![]);
        let Some(r) = area.bounding_rect() else {
            return false;
        };
        let step = f64::from(SEEN_CELL);
        let (nx, ny) = (
            ((r.width() / step).ceil() as usize).min(MAX_PROBES),
            ((r.height() / step).ceil() as usize).min(MAX_PROBES),
        );
        (0..ny).any(|j| {
            (0..nx).any(|i| {
                let (x, y) = (
                    r.min().x + (i as f64 + 0.5) * step,
                    r.min().y + (j as f64 + 0.5) * step,
                );
                self.seen(x, y) && area.contains(&Point::new(x, y))
            })
        })
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

    #[test]
    fn a_hole_without_ground_is_filled_a_courtyard_is_kept() {
        // Ground seen everywhere on 0..50 m but in the square 20..30 (a roof).
        let pts: Vec<[f32; 3]> = (0..100)
            .flat_map(|i| {
                (0..100).map(move |j| [i as f32 * 0.5 + 0.25, j as f32 * 0.5 + 0.25, 0.0])
            })
            .filter(|p| !((20.0..30.0).contains(&p[0]) && (20.0..30.0).contains(&p[1])))
            .collect();
        let g = GroundGrid::from_points(&pts, 2.0, 10).unwrap();
        let square = |x0: f64, y0: f64, side: f64| {
            LineString::from(vec![
                (x0, y0),
                (x0 + side, y0),
                (x0 + side, y0 + side),
                (x0, y0 + side),
                (x0, y0),
            ])
        };
        // One outline with a hole on the unseen roof and one over seen ground.
        let outline = MultiPolygon(vec![Polygon::new(
            square(5.0, 5.0, 40.0),
            vec![square(22.0, 22.0, 4.0), square(8.0, 8.0, 6.0)],
        )]);
        let filled = g.fill_blind_holes(&outline);
        assert_eq!(filled.0.len(), 1);
        let holes = filled.0[0].interiors();
        assert_eq!(holes.len(), 1, "{holes:?}");
        assert_eq!(holes[0], square(8.0, 8.0, 6.0));
    }
}
