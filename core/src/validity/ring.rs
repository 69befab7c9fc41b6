//! The ring checks of one surface: 101, 102 and 104 (val3dity's ring level).

use super::codes::{CONSECUTIVE_POINTS_SAME, RING_SELF_INTERSECTION, TOO_FEW_POINTS};
use crate::scene::vec3::sub;
use geo::{Coord, Line, LineIntersection, line_intersection::line_intersection};

/// 101 when the ring has fewer than 3 distinct vertices, else 102 when two
/// consecutive ones (the last and the first too) are the same vertex or lie
/// within `snap` of each other. `ring` holds merged vertex ids.
pub(super) fn counts(ring: &[usize], vertices: &[[f64; 3]], snap: f64) -> Option<u16> {
    let mut distinct = ring.to_vec();
    distinct.sort_unstable();
    distinct.dedup();
    if distinct.len() < 3 {
        return Some(TOO_FEW_POINTS);
    }
    let n = ring.len();
    let repeats = (0..n).any(|i| same(ring[i], ring[(i + 1) % n], vertices, snap));
    repeats.then_some(CONSECUTIVE_POINTS_SAME)
}

/// 104 when the ring visits a vertex twice or, drawn in its plane (`flat`,
/// one point per vertex), crosses or touches itself.
pub(super) fn self_intersection(
    ring: &[usize],
    vertices: &[[f64; 3]],
    flat: &[[f64; 2]],
    snap: f64,
) -> Option<u16> {
    let n = ring.len();
    // Quadratic in the ring's length: building rings have tens of vertices.
    let revisits = (0..n).any(|i| (i + 1..n).any(|j| same(ring[i], ring[j], vertices, snap)));
    let crosses = (0..n).any(|i| (i + 1..n).any(|j| segments_meet(flat, i, j)));
    (revisits || crosses).then_some(RING_SELF_INTERSECTION)
}

/// Whether ring segments `i` (from vertex i to i+1) and `j > i` meet other
/// than at the vertex two neighbouring segments share.
fn segments_meet(flat: &[[f64; 2]], i: usize, j: usize) -> bool {
    let n = flat.len();
    let hit = line_intersection(segment(flat, i), segment(flat, j));
    let adjacent = j == i + 1 || (i == 0 && j == n - 1);
    match hit {
        None => false,
        // Neighbours always share their vertex; they fail only by folding back along each other.
        Some(LineIntersection::SinglePoint { .. }) => !adjacent,
        Some(LineIntersection::Collinear { .. }) => true,
    }
}

/// Ring segment `i` as a geo line.
pub(super) fn segment(flat: &[[f64; 2]], i: usize) -> Line<f64> {
    let a = flat[i];
    let b = flat[(i + 1) % flat.len()];
    Line::new(Coord { x: a[0], y: a[1] }, Coord { x: b[0], y: b[1] })
}

/// Whether merged vertices `a` and `b` are one position within `snap`.
fn same(a: usize, b: usize, vertices: &[[f64; 3]], snap: f64) -> bool {
    if a == b {
        return true;
    }
    let d = sub(vertices[a], vertices[b]);
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() <= snap
}
