//! Tunables of the ground graph, filled from the planner's params YAML.

use serde::{Deserialize, Serialize};

use crate::density::{Auto, Density};
use crate::params::{Checks, ParamError};

/// Finest node spacing, metres: the reference prior's value.
const MIN_NODE_SPACING: f32 = 1.25;
/// Node spacing over ground point spacing: a node cell (2.5 s)² then holds
/// about 6 ground points, so gaps in sparse ground do not cut the graph.
const NODE_SPACINGS: f32 = 2.5;
/// Edge reach over node spacing: 1.9 / 1.25 m, joining the 8 neighbours
/// (√2 = 1.41) but not cells two apart (2).
const REACH_PER_SPACING: f32 = 1.52;

/// The most obstacle-grid cells a ground graph is built on (a memory bound:
/// about 3.5 km × 3.5 km of ground at the default 0.25 m resolution).
pub const MAX_OCCUPANCY_CELLS: f64 = 2.0e8;

/// How the ground graph is built (docs/design.md step 5).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GraphParams {
    /// Node spacing: ground points are binned into square cells this wide,
    /// one node per cell, metres; `auto`: [`GraphParams::spacing_rule`].
    pub node_spacing_m: Auto<f32>,
    /// Nodes closer than this (3D) are joined when the way between them is
    /// free, metres; `auto`: 1.52 node spacings.
    pub d_threshold_m: Auto<f32>,
    /// Height of the vehicle's body above the ground, metres.
    pub vehicle_height_m: f32,
    /// Half the vehicle's width: obstacles must stay this far from every edge, metres.
    pub vehicle_radius_m: f32,
    /// Steepest edge the vehicle climbs, degrees.
    pub max_slope_deg: f32,
    /// Non-ground points lower than this above the ground (curbs, noise) do not block, metres.
    pub clearance_m: f32,
    /// Cell size of the obstacle grid the edges are checked against, metres.
    pub occupancy_resolution_m: f32,
    /// Vegetation blocks its whole column: aerial scans see crowns but rarely the trunks beneath.
    pub canopy_is_obstacle: bool,
    /// With `canopy_is_obstacle`: above the vehicle's height band only a
    /// disc of this radius about each crown's top blocks (its trunk), so a
    /// street under tree crowns stays open; 0: the whole crown, metres.
    pub canopy_trunk_radius_m: f32,
    /// The start must lie within this distance (xy) of a ground node, metres.
    pub max_start_snap_m: f32,
}

impl Default for GraphParams {
    fn default() -> Self {
        Self {
            node_spacing_m: Auto::Auto,
            d_threshold_m: Auto::Auto,
            vehicle_height_m: 1.8,
            vehicle_radius_m: 0.5,
            max_slope_deg: 20.0,
            clearance_m: 0.2,
            occupancy_resolution_m: 0.25,
            canopy_is_obstacle: true,
            canopy_trunk_radius_m: 0.0,
            max_start_snap_m: 5.0,
        }
    }
}

impl GraphParams {
    /// `node_spacing_m: auto` for ground points `spacing_m` apart: 2.5
    /// point spacings (a node cell holds ~6 ground points), never finer
    /// than the reference prior's 1.25 m.
    pub fn spacing_rule(spacing_m: f32) -> f32 {
        (NODE_SPACINGS * spacing_m).max(MIN_NODE_SPACING)
    }

    /// Node spacing in use (the rule at high density while still `auto`).
    pub fn node_spacing(&self) -> f32 {
        self.node_spacing_m.or_rule(|| Self::spacing_rule(0.0))
    }

    /// Edge reach in use: 1.52 node spacings while `auto`.
    pub fn d_threshold(&self) -> f32 {
        self.d_threshold_m
            .or_rule(|| REACH_PER_SPACING * self.node_spacing())
    }

    /// These parameters with every `auto` resolved for ground points of density `d`.
    pub fn resolved(&self, d: &Density) -> Self {
        let spacing = Self {
            node_spacing_m: self
                .node_spacing_m
                .resolved(|| Self::spacing_rule(d.spacing_m)),
            ..self.clone()
        };
        Self {
            d_threshold_m: Auto::Value(spacing.d_threshold()),
            ..spacing
        }
    }

    /// Obstacle-grid cells a graph over ground spanning `size` (x, y metres) needs.
    pub fn occupancy_cells(&self, size: [f64; 2]) -> f64 {
        let r = f64::from(self.occupancy_resolution_m);
        (size[0] / r).ceil().max(1.0) * (size[1] / r).ceil().max(1.0)
    }

    /// Checks every field's range and that edges can reach the neighbouring cells.
    pub fn validate(&self) -> Result<(), ParamError> {
        let c = Checks("graph");
        let (spacing, reach) = (self.node_spacing(), self.d_threshold());
        let (height, clearance) = (self.vehicle_height_m, self.clearance_m);
        c.within("node_spacing_m", spacing, 0.1, 20.0)?;
        let joins = reach.is_finite() && reach > spacing;
        c.that(
            joins,
            "d_threshold_m",
            reach,
            "must exceed node_spacing_m, or no two nodes are joined",
        )?;
        c.positive("vehicle_height_m", height)?;
        c.non_negative("vehicle_radius_m", self.vehicle_radius_m)?;
        c.within(
            "canopy_trunk_radius_m",
            self.canopy_trunk_radius_m,
            0.0,
            5.0,
        )?;
        let slope_ok = (0.0..90.0).contains(&self.max_slope_deg);
        c.that(
            slope_ok,
            "max_slope_deg",
            self.max_slope_deg,
            "must be in [0, 90)",
        )?;
        let under = clearance.is_finite() && clearance >= 0.0 && clearance < height;
        c.that(
            under,
            "clearance_m",
            clearance,
            "must be ≥ 0 and below vehicle_height_m",
        )?;
        c.within(
            "occupancy_resolution_m",
            self.occupancy_resolution_m,
            0.02,
            5.0,
        )?;
        c.positive("max_start_snap_m", self.max_start_snap_m)?;
        let near = reach <= 10.0 * spacing;
        c.that(
            near,
            "d_threshold_m",
            reach,
            "must be at most 10 × node_spacing_m",
        )
    }
}
