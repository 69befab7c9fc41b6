//! Clipping a triangle to an xy window (Sutherland–Hodgman), z interpolated
//! along the edges so the clipped piece lies in the triangle's plane.

use super::Window;

/// Below this area (m²) a clipped piece is a sliver and dropped.
const MIN_AREA: f64 = 1e-6;

/// The part of triangle `t` inside `w` as a convex polygon (counter-clockwise
/// as `t`), empty when nothing of it is inside.
pub fn clip_triangle(t: [[f64; 3]; 3], w: &Window) -> Vec<[f64; 3]> {
    if t.iter().all(|p| w.contains(p[0], p[1])) {
        return t.to_vec();
    }
    let mut poly = t.to_vec();
    // (axis, bound, keep the side ≥ bound?)
    for (axis, bound, above) in [
        (0, w.min[0], true),
        (0, w.max[0], false),
        (1, w.min[1], true),
        (1, w.max[1], false),
    ] {
        let inside = |p: &[f64; 3]| {
            if above {
                p[axis] >= bound
            } else {
                p[axis] <= bound
            }
        };
        let mut next = Vec::with_capacity(poly.len() + 1);
        for k in 0..poly.len() {
            let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
            match (inside(&p), inside(&q)) {
                (true, true) => next.push(q),
                (true, false) => next.push(crossing(p, q, axis, bound)),
                (false, true) => {
                    next.push(crossing(p, q, axis, bound));
                    next.push(q);
                }
                (false, false) => {}
            }
        }
        poly = next;
        if poly.is_empty() {
            break;
        }
    }
    poly
}

/// Where segment `pq` crosses `x[axis] = bound`. Computed from the
/// endpoints in a fixed order so the two triangles sharing an edge get the
/// very same point (no crack between clipped neighbours).
fn crossing(p: [f64; 3], q: [f64; 3], axis: usize, bound: f64) -> [f64; 3] {
    let (a, b) = if p < q { (p, q) } else { (q, p) };
    let d = b[axis] - a[axis];
    let s = if d == 0.0 { 0.0 } else { (bound - a[axis]) / d };
    let mut out = [0.0; 3];
    for k in 0..3 {
        out[k] = a[k] + (b[k] - a[k]) * s;
    }
    out[axis] = bound;
    out
}

/// A convex polygon as a fan of triangles (indices into it), slivers dropped.
pub fn fan(poly: &[[f64; 3]]) -> Vec<[usize; 3]> {
    (1..poly.len().saturating_sub(1))
        .filter(|&i| area_xyz(poly[0], poly[i], poly[i + 1]) >= MIN_AREA)
        .map(|i| [0, i, i + 1])
        .collect()
}

fn area_xyz(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let v = crate::scene::vec3::area_vector(a, b, c);
    crate::scene::vec3::norm(v) / 2.0
}
