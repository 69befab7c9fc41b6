//! One CART tree: grown on binned features with Gini splits, stored flat in
//! pre-order (a node's left child is the next node).

use serde::{Deserialize, Serialize};

use super::bins::Bins;
use crate::rng::Rng;

/// `feature` value marking a leaf.
pub const LEAF: u16 = u16::MAX;

/// A tree as three parallel columns (compact in JSON).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Tree {
    /// Split feature per node, or [`LEAF`].
    pub feature: Vec<u16>,
    /// Split threshold (go left when value ≤ threshold); unused in leaves.
    pub threshold: Vec<f32>,
    /// Index of the right child; in leaves, the class index.
    pub right: Vec<u32>,
}

impl Tree {
    /// Class index of the leaf `row` falls into.
    pub fn leaf_class(&self, row: &[f32]) -> u32 {
        let mut i = 0usize;
        loop {
            let f = self.feature[i];
            if f == LEAF {
                return self.right[i];
            }
            i = if row[f as usize] <= self.threshold[i] {
                i + 1
            } else {
                self.right[i] as usize
            };
        }
    }

    /// Checks child links and indices so `leaf_class` cannot go out of range.
    pub fn check(&self, dims: usize, classes: usize) -> Result<(), String> {
        let n = self.feature.len();
        if n == 0 || self.threshold.len() != n || self.right.len() != n {
            return Err("tree columns differ in length or are empty".into());
        }
        for i in 0..n {
            let (f, r) = (self.feature[i], self.right[i] as usize);
            if f == LEAF {
                if r >= classes {
                    return Err(format!("leaf {i} has class {r} of {classes}"));
                }
            } else if f as usize >= dims || r <= i + 1 || r >= n || i + 1 >= n {
                return Err(format!("node {i} links out of order"));
            }
        }
        Ok(())
    }
}

/// What growing one tree needs besides its sample.
pub struct Grow<'a> {
    /// Binned training features.
    pub bins: &'a Bins,
    /// Class index per row.
    pub y: &'a [u8],
    /// Number of classes.
    pub classes: usize,
    /// Features tried per split.
    pub mtry: usize,
    /// Deepest split level.
    pub max_depth: usize,
    /// Fewest samples in a leaf.
    pub min_leaf: usize,
}

/// Grows a tree on the rows `sample` (may repeat); also returns the Gini
/// decrease per feature (in sample counts).
pub fn grow(g: &Grow, sample: &mut [u32], rng: &mut Rng) -> (Tree, Vec<f64>) {
    let dims = g.bins.thresholds.len();
    let mut b = Builder {
        g,
        tree: Tree {
            feature: Vec::new(),
            threshold: Vec::new(),
            right: Vec::new(),
        },
        importance: vec![0.0; dims],
        order: (0..dims).collect(),
        hist: vec![0u32; 257 * g.classes],
    };
    b.node(sample, 0, rng);
    (b.tree, b.importance)
}

struct Builder<'a> {
    g: &'a Grow<'a>,
    tree: Tree,
    importance: Vec<f64>,
    order: Vec<usize>,
    hist: Vec<u32>,
}

struct Split {
    feature: usize,
    bin: usize,
    score: f64,
}

impl Builder<'_> {
    fn push(&mut self, feature: u16, threshold: f32, right: u32) -> usize {
        self.tree.feature.push(feature);
        self.tree.threshold.push(threshold);
        self.tree.right.push(right);
        self.tree.feature.len() - 1
    }

    fn node(&mut self, idx: &mut [u32], depth: usize, rng: &mut Rng) {
        let c = self.g.classes;
        let mut counts = vec![0u32; c];
        for &i in idx.iter() {
            counts[self.g.y[i as usize] as usize] += 1;
        }
        let majority = argmax(&counts);
        let n = idx.len();
        let pure = counts.iter().filter(|&&k| k > 0).count() <= 1;
        if pure || depth >= self.g.max_depth || n < 2 * self.g.min_leaf {
            self.push(LEAF, 0.0, majority);
            return;
        }
        let Some(split) = self.best_split(idx, &counts, rng) else {
            self.push(LEAF, 0.0, majority);
            return;
        };
        let parent = sum_sq(&counts) / n as f64;
        self.importance[split.feature] += split.score - parent;
        let codes = self.g.bins.column(split.feature);
        let mut left = 0;
        for k in 0..n {
            if usize::from(codes[idx[k] as usize]) <= split.bin {
                idx.swap(k, left);
                left += 1;
            }
        }
        let threshold = self.g.bins.thresholds[split.feature][split.bin];
        let at = self.push(split.feature as u16, threshold, 0);
        let (l, r) = idx.split_at_mut(left);
        self.node(l, depth + 1, rng);
        let right_at = self.tree.feature.len();
        self.tree.right[at] = right_at as u32;
        self.node(r, depth + 1, rng);
        // Two leaves voting alike are one leaf: smaller model, same votes.
        let t = &self.tree;
        if t.feature.len() == at + 3
            && t.feature[at + 1] == LEAF
            && t.feature[at + 2] == LEAF
            && t.right[at + 1] == t.right[at + 2]
        {
            let class = t.right[at + 1];
            self.tree.feature.truncate(at);
            self.tree.threshold.truncate(at);
            self.tree.right.truncate(at);
            self.push(LEAF, 0.0, class);
        }
    }

    fn best_split(&mut self, idx: &[u32], counts: &[u32], rng: &mut Rng) -> Option<Split> {
        let c = self.g.classes;
        let n = idx.len();
        let dims = self.order.len();
        let mut best: Option<Split> = None;
        for t in 0..self.g.mtry.min(dims) {
            let pick = t + rng.below(dims - t);
            self.order.swap(t, pick);
            let f = self.order[t];
            let nt = self.g.bins.thresholds[f].len();
            if nt == 0 {
                continue;
            }
            let codes = self.g.bins.column(f);
            let hist = &mut self.hist[..(nt + 1) * c];
            hist.fill(0);
            for &i in idx {
                let i = i as usize;
                hist[usize::from(codes[i]) * c + usize::from(self.g.y[i])] += 1;
            }
            let mut left = vec![0u32; c];
            let mut nl = 0usize;
            for b in 0..nt {
                for k in 0..c {
                    left[k] += hist[b * c + k];
                    nl += hist[b * c + k] as usize;
                }
                let nr = n - nl;
                if nl < self.g.min_leaf || nr < self.g.min_leaf {
                    continue;
                }
                let sl: f64 = left.iter().map(|&v| f64::from(v) * f64::from(v)).sum();
                let sr: f64 = (0..c).map(|k| f64::from(counts[k] - left[k]).powi(2)).sum();
                let score = sl / nl as f64 + sr / nr as f64;
                if best.as_ref().is_none_or(|s| score > s.score + 1e-9) {
                    best = Some(Split {
                        feature: f,
                        bin: b,
                        score,
                    });
                }
            }
        }
        let parent = sum_sq(counts) / n as f64;
        best.filter(|s| s.score > parent + 1e-9)
    }
}

fn sum_sq(counts: &[u32]) -> f64 {
    counts.iter().map(|&v| f64::from(v) * f64::from(v)).sum()
}

fn argmax(counts: &[u32]) -> u32 {
    let mut best = 0;
    for (k, &v) in counts.iter().enumerate() {
        if v > counts[best] {
            best = k;
        }
    }
    best as u32
}
