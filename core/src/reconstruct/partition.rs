//! The footprint raster, each cell labelled with a region (0 = outside),
//! turned into a planar partition: boundary chains shared by the two
//! regions they separate, simplified once so both sides keep agreeing.
//! That sharing is what makes the solid built on it watertight.

/// A traced boundary: its grid vertices and the regions on its left and right.
type Traced = (Vec<(isize, isize)>, u32, u32);

use crate::geom::grid::GridFrame;

/// One boundary between two regions: its vertices in order, the region on
/// its left and on its right (0 = outside).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Chain {
    /// Vertex indices; a closed loop repeats its first vertex at the end.
    pub verts: Vec<u32>,
    /// Region on the left when walking the chain.
    pub left: u32,
    /// Region on the right.
    pub right: u32,
}

/// Regions 1..=n and the chains between them (and the outside, 0).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Partition {
    /// Vertex positions, local frame.
    pub verts: Vec<[f64; 2]>,
    /// Boundary chains.
    pub chains: Vec<Chain>,
    /// Number of regions (not counting the outside).
    pub regions: u32,
}

/// Merges regions smaller than `min_cells` into their most common
/// neighbour, then removes diagonal-only contacts, and returns the
/// connected components as regions 1..=n with the input label of each
/// (index r - 1). `labels`: 0 outside, other values any plane code.
pub(crate) fn regions(
    grid: &GridFrame,
    labels: &mut [u32],
    min_cells: usize,
) -> (Vec<u32>, Vec<u32>) {
    for _ in 0..4 {
        let (comp, sizes, code) = components(grid, labels);
        let mut changed = false;
        let mut border = vec![false; sizes.len()];
        for j in 0..grid.ny {
            for i in 0..grid.nx {
                if i == 0 || j == 0 || i + 1 == grid.nx || j + 1 == grid.ny {
                    border[comp[j * grid.nx + i] as usize] = true;
                }
            }
        }
        for (c, &size) in sizes.iter().enumerate() {
            // Small parts merge; so do small holes, but not the open outside.
            if size >= min_cells || (code[c] == 0 && border[c]) {
                continue;
            }
            let mut votes: Vec<(u32, usize)> = Vec::new();
            for idx in 0..labels.len() {
                if comp[idx] != c as u32 {
                    continue;
                }
                for nb in grid.neighbours(idx) {
                    let l = labels[nb];
                    if l != 0 && comp[nb] != c as u32 {
                        match votes.iter_mut().find(|v| v.0 == l) {
                            Some(v) => v.1 += 1,
                            None => votes.push((l, 1)),
                        }
                    }
                }
            }
            if let Some(&(l, _)) = votes.iter().max_by_key(|v| v.1) {
                for idx in 0..labels.len() {
                    if comp[idx] == c as u32 {
                        labels[idx] = l;
                    }
                }
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    remove_diagonals(grid, labels);
    let (comp, _, code) = components(grid, labels);
    let mut region_of_comp = vec![0u32; code.len()];
    let mut region_code = Vec::new();
    for (c, &l) in code.iter().enumerate() {
        if l != 0 {
            region_code.push(l);
            region_of_comp[c] = region_code.len() as u32;
        }
    }
    let region: Vec<u32> = comp.iter().map(|&c| region_of_comp[c as usize]).collect();
    (region, region_code)
}

/// 4-connected components of equal labels: component per cell, sizes, label.
fn components(grid: &GridFrame, labels: &[u32]) -> (Vec<u32>, Vec<usize>, Vec<u32>) {
    let mut comp = vec![u32::MAX; labels.len()];
    let (mut sizes, mut code) = (Vec::new(), Vec::new());
    let mut stack = Vec::new();
    for start in 0..labels.len() {
        if comp[start] != u32::MAX {
            continue;
        }
        let c = sizes.len() as u32;
        let l = labels[start];
        comp[start] = c;
        stack.push(start);
        let mut size = 0;
        while let Some(idx) = stack.pop() {
            size += 1;
            for nb in grid.neighbours(idx) {
                if comp[nb] == u32::MAX && labels[nb] == l {
                    comp[nb] = c;
                    stack.push(nb);
                }
            }
        }
        sizes.push(size);
        code.push(l);
    }
    (comp, sizes, code)
}

/// Where a label meets itself only across a corner (a b / b a), one cell
/// takes its diagonal's label, so every region is a set of cells joined by
/// edges and its boundary a set of simple rings.
fn remove_diagonals(grid: &GridFrame, labels: &mut [u32]) {
    for _ in 0..16 {
        let mut changed = false;
        for j in 0..grid.ny.saturating_sub(1) {
            for i in 0..grid.nx.saturating_sub(1) {
                let p = j * grid.nx + i;
                let (q, r, s) = (p + 1, p + grid.nx, p + grid.nx + 1);
                if labels[p] == labels[s] && labels[q] != labels[p] && labels[r] != labels[p] {
                    labels[q] = labels[p];
                    changed = true;
                } else if labels[q] == labels[r] && labels[p] != labels[q] && labels[s] != labels[q]
                {
                    labels[p] = labels[q];
                    changed = true;
                }
            }
        }
        if !changed {
            break;
        }
    }
}

/// Traces the boundaries of `region` (per cell, 0 outside; cells beyond
/// the grid are outside) into chains and simplifies each by Douglas–Peucker
/// with tolerance `tol` (m), chain ends fixed.
pub(crate) fn trace(grid: &GridFrame, region: &[u32], regions: u32, tol: f64) -> Partition {
    let (nx, ny) = (grid.nx as isize, grid.ny as isize);
    let lab = |i: isize, j: isize| -> u32 {
        if i < 0 || j < 0 || i >= nx || j >= ny {
            0
        } else {
            region[(j * nx + i) as usize]
        }
    };
    let vid = |i: isize, j: isize| (j * (nx + 1) + i) as usize;
    let h_count = (nx * (ny + 1)) as usize;
    let h_id = |i: isize, j: isize| (j * nx + i) as usize;
    let v_id = |i: isize, j: isize| h_count + (j * (nx + 1) + i) as usize;
    let is_h = |i: isize, j: isize| i >= 0 && i < nx && lab(i, j - 1) != lab(i, j);
    let is_v = |i: isize, j: isize| j >= 0 && j < ny && lab(i - 1, j) != lab(i, j);
    // Steps out of vertex (i, j): (edge id, next vertex, left, right).
    let steps = |i: isize, j: isize| -> Vec<(usize, (isize, isize), u32, u32)> {
        let mut out = Vec::with_capacity(4);
        if is_h(i, j) {
            out.push((h_id(i, j), (i + 1, j), lab(i, j), lab(i, j - 1)));
        }
        if is_h(i - 1, j) {
            out.push((h_id(i - 1, j), (i - 1, j), lab(i - 1, j - 1), lab(i - 1, j)));
        }
        if is_v(i, j) {
            out.push((v_id(i, j), (i, j + 1), lab(i - 1, j), lab(i, j)));
        }
        if is_v(i, j - 1) {
            out.push((v_id(i, j - 1), (i, j - 1), lab(i, j - 1), lab(i - 1, j - 1)));
        }
        out
    };
    let edge_total = h_count + ((nx + 1) * ny) as usize;
    let mut used = vec![false; edge_total];
    let mut is_node = vec![false; ((nx + 1) * (ny + 1)) as usize];
    for j in 0..=ny {
        for i in 0..=nx {
            let d = steps(i, j).len();
            is_node[vid(i, j)] = d != 0 && d != 2;
        }
    }
    let mut raw: Vec<Traced> = Vec::new();
    let walk = |start: (isize, isize),
                first: (usize, (isize, isize), u32, u32),
                used: &mut Vec<bool>,
                is_node: &Vec<bool>| {
        let (e, mut at, left, right) = first;
        used[e] = true;
        let mut pts = vec![start, at];
        while !is_node[vid(at.0, at.1)] && at != start {
            let Some(next) = steps(at.0, at.1).into_iter().find(|s| !used[s.0]) else {
                break;
            };
            used[next.0] = true;
            at = next.1;
            pts.push(at);
        }
        (pts, left, right)
    };
    for j in 0..=ny {
        for i in 0..=nx {
            if !is_node[vid(i, j)] {
                continue;
            }
            for s in steps(i, j) {
                if !used[s.0] {
                    raw.push(walk((i, j), s, &mut used, &is_node));
                }
            }
        }
    }
    // Loops with no node (an island in one other region).
    for j in 0..=ny {
        for i in 0..=nx {
            for s in steps(i, j) {
                if !used[s.0] {
                    is_node[vid(i, j)] = true;
                    raw.push(walk((i, j), s, &mut used, &is_node));
                }
            }
        }
    }
    let pos = |(i, j): (isize, isize)| grid.corner(i as f64, j as f64);
    let mut index = std::collections::HashMap::new();
    let mut verts = Vec::new();
    let mut chains = Vec::with_capacity(raw.len());
    let mut straight: std::collections::HashSet<((isize, isize), (isize, isize))> =
        Default::default();
    for (pts, left, right) in raw {
        let p: Vec<[f64; 2]> = pts.iter().map(|&v| pos(v)).collect();
        let mut keep = simplify(&p, tol);
        if keep.len() == 2 && p.len() > 2 {
            // Two chains between the same nodes must not both become the
            // same straight segment (a region of no area).
            let (a, b) = (pts[0].min(pts[p.len() - 1]), pts[0].max(pts[p.len() - 1]));
            if !straight.insert((a, b)) {
                keep = vec![0, farthest(&p), p.len() - 1];
            }
        }
        let ids = keep
            .into_iter()
            .map(|k| {
                *index.entry(pts[k]).or_insert_with(|| {
                    verts.push(p[k]);
                    (verts.len() - 1) as u32
                })
            })
            .collect();
        chains.push(Chain {
            verts: ids,
            left,
            right,
        });
    }
    Partition {
        verts,
        chains,
        regions,
    }
}

/// Indices kept by Douglas–Peucker (first and last always; a closed loop
/// is split at its farthest vertex from the start first).
fn simplify(p: &[[f64; 2]], tol: f64) -> Vec<usize> {
    let n = p.len();
    if n <= 2 {
        return (0..n).collect();
    }
    let mut keep = vec![false; n];
    keep[0] = true;
    keep[n - 1] = true;
    if p[0] == p[n - 1] {
        let far = (1..n - 1)
            .max_by(|&a, &b| dist2(p[a], p[0]).total_cmp(&dist2(p[b], p[0])))
            .unwrap_or(n / 2);
        keep[far] = true;
        dp(p, 0, far, tol, &mut keep);
        dp(p, far, n - 1, tol, &mut keep);
        if keep.iter().filter(|k| **k).count() < 4 {
            // A ring needs three distinct vertices.
            let third = (1..n - 1).filter(|&k| k != far).max_by(|&a, &b| {
                line_dist(p[a], p[0], p[far]).total_cmp(&line_dist(p[b], p[0], p[far]))
            });
            if let Some(t) = third {
                keep[t] = true;
            }
        }
    } else {
        dp(p, 0, n - 1, tol, &mut keep);
    }
    (0..n).filter(|&k| keep[k]).collect()
}

/// The inner vertex farthest from the line through the ends.
fn farthest(p: &[[f64; 2]]) -> usize {
    let n = p.len();
    (1..n - 1)
        .max_by(|&a, &b| {
            line_dist(p[a], p[0], p[n - 1]).total_cmp(&line_dist(p[b], p[0], p[n - 1]))
        })
        .unwrap_or(0)
}

fn dp(p: &[[f64; 2]], a: usize, b: usize, tol: f64, keep: &mut [bool]) {
    if b <= a + 1 {
        return;
    }
    let (mut worst, mut at) = (-1.0, a);
    for k in a + 1..b {
        let d = line_dist(p[k], p[a], p[b]);
        if d > worst {
            worst = d;
            at = k;
        }
    }
    if worst > tol {
        keep[at] = true;
        dp(p, a, at, tol, keep);
        dp(p, at, b, tol, keep);
    }
}

fn dist2(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)
}

/// Distance of `p` from segment a–b.
pub(crate) fn line_dist(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    crate::geom::segment::distance(p, a, b)
}

impl Partition {
    /// Every segment of every chain, as vertex pairs (zero-length ones left out).
    pub fn segments(&self) -> Vec<(u32, u32)> {
        self.chains
            .iter()
            .flat_map(|c| c.verts.windows(2).map(|w| (w[0], w[1])))
            .filter(|s| s.0 != s.1)
            .collect()
    }

    /// The closed rings bounding `region` with it on the left (outer rings
    /// counter-clockwise, holes clockwise), first vertex not repeated.
    pub fn rings(&self, region: u32) -> Vec<Vec<u32>> {
        let mut trav: Vec<Vec<u32>> = Vec::new();
        for c in &self.chains {
            if c.left == region {
                trav.push(c.verts.clone());
            }
            if c.right == region {
                trav.push(c.verts.iter().rev().copied().collect());
            }
        }
        let mut used = vec![false; trav.len()];
        let mut rings = Vec::new();
        for s in 0..trav.len() {
            if used[s] {
                continue;
            }
            used[s] = true;
            let start = trav[s][0];
            let mut ring: Vec<u32> = trav[s][..trav[s].len() - 1].to_vec();
            let mut end = *trav[s].last().unwrap_or(&start);
            let mut guard = 0;
            while end != start && guard < trav.len() {
                guard += 1;
                let Some(t) = (0..trav.len()).find(|&t| !used[t] && trav[t][0] == end) else {
                    break;
                };
                used[t] = true;
                ring.extend_from_slice(&trav[t][..trav[t].len() - 1]);
                end = *trav[t].last().unwrap_or(&end);
            }
            if ring.len() >= 3 {
                rings.push(ring);
            }
        }
        rings
    }

    /// Signed area of a ring (positive counter-clockwise).
    pub fn ring_area(&self, ring: &[u32]) -> f64 {
        let mut a = 0.0;
        for k in 0..ring.len() {
            let p = self.verts[ring[k] as usize];
            let q = self.verts[ring[(k + 1) % ring.len()] as usize];
            a += p[0] * q[1] - q[0] * p[1];
        }
        a * 0.5
    }
}

#[cfg(test)]
/// The traced partition of a 10 × 8 m block on a 1 m grid (one empty
/// cell around it), cell (i, j) labelled by `label`, and each region's label.
pub(crate) fn block_partition(label: impl Fn(usize, usize) -> u32) -> (Partition, Vec<u32>) {
    let g = GridFrame {
        origin: [0.0, 0.0],
        cell: 1.0,
        nx: 12,
        ny: 10,
    };
    let mut labels = vec![0u32; 120];
    for j in 1..9 {
        for i in 1..11 {
            labels[j * 12 + i] = label(i, j);
        }
    }
    let (region, code) = regions(&g, &mut labels, 1);
    (trace(&g, &region, code.len() as u32, 0.3), code)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(nx: usize, ny: usize) -> GridFrame {
        GridFrame {
            origin: [0.0, 0.0],
            cell: 1.0,
            nx,
            ny,
        }
    }

    #[test]
    fn two_regions_share_one_chain_and_rings_close() {
        // 6 × 4 cells inside a 1-cell margin: left half region A, right half B.
        let g = grid(8, 6);
        let mut labels = vec![0u32; 48];
        for j in 1..5 {
            for i in 1..7 {
                labels[j * 8 + i] = if i < 4 { 5 } else { 9 };
            }
        }
        let (region, code) = regions(&g, &mut labels, 1);
        assert_eq!(code.len(), 2);
        let p = trace(&g, &region, 2, 0.3);
        let shared: Vec<_> = p
            .chains
            .iter()
            .filter(|c| c.left != 0 && c.right != 0)
            .collect();
        assert_eq!(shared.len(), 1);
        assert_eq!(shared[0].verts.len(), 2, "straight boundary simplified");
        for r in 1..=2 {
            let rings = p.rings(r);
            assert_eq!(rings.len(), 1);
            assert!((p.ring_area(&rings[0]) - 12.0).abs() < 1e-9);
        }
        let outside = p.rings(0);
        assert_eq!(outside.len(), 1);
        assert!((p.ring_area(&outside[0]) + 24.0).abs() < 1e-9);
    }

    #[test]
    fn courtyard_is_a_hole_and_small_regions_merge() {
        let g = grid(9, 9);
        let mut labels = vec![0u32; 81];
        for j in 1..8 {
            for i in 1..8 {
                let court = (3..6).contains(&i) && (3..6).contains(&j);
                labels[j * 9 + i] = if court { 0 } else { 1 };
            }
        }
        labels[9 + 1] = 7; // one stray cell
        let (region, code) = regions(&g, &mut labels, 2);
        assert_eq!(code, vec![1]);
        let p = trace(&g, &region, 1, 0.3);
        let mut areas: Vec<f64> = p.rings(1).iter().map(|r| p.ring_area(r)).collect();
        areas.sort_by(f64::total_cmp);
        assert_eq!(areas, vec![-9.0, 49.0]);
    }
}
