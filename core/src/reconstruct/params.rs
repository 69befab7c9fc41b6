//! Tunables of building reconstruction, each default with its reason.

use crate::footprint::{DeriveParams, SplitParams};
use crate::geom::planes::{PlaneGrowth, ROOF_MIN_NZ};
use crate::params::{Checks, ParamError};

/// How buildings are reconstructed ([`super::reconstruct_cloud`]).
#[derive(Debug, Clone, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct ReconstructParams {
    /// Points are thinned to one per voxel of this size (m) first: bounds the
    /// cost on dense merged clouds; a fifth of the roof cell keeps every plane.
    pub voxel_m: f64,
    /// Neighbours per point for normals and region growing.
    pub k: usize,
    /// Points whose normal has at least this |z| may belong to a roof plane
    /// (60° slopes and flatter).
    pub roof_min_nz: f64,
    /// Points whose normal has at most this |z| are wall points (within ~17°
    /// of vertical).
    pub wall_max_nz: f64,
    /// A neighbour joins a growing plane when its normal is within this angle (°).
    pub grow_angle_deg: f64,
    /// ... and it lies within this distance (m) of the plane.
    pub grow_dist_m: f64,
    /// Planes with fewer points are dropped (clutter): 8 keeps a dormer or
    /// a porch of ~0.7 m² at AHN3's density (chosen on AHN3 Delft tile 1
    /// and the reference scene's simulated survey).
    pub min_plane_points: usize,
    /// Cell (m) of the raster on which roof planes are assigned to the footprint.
    pub cell_m: f64,
    /// Roof regions smaller than this (m²) merge into a neighbour on sparse
    /// roofs (up to `sparse_roof_density`): small parts keep the dormers
    /// AHN3 shows (chosen with `min_plane_points` on AHN3 Delft tile 1 and
    /// the reference scene's simulated survey).
    pub min_region_m2: f64,
    /// ... and smaller than this (m²) on dense roofs (from
    /// `dense_roof_density`): there a few points make a plane of a few dm²,
    /// so small parts are mostly clutter (chosen on the reference demo's
    /// merged cloud: 0.75 → 0.036 m mean distance to the truth, 3.0 → 0.025).
    pub dense_region_m2: f64,
    /// Roof density (points per m² where the roof was seen, after thinning)
    /// up to which `min_region_m2` holds: above the training set's airborne
    /// surveys (AHN3 Delft tile 1 5–11, the reference scene's simulated
    /// prior 35–48).
    pub sparse_roof_density: f64,
    /// Roof density from which `dense_region_m2` holds, linear in between
    /// (the reference demo's merged cloud: 36–153, its clutter at 134).
    pub dense_roof_density: f64,
    /// Douglas–Peucker tolerance (m) for the region boundaries (above half the
    /// cell diagonal, so raster staircases become straight lines).
    pub simplify_m: f64,
    /// Wall points within this distance (m) of an outline edge may move it
    /// onto their plane.
    pub wall_band_m: f64,
    /// An edge moves onto its wall points only with at least this many.
    pub min_wall_points: usize,
    /// Boundaries between parts whose heights differ by more (m) are walls.
    pub min_step_m: f64,
    /// Share of the footprint's cells holding horizontal points between the
    /// ground and the roof above which the base is raised to that underside
    /// (a slab on pillars, seen from below).
    pub open_base_share: f64,
    /// Footprints derived from the points when none are given.
    pub derive: DeriveParams,
    /// Points to footprints.
    pub split: SplitParams,
}

impl Default for ReconstructParams {
    fn default() -> Self {
        Self {
            voxel_m: 0.1,
            k: 12,
            roof_min_nz: ROOF_MIN_NZ,
            wall_max_nz: 0.3,
            grow_angle_deg: 12.0,
            grow_dist_m: 0.2,
            min_plane_points: 8,
            cell_m: 0.5,
            min_region_m2: 0.75,
            dense_region_m2: 3.0,
            sparse_roof_density: 50.0,
            dense_roof_density: 100.0,
            simplify_m: 0.45,
            wall_band_m: 1.0,
            min_wall_points: 12,
            min_step_m: 1.0,
            open_base_share: 0.3,
            derive: DeriveParams::default(),
            split: SplitParams::default(),
        }
    }
}

impl ReconstructParams {
    /// The roof planes' growth these tunables ask for.
    pub fn plane_growth(&self) -> PlaneGrowth {
        PlaneGrowth {
            min_nz: self.roof_min_nz,
            angle_deg: self.grow_angle_deg,
            dist_m: self.grow_dist_m,
            min_points: self.min_plane_points,
        }
    }

    /// The smallest roof part (m²) on a roof of `density` points per m².
    pub fn region_m2(&self, density: f64) -> f64 {
        let span = self.dense_roof_density - self.sparse_roof_density;
        let t = if span > 0.0 {
            ((density - self.sparse_roof_density) / span).clamp(0.0, 1.0)
        } else if density >= self.dense_roof_density {
            1.0
        } else {
            0.0
        };
        // NaN density (no roof point) keeps the sparse size.
        let t = if t.is_nan() { 0.0 } else { t };
        self.min_region_m2 + t * (self.dense_region_m2 - self.min_region_m2)
    }

    /// Checks ranges, naming the first bad value.
    pub fn validate(&self) -> Result<(), ParamError> {
        let checks: [(&'static str, f64, f64, f64); 16] = [
            ("voxel_m", self.voxel_m, 0.0, 10.0),
            ("k", self.k as f64, 3.0, 100.0),
            ("roof_min_nz", self.roof_min_nz, 0.0, 1.0),
            ("wall_max_nz", self.wall_max_nz, 0.0, 1.0),
            ("grow_angle_deg", self.grow_angle_deg, 0.1, 90.0),
            ("grow_dist_m", self.grow_dist_m, 0.001, 10.0),
            ("min_plane_points", self.min_plane_points as f64, 3.0, 1e9),
            ("cell_m", self.cell_m, 0.05, 10.0),
            ("min_region_m2", self.min_region_m2, 0.0, 1e6),
            ("dense_region_m2", self.dense_region_m2, 0.0, 1e6),
            ("sparse_roof_density", self.sparse_roof_density, 0.0, 1e9),
            ("dense_roof_density", self.dense_roof_density, 0.0, 1e9),
            ("simplify_m", self.simplify_m, 0.0, 10.0),
            ("wall_band_m", self.wall_band_m, 0.0, 10.0),
            ("min_step_m", self.min_step_m, 0.0, 100.0),
            ("open_base_share", self.open_base_share, 0.0, 1.0),
        ];
        let c = Checks("reconstruction");
        for (name, value, lo, hi) in checks {
            c.within(name, value, lo, hi)?;
        }
        self.derive.validate()?;
        self.split.validate()?;
        Ok(())
    }
}
