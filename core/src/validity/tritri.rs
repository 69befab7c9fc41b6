//! Contact between triangles and segments in 3D, closed and with a distance
//! tolerance: the predicates of the shell self-intersection check (306).

use crate::geom::segment;
use crate::scene::vec3::{cross, dot, normalize, sub};

/// A triangle's corners.
pub(super) type Tri = [[f64; 3]; 3];

/// Whether closed triangles `a` and `b` come within `eps` of each other.
/// Complete: where two triangles meet, an edge of one meets the other.
pub(super) fn triangles_meet(a: &Tri, b: &Tri, eps: f64) -> bool {
    (0..3).any(|i| segment_meets_triangle(a[i], a[(i + 1) % 3], b, eps))
        || (0..3).any(|i| segment_meets_triangle(b[i], b[(i + 1) % 3], a, eps))
}

/// Whether segment `p → q` comes within `eps` of closed triangle `t`.
pub(super) fn segment_meets_triangle(p: [f64; 3], q: [f64; 3], t: &Tri, eps: f64) -> bool {
    let Some(n) = normalize(cross(sub(t[1], t[0]), sub(t[2], t[0]))) else {
        return false;
    };
    let dp = dot(sub(p, t[0]), n);
    let dq = dot(sub(q, t[0]), n);
    if (dp > eps && dq > eps) || (dp < -eps && dq < -eps) {
        return false;
    }
    if dp.abs() <= eps && dq.abs() <= eps {
        return coplanar_segment_meets(p, q, t, n, eps);
    }
    let s = (dp / (dp - dq)).clamp(0.0, 1.0);
    let x = [
        p[0] + s * (q[0] - p[0]),
        p[1] + s * (q[1] - p[1]),
        p[2] + s * (q[2] - p[2]),
    ];
    inside(x, t, n, eps)
}

/// Whether `x` (in the triangle's plane) lies in `t` or within `eps` of it.
fn inside(x: [f64; 3], t: &Tri, n: [f64; 3], eps: f64) -> bool {
    (0..3).all(|i| {
        let (a, b) = (t[i], t[(i + 1) % 3]);
        let e = sub(b, a);
        dot(cross(e, sub(x, a)), n) >= -eps * dot(e, e).sqrt()
    })
}

/// The coplanar case, in the coordinate plane the triangle's normal is most along.
fn coplanar_segment_meets(p: [f64; 3], q: [f64; 3], t: &Tri, n: [f64; 3], eps: f64) -> bool {
    let a = n.map(f64::abs);
    let (i, j) = if a[0] >= a[1] && a[0] >= a[2] {
        (1, 2)
    } else if a[1] >= a[2] {
        (2, 0)
    } else {
        (0, 1)
    };
    let flat = |v: [f64; 3]| [v[i], v[j]];
    let (p, q) = (flat(p), flat(q));
    let tri = t.map(flat);
    let in_tri = |x: [f64; 2]| {
        let s: Vec<f64> = (0..3)
            .map(|k| orient(tri[k], tri[(k + 1) % 3], x))
            .collect();
        s.iter().all(|&v| v >= 0.0) || s.iter().all(|&v| v <= 0.0)
    };
    in_tri(p) || in_tri(q) || (0..3).any(|k| segments_meet(p, q, tri[k], tri[(k + 1) % 3], eps))
}

/// Whether 2D segments `a → b` and `c → d` cross or come within `eps`.
fn segments_meet(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2], eps: f64) -> bool {
    let crosses =
        orient(a, b, c) * orient(a, b, d) < 0.0 && orient(c, d, a) * orient(c, d, b) < 0.0;
    crosses
        || segment::distance(a, c, d) <= eps
        || segment::distance(b, c, d) <= eps
        || segment::distance(c, a, b) <= eps
        || segment::distance(d, a, b) <= eps
}

/// Twice the signed area of the 2D triangle `a b c`.
fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}
