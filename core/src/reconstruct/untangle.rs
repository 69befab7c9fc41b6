//! Snapping moves boundary vertices onto wall and ridge lines. Where a
//! move carries a vertex across another boundary, or to within val3dity's
//! snapping of it, two roof rings cross or touch (104) and the solid is
//! rejected. Those moves are undone, vertex by vertex, back to the traced
//! positions (the raster's boundaries, which neither cross nor touch), so
//! the rest of the snapping stays.

use super::exterior::{folded, segments_meet};
use super::partition::Partition;

/// Two boundaries closer than this (m) away from a shared vertex touch:
/// twice val3dity's 1 mm snapping, so the written (1 mm) coordinates
/// cannot bring them together.
const NEAR_M: f64 = 0.002;

/// Untangles `p` (the partition `traced` after snapping, the same
/// vertices): of two segments that cross or touch, a vertex on the other
/// segment (any of the four when they cross inside) leaves its chain when
/// it lies inside a chain between roof parts (a jog the snapping left),
/// else goes back to its traced position; when that moves nothing, every
/// moved vertex of the two segments goes back. Repeats until
/// nothing is tangled or nothing changes; returns the number of changes.
pub(crate) fn undo_crossing_moves(p: &mut Partition, traced: &Partition) -> usize {
    if p.verts.len() != traced.verts.len() {
        return 0;
    }
    let mut changes = 0;
    for _ in 0..32 {
        let found = tangled(p);
        if found.is_empty() {
            break;
        }
        let moved = |p: &Partition, v: u32| p.verts[v as usize] != traced.verts[v as usize];
        let mut changed = false;
        for (pair, blamed) in found {
            let suspects = if blamed.is_empty() {
                pair.to_vec()
            } else {
                blamed
            };
            changed = suspects.iter().any(|&v| drop_inner(p, v));
            for group in [&suspects[..], &pair[..]] {
                if changed {
                    break;
                }
                let back: Vec<u32> = group.iter().copied().filter(|&v| moved(p, v)).collect();
                for &v in &back {
                    p.verts[v as usize] = traced.verts[v as usize];
                }
                changed = !back.is_empty();
            }
            if changed {
                // The rest were found on the old positions.
                break;
            }
        }
        if !changed {
            break;
        }
        changes += 1;
    }
    changes
}

/// Removes `v` from the chain between two roof parts it lies inside of
/// (not an end), when the chain keeps a segment (an open chain) or three
/// corners (a loop). The outline's corners stay.
fn drop_inner(p: &mut Partition, v: u32) -> bool {
    for c in p.chains.iter_mut().filter(|c| c.left != 0 && c.right != 0) {
        let n = c.verts.len();
        let closed = n > 1 && c.verts[0] == c.verts[n - 1];
        let Some(k) = (1..n.saturating_sub(1)).find(|&k| c.verts[k] == v) else {
            continue;
        };
        if n > if closed { 4 } else { 2 } {
            c.verts.remove(k);
            return true;
        }
        return false;
    }
    false
}

/// Every pair of segments of `p`'s chains that cross or touch away from a
/// shared vertex (or run along each other from one): the segments' four
/// vertices, and those of them found on or across the other segment.
pub(crate) fn tangled(p: &Partition) -> Vec<([u32; 4], Vec<u32>)> {
    let segs = p.segments();
    let pt = |v: u32| p.verts[v as usize];
    let bbox = |(a, b): (u32, u32)| {
        let (a, b) = (pt(a), pt(b));
        [
            a[0].min(b[0]),
            a[1].min(b[1]),
            a[0].max(b[0]),
            a[1].max(b[1]),
        ]
    };
    let boxes: Vec<[f64; 4]> = segs.iter().map(|&s| bbox(s)).collect();
    let apart = |u: [f64; 4], w: [f64; 4]| {
        u[0] > w[2] + NEAR_M || w[0] > u[2] + NEAR_M || u[1] > w[3] + NEAR_M || w[1] > u[3] + NEAR_M
    };
    let mut out = Vec::new();
    for i in 0..segs.len() {
        for j in i + 1..segs.len() {
            if apart(boxes[i], boxes[j]) {
                continue;
            }
            let ((a, b), (c, d)) = (segs[i], segs[j]);
            if let Some(blamed) = pair_tangled(p, (a, b), (c, d)) {
                out.push(([a, b, c, d], blamed));
            }
        }
    }
    out
}

