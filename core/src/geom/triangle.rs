//! A triangle's plane over the plan: the height above a point in its
//! projection (barycentric), for draping points onto meshes.

/// The z of triangle `t` above `(x, y)`, when `(x, y)` lies in its xy
/// projection (within `eps` in barycentric terms); `None` outside it or for
/// a triangle standing vertical.
pub fn height_over(t: &[[f64; 3]; 3], x: f64, y: f64, eps: f64) -> Option<f64> {
    let [a, b, c] = *t;
    let det = (b[1] - c[1]) * (a[0] - c[0]) + (c[0] - b[0]) * (a[1] - c[1]);
    if det.abs() < 1e-12 {
        return None;
    }
    let l1 = ((b[1] - c[1]) * (x - c[0]) + (c[0] - b[0]) * (y - c[1])) / det;
    let l2 = ((c[1] - a[1]) * (x - c[0]) + (a[0] - c[0]) * (y - c[1])) / det;
    let l3 = 1.0 - l1 - l2;
    (l1 >= -eps && l2 >= -eps && l3 >= -eps).then(|| l1 * a[2] + l2 * b[2] + l3 * c[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inside_on_the_plane_outside_none_vertical_none() {
        let t = [[0.0, 0.0, 1.0], [4.0, 0.0, 5.0], [0.0, 4.0, 1.0]];
        assert_eq!(height_over(&t, 1.0, 1.0, 0.0), Some(2.0));
        assert_eq!(height_over(&t, 3.0, 3.0, 0.0), None);
        let wall = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, 3.0]];
        assert_eq!(height_over(&wall, 0.5, 0.0, 0.0), None);
    }
}
