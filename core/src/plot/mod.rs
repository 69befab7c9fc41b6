//! Top-down pictures (PNG) of what the method found: clouds, contours,
//! skeletons, missing points, routes. Plain raster drawing with a small
//! bitmap font for the map furniture every picture carries (legend, scale
//! bar in the input's unit, north arrow): a picture is for looking at, the
//! numbers go to JSON.

mod canvas;
mod color;
mod font;
mod furniture;
mod models;
mod plan;
mod scene;
mod side;

pub use canvas::{Canvas, PlotError};
pub use color::{Rgb, ramp};
pub use furniture::nice_length;
pub use models::{ModelView, models_picture};
pub use plan::{PlanView, plan_picture};
pub use scene::{BuildingGain, detection_picture, mission_picture};
pub use side::side_picture;
