//! A given footprint's outline kept exactly: the partition's outer
//! boundary (the chains with the outside on one side), traced on the raster
//! and only fitted to the footprint's lines, is replaced by the footprint's
//! own rings, and the nodes where roof boundaries meet it move onto them.
//! Two footprints sharing a wall then give two models sharing it, vertex
//! for vertex (issue 48: terraced houses without gaps or overlaps).

use geo::MultiPolygon;

use super::partition::Partition;

/// A partition ring farther than this (m) from every footprint ring at
/// some vertex is not that ring traced (a part the raster lost or merged):
/// it keeps its traced shape. Half a cell of rasterisation plus the 0.45 m
/// simplification, with room.
const MAX_MOVE_M: f64 = 1.0;

/// A node this close (m) to a footprint corner moves onto the corner, so
/// no wall a few millimetres long is left beside it.
const SNAP_M: f64 = 0.05;

/// What [`follow_footprint`] did to a partition's outside rings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct Followed {
    /// Rings now on the footprint.
    pub rings: usize,
    /// Rings kept as traced (no footprint ring matched, or the nodes along
    /// it would not keep their order).
    pub kept: usize,
}

/// Replaces each outside ring of `p` by the footprint ring it traces (see
/// the module docs); the whole change is undone when it would make two
/// boundaries cross.
pub(crate) fn follow_footprint(p: &mut Partition, footprint: &MultiPolygon<f64>) -> Followed {
    let before = p.clone();
    let fr = footprint_rings(footprint);
    let outside = p.rings(0);
    let mut out = Followed::default();
    // Which footprint ring each outside ring traces, when one does alone.
    let best: Vec<Option<usize>> = outside.iter().map(|r| nearest_ring(p, r, &fr)).collect();
    for (k, ring) in outside.iter().enumerate() {
        let unique = best[k].filter(|&f| best.iter().filter(|b| **b == Some(f)).count() == 1);
        let done = unique.is_some_and(|f| replace_ring(p, ring, &fr[f]));
        if done {
            out.rings += 1;
        } else {
            out.kept += 1;
        }
    }
    if out.rings > 0 && crosses(p) {
        *p = before;
        out.kept += out.rings;
        out.rings = 0;
    }
    out
}

/// The footprint's rings, open (last vertex not repeated).
fn footprint_rings(mp: &MultiPolygon<f64>) -> Vec<Vec<[f64; 2]>> {
    mp.0.iter()
        .flat_map(|p| std::iter::once(p.exterior()).chain(p.interiors()))
        .map(|ls| {
            let mut v: Vec<[f64; 2]> = ls.coords().map(|c| [c.x, c.y]).collect();
            if v.len() > 1 && v.first() == v.last() {
                v.pop();
            }
            v.dedup();
            v
        })
        .filter(|v| v.len() >= 3)
        .collect()
}

