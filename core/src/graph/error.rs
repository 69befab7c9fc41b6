//! Why a ground graph cannot be built.

/// Errors of [`GroundGraph::build`](super::GroundGraph::build).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GraphError {
    /// A parameter is out of range.
    #[error(transparent)]
    Param(#[from] crate::params::ParamError),
    /// `labels` does not have one entry per point.
    #[error(transparent)]
    LabelLength(#[from] crate::cloud::ColumnLength),
    /// No finite point is labelled ground (class 2): classify the cloud first.
    #[error("no ground points (class 2) in the cloud: classify it first")]
    NoGround,
    /// The ground is too large for the obstacle grid.
    #[error(
        "ground needs {cells} obstacle-grid cells, more than {max}: crop the scene to one cluster of buildings (skyground demo --crop) or raise occupancy_resolution_m"
    )]
    TooLarge {
        /// Cells the grid would need.
        cells: usize,
        /// The limit.
        max: usize,
    },
    /// The start is off the ground graph.
    #[error(
        "start ({x:.1}, {y:.1}) is {distance:.1} m from the nearest ground node (max_start_snap_m {max:.1}); move the start onto open ground"
    )]
    StartOffGraph {
        /// Start x.
        x: f32,
        /// Start y.
        y: f32,
        /// Distance to the nearest node, metres (infinite when there is none).
        distance: f32,
        /// The allowed distance.
        max: f32,
    },
    /// Fewer pieces of ground than the rank asked for.
    #[error("the ground graph has {pieces} pieces; piece {rank} (0 = the largest) does not exist")]
    NoSuchPiece {
        /// The rank asked for.
        rank: usize,
        /// Pieces there are.
        pieces: usize,
    },
}
