//! What the drone's viewpoints and sorties are chosen by.

use serde::{Deserialize, Serialize};

use crate::params::{Checks, ParamError};

/// Viewpoint and sortie parameters (the `sorties.*` params).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SortieParams {
    /// Horizontal distances from a gap, along its outward normal, at which
    /// viewpoints are tried, m.
    pub standoffs_m: Vec<f32>,
    /// Heights above a gap at which viewpoints are tried, m (the LiDAR
    /// looks down to 52° below its horizon).
    pub rises_m: Vec<f32>,
    /// Farthest a gap counts as seen, m (the Mid-360 is rated 40 m at 10 %
    /// reflectivity; its points are dense enough for a facade to ~20 m).
    pub range_m: f32,
    /// Most a sight line may be off a wall's normal, degrees.
    pub max_incidence_deg: f32,
    /// The sensor's field of view above its horizon, degrees (mounted upside down).
    pub fov_up_deg: f32,
    /// The sensor's field of view below its horizon, degrees.
    pub fov_down_deg: f32,
    /// Hovering time at a viewpoint, s (a few LiDAR frames).
    pub hover_s: f32,
    /// Candidates closer than this to a kept one are dropped, m.
    pub thin_m: f32,
}

impl Default for SortieParams {
    fn default() -> Self {
        Self {
            standoffs_m: vec![5.0, 9.0],
            rises_m: vec![0.0, 4.0, 8.0],
            range_m: 20.0,
            max_incidence_deg: 70.0,
            fov_up_deg: 7.0,
            fov_down_deg: 52.0,
            hover_s: 2.0,
            thin_m: 1.5,
        }
    }
}

impl SortieParams {
    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), ParamError> {
        let c = Checks("sorties");
        c.that(
            !self.standoffs_m.is_empty(),
            "standoffs_m",
            0.0,
            "at least one",
        )?;
        c.that(!self.rises_m.is_empty(), "rises_m", 0.0, "at least one")?;
        for &s in &self.standoffs_m {
            c.positive("standoffs_m", s)?;
        }
        for &r in &self.rises_m {
            c.that(r.is_finite(), "rises_m", r, "must be finite")?;
        }
        c.positive("range_m", self.range_m)?;
        c.within("max_incidence_deg", self.max_incidence_deg, 0.0, 90.0)?;
        c.within("fov_up_deg", self.fov_up_deg, -90.0, 90.0)?;
        c.within("fov_down_deg", self.fov_down_deg, -90.0, 90.0)?;
        c.non_negative("hover_s", self.hover_s)?;
        c.non_negative("thin_m", self.thin_m)
    }
}
