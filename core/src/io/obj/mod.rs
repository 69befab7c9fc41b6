//! Wavefront OBJ: scenes read ([`scene`]) and written ([`scene_write`]),
//! footprints read ([`footprints`]), models written ([`models`]).

pub mod footprints;
pub mod models;
pub mod scene;
pub mod scene_write;
