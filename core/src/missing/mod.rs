//! Missing-region detection (docs/design.md step 3, and the choice of step 4):
//! per building, the boundary points q_n of each slice contour are tested
//! against the slice's points along the segment from the nearest skeleton
//! point s_m; those without enough points near the wall are missing.
//!
//! - [`params`] — [`DetectParams`].
//! - [`detection`] — results ([`BuildingDetection`], [`Detection`], [`MissingPoint`]).
//! - [`building`] — [`detect_building`].
//! - [`all`] — [`detect_all`] over every building (rayon).
//! - [`boundary`] — contour sampling; [`band`], point index by band and cell;
//!   [`coverage`], the strip test.
//! - [`ground`] — terrain grid, so sloped ground is not taken for missing wall.
//! - [`wall`] — the wall's direction near q_n, and open ground floors.
//! - [`eval`] — recall / precision against ground-truth wall cells;
//!   [`explain`], where the false missing points lie.

pub mod all;
pub mod band;
pub mod boundary;
pub mod building;
pub mod coverage;
pub mod detection;
pub mod eval;
pub mod explain;
pub mod ground;
pub mod params;
pub mod scene;
pub mod wall;

pub use all::{DetectError, detect_all, detect_all_on};
pub use building::{detect_building, detect_building_on};
pub use detection::{
    BoundaryPoint, BuildingDetection, Detection, MissingPoint, SkipReason, SliceReport, Strategy,
    StructureReport,
};
pub use eval::{BuildingScore, DetectionScore, WallCounts, evaluate};
pub use explain::{Breakdown, Row, evaluate_explained};
pub use ground::GroundGrid;
pub use params::DetectParams;
pub use scene::{SceneDetectError, SceneParams, derive_footprints, detect_scene, shift_missing};
