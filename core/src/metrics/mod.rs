//! Metrics (docs/design.md "Metrics"): ground-truth samples of building surfaces,
//! completeness against an observed cloud, and the two mean-distance terms.
//!
//! - [`gt`]: [`sample_building_surfaces`] → [`GtSamples`] (walls + roofs at
//!   spacing s, bottoms and buried faces left out).
//! - [`completeness`]: share of GT samples with an observed point within τ,
//!   overall / per building / walls vs roofs, and the gap term
//!   [`mean_gt_distance`].
//! - [`accuracy`]: the accuracy term [`mean_cloud_to_mesh`].
//! - [`mesh_distance`]: point-to-mesh distance on a grid or parry3d's `TriMesh`.
//! - [`evaluation`]: both terms and completeness before/after a mission.
//! - [`producer`]: missing points and targets against a survey producer's
//!   building class.

pub mod accuracy;
pub mod completeness;
pub mod evaluation;
mod ground_height;
pub mod gt;
pub mod mesh_distance;
mod nearest;
pub mod producer;
pub(crate) mod triangle_grid;
mod winding;

pub use accuracy::{cloud_to_mesh_distances, cloud_to_mesh_distances_with, mean_cloud_to_mesh};
pub use completeness::{
    BuildingCompleteness, CompletenessReport, Coverage, DEFAULT_TAU, completeness,
    completeness_of_cloud, mean_gt_distance, report_from_distances,
};
pub use evaluation::{
    BuildingRow, Evaluation, MeasureSoFar, Measured, building_points, compare, evaluate,
};
pub use ground_height::GroundHeight;
pub use gt::{
    DEFAULT_SPACING, GtOptions, GtSamples, SurfaceKind, sample_building_surfaces,
    sample_building_surfaces_with,
};
pub use mesh_distance::{MeshBackend, MeshDistance};
pub use nearest::{nearest_distances, nearest_indices};
pub use producer::{ProducerCheck, TARGET_REACH_M, producer_check};
