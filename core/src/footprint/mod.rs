//! Step 2 of the method: individualize buildings with 2D footprints.
//!
//! - [`Footprint`] (`types`): one building's outline in the local frame.
//! - Readers: [`read_footprints`] (then [`SourceFootprints::in_frame`], a
//!   cloud's CRS and unit) picks [`parse_geojson_with`], [`cityjson_footprints`],
//!   [`parse_fgb`] or [`parse_obj_footprints`]; each footprint keeps its own
//!   id ([`ReadOptions`], `ids`); bad polygons are skipped and listed in
//!   [`Loaded::skipped`], `polygon` makes the rest valid. [`resolve_source`]
//!   turns `--footprints model` into the scene's own files; [`load_given`]
//!   reads them as a node's params name them.
//! - [`footprints_of_scene`] (`scene`): the true footprints of a scene.
//! - [`split`] (`split`): a building id per point.
//! - [`derive`] (`derive`, `raster`, `trace`, `inset`): footprints from building points when none are given.
//! - [`iou`], [`match_footprints`] (`compare`): evaluation.

mod cityjson;
mod compare;
mod derive;
mod error;
mod flatgeobuf;
mod geojson;
mod ids;
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

pub use cityjson::{cityjson_footprints, parse_cityjson_footprints};
pub use compare::{FootprintMatch, Segmentation, iou, match_footprints, segmentation};
pub use derive::derive;
pub use error::{FootprintError, ParseError, RingProblem, Skipped};
pub use flatgeobuf::parse_fgb;
pub use geojson::{parse_geojson, parse_geojson_with};
pub use ids::{ID_FIELDS, ReadOptions};
pub use load::{
    MODEL_KEYWORD, SourceFootprints, load_footprints, load_footprints_in, load_given,
    read_footprints, resolve_source,
};
pub use obj::parse_obj_footprints;
pub use params::{DeriveParams, SplitParams};
pub use scene::footprints_of_scene;
pub use split::split;
pub use types::{Footprint, FootprintRings, Loaded};
