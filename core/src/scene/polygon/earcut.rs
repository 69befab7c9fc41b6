//! Ear clipping of a 2D polygon with holes (holes bridged into the outer ring).

/// Merged rings longer than this are fanned instead of ear-clipped (keeps the
/// quadratic clipper bounded on absurd input).
const MAX_CLIP_VERTICES: usize = 4000;

/// Triangulates a polygon given as rings of indices into `points`: the first
/// ring is the outer boundary, the others are holes (either orientation).
///
/// Triangles index into `points` and turn counter-clockwise. Indices out of
/// range, non-finite points and repeated consecutive points are ignored;
/// holes outside the outer ring are dropped.
pub fn triangulate_2d(points: &[[f64; 2]], rings: &[Vec<usize>]) -> Vec<[usize; 3]> {
    let mut cleaned = rings.iter().map(|r| clean_ring(points, r));
    let Some(mut outer) = cleaned.next() else {
        return Vec::new();
    };
    let outer_area = signed_area(points, &outer);
    if outer.len() < 3 || outer_area == 0.0 {
        return Vec::new();
    }
    if outer_area < 0.0 {
        outer.reverse();
    }
    let mut holes: Vec<Vec<usize>> = cleaned
        .filter_map(|mut h| {
            let a = signed_area(points, &h);
            if h.len() < 3 || a == 0.0 {
                return None;
            }
            if a > 0.0 {
                h.reverse();
            }
            Some(h)
        })
        .collect();
    // Rightmost holes first, so each bridge sees the holes already merged.
    holes.sort_by(|a, b| max_x(points, b).total_cmp(&max_x(points, a)));
    for hole in &holes {
        bridge_hole(points, &mut outer, hole);
    }
    clip(points, &outer)
}

fn clean_ring(points: &[[f64; 2]], ring: &[usize]) -> Vec<usize> {
    let mut out: Vec<usize> = Vec::with_capacity(ring.len());
    for &i in ring {
        let Some(p) = points.get(i) else { continue };
        if !p.iter().all(|v| v.is_finite()) {
            continue;
        }
        if out.last().is_some_and(|&q| points[q] == *p) {
            continue;
        }
        out.push(i);
    }
    while out.len() > 1 && out.first().map(|&i| points[i]) == out.last().map(|&i| points[i]) {
        out.pop();
    }
    out
}

fn signed_area(points: &[[f64; 2]], ring: &[usize]) -> f64 {
    let n = ring.len();
    let mut s = 0.0;
    for k in 0..n {
        let a = points[ring[k]];
        let b = points[ring[(k + 1) % n]];
        s += a[0] * b[1] - b[0] * a[1];
    }
    s / 2.0
}

fn max_x(points: &[[f64; 2]], ring: &[usize]) -> f64 {
    ring.iter()
        .map(|&i| points[i][0])
        .fold(f64::NEG_INFINITY, f64::max)
}

