//! Quantile bins per feature: the split candidates of the tree search.

use rayon::prelude::*;

/// Per feature, ascending thresholds; bin `b` holds values `v` with
/// `t[b-1] < v ≤ t[b]` (the last bin: `v > t[last]`).
pub struct Bins {
    /// Thresholds per feature.
    pub thresholds: Vec<Vec<f32>>,
    /// Bin of every value, feature-major (`codes[f * rows + i]`).
    pub codes: Vec<u8>,
    /// Rows.
    pub rows: usize,
}

impl Bins {
    /// Bins `x` (`rows × dims`, row-major) into at most `bins` quantile bins per feature.
    pub fn new(x: &[f32], dims: usize, bins: usize) -> Self {
        let rows = x.len() / dims;
        let thresholds: Vec<Vec<f32>> = (0..dims)
            .into_par_iter()
            .map(|f| {
                let step = (rows / 20_000).max(1);
                let mut v: Vec<f32> = (0..rows).step_by(step).map(|i| x[i * dims + f]).collect();
                v.sort_by(f32::total_cmp);
                let mut t: Vec<f32> = (1..bins)
                    .map(|b| v[(b * v.len() / bins).min(v.len() - 1)])
                    .collect();
                t.dedup();
                // A threshold at the maximum splits nothing off.
                if t.last().is_some_and(|&l| Some(&l) == v.last()) {
                    t.pop();
                }
                t
            })
            .collect();
        let codes: Vec<u8> = (0..dims)
            .into_par_iter()
            .flat_map_iter(|f| {
                let t = &thresholds[f];
                (0..rows).map(move |i| t.partition_point(|&th| th < x[i * dims + f]) as u8)
            })
            .collect();
        Self {
            thresholds,
            codes,
            rows,
        }
    }

    /// Codes of feature `f`.
    pub fn column(&self, f: usize) -> &[u8] {
        &self.codes[f * self.rows..(f + 1) * self.rows]
    }
}
