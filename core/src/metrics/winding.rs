//! Generalised winding number: is a point inside a (possibly leaky) solid?

use crate::scene::vec3::{cross, dot, norm, sub};

/// Winding number of the triangles around `p`: ≈ 1 inside a closed,
/// outward-oriented mesh, ≈ 0 outside, in between near holes of a leaky one.
pub fn winding_number(p: [f64; 3], tris: &[[[f64; 3]; 3]]) -> f64 {
    let mut omega = 0.0;
    for t in tris {
        let (a, b, c) = (sub(t[0], p), sub(t[1], p), sub(t[2], p));
        let (la, lb, lc) = (norm(a), norm(b), norm(c));
        let num = dot(a, cross(b, c));
        let den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
        omega += 2.0 * num.atan2(den);
    }
    omega / (4.0 * std::f64::consts::PI)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_cube_inside_and_outside() {
        let v = |x: f64, y: f64, z: f64| [x, y, z];
        let c = [
            v(0., 0., 0.),
            v(1., 0., 0.),
            v(1., 1., 0.),
            v(0., 1., 0.),
            v(0., 0., 1.),
            v(1., 0., 1.),
            v(1., 1., 1.),
            v(0., 1., 1.),
        ];
        let quads = [
            [0, 3, 2, 1],
            [4, 5, 6, 7],
            [0, 1, 5, 4],
            [1, 2, 6, 5],
            [2, 3, 7, 6],
            [3, 0, 4, 7],
        ];
        let tris: Vec<[[f64; 3]; 3]> = quads
            .iter()
            .flat_map(|q| [[c[q[0]], c[q[1]], c[q[2]]], [c[q[0]], c[q[2]], c[q[3]]]])
            .collect();
        assert!((winding_number([0.5, 0.5, 0.5], &tris) - 1.0).abs() < 1e-9);
        assert!(winding_number([1.5, 0.5, 0.5], &tris).abs() < 1e-9);
        // Without its bottom the cube still reads as mostly inside near its top.
        assert!(winding_number([0.5, 0.5, 0.9], &tris[2..]) > 0.5);
    }
}
