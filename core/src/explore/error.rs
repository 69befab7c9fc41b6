//! Why a region cannot be explored.

/// Errors of the explorer and of the voxel merge ([`VoxelMerge`](super::VoxelMerge), [`resample`](super::resample)).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ExploreError {
    /// A parameter is out of range.
    #[error(transparent)]
    Param(#[from] crate::params::ParamError),
    /// Normals were given but not one per surface sample.
    #[error("{samples} surface samples but {normals} normals; give one normal per sample or none")]
    NormalLength {
        /// Number of samples.
        samples: usize,
        /// Number of normals.
        normals: usize,
    },
    /// The region outline has fewer than three corners.
    #[error("region of building {building} has {corners} corners; at least 3 are needed")]
    DegenerateRegion {
        /// The region's building.
        building: u32,
        /// Corners given.
        corners: usize,
    },
    /// The resampling voxel is not a positive finite size.
    #[error("voxel size {0} must be finite and > 0 (a merge also takes 0: every point kept)")]
    Voxel(f32),
}
