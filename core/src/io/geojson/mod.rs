//! GeoJSON: footprints read ([`footprints`]), and the pieces of the
//! documents written for the field ([`write`]: positions, rings, features).

pub mod footprints;
mod json;
pub mod write;
