//! Step 2 of the method: individualize buildings with 2D footprints.
//!
//! - [`Footprint`] (`types`): one building's outline in the local frame.
//! - Footprint files are read in [`crate::io`] (`io::read_footprints` and
//!   the readers per format); each footprint keeps its own id
//!   ([`ReadOptions`], `ids`); bad polygons are skipped and listed in
//!   [`Loaded::skipped`], `polygon` makes the rest valid.
//! - [`footprints_of_scene`] (`scene`): the true footprints of a scene.
//! - [`split`] (`split`): a building id per point.
//! - [`derive`] (`derive`, `raster`, `valley`, `trace`, `inset`): footprints from building points when none are given.
//! - [`iou`], [`match_footprints`] (`compare`): evaluation.

mod compare;
mod derive;
pub(crate) mod error;
pub(crate) mod ids;
mod inset;
mod params;
pub(crate) mod polygon;
mod raster;
mod scene;
mod split;
mod trace;
mod types;
mod valley;

pub use compare::{FootprintMatch, Segmentation, iou, match_footprints, segmentation};
pub use derive::derive;
pub use error::{ParseError, RingProblem, Skipped};
pub use ids::{ID_FIELDS, ReadOptions};
pub use inset::inset;
pub use params::{DeriveParams, SplitParams};
pub use scene::footprints_of_scene;
pub use split::split;
pub use types::{Footprint, FootprintRings, Loaded};
