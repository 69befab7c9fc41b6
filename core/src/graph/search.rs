//! Shortest paths over the ground graph: Dijkstra from one or several sources.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use super::GroundGraph;

/// No node: the end of a predecessor chain.
pub const NONE: u32 = u32::MAX;

/// Graph distances from a set of sources to every node.
#[derive(Debug, Clone)]
pub struct ShortestPaths {
    /// Distance to the nearest source, metres; infinite when unreachable.
    pub dist: Vec<f32>,
    /// Previous node on the way back to the source; [`NONE`] at sources.
    pub pred: Vec<u32>,
    /// The source each node is nearest to; [`NONE`] when unreachable.
    pub root: Vec<u32>,
}

impl ShortestPaths {
    /// Nodes from `node` back to its nearest source (inclusive both ends);
    /// empty when `node` is unreachable or out of range.
    pub fn path_to_source(&self, node: usize) -> Vec<usize> {
        if node >= self.dist.len() || !self.dist[node].is_finite() {
            return Vec::new();
        }
        let mut out = vec![node];
        let mut n = node;
        while self.pred[n] != NONE {
            n = self.pred[n] as usize;
            out.push(n);
        }
        out
    }
}

#[derive(PartialEq)]
struct Entry(f32, u32);

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl GroundGraph {
    /// Dijkstra from every node in `sources` at once (out-of-range ones are
    /// ignored): each node's distance is to its nearest source.
    pub fn shortest_paths(&self, sources: &[usize]) -> ShortestPaths {
        let n = self.positions.len();
        let mut dist = vec![f32::INFINITY; n];
        let mut pred = vec![NONE; n];
        let mut root = vec![NONE; n];
        let mut heap = BinaryHeap::new();
        for &s in sources.iter().filter(|&&s| s < n) {
            dist[s] = 0.0;
            root[s] = s as u32;
            heap.push(Entry(0.0, s as u32));
        }
        while let Some(Entry(d, u)) = heap.pop() {
            let u = u as usize;
            if u.is_multiple_of(256) {
                // Long searches on city graphs show the watchdog they advance.
                crate::work::step();
            }
            if d > dist[u] {
                continue;
            }
            for e in self.adj_start[u]..self.adj_start[u + 1] {
                let (v, w) = (self.adj[e] as usize, self.adj_w[e]);
                let nd = d + w;
                if nd < dist[v] {
                    dist[v] = nd;
                    pred[v] = u as u32;
                    root[v] = root[u];
                    heap.push(Entry(nd, v as u32));
                }
            }
        }
        ShortestPaths { dist, pred, root }
    }

    /// The shortest node path from `a` to `b` and its length; `None` when
    /// either is out of range or `b` cannot be reached.
    pub fn shortest_path(&self, a: usize, b: usize) -> Option<(f32, Vec<usize>)> {
        if a >= self.positions.len() || b >= self.positions.len() {
            return None;
        }
        let sp = self.shortest_paths(&[b]);
        let d = sp.dist[a];
        d.is_finite().then(|| (d, sp.path_to_source(a)))
    }
}
