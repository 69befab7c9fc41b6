//! What can go wrong in ground filtering, with what to do about it.

/// Errors of [`super::csf`] and [`super::CsfParams::validate`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CsfError {
    /// The cloud has no points at all.
    #[error("ground filter: the cloud is empty; give it at least one point")]
    Empty,
    /// Every point has a NaN or infinite coordinate.
    #[error("ground filter: none of the {count} points has finite x, y, z")]
    NoFinitePoints {
        /// Number of points given.
        count: usize,
    },
    /// A parameter is outside its allowed range.
    #[error(transparent)]
    Param(#[from] crate::params::ParamError),
    /// The cloud's extent divided by the cloth resolution gives too many particles.
    #[error(
        "ground filter: cloth of {nx} × {ny} particles exceeds {max}; raise cloth_resolution or split the cloud"
    )]
    ClothTooLarge {
        /// Particles along x.
        nx: usize,
        /// Particles along y.
        ny: usize,
        /// The largest particle count allowed.
        max: usize,
    },
}
