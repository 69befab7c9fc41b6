//! Ground built around buildings that a city model ships without it: a grid
//! over each footprint box through the buildings' bases (`around`), and
//! streets joining clusters whose patches do not meet (`streets`).

mod around;
mod base;
mod streets;

pub(crate) use around::blend_bases;
pub use around::{TerrainOptions, terrain_around};
pub use base::Footprint;
