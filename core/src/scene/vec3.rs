//! Small 3-vector helpers on `[f64; 3]` / `[f32; 3]`, shared by scene builders and metrics.
//!
//! Only IEEE-exact operations (+, −, ×, ÷, sqrt) are used, so results are the
//! same on every machine.

/// `a - b`.
pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a + b`.
pub fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `a * s`.
pub fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// Dot product.
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Cross product.
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Euclidean length.
pub fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// `a / |a|`, or `None` for a (near-)zero vector.
pub fn normalize(a: [f64; 3]) -> Option<[f64; 3]> {
    let n = norm(a);
    (n > 1e-12 && n.is_finite()).then(|| scale(a, 1.0 / n))
}

/// Widens an `f32` point.
pub fn wide(p: [f32; 3]) -> [f64; 3] {
    p.map(f64::from)
}

/// Narrows to `f32` (the scene's storage precision).
#[allow(clippy::cast_possible_truncation)]
pub fn narrow(p: [f64; 3]) -> [f32; 3] {
    p.map(|v| v as f32)
}

/// Twice the area vector of triangle `abc` (normal direction, length = 2 × area).
pub fn area_vector(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    cross(sub(b, a), sub(c, a))
}

/// Squared distance from `p` to the closest point of triangle `abc`.
///
/// Region-based closest point (vertex, edge or face), robust for degenerate
/// triangles (falls back to the edges).
pub fn point_triangle_dist2(p: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let ab = sub(b, a);
    let ac = sub(c, a);
    let n = cross(ab, ac);
    let nn = dot(n, n);
    if nn > 1e-18 {
        // Barycentric coordinates of p's projection on the plane.
        let ap = sub(p, a);
        let w_b = dot(cross(ap, ac), n) / nn;
        let w_c = dot(cross(ab, ap), n) / nn;
        if w_b >= 0.0 && w_c >= 0.0 && w_b + w_c <= 1.0 {
            let d = dot(ap, n);
            return d * d / nn;
        }
    }
    segment_dist2(p, a, b)
        .min(segment_dist2(p, b, c))
        .min(segment_dist2(p, c, a))
}

/// Squared distance from `p` to segment `ab`.
pub fn segment_dist2(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab = sub(b, a);
    let len2 = dot(ab, ab);
    let t = if len2 > 0.0 {
        (dot(sub(p, a), ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let q = add(a, scale(ab, t));
    let d = sub(p, q);
    dot(d, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_triangle_distance_regions() {
        let (a, b, c) = ([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]);
        assert!((point_triangle_dist2([0.5, 0.5, 3.0], a, b, c) - 9.0).abs() < 1e-12);
        assert!((point_triangle_dist2([-1.0, -1.0, 0.0], a, b, c) - 2.0).abs() < 1e-12);
        assert!((point_triangle_dist2([1.0, -2.0, 0.0], a, b, c) - 4.0).abs() < 1e-12);
        assert!((point_triangle_dist2([2.0, 2.0, 0.0], a, b, c) - 2.0).abs() < 1e-12);
        // Degenerate triangle: distance to its segment.
        assert!((point_triangle_dist2([1.0, 1.0, 0.0], a, b, b) - 1.0).abs() < 1e-12);
    }
}
