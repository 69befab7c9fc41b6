//! A uniform 3D grid over triangles for nearest-triangle queries.

use crate::scene::vec3::point_triangle_dist2;

/// Triangles bucketed by the grid cells their bounding boxes overlap
/// (compressed rows: `start[c]..start[c + 1]` indexes `items`).
pub struct TriangleGrid {
    tris: Vec<[[f64; 3]; 3]>,
    tags: Vec<u32>,
    lo: [f64; 3],
    cell: f64,
    dims: [usize; 3],
    start: Vec<u32>,
    items: Vec<u32>,
}

/// Triangle-in-cell entries allowed before the cell size is grown.
const MAX_ITEMS: usize = 20_000_000;
/// Grid cells allowed before the cell size is grown.
const MAX_CELLS: usize = 8_000_000;

impl TriangleGrid {
    /// Indexes `tris` (each with a caller-chosen `tag`, e.g. its object).
    /// Non-finite triangles are left out.
    pub fn new(tris: Vec<[[f64; 3]; 3]>, tags: Vec<u32>) -> Self {
        let keep: Vec<usize> = (0..tris.len())
            .filter(|&t| tris[t].iter().flatten().all(|v| v.is_finite()))
            .collect();
        let tris: Vec<[[f64; 3]; 3]> = keep.iter().map(|&t| tris[t]).collect();
        let tags: Vec<u32> = keep
            .iter()
            .map(|&t| tags.get(t).copied().unwrap_or(0))
            .collect();
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let mut edge_sum = 0.0;
        for t in &tris {
            for p in t {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            edge_sum += (0..3).map(|k| tri_extent(t, k)).fold(0.0, f64::max);
        }
        if tris.is_empty() {
            return Self {
                tris,
                tags,
                lo: [0.0; 3],
                cell: 1.0,
                dims: [1; 3],
                start: vec![0, 0],
                items: Vec::new(),
            };
        }
        let mean_extent = edge_sum / tris.len() as f64;
        let span = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
        let mut cell = mean_extent.clamp(0.5, 8.0).max(span / 1024.0);
        loop {
            let dims = [0, 1, 2].map(|k| ((hi[k] - lo[k]) / cell).floor() as usize + 1);
            let count: usize = tris
                .iter()
                .map(|t| {
                    let (a, b) = cell_range(t, lo, cell, dims);
                    (0..3).map(|k| b[k] - a[k] + 1).product::<usize>()
                })
                .sum();
            let cells = dims.iter().fold(1usize, |a, &d| a.saturating_mul(d));
            if count <= MAX_ITEMS && cells <= MAX_CELLS {
                return Self::fill(tris, tags, lo, cell, dims);
            }
            cell *= 2.0;
        }
    }

    fn fill(
        tris: Vec<[[f64; 3]; 3]>,
        tags: Vec<u32>,
        lo: [f64; 3],
        cell: f64,
        dims: [usize; 3],
    ) -> Self {
        let n = dims[0] * dims[1] * dims[2];
        let mut counts = vec![0u32; n + 1];
        let each = |t: &[[f64; 3]; 3], f: &mut dyn FnMut(usize)| {
            let (a, b) = cell_range(t, lo, cell, dims);
            for z in a[2]..=b[2] {
                for y in a[1]..=b[1] {
                    for x in a[0]..=b[0] {
                        f((z * dims[1] + y) * dims[0] + x);
                    }
                }
            }
        };
        for t in &tris {
            each(t, &mut |c| counts[c + 1] += 1);
        }
        for c in 0..n {
            counts[c + 1] += counts[c];
        }
        let mut fill = counts.clone();
        let mut items = vec![0u32; counts[n] as usize];
        for (i, t) in tris.iter().enumerate() {
            each(t, &mut |c| {
                items[fill[c] as usize] = u32::try_from(i).unwrap_or(u32::MAX);
                fill[c] += 1;
            });
        }
        Self {
            tris,
            tags,
            lo,
            cell,
            dims,
            start: counts,
            items,
        }
    }

    /// Squared distance to and index of the nearest triangle whose tag
    /// passes `keep`, searching no farther than `max_dist`; `None` when there
    /// is none within reach.
    pub fn nearest(
        &self,
        p: [f64; 3],
        max_dist: f64,
        keep: impl Fn(u32) -> bool,
    ) -> Option<(f64, usize)> {
        if self.tris.is_empty() || !p.iter().all(|v| v.is_finite()) {
            return None;
        }
        let c0 = [0, 1, 2].map(|k| self.cell_of(p[k], k));
        let mut best: Option<(f64, usize)> = None;
        let max_ring = self.dims.iter().copied().max().unwrap_or(1);
        for ring in 0..=max_ring {
            // Cells of this ring are at least `bound` away from p.
            let bound = self.ring_bound(p, c0, ring);
            let best_d = best.map_or(max_dist * max_dist, |(d, _)| d.min(max_dist * max_dist));
            if bound * bound > best_d {
                break;
            }
            self.visit_ring(c0, ring, |i| {
                let t = &self.tris[i];
                if !keep(self.tags[i]) {
                    return;
                }
                let d = point_triangle_dist2(p, t[0], t[1], t[2]);
                if d <= max_dist * max_dist && best.is_none_or(|(bd, _)| d < bd) {
                    best = Some((d, i));
                }
            });
        }
        best
    }

    /// The tag of triangle `i` (as given to [`TriangleGrid::new`], after
    /// non-finite triangles were dropped).
    #[cfg(test)]
    pub fn tag(&self, i: usize) -> u32 {
        self.tags.get(i).copied().unwrap_or(0)
    }

    fn cell_of(&self, v: f64, k: usize) -> usize {
        let c = ((v - self.lo[k]) / self.cell).floor();
        if c <= 0.0 {
            0
        } else {
            (c as usize).min(self.dims[k] - 1)
        }
    }

    /// A lower bound on the distance from `p` to cells of Chebyshev ring `ring`
    /// around `c0`: the distance from p to the outside of the box of rings
    /// `0..ring` (0 when p is not inside that box).
    fn ring_bound(&self, p: [f64; 3], c0: [usize; 3], ring: usize) -> f64 {
        if ring == 0 {
            return 0.0;
        }
        let r = ring - 1;
        let mut bound = f64::INFINITY;
        for k in 0..3 {
            let lo_c = c0[k].saturating_sub(r);
            let hi_c = (c0[k] + r).min(self.dims[k] - 1);
            let lo = self.lo[k] + lo_c as f64 * self.cell;
            let hi = self.lo[k] + (hi_c + 1) as f64 * self.cell;
            if p[k] < lo || p[k] > hi {
                return 0.0;
            }
            // A side at the grid's edge has no cells beyond it.
            if lo_c > 0 {
                bound = bound.min(p[k] - lo);
            }
            if hi_c < self.dims[k] - 1 {
                bound = bound.min(hi - p[k]);
            }
        }
        bound
    }

    fn visit_ring(&self, c0: [usize; 3], ring: usize, mut f: impl FnMut(usize)) {
        let r = ring as i64;
        let range = |k: usize| {
            let c = c0[k] as i64;
            ((c - r).max(0), (c + r).min(self.dims[k] as i64 - 1))
        };
        let ((x0, x1), (y0, y1), (z0, z1)) = (range(0), range(1), range(2));
        for z in z0..=z1 {
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let on_shell = (x - c0[0] as i64).abs() == r
                        || (y - c0[1] as i64).abs() == r
                        || (z - c0[2] as i64).abs() == r;
                    if !on_shell {
                        continue;
                    }
                    let c = ((z as usize) * self.dims[1] + y as usize) * self.dims[0] + x as usize;
                    for &i in &self.items[self.start[c] as usize..self.start[c + 1] as usize] {
                        f(i as usize);
                    }
                }
            }
        }
    }
}

