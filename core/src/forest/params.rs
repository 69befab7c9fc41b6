//! Random Forest hyper-parameters.

use serde::{Deserialize, Serialize};

use super::error::ForestError;

/// How many trees, how deep, how random.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ForestParams {
    /// Number of trees.
    pub trees: usize,
    /// Deepest split level (root = 0).
    pub max_depth: usize,
    /// Fewest training samples in a leaf.
    pub min_samples_leaf: usize,
    /// Features tried per split; `None`: √(features).
    pub max_features: Option<usize>,
    /// Bootstrap sample size per tree, as a fraction of the rows (drawn
    /// with replacement).
    pub sample_fraction: f32,
    /// Quantile bins per feature for the split search (2–256).
    pub bins: usize,
    /// Seed of bootstrap and feature draws.
    pub seed: u64,
}

impl Default for ForestParams {
    fn default() -> Self {
        Self {
            trees: 48,
            max_depth: 18,
            min_samples_leaf: 4,
            max_features: None,
            sample_fraction: 1.0,
            bins: 64,
            seed: 7,
        }
    }
}

impl ForestParams {
    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), ForestError> {
        let bad = |field, value: f64, rule| Err(ForestError::Param { field, value, rule });
        if !(1..=10_000).contains(&self.trees) {
            return bad("trees", self.trees as f64, "must be in 1..=10000");
        }
        if !(1..=64).contains(&self.max_depth) {
            return bad("max_depth", self.max_depth as f64, "must be in 1..=64");
        }
        if self.min_samples_leaf == 0 {
            return bad("min_samples_leaf", 0.0, "must be ≥ 1");
        }
        if self.max_features == Some(0) {
            return bad("max_features", 0.0, "must be ≥ 1 (or null for √features)");
        }
        if !(self.sample_fraction > 0.0 && self.sample_fraction <= 4.0) {
            return bad(
                "sample_fraction",
                self.sample_fraction.into(),
                "must be in (0, 4]",
            );
        }
        if !(2..=256).contains(&self.bins) {
            return bad("bins", self.bins as f64, "must be in 2..=256");
        }
        Ok(())
    }
}
