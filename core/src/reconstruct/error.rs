//! What can go wrong when reconstructing, in terms a user can act on.

use crate::params::ParamError;

/// Errors of [`super::reconstruct_cloud`] and the writers.
#[derive(Debug, thiserror::Error)]
pub enum ReconstructError {
    /// A reconstruction or footprint parameter is out of range.
    #[error(transparent)]
    Param(#[from] ParamError),
    /// The cloud is empty, or unclassified with no finite point.
    #[error(
        "the cloud has no points to take for buildings: give a classified cloud (LAS class 6 = building; `skyground classify`)"
    )]
    NoBuildingPoints,
    /// Writing an output failed.
    #[error("writing {what}: {source}")]
    Write {
        /// What was being written.
        what: String,
        /// The I/O error.
        source: std::io::Error,
    },
}

/// Why one building got no model (the others still do).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Skip {
    /// No point of the cloud lies in its footprint (outside the survey).
    NoPoints,
    /// Fewer points than a plane needs.
    TooFewPoints,
    /// No roof plane was found in its points.
    NoRoofPlane,
    /// Its footprint covers no raster cell.
    EmptyFootprint,
    /// Its LoD 2.2 solid failed the ISO 19107 checks (the codes are in
    /// the model's `rejected_val3dity`).
    InvalidSolid,
}
