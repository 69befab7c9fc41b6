//! Binned surface-area-heuristic construction.
//!
//! Each node bins triangle centroids into [`BINS`] slots per axis, picks the
//! split with the lowest SAH cost and partitions in place; subtrees larger
//! than [`PAR_MIN`] triangles are built in parallel. Below [`MAX_DEPTH`] a
//! node that will not split well is cut at its median instead, which bounds
//! the depth (and the traversal stack) for any input.

/// Centroid bins per axis.
const BINS: usize = 16;
/// Largest leaf (node slots store counts as `u8`).
pub(super) const MAX_LEAF: usize = 8;
/// Depth after which nodes are split at the median.
const MAX_DEPTH: u32 = 64;
/// Smallest subtree built on its own rayon task.
const PAR_MIN: usize = 4096;
/// Cost of visiting a node relative to one triangle test.
const C_TRAV: f32 = 1.0;

/// An axis-aligned box.
#[derive(Debug, Clone, Copy)]
pub(super) struct Aabb {
    pub lo: [f32; 3],
    pub hi: [f32; 3],
}

impl Aabb {
    pub const EMPTY: Self = Self {
        lo: [f32::INFINITY; 3],
        hi: [f32::NEG_INFINITY; 3],
    };

    fn grow(&mut self, p: [f32; 3]) {
        self.lo = std::array::from_fn(|k| self.lo[k].min(p[k]));
        self.hi = std::array::from_fn(|k| self.hi[k].max(p[k]));
    }

    fn union(&mut self, b: &Self) {
        for k in 0..3 {
            self.lo[k] = self.lo[k].min(b.lo[k]);
            self.hi[k] = self.hi[k].max(b.hi[k]);
        }
    }

    /// Half the surface area (the SAH only compares ratios).
    pub fn half_area(&self) -> f32 {
        let d = [
            self.hi[0] - self.lo[0],
            self.hi[1] - self.lo[1],
            self.hi[2] - self.lo[2],
        ];
        if d[0] < 0.0 {
            return 0.0;
        }
        d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
    }
}

/// Per-triangle bounds and centroids.
struct Prims {
    bounds: Vec<Aabb>,
    centroid: Vec<[f32; 3]>,
}

/// The binary tree before flattening.
pub(super) enum BNode {
    Leaf { start: u32, count: u32 },
    Inner(Box<[(BNode, Aabb); 2]>),
}

/// The binary hierarchy over `tris`, its bounds, and the triangles' indices
/// in leaf order; `None` without triangles.
pub(super) fn build(tris: &[[[f32; 3]; 3]]) -> Option<(BNode, Aabb, Vec<u32>)> {
    if tris.is_empty() {
        return None;
    }
    let mut bounds = Vec::with_capacity(tris.len());
    let mut centroid = Vec::with_capacity(tris.len());
    for t in tris {
        let mut b = Aabb::EMPTY;
        t.iter().for_each(|&v| b.grow(v));
        bounds.push(b);
        centroid.push(std::array::from_fn(|k| 0.5 * (b.lo[k] + b.hi[k])));
    }
    let prims = Prims { bounds, centroid };
    // Fewer than 2³² triangles: the caller's ids are u32.
    let mut idx: Vec<u32> = (0..tris.len() as u32).collect();
    let (root, root_box) = build_node(&prims, &mut idx, 0, 0);
    Some((root, root_box, idx))
}

/// Builds the subtree over `idx` (which starts at `offset` in the full array).
fn build_node(p: &Prims, idx: &mut [u32], offset: usize, depth: u32) -> (BNode, Aabb) {
    let n = idx.len();
    let mut bb = Aabb::EMPTY;
    let mut cb = Aabb::EMPTY;
    for &i in idx.iter() {
        bb.union(&p.bounds[i as usize]);
        cb.grow(p.centroid[i as usize]);
    }
    let leaf = BNode::Leaf {
        start: offset as u32,
        count: n as u32,
    };
    if n <= 1 {
        return (leaf, bb);
    }
    let split = if depth >= MAX_DEPTH {
        None
    } else {
        best_split(p, idx, &cb)
    };
    let mid = match split {
        Some((axis, bin, cost)) => {
            if n <= MAX_LEAF && n as f32 <= C_TRAV + cost / bb.half_area().max(f32::MIN_POSITIVE) {
                return (leaf, bb);
            }
            let scale = BINS as f32 / (cb.hi[axis] - cb.lo[axis]);
            partition(idx, |i| {
                bin_of(p.centroid[i as usize][axis], cb.lo[axis], scale) < bin
            })
        }
        None if n <= MAX_LEAF => return (leaf, bb),
        None => n / 2,
    };
    let (left, right) = idx.split_at_mut(mid);
    let (l, r) = if n >= PAR_MIN {
        rayon::join(
            || build_node(p, left, offset, depth + 1),
            || build_node(p, right, offset + mid, depth + 1),
        )
    } else {
        (
            build_node(p, left, offset, depth + 1),
            build_node(p, right, offset + mid, depth + 1),
        )
    };
    (BNode::Inner(Box::new([l, r])), bb)
}

fn bin_of(c: f32, lo: f32, scale: f32) -> usize {
    // Saturating float-to-int cast; NaN maps to 0.
    (((c - lo) * scale) as usize).min(BINS - 1)
}

/// The cheapest `(axis, first bin of the right side, SAH cost)` split, or
/// `None` when all centroids coincide.
fn best_split(p: &Prims, idx: &[u32], cb: &Aabb) -> Option<(usize, usize, f32)> {
    let mut best: Option<(usize, usize, f32)> = None;
    for axis in 0..3 {
        let extent = cb.hi[axis] - cb.lo[axis];
        if extent.is_nan() || extent <= 0.0 {
            continue;
        }
        let scale = BINS as f32 / extent;
        let mut count = [0u32; BINS];
        let mut bins = [Aabb::EMPTY; BINS];
        for &i in idx {
            let b = bin_of(p.centroid[i as usize][axis], cb.lo[axis], scale);
            count[b] += 1;
            bins[b].union(&p.bounds[i as usize]);
        }
        // right[b] = area and count of bins b.. (suffix sums).
        let mut right_area = [0.0f32; BINS];
        let mut right_count = [0u32; BINS];
        let mut acc = Aabb::EMPTY;
        let mut cnt = 0;
        for b in (1..BINS).rev() {
            acc.union(&bins[b]);
            cnt += count[b];
            right_area[b] = acc.half_area();
            right_count[b] = cnt;
        }
        let mut acc = Aabb::EMPTY;
        let mut cnt = 0;
        for b in 1..BINS {
            acc.union(&bins[b - 1]);
            cnt += count[b - 1];
            if cnt == 0 || right_count[b] == 0 {
                continue;
            }
            let cost = acc.half_area() * cnt as f32 + right_area[b] * right_count[b] as f32;
            if best.is_none_or(|(_, _, c)| cost < c) {
                best = Some((axis, b, cost));
            }
        }
    }
    best
}

/// Moves the elements satisfying `left` to the front; returns their number.
fn partition(idx: &mut [u32], left: impl Fn(u32) -> bool) -> usize {
    let mut i = 0;
    let mut j = idx.len();
    while i < j {
        if left(idx[i]) {
            i += 1;
        } else {
            j -= 1;
            idx.swap(i, j);
        }
    }
    i
}
