//! Step 2 of the method: individualize buildings with 2D footprints.
//!
//! - [`Footprint`] (`types`): one building's outline in the local frame.
//! - Readers: [`load_footprints`] (or [`load_footprints_in`] a cloud's CRS and unit) picks [`parse_geojson`],
//!   [`parse_cityjson_footprints`] or [`parse_obj_footprints`]; bad polygons
//!   are skipped and listed in [`Loaded::skipped`], `polygon` makes the rest valid.
//! - [`footprints_of_scene`] (`scene`): the true footprints of a scene.
//! - [`split`] (`split`): a building id per point.
//! - [`derive`] (`derive`, `raster`, `trace`, `inset`): footprints from building points when none are given.
//! - [`iou`], [`match_footprints`] (`compare`): evaluation.

mod cityjson;
mod compare;
mod derive;
mod error;
mod geojson;
mod inset;
mod json;
mod load;
mod obj;
mod params;
mod polygon;
mod raster;
mod scene;
mod split;
mod trace;
mod types;

pub use cityjson::parse_cityjson_footprints;
pub use compare::{FootprintMatch, iou, match_footprints};
pub use derive::derive;
pub use error::{FootprintError, ParseError, RingProblem, Skipped};
pub use geojson::parse_geojson;
pub use load::{load_footprints, load_footprints_in};
pub use obj::parse_obj_footprints;
pub use params::{DeriveParams, SplitParams};
pub use scene::footprints_of_scene;
pub use split::split;
pub use types::{Footprint, FootprintRings, Loaded};
