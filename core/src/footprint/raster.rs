//! An occupancy grid of building points: count and highest z per cell,
//! closing of small gaps, and connected components that may be cut where
//! roof heights jump.

use std::collections::HashMap;

use super::valley::{Heights, absorb, barrier};
use crate::geom::grid::{self, GridFrame};

/// The grid never exceeds this many cells (the cell grows instead).
const MAX_CELLS: f64 = 2.0e7;
/// Empty cells kept around the data, so every component has an outside.
const PAD: usize = 2;

/// Occupancy of a regular xy grid.
pub struct Raster {
    /// The cells' frame; its cell may be larger than asked for (see `MAX_CELLS`).
    pub frame: GridFrame,
    /// Points per cell.
    pub count: Vec<u32>,
    /// Highest z per cell (`NEG_INFINITY` when empty).
    pub top: Vec<f32>,
    /// Occupied (after closing).
    pub filled: Vec<bool>,
}

impl Raster {
    /// Bins finite points; `None` when there are none.
    pub fn new(points: &[[f32; 3]], cell: f64, closing: usize) -> Option<Self> {
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for p in points.iter().filter(|p| p.iter().all(|v| v.is_finite())) {
            for k in 0..2 {
                lo[k] = lo[k].min(f64::from(p[k]));
                hi[k] = hi[k].max(f64::from(p[k]));
            }
        }
        if !lo[0].is_finite() {
            return None;
        }
        let (w, h) = (hi[0] - lo[0], hi[1] - lo[1]);
        let cell = cell.max((w * h / MAX_CELLS).sqrt());
        let pad = PAD + closing;
        // Bounded by MAX_CELLS: the sizes cannot overflow.
        let frame = GridFrame::covering(lo, hi, cell, pad);
        let mut count = vec![0u32; frame.len()];
        let mut top = vec![f32::NEG_INFINITY; frame.len()];
        for p in points.iter().filter(|p| p.iter().all(|v| v.is_finite())) {
            let (i, j) = frame.clamped_cell(f64::from(p[0]), f64::from(p[1]));
            let k = j * frame.nx + i;
            count[k] += 1;
            top[k] = top[k].max(p[2]);
        }
        let filled = count.iter().map(|&c| c > 0).collect();
        let mut r = Self {
            frame,
            count,
            top,
            filled,
        };
        r.close(closing);
        Some(r)
    }

    /// Morphological closing with a (2r+1)² square; cells it fills take the
    /// top of the nearest occupied cell, so height cuts still see a roof.
    fn close(&mut self, r: usize) {
        if r == 0 {
            return;
        }
        let closed = grid::close(&self.filled, self.frame.nx, self.frame.ny, r);
        let ri = r as isize;
        for j in 0..self.frame.ny {
            for i in 0..self.frame.nx {
                let k = j * self.frame.nx + i;
                if !closed[k] || self.filled[k] {
                    continue;
                }
                let mut best = (usize::MAX, f32::NEG_INFINITY);
                for dj in -ri..=ri {
                    for di in -ri..=ri {
                        let (x, y) = (i as isize + di, j as isize + dj);
                        if x < 0
                            || y < 0
                            || x as usize >= self.frame.nx
                            || y as usize >= self.frame.ny
                        {
                            continue;
                        }
                        let n = y as usize * self.frame.nx + x as usize;
                        let d = (di * di + dj * dj) as usize;
                        if self.count[n] > 0 && d < best.0 {
                            best = (d, self.top[n]);
                        }
                    }
                }
                self.top[k] = best.1;
            }
        }
        self.filled = closed;
    }

    /// Component label per cell (0 = empty), 4-connected; with a step
    /// `cuts.jump > 0`, neighbours across a roof-height step ([`Self::step`])
    /// larger than it are cut apart; with `cuts.valley > 0`, cells in a
    /// valley between roofs ([`barrier`]) join no one until
    /// the parts are formed, then the part nearest them; then parts smaller than
    /// `cuts.min_part_cells` or touching open ground on less than
    /// `cuts.min_open` of their edges are merged into the neighbour they
    /// share most edges with.
    pub fn components(&self, cuts: &Cuts) -> (Vec<u32>, u32) {
        let (nx, ny) = (self.frame.nx, self.frame.ny);
        let n = nx * ny;
        let mut uf = UnionFind::new(n);
        let heights = Heights {
            nx,
            ny,
            filled: &self.filled,
            top: &self.top,
        };
        let barrier = barrier(&heights, cuts.valley, cuts.valley_dilate);
        let joins = |a: usize, b: usize, before: Option<usize>, after: Option<usize>| {
            !barrier[a]
                && !barrier[b]
                && (cuts.jump <= 0.0 || self.step(a, b, before, after) <= cuts.jump)
        };
        for j in 0..ny {
            for i in 0..nx {
                let k = j * nx + i;
                if !self.filled[k] {
                    continue;
                }
                if i + 1 < nx && self.filled[k + 1] {
                    let (before, after) = ((i > 0).then(|| k - 1), (i + 2 < nx).then(|| k + 2));
                    if joins(k, k + 1, before, after) {
                        uf.union(k, k + 1);
                    }
                }
                if j + 1 < ny && self.filled[k + nx] {
                    let before = (j > 0).then(|| k - nx);
                    let after = (j + 2 < ny).then(|| k + 2 * nx);
                    if joins(k, k + nx, before, after) {
                        uf.union(k, k + nx);
                    }
                }
            }
        }
        absorb(&heights, &barrier, |a, b| uf.union(a, b));
        if cuts.jump > 0.0 || cuts.valley > 0.0 {
            self.merge_small_and_enclosed(&mut uf, cuts);
        }
        let mut label = vec![0u32; n];
        let mut ids: HashMap<usize, u32> = HashMap::new();
        for (k, slot) in label.iter_mut().enumerate() {
            if self.filled[k] {
                let root = uf.find(k);
                let next = u32::try_from(ids.len() + 1).unwrap_or(u32::MAX);
                *slot = *ids.entry(root).or_insert(next);
            }
        }
        (label, u32::try_from(ids.len()).unwrap_or(u32::MAX))
    }

