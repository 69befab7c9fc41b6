//! A Random Forest classifier (docs/design.md step 1): CART trees with Gini
//! splits on bootstrap samples and random feature subsets, majority vote.
//! Trees train and predict in parallel (rayon) and the result depends only
//! on the data and the seed.
//!
//! Splits are searched on per-feature quantile bins (histograms), which
//! keeps training linear in the samples per level; thresholds are stored as
//! real feature values, so prediction needs no binning.
//!
//! - [`params`]: [`ForestParams`]. - [`error`]: [`ForestError`].
//! - `bins`: quantile binning. - `tree`: one tree, grown and evaluated.
//! - `rng`: the seeded generator. - [`model`]: [`RandomForest`].

mod bins;
pub mod error;
pub mod model;
pub mod params;
mod tree;

pub use error::ForestError;
pub use model::RandomForest;
pub use params::ForestParams;

/// The generator of tree `tree` of a forest grown from `seed` (its own
/// key, so forests trained before the generator was shared grow the same).
pub(crate) fn tree_rng(seed: u64, tree: u64) -> crate::rng::Rng {
    crate::rng::Rng::split(seed, tree, 0xA076_1D64_78BD_642F)
}
