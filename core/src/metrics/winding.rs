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
        use crate::geom::fixtures::{BOX_FACES, UNIT_CUBE as C};
        let tris: Vec<[[f64; 3]; 3]> = BOX_FACES
            .iter()
            .flat_map(|q| [[C[q[0]], C[q[1]], C[q[2]]], [C[q[0]], C[q[2]], C[q[3]]]])
            .collect();
        assert!((winding_number([0.5, 0.5, 0.5], &tris) - 1.0).abs() < 1e-9);
        assert!(winding_number([1.5, 0.5, 0.5], &tris).abs() < 1e-9);
        // Without its bottom the cube still reads as mostly inside near its top.
        assert!(winding_number([0.5, 0.5, 0.9], &tris[2..]) > 0.5);
    }
}
