//! The polygon checks of one surface whose rings passed: 201, 203, 204, 206
//! and 208 (val3dity's polygon level).

use super::codes::{
    INNER_RING_OUTSIDE, INTERSECTION_RINGS, NON_PLANAR_POLYGON_DISTANCE_PLANE,
    NON_PLANAR_POLYGON_NORMALS_DEVIATION, ORIENTATION_RINGS_SAME,
};
use super::plane::Plane;
use super::ring::segment;
use crate::scene::vec3::{cross, dot, sub};
use geo::{Coord, CoordinatePosition, LineIntersection, line_intersection::line_intersection};
use geo::{LineString, Polygon, coordinate_position::CoordPos};

/// 203 when a vertex lies farther than `tol` from the plane.
pub(super) fn distance_to_plane(plane: &Plane, points: &[[f64; 3]], tol: f64) -> Option<u16> {
    let far = points.iter().any(|&p| plane.distance(p).abs() > tol);
    far.then_some(NON_PLANAR_POLYGON_DISTANCE_PLANE)
}

/// 204 when a triangle's normal (`triangles` index `points`) turns more than
/// `max_deg` from the plane's; a folded triangle turns by 180°.
pub(super) fn normals_deviation(
    plane: &Plane,
    points: &[[f64; 3]],
    triangles: &[[usize; 3]],
    max_deg: f64,
) -> Option<u16> {
    let cos_max = max_deg.to_radians().cos();
    let tilted = triangles.iter().any(|t| {
        let [a, b, c] = t.map(|i| points[i]);
        let n = cross(sub(b, a), sub(c, a));
        let len = dot(n, n).sqrt();
        // Slivers have no direction to speak of; their neighbours carry the surface's.
        len > 1e-12 && dot(n, plane.normal) / len < cos_max
    });
    tilted.then_some(NON_PLANAR_POLYGON_NORMALS_DEVIATION)
}

/// 201, 206 and 208 for the rings drawn in their plane (`flat[0]` outer).
pub(super) fn rings(flat: &[Vec<[f64; 2]>]) -> Vec<u16> {
    let mut codes = Vec::new();
    let Some((outer, inners)) = flat.split_first() else {
        return codes;
    };
    if rings_cross(flat) {
        codes.push(INTERSECTION_RINGS);
        // Inside or outside is not defined for rings that cross.
        return codes;
    }
    let shell = Polygon::new(line_string(outer), Vec::new());
    if inners.iter().any(|inner| {
        inner
            .iter()
            .any(|p| shell.coordinate_position(&Coord { x: p[0], y: p[1] }) == CoordPos::Outside)
    }) {
        codes.push(INNER_RING_OUTSIDE);
    }
    let turn = signed_area(outer);
    if inners.iter().any(|r| signed_area(r) * turn > 0.0) {
        codes.push(ORIENTATION_RINGS_SAME);
    }
    codes
}

/// Whether two different rings cross or overlap along a stretch; touching at
/// a point is allowed (ISO 19107), as in val3dity.
fn rings_cross(flat: &[Vec<[f64; 2]>]) -> bool {
    (0..flat.len()).any(|a| {
        (a + 1..flat.len()).any(|b| {
            (0..flat[a].len()).any(|i| {
                (0..flat[b].len()).any(|j| {
                    matches!(
                        line_intersection(segment(&flat[a], i), segment(&flat[b], j)),
                        Some(LineIntersection::SinglePoint {
                            is_proper: true,
                            ..
                        }) | Some(LineIntersection::Collinear { .. })
                    )
                })
            })
        })
    })
}

/// The ring as a geo line string (geo closes it).
pub(super) fn line_string(ring: &[[f64; 2]]) -> LineString<f64> {
    ring.iter().map(|&[x, y]| Coord { x, y }).collect()
}

/// Twice the signed area of the ring: positive when counter-clockwise.
fn signed_area(ring: &[[f64; 2]]) -> f64 {
    let n = ring.len();
    (0..n)
        .map(|i| {
            let (p, q) = (ring[i], ring[(i + 1) % n]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum()
}