fn tri_extent(t: &[[f64; 3]; 3], k: usize) -> f64 {
    let (a, b) = t
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p[k]), b.max(p[k]))
        });
    b - a
}

fn cell_range(
    t: &[[f64; 3]; 3],
    lo: [f64; 3],
    cell: f64,
    dims: [usize; 3],
) -> ([usize; 3], [usize; 3]) {
    let idx = |v: f64, k: usize| (((v - lo[k]) / cell).floor().max(0.0) as usize).min(dims[k] - 1);
    let mut a = [0; 3];
    let mut b = [0; 3];
    for k in 0..3 {
        let (mn, mx) = t
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p[k]), b.max(p[k]))
            });
        a[k] = idx(mn, k);
        b[k] = idx(mx, k);
    }
    (a, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_matches_brute_force() {
        let mut tris = Vec::new();
        for i in 0..20 {
            let x = i as f64 * 1.7;
            tris.push([
                [x, 0.0, 0.0],
                [x + 1.0, 0.3, 0.2],
                [x, 1.0, 2.0 + i as f64 * 0.1],
            ]);
        }
        let tags: Vec<u32> = (0..20).collect();
        let g = TriangleGrid::new(tris.clone(), tags);
        for q in [
            [0.3, 0.2, 5.0],
            [40.0, -3.0, 1.0],
            [17.0, 0.5, 0.5],
            [-50.0, 60.0, -9.0],
        ] {
            let brute = tris
                .iter()
                .map(|t| point_triangle_dist2(q, t[0], t[1], t[2]))
                .fold(f64::INFINITY, f64::min);
            let (d, _) = g
                .nearest(q, f64::INFINITY, |_| true)
                .unwrap_or((f64::NAN, 0));
            assert!((d - brute).abs() < 1e-9, "{q:?}: {d} vs {brute}");
        }
        assert!(g.nearest([0.3, 0.2, 5.0], 0.1, |_| true).is_none());
        let only_odd = g.nearest([0.3, 0.2, 0.1], f64::INFINITY, |t| t % 2 == 1);
        assert_eq!(only_odd.map(|(_, i)| g.tag(i) % 2), Some(1));
    }
}
