//! Random Forest hyper-parameters.

use serde::{Deserialize, Serialize};

use crate::params::{Checks, ParamError};

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
    pub fn validate(&self) -> Result<(), ParamError> {
        let c = Checks("forest");
        let fraction = self.sample_fraction;
        c.within("trees", self.trees as f64, 1.0, 10_000.0)?;
        c.within("max_depth", self.max_depth as f64, 1.0, 64.0)?;
        c.that(
            self.min_samples_leaf > 0,
            "min_samples_leaf",
            0,
            "must be ≥ 1",
        )?;
        let some = self.max_features != Some(0);
        c.that(
            some,
            "max_features",
            0,
            "must be ≥ 1 (or null for √features)",
        )?;
        let fraction_ok = fraction > 0.0 && fraction <= 4.0;
        c.that(
            fraction_ok,
            "sample_fraction",
            fraction,
            "must be in (0, 4]",
        )?;
        c.within("bins", self.bins as f64, 2.0, 256.0)
    }
}
