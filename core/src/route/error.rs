//! Why a route cannot be planned.

/// Errors of [`plan`](super::plan).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RouteError {
    /// A parameter is out of range.
    #[error(transparent)]
    Param(#[from] crate::params::ParamError),
    /// The start is not near the ground graph.
    #[error(
        "start ({x:.1}, {y:.1}) is more than max_snap_m = {max:.1} m from the ground graph; move it onto open ground reachable from the graph's start"
    )]
    StartOffGraph {
        /// Start x.
        x: f32,
        /// Start y.
        y: f32,
        /// The allowed distance.
        max: f32,
    },
    /// A piece of ground for a set-down could not be built.
    #[error(transparent)]
    Graph(#[from] crate::graph::GraphError),
}