    /// The roof-height step between neighbours `a` and `b` (m): their top
    /// difference less the larger of the differences beside it (`before`
    /// → `a`, `b` → `after`, occupied ones only), so a pitched roof's own
    /// slope, however steep, is no step while an eave or ridge that jumps
    /// between two houses is.
    fn step(&self, a: usize, b: usize, before: Option<usize>, after: Option<usize>) -> f64 {
        let top = |k: usize| f64::from(self.top[k]);
        let flank = |x: Option<usize>, y: usize| {
            x.filter(|&x| self.filled[x])
                .map_or(0.0, |x| (top(x) - top(y)).abs())
        };
        let d = (top(b) - top(a)).abs();
        (d - flank(before, a).max(flank(after, b))).max(0.0)
    }

    fn merge_small_and_enclosed(&self, uf: &mut UnionFind, cuts: &Cuts) {
        for _ in 0..8 {
            // Per part: cells, edges to open ground, and edges shared with each neighbour part.
            let mut cells: HashMap<usize, usize> = HashMap::new();
            let mut open: HashMap<usize, usize> = HashMap::new();
            let mut total: HashMap<usize, usize> = HashMap::new();
            let mut shared: HashMap<(usize, usize), usize> = HashMap::new();
            for j in 0..self.frame.ny {
                for i in 0..self.frame.nx {
                    let k = j * self.frame.nx + i;
                    if !self.filled[k] {
                        continue;
                    }
                    let a = uf.find(k);
                    *cells.entry(a).or_default() += 1;
                    let nbrs = [
                        (i > 0).then(|| k - 1),
                        (i + 1 < self.frame.nx).then(|| k + 1),
                        (j > 0).then(|| k - self.frame.nx),
                        (j + 1 < self.frame.ny).then(|| k + self.frame.nx),
                    ];
                    for nb in nbrs {
                        match nb.filter(|&m| self.filled[m]) {
                            None => {
                                *open.entry(a).or_default() += 1;
                                *total.entry(a).or_default() += 1;
                            }
                            Some(m) => {
                                let b = uf.find(m);
                                if b != a {
                                    *shared.entry((a, b)).or_default() += 1;
                                    *total.entry(a).or_default() += 1;
                                }
                            }
                        }
                    }
                }
            }
            let mut merged = false;
            let mut parts: Vec<(usize, usize)> = total.iter().map(|(&a, &t)| (t, a)).collect();
            parts.sort_unstable();
            for (t, a) in parts {
                let o = open.get(&a).copied().unwrap_or(0);
                let small = cells.get(&a).copied().unwrap_or(0) < cuts.min_part_cells;
                if t == 0 || (!small && (o as f64) >= cuts.min_open * t as f64) {
                    continue;
                }
                let best = shared
                    .iter()
                    .filter(|((x, _), _)| *x == a)
                    .max_by_key(|&(&(_, b), &c)| (c, b))
                    .map(|(&(_, b), _)| b);
                if let Some(b) = best
                    && uf.find(a) != uf.find(b)
                {
                    uf.union(a, b);
                    merged = true;
                }
            }
            if !merged {
                break;
            }
        }
    }
}

/// Where [`Raster::components`] cuts touching buildings apart.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cuts {
    /// Roof-height step (m) that separates two buildings; 0: no cuts.
    pub jump: f64,
    /// Depth (m) of a valley between two roofs that separates two
    /// buildings; 0: no valley cuts.
    pub valley: f64,
    /// Valley cells are grown by this many cells (bridging a noisy gutter).
    pub valley_dilate: usize,
    /// Parts with fewer cells join their neighbour (dormers, chimneys, noise).
    pub min_part_cells: usize,
    /// Parts touching open ground on less than this share of their edges
    /// join their neighbour (a tower on its podium).
    pub min_open: f64,
}

/// Disjoint sets over cell indices.
pub struct UnionFind {
    parent: Vec<usize>,
}

impl UnionFind {
    fn new(n: usize) -> Self {
        Self {
            parent: (0..n).collect(),
        }
    }

    /// The root of `x`'s set.
    pub fn find(&mut self, mut x: usize) -> usize {
        while self.parent[x] != x {
            self.parent[x] = self.parent[self.parent[x]];
            x = self.parent[x];
        }
        x
    }

    /// Joins the sets of `a` and `b`.
    pub fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.parent[ra.max(rb)] = ra.min(rb);
        }
    }
}