/// Whether segments a–b and c–d cross or touch (see [`tangled`]), and
/// which of their vertices lie on the other (none when they cross inside).
fn pair_tangled(p: &Partition, (a, b): (u32, u32), (c, d): (u32, u32)) -> Option<Vec<u32>> {
    let pt = |v: u32| p.verts[v as usize];
    let near =
        |v: u32, s: u32, t: u32| crate::geom::segment::distance(pt(v), pt(s), pt(t)) < NEAR_M;
    let shared = [a, b].iter().filter(|v| **v == c || **v == d).count();
    let blamed: Vec<u32> = match shared {
        2 => return Some(Vec::new()),
        1 => {
            let o = if a == c || a == d { a } else { b };
            let x = if o == a { b } else { a };
            let y = if o == c { d } else { c };
            if folded(pt(o), pt(x), pt(y)) {
                return Some(vec![x, y]);
            }
            [(x, y), (y, x)]
                .into_iter()
                .filter(|&(u, w)| near(u, o, w))
                .map(|(u, _)| u)
                .collect()
        }
        _ => {
            let on: Vec<u32> = [(a, c, d), (b, c, d), (c, a, b), (d, a, b)]
                .into_iter()
                .filter(|&(v, s, t)| near(v, s, t))
                .map(|(v, _, _)| v)
                .collect();
            if on.is_empty() && segments_meet(pt(a), pt(b), pt(c), pt(d)) {
                return Some(Vec::new());
            }
            on
        }
    };
    (!blamed.is_empty()).then_some(blamed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reconstruct::partition::Chain;

    /// Two regions side by side on a 4 × 2 block, split at x = 2 by a chain
    /// with an inner vertex; `inner` is that vertex's position.
    fn block(inner: [f64; 2]) -> Partition {
        let chain = |verts: Vec<u32>, left, right| Chain { verts, left, right };
        Partition {
            verts: vec![
                [2.0, 0.0],
                [2.0, 2.0],
                inner,
                [4.0, 0.0],
                [4.0, 2.0],
                [0.0, 2.0],
                [0.0, 0.0],
            ],
            chains: vec![
                chain(vec![0, 2, 1], 1, 2),
                chain(vec![0, 3, 4, 1], 2, 0),
                chain(vec![1, 5, 6, 0], 1, 0),
            ],
            regions: 2,
        }
    }

    #[test]
    fn a_vertex_snapped_across_a_boundary_leaves_it_and_the_rest_stays() {
        let traced = block([2.0, 1.0]);
        assert!(tangled(&traced).is_empty());
        // Snapped past the right wall (x = 4): the chain crosses it.
        let mut p = block([4.5, 1.0]);
        p.verts[3] = [4.1, 0.0]; // a corner moved that crosses nothing
        assert!(!tangled(&p).is_empty());
        assert!(undo_crossing_moves(&mut p, &traced) > 0);
        assert!(tangled(&p).is_empty());
        assert_eq!(
            p.chains[0].verts,
            vec![0, 1],
            "the inner vertex left its chain"
        );
        assert_eq!(p.verts[3], [4.1, 0.0], "a move that crosses nothing stays");
        // A vertex 1 mm from the other boundary touches it too.
        let mut q = block([3.999, 1.0]);
        assert!(!tangled(&q).is_empty());
        undo_crossing_moves(&mut q, &traced);
        assert!(tangled(&q).is_empty());
    }
}
