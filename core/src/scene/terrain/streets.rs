//! Streets between clusters of buildings whose ground patches do not meet:
//! a city model of buildings spread over hundreds of metres (a sample of a
//! city, a campus, farmsteads) gets one piece of ground the vehicle can
//! drive from any building to any other, not an island per cluster.
//!
//! The streets are the edges of a minimum spanning tree over the footprint
//! boxes (Prim's algorithm, O(n²) box distances, O(n) memory) that join two
//! boxes whose patches (each box grown by the terrain's margin) are apart:
//! the shortest set of straight streets that connects every cluster.

use super::base::Footprint;

/// A straight street between two footprint boxes: its ends in plan (m).
pub type Street = [[f64; 2]; 2];

/// The streets that join every cluster of `footprints` whose boxes, grown by
/// `margin`, do not touch; each runs between the nearest points of two boxes.
pub fn streets(footprints: &[Footprint], margin: f64) -> Vec<Street> {
    let n = footprints.len();
    if n < 2 {
        return Vec::new();
    }
    let mut in_tree = vec![false; n];
    // For each box outside the tree: its gap to the tree and the tree box it is nearest.
    let mut best: Vec<(f64, usize)> = vec![(f64::INFINITY, 0); n];
    let mut out = Vec::new();
    let mut next = 0;
    for step in 0..n {
        in_tree[next] = true;
        let (gap, from) = best[next];
        if step > 0 && gap > 2.0 * margin {
            out.push(nearest_points(&footprints[from], &footprints[next]));
        }
        let added = &footprints[next];
        let mut pick: Option<(f64, usize)> = None;
        for (j, f) in footprints.iter().enumerate() {
            if in_tree[j] {
                continue;
            }
            let d = box_gap(added, f);
            if d < best[j].0 {
                best[j] = (d, next);
            }
            if pick.is_none_or(|(g, _)| best[j].0 < g) {
                pick = Some((best[j].0, j));
            }
        }
        match pick {
            Some((_, j)) => next = j,
            None => break,
        }
    }
    out
}

/// The plan distance between two boxes (0 when they overlap).
fn box_gap(a: &Footprint, b: &Footprint) -> f64 {
    let d = [0, 1].map(|k| (a.min[k] - b.max[k]).max(b.min[k] - a.max[k]).max(0.0));
    d[0].hypot(d[1])
}

/// A pair of nearest points of boxes `a` and `b` (the middle of their
/// overlap along an axis where they overlap).
fn nearest_points(a: &Footprint, b: &Footprint) -> Street {
    let mut pa = [0.0; 2];
    let mut pb = [0.0; 2];
    for k in 0..2 {
        if a.max[k] < b.min[k] {
            (pa[k], pb[k]) = (a.max[k], b.min[k]);
        } else if b.max[k] < a.min[k] {
            (pa[k], pb[k]) = (a.min[k], b.max[k]);
        } else {
            let mid = (a.min[k].max(b.min[k]) + a.max[k].min(b.max[k])) / 2.0;
            (pa[k], pb[k]) = (mid, mid);
        }
    }
    [pa, pb]
}

/// Length of a street, m.
pub fn length(s: &Street) -> f64 {
    (s[1][0] - s[0][0]).hypot(s[1][1] - s[0][1])
}

/// The grid cells `(j, i)` (cell `cell`, origin `o`) whose centre lies
/// within `width / 2` of street `s`.
pub fn street_cells(s: &Street, width: f64, cell: f64, o: [f64; 2]) -> Vec<(i64, i64)> {
    let half = width / 2.0;
    let index = |v: f64, o: f64| ((v - o) / cell).floor() as i64;
    let (lo, hi) = (
        [0, 1].map(|k| s[0][k].min(s[1][k]) - half),
        [0, 1].map(|k| s[0][k].max(s[1][k]) + half),
    );
    let mut out = Vec::new();
    for j in index(lo[1], o[1])..=index(hi[1], o[1]) {
        for i in index(lo[0], o[0])..=index(hi[0], o[0]) {
            let c = [
                o[0] + (i as f64 + 0.5) * cell,
                o[1] + (j as f64 + 0.5) * cell,
            ];
            let (p, _) = crate::geom::segment::closest(c, s[0], s[1]);
            if (p[0] - c[0]).hypot(p[1] - c[1]) <= half {
                out.push((j, i));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fp(x: f64, y: f64) -> Footprint {
        Footprint {
            min: [x, y],
            max: [x + 10.0, y + 10.0],
            base: 0.0,
        }
    }

    #[test]
    fn clusters_far_apart_are_joined_by_the_shortest_streets() {
        // Two clusters of two 500 m apart in x, a third 400 m up in y.
        let fps = [
            fp(0.0, 0.0),
            fp(20.0, 0.0),
            fp(520.0, 0.0),
            fp(540.0, 0.0),
            fp(0.0, 410.0),
        ];
        let s = streets(&fps, 30.0);
        assert_eq!(s.len(), 2, "{s:?}");
        let mut lengths: Vec<f64> = s.iter().map(length).collect();
        lengths.sort_by(f64::total_cmp);
        // Box edges 490 m apart in x (30..520), 400 m in y (10..410).
        assert!((lengths[0] - 400.0).abs() < 1e-9, "{lengths:?}");
        assert!((lengths[1] - 490.0).abs() < 1e-9, "{lengths:?}");
        // Patches that touch need none; one building needs none.
        assert!(streets(&fps[..2], 30.0).is_empty());
        assert!(streets(&fps[..1], 30.0).is_empty());
        assert!(streets(&[], 30.0).is_empty());
    }

    #[test]
    fn a_street_covers_the_cells_along_it() {
        let s = [[0.0, 0.0], [100.0, 0.0]];
        let cells = street_cells(&s, 10.0, 2.0, [-50.0, -50.0]);
        // 50 cells along x, 6 across (centres at y = ±1, ±3, ±5), and the rounded ends.
        assert!((300..=340).contains(&cells.len()), "{}", cells.len());
        assert!(cells.contains(&(25, 25 + 25)));
        assert!(!cells.contains(&(25 + 5, 50)));
    }
}
