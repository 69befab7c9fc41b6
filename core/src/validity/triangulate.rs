//! A surface drawn in its plane, cut into triangles by spade's constrained
//! Delaunay triangulation: every vertex is kept (earcut drops collinear ones,
//! which would leave a neighbour's vertex on a triangle's edge).

use super::polygon::line_string;
use geo::{Contains, Coord, Polygon};
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

/// Triangles of the polygon whose rings are `flat` (outer first), as indices
/// into the rings' concatenated vertices, counter-clockwise in the plane.
pub(super) fn triangles(flat: &[Vec<[f64; 2]>]) -> Vec<[usize; 3]> {
    let mut cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::new();
    // Vertex handle index → concatenated index; two vertices at one spot keep the first.
    let mut index_of: Vec<Option<usize>> = Vec::new();
    let mut handles = Vec::new();
    let mut next = 0;
    for ring in flat {
        let mut ring_handles = Vec::with_capacity(ring.len());
        for p in ring {
            let Ok(h) = cdt.insert(Point2::new(p[0], p[1])) else {
                return Vec::new();
            };
            let k = h.index();
            if index_of.len() <= k {
                index_of.resize(k + 1, None);
            }
            if index_of[k].is_none() {
                index_of[k] = Some(next);
            }
            ring_handles.push(h);
            next += 1;
        }
        handles.push(ring_handles);
    }
    for ring in &handles {
        for (i, &a) in ring.iter().enumerate() {
            let b = ring[(i + 1) % ring.len()];
            // The ring checks ruled out crossing edges; a conflict left over is skipped, not fatal.
            if a != b && cdt.can_add_constraint(a, b) {
                cdt.add_constraint(a, b);
            }
        }
    }
    let Some((outer, inners)) = flat.split_first() else {
        return Vec::new();
    };
    let polygon = Polygon::new(
        line_string(outer),
        inners.iter().map(|r| line_string(r)).collect(),
    );
    cdt.inner_faces()
        .filter(|f| {
            let [a, b, c] = f.positions();
            let centroid = Coord {
                x: (a.x + b.x + c.x) / 3.0,
                y: (a.y + b.y + c.y) / 3.0,
            };
            polygon.contains(&centroid)
        })
        .filter_map(|f| {
            let [a, b, c] = f
                .vertices()
                .map(|v| index_of.get(v.fix().index()).copied().flatten());
            Some([a?, b?, c?])
        })
        .collect()
}
