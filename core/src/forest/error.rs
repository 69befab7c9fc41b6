//! What can go wrong training, using or loading a forest.

/// Bad training data, parameters or model files.
#[derive(Debug, thiserror::Error)]
pub enum ForestError {
    /// No training rows.
    #[error("no training samples")]
    Empty,
    /// `dims` is zero or does not divide the data.
    #[error("{values} feature values do not form rows of {dims} features")]
    Shape {
        /// Values given.
        values: usize,
        /// Features per row.
        dims: usize,
    },
    /// Labels and rows differ in number.
    #[error("{rows} rows but {labels} labels")]
    LabelCount {
        /// Rows.
        rows: usize,
        /// Labels.
        labels: usize,
    },
    /// A feature value is NaN or infinite.
    #[error("feature {feature} of row {row} is not finite")]
    NonFinite {
        /// Row.
        row: usize,
        /// Column.
        feature: usize,
    },
    /// Rows to predict have another width than the training data.
    #[error("the forest was trained on {expected} features, got rows of {got}")]
    Dims {
        /// Trained width.
        expected: usize,
        /// Given width.
        got: usize,
    },
    /// A parameter is out of range.
    #[error(transparent)]
    Param(#[from] crate::params::ParamError),
    /// A model file could not be read or written.
    #[error("forest model I/O: {0}")]
    Io(#[from] serde_json::Error),
    /// A loaded model is inconsistent (edited or truncated file).
    #[error("corrupt forest model: {0}")]
    Corrupt(String),
}
