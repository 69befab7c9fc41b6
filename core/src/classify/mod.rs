//! Step 1 of docs/design.md as one pipeline: ground from the ground filter,
//! then vegetation vs building by the Random Forest on per-point features;
//! training on simulated scenes and evaluation against labels.
//!
//! - [`hag`]: height above ground from ground-flagged points (a stand-in
//!   ground model until the CSF's own surface is used).
//! - [`model`]: [`Model`] (feature params + forest), one JSON file.
//! - [`pipeline`]: [`classify`] → LAS codes.
//! - [`blocks`]: the forest's votes block by block on large clouds.
//! - [`scene`]: [`SceneClassifier`]: CSF ground + forest on a raw cloud; [`GroundReport`].
//! - [`lone`]: [`lone_ground`]: where the forest has no neighbour to read, the terrain's slope decides.
//! - [`roofs`]: [`check_roofs`]: large planes are roofs, roofless objects vegetation.
//! - [`report`]: [`ClassReport`] (confusion matrix, precision / recall / F1).
//! - [`coherence`]: [`label_coherence`]: how far the reference labels agree with their neighbours'.
//! - [`disputes`]: [`shapes_by_pairing`]: what the points look like where the reference and we agree and part.
//! - [`training`]: [`TrainingCloud`], [`TrainParams`], [`train`],
//!   [`default_training_set`] (simulated airborne scans of several seeds).

pub mod blocks;
pub mod coherence;
pub mod disputes;
pub mod error;
pub mod grade;
pub mod hag;
pub mod lone;
pub mod model;
pub mod pipeline;
pub mod report;
pub mod roofs;
pub mod scene;
pub mod smooth;
pub mod training;

pub use coherence::{LabelCoherence, label_coherence};
pub use disputes::{PairShape, shapes_by_pairing};
pub use error::ClassifyError;
pub use grade::{AtGrade, join_terrain};
pub use hag::hag_from_ground_points;
pub use lone::lone_ground;
pub use model::{Model, Smoothing};
pub use pipeline::{classify, classify_at};
pub use report::{ClassMetrics, ClassReport, is_scored};
pub use roofs::{RoofCheck, RoofCheckCounts, check_roofs};
pub use scene::{Classified, GroundReport, SceneClassifier, echoes_of};
pub use training::{
    DEFAULT_DENSITIES, FileRole, TrainParams, TrainingCloud, default_training_set,
    file_training_clouds, labelled_cloud, pulse_sample, simulated_cloud, train, training_surveys,
};
