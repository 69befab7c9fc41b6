//! Top-down pictures (PNG) of what the method found: clouds, contours,
//! skeletons, missing points, routes. Plain raster drawing, no fonts: a
//! picture is for looking at, the numbers go to JSON.

mod canvas;
mod color;
mod models;
mod scene;

pub use canvas::{Canvas, PlotError};
pub use color::{Rgb, ramp};
pub use models::{ModelView, models_picture};
pub use scene::{BuildingGain, detection_picture, mission_picture};
