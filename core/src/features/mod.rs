//! Per-point features for classification (docs/design.md step 1): eigen-features
//! of each point's k nearest neighbours, of fixed-radius neighbourhoods on a
//! voxel-thinned cloud, vertical column extents, echoes (multiple returns)
//! and the height above ground.
//!
//! The features are ratios or metric lengths at fixed radii, not absolute
//! densities, so a model trained on one point density transfers to others.
//!
//! - [`params`]: [`FeatureParams`] (k, radii, voxel size).
//! - [`compute`]: [`compute`], [`compute_subset`] → [`Features`]; [`FEATURE_NAMES`].
//! - covariance eigen-analysis of one neighbourhood: [`crate::geom`]'s `shape`.
//! - [`echo`]: return number / number of returns, the real-survey cue for vegetation.
//! - `voxel`: the thinned cloud and its radius / column statistics.

pub mod compute;
pub mod echo;
pub mod error;
pub mod params;
mod voxel;

pub use compute::{FEATURE_NAMES, Features, R1_PLANARITY, compute, compute_subset};
pub use echo::Echoes;
pub use error::FeatureError;
pub use params::FeatureParams;
