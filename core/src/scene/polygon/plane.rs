//! Projecting (possibly non-planar) 3D rings to their best-fit plane.

use super::earcut::triangulate_2d;
use crate::scene::vec3::{cross, dot, normalize, sub};

/// Triangulates a 3D polygon given as rings (the first is the outer boundary,
/// the others are holes).
///
/// The plane is the one of the outer ring's Newell normal (robust to
/// non-planar rings); triangles index into the rings concatenated in order and
/// turn the same way as the outer ring (counter-clockwise seen from the side
/// its normal points to). A ring with no area gives no triangles.
pub fn triangulate_3d(rings: &[&[[f64; 3]]]) -> Vec<[usize; 3]> {
    let Some(outer) = rings.first() else {
        return Vec::new();
    };
    let Some(n) = newell_normal(outer) else {
        return Vec::new();
    };
    let u = match normalize(cross(helper_axis(n), n)) {
        Some(u) => u,
        None => return Vec::new(),
    };
    let v = cross(n, u);
    let centre = centroid(outer);
    let mut points = Vec::new();
    let mut index_rings = Vec::with_capacity(rings.len());
    for ring in rings {
        let start = points.len();
        points.extend(ring.iter().map(|p| {
            let d = sub(*p, centre);
            [dot(d, u), dot(d, v)]
        }));
        index_rings.push((start..points.len()).collect::<Vec<_>>());
    }
    triangulate_2d(&points, &index_rings)
}

/// Unit Newell normal of a ring, or `None` when it encloses no area.
pub fn newell_normal(ring: &[[f64; 3]]) -> Option<[f64; 3]> {
    let c = centroid(ring);
    let mut n = [0.0; 3];
    for (i, a) in ring.iter().enumerate() {
        let b = ring[(i + 1) % ring.len()];
        let (a, b) = (sub(*a, c), sub(b, c));
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    normalize(n)
}

fn centroid(ring: &[[f64; 3]]) -> [f64; 3] {
    let mut c = [0.0; 3];
    for p in ring {
        for k in 0..3 {
            c[k] += p[k];
        }
    }
    let n = ring.len().max(1) as f64;
    c.map(|v| v / n)
}

/// An axis not parallel to `n`.
fn helper_axis(n: [f64; 3]) -> [f64; 3] {
    if n[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::vec3::area_vector;

    fn total_area(points: &[[f64; 3]], tris: &[[usize; 3]]) -> ([f64; 3], f64) {
        let mut sum = [0.0; 3];
        let mut area = 0.0;
        for t in tris {
            let a = area_vector(points[t[0]], points[t[1]], points[t[2]]);
            for k in 0..3 {
                sum[k] += a[k] / 2.0;
            }
            area += dot(a, a).sqrt() / 2.0;
        }
        (sum, area)
    }

    #[test]
    fn vertical_wall_with_window_keeps_orientation_and_area() {
        // A 4 x 3 wall in the plane y = 0, outward normal -y (ring turns
        // counter-clockwise seen from -y), with a 1 x 1 window.
        let outer = [
            [0.0, 0.0, 0.0],
            [4.0, 0.0, 0.0],
            [4.0, 0.0, 3.0],
            [0.0, 0.0, 3.0],
        ];
        let hole = [
            [1.0, 0.0, 1.0],
            [1.0, 0.0, 2.0],
            [2.0, 0.0, 2.0],
            [2.0, 0.0, 1.0],
        ];
        let tris = triangulate_3d(&[&outer, &hole]);
        let all: Vec<_> = outer.iter().chain(hole.iter()).copied().collect();
        let (vec, area) = total_area(&all, &tris);
        assert_eq!(tris.len(), 8);
        assert!((area - 11.0).abs() < 1e-9, "area {area}");
        assert!((vec[1] + 11.0).abs() < 1e-9, "normal sum {vec:?}");
    }

    #[test]
    fn non_planar_ring_still_triangulates() {
        let ring = [
            [0.0, 0.0, 0.0],
            [10.0, 0.0, 0.1],
            [10.0, 10.0, -0.1],
            [0.0, 10.0, 0.05],
        ];
        let tris = triangulate_3d(&[&ring]);
        assert_eq!(tris.len(), 2);
        let (vec, _) = total_area(&ring, &tris);
        assert!(vec[2] > 99.0);
    }

    #[test]
    fn degenerate_rings_give_nothing() {
        assert!(triangulate_3d(&[]).is_empty());
        let line = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        assert!(triangulate_3d(&[&line]).is_empty());
    }
}