/// Twice the signed area of `pqr`: positive for a left (counter-clockwise) turn.
fn orient(p: [f64; 2], q: [f64; 2], r: [f64; 2]) -> f64 {
    (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
}

/// `p` inside or on the counter-clockwise triangle `abc`.
fn in_triangle(p: [f64; 2], a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> bool {
    orient(a, b, p) >= 0.0 && orient(b, c, p) >= 0.0 && orient(c, a, p) >= 0.0
}

/// Connects `hole` (clockwise) to `ring` (counter-clockwise) by a two-way
/// bridge from the hole's rightmost vertex to a ring vertex it can see.
fn bridge_hole(points: &[[f64; 2]], ring: &mut Vec<usize>, hole: &[usize]) {
    let Some(m_at) =
        (0..hole.len()).max_by(|&a, &b| points[hole[a]][0].total_cmp(&points[hole[b]][0]))
    else {
        return;
    };
    let m = points[hole[m_at]];
    let Some(target) = visible_vertex(points, ring, m) else {
        return;
    };
    let mut merged = Vec::with_capacity(ring.len() + hole.len() + 2);
    merged.extend_from_slice(&ring[..=target]);
    merged.extend((0..=hole.len()).map(|k| hole[(m_at + k) % hole.len()]));
    merged.push(ring[target]);
    merged.extend_from_slice(&ring[target + 1..]);
    *ring = merged;
}

/// The position in `ring` of a vertex visible from `m` (a point inside the
/// ring), found by casting a ray from `m` towards +x.
fn visible_vertex(points: &[[f64; 2]], ring: &[usize], m: [f64; 2]) -> Option<usize> {
    let n = ring.len();
    let mut best: Option<(f64, usize)> = None;
    for k in 0..n {
        let (a, b) = (points[ring[k]], points[ring[(k + 1) % n]]);
        // Edges with the interior on their left cross the ray going up.
        if !(a[1] <= m[1] && m[1] <= b[1] && a[1] < b[1]) {
            continue;
        }
        let x = a[0] + (m[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
        if x >= m[0] && best.is_none_or(|(bx, _)| x < bx) {
            best = Some((x, k));
        }
    }
    let (hit_x, k) = best?;
    let (a_at, b_at) = (k, (k + 1) % n);
    let hit = [hit_x, m[1]];
    let (a, b) = (points[ring[a_at]], points[ring[b_at]]);
    let mut chosen = if a == hit {
        a_at
    } else if b == hit || b[0] > a[0] {
        b_at
    } else {
        a_at
    };
    let p = points[ring[chosen]];
    if p != hit {
        // Vertices inside triangle (m, hit, p) may block the view of p: take
        // the one closest in angle to the ray instead.
        let (t0, t1, t2) = if orient(m, hit, p) >= 0.0 {
            (m, hit, p)
        } else {
            (m, p, hit)
        };
        let mut best_tan = tan_from(m, p);
        for (j, &i) in ring.iter().enumerate() {
            let r = points[i];
            if r == p || r[0] <= m[0] || !in_triangle(r, t0, t1, t2) {
                continue;
            }
            let tan = tan_from(m, r);
            let better = tan < best_tan || (tan == best_tan && r[0] < points[ring[chosen]][0]);
            if better && locally_inside(points, ring, j, m) {
                best_tan = tan;
                chosen = j;
            }
        }
    }
    // A vertex may appear twice (earlier bridges): use the copy whose wedge holds m.
    let target = points[ring[chosen]];
    let copy = (0..n).find(|&j| points[ring[j]] == target && locally_inside(points, ring, j, m));
    Some(copy.unwrap_or(chosen))
}

fn tan_from(m: [f64; 2], r: [f64; 2]) -> f64 {
    (r[1] - m[1]).abs() / (r[0] - m[0])
}

/// Whether `m` lies in the interior wedge of the ring at position `j`.
fn locally_inside(points: &[[f64; 2]], ring: &[usize], j: usize, m: [f64; 2]) -> bool {
    let n = ring.len();
    let a = points[ring[(j + n - 1) % n]];
    let v = points[ring[j]];
    let b = points[ring[(j + 1) % n]];
    if orient(a, v, b) >= 0.0 {
        orient(a, v, m) >= 0.0 && orient(v, b, m) >= 0.0
    } else {
        orient(a, v, m) >= 0.0 || orient(v, b, m) >= 0.0
    }
}

/// Ear clipping of one counter-clockwise ring (possibly with bridge seams).
fn clip(points: &[[f64; 2]], ring: &[usize]) -> Vec<[usize; 3]> {
    let n = ring.len();
    if n < 3 {
        return Vec::new();
    }
    if n > MAX_CLIP_VERTICES {
        return (1..n - 1)
            .map(|k| [ring[0], ring[k], ring[k + 1]])
            .collect();
    }
    let pos = |k: usize| points[ring[k]];
    let mut prev: Vec<usize> = (0..n).map(|k| (k + n - 1) % n).collect();
    let mut next: Vec<usize> = (0..n).map(|k| (k + 1) % n).collect();
    let mut out = Vec::with_capacity(n - 2);
    let mut remaining = n;
    let mut cur = 0;
    let mut misses = 0;
    while remaining > 3 {
        let (a, c) = (prev[cur], next[cur]);
        let ear = is_ear(&pos, &next, a, cur, c);
        if !ear {
            cur = c;
            misses += 1;
            if misses < remaining {
                continue;
            }
            // No proper ear anywhere (self-intersecting or degenerate input):
            // clip the first convex vertex, or this one.
            let mut probe = cur;
            for _ in 0..remaining {
                if orient(pos(prev[probe]), pos(probe), pos(next[probe])) > 0.0 {
                    break;
                }
                probe = next[probe];
            }
            cur = probe;
        }
        let (a, c) = (prev[cur], next[cur]);
        out.push([ring[a], ring[cur], ring[c]]);
        next[a] = c;
        prev[c] = a;
        remaining -= 1;
        misses = 0;
        cur = c;
    }
    out.push([ring[prev[cur]], ring[cur], ring[next[cur]]]);
    out
}

fn is_ear(pos: &impl Fn(usize) -> [f64; 2], next: &[usize], a: usize, b: usize, c: usize) -> bool {
    let (pa, pb, pc) = (pos(a), pos(b), pos(c));
    if orient(pa, pb, pc) <= 0.0 {
        return false;
    }
    let mut k = next[c];
    while k != a {
        let p = pos(k);
        if p != pa && p != pb && p != pc && in_triangle(p, pa, pb, pc) {
            return false;
        }
        k = next[k];
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(points: &[[f64; 2]], tris: &[[usize; 3]]) -> f64 {
        tris.iter()
            .map(|t| orient(points[t[0]], points[t[1]], points[t[2]]) / 2.0)
            .sum()
    }

    fn all_ccw(points: &[[f64; 2]], tris: &[[usize; 3]]) -> bool {
        tris.iter()
            .all(|t| orient(points[t[0]], points[t[1]], points[t[2]]) > 0.0)
    }

    #[test]
    fn l_shape_clockwise_input() {
        let pts = [
            [0.0, 0.0],
            [0.0, 4.0],
            [1.0, 4.0],
            [1.0, 1.0],
            [3.0, 1.0],
            [3.0, 0.0],
        ];
        let tris = triangulate_2d(&pts, &[vec![0, 1, 2, 3, 4, 5]]);
        assert_eq!(tris.len(), 4);
        assert!((area(&pts, &tris) - 6.0).abs() < 1e-12);
        assert!(all_ccw(&pts, &tris));
    }

    #[test]
    fn square_with_two_holes() {
        let mut pts = vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]];
        let mut rings = vec![vec![0, 1, 2, 3]];
        for (x, y) in [(2.0, 2.0), (6.0, 5.0)] {
            let s = pts.len();
            pts.extend([[x, y], [x + 2.0, y], [x + 2.0, y + 2.0], [x, y + 2.0]]);
            rings.push((s..s + 4).collect());
        }
        let tris = triangulate_2d(&pts, &rings);
        assert_eq!(tris.len(), 4 + 2 * 4 + 2 * 2 - 2);
        assert!((area(&pts, &tris) - 92.0).abs() < 1e-9);
        assert!(all_ccw(&pts, &tris));
    }

    #[test]
    fn holes_sharing_the_ray_line() {
        // Two holes at the same height: the left one bridges through the right one.
        let mut pts = vec![[0.0, 0.0], [20.0, 0.0], [20.0, 10.0], [0.0, 10.0]];
        let mut rings = vec![vec![0, 1, 2, 3]];
        for x in [3.0, 12.0] {
            let s = pts.len();
            pts.extend([[x, 4.0], [x + 3.0, 4.0], [x + 3.0, 6.0], [x, 6.0]]);
            rings.push((s..s + 4).collect());
        }
        let tris = triangulate_2d(&pts, &rings);
        assert!((area(&pts, &tris) - 188.0).abs() < 1e-9);
        assert!(all_ccw(&pts, &tris));
    }

    #[test]
    fn bad_input_never_panics() {
        let pts = [
            [0.0, 0.0],
            [1.0, 1.0],
            [1.0, 0.0],
            [0.0, 1.0],
            [f64::NAN, 0.0],
        ];
        // Bow tie (no net area), out-of-range and NaN indices.
        assert!(triangulate_2d(&pts, &[vec![0, 1, 2, 3, 4, 99]]).len() <= 2);
        let skew = [[0.0, 0.0], [4.0, 0.0], [0.0, 2.0], [4.0, 3.0], [0.0, 5.0]];
        assert!(triangulate_2d(&skew, &[vec![0, 1, 2, 3, 4]]).len() <= 3);
        assert!(triangulate_2d(&pts, &[vec![0, 0, 0]]).is_empty());
        assert!(triangulate_2d(&pts, &[]).is_empty());
        // A hole outside the polygon is dropped.
        let pts = [
            [0.0, 0.0],
            [1.0, 0.0],
            [0.0, 1.0],
            [5.0, 5.0],
            [6.0, 5.0],
            [5.0, 6.0],
        ];
        let tris = triangulate_2d(&pts, &[vec![0, 1, 2], vec![3, 4, 5]]);
        assert_eq!(tris.len(), 1);
    }

    #[test]
    fn collinear_vertices_are_kept() {
        let pts = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]];
        let tris = triangulate_2d(&pts, &[vec![0, 1, 2, 3, 4]]);
        assert_eq!(tris.len(), 3);
        assert!((area(&pts, &tris) - 2.0).abs() < 1e-12);
    }

    /// Vertices of `pts` lying inside an edge of `tris`: T-junctions, which
    /// leave a solid open along that edge.
    fn t_junctions(pts: &[[f64; 2]], tris: &[[[f64; 2]; 3]]) -> usize {
        let on_edge = |p: &[f64; 2]| {
            tris.iter().any(|t| {
                (0..3).any(|k| {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    let within =
                        (p[0] - a[0]) * (p[0] - b[0]) + (p[1] - a[1]) * (p[1] - b[1]) < 0.0;
                    orient(a, b, *p).abs() < 1e-12 && within
                })
            })
        };
        pts.iter().filter(|p| on_edge(p)).count()
    }

    /// Issue 51 asked for geo's earcut unless a measurement shows ours is
    /// needed. This is it: the reference scene's podium roof (a rectangle
    /// with its two towers' feet as holes, `scene::reference::solids`). geo
    /// 0.33 drops the hole corners that fall on a line with others, leaving
    /// T-junctions (swapped in, the reference podium and slab on pillars got
    /// 4 boundary edges each: not closed); ours keeps every vertex.
    #[test]
    fn geo_earcut_leaves_t_junctions_at_hole_corners_and_ours_does_not() {
        use geo::{LineString, Polygon, TriangulateEarcut};
        let rect =
            |x: f64, y: f64, w: f64, d: f64| vec![[x, y], [x + w, y], [x + w, y + d], [x, y + d]];
        let rings = [
            rect(0.0, 0.0, 10.0, 10.0),
            rect(2.0, 2.0, 3.0, 3.0),
            rect(7.0, 2.0, 2.0, 5.0),
        ];
        let pts: Vec<[f64; 2]> = rings.iter().flatten().copied().collect();
        let ls = |r: &Vec<[f64; 2]>| {
            LineString::from(r.iter().map(|p| (p[0], p[1])).collect::<Vec<_>>())
        };
        let raw =
            Polygon::new(ls(&rings[0]), rings[1..].iter().map(ls).collect()).earcut_triangles_raw();
        let geo: Vec<[[f64; 2]; 3]> = (raw.triangle_indices.chunks_exact(3))
            .map(|t| [0, 1, 2].map(|k| raw.vertices[t[k]]))
            .collect();
        assert!(
            t_junctions(&pts, &geo) > 0,
            "geo's earcut has no T-junction here now: swap to it (issue 51)"
        );
        let index_rings = [(0..4).collect(), (4..8).collect(), (8..12).collect()];
        let ours: Vec<[usize; 3]> = triangulate_2d(&pts, &index_rings);
        let ours_at: Vec<[[f64; 2]; 3]> = ours.iter().map(|t| t.map(|i| pts[i])).collect();
        assert_eq!(t_junctions(&pts, &ours_at), 0);
        assert!((area(&pts, &ours) - (100.0 - 9.0 - 10.0)).abs() < 1e-9);
    }
}

#[cfg(test)]
mod props {
    use super::*;

    proptest::proptest! {
        #[test]
        fn star_polygons_keep_their_area(radii in proptest::collection::vec(0.2f64..5.0, 3..40), hole in proptest::bool::ANY) {
            // A star-shaped polygon around the origin (angles from a rational
            // parametrisation of the circle), optionally with a small square hole.
            let n = radii.len();
            let mut pts: Vec<[f64; 2]> = radii
                .iter()
                .enumerate()
                .map(|(k, r)| {
                    let a = std::f64::consts::TAU * k as f64 / n as f64;
                    [r * a.cos(), r * a.sin()]
                })
                .collect();
            let mut rings = vec![(0..n).collect::<Vec<_>>()];
            let mut want = signed_area(&pts, &rings[0]);
            if hole && radii.iter().all(|&r| r > 0.5) {
                let s = pts.len();
                pts.extend([[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]]);
                rings.push((s..s + 4).collect());
                want -= 0.04;
            }
            let tris = triangulate_2d(&pts, &rings);
            let got: f64 = tris.iter().map(|t| orient(pts[t[0]], pts[t[1]], pts[t[2]]) / 2.0).sum();
            proptest::prop_assert!((got - want).abs() < 1e-9 * want.max(1.0), "area {} want {}", got, want);
            proptest::prop_assert!(tris.iter().all(|t| orient(pts[t[0]], pts[t[1]], pts[t[2]]) >= 0.0));
        }

        #[test]
        fn random_rings_never_panic(
            pts in proptest::collection::vec((-10.0f64..10.0, -10.0f64..10.0), 0..30),
            rings in proptest::collection::vec(proptest::collection::vec(0usize..35, 0..12), 0..4),
        ) {
            let pts: Vec<[f64; 2]> = pts.into_iter().map(|(x, y)| [x, y]).collect();
            let tris = triangulate_2d(&pts, &rings);
            proptest::prop_assert!(tris.iter().flatten().all(|&i| i < pts.len()));
        }
    }
}
