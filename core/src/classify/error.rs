//! What can go wrong classifying, training or loading a model.

use crate::cloud::ColumnLength;
use crate::features::FeatureError;
use crate::forest::ForestError;

/// Errors of the classification pipeline.
#[derive(Debug, thiserror::Error)]
pub enum ClassifyError {
    /// The ground filter failed (bad parameters, no usable points).
    #[error(transparent)]
    Ground(#[from] crate::ground::CsfError),
    /// Bad cloud or feature parameters.
    #[error(transparent)]
    Features(#[from] FeatureError),
    /// Training or prediction of the forest failed.
    #[error(transparent)]
    Forest(#[from] ForestError),
    /// A ground filter, feature, forest or training parameter is out of range.
    #[error(transparent)]
    Param(#[from] crate::params::ParamError),
    /// A per-point column does not match the cloud.
    #[error(transparent)]
    LengthMismatch(#[from] ColumnLength),
    /// The cloud has no points.
    #[error("the cloud is empty")]
    Empty,
    /// A coordinate is NaN or infinite.
    #[error("coordinate of point {index} is not finite: drop or repair such points first")]
    NonFinite {
        /// First offending point.
        index: usize,
    },
    /// No point is flagged as ground, so heights above ground are unknown.
    #[error("no ground points: run the ground filter first or flag ground points")]
    NoGround,
    /// Training found no labelled samples of some class.
    #[error("training data have no samples of class {class}")]
    MissingClass {
        /// LAS code.
        class: u8,
    },
    /// The model's feature count does not match its feature definition.
    #[error("model expects {expected} features but the feature set has {got}: retrain the model")]
    ModelMismatch {
        /// Features the forest was trained on.
        expected: usize,
        /// Features computed now.
        got: usize,
    },
    /// The forest for clouds without echoes does not read the same features
    /// or give the same classes as the main forest.
    #[error(
        "the model's forest without echoes does not match its main forest (features or classes): retrain the model"
    )]
    ForestsDisagree,
    /// Simulating a training scan failed.
    #[error("simulating a training scan: {0}")]
    Simulation(String),
    /// Reading or writing a model file.
    #[error("model file {path}: {message}")]
    File {
        /// The file.
        path: String,
        /// What failed.
        message: String,
    },
}
