//! Tunables of splitting and deriving, as read from a node's params YAML.

use crate::density::{Auto, Density};
use crate::params::{Checks, ParamError};

/// Finest derivation cell, metres: the reference prior's value.
const MIN_DERIVE_CELL: f64 = 0.5;

/// How points are assigned to footprints ([`super::split`]).
#[derive(Debug, Clone, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct SplitParams {
    /// Points outside every footprint but within this distance (m) of one's
    /// outline still belong to it (wall points, roof overhangs, noise).
    pub tolerance_m: f64,
    /// Cell size (m) of the grid that indexes footprints by bounding box.
    pub index_cell_m: f64,
}

impl Default for SplitParams {
    fn default() -> Self {
        Self {
            tolerance_m: 0.5,
            index_cell_m: 4.0,
        }
    }
}

impl SplitParams {
    /// Checks ranges.
    pub fn validate(&self) -> Result<(), ParamError> {
        check(
            "tolerance_m",
            self.tolerance_m,
            0.0,
            100.0,
            "0 ≤ value ≤ 100 m",
        )?;
        check(
            "index_cell_m",
            self.index_cell_m,
            0.1,
            1000.0,
            "0.1 ≤ value ≤ 1000 m",
        )
    }
}

/// How footprints are derived from building points ([`super::derive`]).
#[derive(Debug, Clone, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct DeriveParams {
    /// Occupancy grid cell (m): about twice the point spacing or more;
    /// `auto`: [`DeriveParams::cell_rule`].
    pub cell_m: Auto<f64>,
    /// Closing radius in cells: fills gaps up to twice this between occupied
    /// cells (sparse roofs) while keeping wider alleys open.
    pub closing_cells: u32,
    /// Clusters with fewer points are dropped (clutter, misclassified points).
    pub min_points: usize,
    /// Outlines with less area (m²) are dropped.
    pub min_area_m2: f64,
    /// Outlines are derived only from the building points standing at
    /// least this high (m) over the terrain, where it is known: lower ones
    /// are hedges, bushes, cars and pergolas, alone or against a wall (a
    /// storey with a door is about 2.5 m); 0: off.
    pub min_height_m: f64,
    /// Adjacent cells whose highest points differ by more (m) than the
    /// roof's own slope either side belong to different buildings (the
    /// eave or ridge step between two houses of a row); 0 turns this split off.
    pub height_jump_m: f64,
    /// A cell lower by more than this (m) than the roof two cells away on
    /// both sides (along x or y) lies in the valley between two pitched
    /// roofs, the party wall of a row of gabled houses: such valleys
    /// separate buildings; 0 turns this split off.
    pub valley_m: f64,
    /// Valley cells are grown by this many cells, so that a gutter line
    /// broken by noise still separates its two roofs.
    pub valley_dilate_cells: u32,
    /// A height-split part smaller than this (m²) is merged back into its
    /// neighbour (a dormer, chimney or noisy roof patch, not a house).
    pub min_part_m2: f64,
    /// A height-split part whose outline touches open ground for less than
    /// this share of its cell edges is merged back into its neighbour (a
    /// tower on its podium is one building).
    pub min_open_share: f64,
    /// Douglas–Peucker tolerance (m) for the traced outlines.
    pub simplify_m: f64,
}

impl Default for DeriveParams {
    fn default() -> Self {
        Self {
            cell_m: Auto::Auto,
            closing_cells: 1,
            min_points: 50,
            min_area_m2: 10.0,
            min_height_m: 2.5,
            height_jump_m: 0.0,
            valley_m: 0.2,
            valley_dilate_cells: 1,
            min_part_m2: 35.0,
            min_open_share: 0.1,
            simplify_m: 0.4,
        }
    }
}

impl DeriveParams {
    /// `cell_m: auto` for building points `spacing_m` apart: twice the
    /// spacing, so almost every roof cell holds a point and one closing
    /// cell fills the rest, never finer than the reference prior's 0.5 m.
    pub fn cell_rule(spacing_m: f32) -> f64 {
        (2.0 * f64::from(spacing_m)).max(MIN_DERIVE_CELL)
    }

    /// Cell in use (the rule at high density while still `auto`).
    pub fn cell(&self) -> f64 {
        self.cell_m.or_rule(|| Self::cell_rule(0.0))
    }

    /// These parameters with `auto` resolved for building points of density `d`.
    pub fn resolved(&self, d: &Density) -> Self {
        Self {
            cell_m: self.cell_m.resolved(|| Self::cell_rule(d.spacing_m)),
            ..self.clone()
        }
    }

    /// Checks ranges.
    pub fn validate(&self) -> Result<(), ParamError> {
        check("cell_m", self.cell(), 0.05, 50.0, "0.05 ≤ value ≤ 50 m")?;
        check(
            "closing_cells",
            f64::from(self.closing_cells),
            0.0,
            10.0,
            "0 ≤ value ≤ 10 cells",
        )?;
        check("min_area_m2", self.min_area_m2, 0.0, 1e9, "value ≥ 0 m²")?;
        check(
            "min_height_m",
            self.min_height_m,
            0.0,
            1e3,
            "0 ≤ value ≤ 1000 m (0 = off)",
        )?;
        check(
            "height_jump_m",
            self.height_jump_m,
            0.0,
            1e4,
            "value ≥ 0 m (0 = off)",
        )?;
        check("valley_m", self.valley_m, 0.0, 1e3, "value ≥ 0 m (0 = off)")?;
        check(
            "valley_dilate_cells",
            f64::from(self.valley_dilate_cells),
            0.0,
            5.0,
            "0 ≤ value ≤ 5 cells",
        )?;
        check(
            "min_part_m2",
            self.min_part_m2,
            0.0,
            1e6,
            "0 ≤ value ≤ 10⁶ m²",
        )?;
        check(
            "min_open_share",
            self.min_open_share,
            0.0,
            1.0,
            "0 ≤ value ≤ 1",
        )?;
        check(
            "simplify_m",
            self.simplify_m,
            0.0,
            100.0,
            "0 ≤ value ≤ 100 m",
        )
    }
}

/// `value` in `[lo, hi]`, said as `expected` (with its unit).
fn check(
    name: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    expected: &'static str,
) -> Result<(), ParamError> {
    let ok = value.is_finite() && value >= lo && value <= hi;
    Checks("footprint").that(ok, name, value, expected)
}
