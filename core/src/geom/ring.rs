//! Point-in-polygon against a ring of points, built once and asked often.

use geo::{BoundingRect, Contains, Coord, LineString, Polygon, Rect};

/// A simple polygon (one ring, open or closed, any orientation) ready for
/// inside tests.
#[derive(Debug, Clone)]
pub struct Ring {
    polygon: Polygon<f64>,
    bounds: Option<Rect<f64>>,
}

impl Ring {
    /// The polygon bounded by `points`; fewer than 3 points contain nothing.
    pub fn new(points: &[[f64; 2]]) -> Self {
        let line: LineString<f64> = points.iter().map(|&[x, y]| Coord { x, y }).collect();
        let polygon = Polygon::new(line, Vec::new());
        let bounds = (points.len() >= 3)
            .then(|| polygon.bounding_rect())
            .flatten();
        Self { polygon, bounds }
    }

    /// Whether `p` lies inside (points on the boundary do not).
    pub fn contains(&self, p: [f64; 2]) -> bool {
        let c = Coord { x: p[0], y: p[1] };
        self.bounds.is_some_and(|b| {
            c.x >= b.min().x && c.x <= b.max().x && c.y >= b.min().y && c.y <= b.max().y
        }) && self.polygon.contains(&c)
    }
}

/// Whether `p` lies inside the ring `points` (one-off; build a [`Ring`] to ask often).
pub fn contains(points: &[[f64; 2]], p: [f64; 2]) -> bool {
    Ring::new(points).contains(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn square_and_l_shape() {
        let sq = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
        assert!(contains(&sq, [1.0, 1.0]));
        assert!(!contains(&sq, [3.0, 1.0]));
        let l = Ring::new(&[
            [0.0, 0.0],
            [4.0, 0.0],
            [4.0, 1.0],
            [1.0, 1.0],
            [1.0, 4.0],
            [0.0, 4.0],
        ]);
        assert!(l.contains([0.5, 3.0]));
        assert!(!l.contains([3.0, 3.0]));
        assert!(!contains(&sq[..2], [1.0, 0.0]));
        assert!(!contains(&[], [1.0, 0.0]));
    }
}
