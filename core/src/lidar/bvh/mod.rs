//! A flattened binary bounding-volume hierarchy over triangles.
//!
//! - [`build`]: binned SAH construction (parallel over subtrees).
//! - [`traverse`]: closest-hit traversal, near child first, early exit.
//! - [`packet`]: the same for up to 64 rays sharing an origin, in one walk.
//!
//! - `wide`: the binary tree collapsed into 4-wide nodes.
//!
//! Layout: each node holds the boxes of its four children as structure of
//! arrays (128 bytes, two cache lines), so one visit tests all four with
//! 4-lane arithmetic; leaves are ranges of the triangle arrays, which are
//! stored in leaf order (vertices inline, no index indirection in the inner
//! loop).

mod build;
mod lanes;
mod packet;
mod traverse;
mod wide;
pub(crate) use packet::PACKET;
#[cfg(test)]
pub(crate) use traverse::stats;

/// Children per node.
pub(crate) const WIDTH: usize = 4;

/// Sorts a node's (at most [`WIDTH`]) entered children far to near, so that
/// popping the stack visits the nearest first (insertion sort: four items).
#[inline(always)]
pub(crate) fn far_first<T>(kids: &mut [T], dist: impl Fn(&T) -> f32) {
    for i in 1..kids.len() {
        let mut j = i;
        while j > 0 && dist(&kids[j - 1]) < dist(&kids[j]) {
            kids.swap(j - 1, j);
            j -= 1;
        }
    }
}

/// One node: the boxes of its (up to) four children and where they lead.
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
pub(crate) struct Node {
    /// `bounds[axis][0 = min, 1 = max][child]`.
    pub bounds: [[[f32; WIDTH]; 2]; 3],
    /// Inner child: node index; leaf child: first triangle (leaf order).
    pub child: [u32; WIDTH],
    /// 0 for an inner child, else the leaf's number of triangles (≤ 8).
    pub count: [u8; WIDTH],
    /// Bit `c` set when child `c` is a leaf (an empty slot is neither).
    pub leaves: u8,
}

impl Node {
    /// A node whose every slot is empty (inverted boxes).
    pub const EMPTY: Self = Self {
        bounds: [[[f32::INFINITY; WIDTH], [f32::NEG_INFINITY; WIDTH]]; 3],
        child: [0; WIDTH],
        count: [0; WIDTH],
        leaves: 0,
    };
}

/// The hierarchy plus the triangles in leaf order.
#[derive(Debug, Clone, Default)]
pub(crate) struct Bvh {
    /// Inner nodes; node 0 is the root. Empty when there are no triangles.
    pub nodes: Vec<Node>,
    /// Triangle vertices in leaf order.
    pub tris: Vec<[[f32; 3]; 3]>,
    /// For each leaf-order triangle, its index in the input.
    pub ids: Vec<u32>,
}

/// Build statistics, for benchmarks and tuning.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct BvhStats {
    /// Inner nodes.
    pub nodes: usize,
    /// Leaves.
    pub leaves: usize,
    /// Deepest leaf (root = 1).
    pub depth: usize,
}

impl Bvh {
    /// Builds over `tris`; `ids[i]` is the caller's index of `tris[i]`.
    pub fn new(tris: Vec<[[f32; 3]; 3]>, ids: Vec<u32>) -> Self {
        let Some((root, root_box, order)) = build::build(&tris) else {
            return Self::default();
        };
        Self {
            nodes: wide::flatten(root, root_box),
            tris: order.iter().map(|&i| tris[i as usize]).collect(),
            ids: order.iter().map(|&i| ids[i as usize]).collect(),
        }
    }

    /// Node, leaf and depth counts.
    pub fn stats(&self) -> BvhStats {
        let mut s = BvhStats::default();
        if self.nodes.is_empty() {
            return s;
        }
        let mut stack = vec![(0u32, 1usize)];
        while let Some((n, d)) = stack.pop() {
            s.nodes += 1;
            let Some(node) = self.nodes.get(n as usize) else {
                continue;
            };
            for c in 0..WIDTH {
                if node.count[c] > 0 {
                    s.leaves += 1;
                    s.depth = s.depth.max(d + 1);
                } else if node.bounds[0][0][c] <= node.bounds[0][1][c] {
                    stack.push((node.child[c], d + 1));
                }
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn node_fills_two_cache_lines() {
        assert_eq!(std::mem::size_of::<super::Node>(), 128);
    }
}
