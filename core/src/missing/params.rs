//! Parameters of missing-region detection (docs/design.md steps 3–4).

use serde::{Deserialize, Serialize};

use crate::density::{Auto, Density};
use crate::params::{Checks, ParamError};
use crate::skeleton::SkeletonParams;
use crate::slice::SliceParams;

/// How missing wall parts are found.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DetectParams {
    /// Slicing and outlining.
    pub slice: SliceParams,
    /// Medial-axis skeleton.
    pub skeleton: SkeletonParams,
    /// δ: half-width of the strip around segment s→q searched for points,
    /// metres; `auto`: [`DetectParams::delta_rule`].
    pub delta: Auto<f64>,
    /// Spacing of the boundary points q_n along each contour, metres.
    pub boundary_spacing: f64,
    /// How far inside the contour (from q_n along s→q) points count as "near the boundary", metres.
    pub near: f64,
    /// How far outside the contour points still count, metres.
    pub outside: f64,
    /// A point covers the wall within this radius (the completeness τ), metres.
    pub coverage_radius: f32,
    /// Least covered share of the strip for a boundary point to be collected.
    pub min_coverage: f32,
    /// θ: R_missing below this → point-based targets, else region-based.
    pub theta: f32,
    /// Buildings with fewer points are skipped (reported, not an error).
    pub min_points: usize,
    /// Least share of its base size a slice part keeps and stays in its structure.
    pub structure_keep: f64,
}

impl Default for DetectParams {
    fn default() -> Self {
        DetectParams {
            slice: SliceParams::default(),
            skeleton: SkeletonParams::default(),
            delta: Auto::Auto,
            boundary_spacing: 1.0,
            near: 2.0,
            outside: 0.5,
            coverage_radius: 0.25,
            min_coverage: 0.5,
            theta: 0.3,
            min_points: 50,
            structure_keep: 0.7,
        }
    }
}

impl DetectParams {
    /// `delta: auto`: 1.5 outline cells (0.75 m at the reference prior's
    /// 0.5 m cells), so the strip is as wide, in cells, at every density.
    pub fn delta_rule(cell_m: f64) -> f64 {
        1.5 * cell_m
    }

    /// δ in use (from the outline cell in use while still `auto`).
    pub fn delta_m(&self) -> f64 {
        self.delta.or_rule(|| Self::delta_rule(self.slice.cell_m()))
    }

    /// These parameters with every `auto` resolved for building points of
    /// density `d`.
    pub fn resolved(&self, d: &Density) -> Self {
        let slice = self.slice.resolved(d);
        let delta = self.delta.resolved(|| Self::delta_rule(slice.cell_m()));
        Self {
            slice,
            delta,
            ..self.clone()
        }
    }

    /// [`DetectParams::resolved`] for the density of `points`, when any
    /// parameter is still `auto` and the points have a density.
    pub fn resolved_for(&self, points: &[[f32; 3]]) -> Self {
        let auto = self.delta.value().is_none()
            || self.slice.cell.value().is_none()
            || self.slice.spacing.value().is_none()
            || self.slice.closing.value().is_none();
        match Density::measure(points) {
            Some(d) if auto => self.resolved(&d),
            _ => self.clone(),
        }
    }

    /// Checks every field is usable.
    pub fn validate(&self) -> Result<(), ParamError> {
        self.slice.validate()?;
        self.skeleton.validate()?;
        let c = Checks("detection");
        c.positive("delta", self.delta_m())?;
        c.positive("boundary_spacing", self.boundary_spacing)?;
        c.positive("near", self.near)?;
        c.positive("coverage_radius", self.coverage_radius)?;
        c.non_negative("outside", self.outside)?;
        c.within("min_coverage", self.min_coverage, 0.0, 1.0)?;
        c.within("theta", self.theta, 0.0, 1.0)?;
        c.within("structure_keep", self.structure_keep, 0.0, 1.0)
    }
}