/// The footprint ring every vertex of `ring` lies within [`MAX_MOVE_M`] of,
/// the nearest when several do.
fn nearest_ring(p: &Partition, ring: &[u32], fr: &[Vec<[f64; 2]>]) -> Option<usize> {
    fr.iter()
        .enumerate()
        .filter_map(|(k, f)| {
            let worst = ring
                .iter()
                .map(|&v| project(f, p.verts[v as usize]).1)
                .fold(0.0, f64::max);
            (worst <= MAX_MOVE_M).then_some((k, worst))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|b| b.0)
}

/// Arc length along closed ring `f` of the point nearest `q`, and its distance.
fn project(f: &[[f64; 2]], q: [f64; 2]) -> (f64, f64) {
    let mut s0 = 0.0;
    let mut best = (0.0, f64::INFINITY);
    for k in 0..f.len() {
        let (a, b) = (f[k], f[(k + 1) % f.len()]);
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        let t = crate::geom::segment::project(q, a, b);
        let c = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
        let d = (q[0] - c[0]).hypot(q[1] - c[1]);
        if d < best.1 {
            best = (s0 + t * len, d);
        }
        s0 += len;
    }
    best
}

/// Cumulative arc length at each vertex of closed ring `f`, and its length.
fn arcs(f: &[[f64; 2]]) -> (Vec<f64>, f64) {
    let mut s = Vec::with_capacity(f.len());
    let mut acc = 0.0;
    for k in 0..f.len() {
        s.push(acc);
        let (a, b) = (f[k], f[(k + 1) % f.len()]);
        acc += (b[0] - a[0]).hypot(b[1] - a[1]);
    }
    (s, acc)
}

/// The point at arc length `s` along closed ring `f`.
fn at(f: &[[f64; 2]], arc: &[f64], total: f64, s: f64) -> [f64; 2] {
    let s = s.rem_euclid(total);
    let k = arc.partition_point(|&x| x <= s).saturating_sub(1);
    let (a, b) = (f[k], f[(k + 1) % f.len()]);
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    let t = if len > 0.0 { (s - arc[k]) / len } else { 0.0 };
    [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
}

/// Puts outside ring `ring` of `p` on footprint ring `f`: its nodes (chain
/// ends) onto their nearest points of `f` (or `f`'s corner within
/// [`SNAP_M`]), the chains between them onto `f`'s corners between those
/// points. False, with `p` untouched, when the nodes would not keep their
/// order along `f`.
fn replace_ring(p: &mut Partition, ring: &[u32], f: &[[f64; 2]]) -> bool {
    // Walk `f` the way `ring` goes round (the outside on its left).
    let mut f = f.to_vec();
    let area = |v: &[[f64; 2]]| {
        (0..v.len())
            .map(|k| {
                let (a, b) = (v[k], v[(k + 1) % v.len()]);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum::<f64>()
    };
    if (area(&f) > 0.0) != (p.ring_area(ring) > 0.0) {
        f.reverse();
    }
    let (arc, total) = arcs(&f);
    if total <= 0.0 {
        return false;
    }
    let in_ring: std::collections::HashSet<u32> = ring.iter().copied().collect();
    let chains: Vec<usize> = (0..p.chains.len())
        .filter(|&c| {
            let ch = &p.chains[c];
            (ch.left == 0 || ch.right == 0) && ch.verts.iter().all(|v| in_ring.contains(v))
        })
        .collect();
    let is_node = |v: u32| {
        chains
            .iter()
            .any(|&c| p.chains[c].verts.first() == Some(&v) || p.chains[c].verts.last() == Some(&v))
    };
    // Nodes in ring order with their arc length along `f`.
    let mut nodes: Vec<(u32, f64)> = Vec::new();
    for &v in ring {
        if !is_node(v) {
            continue;
        }
        let (mut s, d) = project(&f, p.verts[v as usize]);
        if d > MAX_MOVE_M {
            return false;
        }
        let q = at(&f, &arc, total, s);
        if let Some(k) = (0..f.len()).find(|&k| (f[k][0] - q[0]).hypot(f[k][1] - q[1]) <= SNAP_M) {
            s = arc[k];
        }
        nodes.push((v, s));
    }
    if nodes.is_empty() {
        return false;
    }
    // Strictly increasing round the ring, less than once round.
    let mut unwrapped = Vec::with_capacity(nodes.len());
    for (k, &(_, s)) in nodes.iter().enumerate() {
        let mut s = s;
        if let Some(&prev) = unwrapped.last() {
            while s <= prev + 1e-9 {
                s += total;
            }
        }
        if k > 0 && s >= unwrapped[0] + total - 1e-9 {
            return false;
        }
        unwrapped.push(s);
    }
    let s_of: std::collections::HashMap<u32, f64> = nodes.iter().copied().collect();
    for &(v, s) in &nodes {
        p.verts[v as usize] = if arc.contains(&s) {
            f[arc.iter().position(|&x| x == s).unwrap_or(0)]
        } else {
            at(&f, &arc, total, s)
        };
    }
    // The footprint's corners strictly after `from` up to strictly before
    // `to` going round (all of them but `from`'s own when they are equal).
    let between = |from: f64, to: f64| -> Vec<[f64; 2]> {
        let span = if to > from + 1e-9 {
            to - from
        } else {
            to - from + total
        };
        let mut v: Vec<(f64, [f64; 2])> = (0..f.len())
            .filter_map(|k| {
                let d = (arc[k] - from).rem_euclid(total);
                (d > 1e-9 && d < span - 1e-9).then_some((d, f[k]))
            })
            .collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        v.into_iter().map(|x| x.1).collect()
    };
    for &c in &chains {
        let ch = &p.chains[c];
        let (Some(&a), Some(&b)) = (ch.verts.first(), ch.verts.last()) else {
            continue;
        };
        let (Some(&sa), Some(&sb)) = (s_of.get(&a), s_of.get(&b)) else {
            continue;
        };
        // The ring runs along a chain with the outside on its left, against one with it on its right.
        let corners = if ch.left == 0 {
            between(sa, sb)
        } else {
            let mut v = between(sb, sa);
            v.reverse();
            v
        };
        let mut verts = vec![a];
        for q in corners {
            p.verts.push(q);
            verts.push((p.verts.len() - 1) as u32);
        }
        verts.push(b);
        p.chains[c].verts = verts;
    }
    true
}

/// Whether two segments of `p`'s chains cross or touch away from a shared vertex.
fn crosses(p: &Partition) -> bool {
    let segs = p.segments();
    let pt = |v: u32| p.verts[v as usize];
    for i in 0..segs.len() {
        for j in i + 1..segs.len() {
            let (a, b) = segs[i];
            let (c, d) = segs[j];
            let shared = [a, b].iter().filter(|v| **v == c || **v == d).count();
            if shared > 0 {
                // Two segments from one vertex overlap only when collinear and
                // pointing the same way.
                if shared == 2 {
                    return true;
                }
                let o = if a == c || a == d { a } else { b };
                let x = if o == a { b } else { a };
                let y = if o == c { d } else { c };
                if folded(pt(o), pt(x), pt(y)) {
                    return true;
                }
                continue;
            }
            if segments_meet(pt(a), pt(b), pt(c), pt(d)) {
                return true;
            }
        }
    }
    false
}

/// `o`→`x` and `o`→`y` run along each other.
pub(super) fn folded(o: [f64; 2], x: [f64; 2], y: [f64; 2]) -> bool {
    let (u, v) = ([x[0] - o[0], x[1] - o[1]], [y[0] - o[0], y[1] - o[1]]);
    let cr = u[0] * v[1] - u[1] * v[0];
    let dt = u[0] * v[0] + u[1] * v[1];
    cr.abs() <= 1e-12 * (u[0].hypot(u[1]) * v[0].hypot(v[1])).max(1e-300) && dt > 0.0
}

/// Closed segments a–b and c–d have a point in common.
pub(super) fn segments_meet(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let orient = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        let v = (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
        v.partial_cmp(&0.0).map_or(0, |o| o as i32)
    };
    let on = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        r[0] >= p[0].min(q[0])
            && r[0] <= p[0].max(q[0])
            && r[1] >= p[1].min(q[1])
            && r[1] <= p[1].max(q[1])
    };
    let (o1, o2) = (orient(a, b, c), orient(a, b, d));
    let (o3, o4) = (orient(c, d, a), orient(c, d, b));
    if o1 * o2 < 0 && o3 * o4 < 0 {
        return true;
    }
    (o1 == 0 && on(a, b, c))
        || (o2 == 0 && on(a, b, d))
        || (o3 == 0 && on(c, d, a))
        || (o4 == 0 && on(c, d, b))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::grid::GridFrame;
    use crate::reconstruct::partition::trace;
    use geo::{Area, polygon};

    /// A 10 × 6 footprint whose right wall is 0.3 m off the 0.5 m raster,
    /// with a notch the raster misses; two roof regions split at x = 5.
    #[test]
    fn the_outside_follows_the_footprint_and_the_ridge_end_stays_on_it() {
        let fp = MultiPolygon::new(vec![polygon![
            (x: 0.0, y: 0.0), (x: 10.3, y: 0.0), (x: 10.3, y: 6.0),
            (x: 6.1, y: 6.0), (x: 6.1, y: 5.8), (x: 5.9, y: 5.8), (x: 5.9, y: 6.0),
            (x: 0.0, y: 6.0)
        ]]);
        let grid = GridFrame {
            origin: [-1.0, -1.0],
            cell: 0.5,
            nx: 26,
            ny: 16,
        };
        let region: Vec<u32> = (0..grid.nx * grid.ny)
            .map(|c| {
                let q = grid.centre(c);
                if q[0] < 0.0 || q[0] > 10.3 || q[1] < 0.0 || q[1] > 6.0 {
                    0
                } else if q[0] < 5.0 {
                    1
                } else {
                    2
                }
            })
            .collect();
        let mut p = trace(&grid, &region, 2, 0.45);
        let done = follow_footprint(&mut p, &fp);
        assert_eq!(done, Followed { rings: 1, kept: 0 });
        let outline = crate::reconstruct::solid::outline(&p);
        assert!((outline.unsigned_area() - fp.unsigned_area()).abs() < 1e-9);
        // Every footprint corner is a vertex of the outline, exactly.
        for c in fp.0[0].exterior().coords() {
            assert!(p.verts.iter().any(|v| v[0] == c.x && v[1] == c.y), "{c:?}");
        }
        // The ridge between the two regions still ends on the outline.
        for r in [1, 2] {
            let a: f64 = p.rings(r).iter().map(|ring| p.ring_area(ring)).sum();
            assert!(a > 25.0, "region {r}: {a}");
        }
        let total: f64 = [1, 2]
            .iter()
            .flat_map(|&r| p.rings(r))
            .map(|ring| p.ring_area(&ring))
            .sum();
        assert!((total - fp.unsigned_area()).abs() < 1e-9, "{total}");
    }

    #[test]
    fn a_footprint_far_from_the_trace_leaves_it_as_traced() {
        let grid = GridFrame {
            origin: [0.0, 0.0],
            cell: 1.0,
            nx: 4,
            ny: 4,
        };
        let region: Vec<u32> = (0..16)
            .map(|c| u32::from((1..3).contains(&(c % 4)) && (1..3).contains(&(c / 4))))
            .collect();
        let mut p = trace(&grid, &region, 1, 0.1);
        let traced = p.clone();
        let far = MultiPolygon::new(vec![polygon![
            (x: 10.0, y: 10.0), (x: 12.0, y: 10.0), (x: 12.0, y: 12.0), (x: 10.0, y: 12.0)
        ]]);
        assert_eq!(
            follow_footprint(&mut p, &far),
            Followed { rings: 0, kept: 1 }
        );
        assert_eq!(p, traced);
    }
}
