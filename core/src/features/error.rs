//! What can go wrong computing features.

/// Bad input to [`super::compute`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FeatureError {
    /// The cloud has no points.
    #[error("the cloud is empty: features need at least {need} points")]
    Empty {
        /// Smallest usable cloud.
        need: usize,
    },
    /// Too few points to form a neighbourhood.
    #[error("the cloud has {got} points; features need at least {need}")]
    TooFewPoints {
        /// Points given.
        got: usize,
        /// Smallest usable cloud.
        need: usize,
    },
    /// `hag` (or another per-point column) does not match `xyz`.
    #[error(transparent)]
    LengthMismatch(#[from] crate::cloud::ColumnLength),
    /// A coordinate or height is NaN or infinite.
    #[error("{what} of point {index} is not finite: drop or repair such points first")]
    NonFinite {
        /// Which column.
        what: &'static str,
        /// Index of the first offending point.
        index: usize,
    },
    /// A requested row is not a point of the cloud.
    #[error("row {row} is out of range for a cloud of {len} points")]
    RowOutOfRange {
        /// The row asked for.
        row: usize,
        /// Number of points.
        len: usize,
    },
    /// A parameter is out of range.
    #[error(transparent)]
    Param(#[from] crate::params::ParamError),
}
