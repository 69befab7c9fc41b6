//! The skeleton itself: a graph in xy, what medial-axis extraction makes and
//! pruning thins.

use crate::geom::segment;

/// A skeleton as a graph in xy.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Skeleton {
    /// Node positions.
    pub nodes: Vec<[f64; 2]>,
    /// Edges between node indices.
    pub edges: Vec<[usize; 2]>,
}

impl Skeleton {
    /// The skeleton point nearest `q` (nodes and points along edges); None
    /// when the skeleton is empty.
    pub fn nearest(&self, q: [f64; 2]) -> Option<[f64; 2]> {
        let mut best: Option<([f64; 2], f64)> = None;
        let mut offer = |p: [f64; 2]| {
            let d = (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
            if best.is_none_or(|(_, b)| d < b) {
                best = Some((p, d));
            }
        };
        for &[a, b] in &self.edges {
            offer(segment::closest(q, self.nodes[a], self.nodes[b]).0);
        }
        if self.edges.is_empty() {
            self.nodes.iter().for_each(|&p| offer(p));
        }
        best.map(|(p, _)| p)
    }

    /// Total edge length, metres.
    pub fn length(&self) -> f64 {
        self.edges
            .iter()
            .map(|&[a, b]| {
                let (p, q) = (self.nodes[a], self.nodes[b]);
                ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt()
            })
            .sum()
    }
}
