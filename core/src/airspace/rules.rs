//! What the drone's airspace allows: its ceiling, its distances to facades
//! and to everything else, and an optional geofence.

use geo::MultiPolygon;
use serde::{Deserialize, Serialize};

use crate::footprint::Footprint;
use crate::params::{Checks, ParamError};

/// The rules a drone's plan must keep (the `airspace.*` params); the
/// geofence is given apart ([`super::Airspace::with_fence`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AirspaceRules {
    /// Highest flight above the take-off point, m (120 m: the usual legal
    /// limit for open-category drones).
    pub ceiling_m: f32,
    /// Nearest a plan may come to a building (facade or roof), m.
    pub facade_min_m: f32,
    /// Kept beyond the body radius from everything else (ground, trees,
    /// anything the prior holds), m: a crown's edge is thinly sampled from
    /// above, so 2 m (in the reference mission 0.5 m let the body brush 95
    /// crowns and walls the prior under-drew).
    pub margin_m: f32,
    /// Edge of the height-map cells built from the prior, m.
    pub cell_m: f32,
}

impl Default for AirspaceRules {
    fn default() -> Self {
        Self {
            ceiling_m: 120.0,
            facade_min_m: 3.0,
            margin_m: 2.0,
            cell_m: 0.5,
        }
    }
}

impl AirspaceRules {
    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), ParamError> {
        let c = Checks("airspace");
        c.positive("ceiling_m", self.ceiling_m)?;
        c.non_negative("facade_min_m", self.facade_min_m)?;
        c.non_negative("margin_m", self.margin_m)?;
        c.within("cell_m", self.cell_m, 0.05, 10.0)
    }
}

/// A geofence: the polygons the drone must stay inside, in the prior's
/// local frame (xy, m).
pub type Geofence = MultiPolygon<f64>;

/// The geofence made of every polygon of `areas` (a GeoJSON read as
/// footprints are, in the prior's frame): the drone may be inside any.
pub fn geofence(areas: &[Footprint]) -> Geofence {
    MultiPolygon(
        areas
            .iter()
            .flat_map(|f| f.polygon.0.iter().cloned())
            .collect(),
    )
}
