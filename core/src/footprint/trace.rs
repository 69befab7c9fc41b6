//! Outlines of labelled raster components: cell edges between a component
//! and anything else, linked into rings (exteriors counter-clockwise, holes
//! clockwise), holes kept.

use std::collections::HashMap;

use geo::{Coord, LineString, MultiPolygon, Polygon};

/// A closed ring of grid vertices (corners only).
type Ring = Vec<(i64, i64)>;

/// Directions of unit edges, counter-clockwise: +x, +y, −x, −y.
const STEP: [(i64, i64); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];

/// The outline of every label `1..=n` of a `nx × ny` grid (index `j * nx + i`),
/// as polygons in world xy (`lo + cell * vertex`). Labels must not touch the
/// grid border. Entry `l - 1` holds label `l`.
pub fn trace(
    label: &[u32],
    nx: usize,
    ny: usize,
    n: u32,
    lo: [f64; 2],
    cell: f64,
) -> Vec<MultiPolygon<f64>> {
    // Directed edges with the component on their left, per label.
    let mut edges: Vec<Vec<((i64, i64), u8)>> = vec![Vec::new(); n as usize];
    for j in 0..ny {
        for i in 0..nx {
            let l = label[j * nx + i];
            if l == 0 {
                continue;
            }
            let other = |di: i64, dj: i64| {
                let (x, y) = (i as i64 + di, j as i64 + dj);
                if x < 0 || y < 0 || x as usize >= nx || y as usize >= ny {
                    return true;
                }
                label[y as usize * nx + x as usize] != l
            };
            let (x, y) = (i as i64, j as i64);
            let e = &mut edges[(l - 1) as usize];
            if other(0, -1) {
                e.push(((x, y), 0));
            }
            if other(1, 0) {
                e.push(((x + 1, y), 1));
            }
            if other(0, 1) {
                e.push(((x + 1, y + 1), 2));
            }
            if other(-1, 0) {
                e.push(((x, y + 1), 3));
            }
        }
    }
    edges.iter().map(|e| polygons(&link(e), lo, cell)).collect()
}

/// Links directed unit edges into closed vertex rings; at a vertex with two
/// ways on, the left turn wins, which keeps diagonal neighbours apart.
fn link(edges: &[((i64, i64), u8)]) -> Vec<Vec<(i64, i64)>> {
    let mut out_of: HashMap<(i64, i64), Vec<(usize, u8)>> = HashMap::new();
    for (k, &(start, dir)) in edges.iter().enumerate() {
        out_of.entry(start).or_default().push((k, dir));
    }
    let mut used = vec![false; edges.len()];
    let mut rings = Vec::new();
    for first in 0..edges.len() {
        if used[first] {
            continue;
        }
        let mut ring = Vec::new();
        let mut k = first;
        loop {
            used[k] = true;
            let (start, dir) = edges[k];
            let (dx, dy) = STEP[dir as usize];
            let end = (start.0 + dx, start.1 + dy);
            if ring.last().is_none_or(|&(_, d)| d != dir) {
                ring.push((start, dir));
            }
            let next = out_of.get(&end).and_then(|outs| {
                [1u8, 0, 3]
                    .iter()
                    .map(|turn| (dir + turn) % 4)
                    .find_map(|want| outs.iter().find(|&&(m, d)| d == want && !used[m]))
                    .map(|&(m, _)| m)
            });
            match next {
                Some(m) => k = m,
                None => break,
            }
        }
        // The first corner may continue the last run.
        if ring.len() > 1 && ring.first().map(|r| r.1) == ring.last().map(|r| r.1) {
            ring.remove(0);
        }
        if ring.len() >= 3 {
            rings.push(ring.into_iter().map(|(p, _)| p).collect());
        }
    }
    rings
}

fn signed_area2(r: &[(i64, i64)]) -> i64 {
    let n = r.len();
    (0..n)
        .map(|k| {
            let (a, b) = (r[k], r[(k + 1) % n]);
            a.0 * b.1 - b.0 * a.1
        })
        .sum()
}

/// Whether `p` lies inside the vertex ring `r`.
fn inside(r: &[(i64, i64)], p: (f64, f64)) -> bool {
    let points: Vec<[f64; 2]> = r.iter().map(|&(x, y)| [x as f64, y as f64]).collect();
    crate::geom::ring::contains(&points, [p.0, p.1])
}

/// Exteriors (positive area) with the holes (negative) that lie inside them.
fn polygons(rings: &[Ring], lo: [f64; 2], cell: f64) -> MultiPolygon<f64> {
    let (outer, holes): (Vec<&Ring>, Vec<&Ring>) = rings.iter().partition(|r| signed_area2(r) > 0);
    let mut owned: Vec<Vec<&Ring>> = vec![Vec::new(); outer.len()];
    for h in holes {
        // A point just left of the hole's first edge lies in the component.
        let (a, b) = (h[0], h[1]);
        let (dx, dy) = ((b.0 - a.0).signum() as f64, (b.1 - a.1).signum() as f64);
        let p = (
            a.0 as f64 + 0.5 * dx - 0.25 * dy,
            a.1 as f64 + 0.5 * dy + 0.25 * dx,
        );
        let owner = outer
            .iter()
            .enumerate()
            .filter(|(_, o)| inside(o, p))
            .min_by_key(|(_, o)| signed_area2(o))
            .map(|(k, _)| k);
        if let Some(k) = owner {
            owned[k].push(h);
        }
    }
    let ls = |r: &Vec<(i64, i64)>| {
        LineString::new(
            r.iter()
                .map(|&(x, y)| Coord {
                    x: lo[0] + x as f64 * cell,
                    y: lo[1] + y as f64 * cell,
                })
                .collect(),
        )
    };
    outer
        .iter()
        .zip(owned)
        .map(|(o, hs)| Polygon::new(ls(o), hs.into_iter().map(ls).collect()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::Area;

    fn grid(rows: &[&str]) -> (Vec<u32>, usize, usize) {
        let ny = rows.len();
        let nx = rows[0].len();
        let mut l = vec![0; nx * ny];
        // Row 0 of the picture is the top (largest j).
        for (r, row) in rows.iter().enumerate() {
            for (i, ch) in row.chars().enumerate() {
                l[(ny - 1 - r) * nx + i] = ch.to_digit(10).unwrap_or(0);
            }
        }
        (l, nx, ny)
    }

    #[test]
    fn ring_with_hole_and_diagonal_touch() {
        let (l, nx, ny) = grid(&[
            "0000000", //
            "0111000", //
            "0101000", //
            "0111000", //
            "0000100", //
            "0000000",
        ]);
        let out = trace(&l, nx, ny, 1, [0.0, 0.0], 1.0);
        let mp = &out[0];
        // The 3×3 ring (8 cells, one hole) and the diagonal cell stay apart.
        assert_eq!(mp.0.len(), 2);
        assert!((mp.unsigned_area() - 9.0).abs() < 1e-9);
        let holes: usize = mp.0.iter().map(|p| p.interiors().len()).sum();
        assert_eq!(holes, 1);
    }

    #[test]
    fn two_labels_side_by_side() {
        let (l, nx, ny) = grid(&["00000", "01220", "01220", "00000"]);
        let out = trace(&l, nx, ny, 2, [10.0, 20.0], 0.5);
        assert!((out[0].unsigned_area() - 0.5).abs() < 1e-9);
        assert!((out[1].unsigned_area() - 1.0).abs() < 1e-9);
        // Corner simplification: a rectangle has 4 vertices.
        assert_eq!(out[1].0[0].exterior().0.len(), 5);
    }
}
